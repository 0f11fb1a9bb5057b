//! The Schur-Cohn (Jury) test: are all roots of a real polynomial inside a circle?
//!
//! Method: the Schur-Cohn step reduction (Jury's table; see e.g. Jury, *Theory and
//! Application of the z-Transform Method*, 1964, or Marden, *Geometry of Polynomials*,
//! section 42). For `p` of degree `m` with leading coefficient `l` and constant term `k`,
//! all roots lie in the open unit disc iff `|k| < |l|` and all roots of
//! `(l p(z) - k p*(z)) / z` do, where `p*` is the reversed polynomial. That is `m` steps of
//! `O(m)` work, no roots, no allocation.
//!
//! The step is the normalized one (`k / l` is the reflection coefficient) multiplied through
//! by `l`, so it needs no division: a division's latency is several multiplications' and the
//! steps form one dependency chain. Left alone, the unnormalized rows square in magnitude at
//! every step; a row whose leading coefficient leaves `[2^-256, 2^256]` is rescaled by a power
//! of two, which is exact, so the verdict is that of the plain unnormalized recursion.

use crate::poly::MAX_COEFFS;

/// Result of one Schur-Cohn recursion.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SchurCohn {
    /// Whether every root lies strictly inside the tested circle.
    pub stable: bool,
    /// The smallest `1 - |k|` over the reflection coefficients `k` reached before stopping.
    ///
    /// The normalized recursion divides by `1 - k^2`, so a small gap means the later steps
    /// magnify rounding by about `1 / gap`: this is the recursion's own condition estimate.
    pub min_gap: f64,
}

/// Runs the recursion on `coeffs` (lowest power first, leading coefficient nonzero) for the
/// circle of radius `radius`: tests whether all roots `z` satisfy `|z| < radius`.
///
/// Returns `stable: false` for a zero or non-finite leading coefficient, a degree above
/// [`MAX_COEFFS`]` - 1`, or a non-finite intermediate.
pub fn schur_cohn(coeffs: &[f64], radius: f64) -> SchurCohn {
    if coeffs.len() > MAX_COEFFS {
        return SchurCohn {
            stable: false,
            min_gap: 0.0,
        };
    }
    with_scratch(2 * coeffs.len(), |buf| schur_cohn_in(coeffs, radius, buf))
}

/// [`schur_cohn`] with caller-provided scratch space of at least `2 * coeffs.len()` values,
/// for callers that already hold a stack buffer (one clearing instead of two per test).
///
/// # Panics
///
/// If `scratch` is shorter than `2 * coeffs.len()` (a caller bug, not user input).
pub fn schur_cohn_in(coeffs: &[f64], radius: f64, scratch: &mut [f64]) -> SchurCohn {
    let fail = SchurCohn {
        stable: false,
        min_gap: 0.0,
    };
    let n = coeffs.len();
    let Some(m) = n.checked_sub(1) else {
        return fail;
    };
    if !(coeffs[m].is_finite() && coeffs[m].abs() > 0.0 && radius > 0.0 && radius.is_finite()) {
        return fail;
    }
    let (a, b) = scratch[..2 * n].split_at_mut(n);
    // p(radius z): roots divided by radius. Scale so the factors only shrink (no overflow):
    // a_i radius^i inside the unit circle, a_i radius^(i - m) outside it.
    if radius < 1.0 {
        let mut s = 1.0;
        for (ai, ci) in a.iter_mut().zip(coeffs) {
            *ai = ci * s;
            s *= radius;
        }
    } else {
        let inv = 1.0 / radius;
        let mut s = 1.0;
        for (ai, ci) in a.iter_mut().zip(coeffs).rev() {
            *ai = ci * s;
            s *= inv;
        }
    }
    recursion(a, b)
}

/// Runs `f` on a zeroed stack buffer of at least `len` values, choosing the smallest of a few
/// fixed sizes so short polynomials do not pay for clearing a buffer sized for degree 504.
///
/// # Panics
///
/// If `len > 2 * MAX_COEFFS` (callers check the degree first; the recursion's two rows of
/// coefficients are the most any caller needs).
pub fn with_scratch<R>(len: usize, f: impl FnOnce(&mut [f64]) -> R) -> R {
    // Sizes doubling from 16, so that no more than twice the length is zeroed: zeroing all
    // 2 MAX_COEFFS (8 kB) for every point test was most of a test's cost at d = 100.
    if len <= 16 {
        f(&mut [0.0; 16][..len])
    } else if len <= 64 {
        f(&mut [0.0; 64][..len])
    } else if len <= 128 {
        f(&mut [0.0; 128][..len])
    } else if len <= 256 {
        f(&mut [0.0; 256][..len])
    } else if len <= 512 {
        f(&mut [0.0; 512][..len])
    } else {
        f(&mut [0.0; 2 * MAX_COEFFS][..len])
    }
}

