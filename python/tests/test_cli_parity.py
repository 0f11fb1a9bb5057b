"""The package against the command-line tool: same inputs, the same numbers bit for bit.

The tool prints shortest round-trip floats (Rust's `Display`, serde_json), so parsing its
text with `float` gives back the exact double it computed; `==` on floats below is exact
comparison on purpose.
"""

import csv
import io
import json
import re
import sys

import numpy as np
import pytest

import stabound
from conftest import ROOT


def rows(text):
    return list(csv.DictReader(io.StringIO(text)))


WALLS = [
    # alpha, beta, delta, d: stable, unstable, fractional delay, long delay, near alpha_max
    (0.1, 0.3, 0.5, 1.0),
    (5.0, 0.3, 0.5, 1.0),
    (0.05, 0.2, 0.1, 2.5),
    (0.01, 0.05, 0.0, 20.0),
    (0.686, 0.8284271247461776, 0.0, 0.0),
    (0.3, -0.1, 2.0, 0.0),
]


@pytest.mark.parametrize("method", ["auto", "schur-cohn", "eigen", "state-space", "argument-principle"])
def test_check_matches_cli_json(cli_ok, method):
    a, b, x, d = (np.array(c) for c in zip(*WALLS))
    r = stabound.check(a, b, x, d, method=method)
    for i, (alpha, beta, delta, dd) in enumerate(WALLS):
        out = json.loads(
            cli_ok("check", "--alpha", alpha, "--beta", beta, "--delta", delta, "--d", dd,
                   "--method", method, "--format", "json", "--radius")
        )
        assert r.spectral_radius[i] == out["spectral_radius"]
        assert r.verdict[i] == out["verdict"]
        assert r.stable[i] == out["stable"]
        assert r.method[i] == out["method"]
        full = stabound.analyze(alpha, beta, delta, dd, method=method)
        assert full["spectral_radius"] == out["spectral_radius"]
        assert full["degree"] == out["degree"]
        assert full["method"] == out["method"]
        roots = np.array(out["roots"], dtype=float)
        assert np.array_equal(full["roots"].real, roots[:, 0])
        assert np.array_equal(full["roots"].imag, roots[:, 1])


@pytest.mark.parametrize("method", ["auto", "schur-cohn", "eigen", "state-space", "argument-principle"])
def test_check_arrays_match_cli_batch(cli_ok, tmp_path, method):
    # `radius=False` is the batch's default output (verdict and method), `radius=True` its
    # `--radius` column, bit for bit
    batch = tmp_path / "walls.csv"
    batch.write_text("alpha,beta,delta,d\n" + "".join(",".join(map(repr, w)) + "\n" for w in WALLS))
    a, b, x, d = (np.array(c) for c in zip(*WALLS))
    short = rows(cli_ok("check", "--batch", batch, "--method", method))
    full = rows(cli_ok("check", "--batch", batch, "--method", method, "--radius"))
    assert list(short[0]) == ["alpha", "beta", "delta", "d", "verdict", "method"]
    assert list(full[0]) == ["alpha", "beta", "delta", "d", "verdict", "spectral_radius", "method"]
    for radius, out in ((False, short), (True, full)):
        r = stabound.check(a, b, x, d, method=method, radius=radius)
        assert r.verdict.tolist() == [o["verdict"] for o in out]
        assert r.method.tolist() == [o["method"] for o in out]
        if radius:
            assert r.spectral_radius.tolist() == [float(o["spectral_radius"]) for o in out]
        else:
            assert np.isnan(r.spectral_radius).all()


def test_check_text_spectral_radius(cli_ok):
    out = cli_ok("check", "--alpha", 0.1, "--beta", 0.3, "--delta", 0.5, "--d", 1, "--radius")
    rho = float(re.search(r"spectral radius (\S+),", out).group(1))
    assert stabound.check(0.1, 0.3, 0.5, 1.0).spectral_radius == rho
    assert out.startswith(stabound.check(0.1, 0.3, 0.5, 1.0).verdict)


