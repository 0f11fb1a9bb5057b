"""One wall given as four Python floats takes a short path through the compiled core; every
answer and every refusal must be the one the general (broadcasting) path gives."""

import math
import random

import numpy as np
import pytest

import stabound
from conftest import rows


def general(*args, **kw):
    # numpy scalars are not exact Python floats: they take the broadcasting path
    return stabound.check(*(np.float64(a) for a in args), **kw)


def walls():
    rng = random.Random(20261202)
    rows = []
    for _ in range(400):
        delta = 10 ** rng.uniform(-4, 1)
        d = rng.choice([0.0, 0.5, 1.0, 2.0, 3.7, 10.0, rng.uniform(0, 20)])
        a = stabound.alpha_max(delta, d)
        # around the boundary and well away from it, both signs of beta
        alpha = a.alpha_max * rng.choice([0.0, 0.3, 0.999, 1.0, 1.001, 3.0])
        beta = rng.choice([a.beta_at_max, -a.beta_at_max, rng.uniform(-5, 5)])
        rows.append((alpha, beta, delta, d))
    return rows


@pytest.mark.parametrize("band", [None, 1e-3])
@pytest.mark.parametrize("radius", [False, True])
@pytest.mark.parametrize("method", ["auto", "schur-cohn", "eigen"])
def test_scalar_floats_answer_as_the_general_path(radius, method, band):
    seen = set()
    kw = dict(method=method, radius=radius, marginal_band=band)
    for w in walls():
        fast = stabound.check(*w, **kw)
        slow = general(*w, **kw)
        assert type(fast) is type(slow) is stabound.CheckResult
        assert fast.verdict == slow.verdict and fast.code == slow.code
        assert fast.stable is slow.stable and fast.method == slow.method
        assert type(fast.code) is type(slow.code) is int
        if radius:
            assert fast.spectral_radius == slow.spectral_radius  # the same computation, bit for bit
        else:
            assert math.isnan(fast.spectral_radius) and math.isnan(slow.spectral_radius)
        seen.add(fast.verdict)
    assert seen == {"stable", "marginal", "unstable"}


@pytest.mark.parametrize(
    "wall",
    [
        (float("nan"), 0.1, 0.5, 1.0),
        (0.1, float("inf"), 0.5, 1.0),
        (0.1, 0.3, -0.5, 1.0),
        (0.1, 0.3, 0.5, -1.0),
        (0.1, 0.3, 1e300, 1.0),
        (0.1, 0.3, 0.5, 1e9),
    ],
)
def test_scalar_floats_are_refused_as_the_general_path_refuses(wall):
    with pytest.raises(ValueError) as fast:
        stabound.check(*wall)
    with pytest.raises(ValueError) as slow:
        general(*wall)
    assert str(fast.value) == str(slow.value)


def test_scalar_result_is_a_named_tuple_of_python_scalars():
    r = stabound.check(0.1, 0.3, 0.5, 1.0)
    assert r == (r.spectral_radius, "stable", 0, True, r.method)
    assert r._fields == stabound.CheckResult._fields
    assert isinstance(r.spectral_radius, float) and r.spectral_radius < 1
    assert r.method in stabound.METHODS


def _fields(r):
    # a result's fields with the radius as its bits (NaN compares unequal to itself)
    return (repr(r.spectral_radius), r.verdict, r.code, r.stable, r.method)


CLI_METHODS = ["auto", "schur-cohn", "eigen", "state-space", "argument-principle"]


def test_verdict_only_results_are_those_of_arrays_and_the_command_line(cli_ok, tmp_path):
    # one scalar call per wall against one array call (the verdict and method names come from
    # numpy arrays of codes there) and against `stabound check --batch` (no radius by
    # default), whose words the command line writes itself
    ws = walls()[:120]
    batch = tmp_path / "walls.csv"
    batch.write_text("alpha,beta,delta,d\n" + "".join(",".join(map(repr, w)) + "\n" for w in ws))
    seen = set()
    for method in CLI_METHODS:
        cols = [np.array(c) for c in zip(*ws)]
        arr = stabound.check(*cols, method=method, radius=False)
        out = rows(cli_ok("check", "--batch", batch, "--method", method))
        assert "spectral_radius" not in out[0]
        assert len(out) == len(ws)
        for i, w in enumerate(ws):
            r = stabound.check(*w, method=method, radius=False)
            assert type(r) is stabound.CheckResult
            assert (r.verdict, r.code, r.stable, r.method) == (
                arr.verdict[i], arr.code[i], arr.stable[i], arr.method[i])
            assert (r.verdict, r.method) == (out[i]["verdict"], out[i]["method"])
            assert type(r.code) is int and type(r.stable) is bool and math.isnan(r.spectral_radius)
            seen.add((r.verdict, r.method))
    assert {v for v, _ in seen} == {"stable", "marginal", "unstable"}
    assert {m for _, m in seen} >= {"schur-cohn", "eigen", "state-space", "argument-principle"}


