//! The Schur-Cohn (Jury) test: are all roots of a real polynomial inside a circle?
//!
//! Method: the Schur-Cohn step reduction with normalization at each step (Jury's table in
//! its lattice form; see e.g. Jury, *Theory and Application of the z-Transform Method*,
//! 1964, or Marden, *Geometry of Polynomials*, section 42). For a monic `p` of degree `m`
//! with reflection coefficient `k = p(0)`, all roots lie in the open unit disc iff `|k| < 1`
//! and all roots of `(p(z) - k p*(z)) / ((1 - k^2) z)` do, where `p*` is the reversed
//! polynomial. That is `m` steps of `O(m)` work, no roots, no allocation.

use crate::poly::MAX_COEFFS;

/// Result of one Schur-Cohn recursion.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SchurCohn {
    /// Whether every root lies strictly inside the tested circle.
    pub stable: bool,
    /// The smallest `1 - |k|` over the reflection coefficients reached before stopping.
    ///
    /// Each step divides by `1 - k^2`, so a small gap means the later steps magnify rounding
    /// by about `1 / gap`: this is the recursion's own condition estimate.
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
    let (a, b) = scratch[..2 * coeffs.len()].split_at_mut(coeffs.len());
    recursion(coeffs, radius, a, b)
}

/// Runs `f` on a zeroed stack buffer of at least `len` values, choosing the smallest of a few
/// fixed sizes so short polynomials do not pay for clearing a buffer sized for degree 504.
///
/// # Panics
///
/// If `len > 3 * MAX_COEFFS` (callers check the degree first; three rows of coefficients
/// is the most any caller needs).
pub fn with_scratch<R>(len: usize, f: impl FnOnce(&mut [f64]) -> R) -> R {
    if len <= 16 {
        f(&mut [0.0; 16][..len])
    } else if len <= 64 {
        f(&mut [0.0; 64][..len])
    } else {
        f(&mut [0.0; 3 * MAX_COEFFS][..len])
    }
}

fn recursion(coeffs: &[f64], radius: f64, a: &mut [f64], b: &mut [f64]) -> SchurCohn {
    let fail = SchurCohn {
        stable: false,
        min_gap: 0.0,
    };
    let Some(m) = coeffs.len().checked_sub(1) else {
        return fail;
    };
    let lead = coeffs[m];
    if !(lead.is_finite() && lead.abs() > 0.0 && radius > 0.0) {
        return fail;
    }
    // p(radius z) / (lead radius^m): monic, roots divided by radius.
    let inv_r = 1.0 / radius;
    let mut scale = 1.0 / lead;
    for i in (0..=m).rev() {
        a[i] = coeffs[i] * scale;
        scale *= inv_r;
    }
    let mut min_gap = f64::INFINITY;
    let (mut cur, mut next) = (a, b);
    for deg in (1..=m).rev() {
        let k = cur[0];
        let gap = 1.0 - k.abs();
        min_gap = min_gap.min(gap);
        if gap.is_nan() || gap <= 0.0 {
            return SchurCohn {
                stable: false,
                min_gap,
            };
        }
        let inv = 1.0 / ((1.0 - k) * (1.0 + k));
        for j in 0..deg {
            next[j] = (cur[j + 1] - k * cur[deg - 1 - j]) * inv;
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
        let mut e = (m as f64 + 8.0) * U * amax;
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

    #[test]
    fn degenerate_input() {
        assert!(!schur_cohn(&[], 1.0).stable);
        assert!(!schur_cohn(&[1.0, 0.0], 1.0).stable);
        assert!(!schur_cohn(&[0.1, f64::NAN], 1.0).stable);
        assert!(schur_cohn(&[7.0], 1.0).stable); // a nonzero constant has no roots
    }
}
