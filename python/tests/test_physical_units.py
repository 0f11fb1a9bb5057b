"""Physical units in passivity(), alpha_max() and the delta-beta boundary with loop elements,
against the command-line tool with the same physical flags (it prints shortest round-trip
floats, so `float` of its text is the exact double: `==` below is exact comparison on
purpose), and against independent numbers."""

import json
import math

import numpy as np
import pytest

import stabound
from conftest import num, rows, same

# b = 200 N s/m, m = 0.1 kg, T = 1 ms: delta = b T / m = 2
DEVICE = dict(mass=0.1, period=1e-3)
DEVICE_FLAGS = ["--mass", 0.1, "--period", 0.001]

SUMMARY_KEYS = ("alpha_max_passive", "beta_at_max", "alpha_max_at_beta", "passive_area",
                "stable_area", "passive_share_of_stable", "stable_share_of_passive",
                "passive_share_error", "passive_share_bound")


@pytest.mark.parametrize("flags,kw", [
    (["--damping", 200, "--delay", 0.001, "--wall-damping", 0],
     dict(damping=200.0, delay=1e-3, wall_damping=0.0)),
    (["--damping", 200, "--delay-samples", 2, "--wall-damping", 15],
     dict(damping=200.0, delay_samples=2, wall_damping=15.0)),
    (["--damping", 150, "--d", 1, "--velocity-filter-cutoff", 40],
     dict(damping=150.0, d=1, velocity_filter_cutoff=40.0)),
])
def test_passivity_physical_summary_matches_cli(cli_ok, flags, kw):
    out = json.loads(cli_ok("passivity", *DEVICE_FLAGS, *flags, "--summary", "--format", "json",
                            "--columns", 16))[0]
    p = stabound.passivity(**DEVICE, **kw, columns=16)
    assert p.at == out["delta"] and p.d == out["d"]
    for key in SUMMARY_KEYS:
        assert same(num(getattr(p, key)), num(out[key])), key
    assert (p.stiffness_max, p.wall_damping_at_max) == (out["K_max_N_per_m"], out["B_at_max_Ns_per_m"])
    assert p.inside == (out["inside"] == "yes")


def test_passivity_physical_is_diolaiti():
    # Diolaiti et al.: one sample of delay, no filter, the largest passive stiffness over beta
    # is (2 sqrt 2 - 2) delta and at beta = 0 it is 2 delta / (1 + 2 d); delta = 2 here. The
    # edge is traced to tol = 1e-7 (distance from the true edge), so 1e-6 bounds the error
    # of a vertex's alpha with room to spare.
    p = stabound.passivity(damping=200.0, delay=1e-3, wall_damping=0.0, **DEVICE)
    assert p.at == 200.0 * 1e-3 / 0.1
    assert abs(p.alpha_max_passive - 2.0 * (2.0 * math.sqrt(2.0) - 2.0)) < 1e-6
    assert abs(p.alpha_max_at_beta - 4.0 / 3.0) < 1e-6
    # K = alpha m / T^2 (to the same relative accuracy)
    assert abs(p.stiffness_max / 1e5 - 2.0 * (2.0 * math.sqrt(2.0) - 2.0)) < 1e-6


def test_passivity_delta_beta_stiffness_matches_cli(cli_ok):
    # K = 50 kN/m on m = 0.1 kg, T = 1 ms is alpha = 0.5; damping 300 N s/m the delta range 3
    flags = ["--plane", "delta-beta", "--stiffness", 50000, "--damping", 300, "--delay-samples", 1]
    out = json.loads(cli_ok("passivity", *DEVICE_FLAGS, *flags, "--summary", "--format", "json",
                            "--columns", 16))[0]
    p = stabound.passivity(plane="delta-beta", stiffness=5e4, damping=300.0, delay_samples=1,
                           columns=16, **DEVICE)
    assert p.at == out["alpha"] and abs(p.at - 0.5) < 1e-12
    for key in ("passive_area", "stable_area", "passive_share_of_stable",
                "stable_share_of_passive"):
        assert getattr(p, key) == out[key], key
    w = p.stable_not_passive
    assert (w.delta, w.beta) == (out["stable_not_passive_delta"], out["stable_not_passive_beta"])


