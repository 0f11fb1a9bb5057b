#!/usr/bin/env python3
"""Check a stabound stability certificate using only the Python standard library.

Usage: verify_certificate.py CERTIFICATE.json  (``-`` reads standard input), or
``python -m stabound.verify_certificate CERTIFICATE.json`` from the Python package.
Exit status 0 when the certificate's claim follows, 1 when it does not (the reason on
stderr), 2 for bad usage.

This program shares no code with the library that wrote the certificate. Model (docs/MODEL.md
sections 2, 3, 8, 11): a device x' = A x + b u, y = c^T x (one mass, or two with a
transmission, an actuator lag) under a wall (alpha, beta) whose force arrives d = n + eps
periods late through a hold, the damping on a velocity filtered by Fn / Fd, has the polynomial
q(z) = z^(n+2) D(z) Fd(z) + N(z) (alpha z Fd(z) + beta (z - 1) Fn(z)), D = det(z I - Phi),
N = c^T adj(z I - Phi) (G0 z + G1), common powers of z divided out.

Part 1, the trusted core, computes in exact rationals or in intervals rounded outward (so they
hold every true value): it recomputes q's coefficients from the inputs (e^M by its Taylor
series with a remainder bound) and checks the claimed balls hold them; it replays the
Schur-Cohn recursion on the claimed balls (every step decided, every claimed reflection ball
holding the recomputed one) to count the roots outside a circle, or up to its first step with
|a_0| > |a_k| (a root on or outside the unit circle: not stable); it checks that boxes tile a
box; by Rouche's theorem on arcs of the unit circle it carries a count from a box's centre to
all of the box; and it checks that a linear necessary condition of stability fails for every
wall from a cap on.

Part 2 reads the formats: the CRC-32, canonical hex floats (exact rationals), exactly the
members of each object (one schema table, SHAPES; a new kind of certificate adds its objects
there and its function to VERIFY). Most kinds are one general shape, a family over a box of
parameters whose leaves tile it, each leaf with a claim replayed by `decide`: a box of walls
(leaves in alpha and beta), a lookup table (each cell's boxes along its interpolation segment),
one wall over an interval of delays (cells of the delay). One wall has the recursions its claim
needs (one circle, or two for marginal); an alpha_max enclosure is a stable wall below and a
box above (with a cap: a box up to the cap of walls none stable), and a grid is a list of
those, each checked by its kind's function. Anything malformed is rejected.
"""

import functools, json, math, re, sys, zlib  # noqa: E401  (the standard library only)
from fractions import Fraction as F

PRECISIONS = (200, 800, 3200)  # bits kept by the outward rounding, tried in turn for q
PREC = PRECISIONS[0]


class Reject(Exception):
    """The claim does not follow from the certificate."""


def need(ok, why):
    """ok, or Reject saying why."""
    if not ok:
        raise Reject(why)
    return ok


# === part 1: the trusted core ================================================================

