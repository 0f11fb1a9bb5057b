//! Interval arithmetic in `f64` with outward rounding, and enclosures of the paper loop's
//! discretization (`docs/MODEL.md` section 2).
//!
//! Every operation rounds to nearest and then steps one unit in the last place outward
//! (`next_down` for the lower end, `next_up` for the upper): the exact result of a rounded
//! operation lies within half a unit of the rounded one, so the widened interval holds it.
//! A NaN end (`inf - inf`, `0 * inf`) becomes the whole line. This is the textbook method
//! (Moore, Kearfott and Cloud, "Introduction to Interval Analysis", SIAM 2009, ch. 3) without
//! switching the rounding mode, which Rust cannot do portably.
//!
//! The transcendental values are Taylor sums with a rigorous remainder: `exp(-y)` for
//! `0 <= y <= 1/2` after halving the argument `s` times, then squared `s` times; `phi1` and
//! `phi2` by their alternating series for `delta tau <= 1` and by their closed forms from the
//! enclosed exponential above.

use std::ops::{Add, Div, Mul, Neg, Sub};

/// A closed interval `[lo, hi]` of real numbers, `lo <= hi` (ends may be infinite).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Interval {
    lo: f64,
    hi: f64,
}

/// Rounds a computed lower end down (NaN: no lower bound).
fn down(x: f64) -> f64 {
    if x.is_nan() {
        f64::NEG_INFINITY
    } else {
        x.next_down()
    }
}

/// Rounds a computed upper end up (NaN: no upper bound).
fn up(x: f64) -> f64 {
    if x.is_nan() {
        f64::INFINITY
    } else {
        x.next_up()
    }
}

impl Interval {
    /// The whole real line: what an operation gives when it cannot bound its result.
    pub(crate) const ENTIRE: Self = Self {
        lo: f64::NEG_INFINITY,
        hi: f64::INFINITY,
    };

    /// The exact number `x` (a degenerate interval).
    pub(crate) fn point(x: f64) -> Self {
        Self { lo: x, hi: x }
    }

    /// `[lo, hi]` as given (the caller has rounded both ends outward).
    pub(crate) fn new(lo: f64, hi: f64) -> Self {
        if lo <= hi {
            Self { lo, hi }
        } else {
            Self::ENTIRE
        }
    }

    /// Whether this is exactly zero (a product with it is exactly zero).
    pub(crate) fn is_zero(self) -> bool {
        // exact on purpose: only the degenerate interval [0, 0]
        self.lo == 0.0 && self.hi == 0.0
    }

    /// The largest modulus in the interval.
    pub(crate) fn mag(self) -> f64 {
        self.lo.abs().max(self.hi.abs())
    }

    /// The smallest modulus in the interval (0 when it holds 0).
    pub(crate) fn mig(self) -> f64 {
        if self.lo <= 0.0 && self.hi >= 0.0 {
            0.0
        } else {
            self.lo.abs().min(self.hi.abs())
        }
    }

    /// Whether `x` lies in the interval widened by `slack` on both sides.
    #[cfg(test)]
    pub(crate) fn contains(self, x: f64, slack: f64) -> bool {
        self.lo - slack <= x && x <= self.hi + slack
    }

    /// The interval with its lower end raised to 0, for a quantity known to be
    /// nonnegative (a product of nonnegative factors whose rounded end stepped below 0).
    pub(crate) fn nonneg(self) -> Self {
        Self {
            lo: self.lo.max(0.0),
            hi: self.hi.max(0.0),
        }
    }

    /// The square of a nonnegative interval.
    fn square_nonneg(self) -> Self {
        Self::new(down(self.lo * self.lo).max(0.0), up(self.hi * self.hi))
    }

    /// The lower end.
    pub(crate) fn lo(self) -> f64 {
        self.lo
    }

    /// The upper end.
    pub(crate) fn hi(self) -> f64 {
        self.hi
    }

    /// The square root of the interval's nonnegative part (IEEE `sqrt` is correctly
    /// rounded, so one step outward holds the exact root).
    pub(crate) fn sqrt(self) -> Self {
        let lo = self.lo.max(0.0);
        Self::new(down(lo.sqrt()).max(0.0), up(self.hi.max(0.0).sqrt()))
    }

    /// `[-r, r]`.
    pub(crate) fn symmetric(r: f64) -> Self {
        Self { lo: -r, hi: r }
    }

