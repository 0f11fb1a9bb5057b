"""passivity(): the passive region and its comparison with the stable region, against
`stabound passivity` for the same inputs (the tool prints shortest round-trip floats, so
`float` of its text is the exact double: `==` below is exact comparison on purpose), input
validation, and the renamed arguments."""

import json
import math
import warnings

import numpy as np
import pytest

import stabound
from conftest import num, rows, same


FILTERS = [
    ([], {}),
    (["--filter-pole", 0.6], dict(filter_pole=0.6)),
    (["--velocity-filter-samples", 3], dict(velocity_filter_samples=3)),
    (["--velocity-filter-cutoff", 50, "--period", 0.001, "--mass", 0.5],
     dict(velocity_filter_cutoff=50.0, period=0.001, mass=0.5)),
]


@pytest.mark.parametrize("flags,kw", FILTERS)
def test_alpha_beta_summary_matches_cli(cli_ok, flags, kw):
    out = json.loads(cli_ok("passivity", "--delta", 1, "--d", 1, "--beta", 0.1, "--summary",
                            "--format", "json", "--columns", 32, *flags))[0]
    p = stabound.passivity(1.0, 1, beta=0.1, columns=32, **kw)
    assert p.filter == out["filter"]
    for key in ("alpha_max_passive", "beta_at_max", "alpha_max_at_beta", "passive_area",
                "stable_area", "passive_share_of_stable", "stable_share_of_passive",
                "passive_share_error", "passive_share_bound"):
        assert same(getattr(p, key), num(out[key])), key
    assert p.inside == (out["inside"] == "yes")
    assert p.stable_method == out["stable_method"]
    assert p.passive_unstable is None and out["witness_alpha"] is None
    w = p.stable_not_passive
    assert (w.alpha, w.beta) == (out["stable_not_passive_alpha"], out["stable_not_passive_beta"])
    assert w.verdict == "stable" and w.margin < 0
    if "mass" in kw:
        assert (p.stiffness_max, p.wall_damping_at_max) == (out["K_max_N_per_m"], out["B_at_max_Ns_per_m"])


@pytest.mark.parametrize("flags,kw", FILTERS[:3])
def test_delta_beta_summary_matches_cli(cli_ok, flags, kw):
    out = json.loads(cli_ok("passivity", "--plane", "delta-beta", "--alpha", 0.5, "--d", 1,
                            "--delta", 3, "--summary", "--format", "json", "--columns", 16,
                            *flags))[0]
    p = stabound.passivity(3.0, 1, plane="delta-beta", alpha=0.5, columns=16, **kw)
    for key in ("passive_area", "stable_area", "passive_share_of_stable",
                "stable_share_of_passive", "passive_share_error", "passive_share_bound"):
        assert getattr(p, key) == out[key], key
    assert p.inside and out["inside"] == "yes"
    w = p.stable_not_passive
    assert (w.delta, w.beta) == (out["stable_not_passive_delta"], out["stable_not_passive_beta"])


@pytest.mark.parametrize("args,kw", [
    (["--delta", 0.5, "--d", 2], dict(delta=0.5, d=2)),
    (["--delta", 1, "--d", 1, "--filter-pole", 0.8, "--columns", 16],
     dict(delta=1.0, d=1, filter_pole=0.8, columns=16)),
    (["--plane", "delta-beta", "--alpha", 0.3, "--d", 1, "--delta", 2, "--columns", 8],
     dict(plane="delta-beta", alpha=0.3, d=1, delta=2.0, columns=8)),
    (["--plane", "delta-beta", "--alpha", 0.3, "--d", 2, "--velocity-filter-samples", 2,
      "--columns", 8], dict(plane="delta-beta", alpha=0.3, d=2, velocity_filter_samples=2, columns=8)),
])
def test_region_rows_match_cli(cli_ok, args, kw):
    got = rows(cli_ok("passivity", "--tol", 1e-6, *args))
    p = stabound.passivity(tol=1e-6, **kw)
    x = "alpha" if p.plane == "alpha-beta" else "delta"
    passive = [r for r in got if r["region"] == "passive"]
    assert [float(r[x]) for r in passive] == p.x.tolist()
    assert [float(r["beta"]) for r in passive] == p.y.tolist()
    assert [float(r["theta"]) for r in passive] == p.theta.tolist()
    assert [r["edge"] for r in passive] == p.edge.tolist()
    stable = [r for r in got if r["region"] == "stable"]
    assert {r["edge"] for r in stable} == {p.stable_points}
    assert all(same(num(r[x]), v) for r, v in zip(stable, p.stable_x.tolist()))
    assert all(same(num(r["beta"]), v) for r, v in zip(stable, p.stable_y.tolist()))
    assert len(stable) == len(p.stable_x)


def test_published_values():
    s2 = math.sqrt(2.0)
    # d = 0: Colgate's triangle delta > alpha/2 + |beta| (eq. 21), largest stiffness 2 delta
    # (within the default tol = 1e-7, twice for the golden-section search over beta)
    p = stabound.passivity(0.5, 0)
    assert abs(p.alpha_max_passive - 1.0) < 2e-7 and abs(p.passive_area - 0.5) < 1e-6
    # d = 1: (2 sqrt 2 - 2) delta at beta = (1 - 1/sqrt 2) delta
    p = stabound.passivity(2.0, 1, beta=0.0)
    assert abs(p.alpha_max_passive - 2.0 * (2 * s2 - 2)) < 1e-6
    # Diolaiti et al.: at beta = 0, alpha < 2 delta / (1 + 2 d)
    assert abs(p.alpha_max_at_beta - 4.0 / 3.0) < 1e-6