def rnd(q, up):
    """q rounded to PREC significant bits (none finer than 2^-(PREC+2200)), up or down."""
    n, d = q.numerator, q.denominator
    s = min(PREC - n.bit_length() + d.bit_length(), PREC + 2200)
    num, den = (n << s, d) if s >= 0 else (n, d << -s)
    m = -(-num // den) if up else num // den
    return F(m, 1 << s) if s >= 0 else F(m << -s)


def hull(xs):
    return Iv(rnd(min(xs), False), rnd(max(xs), True))


def iv(x):
    return x if isinstance(x, Iv) else Iv(x)


class Iv:
    """A closed interval [lo, hi] with rational ends (a rational operand is a point)."""

    def __init__(self, lo, hi=None):
        self.lo = lo if type(lo) is F else F(lo)
        self.hi = self.lo if hi is None else hi if type(hi) is F else F(hi)

    __neg__ = lambda s: Iv(-s.hi, -s.lo)
    mag = lambda s: max(abs(s.lo), abs(s.hi))
    mig = lambda s: F(0) if s.lo <= 0 <= s.hi else min(abs(s.lo), abs(s.hi))
    inside = lambda s, o: o.lo <= s.lo and s.hi <= o.hi

    def __add__(self, o):
        o = iv(o)
        return Iv(rnd(self.lo + o.lo, False), rnd(self.hi + o.hi, True))

    def __sub__(self, o):
        o = iv(o)
        return Iv(rnd(self.lo - o.hi, False), rnd(self.hi - o.lo, True))

    def __mul__(self, o):
        o = iv(o)
        if o.lo == o.hi:  # exact: a point scales both ends (their order turns with its sign)
            return hull([self.lo * o.lo, self.hi * o.lo])
        return hull([self.lo * o.lo, self.lo * o.hi, self.hi * o.lo, self.hi * o.hi])

    def __truediv__(self, o):
        o = iv(o)
        need(o.mig() > 0, "division by an interval holding 0")
        return hull([self.lo / o.lo, self.lo / o.hi, self.hi / o.lo, self.hi / o.hi])


def total(xs):
    """A sum of intervals: the ends summed exactly, then rounded once."""
    xs = list(xs)
    return Iv(rnd(sum((x.lo for x in xs), F(0)), False), rnd(sum((x.hi for x in xs), F(0)), True))


def mul(a, b):
    return [[total(x * y for x, y in zip(row, col)) for col in zip(*b)] for row in a]


def conv(a, b):
    return [total(a[i] * b[k - i] for i in range(len(a)) if 0 <= k - i < len(b))
            for k in range(len(a) + len(b) - 1)]


def eye(n):
    return [[Iv(int(i == j)) for j in range(n)] for i in range(n)]


def expm(m):
    """e^M: Taylor series of X = M / 2^s (infinity norm theta <= 1/8) until the remainder
    bound theta^(k+1) / (k+1)! * 8/7 falls below 2^-(PREC+16), added to every entry off the
    zero rows and columns of M (every power of M keeps them); then s squarings."""
    norm, s = max(total(Iv(x.mag()) for x in row).hi for row in m), 0
    while norm > F(1, 8) * 2**s:
        s += 1
    x, theta = [[e * Iv(F(1, 2**s)) for e in row] for row in m], norm / 2**s
    term, out, k, bound = eye(len(m)), eye(len(m)), 0, rnd(theta * F(8, 7), True)
    while bound >= F(1, 1 << (PREC + 16)):
        k += 1
        term = [[e / Iv(k) for e in row] for row in mul(term, x)]
        out = [[a + b for a, b in zip(r, t)] for r, t in zip(out, term)]
        bound = rnd(bound * theta / (k + 1), True)
    live = [[any(v.mag() for v in row) and any(r[j].mag() for r in m) for j in range(len(m))]
            for row in m]
    out = [[e + Iv(-bound, bound) if ok else e for e, ok in zip(r, o)] for r, o in zip(out, live)]
    for _ in range(s):
        out = mul(out, out)
    return out


def device(el, delta):
    """A, b, c of the device from the elements' exact values (MODEL.md 8); delta may be an
    interval, then the entries it enters are."""
    (mu, dh, kh), tr, tau = el.get("hand", [F(0)] * 3), el.get("transmission"), el.get("actuator")
    s = (4 if tr else 2) + (1 if tau else 0)
    a, b, c = [[F(0)] * s for _ in range(s)], [F(0)] * s, [F(0)] * s
    a[0][1] = F(1)
    if tr is None:
        a[1][0], a[1][1], c[0], scale = -kh / (1 + mu), -(delta + dh) / (1 + mu), F(1), 1 / (1 + mu)
    else:
        r, kc, dc, d2, motor = tr
        m1, m2 = 1 - r, r + mu
        a[1][0], a[1][1], a[1][2], a[1][3] = -kc / m1, -(delta - d2 + dc) / m1, kc / m1, dc / m1
        a[2][3] = F(1)
        a[3][0], a[3][1], a[3][2], a[3][3] = kc / m2, dc / m2, -(kh + kc) / m2, -(d2 + dh + dc) / m2
        c[0 if motor else 2], scale = F(1), 1 / m1
    if tau is None:
        b[1] = scale
    else:
        a[1][s - 1], a[s - 1][s - 1], b[s - 1] = scale, -1 / tau[0], 1 / tau[0]
    return a, b, c


def parts(el, delta, d):
    """Enclosures of (Q0, QA, QB), q = Q0 + alpha QA + beta QB, lowest power first (MODEL.md
    8): the device sampled by exp([[A, b], [0, 0]] tau) (Van Loan), D and adj(z I - Phi) by
    Faddeev-LeVerrier; el["filter"] = (Fn, Fd) exact, lowest power first."""
    a, b, c = device(el, delta)
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
    dpoly, num, bk = [Iv(0)] * s + [Iv(1)], [Iv(0)] * (s + 1), eye(s)
    for k in range(1, s + 1):  # num = c^T adj(zI - Phi) (G0 z + G1), adj = sum B_k z^(s-k)
        cb = [total(Iv(c[i]) * bk[i][j] for i in range(s)) for j in range(s)]
        num[s - k + 1] = num[s - k + 1] + total(x * y for x, y in zip(cb, g0))
        num[s - k] = num[s - k] + total(x * y for x, y in zip(cb, g1))
        ab = mul(phi, bk)
        dpoly[s - k] = -(total(ab[i][i] for i in range(s)) / Iv(k))
        bk = [[x + (dpoly[s - k] if i == j else Iv(0)) for j, x in enumerate(row)]
              for i, row in enumerate(ab)]
    fn, fd = ([Iv(x) for x in p] for p in el.get("filter", ([1], [1])))
    q0 = [Iv(0)] * (n + 2) + conv(dpoly, fd)
    qa, qb = [Iv(0)] + conv(fd, num), conv([Iv(-1), Iv(1)], conv(fn, num))
    out = list(zip(q0, *(p + [Iv(0)] * (len(q0) - len(p)) for p in (qa, qb))))
    while all(x.lo == x.hi == 0 for x in out[0]):  # exact: a common power of z
        out.pop(0)
    return out


@functools.lru_cache(maxsize=4096)
def paper_sample(delta, tau, prec):
    """(e^(-delta tau), phi1(tau), phi2(tau)) at an exact delta, prec bits."""
    e = expm([[Iv(0), Iv(tau), Iv(0)], [Iv(0), Iv(-delta * tau), Iv(tau)], [Iv(0)] * 3])
    return e[1][1], e[0][1], e[0][2]


def paper_parts(lo, hi, d):
    """(Q0, QA, QB) of the paper's loop for every delta in [lo, hi] (MODEL.md 2-3): q =
    z^(n+2) (z - 1)(z - c) + ((alpha + beta) z - beta) (m2 z^2 + m1 z + m0), divided by z for
    a whole d. e^(-delta t), phi1 and phi2 are integrals of e^(-delta t) with nonnegative
    weights, so they decrease in delta: each is enclosed by its values at the ends."""
    n, zero = math.floor(d), Iv(0)
    eps = d - n

    def at_tau(tau):
        ends = paper_sample(hi, tau, PREC), paper_sample(lo, tau, PREC)
        return [Iv(x.lo, y.hi) for x, y in zip(*ends)]
    (c, p1, _), (c_rest, g0v, g0x) = at_tau(F(1)), at_tau(1 - eps)
    if eps:
        _, p1e, p2e = at_tau(eps)
        g1x, g1v = p2e + g0v * p1e, c_rest * p1e
        m2, m1, m0 = g0x, p1 * g0v - c * g0x + g1x, p1 * g1v - c * g1x
        qa, qb, low = [zero, m0, m1, m2], [-m0, m0 - m1, m1 - m2, m2], n + 2
    else:
        m1 = p1 * g0v - c * g0x
        qa, qb, low = [zero, m1, g0x, zero], [-m1, m1 - g0x, g0x, zero], n + 1
    q0 = [zero] * low + [c, -(Iv(1) + c), Iv(1)]
    return [(z, qa[i] if i < 4 else zero, qb[i] if i < 4 else zero) for i, z in enumerate(q0)]


def fraction_family(delta, n, e, mid, wall):
    """(q(mid), q' over e): q's coefficients for every delay n + eps, eps in e, of the
    paper's loop (fractional form, MODEL.md 2-3) in centred form, q(eps) = q(mid) + q'(xi)
    (eps - mid) for some xi in e (mean-value theorem). With u = 1 - eps, m2' = -phi1(u), m1' =
    (1 + c) phi1(u) - phi1(1) c(u), m0' = phi1(1) c(u) - c phi1(u) (c(u) = e^(-delta u); the
    force's total effect G0 + G1 does not depend on eps), and phi1, c(u) are monotone in u:
    each is enclosed by its values at the ends of e."""
    ends = [paper_sample(delta, 1 - x, PREC) for x in (e.lo, e.hi)]
    cu, p1u = (Iv(min(v[i].lo for v in ends), max(v[i].hi for v in ends)) for i in (0, 1))
    c, p1, _ = paper_sample(delta, F(1), PREC)
    m2, m1, m0 = -p1u, (Iv(1) + c) * p1u - p1 * cu, p1 * cu - c * p1u
    qa, qb = [Iv(0), m0, m1, m2], [-m0, m0 - m1, m1 - m2, m2]
    slope = [wall[0] * x + wall[1] * y for x, y in zip(qa, qb)] + [Iv(0)] * (n + 1)
    return at(paper_parts(delta, delta, n + mid), *wall), slope


def at(parts, alpha, beta):
    """q's coefficients for all walls in the intervals alpha, beta: each is affine in the
    wall and holds each of them once, so this encloses its range."""
    return [z + (alpha * x + beta * y) for z, x, y in parts]


def held(compute, claimed):
    """compute() gives (lists of recomputed coefficients, its parts); each recomputed one must
    lie in its claimed interval. Cancellation costs absolute accuracy: the precisions are
    tried in turn until more bits cannot change the outcome. Returns compute()."""
    global PREC
    try:
        for PREC in PRECISIONS:
            owns, p = compute()
            pairs = [(o, c) for own, cl in zip(owns, claimed) for o, c in zip(own, cl)]
            ragged = any(len(o) != len(c) for o, c in zip(owns, claimed))
            if ragged or all(o.inside(c) for o, c in pairs) or any(
                    o.hi < c.lo or c.hi < o.lo for o, c in pairs):
                break  # decided: more bits cannot move a true value into a disjoint ball
    finally:
        PREC = PRECISIONS[0]
    for own, cl in zip(owns, claimed):
        need(len(cl) == len(own), f"the model's polynomial has degree {len(own) - 1}")
        need(all(o.inside(c) for o, c in zip(own, cl)),
             "a claimed ball does not hold the recomputed coefficient")
    return owns, p


def outside(coeffs, r, given, until_greater=False):
    """Roots of q outside |z| = r: the Schur-Cohn recursion (MODEL.md 11) on q(r z), every
    step decided and every given reflection (intervals) holding the recomputed a_0 / a_k.
    until_greater: the recursion must reach a step with |a_0| > |a_k| for every value, and
    stops there (its earlier steps keep the count of roots outside, so every polynomial in
    the enclosures has a root outside the unit circle or on it), and returns None."""
    a, less = [c * Iv(r**i) for i, c in enumerate(coeffs)], []
    while len(a) > 1:
        k, j = len(a) - 1, len(less)
        lt = a[0].mag() < a[k].mig()
        need(lt or a[0].mig() > a[k].mag(), f"step {j} of the recursion is undecided")
        refl = a[0] / a[k]
        need(j < len(given) and refl.inside(given[j]),
             f"reflection {j} is not in its claimed ball ({len(given)} given)")
        if until_greater and not lt:
            need(len(given) == j + 1, f"{j + 1} reflection coefficients expected")
            return None
        inv = None if lt else a[k] / a[0]
        a = [a[i + 1] - refl * a[k - 1 - i] if lt else inv * a[i + 1] - a[k - 1 - i]
             for i in range(k)]
        less.append(lt)
    need(not until_greater, "no step proves |a_0| > |a_k|")
    need(len(given) == len(less), f"{len(less)} reflection coefficients expected")
    inside = 0
    for k, lt in enumerate(reversed(less), 1):
        inside = inside + 1 if lt else k - 1 - inside
    return len(less) - inside


def capped(p, alpha, betas, k=None, sign=1):
    """Whether no wall (a, b) with a >= alpha and b in betas is stable, q = Q0 + a QA + b QB
    (parts p) monic of degree m: a stable q has L(q) < c for the linear form L of the rule:
    (-1)^m q(-1) = prod (1 + r_i) > 0 (k None: L = -(-1)^m q(-1), c = 0), or sign a_k <
    C(m, k) (|a_k| = |e_(m-k)(r)|). L(QA) > 0 and L(q) >= c at alpha for every b in betas
    prove L(q) >= c for every a >= alpha."""
    m = len(p) - 1
    w = [-(-1) ** (m + j) if k is None else sign * (j == k) for j in range(m + 1)]
    l0, la, lb = (total(Iv(wj) * x[i] for wj, x in zip(w, p) if wj) for i in range(3))
    monic = all(x.lo == x.hi == v for x, v in zip(p[m], (1, 0, 0)))  # exact
    return monic and la.lo > 0 and (l0 + Iv(alpha) * la + betas * lb).lo >= (
        0 if k is None else math.comb(m, k))


def covers(whole, boxes):
    """Whether the boxes (lists of sides) lie in the box whole, their interiors are disjoint
    and their measures add up to its measure (a side of zero width counts as 1): the union of
    finitely many closed boxes is closed, so what it missed of whole would be open there, of
    measure 0, hence empty. The ends are taken as integers (all over one common denominator)
    and the interiors tested pairwise after sorting on the first side."""
    flat = [w.lo == w.hi for w in whole]  # exact rationals
    den = math.lcm(*(x.denominator for b in [whole, *boxes] for s in b for x in (s.lo, s.hi)))
    whole, *boxes = [[(s.lo.numerator * (den // s.lo.denominator), s.hi.numerator * (
        den // s.hi.denominator)) for s in b] for b in [whole, *boxes]]
    measure = lambda b: math.prod(1 if f else hi - lo for (lo, hi), f in zip(b, flat))  # noqa: E731
    if not all(w[0] <= lo and hi <= w[1] for b in boxes for (lo, hi), w in zip(b, whole)) or sum(
            map(measure, boxes)) != measure(whole):
        return False
    boxes.sort()
    for i, b in enumerate(boxes):
        for c in boxes[i + 1:]:
            if not flat[0] and c[0][0] >= b[0][1]:
                break
            if all(f or max(s[0], t[0]) < min(s[1], t[1]) for s, t, f in zip(b, c, flat)):
                return False
    return True


def fixed(q):
    """ceil(q 2^PREC): a rational rounded up to an integer count of 2^-PREC."""
    return -(-(q.numerator << PREC) // q.denominator)


def integral(balls):
    """A polynomial of coefficient balls (mid, rad), lowest power first, as (integers c, den,
    the radii's sum in 2^-PREC rounded up) with mid = c / den, as modulus takes it."""
    den = math.lcm(*(m.denominator for m, _ in balls))
    cs = [m.numerator * (den // m.denominator) for m, _ in balls]
    return cs, den, fixed(sum(r for _, r in balls))


def modulus(poly, z):
    """Bounds of |p(z)| 2^PREC for |z| = 1, p as integral gives it, z = (x + i y) / w
    (integers): Horner's rule on sum c_k (x + i y)^k w^(n-k) in integers, each bound rounded
    outward."""
    (x, y, w), (cs, den, r) = z, poly
    re = im = 0
    for k, c in enumerate(reversed(cs)):
        re, im = re * x - im * y + c * w**k, re * y + im * x
    s, scale = math.isqrt(re * re + im * im), den * w ** (len(cs) - 1)
    return (s << PREC) // scale - r, -(-((s + 1) << PREC) // scale) + r


def clear(f, parts, box, c, us):
    """Rouche on the unit circle (MODEL.md 11): |f| > ra |QA| + rb |QB| on every arc between
    the points ((1 - t^2) + 2 i t) / (1 + t^2) of the parameters us (t = u - 1 up to u = 2,
    then minus the point of t = u - 3): at an arc's first end z0, with h its chord, |p(z)| is
    within h |p'(z0)| + h^2 sum C(k, 2) |p_k| of |p(z0)|. So every wall of the box has the
    count of roots outside of its centre c, none on the circle. Every quantity is an integer
    count of 2^-PREC rounded the way that keeps the inequality a proof."""
    qa, qb = [x for _, x, _ in parts], [y for _, _, y in parts]
    need(not (qa[-1].mag() or qb[-1].mag()), "the wall changes the degree of q")
    need(us[:1] == [0] and us[-1:] == [4] and 2 in us and all(a < b for a, b in zip(us, us[1:])),
         "the arcs must rise from 0 to 4 through 2")
    radii = [max(m.lo - s.lo, s.hi - m.hi) for m, s in zip(c, box)]
    balls = [[((x.lo + x.hi) / 2, (x.hi - x.lo) / 2) for x in p] for p in (f, qa, qb)]
    curve = fixed(sum(w * sum(math.comb(k, 2) * (abs(m) + r) for k, (m, r) in enumerate(p))
                      for w, p in zip([1] + radii, balls)))
    ra, rb = map(fixed, radii)
    polys = [integral(p) for p in balls]
    slopes = [integral([(k * m, k * r) for k, (m, r) in enumerate(p)][1:]) for p in balls]
    for u0, u1 in zip(us, us[1:]):
        shift, sign = (1, 1) if u1 <= 2 else (3, -1)
        (p0, q0), (p1, q1) = ((u - shift).as_integer_ratio() for u in (u0, u1))
        z = (sign * (q0 * q0 - p0 * p0), sign * 2 * p0 * q0, q0 * q0 + p0 * p0)
        h2 = (4 * (p1 * q0 - p0 * q1) ** 2 << 2 * PREC) // (z[2] * (q1 * q1 + p1 * p1))
        h = math.isqrt(h2) + 1  # >= the chord 2^PREC: (isqrt(n) + 1)^2 >= n + 1 > its square
        (f_lo, _), (_, a_hi), (_, b_hi) = (modulus(p, z) for p in polys)
        slope = sum(w * modulus(p, z)[1] for w, p in zip([1 << PREC, ra, rb], slopes))
        if not ((f_lo << PREC) - ra * a_hi - rb * b_hi) << PREC > h * slope + h * h * curve:
            return False
    return True


# === part 2: the formats =====================================================================

# The schema: every object's members, the required ones first, then groups present all
# together or not at all. A certificate of kind K says "certificate": "stabound K certificate 1"
# and is checked by VERIFY[K]: a new kind adds its line here and its function there.
SHAPES = {shape: [group.split() for group in groups] for shape, *groups in [
    ("stability", "certificate model inputs degree coefficients recursions claim"),
    ("box", "certificate model inputs degree leaves claim"),
    ("alpha_max", "certificate stable_below unstable_above claim", "cap"),
    ("alpha_max grid", "certificate rows claim"),
    ("table", "certificate model table cells claim"),
    ("delays", "certificate model inputs cells claim"),
    ("model", "loop elements polynomial"),
    ("recursion", "radius outside reflections"),
    ("leaf", "alpha beta claim coefficients reflections", "centre arcs"),
    ("unstable leaf", "alpha beta claim coefficients reflections outside", "centre arcs", "eps"),
    ("enclosure", "alpha_lo alpha_hi"),
    ("enclosure to a cap", "alpha_lo alpha_hi stiffer"),
    ("cap", "alpha rule", "k sign"),
    ("lookup", "precision guard delta d alpha beta"),
    ("cell", "row column boxes"),
    ("table box", "s coefficients reflections"),
    ("table box with elements", "s coefficients reflections", "centre delta family arcs"),
    ("delays cell", "n eps centre claim coefficients reflections", "slope arcs"),
    ("unstable delays cell", "n eps centre claim coefficients reflections outside", "slope arcs"),
    ("hand", "mu_h delta_h kappa_h"),  # the elements, in the order a model names them
    ("transmission", "r kappa_c delta_c delta_2 encoder"),
    ("actuator", "tau")]}
ELEMENTS = ("hand", "transmission", "actuator", "filter")
GUARDS = {"double": F(16, 2**53), "float": F(16, 2**24)}  # a table's: 16 units of roundoff
CLAIMS = ("stable", "unstable", "undecided", "not stable")  # a leaf's


def canonical_hex(v):
    mant, exp = v.hex().split("p")
    return (mant.rstrip("0").rstrip(".") if "." in mant else mant) + "p" + exp


def number(s):
    """An exact rational from a canonical finite C99 hex float."""
    try:
        v = float.fromhex(s)
    except (TypeError, ValueError, OverflowError):
        raise Reject(f"{s!r} is not a hex float") from None
    need(math.isfinite(v) and canonical_hex(v) == s, f"{s!r} is not a canonical finite hex float")
    return F(v)


def balls(bs):
    """A list of balls {"mid", "rad"} as intervals."""
    need(isinstance(bs, list) and all(isinstance(b, dict) and set(b) == {"mid", "rad"} for b in bs),
         f"{bs!r:.40} is not a list of balls")
    mid_rad = [(number(b["mid"]), number(b["rad"])) for b in bs]
    need(all(rad >= 0 for _, rad in mid_rad), "negative radius")
    return [Iv(mid - rad, mid + rad) for mid, rad in mid_rad]


def pair(p):
    """A box side [lo, hi] of hex floats as an interval."""
    need(isinstance(p, list) and len(p) == 2 and number(p[0]) <= number(p[1]),
         f"{p!r} is not a side [lo, hi] of a box")
    return Iv(number(p[0]), number(p[1]))


def members(obj, shape, *extra):
    """obj is a dict with exactly the members of its shape (SHAPES) and the extra ones."""
    required, *groups = (set(g) for g in SHAPES[shape])
    have = set(obj) - required - set(extra) if isinstance(obj, dict) else None
    need(have is not None and required | set(extra) <= set(obj) and have <= set().union(*groups)
         and all(g <= have or not g & have for g in groups), f"unexpected members in {obj!r:.80}")
    return obj


def kind(cert, want=None, *extra):
    """The certificate's kind (want, or any), with exactly that kind's members."""
    got = cert.get("certificate") if isinstance(cert, dict) else None
    m = re.fullmatch("stabound (.*) certificate 1", got) if isinstance(got, str) else None
    need(m and m.group(1) in VERIFY and want in (None, m.group(1)), "unknown certificate format")
    members(cert, m.group(1), *extra)
    return m.group(1)


def unique(pairs):
    need(len({k for k, _ in pairs}) == len(pairs), f"duplicate keys in {[k for k, _ in pairs]}")
    return dict(pairs)


def load(data):
    """The certificate's JSON, its CRC-32 checked (any changed character fails)."""
    m = re.fullmatch(rb'(\{\n.*,\n)  "crc32": "([0-9a-f]{8})"\n\}\n', data, re.S)
    need(m, "not a certificate: no crc32 member at its end")
    need(zlib.crc32(m.group(1)) == int(m.group(2), 16),
         "the CRC-32 does not match the text: the certificate was changed")
    try:
        cert = json.loads(data, object_pairs_hook=unique, parse_constant=lambda c: need(
            False, f"{c} is not a number a certificate may hold"))
    except ValueError as e:
        raise Reject(f"not JSON: {e}") from None
    kind(cert, None, "crc32")
    return cert


def elements(model, source):
    """The elements in source, which the model must name in ELEMENTS' order, as device and
    parts take them (exact values, checked in range)."""
    names = [k for k in ELEMENTS if k in source]
    need(members(model, "model")["elements"] == names and model["loop"] == (
        "elements" if names else "paper"), "the model must name the loop and its elements")
    el = {k: [number(members(source[k], k)[m]) for m in SHAPES[k][0] if m != "encoder"]
          for k in names if k != "filter"}
    hand, tr = el.get("hand", [0]), el.get("transmission", [F(1, 2), 0])
    need(min(hand) >= 0 and 0 < tr[0] < 1 and min(tr[1:]) >= 0 and el.get("actuator", [1])[0] > 0,
         "an element's value is out of range (hand and transmission >= 0, 0 < r < 1, tau > 0)")
    if "transmission" in el:
        encoder = source["transmission"]["encoder"]
        need(encoder in ("motor", "handle"), f"unknown encoder {encoder!r}")
        el["transmission"].append(encoder == "motor")
    if "filter" in source:
        el["filter"] = velocity_filter(source["filter"])
    return names, el


def velocity_filter(f):
    """(Fn, Fd), lowest power first, exact."""
    if set(f) == {"pole"} and 0 < number(f["pole"]) < 1:
        return [F(0), 1 - number(f["pole"])], [-number(f["pole"]), F(1)]
    if set(f) == {"samples"} and type(f["samples"]) is int and 2 <= f["samples"] <= 64:
        return [F(1, f["samples"])] * f["samples"], [F(0)] * (f["samples"] - 1) + [F(1)]
    need(set(f) == {"numerator", "denominator"} and len(f["denominator"]) == 3 == len(
        f["numerator"]) and f["denominator"][2] == "0x1p+0", f"unknown filter {f!r}")
    return [number(x) for x in f["numerator"]], [number(x) for x in f["denominator"]]


def point(x):
    return Iv(number(x))


def centre(leaf, box):
    """A leaf decided around its centre: the centre as a wall of points (inside the leaf's
    box), else None."""
    c = leaf.get("centre")
    need(c is None or isinstance(c, list) and len(c) == 2, "a leaf's centre is [alpha, beta]")
    c = c and tuple(map(point, c))
    need(not c or all(p.inside(s) for p, s in zip(c, box)), "a leaf's centre lies outside it")
    return c


def each(items, label, check):
    """check(i, item) for every item of the list items (one or more), its rejection labelled."""
    need(isinstance(items, list) and items, f"one or more {label}s are needed")
    done = []
    for i, item in enumerate(items):
        try:
            done.append(check(i, item))
        except Reject as e:
            raise Reject(f"{label} {i}: {e}") from None
    return done


def decide(leaf, claim, coeffs, rouche=None, r=F(1)):
    """A leaf's claim (CLAIMS) from coeffs, its claimed coefficients (at its centre when
    rouche is given): undecided proves nothing and lists no reflections; not stable is the
    recursion up to its step |a_0| > |a_k|; stable and unstable count the roots outside the
    circle |z| = r (r > 1 for an unstable leaf only: a root outside it is outside 1),
    and rouche = (f, parts, box, centre) carries the centre's count to the whole leaf (clear,
    on the leaf's arcs). Returns claim."""
    need(claim in CLAIMS, f"unknown claim {claim!r}")
    given = balls(leaf["reflections"])
    if claim in ("undecided", "not stable"):
        need(not rouche, f"a leaf {claim} is not decided around a centre")
        need(claim == "not stable" or given == [], "an undecided leaf lists no reflections")
        if claim == "not stable":
            outside(coeffs, 1, given, until_greater=True)
        return claim
    need(1 <= r < 2 and (r == 1 or claim == "unstable"), "eps must be in [0, 1)")
    out = outside(coeffs, r, given)
    need(not rouche or r == 1 and clear(*rouche, [number(u) for u in leaf["arcs"]]),
         "a root may cross the unit circle within the leaf")
    need((out == 0) == (claim == "stable") and (out == 0 or out == leaf["outside"]),
         f"{out} roots outside do not prove {claim}")
    return claim


def proved(claims, claim):
    """The family's verdict from its leaves' claims, which the certificate's claim must state
    with the counts (that of not stable leaves only where there are some)."""
    counts = {k: claims.count(k) for k in CLAIMS if k != "not stable" or k in claims}
    n, (stable, unstable) = len(claims), (counts["stable"], counts["unstable"])
    verdict = "stable" if stable == n else "unstable" if unstable == n else "not stable" if (
        unstable + counts.get("not stable", 0) == n) else "not proved"
    need(claim == dict(verdict=verdict, **counts),
         f"the leaves prove {verdict} with counts {counts}, not {claim!r}")
    return verdict, counts


def wall_inputs(cert):
    """The model's elements, and the exact delta and d, of a certificate's inputs."""
    inputs = cert["inputs"]
    names, el = elements(cert["model"], inputs)
    need(list(inputs) == ["alpha", "beta", "delta", "d", *names],
         "inputs must be alpha, beta, delta, d and the elements in order")
    delta, d = number(inputs["delta"]), number(inputs["d"])
    need(delta >= 0 and 0 <= d <= 10000, "delta must be >= 0 and d in [0, 10000]")
    return el, delta, d


def enclosures(cert, walls, claims):
    """q's coefficients for each box of walls (alpha, beta) of a wall or box certificate,
    each inside its claimed ball; returns (recomputed, claimed, parts)."""
    el, delta, d = wall_inputs(cert)
    claimed = [balls(c) for c in claims]

    def compute():
        p = parts(el, delta, d)
        return [at(p, *w) for w in walls], p
    owns, p = held(compute, claimed)
    n = len(owns[0]) - 1
    need(cert["degree"] == n, f"the model's polynomial has degree {n}")
    return owns, claimed, p


def verify_single(cert):
    """One wall: q's coefficients, then the recursions at the radii the claim needs."""
    inputs, claim, runs = cert["inputs"], cert["claim"], cert["recursions"]
    (own,), (coeffs,), _ = enclosures(cert, [(point(inputs["alpha"]), point(inputs["beta"]))],
                              [cert["coefficients"]])
    verdict, n = claim.get("verdict"), len(own) - 1
    if "coefficient_above_binomial" in claim:
        # a monic q with every root in |z| <= 1 has |a_k| = |e_(n-k)(roots)| <= binom(n, k)
        k = claim["coefficient_above_binomial"]
        need(set(claim) == {"verdict", "coefficient_above_binomial"} and verdict == "unstable"
             and runs == [], "unexpected members in the claim")
        need(type(k) is int and 0 <= k <= n and own[n].lo == own[n].hi == 1  # exact
             and own[k].mig() > math.comb(n, k),
             f"coefficient {k} is not proven above binom({n}, {k})")
        return f"unstable: coefficient {k} exceeds binom({n}, {k}), so a root is outside"
    extra = {"unstable": ["outside"], "marginal": ["eps"]}.get(verdict, [])
    need(verdict in ("stable", "unstable", "marginal") and set(claim) == {"verdict", *extra},
         "unexpected members in the claim")
    eps = number(claim["eps"]) if verdict == "marginal" else F(0)
    need(verdict != "marginal" or 0 < eps < F(1, 2), "eps must be in (0, 1/2)")
    radii = {"1": 1, "1+eps": 1 + eps, "1-eps": 1 - eps}
    names = ["1+eps", "1-eps"] if eps else ["1"]
    need(isinstance(runs, list) and [r.get("radius") for r in runs] == names,
         f"the {verdict} claim needs the recursions at radius {names}")

    def run(i, r):
        out = outside(coeffs, radii[members(r, "recursion")["radius"]], balls(r["reflections"]))
        return need(r["outside"] == out, f"{out} roots outside, not {r['outside']}") and out
    counts = each(runs, "recursion", run)
    if eps:
        need(counts[0] == 0 and counts[1] >= 1, f"the counts {counts} do not prove {claim!r}")
        return f"marginal: spectral radius within {float(eps)!r} of 1"
    need((counts[0] == 0) == (verdict == "stable") and claim.get("outside", 0) == counts[0],
         f"the counts {counts} do not prove {claim!r}")
    return "stable: every root inside the unit circle" if verdict == "stable" else \
        f"unstable: {counts[0]} roots outside the unit circle, none on it"


def verify_box(cert):
    """A box of walls: the leaves tile it, and each leaf's claim is replayed."""
    leaves = each(cert["leaves"], "leaf", lambda i, leaf: members(
        leaf, "unstable leaf" if leaf.get("claim") == "unstable" else "leaf"))
    walls = [(pair(leaf["alpha"]), pair(leaf["beta"])) for leaf in leaves]
    need(covers((pair(cert["inputs"]["alpha"]), pair(cert["inputs"]["beta"])), walls),
         "the leaves do not cover the box exactly")
    centres = [centre(leaf, box) for leaf, box in zip(leaves, walls)]
    _, claimed, p = enclosures(cert, [c or w for c, w in zip(centres, walls)],
                               [leaf["coefficients"] for leaf in leaves])
    claims = each(leaves, "leaf", lambda i, leaf: decide(
        leaf, leaf["claim"], claimed[i], centres[i] and (claimed[i], p, walls[i], centres[i]),
        1 + number(leaf.get("eps", "0x0p+0"))))
    verdict, counts = proved(claims, cert["claim"])
    return f"not proved for the whole box: leaves {counts}" if verdict == "not proved" \
        else f"{verdict} for every wall of the box ({len(leaves)} leaves)"


def verify_amax(cert):
    """An enclosure of alpha_max: a stable wall at alpha_lo, and no damping of the box's
    range that stabilizes alpha_hi (without a cap: the box is the strip at alpha_hi, every
    wall unstable) or any stiffer wall (with one: the box reaches the cap, no wall of it
    stable, and the cap's rule fails from the cap on: see capped); both on the same loop."""
    below, above, claim = cert["stable_below"], cert["unstable_above"], cert["claim"]
    cap = cert.get("cap")
    kind(below, "stability")
    kind(above, "box")
    members(claim, "enclosure" if cap is None else "enclosure to a cap")
    need(cap is None or claim["stiffer"] == "none stable", "unexpected members in the claim")
    lo, hi, ins, ina = number(claim["alpha_lo"]), number(claim["alpha_hi"]), below["inputs"], \
        above["inputs"]
    need(below["model"] == above["model"] and list(ins) == list(ina) and all(
        ins[k] == ina[k] for k in list(ins)[2:]),
        "the stable wall and the unstable strip are on different loops")
    alphas, betas = pair(ina["alpha"]), pair(ina["beta"])
    need(number(ins["alpha"]) == lo < hi == alphas.lo  # exact rationals
         and (cap is not None or alphas.hi == hi) and point(ins["beta"]).inside(betas),
         "the certificates are not at alpha_lo < alpha_hi within the dampings")
    need(verify(below).startswith("stable") and verify(above).startswith(
        ("unstable", "not stable") if cap is not None else "unstable"),
        "the wall below is not proved stable or the walls above not unstable")
    if cap is not None:
        rule, k, sign = members(cap, "cap")["rule"], cap.get("k"), cap.get("sign", 1)
        p = parts(wall_inputs(above)[0], number(ina["delta"]), number(ina["d"]))
        need(rule == "q(-1)" and "k" not in cap or rule == "coefficient" and "k" in cap and type(
            k) is int and 0 <= k < len(p) - 1 and sign in (1, -1) and type(sign) is int,
            f"unknown cap {cap!r}")
        need(capped(p, number(cap["alpha"]), betas, k, sign),
             "the cap's condition is not proved to fail from the cap on")
        need(alphas.hi >= number(cap["alpha"]), "the box above does not reach the cap")
    return f"alpha_max in [{float(lo)!r}, {float(hi)!r}]: a stable wall at alpha_lo, and no " \
        f"damping in [{float(betas.lo)!r}, {float(betas.hi)!r}] stabilizes " + (
            "alpha_hi or any stiffer wall" if cap is not None else "alpha_hi")


def verify_grid(cert):
    """Several alpha_max enclosures (the rows of a grid of devices), each checked alone."""
    done = each(cert["rows"], "row", lambda i, row: kind(row, "alpha_max") and verify_amax(row))
    need(cert["claim"] == {"rows": len(done)}, "the claim must count the rows")
    return f"{len(done)} rows" + "".join(f"\nrow {i}: {text}" for i, text in enumerate(done))


def span(v0, v1, s, guard):
    """v0 + t (v1 - v0) for t in the interval s, widened either way by guard * max(|v0|, |v1|)
    (delta is clipped at 0 by the caller)."""
    ends, slack = [v0 + t * (v1 - v0) for t in (s.lo, s.hi)], guard * max(abs(v0), abs(v1))
    return Iv(min(ends) - slack, max(ends) + slack)


def verify_table(cert):
    """A lookup table: a cell is one delta interval [X[j], X[j+1]] of one row d (whole delays,
    or one row); a query at delta = X[j] + s (X[j+1] - X[j]), s in [0, 1], reads alpha = A[j]
    + s (A[j+1] - A[j]), beta alike, all within the guard (firmware rounding: span). A cell's
    boxes are s ranges tiling [0, 1], each a leaf proved stable for its whole (delta, alpha,
    beta) box: the paper's loop enclosed by monotonicity, a loop with elements with an interval
    delta (or at a centre, its delta one member's, carried to the box by Rouche)."""
    tab, cells = cert["table"], cert["cells"]
    names, el = elements(cert["model"], tab)
    members(tab, "lookup", *names)
    guard = GUARDS.get(tab["precision"])
    need(guard is not None and number(tab["guard"]) == guard, f"the guard is {GUARDS}[precision]")
    xs, ds = ([number(x) for x in tab[k]] for k in ("delta", "d"))
    need(xs and ds and xs[0] >= 0 and all(a < b for v in (xs, ds) for a, b in zip(v, v[1:]))
         and (len(ds) == 1 or all(x.denominator == 1 for x in ds)) and 0 <= ds[0] <= 10000,
         "the axes must be increasing, delta >= 0, d whole (or one) in [0, 10000]")
    nodes = [[[number(x) for x in row] for row in tab[k]] for k in ("alpha", "beta")]
    need(all(len(g) == len(ds) and all(len(r) == len(xs) for r in g) for g in nodes),
         "the nodes must be a d by delta grid")
    want = [(i, j) for i in range(len(ds)) for j in range(max(len(xs) - 1, 1))]
    need(isinstance(cells, list) and [(c.get("row"), c.get("column")) if isinstance(c, dict)
                                      else None for c in cells] == want,
         f"the cells must be every (row, column) in order: {len(want)} cells")

    def check_box(i, j, box):
        members(box, "table box with elements" if names else "table box")
        j1, s = min(j + 1, len(xs) - 1), pair(box["s"])
        walls = [span(g[i][j], g[i][j1], s, guard) for g in nodes]
        deltas = span(xs[j], xs[j1], s, guard)
        lo, hi, c = max(deltas.lo, F(0)), deltas.hi, centre(box, walls)
        member = number(box["delta"]) if c else None
        need(not c or lo <= member <= hi, "the member's delta lies outside the box")

        def compute():  # at a centre: q of one member there, and the family's
            p = parts(el, Iv(lo, hi), ds[i]) if names else paper_parts(lo, hi, ds[i])
            return ([at(parts(el, member, ds[i]), *c), at(p, *c)] if c else [at(p, *walls)]), p
        claimed = [balls(box["coefficients"])] + ([balls(box["family"])] if c else [])
        _, p = held(compute, claimed)
        # Rouche on the arcs for every loop of the box's delta range and every wall: no root
        # on the circle, so each has the member's count (the family is connected)
        decide(box, "stable", claimed[0], c and (claimed[1], p, walls, c))
        return s

    def check_cell(_, cell):
        boxes = each(members(cell, "cell")["boxes"], "box",
                     lambda k, box: check_box(cell["row"], cell["column"], box))
        need(covers([Iv(0, 1)], [[s] for s in boxes]), "the boxes' s ranges do not tile [0, 1]")
        return len(boxes)
    n = sum(each(cells, "cell", check_cell))
    need(cert["claim"] == {"verdict": "stable", "cells": len(cells), "boxes": n},
         f"the cells prove stable with {len(cells)} cells and {n} boxes, not {cert['claim']!r}")
    return f"stable for every wall of the table's lookup: {len(cells)} cells, {n} boxes, " \
        f"delta in [{float(xs[0])!r}, {float(xs[-1])!r}], guard {float(guard)!r}"


def verify_delays(cert):
    """One wall of the paper's loop over every delay d of [d0, d1] (a set of devices that
    differ in their delay): the cells (n whole samples, fractions [e0, e1]) tile [d0, d1];
    each cell's coefficients are recomputed for every delay n + eps, eps in [e0, e1], in the
    fractional form (at eps = 0 it is z times the whole delay's polynomial, at 1 the delay n +
    1's, so a cell is one family) by fraction_family around the cell's centre, and its claim
    replayed: no root outside (stable) or the claimed count outside (unstable) for every delay
    of it. A cell with arcs counts the roots of its centre's polynomial, and Rouche on the arcs
    (the slope as the perturbation's direction, |eps - mid| its radius) carries that count to
    every delay of the cell."""
    inputs = cert["inputs"]
    elements(cert["model"], {})  # the paper's loop
    need(list(inputs) == ["alpha", "beta", "delta", "d"], "inputs must be alpha, beta, delta, d")
    wall, delta = (point(inputs["alpha"]), point(inputs["beta"])), number(inputs["delta"])
    ds = pair(inputs["d"])
    need(delta >= 0 and 0 <= ds.lo < ds.hi <= 10000,
         "delta must be >= 0 and the delays an interval within [0, 10000]")

    def check(_, cell):
        unstable = cell.get("claim") == "unstable"
        claim = members(cell, "unstable delays cell" if unstable else "delays cell")["claim"]
        n, e, mid = cell["n"], pair(cell["eps"]), number(cell["centre"])
        need(type(n) is int and 0 <= n and 0 <= e.lo < e.hi <= 1 and e.lo <= mid <= e.hi
             and 0 < mid < 1,
             "the cell is not a fraction of a sample around its centre")
        centred = "arcs" in cell
        claimed = [balls(cell["coefficients"])] + ([balls(cell["slope"])] if centred else [])

        def compute():
            c, s = fraction_family(delta, n, e, mid, wall)
            off = Iv(e.lo - mid, e.hi - mid)
            return ([c, s] if centred else [[x + y * off for x, y in zip(c, s)]]), None
        owns, _ = held(compute, claimed)
        need(claim != "not stable", "a cell is stable, unstable or undecided")
        slope = centred and [(Iv(0), x, Iv(0)) for x in owns[1]]
        rouche = centred and (claimed[0], slope, (e, Iv(0)), (Iv(mid), Iv(0)))
        return decide(cell, claim, claimed[0], rouche), Iv(n + e.lo, n + e.hi)
    cells = each(cert["cells"], "cell", check)
    need(covers([ds], [[d] for _, d in cells]), "the cells do not tile the delays")
    verdict, counts = proved([c for c, _ in cells], cert["claim"])
    return f"{verdict} at every delay in [{float(ds.lo)!r}, {float(ds.hi)!r}] " \
        f"({len(cells)} cells)" \
        if verdict != "not proved" else f"not proved for every delay: cells {counts}"


def verify(cert):
    """The proven claim as text, or Reject (a malformed certificate too)."""
    try:
        return VERIFY[kind(cert, None, *{"crc32"} & set(cert))](cert)
    except (KeyError, IndexError, TypeError, AttributeError, ValueError, ArithmeticError) as e:
        raise Reject(f"malformed certificate ({type(e).__name__}: {e})") from None


VERIFY = {"stability": verify_single, "box": verify_box, "alpha_max": verify_amax,
          "alpha_max grid": verify_grid, "table": verify_table, "delays": verify_delays}


def main(argv):
    if len(argv) != 2:
        print(__doc__.split("\n\n")[1], file=sys.stderr)
        return 2
    try:
        with open(0 if argv[1] == "-" else argv[1], "rb") as f:
            print("verified:", verify(load(f.read())))
        return 0
    except OSError as e:
        print(f"cannot read {argv[1]}: {e}", file=sys.stderr)
        return 2
    except Reject as e:
        print(f"rejected: {e}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