    /// The midpoint and a radius with `[mid - rad, mid + rad]` holding the interval, both
    /// finite, or `None` for an unbounded interval.
    pub(crate) fn ball(self) -> Option<(f64, f64)> {
        let mid = 0.5 * self.lo + 0.5 * self.hi;
        let rad = up((self.hi - mid).max(mid - self.lo));
        (mid.is_finite() && rad.is_finite()).then_some((mid, rad))
    }

    /// `[mid - rad, mid + rad]`, rounded outward.
    pub(crate) fn from_ball(mid: f64, rad: f64) -> Self {
        Self::new(down(mid - rad), up(mid + rad))
    }
}

impl Add for Interval {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Self::new(down(self.lo + o.lo), up(self.hi + o.hi))
    }
}

impl Sub for Interval {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        Self::new(down(self.lo - o.hi), up(self.hi - o.lo))
    }
}

impl Neg for Interval {
    type Output = Self;
    fn neg(self) -> Self {
        Self {
            lo: -self.hi,
            hi: -self.lo,
        }
    }
}

impl Mul for Interval {
    type Output = Self;
    fn mul(self, o: Self) -> Self {
        if self.is_zero() || o.is_zero() {
            return Self::point(0.0);
        }
        let p = [
            self.lo * o.lo,
            self.lo * o.hi,
            self.hi * o.lo,
            self.hi * o.hi,
        ];
        if p.iter().any(|x| x.is_nan()) {
            return Self::ENTIRE;
        }
        let lo = p.iter().fold(f64::INFINITY, |m, &x| m.min(x));
        let hi = p.iter().fold(f64::NEG_INFINITY, |m, &x| m.max(x));
        Self::new(down(lo), up(hi))
    }
}

impl Div for Interval {
    type Output = Self;
    fn div(self, o: Self) -> Self {
        if o.lo <= 0.0 && o.hi >= 0.0 {
            return Self::ENTIRE;
        }
        let q = [
            self.lo / o.lo,
            self.lo / o.hi,
            self.hi / o.lo,
            self.hi / o.hi,
        ];
        if q.iter().any(|x| x.is_nan()) {
            return Self::ENTIRE;
        }
        let lo = q.iter().fold(f64::INFINITY, |m, &x| m.min(x));
        let hi = q.iter().fold(f64::NEG_INFINITY, |m, &x| m.max(x));
        Self::new(down(lo), up(hi))
    }
}

/// Above this argument `exp(-x) < 2^-1074`, the smallest positive `f64`:
/// `ln 2^-1074 = -744.44...`.
const EXP_FLOOR: f64 = 745.25;

/// Terms of the Taylor series of `exp(-y)` for `y <= 1/2`: the first omitted term is at most
/// `2^-21 / 21! < 1e-25`, far below the unit roundoff of a result near 1.
const EXP_TERMS: u32 = 20;
const EXP_TAIL: f64 = 1e-25;

/// Terms of the series of `phi1`'s and `phi2`'s kernels for `x <= 1`: the first omitted
/// term is at most `1 / 26! < 3e-27`.
const PHI_TERMS: u32 = 24;
const PHI_TAIL: f64 = 3e-27;

/// `sum_{k=0..=terms} prod_{j=1..=k} (-x / (first + j - 1))` by Horner's rule in interval
/// arithmetic: `1 - x/first (1 - x/(first+1) (...))`, with the alternating series' first
/// omitted term `tail` added on both sides. Valid for `0 <= x < first` (terms decrease).
fn alternating(x: f64, first: u32, terms: u32, tail: f64) -> Interval {
    let one = Interval::point(1.0);
    let mx = Interval::point(-x);
    let mut acc = one;
    for k in (first..first + terms).rev() {
        acc = one + mx * acc / Interval::point(f64::from(k));
    }
    acc + Interval::symmetric(tail)
}

/// `exp(-x)` for an exact `x >= 0`.
fn exp_neg_at(x: f64) -> Interval {
    if x.is_nan() {
        return Interval::ENTIRE;
    }
    let x = x.max(0.0);
    if x > EXP_FLOOR {
        return Interval::new(0.0, f64::from_bits(1));
    }
    // halving a number above 1/2 is exact
    let (mut y, mut s) = (x, 0);
    while y > 0.5 {
        y *= 0.5;
        s += 1;
    }
    let mut e = alternating(y, 1, EXP_TERMS, EXP_TAIL);
    for _ in 0..s {
        e = e.square_nonneg();
    }
    e
}

