#!/usr/bin/env python3
"""An independent high-precision check of alpha_max answers: is the wall a relative 1e-6
below alpha_max, at the answer's damping, strictly stable, and if not, does any damping
within the beta limits stabilize that stiffness?

Independent of stabound's code: everything is rebuilt here from docs/MODEL.md at 50
significant digits with mpmath. The device's continuous model (one mass, optionally an
operator's hand, section 8), its zero-order-hold discretization with the delay d = n + eps
by mpmath's matrix exponential of the augmented matrix (Van Loan 1978), the velocity
filter (first-order low-pass w_k = a w_{k-1} + (1 - a)(y_k - y_{k-1}), or the second-order
Butterworth of scipy.signal.butter(2, 2 f_c T), designed here from tan(pi f_c T)), and the
closed loop's state matrix assembled column by column from the difference equations
themselves (state: device, held past forces, past position, past filter inputs and
outputs). Its spectral radius comes from mpmath's eigenvalues (QR at 50 digits), seconded by
the roots of its characteristic polynomial det(zI - M), interpolated from determinants at
the roots of unity.

Where the answer's wall is not stable, the stable dampings at that stiffness are found
exactly on the line: the dampings where a root crosses the unit circle are
beta = -P(z) / QB(z) at the unimodular roots of z^N (P(z) QB(1/z) - P(1/z) QB(z)) (P the
polynomial at beta = 0, QB its beta part), and each piece between them is decided at its
middle by the polynomial's roots.

Usage: rows in the sweep's own output format on stdin, e.g.

    cargo run --release -p stabound --example amax_sweep > sweep.txt
    grep NOT-STABLE sweep.txt | python3 tools/amax_oracle.py

Each row is printed with the oracle's radius at (alpha_max (1 - 1e-6), beta_at_max) and a
verdict: "stable" (the wall is strictly stable: a check that called it unstable erred),
"other-damping" (that wall is unstable, another damping within the limits is stable: the
answer's damping is off), "none" (no damping within the limits stabilizes that stiffness:
the answer is wrong). Needs mpmath (pip install mpmath)."""

import math
import re
import sys

import mpmath as mp

mp.mp.dps = 50

#: The operator hands of the sweep: mu_h -> (mu_h, delta_h, kappa_h).
HANDS = {"0.5": ("0.5", "0.2", "0"), "2.4121": ("2.4121", "0.624", "0.131521")}


def f(x):
    """A double (given as its shortest decimal, as Rust prints it) exactly, as an mpf."""
    return mp.mpf(float(x))


def device(delta, hand):
    """A, b of the one-mass device (states y, v), with the operator's hand if any."""
    mu, dh, kh = (f(x) for x in hand) if hand else (mp.mpf(0), mp.mpf(0), mp.mpf(0))
    m = 1 + mu
    a = mp.matrix([[0, 1], [-kh / m, -(delta + dh) / m]])
    return a, [mp.mpf(0), 1 / m]


def hold(a, b, tau):
    """e^{A tau} and Gamma(tau) = integral_0^tau e^{A s} b ds, from the augmented exponential."""
    s = a.rows
    aug = mp.zeros(s + 1, s + 1)
    for i in range(s):
        for j in range(s):
            aug[i, j] = a[i, j] * tau
        aug[i, s] = b[i] * tau
    e = mp.expm(aug)
    phi = mp.matrix([[e[i, j] for j in range(s)] for i in range(s)])
    return phi, [e[i, s] for i in range(s)]


def filter_coefficients(kind, value):
    """(num, den) of F in powers of z^-1, den[0] = 1."""
    if kind is None:
        return [mp.mpf(1)], [mp.mpf(1)]
    if kind == "low-pass":
        a = f(value)
        return [1 - a], [mp.mpf(1), -a]
    # bilinear transform prewarped at the cutoff: K = tan(pi f_c T)
    k = mp.tan(mp.pi * f(value))
    s2 = mp.sqrt(2)
    norm = 1 + s2 * k + k * k
    g = k * k / norm
    return [g, 2 * g, g], [mp.mpf(1), 2 * (k * k - 1) / norm, (1 - s2 * k + k * k) / norm]


