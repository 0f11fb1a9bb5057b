#!/usr/bin/env python3
"""Check a stabound stability certificate using only the Python standard library.

Usage: verify_certificate.py CERTIFICATE.json  (``-`` reads standard input), or
``python -m stabound.verify_certificate CERTIFICATE.json`` from the Python package.
Exit status 0 when the certificate's claim follows, 1 when it does not (the reason on
stderr), 2 for bad usage.

This program shares no code with the library that wrote the certificate. Model and claim
(docs/MODEL.md sections 2, 3 and 11): a mass with physical damping ``delta`` under a wall
(``alpha``, ``beta``) whose force arrives ``d = n + eps`` periods late through a hold has the
characteristic polynomial

    q(z) = z^(n+2) (z - 1)(z - c) + ((alpha + beta) z - beta) M(z),   c = exp(-delta),

divided by z when eps = 0. The checks:

1. The CRC-32 of the text before its "crc32" member matches (any changed character fails).
2. Every number is a canonical hex float, so an exact rational.
3. The coefficients of q are recomputed from the inputs in exact rational arithmetic, the
   exponential and the phi functions by their own Taylor series with the alternating-series
   remainder bound, and each claimed coefficient ball must contain them.
4. The Schur-Cohn recursion is replayed on the claimed balls in rational interval arithmetic
   (ends rounded outward to PREC bits, so that sizes stay bounded; every rounding moves an end
   outward, so the intervals still hold every true value). Every step must be decided, and
   every claimed reflection ball must contain the recomputed reflection interval.
5. The counts of roots outside the circles prove the claim.
"""

import json
import math
import re
import sys
import zlib
from fractions import Fraction as F

PREC = 200  # bits kept by the outward rounding of interval ends
TINY = F(1, 1 << (PREC + 16))  # series are summed until their terms fall below this
EXP_CUT = 1000  # exp(-x) <= exp(-1000) for x >= 1000 (far below the smallest double)


class Reject(Exception):
    """The claim does not follow from the certificate."""


def rnd(q, up):
    """q rounded to PREC significant bits, toward +inf if up else toward -inf."""
    if q == 0:
        return q
    n, d = q.numerator, q.denominator
    s = PREC - (n.bit_length() - d.bit_length())
    num, den = (n << s, d) if s >= 0 else (n, d << -s)
    m, rem = divmod(num, den)
    if up and rem:
        m += 1
    return F(m, 1 << s) if s >= 0 else F(m << -s)


class Iv:
    """A closed interval [lo, hi] with rational ends, every operation rounded outward."""

    def __init__(self, lo, hi=None):
        self.lo, self.hi = F(lo), F(lo if hi is None else hi)

    def __add__(self, o):
        return Iv(rnd(self.lo + o.lo, False), rnd(self.hi + o.hi, True))

    def __sub__(self, o):
        return Iv(rnd(self.lo - o.hi, False), rnd(self.hi - o.lo, True))

    def __neg__(self):
        return Iv(-self.hi, -self.lo)

    def __mul__(self, o):
        p = [self.lo * o.lo, self.lo * o.hi, self.hi * o.lo, self.hi * o.hi]
        return Iv(rnd(min(p), False), rnd(max(p), True))

    def __truediv__(self, o):
        if o.lo <= 0 <= o.hi:
            raise Reject("division by an interval holding 0")
        q = [self.lo / o.lo, self.lo / o.hi, self.hi / o.lo, self.hi / o.hi]
        return Iv(rnd(min(q), False), rnd(max(q), True))

    def mag(self):
        return max(abs(self.lo), abs(self.hi))

    def mig(self):
        return F(0) if self.lo <= 0 <= self.hi else min(abs(self.lo), abs(self.hi))

    def inside(self, o):
        return o.lo <= self.lo and self.hi <= o.hi


def series(x, shift):
    """sum_k (-x)^k / (k + shift)! for 0 <= x <= 1/2: the terms alternate and decrease, so
    the first omitted term bounds the tail."""
    total, term, k = F(0), F(1, math.factorial(shift)), 0
    while term > TINY:
        total += term if k % 2 == 0 else -term
        k += 1
        term = term * x / (k + shift)
    return Iv(rnd(total - term, False), rnd(total + term, True))


def exp_neg(x):
    """exp(-x) for a rational x >= 0: series at x / 2^s <= 1/8, then s squarings."""
    if x > EXP_CUT:
        return Iv(0, exp_neg(F(EXP_CUT)).hi)
    s = 0
    while x > F(1, 8) * 2**s:
        s += 1
    e = series(x / 2**s, 0)
    for _ in range(s):
        e = Iv(rnd(e.lo * e.lo, False), rnd(e.hi * e.hi, True))
    return e