def test_passivity_physical_region_rows_match_cli(cli_ok):
    got = rows(cli_ok("passivity", "--tol", 1e-6, *DEVICE_FLAGS, "--damping", 100,
                      "--delay", 0.002))
    p = stabound.passivity(tol=1e-6, damping=100.0, delay=2e-3, **DEVICE)
    passive = [r for r in got if r["region"] == "passive"]
    assert [float(r["alpha"]) for r in passive] == p.x.tolist()
    assert [float(r["beta"]) for r in passive] == p.y.tolist()
    assert [float(r["delta"]) for r in passive] == [p.at] * len(passive)
    assert [float(r["d"]) for r in passive] == [2.0] * len(passive)


@pytest.mark.parametrize("kw,flags,match", [
    (dict(damping=200.0, d=1), ["--damping", 200, "--d", 1], "damping= is in physical units"),
    (dict(damping=200.0, stiffness=1.0, d=1, plane="delta-beta"),
     ["--damping", 200, "--stiffness", 1, "--d", 1, "--plane", "delta-beta"],
     "damping=, stiffness= are in physical units"),
    (dict(delta=1.0, wall_damping=3.0, period=1e-3), ["--delta", 1, "--wall-damping", 3,
                                                      "--period", 0.001],
     "wall_damping= is in physical units"),
    (dict(damping=200.0, delay=1e-3, period=1e-3), ["--damping", 200, "--delay", 0.001,
                                                    "--period", 0.001],
     "damping=, delay= are in physical units"),
    (dict(delta=1.0, stiffness=5e3, **DEVICE), ["--delta", 1, "--stiffness", 5000, *DEVICE_FLAGS],
     "alpha= belongs to plane='delta-beta', as stiffness= does"),
    (dict(plane="delta-beta", alpha=0.5, wall_damping=3.0, **DEVICE),
     ["--plane", "delta-beta", "--alpha", 0.5, "--wall-damping", 3, *DEVICE_FLAGS],
     "beta= belongs to the alpha-beta plane, as wall_damping= does"),
    (dict(delta=1.0, delay=1e-3), ["--delta", 1, "--delay", 0.001], r"delay= needs period= \(the sampling period in s\)"),
    (dict(delta=1.0, damping=100.0, **DEVICE), ["--delta", 1, "--damping", 100, *DEVICE_FLAGS],
     "give delta= or damping=, not both"),
    (dict(delta=1.0, d=1, delay=1e-3, **DEVICE), ["--delta", 1, "--d", 1, "--delay", 0.001,
                                                 *DEVICE_FLAGS], "give d= or delay=, not both"),
    (dict(delta=1.0, delay_samples=1, delay=1e-3, **DEVICE),
     ["--delta", 1, "--delay-samples", 1, "--delay", 0.001, *DEVICE_FLAGS],
     "give delay_samples= or delay=, not both"),
    (dict(delta=1.0, beta=0.0, wall_damping=0.0, **DEVICE),
     ["--delta", 1, "--beta", 0, "--wall-damping", 0, *DEVICE_FLAGS], "give beta= or wall_damping="),
    (dict(plane="delta-beta", alpha=0.5, stiffness=5e4, **DEVICE),
     ["--plane", "delta-beta", "--alpha", 0.5, "--stiffness", 50000, *DEVICE_FLAGS],
     "give alpha= or stiffness="),
])
def test_passivity_physical_errors_as_cli(cli, kw, flags, match):
    with pytest.raises(ValueError, match=match):
        stabound.passivity(**kw)
    code, _, _ = cli("passivity", *flags)
    assert code == 2


def test_passivity_fractional_delay_in_seconds_is_refused(cli):
    # 1.5 ms at T = 1 ms is 1.5 samples: the passivity condition is for whole samples
    with pytest.raises(ValueError):
        stabound.passivity(damping=100.0, delay=1.5e-3, **DEVICE)
    assert cli("passivity", "--damping", 100, "--delay", 0.0015, *DEVICE_FLAGS)[0] == 2


