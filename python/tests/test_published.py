"""The package against independent sources: the paper's published values (model document,
section 6), the characteristic polynomial written out here from the model's formulas and
solved by numpy, and Colgate's passivity condition."""

import json
import math

import numpy as np
import pytest

import stabound


def test_alpha_max_undamped_no_delay_is_12_minus_8_sqrt2():
    r = stabound.alpha_max(0.0, 0.0)
    assert isinstance(r.alpha_max, float)
    # the search refines theta to 1e-12 rad; alpha(theta) is flat at its maximum, so alpha
    # is far more accurate than that, and 1e-11 leaves room for rounding
    assert r.alpha_max == pytest.approx(12 - 8 * math.sqrt(2), abs=1e-11)
    assert r.beta_at_max == pytest.approx(2 * math.sqrt(2) - 2, abs=1e-6)
    assert f"{r.alpha_max:.12f}" == "0.686291501015"
    # print(stabound.alpha_max(0.0, 0.0)) shows the number itself
    assert str(r).startswith("0.686291501015")
    assert "beta_at_max" in repr(r)


def test_alpha_max_one_sample_delay():
    assert round(stabound.alpha_max(0.0, 1.0).alpha_max, 4) == 0.1445


def test_section_viii_walls():
    # 75 % of alpha_max at d = 1 for delta = 0, 0.1, 1 and beta there (paper Section VIII)
    r = stabound.alpha_max([0.0, 0.1, 1.0], 1.0)
    assert np.round(0.75 * r.alpha_max, 3).tolist() == [0.108, 0.149, 0.656]
    assert np.round(r.beta_at_max, 3).tolist() == [0.425, 0.416, 0.388]


def test_scalars_in_scalars_out_arrays_keep_shape():
    assert isinstance(stabound.alpha_max(0.5, 1.0).beta_at_max, float)
    r = stabound.alpha_max(np.zeros((2, 3)), [0.0, 1.0, 2.0])
    assert r.alpha_max.shape == (2, 3) and r.beta_at_max.shape == (2, 3)
    c = stabound.check(np.linspace(0.01, 2, 12).reshape(3, 4), 0.3, [[0.0], [0.5], [1.0]], 1.0)
    assert c.spectral_radius.shape == c.verdict.shape == c.code.shape == (3, 4)


def test_boundary_rightmost_point_is_alpha_max():
    for delta, d in [(0.0, 0.0), (0.5, 1.0), (1.0, 2.0)]:
        b = stabound.boundary(delta, d, tol=1e-7)
        i = int(np.argmax(b.alpha))
        r = stabound.alpha_max(delta, d)
        assert b.alpha[i] == pytest.approx(r.alpha_max, abs=1e-6)
        # closed polyline from (0, -delta) (paper eq. 19)
        assert (b.alpha[0], b.beta[0]) == (b.alpha[-1], b.beta[-1])
        assert b.alpha[0] == 0.0 and b.beta[0] == pytest.approx(-delta, abs=1e-7)
        assert set(b.piece.tolist()) <= set(stabound.PIECES)


def q_coefficients(alpha, beta, delta, d):
    """q(z) of the model document (section 3), highest power first, for numpy.roots."""
    n = math.floor(d)
    eps = d - n

    def c(t):
        return math.exp(-delta * t)

    def phi1(t):
        return t if delta == 0 else -math.expm1(-delta * t) / delta

    def phi2(t):
        return t * t / 2 if delta == 0 else (t - phi1(t)) / delta

    g0x, g0v = phi2(1 - eps), phi1(1 - eps)
    g1x, g1v = phi2(eps) + phi1(1 - eps) * phi1(eps), c(1 - eps) * phi1(eps)
    P = np.polynomial.Polynomial
    z = P([0, 1])
    cc = c(1)
    n0 = (z - cc) * g0x + phi1(1) * g0v
    n1 = (z - cc) * g1x + phi1(1) * g1v
    q = z ** (n + 2) * (z - 1) * (z - cc) + ((alpha + beta) * z - beta) * (n0 * z + n1)
    coef = q.coef
    if eps == 0:
        coef = coef[1:]  # every term has the factor z
    return coef[::-1]


def test_spectral_radius_matches_numpy_roots_of_q():
    rng = np.random.default_rng(7)
    n = 400
    alpha = rng.uniform(0.0, 3.0, n)
    beta = rng.uniform(-0.5, 1.5, n)
    delta = rng.uniform(0.0, 3.0, n)
    d = rng.choice([0.0, 0.5, 1.0, 2.0, 3.3], n)
    r = stabound.check(alpha, beta, delta, d)
    for i in range(n):
        rho = max(abs(np.roots(q_coefficients(alpha[i], beta[i], delta[i], d[i]))))
        # low-degree polynomials with well-scaled coefficients: companion eigenvalues are
        # good to ~1e-12; 1e-8 allows for near-double roots, whose modulus loses half the digits
        assert r.spectral_radius[i] == pytest.approx(rho, rel=1e-7, abs=1e-7), i
        if abs(rho - 1) > 1e-6:
            assert r.stable[i] == (rho < 1), i


def test_passive_walls_are_stable():
    # Colgate's condition for d = 0 (paper eq. 21): delta > alpha / 2 + |beta| is passive,
    # and the passive region is a subset of the stable region.
    rng = np.random.default_rng(11)
    delta = rng.uniform(0.05, 5.0, 2000)
    alpha = rng.uniform(0.0, 1.0, 2000) * 2 * delta
    room = delta - alpha / 2
    beta = rng.uniform(-1.0, 1.0, 2000) * room * 0.999
    keep = alpha > 1e-6
    r = stabound.check(alpha[keep], beta[keep], delta[keep], 0.0)
    assert r.stable.all()


def test_the_deciding_method_is_named_as_the_command_line_names_it(cli_ok):
    # a stiffness at the top of f64: unstable, decided by the certified last stage
    r = stabound.check(1.7976931348623157e308, 0.0, 0.5, 1.0)
    out = cli_ok("check", "--alpha", "1.7976931348623157e308", "--beta", "0", "--delta", "0.5",
                 "--d", "1", "--format", "json")
    v = json.loads(out)
    assert r.verdict == v["verdict"] == "unstable"
    assert r.method == v["method"] == "certified"
