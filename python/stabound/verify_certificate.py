#!/usr/bin/env python3
"""Check a stabound stability certificate using only the Python standard library.

Usage: verify_certificate.py CERTIFICATE.json  (``-`` reads standard input), or
``python -m stabound.verify_certificate CERTIFICATE.json`` from the Python package.
Exit status 0 when the certificate's claim follows, 1 when it does not (the reason on
stderr), 2 for bad usage.

This program shares no code with the library that wrote the certificate. Model and claim
(docs/MODEL.md sections 2, 3, 8 and 11): a device x' = A x + b u, y = c^T x (one mass, or two
with a transmission, an actuator lag; A, b, c from the normalized inputs), under a wall
(alpha, beta) whose force arrives d = n + eps periods late through a hold, the damping term on
a filtered velocity F = Fn / Fd, has the characteristic polynomial

    q(z) = z^(n+2) D(z) Fd(z) + N(z) (alpha z Fd(z) + beta (z - 1) Fn(z)),

D = det(z I - Phi), N = c^T adj(z I - Phi) (G0 z + G1), the common powers of z divided out.
The checks:

1. The CRC-32 of the text before its "crc32" member matches (any changed character fails).
2. Every number is a canonical hex float, so an exact rational.
3. The coefficients of q are recomputed from the inputs in rational interval arithmetic (the
   matrix exponential by its own Taylor series with a remainder bound, then squarings), and
   each claimed coefficient ball must contain them.
4. The Schur-Cohn recursion is replayed on the claimed balls in rational interval arithmetic
   (ends rounded outward to PREC bits, so that sizes stay bounded; every rounding moves an end
   outward, so the intervals still hold every true value). Every step must be decided, and
   every claimed reflection ball must contain the recomputed reflection interval.
5. The counts of roots outside the circles prove the claim.

A box certificate (walls with alpha and beta in intervals) lists leaf boxes: the leaves must
cover the box exactly (inside it, interiors disjoint, areas adding up), and each leaf is
checked as above with the wall's intervals in place of its numbers (q is affine in the wall,
so the recomputed enclosures hold q for every wall of the leaf); an unstable leaf may count
the roots outside 1 + eps. A leaf with a centre and arcs is checked at its centre, and
Rouche's theorem on the arcs of the unit circle (see clear) carries the centre's count to
every wall of the leaf. A leaf claimed "not stable" replays the recursion up to its first
step that is not |a_0| < |a_k|, which must have |a_0| > |a_k|: no wall of it is stable. An
alpha_max certificate holds a stable wall's certificate at alpha_lo and a box's from
alpha_hi on the same loop; both are checked. With a cap, the box reaches the cap and no wall
of it is stable, and a linear necessary condition of stability fails for every wall from the
cap on (see capped): no wall at alpha_hi or stiffer is stable. Without one, the box is the
strip at alpha_hi alone, every wall of it unstable. A grid certificate lists such
certificates, one per row, and each is checked.
"""

import functools
import json
import math
import re
import sys
import zlib
from fractions import Fraction as F

PREC = 200  # bits kept by the outward rounding of interval ends (raised for coefficients)
PRECISIONS = (200, 800, 3200)  # tried in turn for the coefficients; the last is the cap
ELEMENTS = ["hand", "transmission", "actuator", "filter"]


class Reject(Exception):
    """The claim does not follow from the certificate."""


def rnd(q, up):
    """q rounded to PREC significant bits (no finer than 2^-(PREC+2200)), up or down."""
    if q == 0:
        return q
    n, d = q.numerator, q.denominator
    s = min(PREC - (n.bit_length() - d.bit_length()), PREC + 2200)
    num, den = (n << s, d) if s >= 0 else (n, d << -s)
    m, rem = divmod(num, den)
    if up and rem:
        m += 1
    return F(m, 1 << s) if s >= 0 else F(m << -s)


def iv(x):
    """x as an interval (a rational as a point)."""
    return x if isinstance(x, Iv) else Iv(x)


class Iv:
    """A closed interval [lo, hi] with rational ends, every operation rounded outward (a
    rational operand is a point)."""

    def __init__(self, lo, hi=None):
        self.lo, self.hi = F(lo), F(lo if hi is None else hi)

    def __add__(self, o):
        o = iv(o)
        return Iv(rnd(self.lo + o.lo, False), rnd(self.hi + o.hi, True))

    def __sub__(self, o):
        o = iv(o)
        return Iv(rnd(self.lo - o.hi, False), rnd(self.hi - o.lo, True))

    def __neg__(self):
        return Iv(-self.hi, -self.lo)

    def __mul__(self, o):
        o = iv(o)
        p = [self.lo * o.lo, self.lo * o.hi, self.hi * o.lo, self.hi * o.hi]
        return Iv(rnd(min(p), False), rnd(max(p), True))

    def __truediv__(self, o):
        o = iv(o)
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


def total(xs):
    return functools.reduce(Iv.__add__, xs, Iv(0))


def mul(a, b):
    return [[total(a[i][k] * b[k][j] for k in range(len(b))) for j in range(len(b[0]))]
            for i in range(len(a))]