/// `exp(-x)` over a nonnegative interval `x` (decreasing in `x`).
pub(crate) fn exp_neg(x: Interval) -> Interval {
    Interval::new(exp_neg_at(x.hi).lo, exp_neg_at(x.lo).hi)
}

/// Terms of the series of `cos x` and `sin x / x` in [`tan_at`], after the first: for
/// `x < pi / 2` (`x^2 < 2.47`) the first omitted terms are `x^30 / 30!` and `x^30 / 31!`,
/// below `2.47^15 / 30! < 3e-27`.
const TRIG_TERMS: u32 = 14;

/// `sum_{k=0..=TRIG_TERMS} (-y)^k / ((a)(a+1)(a+2)...(a+2k-1))` by Horner's rule in
/// interval arithmetic, `1 - y/(a (a+1)) (1 - y/((a+2)(a+3)) (...))`, plus the modulus of
/// the first omitted term on both sides: at `y = x^2` the series of `cos x` (`a = 1`) and
/// of `sin x / x` (`a = 2`). Both alternate, and from the first omitted term on their terms
/// decrease in modulus (each is the one before times `y / ((a + 2k)(a + 2k + 1))`, below
/// `2.5 / 30` there), so that term bounds the rest (Leibniz).
fn trig_series(y: Interval, a: u32) -> Interval {
    let one = Interval::point(1.0);
    let denominator = |k: u32| {
        // exact: products of whole numbers below 2^53
        let j = f64::from(a + 2 * k);
        Interval::point(j * (j + 1.0))
    };
    let mut acc = one;
    let mut tail = one;
    for k in 0..=TRIG_TERMS {
        tail = tail * y / denominator(k);
    }
    for k in (0..TRIG_TERMS).rev() {
        acc = one - y * acc / denominator(k);
    }
    acc + Interval::symmetric(tail.mag())
}

/// `tan x` at an exact `x` in `[0, pi / 2)`: `sin x / cos x`, each by its Taylor series
/// with the remainder bounded ([`trig_series`]); the whole line elsewhere, or where the
/// enclosure of `cos x` reaches 0.
fn tan_at(x: f64) -> Interval {
    // `FRAC_PI_2` is pi / 2 rounded to nearest, which is below it
    if !(0.0..std::f64::consts::FRAC_PI_2).contains(&x) {
        return Interval::ENTIRE;
    }
    let xi = Interval::point(x);
    let y = xi * xi;
    (xi * trig_series(y, 2)) / trig_series(y, 1)
}

/// `tan` over an interval `x` within `[0, pi / 2)`, where it increases: from the lower
/// enclosure at `x`'s lower end to the upper one at its upper end (the whole line for an `x`
/// that leaves that range).
pub(crate) fn tan(x: Interval) -> Interval {
    Interval::new(tan_at(x.lo).lo, tan_at(x.hi).hi)
}

/// `g(x) = (1 - exp(-x)) / x = sum_k (-x)^k / (k+1)!` at an exact `x >= 0`.
fn g_at(x: f64) -> Interval {
    let x = x.max(0.0);
    if x <= 1.0 {
        alternating(x, 2, PHI_TERMS, PHI_TAIL)
    } else {
        let xi = Interval::point(x);
        (Interval::point(1.0) - exp_neg_at(x)) / xi
    }
}

/// `h(x) = (x - 1 + exp(-x)) / x^2 = sum_k (-x)^k / (k+2)!` at an exact `x >= 0`.
fn h_at(x: f64) -> Interval {
    let x = x.max(0.0);
    let half = Interval::point(0.5);
    if x <= 1.0 {
        half * alternating(x, 3, PHI_TERMS, PHI_TAIL)
    } else {
        let xi = Interval::point(x);
        (xi - Interval::point(1.0) + exp_neg_at(x)) / (xi * xi)
    }
}

/// `g` and `h` both decrease on `x >= 0`: their range over `x` is given by its ends.
fn decreasing(f: fn(f64) -> Interval, x: Interval) -> Interval {
    Interval::new(f(x.hi).lo, f(x.lo).hi)
}