# ---------------------------------------------------------------------------------------
# alpha_max with wall-damping limits

AMAX_FLAGS = [*DEVICE_FLAGS, "--damping", "0,10,100", "--delay-samples", "1,2"]
AMAX_KW = dict(**DEVICE, damping=np.array([0.0, 10.0, 100.0]), delay_samples=np.array([[1.0], [2.0]]))


@pytest.mark.parametrize("flags,kw", [
    (["--wall-damping-min", 0, "--wall-damping-max", 30],
     dict(wall_damping_min=0.0, wall_damping_max=30.0)),
    (["--wall-damping-max", 1], dict(wall_damping_max=1.0)),
    (["--wall-damping-min", 5, "--beta-max", 2], dict(wall_damping_min=5.0, beta_max=2.0)),
])
def test_alpha_max_wall_damping_limits_match_cli(cli_ok, flags, kw):
    got = rows(cli_ok("amax", *AMAX_FLAGS, *flags))
    r = stabound.alpha_max(**AMAX_KW, **kw)
    for col, arr in (("alpha_max", r.alpha_max), ("beta_at_max", r.beta_at_max),
                     ("K_max_N_per_m", r.stiffness), ("B_at_max_Ns_per_m", r.wall_damping)):
        assert [float(g[col]) for g in got] == arr.ravel().tolist(), col


def test_alpha_max_wall_damping_limits_by_point_tests():
    # independent of the alpha_max search: walls just below alpha_max at its beta are stable
    # (Schur-Cohn point tests); just above it, no admissible beta is stable. 1e-6 relative is
    # far above the search's accuracy (theta to 1e-12) and far below the spread of alpha over
    # the beta grid.
    lo_b, hi_b = 5.0, 30.0  # N s/m: beta in [0.05, 0.3]
    r = stabound.alpha_max(**DEVICE, damping=10.0, delay_samples=1,
                           wall_damping_min=lo_b, wall_damping_max=hi_b)
    assert lo_b - 1e-9 <= r.wall_damping <= hi_b + 1e-9
    delta = 10.0 * 1e-3 / 0.1
    assert stabound.check(r.alpha_max * (1 - 1e-6), r.beta_at_max, delta, 1.0).stable
    betas = np.linspace(lo_b * 1e-3 / 0.1, hi_b * 1e-3 / 0.1, 201)
    assert not stabound.check(r.alpha_max * (1 + 1e-6), betas, delta, 1.0).stable.any()
    # unrestricted, this device's optimum lies above B = 30 N s/m: the limit binds
    free = stabound.alpha_max(**DEVICE, damping=10.0, delay_samples=1)
    assert free.wall_damping > hi_b and free.alpha_max > r.alpha_max


def test_alpha_max_loop_wall_damping_limit_matches_cli(cli_ok):
    got = rows(cli_ok("amax", *DEVICE_FLAGS, "--damping", 10, "--delay-samples", 1,
                      "--velocity-filter-cutoff", 30, "--wall-damping-max", 5))
    r = stabound.alpha_max(**DEVICE, damping=10.0, delay_samples=1, velocity_filter_cutoff=30.0,
                           wall_damping_max=5.0)
    assert (r.alpha_max, r.beta_at_max, r.stiffness, r.wall_damping) == tuple(
        float(got[0][c]) for c in ("alpha_max", "beta_at_max", "K_max_N_per_m", "B_at_max_Ns_per_m"))


@pytest.mark.parametrize("kw,flags,match", [
    (dict(delta=0.0, d=1.0, wall_damping_min=0.0), ["--delta", 0, "--d", 1, "--wall-damping-min", 0],
     "wall_damping_min= is a wall damping"),
    (dict(delta=0.0, d=1.0, wall_damping_max=0.0), ["--delta", 0, "--d", 1, "--wall-damping-max", 0],
     "wall_damping_max= is a wall damping"),
    (dict(**DEVICE, damping=0.0, delay_samples=1, beta_min=0.0, wall_damping_min=0.0),
     [*DEVICE_FLAGS, "--damping", 0, "--delay-samples", 1, "--beta-min", 0, "--wall-damping-min", 0],
     "not both"),
])
def test_alpha_max_wall_damping_errors_as_cli(cli, kw, flags, match):
    with pytest.raises(ValueError, match=match):
        stabound.alpha_max(**kw)
    assert cli("amax", *flags)[0] == 2