def kernel(x, shift):
    """g(x) = (1 - exp(-x)) / x (shift 1) or h(x) = (x - 1 + exp(-x)) / x^2 (shift 2)."""
    if x <= F(1, 2):
        return series(x, shift)
    e = exp_neg(x)
    if shift == 1:
        return (Iv(1) - e) / Iv(x)
    return (Iv(x - 1) + e) / Iv(x * x)


def coefficients(alpha, beta, delta, d):
    """Enclosures of q's coefficients, lowest power first (docs/MODEL.md sections 2-3)."""
    n = math.floor(d)
    eps = d - n

    def phi(tau):  # (phi1(tau), phi2(tau), exp(-delta tau))
        x = delta * tau
        return Iv(tau) * kernel(x, 1), Iv(tau * tau) * kernel(x, 2), exp_neg(x)

    c = exp_neg(delta)
    p1 = phi(F(1))[0]
    g0v, g0x, c_rest = phi(1 - eps)
    p1e, p2e, _ = phi(eps)
    g1x = p2e + g0v * p1e
    g1v = c_rest * p1e
    zero = Iv(0)
    m2 = g0x
    m1 = p1 * g0v - c * g0x + g1x
    if eps:
        m0 = p1 * g1v - c * g1x
        qa, qb, low = [zero, m0, m1, m2], [-m0, m0 - m1, m1 - m2, m2], n + 2
    else:
        qa, qb, low = [zero, m1, m2, zero], [-m1, m1 - m2, m2, zero], n + 1
    q0 = {low: c, low + 1: -(Iv(1) + c), low + 2: Iv(1)}
    out = []
    for i in range(low + 3):
        v = q0.get(i, zero)
        if i < 4:
            v = v + (Iv(alpha) * qa[i] + Iv(beta) * qb[i])
        out.append(v)
    return out


def recursion(a):
    """Schur-Cohn: reflection intervals a_0/a_k and the count of roots outside the unit
    circle, or None for the count when a step is undecided (docs/MODEL.md section 11)."""
    refl, less = [], []
    while len(a) > 1:
        k = len(a) - 1
        a0, ak = a[0], a[k]
        if a0.mag() < ak.mig():
            r = a0 / ak
            less.append(True)
            a = [a[j + 1] - r * a[k - 1 - j] for j in range(k)]
        elif a0.mig() > ak.mag():
            r = a0 / ak
            inv = ak / a0
            less.append(False)
            a = [inv * a[j + 1] - a[k - 1 - j] for j in range(k)]
        else:
            return refl + [None], None
        refl.append(r)
    inside = 0
    for k, lt in zip(range(1, len(less) + 1), reversed(less)):
        inside = inside + 1 if lt else k - 1 - inside
    return refl, len(less) - inside


def canonical_hex(v):
    mant, exp = v.hex().split("p")
    if "." in mant:
        mant = mant.rstrip("0").rstrip(".")
    return mant + "p" + exp


def number(s):
    """An exact rational from a canonical C99 hex float."""
    if not isinstance(s, str):
        raise Reject(f"{s!r} is not a hex float string")
    try:
        v = float.fromhex(s)
    except (ValueError, OverflowError):
        raise Reject(f"{s!r} is not a hex float") from None
    if not math.isfinite(v) or canonical_hex(v) != s:
        raise Reject(f"{s!r} is not a canonical finite hex float")
    return F(v)


def ball(b):
    if not isinstance(b, dict) or set(b) != {"mid", "rad"}:
        raise Reject(f"{b!r} is not a ball")
    mid, rad = number(b["mid"]), number(b["rad"])
    if rad < 0:
        raise Reject("negative radius")
    return Iv(mid - rad, mid + rad)


def no_duplicates(pairs):
    keys = [k for k, _ in pairs]
    if len(set(keys)) != len(keys):
        raise Reject(f"duplicate keys in {keys}")
    return dict(pairs)


def no_constant(name):
    raise Reject(f"{name} is not a number a certificate may hold")


def load(data):
    m = re.fullmatch(rb'(\{\n.*,\n)  "crc32": "([0-9a-f]{8})"\n\}\n', data, re.S)
    if not m:
        raise Reject("not a certificate: no crc32 member at its end")
    if zlib.crc32(m.group(1)) != int(m.group(2), 16):
        raise Reject("the CRC-32 does not match the text: the certificate was changed")
    try:
        cert = json.loads(data, object_pairs_hook=no_duplicates, parse_constant=no_constant)
    except ValueError as e:
        raise Reject(f"not JSON: {e}") from None
    want = {"certificate", "model", "inputs", "degree", "coefficients", "recursions", "claim",
            "crc32"}
    if not isinstance(cert, dict) or set(cert) != want:
        raise Reject("unexpected members")
    if cert["certificate"] != "stabound stability certificate 1":
        raise Reject("unknown certificate format")
    model = cert["model"]
    if not isinstance(model, dict) or model.get("loop") != "paper" or model.get("elements") != []:
        raise Reject("this checker covers the paper's loop without elements")
    return cert