def expm(m):
    """e^M: Taylor series of X = M / 2^s (infinity norm theta <= 1/8) until the remainder
    bound theta^(k+1) / (k+1)! * 8/7 falls below 2^-(PREC+16), added to every entry off the
    zero rows and columns of M (every power of M keeps them); then s squarings."""
    n = len(m)
    norm = max(total(Iv(x.mag()) for x in row).hi for row in m)
    s = 0
    while norm > F(1, 8) * 2**s:
        s += 1
    x = [[e * Iv(F(1, 2**s)) for e in row] for row in m]
    theta = norm / 2**s
    eye = [[Iv(int(i == j)) for j in range(n)] for i in range(n)]
    term, out, k, bound = eye, eye, 0, rnd(theta * F(8, 7), True)
    while bound >= F(1, 1 << (PREC + 16)):
        k += 1
        term = [[e / Iv(k) for e in row] for row in mul(term, x)]
        out = [[a + b for a, b in zip(r, t)] for r, t in zip(out, term)]
        bound = rnd(bound * theta / (k + 1), True)
    live = [[any(v.mag() for v in row) and any(r[j].mag() for r in m) for j, e in
             enumerate(row)] for row in m]
    out = [[e + Iv(-bound, bound) if ok else e for e, ok in zip(r, o)] for r, o in zip(out, live)]
    for _ in range(s):
        out = mul(out, out)
    return out


def device(inp, delta):
    """A, b, c of the device in exact rationals (docs/MODEL.md section 8); delta may be an
    interval (the entries it enters are then intervals)."""
    mu, dh, kh = (number(inp["hand"][k]) for k in ("mu_h", "delta_h", "kappa_h")) \
        if "hand" in inp else (F(0),) * 3
    tr, act = inp.get("transmission"), inp.get("actuator")
    s = (4 if tr else 2) + (1 if act else 0)
    a, b, c = [[F(0)] * s for _ in range(s)], [F(0)] * s, [F(0)] * s
    if min(mu, dh, kh) < 0:
        raise Reject("the hand's values must be >= 0")
    a[0][1] = F(1)
    if tr is None:
        m = 1 + mu
        a[1][0], a[1][1], c[0], scale = -kh / m, -(delta + dh) / m, F(1), 1 / m
    else:
        r, kc, dc, d2 = (number(tr[k]) for k in ("r", "kappa_c", "delta_c", "delta_2"))
        if not (0 < r < 1 and min(kc, dc, d2) >= 0 and tr["encoder"] in ("motor", "handle")):
            raise Reject("transmission values out of range")
        m1, m2 = 1 - r, r + mu
        a[1][0], a[1][1], a[1][2], a[1][3] = -kc / m1, -(delta - d2 + dc) / m1, kc / m1, dc / m1
        a[2][3] = F(1)
        a[3][0], a[3][1], a[3][2], a[3][3] = kc / m2, dc / m2, -(kh + kc) / m2, -(d2 + dh + dc) / m2
        c[0 if tr["encoder"] == "motor" else 2], scale = F(1), 1 / m1
    if act is None:
        b[1] = scale
    else:
        tau = number(act["tau"])
        if tau <= 0:
            raise Reject("the actuator's tau must be > 0")
        a[1][s - 1], a[s - 1][s - 1], b[s - 1] = scale, -1 / tau, 1 / tau
    return a, b, c


def velocity_filter(f):
    """(Fn, Fd), lowest power first, exact."""
    if f is None:
        return [F(1)], [F(1)]
    if set(f) == {"pole"} and 0 < number(f["pole"]) < 1:
        return [F(0), 1 - number(f["pole"])], [-number(f["pole"]), F(1)]
    if set(f) == {"samples"} and type(f["samples"]) is int and 2 <= f["samples"] <= 64:
        return [F(1, f["samples"])] * f["samples"], [F(0)] * (f["samples"] - 1) + [F(1)]
    if set(f) == {"numerator", "denominator"} and len(f["denominator"]) == 3 == len(
            f["numerator"]) and f["denominator"][2] == "0x1p+0":
        return [number(x) for x in f["numerator"]], [number(x) for x in f["denominator"]]
    raise Reject(f"unknown filter {f!r}")


def conv(a, b):
    out = [Iv(0) for _ in range(len(a) + len(b) - 1)]
    for i, x in enumerate(a):
        for j, y in enumerate(b):
            out[i + j] = out[i + j] + x * y
    return out