@pytest.mark.parametrize("radius", [False, True])
def test_scalar_result_behaves_as_a_named_tuple(radius):
    import copy
    import pickle

    w = (0.1, 0.3, 0.5, 1.0)
    r = stabound.check(*w, radius=radius)
    radius_value, verdict, code, stable, method = r  # unpacking
    assert (verdict, code, stable, method) == ("stable", 0, True, r.method)
    assert isinstance(r, tuple) and len(r) == 5 and r[1] == r.verdict == r[-4]
    assert r._fields == ("spectral_radius", "verdict", "code", "stable", "method")
    assert r._asdict()["verdict"] == "stable"
    assert repr(r) == (f"CheckResult(spectral_radius={radius_value!r}, verdict='stable', code=0, "
                       f"stable=True, method={method!r})")
    assert math.isnan(radius_value) is not radius
    for back in (pickle.loads(pickle.dumps(r)), copy.deepcopy(r), stabound.CheckResult(*r)):
        assert type(back) is stabound.CheckResult and _fields(back) == _fields(r)
    assert r._replace(verdict="x").verdict == "x" and r.verdict == "stable"
    with pytest.raises(AttributeError):
        r.verdict = "unstable"
    assert hash(r) == hash(tuple(r))
    # equality as tuples: a result equals itself and a plain tuple of its very items
    assert r == r and r == tuple(r) and not r != tuple(r)
    u = stabound.check(5.0, 0.3, 0.5, 1.0, radius=radius)
    assert u.verdict == "unstable" and u != r


def test_verdict_only_scalar_results_are_shared_per_verdict_and_method():
    a = stabound.check(0.1, 0.3, 0.5, 1.0, radius=False)
    b = stabound.check(0.2, 0.3, 0.5, 1.0, radius=False)
    c = stabound.check(0.1, 0.3, 0.5, 1.0, radius=False, method="eigen")
    assert a is b and a == b  # the same verdict and method: one immutable object
    assert c is not a and c != a and (c.verdict, c.method) == ("stable", "eigen")
    # with the radius every result is its own
    x, y = stabound.check(0.1, 0.3, 0.5, 1.0), stabound.check(0.2, 0.3, 0.5, 1.0)
    assert x is not y and x.spectral_radius != y.spectral_radius


@pytest.mark.parametrize("spelled", ["schur_cohn", "state_space", "argument_principle"])
def test_method_names_take_underscores_for_hyphens(spelled):
    w = (0.1, 0.3, 0.5, 1.0)
    assert stabound.check(*w, method=spelled) == stabound.check(*w, method=spelled.replace("_", "-"))


@pytest.mark.parametrize("bad", ["jury", "", "Auto", "schur__cohn", "schur-coh", "auto ", "eigen_"])
def test_unknown_method_names_are_refused_with_the_list(bad):
    expected = ("invalid method = '" + bad + "': expected one of "
                + ", ".join(f"'{m}'" for m in stabound.METHODS))
    for w in [(0.1, 0.3, 0.5, 1.0), (np.float64(0.1), 0.3, 0.5, 1.0)]:
        with pytest.raises(ValueError) as e:
            stabound.check(*w, method=bad)
        assert str(e.value) == expected


def test_default_band_is_the_library_default():
    # walls whose radius is just inside 1: inside the default band they are marginal, outside
    # a narrower one stable; the default must act as DEFAULT_MARGINAL_BAND given explicitly
    delta, d = 0.5, 1.0
    a = stabound.alpha_max(delta, d)
    for f in (1 - 1e-12, 1 - 1e-10, 1 - 1e-8, 0.5):
        w = (a.alpha_max * f, a.beta_at_max, delta, d)
        r = stabound.check(*w)
        assert r == stabound.check(*w, marginal_band=stabound.DEFAULT_MARGINAL_BAND)
        assert r == stabound.check(*(np.float64(x) for x in w))