def verify(cert):
    """Returns the proven claim as text, or raises Reject."""
    inputs = cert["inputs"]
    if not isinstance(inputs, dict) or set(inputs) != {"alpha", "beta", "delta", "d"}:
        raise Reject("inputs must be alpha, beta, delta, d")
    alpha, beta, delta, d = (number(inputs[k]) for k in ("alpha", "beta", "delta", "d"))
    if delta < 0 or not 0 <= d <= 10000:
        raise Reject("delta must be >= 0 and d in [0, 10000]")
    own = coefficients(alpha, beta, delta, d)
    claimed = cert["coefficients"]
    if not isinstance(claimed, list) or cert["degree"] != len(own) - 1 or len(claimed) != len(own):
        raise Reject(f"the model's polynomial has degree {len(own) - 1}")
    claimed = [ball(b) for b in claimed]
    for i, (o, c) in enumerate(zip(own, claimed)):
        if not o.inside(c):
            raise Reject(f"coefficient {i}: the claimed ball does not hold the recomputed one")
    claim = cert["claim"]
    verdict = claim.get("verdict") if isinstance(claim, dict) else None
    if verdict == "unstable" and "coefficient_above_binomial" in claim:
        # monic q with every root in |z| <= 1 has |a_k| = |e_(n-k)(roots)| <= binom(n, k)
        k, n = claim["coefficient_above_binomial"], len(own) - 1
        if set(claim) != {"verdict", "coefficient_above_binomial"} or cert["recursions"] != []:
            raise Reject("unexpected members in the claim")
        if not (type(k) is int and 0 <= k <= n and own[n].lo == own[n].hi == 1
                and own[k].mig() > math.comb(n, k)):
            raise Reject(f"coefficient {k} is not proven above binom({n}, {k})")
        return f"unstable: coefficient {k} exceeds binom({n}, {k}), so a root is outside"
    if verdict in ("stable", "unstable"):
        radius = {"1": F(1)}
    elif verdict == "marginal":
        eps = number(claim.get("eps"))
        if not 0 < eps < F(1, 2):
            raise Reject("eps must be in (0, 1/2)")
        radius = {"1+eps": 1 + eps, "1-eps": 1 - eps}
    else:
        raise Reject(f"unknown claim {claim!r}")
    want_claim = {"stable": {"verdict"}, "unstable": {"verdict", "outside"},
                  "marginal": {"verdict", "eps"}}[verdict]
    if set(claim) != want_claim:
        raise Reject("unexpected members in the claim")
    runs = cert["recursions"]
    if not isinstance(runs, list) or [r.get("radius") for r in runs] != list(radius):
        raise Reject(f"the {verdict} claim needs the recursions at radius {list(radius)}")
    counts = {}
    for run in runs:
        if set(run) != {"radius", "outside", "reflections"}:
            raise Reject("unexpected members in a recursion")
        r = radius[run["radius"]]
        refl, outside = recursion([c * Iv(r**i) for i, c in enumerate(claimed)])
        if outside is None:
            raise Reject(f"radius {run['radius']}: step {len(refl)} of the recursion is undecided")
        given = run["reflections"]
        if not isinstance(given, list) or len(given) != len(refl):
            raise Reject(f"radius {run['radius']}: {len(refl)} reflection coefficients expected")
        for k, (o, g) in enumerate(zip(refl, given)):
            if not o.inside(ball(g)):
                raise Reject(f"radius {run['radius']}: reflection {k} is not in its claimed ball")
        if run["outside"] != outside:
            raise Reject(f"radius {run['radius']}: {outside} roots outside, not {run['outside']}")
        counts[run["radius"]] = outside
    if verdict == "stable" and counts["1"] == 0:
        return "stable: every root inside the unit circle"
    if verdict == "unstable" and counts["1"] >= 1 and claim["outside"] == counts["1"]:
        return f"unstable: {counts['1']} roots outside the unit circle, none on it"
    if verdict == "marginal" and counts["1+eps"] == 0 and counts["1-eps"] >= 1:
        return f"marginal: spectral radius within {float(eps)!r} of 1"
    raise Reject(f"the counts {counts} do not prove the claim {claim!r}")


def main(argv):
    if len(argv) != 2:
        print(__doc__.split("\n\n")[1], file=sys.stderr)
        return 2
    try:
        data = sys.stdin.buffer.read() if argv[1] == "-" else open(argv[1], "rb").read()
    except OSError as e:
        print(f"cannot read {argv[1]}: {e}", file=sys.stderr)
        return 2
    try:
        print("verified:", verify(load(data)))
    except Reject as e:
        print(f"rejected: {e}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