def parts(inp, delta, d):
    """Enclosures of the parts (Q0, QA, QB) of q = Q0 + alpha QA + beta QB, lowest power
    first (docs/MODEL.md section 8): the device sampled by exp([[A, b], [0, 0]] tau) (Van
    Loan), D and adj(z I - Phi) by Faddeev-LeVerrier, the common powers of z divided out."""
    a, b, c = device(inp, delta)
    n, s = math.floor(d), len(a)
    eps = d - n

    def sample(tau):  # (e^(A tau), Gamma(tau))
        e = expm([[iv(x * tau) for x in row] + [Iv(bi * tau)] for row, bi in zip(a, b)]
                 + [[Iv(0)] * (s + 1)])
        return [row[:s] for row in e[:s]], [row[s] for row in e[:s]]

    phi, g0 = sample(1 - eps)
    g1 = [Iv(0)] * s
    if eps:
        rest, gam = phi, sample(eps)[1]
        phi = sample(F(1))[0]
        g1 = [total(r * g for r, g in zip(row, gam)) for row in rest]
    dpoly, num, bk = [Iv(0)] * s + [Iv(1)], [Iv(0)] * (s + 1), [[Iv(int(i == j)) for j in
                                                                 range(s)] for i in range(s)]
    for k in range(1, s + 1):  # num = c^T adj(zI - Phi) (G0 z + G1), adj = sum B_k z^(s-k)
        cb = [total(Iv(c[i]) * bk[i][j] for i in range(s)) for j in range(s)]
        num[s - k + 1] = num[s - k + 1] + total(x * y for x, y in zip(cb, g0))
        num[s - k] = num[s - k] + total(x * y for x, y in zip(cb, g1))
        ab = mul(phi, bk)
        dpoly[s - k] = -(total(ab[i][i] for i in range(s)) / Iv(k))
        bk = [[x + (dpoly[s - k] if i == j else Iv(0)) for j, x in enumerate(row)]
              for i, row in enumerate(ab)]
    fn, fd = (list(map(Iv, p)) for p in velocity_filter(inp.get("filter")))
    q0 = [Iv(0)] * (n + 2) + conv(dpoly, fd)
    qa = [Iv(0)] + conv(fd, num)
    qb = conv([Iv(-1), Iv(1)], conv(fn, num))
    qa, qb = (p + [Iv(0)] * (len(q0) - len(p)) for p in (qa, qb))
    parts = list(zip(q0, qa, qb))
    while all(x.lo == x.hi == 0 for x in parts[0]):
        parts.pop(0)
    return parts


def at(parts, alpha, beta):
    """q's coefficients for every wall with alpha, beta in the intervals given: each is
    affine in the wall and holds each of them once, so this encloses its range."""
    return [z + (alpha * x + beta * y) for z, x, y in parts]


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


SINGLE, BOX, AMAX = (f"stabound {k} certificate 1" for k in ("stability", "box", "alpha_max"))
MEMBERS = {SINGLE: {"model", "inputs", "degree", "coefficients", "recursions", "claim"},
           BOX: {"model", "inputs", "degree", "leaves", "claim"},
           AMAX: {"stable_below", "unstable_above", "claim"}}
OPTIONAL = {AMAX: {"cap"}}


def shape(cert, kind, extra=frozenset()):
    """The certificate's format (kind, or any when None) and members, or Reject."""
    got = cert.get("certificate") if isinstance(cert, dict) else None
    if got not in MEMBERS or kind not in (None, got):
        raise Reject("unknown certificate format")
    if set(cert) - OPTIONAL.get(got, set()) != MEMBERS[got] | {"certificate"} | set(extra):
        raise Reject("unexpected members")


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
    shape(cert, None, {"crc32"})
    return cert


def model_inputs(cert):
    """The inputs' elements checked against the model; returns (delta, d)."""
    inputs, model = cert["inputs"], cert["model"]
    names = [k for k in inputs if k in ELEMENTS] if isinstance(inputs, dict) else None
    if names is None or list(inputs)[:4] != ["alpha", "beta", "delta", "d"] or len(inputs) != 4 \
            + len(names) or names != sorted(names, key=ELEMENTS.index):
        raise Reject("inputs must be alpha, beta, delta, d and the elements in order")
    if not isinstance(model, dict) or model.get("elements") != names or model.get("loop") != (
            "elements" if names else "paper"):
        raise Reject("the model must name the loop and the elements of the inputs")
    delta, d = number(inputs["delta"]), number(inputs["d"])
    if delta < 0 or not 0 <= d <= 10000:
        raise Reject("delta must be >= 0 and d in [0, 10000]")
    return delta, d


def enclosures(cert, walls, claims):
    """q's coefficients recomputed for each box of walls ((alpha, beta) intervals) and
    checked inside the claimed balls (lists of balls as JSON); returns the recomputed ones.
    Cancellation costs absolute accuracy: the precisions are tried in turn."""
    delta, d = model_inputs(cert)
    claimed = [[ball(b) for b in c] if isinstance(c, list) else [] for c in claims]
    global PREC
    for PREC in PRECISIONS:
        try:
            p = parts(cert["inputs"], delta, d)
        except (KeyError, TypeError, AttributeError):
            raise Reject("an element's inputs are incomplete") from None
        owns = [at(p, a, b) for a, b in walls]
        pairs = [(o, c) for own, cl in zip(owns, claimed) for o, c in zip(own, cl)]
        if any(len(o) != len(c) for o, c in zip(owns, claimed)) or all(
                o.inside(c) for o, c in pairs) or any(o.hi < c.lo or c.hi < o.lo for o, c in pairs):
            break  # decided: more bits cannot move a true value into a disjoint ball
    PREC = PRECISIONS[0]
    for own, cl in zip(owns, claimed):
        if cert["degree"] != len(own) - 1 or len(cl) != len(own):
            raise Reject(f"the model's polynomial has degree {len(own) - 1}")
        for i, (o, c) in enumerate(zip(own, cl)):
            if not o.inside(c):
                raise Reject(f"coefficient {i}: the claimed ball does not hold the recomputed one")
    return owns, claimed, p


