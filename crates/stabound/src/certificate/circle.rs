//! Zero exclusion on the unit circle over a box of walls (Rouché's theorem), keeping the
//! affine structure of `q` in the wall (`docs/MODEL.md` section 11).
//!
//! For a box with centre `(alpha_c, beta_c)` and half-widths `(r_a, r_b)`, the polynomial of
//! every wall in it is `q = q_c + da QA + db QB` with `|da| <= r_a`, `|db| <= r_b`. When
//! `|q_c(z)| > r_a |QA(z)| + r_b |QB(z)|` on the whole unit circle, Rouché's theorem gives
//! every such `q` as many roots inside the circle as `q_c`, and none on it; the top
//! coefficient is `Q0`'s alone, so the degree, and with it the count of roots outside, is
//! `q_c`'s, which the Schur-Cohn recursion at the centre proves. The interval recursion over
//! the whole box instead lets each coefficient take its own `da` and `db`, which loses their
//! correlation and fails on narrow boxes when the roots crowd near `z = 1` (fast sampling).
//!
//! The circle is covered by arcs between rational points, without trigonometry: the
//! parameter `u` in `[0, 4]` names `z(u - 1)` for `u <= 2` and `-z(u - 3)` for `u >= 2`,
//! where `z(t) = ((1 - t^2) + 2 i t) / (1 + t^2)` (the Pythagorean parametrization; `u = 0,
//! 2, 4` are `-i, i, -i`). An arc lies in one half; the chord between its ends `t0`, `t1` is
//! `h = 2 |t1 - t0| / sqrt((1 + t0^2)(1 + t1^2))`, and every point `z` of the arc (at most a
//! half circle) lies within `h` of its first end `z0`. By Taylor's theorem with the
//! remainder on the segment `[z0, z]` (inside the closed disc), for `p = sum_k p_k z^k`:
//! `| |p(z)| - |p(z0)| | <= h |p'(z0)| + h^2 sum_k C(k, 2) |p_k|`. An arc is cleared when
//!
//! `|q_c(z0)| - r_a |QA(z0)| - r_b |QB(z0)| > h S + h^2 C`,
//!
//! with `S = |q_c'(z0)| + r_a |QA'(z0)| + r_b |QB'(z0)|` and `C` the same sum of the
//! second-order bounds, every value enclosed in outward-rounded interval arithmetic. The
//! arcs are marched from `u = 0`: each step takes the chord that the bound at its start
//! allows for most of its margin ([`REACH`]), halved until the arc is cleared.

use super::interval::Interval;
use super::schur::Recursion;
use super::{Ball, Parts, balls};

/// The most arcs one box may use before the box is split instead: tens of microseconds
/// of arithmetic each, and a few milliseconds each for the rational checker.
pub(crate) const MAX_ARCS: usize = 2048;

/// The share of the margin an arc keeps unused: the checker recomputes `QA` and `QB` by its
/// own series, whose enclosures may differ from these in the last units of `f64`, far below
/// `1e-9` of the margin.
const SLACK: f64 = 1e-9;

/// The share of an arc's margin its first try spends: the rigorous bound at the arc's end
/// differs from the estimate by rounding and by the chord's dependence on both ends, and a
/// try that falls short is halved; 0.9 leaves about 1.6 times fewer arcs than 0.5.
const REACH: f64 = 0.9;

/// A complex number enclosed by its real and imaginary parts.
#[derive(Debug, Clone, Copy)]
struct Complex {
    re: Interval,
    im: Interval,
}

impl Complex {
    /// `self z + c` for a real `c`.
    fn times_plus(self, z: Self, c: Interval) -> Self {
        Self {
            re: self.re * z.re - self.im * z.im + c,
            im: self.re * z.im + self.im * z.re,
        }
    }

    /// The modulus.
    fn modulus(self) -> Interval {
        let square = |x: Interval| {
            let m = Interval::new(x.mig(), x.mag());
            m * m
        };
        (square(self.re) + square(self.im)).sqrt()
    }
}

/// `|x|` for the enclosure `x`.
fn abs(x: Interval) -> Interval {
    Interval::new(x.mig(), x.mag())
}

/// A polynomial (lowest power first), its derivative, and `sum_k C(k, 2) |p_k|`, which
/// bounds `|p''| / 2` on the closed unit disc.
#[derive(Debug, Clone)]
struct Poly {
    p: Vec<Interval>,
    dp: Vec<Interval>,
    curve: Interval,
}

