"""The examples in the docstrings run and print what they show."""

import doctest
from pathlib import Path

import stabound


def test_docstring_examples():
    failures, tried = doctest.testmod(stabound, optionflags=doctest.NORMALIZE_WHITESPACE)
    assert tried > 10
    assert failures == 0


def test_type_stubs_match_the_runtime_signatures():
    # mypy's stubtest compares every stub with what the installed module exposes
    import subprocess
    import sys

    import pytest

    pytest.importorskip("mypy")
    # the certificate checker is a standalone standard-library script run as `python -m`,
    # not typed API: it has no stub, so stubtest skips it (its memoized helpers would
    # otherwise read as untyped wrappers)
    allow = Path(__file__).with_name("stubtest_allowlist.txt")
    p = subprocess.run([sys.executable, "-m", "mypy.stubtest", "stabound", "--allowlist",
                        str(allow)], capture_output=True, text=True)
    assert p.returncode == 0, p.stdout + p.stderr