def replay(coeffs, given, label):
    """Replays the recursion on the claimed coefficients; every step must be decided and
    every claimed reflection ball must hold the recomputed one. Returns the count outside."""
    refl, outside = recursion(coeffs)
    if outside is None:
        raise Reject(f"{label}: step {len(refl)} of the recursion is undecided")
    if not isinstance(given, list) or len(given) != len(refl):
        raise Reject(f"{label}: {len(refl)} reflection coefficients expected")
    for k, (o, g) in enumerate(zip(refl, given)):
        if not o.inside(ball(g)):
            raise Reject(f"{label}: reflection {k} is not in its claimed ball")
    return outside


def not_stable(a, given, label):
    """Replays the recursion while |a_0| < |a_k|; the first other step must have |a_0| >
    |a_k| for every value, and then the polynomial of that step, so every polynomial in the
    enclosures, has a root outside the unit circle or on it (docs/MODEL.md section 11)."""
    refl = []
    while len(a) > 1 and a[0].mag() < a[-1].mig():
        k = len(a) - 1
        r = a[0] / a[k]
        refl.append(r)
        a = [a[j + 1] - r * a[k - 1 - j] for j in range(k)]
    if len(a) < 2 or not a[0].mig() > a[-1].mag():
        raise Reject(f"{label}: step {len(refl)} does not prove |a_0| > |a_k|")
    refl.append(a[0] / a[-1])
    if not isinstance(given, list) or len(given) != len(refl):
        raise Reject(f"{label}: {len(refl)} reflection coefficients expected")
    if not all(o.inside(ball(g)) for o, g in zip(refl, given)):
        raise Reject(f"{label}: a reflection is not in its claimed ball")


def verify(cert):
    """Returns the proven claim as text, or raises Reject."""
    if cert["certificate"] == BOX:
        return verify_box(cert)
    if cert["certificate"] == AMAX:
        return verify_amax(cert)
    if cert["certificate"] == GRID:
        return verify_grid(cert)
    inputs = cert["inputs"]
    alpha, beta = number(inputs["alpha"]), number(inputs["beta"])
    (own,), (claimed,), _ = enclosures(cert, [(Iv(alpha), Iv(beta))], [cert["coefficients"]])
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
        outside = replay([c * Iv(r**i) for i, c in enumerate(claimed)], run["reflections"],
                         f"radius {run['radius']}")
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


def pair(p):
    """A box side [lo, hi] of hex floats as an interval."""
    if not (isinstance(p, list) and len(p) == 2) or number(p[0]) > number(p[1]):
        raise Reject(f"{p!r} is not a side [lo, hi] of a box")
    return Iv(number(p[0]), number(p[1]))


def covers(whole, boxes):
    """Whether the boxes lie in the box whole, their interiors are disjoint and their measures
    add up to its measure (a side of zero width counts as 1): the union of finitely many
    closed boxes is closed, so what it misses of whole would be open there, of measure 0,
    hence empty. Interiors are tested pairwise after sorting on alpha."""
    flat = [w.lo == w.hi for w in whole]

    def measure(b):
        return math.prod(F(1) if f else s.hi - s.lo for s, f in zip(b, flat))
    for b in boxes:
        if not all(s.inside(w) for s, w in zip(b, whole)):
            return False
    if sum(map(measure, boxes)) != measure(whole):
        return False
    boxes = sorted(boxes, key=lambda b: b[0].lo)
    for i, b in enumerate(boxes):
        for c in boxes[i + 1:]:
            if not flat[0] and c[0].lo >= b[0].hi:
                break
            if all(f or max(s.lo, t.lo) < min(s.hi, t.hi) for s, t, f in zip(b, c, flat)):
                return False
    return True