class Loop:
    """The closed loop of one row: M(alpha, beta) = M0 + alpha MA + beta MB."""

    def __init__(self, delta, d, hand=None, filt=(None, None)):
        a, b = device(f(delta), hand)
        d = f(d)
        self.n = int(mp.floor(d))
        eps = d - self.n
        self.phi, _ = hold(a, b, 1)
        self.g0 = hold(a, b, 1 - eps)[1]
        e1, _ = hold(a, b, 1 - eps)
        gam = hold(a, b, eps)[1]
        self.g1 = [sum(e1[i, j] * gam[j] for j in range(2)) for i in range(2)]
        self.num, self.den = filter_coefficients(*filt)
        self.p, self.q = len(self.num) - 1, len(self.den) - 1
        self.dim = 2 + (self.n + 1) + 1 + self.p + self.q
        m0 = self.matrix(0, 0)
        ma, mb = self.matrix(1, 0) - m0, self.matrix(0, 1) - m0
        self.m = (m0, ma, mb)
        self.poly = tuple(self.charpoly(x) for x in (m0, m0 + ma, m0 + mb))

    def step(self, s, alpha, beta):
        """The next state from state s, by the difference equations."""
        n, p, q = self.n, self.p, self.q
        x, us = s[0:2], s[2 : 3 + n]
        yprev = s[3 + n]
        es, ws = s[4 + n : 4 + n + p], s[4 + n + p : 4 + n + p + q]
        y = x[0]
        e = y - yprev
        w = self.num[0] * e + sum(self.num[i] * es[i - 1] for i in range(1, p + 1))
        w -= sum(self.den[j] * ws[j - 1] for j in range(1, q + 1))
        u = -(alpha * y + beta * w)
        cur = [u] + list(us)  # cur[i] = u_{k-i}
        nx = [
            sum(self.phi[i, j] * x[j] for j in range(2)) + self.g0[i] * cur[n] + self.g1[i] * cur[n + 1]
            for i in range(2)
        ]
        return nx + cur[: n + 1] + [y] + ([e] + list(es))[:p] + ([w] + list(ws))[:q]

    def matrix(self, alpha, beta):
        m = mp.zeros(self.dim, self.dim)
        for j in range(self.dim):
            col = self.step([mp.mpf(1 if i == j else 0) for i in range(self.dim)], alpha, beta)
            for i in range(self.dim):
                m[i, j] = col[i]
        return m

    def charpoly(self, m):
        """det(zI - m), highest power first, interpolated at the roots of unity."""
        big = self.dim + 1
        vals = []
        for k in range(big):
            z = mp.expjpi(mp.mpf(2 * k) / big)
            vals.append(det(z * mp.eye(self.dim) - m))
        coeffs = []
        for j in range(big):  # coefficient of z^j
            c = sum(vals[k] * mp.expjpi(-mp.mpf(2 * j * k) / big) for k in range(big)) / big
            coeffs.append(mp.re(c))
        coeffs[self.dim] = mp.mpf(1)  # monic, exactly
        # the interpolation leaves about 1e-50 of the largest coefficient where the true one
        # is 0 (the extra roots at z = 0 of the non-minimal state); 1e-40 is far above that
        # and far below any true coefficient of these loops
        top = max(abs(c) for c in coeffs)
        coeffs = [c if abs(c) > mp.mpf(10) ** (-40) * top else mp.mpf(0) for c in coeffs]
        return coeffs[::-1]

    def coefficients(self, alpha, beta):
        q0, qa, qb = self.poly
        return [c0 + alpha * (ca - c0) + beta * (cb - c0) for c0, ca, cb in zip(q0, qa, qb)]

    def radius_eig(self, alpha, beta):
        m0, ma, mb = self.m
        ev = mp.eig(m0 + alpha * ma + beta * mb, left=False, right=False)
        return max(abs(z) for z in ev)

    def radius_poly(self, alpha, beta):
        return max(abs(z) for z in roots(self.coefficients(alpha, beta)))

    def crossings(self, alpha):
        """The dampings where a root of q crosses the unit circle at stiffness alpha."""
        q0, qa, qb = self.poly
        pz = [c0 + alpha * (ca - c0) for c0, ca in zip(q0, qa)]
        rb = [cb - c0 for c0, cb in zip(q0, qb)]
        deg = len(pz) - 1
        # z^deg (P(z) R(1/z) - P(1/z) R(z)), coefficients highest first
        s = [mp.mpf(0)] * (2 * deg + 1)
        for i, pc in enumerate(pz):  # pc is the coefficient of z^(deg - i)
            for j, rc in enumerate(rb):
                # P(z) R(1/z): z^(deg-i) z^-(deg-j) -> z^(deg + (deg - i) - (deg - j)) after z^deg
                s[2 * deg - (deg + j - i)] += pc * rc
                s[2 * deg - (deg + i - j)] -= pc * rc
        while s and s[0] == 0:
            s.pop(0)
        out = []
        for z0 in (mp.mpf(1), mp.mpf(-1)):
            rv = mp.polyval(rb, z0)
            if rv != 0:
                out.append(-mp.polyval(pz, z0) / rv)
        if len(s) > 1:
            for z in roots(s):
                if abs(abs(z) - 1) < mp.mpf(10) ** (-20) and abs(mp.im(z)) > mp.mpf(10) ** (-30):
                    rv = mp.polyval(rb, z)
                    if rv != 0:
                        out.append(mp.re(-mp.polyval(pz, z) / rv))
        return sorted(set(out))

    def stable_dampings(self, alpha, lo, hi):
        """The pieces of [lo, hi] between crossings whose middles are strictly stable, with
        the radius at each middle."""
        cuts = [c for c in self.crossings(alpha) if lo < c < hi]
        ends = [lo] + cuts + [hi]
        found = []
        for a, b in zip(ends, ends[1:]):
            if mp.isinf(a) and mp.isinf(b):
                mid = mp.mpf(0)
            elif mp.isinf(a):
                mid = b - 1 - abs(b)
            elif mp.isinf(b):
                mid = a + 1 + abs(a)
            else:
                mid = (a + b) / 2
            rho = self.radius_poly(alpha, mid)
            if rho < 1:
                found.append((a, b, mid, rho))
        return found


