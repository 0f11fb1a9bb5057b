"""Shared fixtures: the command-line tool of the same repository, built with cargo."""

import csv
import functools
import io
import json
import math
import os
import subprocess
from pathlib import Path

import pytest

def rows(text):
    """The rows of the tool's CSV output, as dicts of strings (`#` lines are comments)."""
    return list(csv.DictReader(line for line in io.StringIO(text) if not line.startswith("#")))


def num(v):
    """A CSV or JSON cell as a float (empty and null are NaN, as the tool writes NaN)."""
    return math.nan if v in ("", None) else float(v)


def same(a, b):
    """Exact equality of two floats, NaN equal to NaN (`==` on purpose: the tool's floats
    round-trip)."""
    return (math.isnan(a) and math.isnan(b)) or a == b


#: The repository root (python/tests/ -> python/ -> root).
ROOT = Path(__file__).resolve().parents[2]


@functools.lru_cache(maxsize=None)
def executable():
    """The command-line tool: ``$STABOUND_CLI`` if set, else this repository's release build,
    brought up to date with ``cargo build --release`` (a no-op when it is), so that it is
    never older than the library the package was built from."""
    exe = os.environ.get("STABOUND_CLI")
    if exe:
        return exe
    subprocess.run(["cargo", "build", "--release", "--bin", "stabound"], cwd=ROOT, check=True)
    meta = subprocess.run(
        ["cargo", "metadata", "--format-version", "1", "--no-deps"],
        cwd=ROOT, check=True, capture_output=True, text=True,
    )
    return str(Path(json.loads(meta.stdout)["target_directory"]) / "release" / "stabound")


@pytest.fixture
def cli():
    """A function running ``stabound ARGS...``: returns (exit code, stdout, stderr)."""
    exe = executable()

    def run(*args):
        p = subprocess.run([exe, *map(str, args)], capture_output=True, text=True)
        return p.returncode, p.stdout, p.stderr

    return run


@pytest.fixture
def cli_ok(cli):
    """Like ``cli`` but expects exit code 0 and returns stdout."""

    def run(*args):
        code, out, err = cli(*args)
        assert code == 0, err
        return out

    return run
