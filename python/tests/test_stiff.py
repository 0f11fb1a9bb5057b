"""Walls near the alpha = 0 edge of a stiff transmission (coupling 5.2e5 normalized): the
command line's verdicts never contradict an independent evaluation at 40 digits (mpmath's
matrix exponential and eigenvalues, tools/stiff_reference.py), and the golden reference in
data/stiff/walls.csv is what that evaluation gives."""

import csv
import io
import subprocess
import sys

import pytest

from conftest import ROOT, executable

mpmath = pytest.importorskip("mpmath")

sys.path.insert(0, str(ROOT / "tools"))
import stiff_reference  # noqa: E402

GOLDEN = ROOT / "data" / "stiff" / "walls.csv"

#: The default marginal band.
MARGIN = 1e-9


def golden_rows():
    with open(GOLDEN) as f:
        return list(csv.DictReader(f))


def test_golden_reference_is_the_mpmath_evaluation():
    rows = golden_rows()
    walls = stiff_reference.walls()
    assert [(r["alpha"], r["beta"]) for r in rows] == walls
    # every third wall recomputed (the whole file takes about ten seconds)
    for r in rows[::3]:
        rho = stiff_reference.radius(stiff_reference.DEVICE, mpmath.mpf(r["alpha"]), mpmath.mpf(r["beta"]))
        assert abs(rho - mpmath.mpf(r["radius"])) < mpmath.mpf("1e-24")


def test_no_verdict_contradicts_the_reference():
    rows = golden_rows()
    d = stiff_reference.DEVICE
    text = "stiffness_N_per_m,wall_damping_Ns_per_m\n" + "".join(
        f"{r['alpha']},{r['beta']}\n" for r in rows)
    p = subprocess.run(
        [executable(), "check", "--mass", "1", "--period", "1", "--damping", d["delta"],
         "--delay-samples", str(d["d"]), "--handle-mass", d["r"],
         "--transmission-stiffness", d["kappa_c"], "--encoder", d["encoder"], "--batch", "-", "--radius"],
        input=text, capture_output=True, text=True, check=True)
    out = list(csv.DictReader(io.StringIO(p.stdout)))
    assert len(out) == len(rows)
    decided = 0
    for r, o in zip(rows, out):
        ref = float(r["radius"])
        v = o["verdict"]
        assert not (v == "stable" and ref >= 1), (r, o)
        assert not (v == "unstable" and ref <= 1), (r, o)
        # outside the band by a tenth of its width the verdict is the band's
        if ref < 1 - 1.1 * MARGIN:
            assert v == "stable", (r, o)
            decided += 1
        # the radius printed is the reference's to far better than the band
        assert abs(float(o["spectral_radius"]) - ref) < 1e-11, (r, o)
    assert decided >= 10
