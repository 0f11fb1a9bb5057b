//! The Schur-Cohn recursion on interval coefficients, counting the roots outside the unit
//! circle (Schur 1917, Cohn 1922; the counting form is that of Marden, "Geometry of
//! Polynomials", AMS 1966, section 42, and of Jury's table).
//!
//! For `p` of degree `k` with coefficients `a_0 .. a_k` and its reverse `p*(z) = z^k p(1/z)`,
//! the reflection coefficient is `r = a_0 / a_k` and the next polynomial is
//! `Q = (a_k p - a_0 p*) / z`, of degree `k - 1`:
//!
//! - `|a_0| < |a_k|`: `Q = (p - r p*) / z` has one root fewer inside the circle than `p`
//!   (Rouche: `|r p*| < |p|` on the circle);
//! - `|a_0| > |a_k|`: `Q = (p / r - p*) / z` has `k - 1 - I` roots inside, where `I` is the
//!   number of `p`'s roots inside (Rouche the other way: `Q` counts the roots of `p*`).
//!
//! When every step is decided (the recursion is regular), `p` has no root on the circle: such
//! a root is also a root of `p*`, so of every later polynomial, down to a nonzero constant.
//! (A pair of roots `z`, `1/z` is passed down the same way and also ends in an undecided
//! step; the loop's polynomials have such a pair only on a set of walls of measure zero.)
//! With intervals a step is decided only when the modulus comparison holds for every value in
//! the enclosures, so the count holds for every polynomial in them. The coefficients are
//! rescaled by a power of two after each step so that nothing overflows (the roots and the
//! reflection coefficients do not change).
//!
//! A step decided with `|a_0| > |a_k|` after steps that were all decided with `|a_0| <
//! |a_k|` proves on its own that `p` is not Schur stable, whatever the later steps do: while
//! `|r| < 1`, `p` has every root inside exactly when `Q` has (the count above), and the
//! polynomial of that step has `|a_0| > |a_k| > 0`, so the product of its roots' moduli
//! exceeds 1 (Jury's table stops there for the same reason). That answers for a set of
//! walls that crosses a curve where the count of roots outside changes, which no count
//! decides.

use super::interval::Interval;
use crate::stability::schur_cohn::{in_range, pow2_inverse};

/// The recursion's reflection coefficients and what they prove.
#[derive(Debug, Clone)]
pub(crate) struct Recursion {
    /// `a_0 / a_k` at each step, degree `k` from the top down to 1 (as far as it got).
    pub reflections: Vec<Interval>,
    /// The number of roots outside the circle, or `None` when a step was undecided.
    pub outside: Option<usize>,
    /// The index in `reflections` of the first step, when it was decided with `|a_0| >
    /// |a_k|` and every step before it with `|a_0| < |a_k|`: then no polynomial in the
    /// enclosures is Schur stable (see the module documentation).
    pub first_greater: Option<usize>,
}

/// Runs the recursion on `coeffs` (lowest power first, the top one not containing 0 for a
/// decided first step).
pub(crate) fn recursion(coeffs: &[Interval]) -> Recursion {
    let mut a: Vec<Interval> = coeffs.to_vec();
    let mut next: Vec<Interval> = Vec::with_capacity(a.len());
    let mut reflections = Vec::with_capacity(a.len());
    // inside_first[k] for the step at degree k: whether |a_0| < |a_k|
    let mut less: Vec<bool> = Vec::with_capacity(a.len());
    let mut first_greater = None;
    while a.len() > 1 {
        let (r, decided) = step(&a, &mut next);
        reflections.push(r);
        let Some(l) = decided else {
            return Recursion {
                reflections,
                outside: None,
                first_greater,
            };
        };
        if !l && less.iter().all(|&l| l) {
            first_greater.get_or_insert(less.len());
        }
        less.push(l);
        std::mem::swap(&mut a, &mut next);
    }
    // I_0 = 0; I_k = I_{k-1} + 1 when |a_0| < |a_k| at degree k, else k - 1 - I_{k-1}.
    let n = less.len();
    let mut inside = 0usize;
    for (k, &l) in (1..=n).zip(less.iter().rev()) {
        inside = if l { inside + 1 } else { k - 1 - inside };
    }
    Recursion {
        reflections,
        outside: Some(n - inside),
        first_greater,
    }
}