def test_check_physical_matches_cli(cli_ok):
    args = dict(mass=0.1, period=0.001, damping=10.0, stiffness=14000.0, wall_damping=42.5)
    for key, val in (("delay", 0.0015), ("delay_samples", 1.0)):
        out = json.loads(
            cli_ok("check", "--mass", 0.1, "--period", 0.001, "--damping", 10.0,
                   "--stiffness", 14000.0, "--wall-damping", 42.5,
                   "--" + key.replace("_", "-"), val, "--format", "json", "--radius")
        )
        r = stabound.check(**args, **{key: val})
        assert (r.spectral_radius, r.verdict) == (out["spectral_radius"], out["verdict"])
        full = stabound.analyze(**args, **{key: val})
        for k in ("alpha", "beta", "delta", "d", "spectral_radius"):
            assert full[k] == out[k], k
        assert full["physical"] == out["physical"]


def test_amax_matches_cli_csv(cli_ok):
    deltas, ds = [0.0, 0.1, 1.0, 3.0, 10.0], [0.0, 0.5, 1.0, 2.5]
    got = rows(cli_ok("amax", "--delta", ",".join(map(str, deltas)), "--d", ",".join(map(str, ds))))
    # rows: d outer, delta inner
    x, d = np.meshgrid(deltas, ds)
    r = stabound.alpha_max(x, d)
    assert r.alpha_max.shape == (len(ds), len(deltas))
    assert [float(g["alpha_max"]) for g in got] == r.alpha_max.ravel().tolist()
    assert [float(g["beta_at_max"]) for g in got] == r.beta_at_max.ravel().tolist()


def test_amax_options_match_cli(cli_ok):
    got = rows(cli_ok("amax", "--delta", "0,5,20", "--d", "0", "--beta-min", 0, "--theta-tol", 1e-9))
    r = stabound.alpha_max([0.0, 5.0, 20.0], 0.0, beta_min=0.0, theta_tol=1e-9)
    assert [float(g["alpha_max"]) for g in got] == r.alpha_max.tolist()
    assert [float(g["beta_at_max"]) for g in got] == r.beta_at_max.tolist()


def test_amax_physical_matches_cli(cli_ok):
    got = rows(cli_ok("amax", "--mass", 0.1, "--period", 0.001, "--damping", "0,10,100",
                      "--delay", "0,0.001,0.0025"))
    b = np.array([0.0, 10.0, 100.0])
    delay = np.array([0.0, 0.001, 0.0025])[:, None]
    r = stabound.alpha_max(mass=0.1, period=0.001, damping=b, delay=delay)
    assert isinstance(r, stabound.AmaxPhysical)
    for col, arr in (("alpha_max", r.alpha_max), ("beta_at_max", r.beta_at_max),
                     ("K_max_N_per_m", r.stiffness), ("B_at_max_Ns_per_m", r.wall_damping)):
        assert [float(g[col]) for g in got] == arr.ravel().tolist(), col


@pytest.mark.parametrize("method", ["exact", "bisect"])
def test_boundary_matches_cli_csv(cli_ok, method):
    got = rows(cli_ok("boundary", "--delta", "0,0.5", "--d", "0,1", "--tol", 1e-5, "--method", method))
    curves = stabound.boundary([0.0, 0.5], [0.0, 1.0], tol=1e-5, method=method)
    assert [(c.delta, c.d) for c in curves] == [(0.0, 0.0), (0.0, 1.0), (0.5, 0.0), (0.5, 1.0)]
    at = 0
    for c in curves:
        part = got[at : at + len(c.alpha)]
        at += len(c.alpha)
        assert [float(g["alpha"]) for g in part] == c.alpha.tolist()
        assert [float(g["beta"]) for g in part] == c.beta.tolist()
        assert [g["piece"] for g in part] == c.piece.tolist()
        assert {float(g["delta"]) for g in part} == {c.delta}
    assert at == len(got)


@pytest.mark.parametrize("conservative", [False, True])
def test_table_matches_cli_every_format(cli_ok, conservative):
    extra = ["--conservative"] if conservative else []
    t = stabound.table([0.0, 0.5, 1.0, 2.0], [0.0, 1.0, 2.0], conservative=conservative)
    for fmt, text in (("csv", t.csv), ("json", t.json), ("c", t.c_header), ("rust", t.rust)):
        assert cli_ok("table", "--delta", "0,0.5,1,2", "--d", "0,1,2", "--format", fmt, *extra) == text, fmt
    got = rows(t.csv)
    assert [float(g["alpha_max"]) for g in got] == t.alpha_max.ravel().tolist()
    assert [float(g["beta_at_max"]) for g in got] == t.beta_at_max.ravel().tolist()


