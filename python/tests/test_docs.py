"""The examples in the docstrings run and print what they show."""

import doctest

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
    p = subprocess.run([sys.executable, "-m", "mypy.stubtest", "stabound"], capture_output=True,
                       text=True)
    assert p.returncode == 0, p.stdout + p.stderr
