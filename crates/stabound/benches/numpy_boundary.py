#!/usr/bin/env python3
"""The straightforward vectorized numpy way to the same boundary, for comparison.

Request: the stability boundary in the (alpha, beta) plane for delta = 0.5, d = 1
(`stabound boundary --delta 0.5 --d 1`). Method: column-wise bisection. For each of
COLUMNS values of alpha, a coarse column of BETAS values of beta is tested with batched
companion-matrix eigenvalues (numpy.linalg.eigvals on a stack of matrices); every
stable/unstable change along a column is then bisected in beta, all columns at once, until
the bracket is below TOL. The characteristic polynomial is built from docs/MODEL.md section 3
independently of the Rust code.

Usage: python3 benches/numpy_boundary.py [--tol 1e-6] [--repeat 5]
Prints the median wall time and the number of boundary points.
"""
import argparse
import math
import statistics
import time

import numpy as np


def char_poly_parts(delta, d):
    """Q0, QA, QB coefficients (highest power first) of q = Q0 + alpha QA + beta QB."""
    n = int(math.floor(d))
    eps = d - n

    def phi1(t):
        return t if delta == 0 else -math.expm1(-delta * t) / delta

    def phi2(t):
        return t * t / 2 if delta == 0 else (t - phi1(t)) / delta

    c = math.exp(-delta)
    p1 = phi1(1.0)
    g0x, g0v = phi2(1 - eps), phi1(1 - eps)
    g1x = phi2(eps) + phi1(1 - eps) * phi1(eps)
    g1v = math.exp(-delta * (1 - eps)) * phi1(eps)
    # M(z) = N0 z + N1 = m2 z^2 + m1 z + m0
    m = np.array([g0x, p1 * g0v - c * g0x + g1x, p1 * g1v - c * g1x])
    q0 = np.polymul(np.r_[1.0, np.zeros(n + 2)], np.polymul([1.0, -1.0], [1.0, -c]))
    qa = np.polymul([1.0, 0.0], m)
    qb = np.polymul([1.0, -1.0], m)
    deg = len(q0) - 1
    qa = np.r_[np.zeros(deg + 1 - len(qa)), qa]
    qb = np.r_[np.zeros(deg + 1 - len(qb)), qb]
    if eps == 0:  # common factor z
        q0, qa, qb = q0[:-1], qa[:-1], qb[:-1]
    return q0, qa, qb


def spectral_radius(parts, alpha, beta):
    """Largest root modulus for arrays alpha, beta (same shape), by batched eigvals."""
    q0, qa, qb = parts
    coef = q0 + alpha[..., None] * qa + beta[..., None] * qb  # monic, highest first
    deg = coef.shape[-1] - 1
    comp = np.zeros(alpha.shape + (deg, deg))
    comp[..., 0, :] = -coef[..., 1:]
    comp[..., np.arange(1, deg), np.arange(0, deg - 1)] = 1.0
    return np.abs(np.linalg.eigvals(comp)).max(axis=-1)


def boundary(delta, d, tol, alpha_hi=1.2, beta_lo=-1.0, beta_hi=2.0, columns=400, betas=400):
    """Boundary points of the window (0, alpha_hi] x [beta_lo, beta_hi]; the default window
    fits delta = 0.5, d = 1 (alpha_max = 0.466, margin included)."""
    parts = char_poly_parts(delta, d)
    alpha = np.linspace(1e-6, alpha_hi, columns)
    beta = np.linspace(beta_lo, beta_hi, betas)
    A, B = np.meshgrid(alpha, beta, indexing="ij")
    stable = spectral_radius(parts, A, B) < 1.0
    i, j = np.nonzero(stable[:, :-1] != stable[:, 1:])
    lo, hi = beta[j], beta[j + 1]
    s_lo = stable[i, j]
    a = alpha[i]
    while (hi - lo).max(initial=0.0) > tol:
        mid = 0.5 * (lo + hi)
        s = spectral_radius(parts, a, mid) < 1.0
        same = s == s_lo
        lo = np.where(same, mid, lo)
        hi = np.where(same, hi, mid)
    return np.c_[a, 0.5 * (lo + hi)]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--tol", type=float, default=1e-6)
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args()
    times = []
    for _ in range(args.repeat):
        t = time.perf_counter()
        pts = boundary(0.5, 1.0, args.tol)
        times.append(time.perf_counter() - t)
    print(f"numpy column-wise bisection, delta 0.5 d 1, tol {args.tol:g}: "
          f"median {statistics.median(times) * 1e3:.1f} ms over {args.repeat} runs, "
          f"{len(pts)} points, alpha_max found {pts[:, 0].max():.4f}")


if __name__ == "__main__":
    main()