def cli_message(cli, *args):
    code, out, err = cli(*args)
    assert code == 2, (out, err)
    msg = err.strip().splitlines()[-1][len("error: "):]
    if msg.startswith("--") and ": " in msg:
        msg = msg.split(": ", 1)[1]
    return msg


@pytest.mark.parametrize("kw,args", [
    (dict(delta=1.0, d=0.5), ["--delta", 1, "--d", 0.5]),
    (dict(delta=-1.0, d=1), ["--delta", -1, "--d", 1]),
    (dict(delta=1.0, d=1, tol=0.0), ["--delta", 1, "--d", 1, "--tol", 0]),
    (dict(delta=1.0, d=1, filter_pole=1.0), ["--delta", 1, "--d", 1, "--filter-pole", 1]),
    (dict(delta=1.0, d=1, filter_pole=0.5, columns=1),
     ["--delta", 1, "--d", 1, "--filter-pole", 0.5, "--columns", 1]),
])
def test_value_errors_carry_the_library_message(cli, kw, args):
    with pytest.raises(ValueError) as e:
        stabound.passivity(**kw)
    assert str(e.value) == cli_message(cli, "passivity", *args)


@pytest.mark.parametrize("kw,match", [
    (dict(delta=1.0, filter_pole=0.5, velocity_filter_samples=2), "one velocity filter"),
    (dict(delta=1.0, velocity_filter_cutoff=30.0), "period="),
    (dict(delta=1.0, alpha=0.5), "alpha= belongs"),
    (dict(plane="delta-beta"), "missing alpha="),
    (dict(plane="delta-beta", alpha=0.5, beta=0.1), "beta= belongs"),
    (dict(delta=1.0, plane="alpha_beta"), "invalid plane"),
    (dict(), "missing delta"),
    (dict(delta=1.0, columns=2.5), "whole number"),
    (dict(delta=1.0, velocity_filter_samples=-3), "whole number"),
    (dict(delta=1.0, mass=1.0), "period="),
    (dict(delta=1.0, mass=-1.0, period=0.001), "mass"),
    (dict(delta=float("nan")), "delta"),
])
def test_bad_input(kw, match):
    with pytest.raises(ValueError, match=match):
        stabound.passivity(**kw)


def test_amax_margin_matches_cli(cli_ok):
    got = rows(cli_ok("amax", "--delta", "0,0.5", "--d", 1, "--margin", 0.75))
    r = stabound.alpha_max([0.0, 0.5], 1.0, margin=0.75)
    assert [float(g["alpha_margin"]) for g in got] == r.alpha_margin.tolist()
    assert [float(g["beta_margin"]) for g in got] == r.beta_margin.tolist()
    got = rows(cli_ok("amax", "--mass", 1, "--period", 0.001, "--damping", "0,1",
                      "--delay-samples", 1, "--margin", 0.75))
    r = stabound.alpha_max(mass=1.0, period=0.001, damping=[0.0, 1.0], delay_samples=1, margin=0.75)
    assert [float(g["K_margin_N_per_m"]) for g in got] == r.stiffness_margin.tolist()
    assert [float(g["alpha_margin"]) for g in got] == r.alpha_margin.tolist()
    for bad in (0.0, 1.5, float("nan")):
        with pytest.raises(ValueError, match="fraction"):
            stabound.alpha_max(0.0, 1.0, margin=bad)


def test_old_argument_names_still_work():
    new = stabound.check(0.1, 0.3, 0.5, 1.0, marginal_band=1e-3)
    with pytest.warns(DeprecationWarning, match="marginal_band"):
        old = stabound.check(0.1, 0.3, 0.5, 1.0, margin=1e-3)
    assert old == new
    with pytest.warns(DeprecationWarning, match="theta_tol"):
        assert stabound.alpha_max(0.5, 1.0, tol=1e-9) == stabound.alpha_max(0.5, 1.0, theta_tol=1e-9)
    with pytest.raises(ValueError, match="old name"):
        stabound.alpha_max(0.5, 1.0, tol=1e-9, theta_tol=1e-9)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        stabound.check(0.1, 0.3, 0.5, 1.0)
        stabound.alpha_max(0.5, 1.0)
    assert stabound.DEFAULT_MARGIN == stabound.DEFAULT_MARGINAL_BAND
    assert stabound.DEFAULT_AMAX_TOL == stabound.DEFAULT_THETA_TOL


def test_figures_match_cli_files(cli_ok, tmp_path):
    cli_ok("figure", 10, "-o", tmp_path)
    f = stabound.figure(10)
    assert f.name == "fig10"
    assert f.svg == (tmp_path / "fig10.svg").read_text()
    assert f.csv == (tmp_path / "fig10.csv").read_text()
    cli_ok("passivity", "--figures-dir", tmp_path / "companions")
    for name in ("fig08-d2", "fig09-d4"):
        g = stabound.figure(name)
        assert g.svg == (tmp_path / "companions" / f"{name}.svg").read_text()
        assert g.csv == (tmp_path / "companions" / f"{name}.csv").read_text()
    for bad in (4, -1, "fig08-d3", True, 2.5):
        with pytest.raises(ValueError):
            stabound.figure(bad)