/// Whether every polynomial within the enclosures `coeffs` (lowest power first) has all its
/// roots strictly inside the unit circle: [`recursion`]'s count of none outside, stopped at
/// the first step not decided with `|a_0| < |a_k|` (a step decided the other way leaves
/// fewer than `k` roots inside at its degree, and each later step adds at most one, so the
/// count cannot end at none outside).
pub(crate) fn all_inside(coeffs: Vec<Interval>) -> bool {
    let mut a = coeffs;
    let mut next = Vec::with_capacity(a.len());
    while a.len() > 1 {
        if step(&a, &mut next).1 != Some(true) {
            return false;
        }
        std::mem::swap(&mut a, &mut next);
    }
    true
}

/// Unit roundoff of `f64` (rounding to nearest).
const U: f64 = f64::EPSILON / 2.0;

/// Whether every polynomial whose coefficients (lowest power first) lie within `rad` of
/// those in `a` has all its roots strictly inside the circle of radius `radius` (`0 < radius
/// <= 1`): [`all_inside`]'s proof in plain `f64` with a running bound on the rounding, a
/// fraction of its cost. `a` and `b` (scratch, at least as long) are overwritten. `false`
/// says only that this could not prove it.
///
/// Method: the recursion of the module documentation, division-free (`Q = (a_k p - a_0 p*) /
/// z`, the same polynomial times `a_k`), in midpoint-radius arithmetic (Rump, "Fast and
/// parallel interval arithmetic", BIT 39, 1999) with one radius `R` for all coefficients of a
/// step and `M` the largest computed midpoint's modulus: every exact value in the set lies
/// within `R` of its midpoint. The scaled coefficients `a_i radius^i` are rounded `i + 1`
/// times (the powers and the product), off by at most `1.01 (i + 1) u` relative (`u =
/// 2^-53`; Higham, "Accuracy and Stability of Numerical Algorithms", 2002, lemma 3.1), so
/// their radius is `rad + 2 n u M` (`rad radius^i <= rad`, `n` coefficients). A step at
/// degree `k` is decided only when `|a_0| + R < |a_k| - R`, compared as `|a_0| + 2R < |a_k|
/// (1 - 4u)` (the rounded sum is at least `1 - 2u` of the exact one, the rounded right side
/// below `|a_k| (1 - 2u)`); it then holds for every polynomial in the set. Each new
/// coefficient `a_k x - a_0 y` is within `(|a_k| + R) R + R |x| + (|a_0| + R) R + R |y|` of
/// `a_k x - a_0 y` for the exact values, and the computed one within `3 u (|a_k| + |a_0|) M`
/// of that (two products and a difference: at most `2.01 u (|a_k x| + |a_0 y|)`, Higham's
/// lemma 3.1 again); with `|x|, |y| <= M` the sum of these nonnegative terms is rounded at
/// most 16 times, each rounding down by at most a factor `1 - u`, so multiplying it by `1 +
/// 64 u` keeps it an upper bound. A row whose leading midpoint leaves `[2^-256, 2^256]` is
/// rescaled by a power of two, and `f64::MIN_POSITIVE` added to the radius covers the
/// absolute error of any operation of the step that underflows (at most `2^-1075` each). A
/// non-finite value fails the comparison (an infinite leading coefficient by name). The steps
/// need no division; the radius grows as the one of every coefficient would, so a polynomial
/// with a root `1e-7` inside the circle is proved as [`all_inside`] proves it.
pub(crate) fn balls_inside(a: &mut [f64], b: &mut [f64], rad: f64, radius: f64) -> bool {
    let n = a.len();
    if n == 0 || b.len() < n || !(radius > 0.0 && radius <= 1.0) {
        return false;
    }
    let mut pow = 1.0;
    let mut big = 0.0f64;
    for x in a.iter_mut() {
        *x *= pow;
        big = super::larger(big, x.abs());
        pow *= radius;
    }
    let mut r = (rad + 2.0 * n as f64 * U * big) * (1.0 + 64.0 * U) + f64::MIN_POSITIVE;
    let (mut cur, mut next) = (a, &mut b[..n]);
    if !in_range(cur[n - 1]) {
        (big, r) = rescale_balls(cur, r);
    }
    for k in (1..n).rev() {
        let (a0, ak) = (cur[0], cur[k]);
        let right = ak.abs() * (1.0 - 4.0 * U);
        // false for NaN; an infinite leading coefficient proves nothing
        if !(right.is_finite() && a0.abs() + 2.0 * r < right) {
            return false;
        }
        let mut m = 0.0f64;
        for j in 0..k {
            let v = ak * cur[j + 1] - a0 * cur[k - 1 - j];
            next[j] = v;
            m = super::larger(m, v.abs());
        }
        let (la, l0) = (ak.abs(), a0.abs());
        r = ((la + l0 + 2.0 * r) * r + 2.0 * r * big + 3.0 * U * (la + l0) * big)
            * (1.0 + 64.0 * U)
            + f64::MIN_POSITIVE;
        big = m;
        std::mem::swap(&mut cur, &mut next);
        if !in_range(cur[k - 1]) {
            (big, r) = rescale_balls(&mut cur[..k], r);
        }
    }
    true
}

