"""alpha_max of loops with elements is accurate to 1e-9 relative: at the damping the command
line returns, the largest stable stiffness found by bisection on the closed loop's spectral
radius at 40 digits (mpmath's matrix exponential and eigenvalues, tools/stiff_reference.py,
independent of stabound's code) is the returned alpha_max. At a smooth maximum an error in
the damping changes the limit only to second order, so this measures alpha_max itself."""

import json
import math
import subprocess
import sys

import pytest

from conftest import ROOT, executable

mp = pytest.importorskip("mpmath")

sys.path.insert(0, str(ROOT / "tools"))
import stiff_reference  # noqa: E402



def one_mass(delta):
    a = mp.matrix([[0, 1], [0, -delta]])
    return a, [0, 1], [1, 0]


def lagged(delta, tau):
    """One mass driven through an actuator lag: tau f' = u - f (states y, v, f)."""
    a = mp.matrix([[0, 1, 0], [0, -delta, 1], [0, 0, -1 / tau]])
    return a, [0, 0, 1 / tau], [1, 0, 0]


def transmission(delta, r, kc, dc):
    return stiff_reference.continuous(delta, r, kc, dc, mp.mpf(0), "motor")


#: name: (mass kg, period s, damping N s/m, low-pass cutoff Hz or None, element flags,
#: other flags, the device A, b, c in normalized units from delta)
CASES = {
    # the paper's Section VIII device behind a 50 ms filter, without and with damping
    "section VIII b=0, 50 ms": (0.1, 0.001, 0, 3.1831, [], [], lambda d: one_mass(d)),
    "section VIII b=10, 50 ms": (0.1, 0.001, 10, 3.1831, [], [], lambda d: one_mass(d)),
    "section VIII b=10, 50 ms, B >= 0": (0.1, 0.001, 10, 3.1831, [], ["--beta-min", "0"],
                                         lambda d: one_mass(d)),
    "section VIII b=0, 5 ms": (0.1, 0.001, 0, 31.831, [], [], lambda d: one_mass(d)),
    "actuator lag": (1, 1, 0.1, None, ["--actuator-time-constant", "0.5"], [],
                     lambda d: lagged(d, mp.mpf("0.5"))),
    "transmission": (1, 1, 0.05, None, ["--handle-mass", "0.3", "--transmission-stiffness", "50",
                                        "--transmission-damping", "0.5"], [],
                     lambda d: transmission(d, mp.mpf("0.3"), mp.mpf(50), mp.mpf("0.5"))),
}


@pytest.mark.parametrize("name", sorted(CASES))
def test_alpha_max_to_1e_9_relative(name):
    mass, period, damping, cutoff, elements, extra, device = CASES[name]
    args = [executable(), "amax", "--mass", str(mass), "--period", str(period),
            "--damping", str(damping), "--delay-samples", "1", "--format", "json",
            *elements, *extra]
    if cutoff is not None:
        args += ["--velocity-filter-cutoff", str(cutoff)]
    p = subprocess.run(args, capture_output=True, text=True, check=True)
    row = json.loads(p.stdout)[0]
    alpha, beta = mp.mpf(row["alpha_max"]), mp.mpf(row["beta_at_max"])
    a, b, c = device(mp.mpf(row["delta"]))
    pole = None if cutoff is None else mp.exp(-2 * mp.pi * mp.mpf(cutoff) * mp.mpf(period))

    def radius(x):
        return stiff_reference.loop_radius(a, b, c, 1, x, beta, pole)

    lo, hi = alpha * (1 - mp.mpf("1e-6")), alpha * (1 + mp.mpf("1e-6"))
    assert radius(lo) < 1 < radius(hi), name
    while hi - lo > alpha * mp.mpf("1e-13"):
        mid = (lo + hi) / 2
        if radius(mid) < 1:
            lo = mid
        else:
            hi = mid
    rel = abs(alpha - lo) / lo
    assert rel < 1e-9, f"{name}: {row['alpha_max']} against {mp.nstr(lo, 17)} ({float(rel):.2e})"
    assert math.isfinite(float(beta))