def verify_box(cert):
    """A box of walls: every leaf's claim replayed, the leaves covering the box."""
    inputs, leaves, claim = cert["inputs"], cert["leaves"], cert["claim"]
    whole = (pair(inputs["alpha"]), pair(inputs["beta"]))
    if not isinstance(leaves, list) or not leaves:
        raise Reject("a box certificate lists its leaves")
    walls = []
    for leaf in leaves:
        unstable = leaf.get("claim") == "unstable" if isinstance(leaf, dict) else None
        extra = {"outside"} | ({"eps"} if "eps" in leaf else set()) if unstable else set()
        extra |= {"centre", "arcs"} if "centre" in leaf else set()
        if unstable is None or set(leaf) != {"alpha", "beta", "claim", "coefficients",
                                             "reflections"} | extra:
            raise Reject("unexpected members in a leaf")
        walls.append((pair(leaf["alpha"]), pair(leaf["beta"])))
    if not covers(whole, walls):
        raise Reject("the leaves do not cover the box exactly")
    at_centre = [centre(leaf, box) for leaf, box in zip(leaves, walls)]
    _, claimed, parts = enclosures(cert, [c or w for c, w in zip(at_centre, walls)],
                                   [leaf["coefficients"] for leaf in leaves])
    counts = {"stable": 0, "unstable": 0, "undecided": 0, "not stable": 0}
    for i, (leaf, coeffs) in enumerate(zip(leaves, claimed)):
        kind = leaf["claim"]
        if kind == "undecided":
            if leaf["reflections"] != []:
                raise Reject(f"leaf {i}: an undecided leaf lists no reflections")
        elif kind == "not stable":
            if at_centre[i]:
                raise Reject(f"leaf {i}: a leaf not stable is not decided around a centre")
            not_stable(coeffs, leaf["reflections"], f"leaf {i}")
        elif kind not in counts:
            raise Reject(f"leaf {i}: unknown claim {kind!r}")
        else:
            # an unstable leaf may count the roots outside 1 + eps > 1: one there is outside
            r = 1 + number(leaf["eps"]) if "eps" in leaf else F(1)
            if not 1 <= r < 2:
                raise Reject(f"leaf {i}: eps must be in [0, 1)")
            outside = replay([c * Iv(r**j) for j, c in enumerate(coeffs)], leaf["reflections"],
                             f"leaf {i}")
            if at_centre[i] and (r != 1 or not clear(coeffs, parts, walls[i], at_centre[i],
                                                     leaf["arcs"])):
                raise Reject(f"leaf {i}: a root may cross the unit circle within the leaf")
            if (outside == 0) != (kind == "stable") or kind == "unstable" and outside != \
                    leaf["outside"]:
                raise Reject(f"leaf {i}: {outside} roots outside do not prove {kind}")
        counts[kind] += 1
    n = len(leaves)
    verdict = "stable" if counts["stable"] == n else "unstable" if counts["unstable"] == n \
        else "not stable" if counts["unstable"] + counts["not stable"] == n else "not proved"
    if not counts["not stable"]:
        del counts["not stable"]  # written only where it occurs
    if claim != dict(verdict=verdict, **counts):
        raise Reject(f"the leaves prove {verdict} with counts {counts}, not {claim!r}")
    if verdict == "not proved":
        return f"not proved for the whole box: leaves {counts}"
    return f"{verdict} for every wall of the box ({n} leaves)"


def centre(leaf, box):
    """A leaf decided around its centre: the centre as a wall of points, else None."""
    if "centre" not in leaf:
        return None
    c = leaf["centre"]
    if not isinstance(c, list) or len(c) != 2:
        raise Reject("a leaf's centre is [alpha, beta]")
    c = (Iv(number(c[0])), Iv(number(c[1])))
    if not all(p.inside(s) for p, s in zip(c, box)):
        raise Reject("a leaf's centre lies outside it")
    return c