/// The discretization values of `docs/MODEL.md` section 2, enclosed.
#[derive(Debug, Clone, Copy)]
pub(crate) struct DiscretizationEnclosure {
    /// `c = exp(-delta)`.
    pub c: Interval,
    /// `phi1(1)`.
    pub p1: Interval,
    /// `phi2(1 - eps)`.
    pub g0x: Interval,
    /// `phi1(1 - eps)`.
    pub g0v: Interval,
    /// `phi2(eps) + phi1(1 - eps) phi1(eps)`.
    pub g1x: Interval,
    /// `exp(-delta (1 - eps)) phi1(eps)`.
    pub g1v: Interval,
}

impl DiscretizationEnclosure {
    /// The enclosures for every `delta` in the nonnegative interval `dl` and the exact
    /// `eps = d - floor(d)` (exact in `f64`: the difference of `d` and its floor is a multiple
    /// of `d`'s unit in the last place below `d`): `exp(-x)`, `g` and `h` decrease in their
    /// argument, so each is enclosed by its values at the ends.
    pub(crate) fn over(dl: Interval, eps: f64) -> Self {
        Self::over_fractions(dl, Interval::point(eps))
    }

    /// The enclosures for every `delta` in the nonnegative interval `dl` and every fraction
    /// of delay in `e`, a sub-interval of `[0, 1]`: each value is a product and sum of
    /// `tau`, `exp(-x)`, `g(x)` and `h(x)` at `tau` in `e` or `1 - e` and `x = delta tau`,
    /// each factor enclosed over its interval (the functions decrease in `x`), so interval
    /// arithmetic encloses the value's range (with the dependency between `e` and `1 - e`
    /// overestimated, by a width proportional to `e`'s).
    pub(crate) fn over_fractions(dl: Interval, e: Interval) -> Self {
        let one = Interval::point(1.0);
        let phi = |tau: Interval| {
            let x = (dl * tau).nonneg();
            let p1 = (tau * decreasing(g_at, x)).nonneg();
            let p2 = (tau * tau * decreasing(h_at, x)).nonneg();
            (p1, p2, exp_neg(x))
        };
        let (p1, _, c) = phi(one);
        let rest = (one - e).nonneg();
        let (g0v, g0x, c_rest) = phi(rest);
        let (p1e, p2e, _) = phi(e);
        Self {
            c,
            p1,
            g0x,
            g0v,
            g1x: p2e + g0v * p1e,
            g1v: c_rest * p1e,
        }
    }
}

/// The values the derivatives of the fractional form's coefficients in the fraction `eps`
/// are made of (`docs/MODEL.md` section 2), enclosed over a cell of fractions.
///
/// With `u = 1 - eps`, `phi1' = c(tau)` and `phi2' = phi1` give `G0x' = -phi1(u)`,
/// `G1x' = phi1(u)`, `G0v' = -c(u)` and `G1v' = c(u)` (the force's total effect over a
/// period, `G0x + G1x` and `G0v + G1v`, does not depend on how the period is shared), so
/// every derivative is a product and sum of `c`, `phi1(1)`, `phi1(u)` and `c(u)`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct FractionSlopes {
    /// `c = exp(-delta)`.
    pub c: Interval,
    /// `phi1(1)`.
    pub p1: Interval,
    /// `phi1(1 - eps)`.
    pub p1u: Interval,
    /// `c(1 - eps) = exp(-delta (1 - eps))`.
    pub cu: Interval,
}