/// The midpoints times the power of two that brings the last (leading) one near 1
/// (exact but where a value underflows), and the new largest modulus and radius, with
/// `f64::MIN_POSITIVE` added for that underflow (see [`balls_inside`]).
fn rescale_balls(m: &mut [f64], r: f64) -> (f64, f64) {
    let lead = m[m.len() - 1].abs();
    let s = if lead.is_finite() && lead > 0.0 {
        pow2_inverse(lead)
    } else {
        1.0
    };
    let mut big = 0.0f64;
    for x in m.iter_mut() {
        *x *= s;
        big = big.max(x.abs());
    }
    (big, r * s + f64::MIN_POSITIVE)
}

/// One step of the recursion at degree `k = a.len() - 1`: the reflection coefficient
/// `a_0 / a_k` and whether `|a_0| < |a_k|` for every value in the enclosures (`Some(false)`
/// when `|a_0| > |a_k|` for every one, `None` when undecided); a decided step writes the
/// next polynomial, rescaled, into `next`.
fn step(a: &[Interval], next: &mut Vec<Interval>) -> (Interval, Option<bool>) {
    let k = a.len() - 1;
    let (a0, ak) = (a[0], a[k]);
    let r = a0 / ak;
    next.clear();
    let less = if a0.mag() < ak.mig() {
        next.extend((0..k).map(|j| a[j + 1] - r * a[k - 1 - j]));
        true
    } else if a0.mig() > ak.mag() && ak.mig() > 0.0 {
        let inv = ak / a0;
        next.extend((0..k).map(|j| inv * a[j + 1] - a[k - 1 - j]));
        false
    } else {
        return (r, None);
    };
    rescale(next);
    (r, Some(less))
}

/// The coefficients times a power of two that brings the largest modulus near 1.
fn rescale(a: &mut [Interval]) {
    let big = a.iter().fold(0.0f64, |m, c| m.max(c.mag()));
    if !(big.is_finite() && big > 0.0) {
        return;
    }
    let e = big.log2().floor().clamp(-1000.0, 1000.0) as i32;
    if e == 0 {
        return;
    }
    let s = Interval::point(2f64.powi(-e));
    for c in a.iter_mut() {
        *c = *c * s;
    }
}

