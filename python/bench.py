"""Cost of stabound's point test and alpha_max from Python, against python-control and numpy.

    pip install ./python control    # control is needed only here
    python python/bench.py [N]      # N inputs (default 100000)

For the same random walls (alpha, beta, delta) at one sample of delay (d = 1, polynomials
of degree 4), it times:

* ``stabound.check`` on all N points (verdict and spectral radius, all cores, GIL released),
  and with ``radius=False`` (verdict only);
* python-control: the closed loop as a discrete transfer function ``tf(1, q, dt=1)`` with the
  characteristic polynomial ``q(z)`` of the model document (section 3), then ``poles()``,
  on a sample of points, scaled to N;
* numpy: ``eigvals`` of the companion matrix of ``q``, one call per point (a sample, scaled)
  and one batched call on all N stacked matrices;
* ``stabound.alpha_max`` on N values of delta (d = 1). python-control and numpy have no
  alpha_max; the figure given for them is what a search built on their root finder would
  cost at the same per-call price: a grid of 64 betas times 40 bisection steps on alpha
  (about 1e-12 relative) is 2560 root computations per value, and even that only finds the
  maximum to the grid's resolution in beta.

It also checks that the three agree on the verdict (away from the unit circle).
"""

import math
import os
import sys
import time

import numpy as np

# This script sits beside the source package python/stabound (which has no compiled module):
# import the installed package instead.
if sys.path and os.path.abspath(sys.path[0]) == os.path.dirname(os.path.abspath(__file__)):
    sys.path.pop(0)

import stabound  # noqa: E402


def q_coefficients(alpha, beta, delta, d):
    """q(z), highest power first (the model document, section 3)."""
    n = math.floor(d)
    eps = d - n

    def phi1(t):
        return t if delta == 0 else -math.expm1(-delta * t) / delta

    def phi2(t):
        return t * t / 2 if delta == 0 else (t - phi1(t)) / delta

    c = math.exp(-delta)
    g0x, g0v = phi2(1 - eps), phi1(1 - eps)
    g1x, g1v = phi2(eps) + phi1(1 - eps) * phi1(eps), math.exp(-delta * (1 - eps)) * phi1(eps)
    P = np.polynomial.Polynomial
    z = P([0, 1])
    n0 = (z - c) * g0x + phi1(1) * g0v
    n1 = (z - c) * g1x + phi1(1) * g1v
    q = z ** (n + 2) * (z - 1) * (z - c) + ((alpha + beta) * z - beta) * (n0 * z + n1)
    coef = q.coef if eps else q.coef[1:]
    return coef[::-1]


def companion(coef):
    """Companion matrix of a monic polynomial (highest power first)."""
    m = len(coef) - 1
    a = np.zeros((m, m))
    a[0, :] = -np.asarray(coef[1:]) / coef[0]
    a[1:, :-1] = np.eye(m - 1)
    return a


def timed(f):
    t = time.perf_counter()
    r = f()
    return time.perf_counter() - t, r


def main():
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 100_000
    sample = min(n, 1000)
    rng = np.random.default_rng(1)
    alpha = rng.uniform(0.0, 1.0, n)
    beta = rng.uniform(-0.2, 1.0, n)
    delta = rng.uniform(0.0, 2.0, n)
    d = 1.0
    print(f"{n} inputs, d = 1 (degree 4); peers timed on {sample} and scaled")

    stabound.check(alpha[:100], beta[:100], delta[:100], d)  # warm-up
    t_check, r = timed(lambda: stabound.check(alpha, beta, delta, d))
    t_verdict, _ = timed(lambda: stabound.check(alpha, beta, delta, d, radius=False))

    coefs = [q_coefficients(alpha[i], beta[i], delta[i], d) for i in range(n)]

    import control

    def with_control():
        return [max(abs(control.tf([1.0], coefs[i], dt=1).poles())) for i in range(sample)]

    t_ctrl, rho_ctrl = timed(with_control)
    t_ctrl *= n / sample

    def eig_loop():
        return [max(abs(np.linalg.eigvals(companion(coefs[i])))) for i in range(sample)]

    t_eig, rho_eig = timed(eig_loop)
    t_eig *= n / sample
    stack = np.stack([companion(c) for c in coefs])
    t_batch, ev = timed(lambda: np.abs(np.linalg.eigvals(stack)).max(axis=1))

    for name, rho in (("control", np.array(rho_ctrl)), ("numpy", np.array(rho_eig)), ("numpy batched", ev[:sample])):
        far = np.abs(rho - 1) > 1e-6
        agree = np.mean((rho[far] < 1) == r.stable[:sample][far])
        print(f"  verdicts agree with {name}: {agree:.4f}; max |rho difference| "
              f"{np.max(np.abs(rho - r.spectral_radius[:sample])):.1e}")

    m = n
    x = rng.uniform(0.0, 2.0, m)
    stabound.alpha_max(x[:10], d)  # warm-up
    t_amax, _ = timed(lambda: stabound.alpha_max(x, d))

    us = 1e6
    print(f"check, per point ({n} points):")
    print(f"  stabound.check                 {t_check / n * us:9.3f} us")
    print(f"  stabound.check(radius=False)   {t_verdict / n * us:9.3f} us")
    print(f"  control.tf(...).poles()        {t_ctrl / n * us:9.3f} us   ({t_ctrl / t_check:.0f}x stabound)")
    print(f"  numpy eigvals, loop            {t_eig / n * us:9.3f} us   ({t_eig / t_check:.0f}x)")
    print(f"  numpy eigvals, batched         {t_batch / n * us:9.3f} us   ({t_batch / t_check:.1f}x)")
    per_ctrl, per_eig = t_ctrl / n, t_eig / n
    calls = 64 * 40
    print(f"alpha_max, per value ({m} values):")
    print(f"  stabound.alpha_max             {t_amax / m * us:9.3f} us")
    print(f"  search on control poles()      {calls * per_ctrl * us:9.1f} us   (estimate: {calls} calls, "
          f"{calls * per_ctrl / (t_amax / m):.0f}x)")
    print(f"  search on numpy eigvals loop   {calls * per_eig * us:9.1f} us   (estimate, "
          f"{calls * per_eig / (t_amax / m):.0f}x)")


if __name__ == "__main__":
    main()