/// Runs `f` on two zeroed rows of `len` values each, from one [`with_scratch`] buffer: the
/// coefficients of a polynomial and the output of a deflation or a recursion.
pub(crate) fn with_two_rows<R>(len: usize, f: impl FnOnce(&mut [f64], &mut [f64]) -> R) -> R {
    with_scratch(2 * len, |s| {
        let (a, b) = s.split_at_mut(len);
        f(a, b)
    })
}

/// `2^-e` for the binary exponent `e` of a finite nonzero `x`, so `x * pow2_inverse(x)` lies in
/// `[1, 2)` (or close to it for subnormal `x`). Multiplying by it is exact.
pub(crate) fn pow2_inverse(x: f64) -> f64 {
    let biased = (x.to_bits() >> 52) & 0x7ff; // 0 (subnormal) ..= 2046 for finite x
    f64::from_bits((2046 - biased.min(2045)) << 52)
}

/// Whether `x` is far enough from both overflow and underflow that a row led by it needs no
/// rescaling: its entries then stay representable through the next step's products.
pub(crate) fn in_range(x: f64) -> bool {
    const LO: f64 = f64::from_bits((1023 - 256) << 52); // 2^-256
    const HI: f64 = f64::from_bits((1023 + 256) << 52); // 2^256
    let a = x.abs();
    a > LO && a < HI
}

/// Whether every root of the polynomial with coefficients `a` (lowest power first) lies in
/// the open unit disc: [`recursion`]'s verdict without its condition estimate, for the hot
/// path where only the verdict is wanted. `b` is scratch of the same length; both are
/// overwritten.
///
/// # Panics
///
/// If `b` is shorter than `a` (a caller bug).
pub(crate) fn unit_disc_stable(a: &mut [f64], b: &mut [f64]) -> bool {
    reduce::<false>(a, b).stable
}

/// The recursion on the (already radius-scaled) coefficients in `a`; `b` is scratch of the
/// same length. Both are overwritten.
///
/// # Panics
///
/// If `b` is shorter than `a` (a caller bug).
pub(crate) fn recursion(a: &mut [f64], b: &mut [f64]) -> SchurCohn {
    reduce::<true>(a, b)
}

/// The step reduction itself; with `GAP` it also tracks [`SchurCohn::min_gap`] (otherwise
/// left infinite), a division per step that the verdict alone does not need.
fn reduce<const GAP: bool>(a: &mut [f64], b: &mut [f64]) -> SchurCohn {
    let fail = SchurCohn {
        stable: false,
        min_gap: 0.0,
    };
    let Some(m) = a.len().checked_sub(1) else {
        return fail;
    };
    let lead = a[m];
    if !(lead.is_finite() && lead.abs() > 0.0) {
        return fail;
    }
    if !in_range(lead) {
        let s = pow2_inverse(lead);
        a.iter_mut().for_each(|x| *x *= s);
    }
    let mut min_gap = f64::INFINITY;
    let (mut cur, mut next) = (a, &mut b[..m + 1]);
    for deg in (1..=m).rev() {
        let (k, l) = (cur[0], cur[deg]);
        if GAP {
            // Off the dependency chain: the division here does not delay the next step.
            min_gap = min_gap.min(1.0 - (k / l).abs());
        }
        // False for NaN anywhere, which is therefore unstable.
        let inside = k.abs() < l.abs();
        if !inside {
            return SchurCohn {
                stable: false,
                min_gap,
            };
        }
        for j in 0..deg - 1 {
            next[j] = l * cur[j + 1] - k * cur[deg - 1 - j];
        }
        // The new leading coefficient is l^2 - k^2; factored, it keeps its relative accuracy
        // when |k| is close to |l| (a root near the circle), where l*l - k*k would cancel.
        let lead = (l - k) * (l + k);
        next[deg - 1] = lead;
        if !in_range(lead) && lead.is_finite() && lead.abs() > 0.0 {
            let s = pow2_inverse(lead);
            next[..deg].iter_mut().for_each(|x| *x *= s);
        }
        std::mem::swap(&mut cur, &mut next);
    }
    SchurCohn {
        stable: true,
        min_gap,
    }
}

/// Unit roundoff of `f64` (half the machine epsilon).
const U: f64 = f64::EPSILON / 2.0;