/// `coeffs[i] * radius^i`: the coefficients of `q(radius z)`, whose roots are `q`'s divided
/// by `radius`.
pub(crate) fn scaled(coeffs: &[Interval], radius: Interval) -> Vec<Interval> {
    let mut pow = Interval::point(1.0);
    coeffs
        .iter()
        .map(|&c| {
            let v = c * pow;
            pow = pow * radius;
            v
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn poly(roots: &[f64]) -> Vec<Interval> {
        let mut p = vec![1.0];
        for &r in roots {
            let mut q = vec![0.0; p.len() + 1];
            for (i, &c) in p.iter().enumerate() {
                q[i + 1] += c;
                q[i] -= r * c;
            }
            p = q;
        }
        p.into_iter().map(Interval::point).collect()
    }

    /// Polynomials with known real roots (exact dyadic coefficients): the count of roots
    /// outside is the known one.
    #[test]
    fn counts_known_roots() {
        for (roots, out) in [
            (&[0.5, -0.25, 0.75][..], 0),
            (&[3.0, 0.5, -0.25][..], 1),
            (&[2.0, -3.0, 0.25, 0.125][..], 2),
            (&[2.0, -3.0, 4.0][..], 3),
            (&[1.5, -1.25, 0.5, 8.0, 0.0625][..], 3),
        ] {
            assert_eq!(recursion(&poly(roots)).outside, Some(out), "{roots:?}");
        }
        // a root on the circle is never decided
        assert_eq!(recursion(&poly(&[1.0, 0.5])).outside, None);
        assert_eq!(recursion(&poly(&[-1.0, 0.5, 2.0])).outside, None);
        // radius 4 puts every root of the third case inside
        let p = poly(&[2.0, -3.0, 0.25, 0.125]);
        let s = scaled(&p, Interval::point(4.0));
        assert_eq!(recursion(&s).outside, Some(0));
    }

    /// A step with `|r| > 1` after steps with `|r| < 1` is found exactly when the polynomial
    /// has a root outside (here with a root on the circle too, which leaves the count
    /// undecided), and never for a stable one.
    #[test]
    fn first_greater_step_marks_instability() {
        assert_eq!(recursion(&poly(&[0.5, -0.25, 0.75])).first_greater, None);
        let both = recursion(&poly(&[1.0, 3.0, 0.5]));
        assert_eq!(both.outside, None);
        assert_eq!(both.first_greater, Some(0));
        // roots 0.25, 0.5 and 1.5: |a_0| = 0.1875 < 1, so the first step is not the one
        let later = recursion(&poly(&[0.25, 0.5, 1.5]));
        assert_eq!(later.outside, Some(1));
        assert!(later.first_greater.is_some_and(|j| j > 0));
    }

    /// The `f64` proof with its rounding bound agrees with the known roots: all inside is
    /// proved, a root on or outside the circle (or pushed outside by the radius, or within
    /// the coefficients' radius of it) never is.
    #[test]
    fn balls_prove_known_roots() {
        let run = |roots: &[f64], rad: f64, radius: f64| {
            let mut a: Vec<f64> = poly(roots).iter().map(|c| c.lo()).collect();
            let mut b = vec![0.0; a.len()];
            balls_inside(&mut a, &mut b, rad, radius)
        };
        assert!(run(&[0.5, -0.25, 0.75], 0.0, 1.0));
        assert!(run(&[0.5, -0.25, 0.75], 1e-3, 1.0));
        assert!(!run(&[0.5, -0.25, 0.75], 0.0, 0.7));
        assert!(!run(&[0.5, -0.25, 0.75], 0.3, 1.0));
        assert!(!run(&[1.0, 0.5], 0.0, 1.0));
        assert!(!run(&[-1.0, 0.5, 0.25], 0.0, 1.0));
        assert!(!run(&[3.0, 0.5, -0.25], 0.0, 1.0));
        // a root 2^-20 inside the circle: proved at radius 1, not at 1 - 2^-19
        let near = 1.0 - 2f64.powi(-20);
        assert!(run(&[near, 0.5], 0.0, 1.0));
        assert!(!run(&[near, 0.5], 0.0, 1.0 - 2f64.powi(-19)));
        // a nonzero constant has no root; a radius that is not in (0, 1] proves nothing
        assert!(run(&[], 0.0, 1.0));
        assert!(!run(&[0.5], 0.0, 0.0) && !run(&[0.5], 0.0, 2.0));
    }
}