def root(x, up):
    """A bound of sqrt(x), x >= 0 rational, within 2^-PREC."""
    n = math.isqrt(x.numerator * 4**PREC // x.denominator)
    return F(n + up, 2**PREC)


def modulus(balls, z):
    """Bounds of |p(z)| for |z| = 1, p with coefficient balls (mid, rad), z = (x + i y) / w
    (integers): Horner's rule on sum c_k (x + i y)^k w^(n-k) in integers, c = den * mid."""
    (x, y, w), den = z, math.lcm(*(m.denominator for m, _ in balls))
    re = im = 0
    for k, (m, _) in enumerate(reversed(balls)):
        c = m.numerator * (den // m.denominator) * w**k
        re, im = re * x - im * y + c, re * y + im * x
    s, r = math.isqrt(re * re + im * im), sum(rad for _, rad in balls)
    return F(s, den * w ** (len(balls) - 1)) - r, F(s + 1, den * w ** (len(balls) - 1)) + r


def clear(f, parts, box, c, arcs):
    """Rouche on the unit circle (docs/MODEL.md section 11): |f| > ra |QA| + rb |QB| on
    every arc between the points ((1 - t^2) + 2 i t) / (1 + t^2) of the parameters u of arcs
    (t = u - 1 up to u = 2, then minus the point of t = u - 3): at an arc's first end z0,
    with h its chord, |p(z)| is within h |p'(z0)| + h^2 sum C(k, 2) |p_k| of |p(z0)|. So
    every wall of the box has the centre's count of roots outside, none on the circle."""
    qa, qb = [x for _, x, _ in parts], [y for _, _, y in parts]
    if qa[-1].mag() or qb[-1].mag():
        raise Reject("the wall changes the degree of q")
    us = [number(u) for u in arcs] if isinstance(arcs, list) else []
    if us[:1] != [0] or us[-1:] != [4] or 2 not in us or any(a >= b for a, b in zip(us, us[1:])):
        raise Reject("the arcs must rise from 0 to 4 through 2")
    radii = [max(m.lo - s.lo, s.hi - m.hi) for m, s in zip(c, box)]
    polys = [[((x.lo + x.hi) / 2, (x.hi - x.lo) / 2) for x in p] for p in (f, qa, qb)]
    slopes = [[(k * m, k * r) for k, (m, r) in enumerate(p)][1:] for p in polys]
    curve = sum(w * sum(math.comb(k, 2) * (abs(m) + r) for k, (m, r) in enumerate(p))
                for w, p in zip([1] + radii, polys))
    for u0, u1 in zip(us, us[1:]):
        shift, sign = (1, 1) if u1 <= 2 else (3, -1)
        t0, t1 = u0 - shift, u1 - shift
        p, q = t0.numerator, t0.denominator
        z = (sign * (q * q - p * p), sign * 2 * p * q, q * q + p * p)
        h = root(4 * (t1 - t0) ** 2 / ((1 + t0 * t0) * (1 + t1 * t1)), True)
        (f_lo, _), (_, a_hi), (_, b_hi) = (modulus(p, z) for p in polys)
        slope = sum(w * modulus(p, z)[1] for w, p in zip([1] + radii, slopes))
        if not f_lo - radii[0] * a_hi - radii[1] * b_hi > h * slope + h * h * curve:
            return False
    return True


def capped(box, cap, betas):
    """The cap: q = Q0 + alpha QA + beta QB is monic of degree m, and a stable q has
    L(q) < c for the rule's linear form: (-1)^m q(-1) = prod (1 + r_i) > 0 (weights
    -(-1)^(m+k), c = 0), or sign a_k < C(m, k) (|a_k| = |e_(m-k)(r)|). L(QA) > 0 and
    L(q) >= c at alpha for every beta of the range prove L(q) >= c for every stiffer wall.
    Returns alpha."""
    alpha, rule = number(cap.get("alpha")), cap.get("rule")
    p = parts(box["inputs"], *model_inputs(box))
    m = len(p) - 1
    if any((x.lo, x.hi) != (v, v) for x, v in zip(p[m], (1, 0, 0))):
        raise Reject("q is not monic with a top coefficient free of the wall")
    if rule == "q(-1)" and set(cap) == {"alpha", "rule"}:
        w, c = [-(-1) ** (m + k) for k in range(m + 1)], 0
    elif rule == "coefficient" and set(cap) == {"alpha", "rule", "k", "sign"} and type(
            cap["k"]) is int and 0 <= cap["k"] < m and cap["sign"] in (1, -1):
        w, c = [cap["sign"] if k == cap["k"] else 0 for k in range(m + 1)], math.comb(m, cap["k"])
    else:
        raise Reject(f"unknown cap {cap!r}")
    l0, la, lb = (total(Iv(wk) * x[j] for wk, x in zip(w, p) if wk) for j in range(3))
    if not (la.lo > 0 and (l0 + Iv(alpha) * la + betas * lb).lo >= c):
        raise Reject("the cap's condition is not proved to fail from the cap on")
    return alpha


def verify_amax(cert):
    """An enclosure of alpha_max: a stable wall at alpha_lo, and no damping of the box's
    range that stabilizes alpha_hi (without a cap) or any stiffer wall (with one); both on
    the same loop."""
    below, above, claim = cert["stable_below"], cert["unstable_above"], cert["claim"]
    shape(below, SINGLE)
    shape(above, BOX)
    cap = cert.get("cap")
    if not isinstance(claim, dict) or set(claim) != {"alpha_lo", "alpha_hi"} | (
            {"stiffer"} if cap is not None else set()) or cap is not None and (
            claim["stiffer"] != "none stable" or not isinstance(cap, dict)):
        raise Reject("unexpected members in the claim")
    lo, hi = number(claim["alpha_lo"]), number(claim["alpha_hi"])
    ins, ina = below["inputs"], above["inputs"]
    same = {k: v for k, v in ins.items() if k not in ("alpha", "beta")} == {
        k: v for k, v in ina.items() if k not in ("alpha", "beta")}
    if below["model"] != above["model"] or not same or list(ins) != list(ina):
        raise Reject("the stable wall and the unstable strip are on different loops")
    betas, alphas = pair(ina["beta"]), pair(ina["alpha"])
    top = capped(above, cap, betas) if cap is not None else hi
    if number(ins["alpha"]) != lo or alphas.lo != hi or alphas.hi < top or cap is None and \
            alphas.hi != hi or not Iv(number(ins["beta"])).inside(betas) or not lo < hi:
        raise Reject("the certificates are not at alpha_lo < alpha_hi within the dampings")
    proved = ("unstable", "not stable") if cap is not None else ("unstable",)
    if not verify(below).startswith("stable") or not verify(above).startswith(proved):
        raise Reject("the wall below is not proved stable or the walls above not unstable")
    which = "alpha_hi or any stiffer wall" if cap is not None else "alpha_hi"
    return f"alpha_max in [{float(lo)!r}, {float(hi)!r}]: a stable wall at alpha_lo, and " \
        f"no damping in [{float(betas.lo)!r}, {float(betas.hi)!r}] stabilizes {which}"


GRID = "stabound alpha_max grid certificate 1"
MEMBERS[GRID] = {"rows", "claim"}


def verify_grid(cert):
    """Several alpha_max enclosures (the rows of a grid of devices), each checked alone."""
    rows = cert["rows"]
    if not isinstance(rows, list) or not rows or cert["claim"] != {"rows": len(rows)}:
        raise Reject("the claim must count the rows, one or more")
    done = []
    for i, row in enumerate(rows):
        try:
            shape(row, AMAX)
            done.append(f"row {i}: {verify_amax(row)}")
        except Reject as e:
            raise Reject(f"row {i}: {e}") from None
    return f"{len(rows)} rows\n" + "\n".join(done)


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


# Certified lookup tables ("stabound table certificate 1"). A cell is one delta interval
# [X[j], X[j+1]] of one row d (whole delays, or one row: d is not interpolated). A query at
# delta = X[j] + s (X[j+1] - X[j]), s in [0, 1], reads alpha = A[j] + s (A[j+1] - A[j]) and
# beta alike; firmware rounding is allowed for by the guard g: every wall with alpha and beta
# each within g * (the larger node magnitude of the cell) of those values, either way, for
# every delta within g * (the larger axis value) of the query's (delta >= 0). Each box
# of a cell is an s range; the checker builds its (delta, alpha, beta) box from the nodes in
# exact arithmetic, encloses the loop's parts over the delta interval (the paper's loop by
# monotonicity, a loop with elements, listed in the table, by parts with an interval delta),
# checks the claimed balls hold them, replays the recursion (stable), and checks the s ranges
# tile [0, 1]. A box of a loop with elements may be decided around its centre wall as a box
# certificate's leaf: the enclosures there, and Rouche on its arcs for every delta.

TABLE = "stabound table certificate 1"
MEMBERS[TABLE] = {"model", "table", "cells", "claim"}
GUARDS = {"double": F(16, 2**53), "float": F(16, 2**24)}  # 16 units of roundoff


@functools.lru_cache(maxsize=4096)
def paper_sample(delta, tau):
    """(e^(-delta tau), phi1(tau), phi2(tau)) at an exact delta: entries of
    e^([[0, 1, 0], [0, -delta, 1], [0, 0, 0]] tau) (Phi22, Phi12, Gamma_x)."""
    e = expm([[Iv(0), Iv(tau), Iv(0)], [Iv(0), Iv(-delta * tau), Iv(tau)], [Iv(0)] * 3])
    return e[1][1], e[0][1], e[0][2]


def paper_parts_over(lo, hi, d):
    """Parts (Q0, QA, QB) of the paper's loop for every delta in [lo, hi] (docs/MODEL.md
    sections 2-3): q = z^(n+2) (z - 1)(z - c) + ((alpha + beta) z - beta) (m2 z^2 + m1 z + m0),
    divided by z for a whole d. e^(-delta t), phi1 and phi2 are integrals of e^(-delta t) with
    nonnegative weights, so they decrease in delta: each is enclosed by its ends' values."""
    n = math.floor(d)
    eps = d - n

    def hull(tau):
        return [Iv(x.lo, y.hi) for x, y in zip(paper_sample(hi, tau), paper_sample(lo, tau))]
    c, p1, _ = hull(F(1))
    c_rest, g0v, g0x = hull(1 - eps)
    zero, one = Iv(0), Iv(1)
    m2 = g0x
    if eps:
        _, p1e, p2e = hull(eps)
        g1x, g1v = p2e + g0v * p1e, c_rest * p1e
        m1 = p1 * g0v - c * g0x + g1x
        m0 = p1 * g1v - c * g1x
        qa, qb, low = [zero, m0, m1, m2], [-m0, m0 - m1, m1 - m2, m2], n + 2
    else:
        m1 = p1 * g0v - c * g0x
        qa, qb, low = [zero, m1, m2, zero], [-m1, m1 - m2, m2, zero], n + 1
    q0 = [zero] * low + [c, -(one + c), one]
    return [(z, qa[i] if i < 4 else zero, qb[i] if i < 4 else zero) for i, z in enumerate(q0)]


def hexes(v):
    """A nonempty list of hex floats as exact rationals."""
    if not isinstance(v, list) or not v:
        raise Reject(f"{v!r} is not a list of numbers")
    return [number(x) for x in v]


def own_in(own, claimed, label):
    """The claimed balls (JSON) as intervals, each holding the recomputed one."""
    if not isinstance(claimed, list) or len(claimed) != len(own):
        raise Reject(f"{label}: {len(own)} coefficients expected")
    claimed = [ball(b) for b in claimed]
    if not all(o.inside(c) for o, c in zip(own, claimed)):
        raise Reject(f"{label}: a claimed ball does not hold the recomputed coefficient")
    return claimed


def verify_table(cert):
    """Every cell of a lookup table: its boxes tile s in [0, 1] and each is proved stable."""
    model, tab, cells, claim = cert["model"], cert["table"], cert["cells"], cert["claim"]
    inp = {k: tab[k] for k in ELEMENTS if k in tab} if isinstance(tab, dict) else {}
    if not isinstance(model, dict) or model.get("elements") != list(inp) or model.get(
            "loop") != ("elements" if inp else "paper"):
        raise Reject("the model must name the loop and the elements of the table")
    if not isinstance(tab, dict) or set(tab) != {"precision", "guard", "delta", "d", "alpha",
                                                 "beta"} | set(inp) or tab["precision"] not \
            in GUARDS:
        raise Reject("unexpected members in the table")
    if number(tab["guard"]) != GUARDS[tab["precision"]]:
        raise Reject(f"the guard of a {tab['precision']} table is {GUARDS[tab['precision']]}")
    xs, ds = hexes(tab["delta"]), hexes(tab["d"])
    if xs[0] < 0 or any(b <= a for v in (xs, ds) for a, b in zip(v, v[1:])) or len(ds) > 1 and \
            any(x.denominator != 1 for x in ds) or not 0 <= ds[0] <= 10000:
        raise Reject("the axes must be increasing, delta >= 0, d whole (or one) in [0, 10000]")
    grid = {k: [hexes(r) for r in tab[k]] if isinstance(tab[k], list) else [] for k in
            ("alpha", "beta")}
    if any(len(g) != len(ds) or any(len(r) != len(xs) for r in g) for g in grid.values()):
        raise Reject("the nodes must be a d by delta grid")
    columns = max(len(xs) - 1, 1)
    want = [(i, j) for i in range(len(ds)) for j in range(columns)]
    if not isinstance(cells, list) or [(c.get("row"), c.get("column")) if isinstance(c, dict)
                                       else None for c in cells] != want:
        raise Reject(f"the cells must be every (row, column) in order: {len(want)} cells")
    guard, total_boxes = GUARDS[tab["precision"]], 0
    for cell in cells:
        i, j = cell["row"], cell["column"]
        j1 = min(j + 1, len(xs) - 1)
        boxes = cell["boxes"]
        if set(cell) != {"row", "column", "boxes"} or not isinstance(boxes, list) or not boxes:
            raise Reject(f"cell ({i}, {j}): unexpected members or no boxes")
        ends = F(0)
        for k, box in enumerate(boxes):
            label = f"cell ({i}, {j}) box {k}"
            extra = {"centre", "delta", "family", "arcs"} if inp and isinstance(box, dict) and \
                "centre" in box else set()
            if not isinstance(box, dict) or set(box) != {"s", "coefficients", "reflections"} | extra:
                raise Reject(f"{label}: unexpected members")
            s = pair(box["s"])
            if s.lo != ends or s.hi > 1:
                raise Reject(f"{label}: the boxes' s ranges do not tile [0, 1]")
            ends = s.hi
            x0, h = xs[j], xs[j1] - xs[j]
            walls = []
            for g in (grid["alpha"], grid["beta"]):
                v0, v1, slack = g[i][j], g[i][j1], guard * max(abs(g[i][j]), abs(g[i][j1]))
                ends_v = [v0 + t * (v1 - v0) for t in (s.lo, s.hi)]
                walls.append(Iv(min(ends_v) - slack, max(ends_v) + slack))
            slack = guard * max(abs(xs[j]), abs(xs[j1]))
            lo, hi = max(x0 + s.lo * h - slack, F(0)), x0 + s.hi * h + slack
            c = centre(box, walls)
            member = number(box["delta"]) if c else None
            if c and not lo <= member <= hi:
                raise Reject(f"{label}: the member's delta lies outside the box")
            try:
                p = parts(inp, Iv(lo, hi), ds[i]) if inp else paper_parts_over(lo, hi, ds[i])
                # a box decided around its centre counts the roots of one member's q there
                own = at(parts(inp, member, ds[i]) if c else p, *(c or walls))
            except (KeyError, TypeError, AttributeError):
                raise Reject("an element's inputs are incomplete") from None
            claimed = own_in(own, box["coefficients"], label)
            if replay(claimed, box["reflections"], label) != 0:
                raise Reject(f"{label}: a root is outside the unit circle")
            # Rouche on the arcs for every loop of the box's delta range and every wall: no
            # root on the circle, so each has the member's count (the family is connected)
            if c and not clear(own_in(at(p, *c), box["family"], label), p, walls, c, box["arcs"]):
                raise Reject(f"{label}: a root may cross the unit circle within the box")
        if ends != 1:
            raise Reject(f"cell ({i}, {j}): the boxes' s ranges do not reach 1")
        total_boxes += len(boxes)
    if claim != {"verdict": "stable", "cells": len(cells), "boxes": total_boxes}:
        raise Reject(f"the cells prove stable with {len(cells)} cells and {total_boxes} boxes, "
                     f"not {claim!r}")
    return f"stable for every wall of the table's lookup: {len(cells)} cells, {total_boxes} " \
        f"boxes, delta in [{float(xs[0])!r}, {float(xs[-1])!r}], guard {float(guard)!r}"


_verify_one = verify


def verify(cert):  # noqa: F811 (the table format joins the formats above)
    return verify_table(cert) if cert["certificate"] == TABLE else _verify_one(cert)


if __name__ == "__main__":
    sys.exit(main(sys.argv))