impl Poly {
    fn new(p: &[Interval]) -> Self {
        let k = |i: usize| Interval::point(i as f64);
        let dp = p.iter().enumerate().skip(1).map(|(i, &c)| k(i) * c);
        let curve = p
            .iter()
            .enumerate()
            .skip(2)
            .map(|(i, &c)| k(i * (i - 1) / 2) * Interval::point(c.mag()))
            .fold(Interval::point(0.0), |s, x| s + x);
        Self {
            p: p.to_vec(),
            dp: dp.collect(),
            curve,
        }
    }

    /// `(|p(z)|, |p'(z)|)`.
    fn at(&self, z: Complex) -> (Interval, Interval) {
        let horner = |c: &[Interval]| {
            let zero = Complex {
                re: Interval::point(0.0),
                im: Interval::point(0.0),
            };
            c.iter()
                .rev()
                .fold(zero, |v, &ck| v.times_plus(z, ck))
                .modulus()
        };
        (horner(&self.p), horner(&self.dp))
    }
}

/// A polynomial of coefficient balls `(mid, r)`: its midpoints' polynomial, with the bound
/// on `|p''| / 2` of the whole balls, and `(sum_k r_k, sum_k k r_k)`, by which the balls'
/// values and derivatives on the closed unit disc may differ from the midpoints'.
fn of_balls(balls: &[(f64, f64)]) -> (Poly, (Interval, Interval)) {
    let point = Interval::point;
    let whole: Vec<Interval> = balls
        .iter()
        .map(|&(m, r)| Interval::from_ball(m, r))
        .collect();
    let mids: Vec<Interval> = balls.iter().map(|&(m, _)| point(m)).collect();
    let mut p = Poly::new(&mids);
    p.curve = Poly::new(&whole).curve;
    let spread = balls
        .iter()
        .enumerate()
        .fold((point(0.0), point(0.0)), |(s, ds), (i, &(_, r))| {
            (s + point(r), ds + point(i as f64) * point(r))
        });
    (p, spread)
}

/// The parameter `t` of `u` on the half that `shift` names (1: `u <= 2`, 3: `u >= 2`), and
/// `1 + t^2`.
fn parameter(u: f64, shift: f64) -> (Interval, Interval) {
    let t = Interval::point(u) - Interval::point(shift);
    let m = abs(t);
    (t, Interval::point(1.0) + m * m)
}

/// The arcs' test for one box (module documentation).
#[derive(Debug, Clone)]
pub(crate) struct Circle {
    f: Poly,
    a: Poly,
    b: Poly,
    ra: Interval,
    rb: Interval,
    curve: Interval,
    /// `sum_k r_k` and `sum_k k r_k` of the centre's balls (mid, r) when the centre is
    /// evaluated at its midpoints ([`Circle::balls`]); zero otherwise.
    spread: (Interval, Interval),
}

/// The bound at an arc's first end: the parameter there, `1 + t^2`, the margin
/// `|q_c| - r_a |QA| - r_b |QB|` and the slope `S`.
#[derive(Debug, Clone, Copy)]
struct Start {
    t: Interval,
    w: Interval,
    margin: Interval,
    slope: Interval,
}

impl Circle {
    /// The test for `q_c + da QA + db QB`, `|da| <= ra`, `|db| <= rb`.
    pub(crate) fn new(
        centre: &[Interval],
        qa: &[Interval],
        qb: &[Interval],
        ra: f64,
        rb: f64,
    ) -> Self {
        let (f, a, b) = (Poly::new(centre), Poly::new(qa), Poly::new(qb));
        let (ra, rb) = (Interval::point(ra), Interval::point(rb));
        let curve = f.curve + ra * a.curve + rb * b.curve;
        let zero = Interval::point(0.0);
        Self {
            f,
            a,
            b,
            ra,
            rb,
            curve,
            spread: (zero, zero),
        }
    }