def det(m):
    """mp.det, with 0 for an exactly singular matrix: at z = 1 with the device's free
    integrator (no physical damping) a column has no nonzero pivot, and mpmath 1.3's LU then
    fails with a TypeError instead of returning 0."""
    try:
        return mp.det(m)
    except (TypeError, ZeroDivisionError):
        return mp.mpf(0)


def roots(coeffs):
    """All roots, at the working precision (clusters near z = 1 need extra)."""
    while coeffs and coeffs[-1] == 0 and len(coeffs) > 1:
        coeffs = coeffs[:-1]  # roots at 0: moduli 0, never the largest
    if len(coeffs) < 2:
        return [mp.mpf(0)]
    return mp.polyroots(coeffs, maxsteps=400, extraprec=3 * mp.mp.prec)


ROW = re.compile(
    r"^(?P<family>[^|]+?) \| delta (?P<delta>\S+) \| d (?P<d>\S+) \| beta (?P<lo>\S+)\.\.(?P<hi>\S+) \| "
    r"(?P<how>direct|fallback) (?P<a>\S+) at (?P<b>\S+)"
)


def limit(text, default):
    m = re.fullmatch(r"Some\((\S+)\)", text)
    return f(m.group(1)) if m else default


def loop_of(family, delta, d):
    hand, filt = None, (None, None)
    for part in family.split(" + "):
        kind, _, value = part.rpartition(" ")
        if part == "bare":
            continue
        if kind == "hand":
            hand = HANDS[value]
        elif kind in ("low-pass", "butterworth"):
            filt = (kind, value)
        else:
            raise ValueError(f"unknown element {part!r}")
    return Loop(delta, d, hand, filt)


def check(line):
    m = ROW.match(line)
    if not m:
        return None
    lp = loop_of(m["family"], m["delta"], m["d"])
    a, b = float(m["a"]), float(m["b"])
    below = mp.mpf(a * (1.0 - 1e-6))  # the same double as the sweep's
    beta = mp.mpf(b)
    rho = lp.radius_eig(below, beta)
    rho_p = lp.radius_poly(below, beta)
    lo, hi = limit(m["lo"], -mp.inf), limit(m["hi"], mp.inf)
    if rho < 1 and rho_p < 1:
        verdict, extra = "stable", ""
    else:
        pieces = lp.stable_dampings(below, lo, hi)
        if pieces:
            best = min(pieces, key=lambda p: p[3])
            verdict = "other-damping"
            extra = f" | stable at beta {mp.nstr(best[2], 17)} radius {mp.nstr(best[3], 20)}"
        else:
            verdict, extra = "none", ""
    head = " | ".join(x.strip() for x in line.split("|")[:5])
    return f"{head} | oracle radius {mp.nstr(rho, 20)} (roots {mp.nstr(rho_p, 20)}) | {verdict}{extra}"


def main():
    for line in sys.stdin:
        out = check(line.rstrip("\n"))
        if out:
            print(out, flush=True)


if __name__ == "__main__":
    main()