/// Result of a Schur-Cohn recursion with a running rounding-error bound.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Guarded {
    /// The verdict of the plain recursion (identical to [`schur_cohn`]'s).
    pub stable: bool,
    /// Whether rounding cannot have changed the verdict: every reflection coefficient that
    /// decided it is farther from `|k| = 1` than the bound on its error.
    pub trusted: bool,
    /// The smallest `1 - |k|` reached (as [`SchurCohn::min_gap`]).
    pub min_gap: f64,
    /// The error bound on `|k|` at the step with the smallest margin over its bound.
    pub error: f64,
}

/// [`schur_cohn`] with a running error analysis (Wilkinson's running error bound, see
/// Higham, *Accuracy and Stability of Numerical Algorithms*, 2nd ed., 2002, section 3.3).
///
/// The coefficients enter with an error of `(m + 8) u` of the largest one (their own
/// construction from `alpha`, `beta` and the discretization, plus the scaling by
/// `radius^-i`; `u = 2^-53`). Each step `next_j = (cur_{j+1} - k cur_{deg-1-j}) / (1 - k^2)`
/// propagates an entry error `e` to first order as
///
/// ```text
/// e' = [e (1 + |k|) + e A + 3 u A (1 + |k|)] / (1 - k^2)
///    + A (1 + |k|) / (1 - k^2) * (2 |k| e / (1 - k^2) + 4 u)
/// ```
///
/// with `A` the largest entry of the current polynomial (the error of `k` itself is `e`,
/// and `1/(1-k^2)` has relative error `2 |k| e / (1 - k^2)`). The verdict is trusted when
/// every step that decided it has `|1 - |k|| > e`: then a perturbation of the exact recursion
/// within the bound cannot move any `|k|` across 1. The bound grows like the product of
/// `1 / (1 - k_i^2)`, so it is pessimistic, never optimistic to first order.
pub fn schur_cohn_guarded(coeffs: &[f64], radius: f64) -> Guarded {
    schur_cohn_guarded_with(coeffs, radius, 0.0)
}

/// [`schur_cohn_guarded`] for coefficients known only to within `coeff_err` each (absolute,
/// before the scaling by `radius`): the bound enters the first step's error besides the
/// guard's own `(m + 8) u` of the largest coefficient. A NaN or infinite `coeff_err` gives
/// an untrusted verdict.
pub fn schur_cohn_guarded_with(coeffs: &[f64], radius: f64, coeff_err: f64) -> Guarded {
    let fail = Guarded {
        stable: false,
        trusted: false,
        min_gap: 0.0,
        error: f64::INFINITY,
    };
    if coeffs.len() > MAX_COEFFS {
        return fail;
    }
    let Some(m) = coeffs.len().checked_sub(1) else {
        return fail;
    };
    let lead = coeffs[m];
    if !(lead.is_finite() && lead.abs() > 0.0 && radius > 0.0) {
        return fail;
    }
    with_scratch(2 * coeffs.len(), |buf| {
        let (a, b) = buf.split_at_mut(coeffs.len());
        let inv_r = 1.0 / radius;
        let mut scale = 1.0 / lead;
        let mut amax = 0.0f64;
        for i in (0..=m).rev() {
            a[i] = coeffs[i] * scale;
            amax = amax.max(a[i].abs());
            scale *= inv_r;
        }
        // After the loop `scale` is r^-(m+1) / lead: the largest factor that multiplied a
        // coefficient is 1 / |lead| (at power m) for r >= 1 and r^-m / |lead| (at power 0)
        // below; that factor times coeff_err bounds the scaled coefficients' extra error.
        let grow = (scale.abs() * radius).max(1.0 / lead.abs());
        let mut e = (m as f64 + 8.0) * U * amax + coeff_err * grow * (1.0 + 1e-6);
        if e.is_nan() {
            return Guarded { ..fail };
        }
        let mut min_gap = f64::INFINITY;
        let mut trusted = true;
        let mut worst = (f64::INFINITY, 0.0);
        let (mut cur, mut next) = (a, b);
        for deg in (1..=m).rev() {
            let k = cur[0];
            let gap = 1.0 - k.abs();
            min_gap = min_gap.min(gap);
            if gap.is_nan() || !e.is_finite() {
                return Guarded { min_gap, ..fail };
            }
            if gap.abs() - e < worst.0 {
                worst = (gap.abs() - e, e);
            }
            if gap <= 0.0 {
                // Decided unstable here: trusted if |k| exceeds 1 by more than its error.
                return Guarded {
                    stable: false,
                    trusted: trusted && -gap > e,
                    min_gap,
                    error: worst.1,
                };
            }
            if gap <= e {
                trusted = false;
            }
            let ak = k.abs();
            let inv = 1.0 / ((1.0 - k) * (1.0 + k));
            let mut next_max = 0.0f64;
            for j in 0..deg {
                let v = (cur[j + 1] - k * cur[deg - 1 - j]) * inv;
                next_max = next_max.max(v.abs());
                next[j] = v;
            }
            let num = amax * (1.0 + ak);
            e = inv * (e * (1.0 + ak) + e * amax + 3.0 * U * num)
                + num * inv * (2.0 * ak * e * inv + 4.0 * U);
            amax = next_max;
            std::mem::swap(&mut cur, &mut next);
        }
        Guarded {
            stable: true,
            trusted,
            min_gap,
            error: worst.1,
        }
    })
}