def test_alpha_max_wall_damping_needs_one_device():
    with pytest.raises(ValueError, match="one number each"):
        stabound.alpha_max(mass=[0.1, 0.2], period=1e-3, damping=0.0, delay_samples=1,
                           wall_damping_min=0.0)


# ---------------------------------------------------------------------------------------
# the delta-beta boundary with loop elements


def test_delta_beta_loop_boundary_matches_cli(cli_ok):
    got = rows(cli_ok("boundary", "--plane", "delta-beta", "--alpha", "0,0.5", "--d", "1,2",
                      "--delta", "0,2", "--tol", 1e-4, *DEVICE_FLAGS,
                      "--velocity-filter-cutoff", 30, "--hand-mass", 0.05))
    curves = stabound.boundary(plane="delta-beta", alpha=[0.0, 0.5], d=[1.0, 2.0],
                               delta=[0.0, 2.0], tol=1e-4, velocity_filter_cutoff=30.0,
                               hand_mass=0.05, **DEVICE)
    assert [(c.alpha, c.d) for c in curves] == [(0.0, 1.0), (0.0, 2.0), (0.5, 1.0), (0.5, 2.0)]
    flat = [(c.alpha, c.d, x, b, lp, p) for c in curves
            for x, b, lp, p in zip(c.delta.tolist(), c.beta.tolist(), c.loop.tolist(), c.piece.tolist())]
    assert len(flat) == len(got)
    for g, (a, d, x, b, lp, p) in zip(got, flat):
        assert (float(g["alpha"]), float(g["d"]), float(g["delta"]), float(g["beta"])) == (a, d, x, b)
        assert (int(float(g["loop"])), g["piece"]) == (lp, p)


def test_delta_beta_loop_boundary_points_are_marginal():
    # independent of the bisection: the loop's point test (its own root finder) at each
    # boundary vertex has spectral radius near 1, while the bare device's at the same walls
    # is not; the vertices are within tol = 1e-6 of the edge, where the radius moves by a
    # few times that (1.6e-7 measured), so 1e-4 is a wide margin
    c = stabound.boundary(plane="delta-beta", alpha=0.5, d=1.0, delta=[0.0, 2.0], tol=1e-6,
                          velocity_filter_cutoff=30.0, **DEVICE)
    on = c.piece == "bisection"
    assert on.sum() > 10
    damping = c.delta[on] * 0.1 / 1e-3
    # the walls in physical units: K = alpha m / T^2, B = beta m / T
    rho = [stabound.check(mass=0.1, period=1e-3, damping=x, delay_samples=1, stiffness=5e4,
                          wall_damping=b * 0.1 / 1e-3, velocity_filter_cutoff=30.0).spectral_radius
           for x, b in zip(damping, c.beta[on])]
    assert np.all(np.abs(np.array(rho) - 1.0) < 1e-4)
    bare = stabound.check(0.5, c.beta[on], c.delta[on], 1.0).spectral_radius
    assert np.max(np.abs(bare - 1.0)) > 1e-2


@pytest.mark.parametrize("kw,match", [
    (dict(hand_mass=0.05), "missing mass="),
    (dict(hand_mass=0.05, mass=0.1), "missing period="),
    (dict(hand_mass=0.05, damping=1.0, **DEVICE), "damping= is not taken"),
    (dict(hand_mass=0.05, delay_samples=1, **DEVICE), "delay_samples= is not taken"),
    (dict(**DEVICE), "only with loop elements"),
])
def test_delta_beta_loop_boundary_errors(kw, match):
    with pytest.raises(ValueError, match=match):
        stabound.boundary(plane="delta-beta", alpha=0.5, d=1.0, tol=1e-4, **kw)