    /// The test for `q_c + da QA + db QB`, `|da| <= ra`, `|db| <= rb`, with `q_c`, `QA` and
    /// `QB` given as balls `(mid, r)` (a family of loops: each ball holds its coefficient
    /// for every loop): each is bounded on the closed unit disc by its midpoints' polynomial
    /// moved by at most `sum_k r_k` (its derivative by `sum_k k r_k`). That is the bound the
    /// checker takes, on its own enclosures, which lie inside these balls; an interval
    /// Horner's rule on `QA` and `QB` can be tighter than it (the balls' radii enter each
    /// part of `z^k` with their own weight), and an arc cleared by the tighter bound only
    /// would be refused.
    pub(crate) fn balls(
        centre: &[(f64, f64)],
        qa: &[(f64, f64)],
        qb: &[(f64, f64)],
        ra: f64,
        rb: f64,
    ) -> Self {
        let ((f, s), (a, sa), (b, sb)) = (of_balls(centre), of_balls(qa), of_balls(qb));
        let (ra, rb) = (Interval::point(ra), Interval::point(rb));
        Self {
            curve: f.curve + ra * a.curve + rb * b.curve,
            spread: (s.0 + ra * sa.0 + rb * sb.0, s.1 + ra * sa.1 + rb * sb.1),
            f,
            a,
            b,
            ra,
            rb,
        }
    }

    /// The test for `q_c + t S`, `|t| <= r`, with the centre's and the slope's coefficients
    /// both given as balls `(mid, rad)`, bounded as [`Circle::balls`] bounds them.
    pub(crate) fn ball_family(centre: &[(f64, f64)], slope: &[(f64, f64)], r: f64) -> Self {
        Self::balls(centre, slope, &vec![(0.0, 0.0); slope.len()], r, 0.0)
    }

    fn start(&self, u: f64, shift: f64) -> Start {
        let (t, w) = parameter(u, shift);
        let one = Interval::point(1.0);
        let sign = Interval::point(if shift < 2.0 { 1.0 } else { -1.0 });
        let z = Complex {
            re: sign * (one - (w - one)) / w,
            im: sign * (Interval::point(2.0) * t) / w,
        };
        let ((f, df), (a, da), (b, db)) = (self.f.at(z), self.a.at(z), self.b.at(z));
        Start {
            t,
            w,
            margin: f - self.spread.0 - self.ra * a - self.rb * b,
            slope: df + self.spread.1 + self.ra * da + self.rb * db,
        }
    }

    /// Whether the arc from `start` to `u1` (same half) is cleared.
    fn clears(&self, start: &Start, u1: f64, shift: f64) -> bool {
        let (t1, w1) = parameter(u1, shift);
        let h = Interval::point(2.0) * abs(t1 - start.t) / (start.w * w1).sqrt();
        let rest = start.margin - h * start.slope - h * h * self.curve;
        rest.lo() > SLACK * start.margin.hi()
    }

    /// The ends `u` of arcs that cover the circle, from 0 to 4 with 2 among them, each arc
    /// cleared; `None` when the margin vanishes somewhere (the box is too wide there, or
    /// crosses the boundary) or `max_arcs` do not suffice.
    pub(crate) fn cover(&self, max_arcs: usize) -> Option<Vec<f64>> {
        let mut ends = vec![0.0];
        let mut u = 0.0;
        while u < 4.0 {
            let (shift, end) = if u < 2.0 { (1.0, 2.0) } else { (3.0, 4.0) };
            let start = self.start(u, shift);
            // an interval's end is never NaN (an undefined result is the whole line)
            let m = start.margin.lo();
            if m <= 0.0 || ends.len() > max_arcs {
                return None;
            }
            // the chord h with C h^2 + S h = REACH m, and dt = h (1 + t^2) / 2 for it
            let (s, c) = (start.slope.hi(), self.curve.hi());
            let h = 2.0 * REACH * m / (s + (s * s + 4.0 * REACH * c * m).sqrt());
            let t = 0.5 * start.t.lo() + 0.5 * start.t.hi();
            let mut next = (u + 0.5 * h * (1.0 + t * t)).min(end);
            while !self.clears(&start, next, shift) {
                let mid = 0.5 * u + 0.5 * next;
                if !(u < mid && mid < next) {
                    return None;
                }
                next = mid;
            }
            ends.push(next);
            u = next;
        }
        Some(ends)
    }
}

