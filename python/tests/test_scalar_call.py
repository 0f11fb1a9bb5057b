"""One wall given as four Python floats takes a short path through the compiled core; every
answer and every refusal must be the one the general (broadcasting) path gives."""

import math
import random

import numpy as np
import pytest

import stabound


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
