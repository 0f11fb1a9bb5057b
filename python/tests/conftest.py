"""Shared fixtures: the command-line tool of the same repository, built with cargo."""

import os
import subprocess
from pathlib import Path

import pytest

#: The repository root (python/tests/ -> python/ -> root).
ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def cli():
    """A function running ``stabound ARGS...``: returns (exit code, stdout, stderr).

    The binary is ``$STABOUND_CLI`` if set, else ``target/release/stabound`` of this
    repository, built with ``cargo build --release`` when it is missing.
    """
    exe = os.environ.get("STABOUND_CLI")
    if exe is None:
        exe = str(ROOT / "target" / "release" / "stabound")
        if not os.path.exists(exe):
            subprocess.run(
                ["cargo", "build", "--release", "--bin", "stabound"], cwd=ROOT, check=True
            )

    def run(*args):
        p = subprocess.run([exe, *map(str, args)], capture_output=True, text=True)
        return p.returncode, p.stdout, p.stderr

    return run


@pytest.fixture(scope="session")
def cli_ok(cli):
    """Like ``cli`` but expects exit code 0 and returns stdout."""

    def run(*args):
        code, out, err = cli(*args)
        assert code == 0, err
        return out

    return run