/// The Schur-Cohn verdict with the roots at `z = 1` and `z = -1` deflated first: a free
/// integrator (no wall stiffness) puts a root at `z = 1`, a free mass (no damping either)
/// two, a two-sample average one at `z = -1`. Rounding splits a double root on the circle
/// into two at a distance of about the square root of the rounding, far outside any
/// marginal band, so the plain recursion calls such a loop unstable; deflated, each such root
/// is on the circle (marginal) and the rest decides.
///
/// Method: `q(+-1)` by Horner's rule against a bound of `roundings (n + 8) eps sum |q_i|`
/// (the coefficients' own error and the evaluation's; `roundings` as the caller's error
/// model); while within it, synthetic division by `z -+ 1`. Then [`schur_cohn`] on the
/// quotient at `1 - margin` and `1 + margin`. A root deflated here is within the bound's
/// reach of the circle, so a verdict of marginal is never confidently wrong.
pub(crate) fn deflated_verdict(q: &[f64], margin: f64, roundings: f64) -> super::Verdict {
    use super::Verdict;
    let plain = |p: &[f64]| {
        if schur_cohn(p, 1.0 - margin).stable {
            Verdict::Stable
        } else if schur_cohn(p, 1.0 + margin).stable {
            Verdict::Marginal
        } else {
            Verdict::Unstable
        }
    };
    let n = q.len();
    let mut p = q.to_vec();
    let mut on_circle = 0;
    for root in [1.0, -1.0] {
        while p.len() > 1 {
            let scale: f64 = p.iter().map(|c| c.abs()).sum();
            let bound = roundings * (n as f64 + 8.0) * f64::EPSILON * scale;
            let value = p.iter().rev().fold(0.0, |acc, &c| acc * root + c);
            if value.is_nan() || value.abs() > bound {
                break;
            }
            let mut quotient = vec![0.0; p.len() - 1];
            crate::poly::deflate_linear(&p, root, &mut quotient);
            p = quotient;
            on_circle += 1;
        }
    }
    match (on_circle, plain(&p)) {
        (0, v) => v,
        (_, Verdict::Unstable) => Verdict::Unstable,
        // a root on the circle: within any marginal band
        _ => Verdict::Marginal,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Coefficients (lowest first) of prod (z - r_i) for real roots.
    fn from_roots(roots: &[f64]) -> Vec<f64> {
        let mut p = vec![1.0];
        for &r in roots {
            let mut q = vec![0.0; p.len() + 1];
            for (i, &c) in p.iter().enumerate() {
                q[i + 1] += c;
                q[i] -= r * c;
            }
            p = q;
        }
        p
    }

    #[test]
    fn known_roots() {
        assert!(schur_cohn(&from_roots(&[0.5, -0.9, 0.99]), 1.0).stable);
        assert!(!schur_cohn(&from_roots(&[0.5, -0.9, 1.01]), 1.0).stable);
        assert!(!schur_cohn(&from_roots(&[0.5, -1.5]), 1.0).stable);
        // radius scaling: roots 0.5 and 0.9 are inside 0.95 but not inside 0.85
        assert!(schur_cohn(&from_roots(&[0.5, 0.9]), 0.95).stable);
        assert!(!schur_cohn(&from_roots(&[0.5, 0.9]), 0.85).stable);
        // z^2 + 0.81 has roots +-0.9i
        assert!(schur_cohn(&[0.81, 0.0, 1.0], 1.0).stable);
        assert!(!schur_cohn(&[1.21, 0.0, 1.0], 1.0).stable);
        // non-monic leading coefficient is normalized
        assert!(schur_cohn(&[0.81 * 3.0, 0.0, 3.0], 1.0).stable);
    }

    /// Multiplies `p` by `z^2 - 2 re z + |w|^2`, the factor of the conjugate pair `w, w*`.
    fn times_pair(p: &[f64], re: f64, abs2: f64) -> Vec<f64> {
        let mut q = vec![0.0; p.len() + 2];
        for (i, &c) in p.iter().enumerate() {
            q[i] += abs2 * c;
            q[i + 1] -= 2.0 * re * c;
            q[i + 2] += c;
        }
        q
    }

    #[test]
    fn scale_of_the_coefficients_does_not_matter() {
        // Without the power-of-two rescaling, rows led by 1e200 overflow in the first step
        // and rows led by 1e-200 underflow: the verdict must not depend on the scale.
        let stable = from_roots(&[0.5, -0.9, 0.99, 0.3]);
        let unstable = from_roots(&[0.5, -0.9, 1.01, 0.3]);
        for scale in [1e-300, 1e-200, 1e-100, 1.0, 1e100, 1e200, 1e300] {
            let s: Vec<f64> = stable.iter().map(|c| c * scale).collect();
            let u: Vec<f64> = unstable.iter().map(|c| c * scale).collect();
            assert!(schur_cohn(&s, 1.0).stable, "scale {scale}");
            assert!(!schur_cohn(&u, 1.0).stable, "scale {scale}");
        }
    }

    #[test]
    fn high_degree_with_known_roots() {
        // Degree up to 200 from known roots (conjugate pairs of modulus 0.2 to 0.8 and one
        // real root at most 0.97 or at least 1.03): the verdict is known without any other
        // root finder. Pairs closer to the circle make the expanded degree-150 polynomial
        // itself ill-conditioned: with moduli up to 0.97, 4 of 400 such polynomials were
        // misjudged by this recursion and, identically, by the normalized one it replaced.
        let mut rnd = crate::stability::test_rng(0x2545_f491_4f6c_dd1d_u64);
        for trial in 0..200 {
            let degree = 2 + trial % 199;
            let outside = trial % 2 == 1;
            let mut p = vec![1.0];
            while p.len() < degree {
                let r = 0.2 + 0.6 * rnd();
                let t = std::f64::consts::PI * rnd();
                p = times_pair(&p, r * t.cos(), r * r);
            }
            let last = if outside { 1.03 + rnd() } else { 0.97 * rnd() };
            let p = from_roots_times(&p, last);
            assert_eq!(
                schur_cohn(&p, 1.0).stable,
                !outside,
                "degree {}",
                p.len() - 1
            );
            // and against a circle that excludes the largest root of the stable ones
            if !outside {
                assert!(!schur_cohn(&p, 0.15).stable);
            }
        }
    }

    fn from_roots_times(p: &[f64], r: f64) -> Vec<f64> {
        let mut q = vec![0.0; p.len() + 1];
        for (i, &c) in p.iter().enumerate() {
            q[i + 1] += c;
            q[i] -= r * c;
        }
        q
    }

    #[test]
    fn degenerate_input() {
        assert!(!schur_cohn(&[], 1.0).stable);
        assert!(!schur_cohn(&[1.0, 0.0], 1.0).stable);
        assert!(!schur_cohn(&[0.1, f64::NAN], 1.0).stable);
        assert!(schur_cohn(&[7.0], 1.0).stable); // a nonzero constant has no roots
    }

    /// A double root at `z = 1` (a free mass) and one at `z = -1` (a two-sample average),
    /// times a stable factor: deflated, marginal; the plain recursion cannot say so.
    #[test]
    fn deflation_of_roots_on_the_circle() {
        use crate::stability::Verdict;
        // (z - 1)^2 (z + 1) (z - 0.5) = z^4 - 1.5 z^3 - 0.5 z^2 + 1.5 z - 0.5
        let q = [-0.5, 1.5, -0.5, -1.5, 1.0];
        assert_eq!(deflated_verdict(&q, 1e-9, 1024.0), Verdict::Marginal);
        // with an unstable factor: (z - 1)^2 (z - 1.5)
        let q = [-1.5, 4.0, -3.5, 1.0];
        assert_eq!(deflated_verdict(&q, 1e-9, 1024.0), Verdict::Unstable);
        // no root on the circle: the plain verdicts
        assert_eq!(
            deflated_verdict(&[0.25, -1.0, 1.0], 1e-9, 1024.0),
            Verdict::Stable
        );
        assert_eq!(
            deflated_verdict(&[2.0, -3.0, 1.0], 1e-9, 1024.0),
            Verdict::Unstable
        );
        // a root 1e-6 outside the circle is not deflated: (z - 1.000001)(z - 0.5)
        let r = 1.000001;
        assert_eq!(
            deflated_verdict(&[0.5 * r, -(r + 0.5), 1.0], 1e-9, 1024.0),
            Verdict::Unstable
        );
    }
}
