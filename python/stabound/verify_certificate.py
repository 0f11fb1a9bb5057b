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

Part 2 reads the one format (version 2; format 1 is refused, to be written again): the CRC-32,
JSON with no repeated member, every member named in HEX a canonical hex float (an exact
rational) or lists of them, every object {"mid", "rad"} a ball (an interval), and exactly the
members the checks read (any other member is refused: see Obj). A kind over a box of
parameters lists leaves (its box, claim, evidence, and a centre with arcs when decided around
it), each replayed by `decide`: a box of walls (leaves in alpha and beta), one wall over an
interval of delays (leaves n + [e0, e1]) and a lookup table (each cell's leaves along its
interpolation segment, in s). One wall has the recursions its claim needs (one circle, or
two for marginal); an alpha_max enclosure is a stable wall below and a box above (with a
cap: a box up to the cap of walls none stable), and a grid is a list of those. A set of
devices wraps one-loop certificates of one kind, one per member (every combination of the
set's alternatives once), for the verdict over the set or the robust alpha_max's enclosure
(above it, one member's proof, or pieces of the damping range each proved for one member);
members of another mass than the set's reference are stated in its normalization with their
mass, and scaled exactly (wall_inputs).
Anything malformed is rejected.
"""

import functools, itertools, json, math, re, sys, zlib  # noqa: E401  (the standard library only)
from fractions import Fraction as F

PRECISIONS = (200, 800, 3200)  # bits kept by the outward rounding, tried in turn for q
PIECES = (1, 2, 4, 8, 16)  # a table leaf's delta range split into as many, tried in turn
PREC, FIRST = PRECISIONS[0], 64  # FIRST: the bits of a table box's first try


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


def hull(los, his=None):
    """[min(los), max(his)] (his = los when omitted), rounded outward."""
    return Iv(rnd(min(los), False), rnd(max(his or los), True))


def iv(x):
    return x if isinstance(x, Iv) else Iv(x)


class Iv:
    """A closed interval [lo, hi] with rational ends (a rational operand is a point, a product
    by it two products); every operation rounds its exact result outward once."""

    def __init__(self, lo, hi=None):
        self.lo = lo if type(lo) is F else F(lo)
        self.hi = self.lo if hi is None else hi if type(hi) is F else F(hi)

    __neg__ = lambda s: Iv(-s.hi, -s.lo)
    __sub__ = lambda s, o: Iv(rnd(s.lo - iv(o).hi, False), rnd(s.hi - iv(o).lo, True))
    __add__ = lambda s, o: Iv(rnd(s.lo + iv(o).lo, False), rnd(s.hi + iv(o).hi, True))

    __mul__ = lambda s, o: hull([x * y for o in [iv(o)] for x in (s.lo, s.hi)
                                 for y in (o.lo, o.hi)[:2 - (o.lo == o.hi)]])
    __truediv__ = lambda s, o: need(iv(o).mig() > 0, "division by an interval holding 0") and (
        hull([x / y for x in (s.lo, s.hi) for y in (iv(o).lo, iv(o).hi)]))
    mag = lambda s: max(abs(s.lo), abs(s.hi))
    mig = lambda s: F(0) if s.lo <= 0 <= s.hi else min(abs(s.lo), abs(s.hi))
    inside = lambda s, o: o.lo <= s.lo and s.hi <= o.hi


def total(xs):
    """A sum of intervals: the ends summed exactly, then rounded once."""
    xs = list(xs)
    return Iv(rnd(sum((x.lo for x in xs), F(0)), False), rnd(sum((x.hi for x in xs), F(0)), True))


def conv(a, b):
    return [total(a[i] * b[k - i] for i in range(len(a)) if 0 <= k - i < len(b))
            for k in range(len(a) + len(b) - 1)]


def imul(a, b, w, k=1):  # a b / (k 2^w), matrices of integer intervals (lo, hi), outward
    return [[(sum(min(p) for p in ps) // (k << w), -(-sum(max(p) for p in ps) // (k << w)))
             for ps in ([[x * y for x in u for y in v] for u, v in zip(row, col)]
                        for col in zip(*b))] for row in a]


def expm(m):
    """e^M: Taylor series of X = M / 2^s (infinity norm theta <= 1/8) until the remainder
    bound theta^(k+1) / (k+1)! * 8/7 falls below 2^-(PREC+16), added to every entry off the
    zero rows and columns of M (every power of M keeps them); then s squarings; all in integer
    intervals, counts of 2^-(PREC+24), each step rounded outward (floor below, ceiling above)."""
    w = PREC + 24
    x = [[(math.floor(e.lo * 2**w), math.ceil(e.hi * 2**w)) for e in row] for row in m]
    norm = max(sum(max(-lo, hi) for lo, hi in row) for row in x)  # of M 2^w, rounded up
    s = max(0, norm.bit_length() + 3 - w)  # so that theta = norm 2^-(w+s) <= 1/8
    x = [[(lo >> s, -(-hi >> s)) for lo, hi in row] for row in x]
    term = out = [[(int(i == j) << w,) * 2 for j in range(len(m))] for i in range(len(m))]
    k, r = 0, -(-8 * norm // (7 << s))  # the remainder bound theta 8/7 in counts of 2^-w
    while r >= 1 << 8:  # 2^-(PREC+16)
        k += 1
        term = imul(term, x, w, k)
        out = [[(a[0] + b[0], a[1] + b[1]) for a, b in zip(u, t)] for u, t in zip(out, term)]
        r = -(-r * norm // ((k + 1) << w + s))  # times theta / (k + 1)
    out = [[(lo - r, hi + r) if any(v.mag() for v in row) and any(c[j].mag() for c in m) else (
        lo, hi) for j, (lo, hi) in enumerate(o)] for row, o in zip(m, out)]
    for _ in range(s):
        out = imul(out, out, w)
    return [[Iv(F(lo, 1 << w), F(hi, 1 << w)) for lo, hi in row] for row in out]


def device(el, delta):
    """A, b and the output y = x_out of the device from the elements' exact values (MODEL.md 8;
    c is the unit vector e_out); delta may be an interval, then the entries it enters are."""
    (mu, dh, kh), tr, tau = el.get("hand", [F(0)] * 3), el.get("transmission"), el.get("actuator")
    s = (4 if tr else 2) + (1 if tau else 0)
    a, b, out = [[F(0)] * s for _ in range(s)], [F(0)] * s, 0
    a[0][1] = F(1)
    if tr is None:
        a[1][0], a[1][1], scale = -kh / (1 + mu), -(delta + dh) / (1 + mu), 1 / (1 + mu)
    else:
        r, kc, dc, d2, encoder = tr
        m1, m2 = 1 - r, r + mu
        a[1][:4] = -kc / m1, -(delta - d2 + dc) / m1, kc / m1, dc / m1
        a[2][3] = F(1)
        a[3][:4] = kc / m2, dc / m2, -(kh + kc) / m2, -(d2 + dh + dc) / m2
        out, scale = 0 if encoder == "motor" else 2, 1 / m1
    if tau:  # the lag's state is last: the force enters it, it enters the motor's velocity
        a[1][s - 1], a[s - 1][s - 1] = scale, -1 / tau[0]
    b[s - 1 if tau else 1] = (1 / tau[0] if tau else scale) * el.get("scale", 1)  # the wall's
    return a, b, out


def parts(el, delta, d):
    """Enclosures of (Q0, QA, QB), q = Q0 + alpha QA + beta QB, lowest power first (MODEL.md
    8): the device sampled by exp([[A, b], [0, 0]] tau) (Van Loan), D and adj(z I - Phi) by
    Faddeev-LeVerrier; el["filter"] = (Fn, Fd) exact, lowest power first."""
    a, b, out = device(el, delta)
    n, s = math.floor(d), len(a)
    eps = d - n

    def sample(tau):  # (e^(A tau), Gamma(tau))
        e = expm([[iv(x * tau) for x in row] + [Iv(bi * tau)] for row, bi in zip(a, b)]
                 + [[Iv(0)] * (s + 1)])
        return [row[:s] for row in e[:s]], [row[s] for row in e[:s]]

    (rest, g0), gam = sample(1 - eps), sample(eps)[1]  # Gamma(0) = 0: then G1 = 0 exactly
    phi = sample(F(1))[0] if eps else rest
    g1 = [total(r * g for r, g in zip(row, gam)) for row in rest]
    dpoly, num = [Iv(0)] * s + [Iv(1)], [Iv(0)] * (s + 1)
    bk = [[Iv(int(i == j)) for j in range(s)] for i in range(s)]
    for k in range(1, s + 1):  # num = c^T adj(zI - Phi) (G0 z + G1), adj = sum B_k z^(s-k)
        num[s - k + 1] = num[s - k + 1] + total(x * y for x, y in zip(bk[out], g0))
        num[s - k] = num[s - k] + total(x * y for x, y in zip(bk[out], g1))
        ab = [[total(x * y for x, y in zip(row, col)) for col in zip(*bk)] for row in phi]
        dpoly[s - k] = -(total(ab[i][i] for i in range(s)) / Iv(k))
        bk = [[x + (dpoly[s - k] if i == j else Iv(0)) for j, x in enumerate(row)]
              for i, row in enumerate(ab)]
    fn, fd = ([Iv(x) for x in p] for p in el.get("filter", ([1], [1])))
    return joined([Iv(0)] * (n + 2) + conv(dpoly, fd), [Iv(0)] + conv(fd, num),
                  conv([Iv(-1), Iv(1)], conv(fn, num)))


def joined(q0, qa, qb):
    """The parts as rows (Q0, QA, QB) of one power of z, lowest first (QA and QB padded with
    zeros), without the powers of z common to all (leading rows exactly 0)."""
    out = list(zip(q0, *(p + [Iv(0)] * (len(q0) - len(p)) for p in (qa, qb))))
    while all(x.lo == x.hi == 0 for x in out[0]):  # exact: a common power of z
        out.pop(0)
    return out


def pieces(el, lo, hi, d, n):
    """parts for every delta in [lo, hi]: the hull of those of its n equal pieces (interval
    arithmetic overestimates a range by wrapping, which shrinks with the width, so n pieces
    come nearer the range than its whole)."""
    ends = [lo + (hi - lo) * F(k, n) for k in range(n + 1)]
    ps = [parts(el, Iv(a, b), d) for a, b in zip(ends, ends[1:])]
    return [tuple(hull([x.lo for x in xs], [x.hi for x in xs]) for xs in zip(*c)) for c in zip(*ps)]


@functools.lru_cache(maxsize=4096)
def paper_sample(delta, tau, prec):
    """(e^(-delta tau), phi1(tau), phi2(tau)) at an exact delta, prec bits."""
    e = expm([[Iv(0), Iv(tau), Iv(0)], [Iv(0), Iv(-delta * tau), Iv(tau)], [Iv(0)] * 3])
    return e[1][1], e[0][1], e[0][2]


def corners(lo, hi, t0, t1):
    """paper_sample for every delta in [lo, hi] and tau in [t0, t1]: e^(-delta tau), phi1 and
    phi2 are integrals of e^(-delta t) over [0, tau] (with nonnegative weights), so each is
    monotone in delta and in tau, and enclosed by the hull of its values at the corners (at
    tau = 0, exactly (1, 0, 0): e^0 has no remainder)."""
    vs = [paper_sample(x, t, PREC) for x in {lo, hi} for t in {t0, t1}]
    return [Iv(min(v[i].lo for v in vs), max(v[i].hi for v in vs)) for i in range(3)]


def paper_parts(lo, hi, d):
    """(Q0, QA, QB) of the paper's loop for every delta in [lo, hi] (MODEL.md 2-3): q =
    z^(n+2) (z - 1)(z - c) + ((alpha + beta) z - beta) (m2 z^2 + m1 z + m0) (for a whole d,
    m0 = 0 exactly: z divides out), the samples enclosed by corners."""
    n = math.floor(d)
    eps = d - n
    (c, p1, _), (c_rest, g0v, g0x), (_, p1e, p2e) = (corners(lo, hi, t, t) for t in (
        F(1), 1 - eps, eps))
    g1x, g1v = p2e + g0v * p1e, c_rest * p1e
    m2, m1, m0 = g0x, p1 * g0v - c * g0x + g1x, p1 * g1v - c * g1x
    return joined([Iv(0)] * (n + 2) + [c, -(Iv(1) + c), Iv(1)], [Iv(0), m0, m1, m2],
                  [-m0, m0 - m1, m1 - m2, m2])


def fraction_family(delta, n, e, mid, wall):
    """(q(mid), q' over e): q's coefficients for every delay n + eps, eps in e, of the
    paper's loop (fractional form, MODEL.md 2-3) in centred form, q(eps) = q(mid) + q'(xi)
    (eps - mid) for some xi in e (mean-value theorem). With u = 1 - eps, m2' = -phi1(u), m1' =
    (1 + c) phi1(u) - phi1(1) c(u), m0' = phi1(1) c(u) - c phi1(u) (c(u) = e^(-delta u); the
    force's total effect G0 + G1 does not depend on eps), c(u) and phi1(u) by corners."""
    (cu, p1u, _), (c, p1, _) = corners(delta, delta, 1 - e.hi, 1 - e.lo), paper_sample(
        delta, F(1), PREC)
    m2, m1, m0 = -p1u, (Iv(1) + c) * p1u - p1 * cu, p1 * cu - c * p1u
    qa, qb = [Iv(0), m0, m1, m2], [-m0, m0 - m1, m1 - m2, m2]
    slope = [wall[0] * x + wall[1] * y for x, y in zip(qa, qb)] + [Iv(0)] * (n + 1)
    return at(paper_parts(delta, delta, n + mid), *wall), slope


def at(parts, alpha, beta):
    """q's coefficients for all walls in the intervals alpha, beta: each is affine in the
    wall and holds each of them once, so this encloses its range."""
    return [z + (alpha * x + beta * y) for z, x, y in parts]


def held(compute, claimed, precisions=PRECISIONS, then=lambda owns, p: (owns, p)):
    """compute() gives (lists of recomputed coefficients, its parts); each recomputed one must
    lie in its claimed interval. Cancellation costs absolute accuracy: the precisions are
    tried in turn until more bits cannot change the outcome; then(*compute()) at the first."""
    global PREC
    try:
        for PREC in precisions:
            owns, p = compute()
            pairs = [(o, c) for own, cl in zip(owns, claimed) for o, c in zip(own, cl)]
            if all(o.inside(c) for o, c in pairs) or any(o.hi < c.lo or c.hi < o.lo
                                                         for o, c in pairs):
                break  # decided: more bits cannot move a true value into a disjoint ball
        need([len(x) for x in owns] == [len(x) for x in claimed],
             f"the model's polynomial has degree {len(owns[0]) - 1}")
        PREC = precisions[0]
        return need(all(o.inside(c) for o, c in pairs), "a claimed ball does not hold the "
                    "recomputed coefficient") and then(owns, p)
    finally:
        PREC = PRECISIONS[0]


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
            return need(len(given) == j + 1, f"{j + 1} reflection coefficients expected") and None
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
    whole, *boxes = [[(int(s.lo * den), int(s.hi * den)) for s in b] for b in [whole, *boxes]]
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
    return [m.numerator * (den // m.denominator) for m, _ in balls], den, fixed(sum(
        r for _, r in balls))


def modulus(poly, z):
    """Bounds of |p(z)| 2^PREC for |z| = 1, p as integral gives it, z = (x + i y) / w
    (integers): Horner's rule on sum c_k (x + i y)^k w^(n-k) in integers, each bound rounded
    outward."""
    (x, y, w), (cs, den, r) = z, poly
    re = im = 0
    wk = 1  # w^k at the k-th step of Horner's rule
    for c in reversed(cs):
        re, im, wk = re * x - im * y + c * wk, re * y + im * x, wk * w
    s, scale = math.isqrt(re * re + im * im), den * wk // w
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


# === part 2: the format ======================================================================

FORMAT = "stabound certificate 2"
HEX = set("alpha beta delta d eps s guard alpha_lo alpha_hi arcs mid rad pole numerator mass "
          "reference_mass denominator mu_h delta_h kappa_h r kappa_c delta_c delta_2 tau".split())
ELEMENTS = {"hand": "mu_h delta_h kappa_h", "transmission": "r kappa_c delta_c delta_2 encoder",
            "actuator": "tau", "filter": ""}  # in the order a model names them
GUARDS = {"double": F(16, 2**53), "float": F(16, 2**24)}  # a table's: 16 units of roundoff
CLAIMS = ("stable", "unstable", "undecided", "not stable")  # a leaf's
RANK = ("stable", "marginal", "not proved", "unstable")  # a set's member verdicts, worst last
MALFORMED = (KeyError, IndexError, TypeError, AttributeError, ValueError, ArithmeticError)


class Obj(dict):
    """A JSON object, its members named in HEX read as numbers, that notes which members were
    read: a certificate holds exactly the members its checks read (a missing one is a
    KeyError, an unread one is refused: unread)."""

    def __init__(self, pairs):
        need(len({k for k, _ in pairs}) == len(pairs) and all(v is not None for _, v in pairs),
             f"duplicate keys or a null in {[k for k, _ in pairs]}")
        super().__init__((k, number(v) if k in HEX else v) for k, v in pairs)
        self.read = set()

    def __getitem__(self, k):
        self.read.add(k)
        return dict.__getitem__(self, k)

    get = lambda self, k, default=None: self[k] if k in self else default  # noqa: E731


def same(obj, want):
    """Whether obj is an object with exactly the members of the dict want, of its values."""
    return type(obj) is Obj and set(obj) == set(want) and all(obj[k] == v for k, v in want.items())


def unread(x):
    """The members in x (at any depth) that no check read."""
    if isinstance(x, Obj):
        return [*(set(x) - x.read), *unread(list(x.values()))]
    return [u for y in x for u in unread(y)] if isinstance(x, list) else []


def canonical_hex(v):
    """The hex float of v without trailing zeros (float.hex writes its point always)."""
    mant, exp = v.hex().split("p")
    return mant.rstrip("0").rstrip(".") + "p" + exp


def number(s):
    """An exact rational from a canonical finite C99 hex float (or a list of them)."""
    if isinstance(s, list):
        return [number(x) for x in s]
    need(type(s) is str and canonical_hex(float.fromhex(s)) == s,  # inf, nan: no "p"
         f"{s!r} is not a canonical finite hex float")
    return F(float.fromhex(s))


def ball(o):
    """An object {"mid", "rad"} as the interval mid +- rad; any other as itself."""
    return o if set(o) != {"mid", "rad"} else need(o["rad"] >= 0, "negative radius") and Iv(
        o["mid"] - o["rad"], o["mid"] + o["rad"])


def balls(bs):
    return need(type(bs) is list and all(type(b) is Iv for b in bs), "not balls") and bs


def side(p):
    """A box side [lo, hi] as an interval."""
    return need(type(p) is list and len(p) == 2 and p[0] <= p[1], f"{p!r} is not a side") and Iv(*p)


def load(data):
    """The certificate's JSON, its CRC-32 checked (any changed character fails)."""
    m = re.fullmatch(rb'(\{\n.*,\n)  "crc32": "([0-9a-f]{8})"\n\}\n', data, re.S)
    need(m, "not a certificate: no crc32 member at its end")
    need(zlib.crc32(m.group(1)) == int(m.group(2), 16),
         "the CRC-32 does not match the text: the certificate was changed")
    try:
        cert = json.loads(data, object_pairs_hook=lambda p: ball(Obj(p)), parse_constant=number,
                          parse_float=number)
        return need(cert["crc32"] == m.group(2).decode(), "the CRC-32 is not the object's") and cert
    except MALFORMED as e:
        raise Reject(f"not a certificate ({type(e).__name__}: {e})") from None


def elements(model, source):
    """The elements in source, which the model must name in ELEMENTS' order, as device and
    parts take them (exact values, checked in range; a filter as (Fn, Fd), lowest power
    first)."""
    names = [k for k in ELEMENTS if k in source]
    need(model["elements"] == names and model["loop"] == ("elements" if names else "paper")
         and type(model["polynomial"]) is str, "the model must name the loop and its elements")
    el = {k: [source[k][m] for m in ELEMENTS[k].split()] for k in names if k != "filter"}
    hand, tr = el.get("hand", [0]), el.get("transmission", [F(1, 2), 0, "motor"])
    need(min(hand) >= 0 and 0 < tr[0] < 1 and min(tr[1:-1]) >= 0 and el.get("actuator", [1])[
        0] > 0 and tr[-1] in ("motor", "handle"), "an element's value is out of range (hand and "
         "transmission >= 0, 0 < r < 1, tau > 0, the encoder on the motor or the handle)")
    f = source.get("filter")
    if f is not None and "pole" in f:
        el["filter"] = [F(0), 1 - f["pole"]], [-f["pole"], F(1)]
        need(0 < f["pole"] < 1, "the filter's pole must be in (0, 1)")
    elif f is not None and "samples" in f:
        n = f["samples"]
        need(type(n) is int and 2 <= n <= 64, "a moving average of 2 to 64 samples")
        el["filter"] = [F(1, n)] * n, [F(0)] * (n - 1) + [F(1)]
    elif f is not None:
        el["filter"] = f["numerator"], f["denominator"]
        need(len(f["numerator"]) == 3 == len(f["denominator"]) and f["denominator"][2] == 1,
             "the filter's numerator and denominator are of degree 2, monic")  # exact
    return names, el


def each(items, label, check):
    """check(i, item) for every item of the list items (one or more), its rejection labelled."""
    need(type(items) is list and items, f"one or more {label}s are needed")
    done = []
    try:
        for item in items:
            done.append(check(len(done), item))
    except Reject as e:
        raise Reject(f"{label} {len(done)}: {e}") from None
    return done


def decide(leaf, coeffs, rouche=None, r=1):
    """A leaf's claim (CLAIMS) from coeffs, its claimed coefficients (at its centre when
    rouche is given): undecided proves nothing and lists no reflections; not stable is the
    recursion up to its step |a_0| > |a_k|; stable and unstable count the roots outside the
    circle |z| = r (r > 1 for an unstable leaf only: a root outside it is outside 1),
    and rouche = (f, parts, box, centre) carries the centre's count to the whole leaf (clear,
    on the leaf's arcs). Returns the claim."""
    claim, given = leaf["claim"], balls(leaf["reflections"])
    need(claim in CLAIMS and not (rouche and claim in CLAIMS[2:]) and 1 <= r < 2 and (
        r == 1 or claim == "unstable"), f"{claim!r} is not a claim of this leaf")
    if claim in CLAIMS[2:]:
        need(claim == "not stable" or given == [], "an undecided leaf lists no reflections")
        return claim if claim == "undecided" else outside(coeffs, 1, given, True) or claim
    out = outside(coeffs, r, given)
    need(not rouche or r == 1 and clear(*rouche, leaf["arcs"]),
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
    need(same(claim, dict(verdict=verdict, **counts)),
         f"the leaves prove {verdict} with counts {counts}, not {claim!r}")
    return verdict, counts


def wall_inputs(cert):
    """The model's elements, the exact delta and d (an interval over delays) of the inputs.
    A member of a set of devices of other masses (MODEL.md 11) is stated in the normalization
    of the set's reference mass: its own values in units of the mass (delta, the hand's, the
    transmission's; the wall through the force's gain, el["scale"]) are those times s =
    reference_mass / mass, exactly."""
    inputs, over = cert["inputs"], cert["kind"] == "delays"
    names, el = elements(cert["model"], inputs)
    delta, d = inputs["delta"], side(inputs["d"]) if over else Iv(inputs["d"])
    masses = ["mass", "reference_mass"] if "mass" in inputs else []
    s = inputs["reference_mass"] / inputs["mass"] if masses else 1
    need(list(inputs) == ["alpha", "beta", "delta", "d", *masses, *names] and not (
        (names or masses) and over) and delta >= 0 and 0 <= d.lo and d.hi <= 10000 and (
        d.lo < d.hi or not over) and 0 < s <= 1, "inputs: alpha, beta, delta >= 0, d in [0, "
        "10000] (over delays an interval, and no elements or masses), a mass at least the "
        "reference mass, and the elements, in order")
    for k, n in (("hand", 3), ("transmission", 4)):  # their values in units of the mass
        if k in el:
            el[k] = [s * x for x in el[k][:n]] + el[k][n:]
    return el | {"scale": s}, s * delta, d


def verify_single(cert):
    """One wall: q's coefficients, then the recursions at the radii the claim needs."""
    inputs, claim, runs = cert["inputs"], cert["claim"], cert["recursions"]
    (el, delta, d), coeffs = wall_inputs(cert), balls(cert["coefficients"])
    (own,), _ = held(lambda: ([at(parts(el, delta, d.lo), Iv(inputs["alpha"]), Iv(inputs[
        "beta"]))], None), [coeffs])
    n, verdict, k = len(own) - 1, claim["verdict"], claim.get("coefficient_above_binomial")
    need(cert["degree"] == n, f"the model's polynomial has degree {n}")
    if k is not None:  # a monic q with its roots in |z| <= 1 has |a_k| = |e_(n-k)| <= C(n, k)
        need(verdict == "unstable" and runs == [] and type(k) is int and 0 <= k <= n
             and own[n].lo == own[n].hi == 1 and own[k].mig() > math.comb(n, k),  # exact
             f"coefficient {k} is not proven above binom({n}, {k})")
        return f"unstable: coefficient {k} exceeds binom({n}, {k}), so a root is outside"
    eps = claim["eps"] if verdict == "marginal" else 0
    need(verdict in ("stable", "unstable", "marginal") and 0 <= eps < F(1, 2) and (
        eps > 0) == (verdict == "marginal"), "eps must be in (0, 1/2)")
    need([r["radius"] for r in runs] == (["1+eps", "1-eps"] if eps else ["1"]),
         f"the {verdict} claim needs the recursions at radius 1 (marginal: 1+eps, 1-eps)")
    counts = each(runs, "recursion", lambda i, r: need(r["outside"] == outside(
        coeffs, 1 + eps * (1 - 2 * i), balls(r["reflections"])), "not the count of roots "
        "outside") and r["outside"])
    need(counts[0] == 0 and counts[-1] >= 1 if eps else (counts[0] == 0) == (
        verdict == "stable") and (verdict == "stable" or claim["outside"] == counts[0]),
        f"the counts {counts} do not prove {claim!r}")
    return {"stable": "stable: every root inside the unit circle", "marginal": f"marginal: "
            f"spectral radius within {float(eps)!r} of 1", "unstable": f"unstable: {counts[0]} "
            "roots outside the unit circle, none on it"}[verdict]


def verify_leaves(cert):
    """A box of walls (leaves in alpha and beta) or one wall of the paper's loop over an
    interval of delays (leaves n + [e0, e1], enclosed by fraction_family around their centre
    e_c): the leaves tile the inputs' box, and each leaf's claim is replayed (decide) on its
    enclosures, recomputed over the leaf or around its centre, whose count Rouche on the
    leaf's arcs carries to the leaf (a delay cell: its slope the perturbation's direction,
    |eps - e_c| its radius)."""
    k, inputs, cache = cert["kind"], cert["inputs"], {}
    (el, delta, d), over = wall_inputs(cert), k == "delays"
    wall = [Iv(inputs[a]) if over else side(inputs[a]) for a in ("alpha", "beta")]

    def check(_, leaf):
        coeffs, box, c, slope = balls(leaf["coefficients"]), leaf["box"], leaf.get("centre"), None
        if over:  # q(eps) = q(mid) + (eps - mid) q'(xi): parts (q(mid), q', 0) in (eps - mid, 0)
            n, e, mid, slope = box["n"], side(box["eps"]), c["eps"], leaf.get("slope")
            need(type(n) is int and 0 <= n and 0 <= e.lo < e.hi <= 1 and e.lo <= mid <= e.hi
                 and 0 < mid < 1 and leaf["claim"] != "not stable", "a cell is a fraction of a "
                 "sample around its centre, stable, unstable or undecided")
            box, tile = [Iv(e.lo - mid, e.hi - mid), Iv(0)], [Iv(n + e.lo, n + e.hi)]
            c = None if slope is None else [Iv(0), Iv(0)]
        else:
            box = tile = [side(box["alpha"]), side(box["beta"])]
            c = c if c is None else [Iv(c[a]) for a in ("alpha", "beta")]
            need(not c or all(p.inside(s) for p, s in zip(c, box)), "a leaf's centre lies outside it")

        def compute():  # a box's parts once for every leaf, at each precision
            if over:
                p = [(q, s, Iv(0)) for q, s in zip(*fraction_family(delta, n, e, mid, wall))]
            p = p if over else cache.get(PREC) or cache.setdefault(PREC, parts(el, delta, d.lo))
            return [at(p, *(c or box))] + ([] if slope is None else [[s for _, s, _ in p]]), p
        _, p = held(compute, [coeffs] + ([] if slope is None else [balls(slope)]))
        need(over or cert["degree"] == len(coeffs) - 1, f"the model's polynomial has degree "
             f"{len(coeffs) - 1}")
        return decide(leaf, coeffs, c and (coeffs, p, box, c), 1 + (leaf.get("eps", 0) if (
            not over and leaf["claim"] == "unstable") else 0)), tile
    done = each(cert["leaves"], "leaf", check)
    need(covers([d] if over else wall, [b for _, b in done]), f"the leaves do not tile the {k}")
    verdict, counts = proved([c for c, _ in done], cert["claim"])
    where = f"at every delay in [{float(d.lo)!r}, {float(d.hi)!r}]" if over else \
        "for every wall of the box"
    return f"{verdict} {where} ({len(done)} leaves)" if verdict != "not proved" else \
        f"not proved {where}: leaves {counts}"


def verify_amax(cert):
    """An enclosure of alpha_max: a stable wall at alpha_lo, and above it (above) on its loop
    no wall stable at alpha_hi for any damping of a range that holds the wall's."""
    below, claim, cap = cert["stable_below"], cert["claim"], cert.get("cap")
    lo, hi = claim["alpha_lo"], claim["alpha_hi"]
    betas = above(below, cert["unstable_above"], cap, hi)
    need(below["inputs"]["alpha"] == lo < hi and (cap is None or claim["stiffer"] == "none "
         "stable") and Iv(below["inputs"]["beta"]).inside(betas) and verify(
        below, "stability").startswith("stable"), "the wall at alpha_lo < alpha_hi is not "
         "proved stable, or its damping is not of the range above")  # exact rationals
    return f"alpha_max in [{float(lo)!r}, {float(hi)!r}]: a stable wall at alpha_lo, and no " \
        f"damping in [{float(betas.lo)!r}, {float(betas.hi)!r}] stabilizes " + (
            "alpha_hi or any stiffer wall" if cap is not None else "alpha_hi")


def above(wall, box, cap, hi):
    """No damping of the box's range stabilizes alpha_hi (without a cap: the box is the strip
    at alpha_hi, every wall unstable) or any stiffer wall (with one: the box reaches the cap,
    no wall of it stable, and the cap's rule fails from the cap on: see capped), on the loop
    of the one-wall certificate wall. Returns the range."""
    ins, ina = wall["inputs"], box["inputs"]
    alphas, betas = side(ina["alpha"]), side(ina["beta"])
    need(wall["model"] == box["model"] and list(ins) == list(ina) and all(
        ins[k] == ina[k] for k in list(ins)[2:]) and hi == alphas.lo and (
            cap is not None or alphas.hi == hi) and verify(box, "box").startswith(
            ("unstable", "not stable") if cap is not None else "unstable"),
         "the walls above are not proved unstable at alpha_hi on the loop of the wall below")
    if cap is not None:
        p = parts(*wall_inputs(box)[:2], ina["d"])
        q1 = cap["rule"] == "q(-1)"
        k, sign = (None, 1) if q1 else (cap["k"], cap["sign"])
        need(q1 or cap["rule"] == "coefficient" and type(k) is int and 0 <= k < len(p) - 1
             and sign in (1, -1) and type(sign) is int, f"unknown cap {cap!r}")
        need(capped(p, cap["alpha"], betas, k, sign)
             and alphas.hi >= cap["alpha"], "the cap's condition is not proved to fail from "
             "the cap on, or the box above does not reach the cap")
    return betas


def verify_grid(cert):
    """Several alpha_max enclosures (the rows of a grid of devices or of sets of devices),
    each checked alone."""
    done = each(cert["rows"], "row", lambda _, r: need("alpha_lo" in r["claim"], "a row is an "
                "alpha_max enclosure") and verify(r, "set" if "set" in r else "alpha_max"))
    need(same(cert["claim"], {"rows": len(done)}), "the claim must count the rows")
    return f"{len(done)} rows" + "".join(f"\nrow {i}: {text}" for i, text in enumerate(done))


def span(v0, v1, s, guard):
    """v0 + t (v1 - v0) for t in the interval s, widened either way by guard * max(|v0|, |v1|)
    (delta is clipped at 0 by the caller)."""
    ends, slack = [v0 + t * (v1 - v0) for t in (s.lo, s.hi)], guard * max(abs(v0), abs(v1))
    return Iv(min(ends) - slack, max(ends) + slack)


def verify_set(cert):
    """A finite set of devices: the set names the alternatives of the device's mass, delta
    and d where the members differ in them, then each element's (an object, or "none": a
    member without it, as the device with the hand let go); the members, one-loop
    certificates of one kind, are every combination of them, each once, in order (the first
    outermost), and agree on all else (one wall, box or table). The claim: the worst
    member's verdict (stable for all, else the first member marginal, not proved or unstable),
    or the robust alpha_max's enclosure: every member stable at the one wall at alpha_lo, and
    above it a binding member's alpha_max certificate (at its stable wall), or pieces of the
    damping range meeting end to end, each with a member's proof that none is stable above."""
    s, ms, claim, bind = cert["set"], cert["members"], cert["claim"], cert.get("binding")
    need(list(s) == [k for k in ("mass", "delta", "d", *ELEMENTS) if k in s] and all(
        type(v) is list and v and all(a != b for i, a in enumerate(v) for b in v[i + 1:])
        for v in s.values()), "the set names the device's parameters, then the elements, in "
        "order, each with distinct alternatives")
    texts = each(ms, "member", lambda i, m: need(m["kind"] == ms[0]["kind"] in (
        "stability", "box", "table"), "members of one one-loop kind") and verify(m))
    src = [m["table" if m["kind"] == "table" else "inputs"] for m in ms]
    rest = [{k: x[k] for k in x if k not in s} for x in src]
    need([tuple(plain(x.get(k, "none")) for k in s) for x in src] == list(itertools.product(
        *([plain(a) for a in s[k]] for k in s))) and all(r == rest[0] for r in rest),
        f"the members are not the set's {math.prod(map(len, s.values()))} combinations, each "
        "once, in order, on one wall, box or table")
    words = [next((w for w in RANK if t.startswith(w)), "not proved") for t in texts]
    worst, n = max(words, key=RANK.index), len(ms)
    if "alpha_lo" not in claim:
        i = words.index(worst)
        need(same(claim, {"verdict": worst, "members": n} | ({} if worst == "stable" else {
            "member": i})), f"the members prove {worst}, not {claim!r}")
        return f"stable for each of the set's {n} devices" if worst == "stable" else \
            f"{worst} for the set of {n} devices: member {i}, {texts[i]}"
    if bind is not None:
        i, text = claim["member"], verify(bind, "alpha_max")
        need(worst == "stable" and bind["stable_below"]["inputs"] == src[i] and bind[
            "stable_below"]["model"] == ms[i]["model"] and same(claim, {k: bind["claim"][k] for k
            in ("alpha_lo", "alpha_hi")} | {"members": n, "member": i}), "the binding member's "
             "enclosure is not at the stable wall of every member, or not the claim's")
        return f"robust alpha_max of the set's {n} devices: every member stable at alpha_lo; " \
            f"member {i}'s {text}"
    # pieces of the damping range meeting end to end, each with no wall stable at alpha_hi
    # (capped: nor stiffer) for one member
    ps, lo, hi = cert["pieces"], claim["alpha_lo"], claim["alpha_hi"]
    got = each(ps, "piece", lambda _, p: above(ms[need(type(p["member"]) is int and 0 <= p[
        "member"] < n, "no such member") and p["member"]], p["unstable_above"], p.get("cap"), hi))
    capped, b, r = all("cap" in p for p in ps), Iv(src[0]["beta"]), side(claim["beta"])
    need(worst == "stable" and src[0]["alpha"] == lo < hi and all(x.hi == y.lo for x, y in zip(
        got, got[1:])) and got[0].lo <= r.lo and b.inside(r) and r.hi <= got[-1].hi and same(
        claim, {"alpha_lo": lo, "alpha_hi": hi, "members": n, "beta": claim["beta"]} | (
            {"stiffer": "none stable"} if capped else {})), "the pieces do not meet end to end "
        "over the claim's range, which holds the stable wall's damping")  # exact rationals
    return f"robust alpha_max of the set's {n} devices in [{float(lo)!r}, {float(hi)!r}]: every " \
        f"member stable at alpha_lo, and no damping in [{float(r.lo)!r}, {float(r.hi)!r}] " \
        f"stabilizes alpha_hi{' or any stiffer wall' if capped else ''} ({len(ps)} pieces)"


def plain(x):
    """An object's members as a plain dict (each read), anything else as itself."""
    return {k: x[k] for k in x} if type(x) is Obj else x


def verify_table(cert):
    """A lookup table of one loop proved by its cells, the claim counting them and their
    leaves. A cell is one delta interval [X[j], X[j+1]] of one row d (whole delays, or one
    row); a query at delta = X[j] + s (X[j+1] - X[j]), s in [0, 1], reads alpha = A[j] + s
    (A[j+1] - A[j]), beta alike, all within the guard (firmware rounding: span). A cell's
    boxes are s ranges tiling [0, 1], each a leaf proved stable for its whole (delta, alpha,
    beta) box: the paper's loop enclosed by monotonicity, a loop with elements with an interval
    delta; or at a centre, its delta one member's, carried to the box by Rouche."""
    tab, cells = cert["table"], cert["cells"]
    (names, el), guard = elements(cert["model"], tab), GUARDS.get(tab["precision"])
    xs, ds, nodes = tab["delta"], tab["d"], [tab["alpha"], tab["beta"]]
    need(guard is not None and tab["guard"] == guard, f"the guard is {GUARDS}[precision]")
    need(xs and ds and xs[0] >= 0 and all(a < b for v in (xs, ds) for a, b in zip(v, v[1:]))
         and (len(ds) == 1 or all(x.denominator == 1 for x in ds)) and 0 <= ds[0] <= 10000
         and all(len(g) == len(ds) and all(len(r) == len(xs) for r in g) for g in nodes),
         "the axes must be increasing, delta >= 0, d whole (or one) in [0, 10000], the nodes "
         "a d by delta grid")
    want = [(i, j) for i in range(len(ds)) for j in range(max(len(xs) - 1, 1))]
    need([(c["row"], c["column"]) for c in cells] == want,
         f"the cells must be every (row, column) in order: {len(want)} cells")

    def check_box(i, j, box):
        s, c, j1 = side(box["box"]["s"]), box.get("centre"), min(j + 1, len(xs) - 1)
        walls = [span(g[i][j], g[i][j1], s, guard) for g in nodes]
        deltas = span(xs[j], xs[j1], s, guard)
        lo, hi, member = max(deltas.lo, F(0)), deltas.hi, c and c["delta"]
        c = c if c is None else [Iv(c["alpha"]), Iv(c["beta"])]
        need(box["claim"] == "stable" and (not c or lo <= member <= hi and all(
            p.inside(w) for p, w in zip(c, walls))), "a table's leaves are stable, decided around "
             "a centre inside them")

        def compute():  # at a centre: q of one member there, and the family's
            p = pieces(el, lo, hi, ds[i], n) if names else paper_parts(lo, hi, ds[i])
            return ([at(parts(el, member, ds[i]), *c), at(p, *c)] if c else [at(p, *walls)]), p
        claimed = [balls(box["coefficients"])] + ([balls(box["family"])] if c else [])
        # finer pieces of the delta range in turn, first at FIRST bits throughout (outward at
        # any precision: what it accepts is proved), then as before; the last rejection stands
        tries = [(n, b) for b in ((FIRST,), PRECISIONS) for n in (PIECES if names else [1])]
        for n, bits in tries:
            try:  # Rouche on the arcs: each loop and wall of the box has the member's count
                return held(compute, claimed, bits if (n, bits) == tries[-1] else bits[:1], lambda
                            _, p: decide(box, claimed[0], c and (claimed[1], p, walls, c)) and [s])
            except Reject:
                if (n, bits) == tries[-1]:
                    raise

    def check_cell(_, cell):
        boxes = each(cell["leaves"], "leaf", lambda k, box: check_box(cell["row"], cell[
            "column"], box))
        return need(covers([Iv(0, 1)], boxes), "the boxes' s ranges do not tile [0, 1]") and len(
            boxes)
    n = sum(each(cells, "cell", check_cell))
    need(same(cert["claim"], {"verdict": "stable", "cells": len(cells), "leaves": n}),
         f"the cells prove stable with {len(cells)} cells and {n} leaves, not {cert['claim']!r}")
    return f"stable for every wall of the table's lookup: {len(cells)} cells, {n} boxes, " \
        f"delta in [{float(xs[0])!r}, {float(xs[-1])!r}], guard {float(guard)!r}"


VERIFY = {"stability": verify_single, "box": verify_leaves, "alpha_max": verify_amax,
          "alpha_max grid": verify_grid, "table": verify_table, "delays": verify_leaves,
          "set": verify_set}


def verify(cert, want=None):
    """The proven claim as text, or Reject (a malformed certificate too); want: the kind."""
    try:
        need(not re.fullmatch("stabound .* certificate 1", str(cert["certificate"])) and cert.get(
            "kind") != "table set", "a certificate of format 1 or of the kind table set, which "
             f"this checker no longer reads: write it again with the stabound of {FORMAT!r}")
        need(cert["certificate"] == FORMAT and cert["kind"] in VERIFY and want in (
            None, cert["kind"]), "unknown certificate format")
        text = VERIFY[cert["kind"]](cert)
        return need(not unread(cert), f"unexpected members {unread(cert)}") and text
    except MALFORMED as e:
        raise Reject(f"malformed certificate ({type(e).__name__}: {e})") from None


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