def test_table_physical_matches_cli(cli_ok):
    t = stabound.table(mass=0.1, period=0.001, damping=[0.0, 10.0, 100.0], delay_samples=[0.0, 1.0])
    out = cli_ok("table", "--mass", 0.1, "--period", 0.001, "--damping", "0,10,100",
                 "--delay-samples", "0,1", "--format", "c")
    assert out == t.c_header
    got = rows(cli_ok("table", "--mass", 0.1, "--period", 0.001, "--damping", "0,10,100",
                      "--delay-samples", "0,1"))
    assert [float(g["K_max_N_per_m"]) for g in got] == t.stiffness.ravel().tolist()
    assert [float(g["B_at_max_Ns_per_m"]) for g in got] == t.wall_damping.ravel().tolist()


SCENE = ROOT / "data" / "scenes" / "phantom.toml"


def test_scene_matches_cli(cli_ok):
    assert stabound.scene(SCENE) == json.loads(cli_ok("scene", SCENE, "--format", "json"))
    assert stabound.scene_text(SCENE) == cli_ok("scene", SCENE)
    assert stabound.scene(str(SCENE), marginal_band=1e-6) == json.loads(
        cli_ok("scene", SCENE, "--format", "json", "--marginal-band", 1e-6)
    )


@pytest.mark.skipif(sys.version_info < (3, 11), reason="tomllib is Python 3.11+")
def test_scene_from_dict_matches_file(cli_ok):
    import tomllib

    with open(SCENE, "rb") as f:
        as_dict = tomllib.load(f)
    assert stabound.scene(as_dict) == json.loads(cli_ok("scene", SCENE, "--format", "json"))


@pytest.mark.parametrize(
    "wall",
    [["--margin", 0.75], ["--stiffness", 20000, "--wall-damping", 30]],
)
def test_step_matches_cli(cli_ok, wall):
    args = ["--mass", 0.1, "--period", 0.001, "--damping", "0,10,100", "--delay-samples", 1,
            "--duration", 0.03, "--points-per-period", 4]
    got = rows(cli_ok("step", *args, *wall))
    kw = dict(zip([w.lstrip("-").replace("-", "_") for w in wall[::2]], wall[1::2]))
    rs = stabound.step(mass=0.1, period=0.001, damping=[0.0, 10.0, 100.0], delay_samples=1,
                       duration=0.03, points_per_period=4, **kw)
    assert len(rs) == 3
    at = 0
    for r in rs:
        part = got[at : at + len(r.time)]
        at += len(r.time)
        assert [float(g["time_s"]) for g in part] == r.time.tolist()
        assert [float(g["position_m"]) for g in part] == r.position.tolist()
        assert {float(g["stiffness_N_per_m"]) for g in part} == {r.stiffness}
        assert {float(g["wall_damping_Ns_per_m"]) for g in part} == {r.wall_damping}
    assert at == len(got)
    summary = cli_ok("step", *args, *wall, "--format", "summary").splitlines()
    assert [re.search(r"\), (\w+); final", s).group(1) for s in summary] == [r.verdict for r in rs]


def test_delta_beta_boundary_matches_cli_csv(cli_ok):
    got = rows(cli_ok("boundary", "--plane", "delta-beta", "--alpha", "0,0.5", "--d", "0,1",
                      "--delta", "0,2", "--tol", 1e-4))
    curves = stabound.boundary(plane="delta-beta", alpha=[0.0, 0.5], d=[0.0, 1.0],
                               delta=[0.0, 2.0], tol=1e-4)
    assert [(c.alpha, c.d) for c in curves] == [(0.0, 0.0), (0.0, 1.0), (0.5, 0.0), (0.5, 1.0)]
    at = 0
    for c in curves:
        part = got[at : at + len(c.delta)]
        at += len(c.delta)
        assert [float(g["delta"]) for g in part] == c.delta.tolist()
        assert [float(g["beta"]) for g in part] == c.beta.tolist()
        assert [int(float(g["loop"])) for g in part] == c.loop.tolist()
        assert [g["piece"] for g in part] == c.piece.tolist()
        assert {(float(g["alpha"]), float(g["d"])) for g in part} == {(c.alpha, c.d)}
    assert at == len(got)