impl FractionSlopes {
    /// The enclosures for every `delta` in the nonnegative interval `dl` and every fraction
    /// in `e`, a sub-interval of `[0, 1]` (each factor enclosed over its interval as in
    /// [`DiscretizationEnclosure::over_fractions`]).
    pub(crate) fn over(dl: Interval, e: Interval) -> Self {
        let one = Interval::point(1.0);
        let u = (one - e).nonneg();
        let x = (dl * u).nonneg();
        Self {
            c: exp_neg(dl),
            p1: decreasing(g_at, dl),
            p1u: (u * decreasing(g_at, x)).nonneg(),
            cu: exp_neg(x),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every enclosure holds the library's own `f64` value (the reference here is the
    /// closed form in `std`, accurate to a few units in the last place, so it must lie within
    /// a few ulps of the enclosure) and is narrow.
    #[test]
    fn enclosures_hold_and_are_narrow() {
        for x in [0.0, 1e-300, 1e-8, 0.3, 0.5, 0.7, 1.0, 2.5, 30.0, 700.0] {
            let e = exp_neg_at(x);
            let v = (-x).exp();
            let slack = 4.0 * f64::EPSILON * v;
            assert!(e.lo <= v + slack && v - slack <= e.hi, "{x}: {e:?} {v}");
            assert!(e.hi - e.lo <= 1e-12 * v + 1e-300, "{x}: {e:?}");
            if x > 0.0 {
                let g = g_at(x);
                let gv = -(-x).exp_m1() / x;
                assert!(g.lo <= gv * (1.0 + 1e-15) && gv * (1.0 - 1e-15) <= g.hi);
                assert!(g.hi - g.lo <= 1e-13 * gv, "{x}: {g:?}");
            }
        }
        assert_eq!(exp_neg_at(800.0).lo, 0.0);
        // h(1) = e^-1 exactly by the closed form: both branches agree there
        let (a, b) = (h_at(1.0), h_at(f64::from_bits(1.0f64.to_bits() + 1)));
        let e1 = (-1.0f64).exp();
        assert!(a.lo <= e1 && e1 <= a.hi + 1e-15 && b.lo <= e1);
    }

    #[test]
    fn arithmetic_is_outward() {
        let third = Interval::point(1.0) / Interval::point(3.0);
        assert!(third.lo < 1.0 / 3.0 && 1.0 / 3.0 < third.hi);
        assert_eq!(
            Interval::point(1.0) / Interval::new(-1.0, 1.0),
            Interval::ENTIRE
        );
        let inf = Interval::point(f64::INFINITY);
        assert_eq!(inf - inf, Interval::ENTIRE);
        assert_eq!(Interval::new(-2.0, 1.0).mig(), 0.0);
        assert_eq!(Interval::new(-2.0, 1.0).mag(), 2.0);
    }

    /// `tan` against values computed by its Taylor series in 60-digit decimal arithmetic
    /// (Python's `decimal` module, the series of `sin` and `cos` summed until the terms fall
    /// below `1e-55`) at `x = pi c` as `f64` computes it, for cutoffs `c = f_c T` from 0.001
    /// to 0.49: each enclosure holds the value (rounded to the nearest `f64`, which stays
    /// between the enclosure's `f64` ends when the value does) and is a few units wide.
    #[test]
    fn tan_holds_high_precision_values() {
        let cases = [
            (0.0031415926535897933, "3.1416029890561561943969204e-3"),
            (0.09424777960769379, "9.4527831179282039706668376e-2"),
            (0.18849555921538758, "1.9076020221856672943832556e-1"),
            (0.3141592653589793, "3.2491969623290631261650939e-1"),
            // pi 0.25 rounds to the same number as pi / 4 (a product by a power of two)
            (
                std::f64::consts::FRAC_PI_4,
                "9.9999999999999993876766004e-1",
            ),
            (1.2566370614359172, "3.0776835371752528895835795e+0"),
            (1.5393804002589986, "3.1820515953773852208377771e+1"),
        ];
        for (x, want) in cases {
            let want: f64 = want.parse().unwrap();
            let t = tan(Interval::point(x));
            assert!(t.contains(want, 0.0), "{x}: {t:?} {want}");
            // a few units of each sum of terms below 1.2 in modulus: relative to `cos x`
            // that is `1 / cos x = sqrt(1 + tan^2 x)` times more (at x = 1.54, cos x = 0.031
            // loses five bits to cancellation)
            let units = 64.0 * f64::EPSILON * want * (1.0 + want * want).sqrt();
            assert!(t.hi() - t.lo() <= units, "{x}: {t:?}");
        }
        // increasing: an interval's enclosure runs from its lower end's to its upper end's
        let over = tan(Interval::new(0.09424777960769379, 0.3141592653589793));
        assert!(over.contains(0.09452783117928204, 0.0) && over.contains(0.3249196962329063, 0.0));
        // pi / 2 and beyond, and negative arguments: the whole line
        for bad in [std::f64::consts::FRAC_PI_2, 2.0, -0.1] {
            let t = tan(Interval::point(bad));
            // exact: the whole line's ends are the infinities
            assert!(
                t.lo() == f64::NEG_INFINITY && t.hi() == f64::INFINITY,
                "{bad}"
            );
        }
    }
}