/// A set of walls decided around its centre: the centre, the enclosures of `q`'s
/// coefficients the recursion ran on and that recursion (proving their count of roots
/// outside the unit circle), the ends of the arcs on which no wall of the set lets a root
/// cross the circle, and, when the arcs ran on a family of loops, the family's enclosures
/// at the centre.
#[derive(Debug, Clone)]
pub(super) struct Centred {
    pub(super) centre: (f64, f64),
    pub(super) coefficients: Vec<Ball>,
    pub(super) recursion: Recursion,
    pub(super) outside: usize,
    pub(super) arcs: Vec<f64>,
    pub(super) family: Option<Vec<Ball>>,
}

/// The walls with `alpha` and `beta` in the closed ranges given, decided around their
/// centre, or `None`: the recursion proves the centre's count of roots outside, and Rouché
/// on the arcs ([`Circle::cover`]) proves that no root crosses the unit circle anywhere in
/// the set.
///
/// `parts` may enclose a family of loops (a range of `delta`), and `member` the parts of one
/// loop of it. The arcs then prove, for every loop of the family and every wall of the set,
/// that `q` has no root on the unit circle (each value is enclosed over the family); the
/// family is connected and `q` keeps its degree (its top coefficient is 1), so every such
/// `q` has as many roots outside as the member's at the centre, which the recursion proves
/// on the member's tight enclosures (over the family's, the recursion loses the
/// coefficients' correlation, as over a box of walls).
pub(super) fn around_centre(
    parts: &Parts,
    member: Option<&Parts>,
    alpha: (f64, f64),
    beta: (f64, f64),
) -> Option<Centred> {
    let centre = (0.5 * alpha.0 + 0.5 * alpha.1, 0.5 * beta.0 + 0.5 * beta.1);
    let point = Interval::point;
    let at_centre = |p: &Parts| balls(p.at(point(centre.0), point(centre.1)));
    let (coefficients, q) = at_centre(parts)?;
    let (family, counted) = match member {
        Some(m) => (Some(coefficients), at_centre(m)?),
        None => (None, (coefficients, q.clone())),
    };
    let recursion = super::schur::recursion(&counted.1);
    let outside = recursion.outside?;
    // the largest distance from the centre to an end, rounded up
    let half =
        |(lo, hi): (f64, f64), c: f64| (point(c) - point(lo)).hi().max((point(hi) - point(c)).hi());
    let zero = (point(0.0), point(0.0));
    let (qa, qb): (Vec<Interval>, Vec<Interval>) =
        parts.0.iter().map(|(_, w)| w.unwrap_or(zero)).unzip();
    let (ra, rb) = (half(alpha, centre.0), half(beta, centre.1));
    let circle = match &family {
        Some(f) => {
            let as_balls = |p: &[Interval]| p.iter().map(|x| x.ball()).collect::<Option<Vec<_>>>();
            Circle::balls(f, &as_balls(&qa)?, &as_balls(&qb)?, ra, rb)
        }
        None => Circle::new(&q, &qa, &qb, ra, rb),
    };
    let arcs = circle.cover(MAX_ARCS)?;
    Some(Centred {
        centre,
        coefficients: counted.0,
        recursion,
        outside,
        arcs,
        family,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn poly(c: &[f64]) -> Vec<Interval> {
        c.iter().map(|&x| Interval::point(x)).collect()
    }

    /// `z^2 - 1/4` (roots +-1/2) perturbed by `r (z + 1)`: on the circle the ratio
    /// `|z^2 - 1/4| / |z + 1|` is smallest at `z = 1`, where it is 3/8, so `r = 0.37` is
    /// cleared (the cover tiles [0, 4] with 2 among its ends) and `r = 0.38` is not.
    #[test]
    fn covers_when_the_perturbation_is_smaller() {
        let f = poly(&[-0.25, 0.0, 1.0]);
        let g = poly(&[1.0, 1.0, 0.0]);
        let zero = poly(&[0.0, 0.0, 0.0]);
        let ends = Circle::new(&f, &g, &zero, 0.37, 0.0)
            .cover(MAX_ARCS)
            .expect("cleared");
        assert_eq!((ends[0], *ends.last().unwrap()), (0.0, 4.0));
        assert!(ends.contains(&2.0));
        assert!(ends.windows(2).all(|w| w[0] < w[1]));
        assert!(
            Circle::new(&f, &g, &zero, 0.38, 0.0)
                .cover(MAX_ARCS)
                .is_none()
        );
    }
}
