//! One-dimensional stability searches: the stable stiffnesses at a fixed damping, and the
//! stable dampings at a fixed stiffness.
//!
//! Both are exact, not bisections. Along a line in the wall plane (one wall parameter `s`
//! free, the other fixed) the characteristic polynomial is affine in `s`:
//! `q(z) = P(z) + s D(z)` (with `D = QA` when `s = alpha`, `D = QB` when `s = beta`,
//! `docs/MODEL.md` section 4). Stability can change only where a root crosses the unit circle, that
//! is at an `s` with `P(z) + s D(z) = 0` for some `|z| = 1`. On the circle `conj(D(z)) =
//! D(1/z)` (real coefficients), so `s = -P(z)/D(z)` is real exactly when
//!
//! ```text
//! S(z) = P(z) D*(z) - P*(z) D(z) = 0,        P*(z) = z^N P(1/z), D*(z) = z^N D(1/z),
//! ```
//!
//! a polynomial of degree `2N` (`N = deg q`). This is the D-decomposition of Neimark (1948)
//! restricted to one line (the "root-locus crossing" form used e.g. in Ackermann, *Robust
//! Control*, 2nd ed., 2002, section 4.3). Its roots on the unit circle give every crossing
//! value `s`; between two consecutive crossings the number of unstable roots is constant, so
//! one Schur-Cohn point test per piece decides the whole piece (a thin piece, as at a wedge's
//! tip, whose middle is not called stable is tried at a few more points: the verdict there
//! varies within a few `1e-9` of the circle). The result is the stable set
//! on the line as a union of open intervals, the empty set included.
//!
//! Cost: one polynomial root-finding of degree `2N` (companion eigenvalues) and one point
//! test per piece; for one sample of delay (`N = 4`) a few tens of microseconds.

use crate::curve::{Decomposition, Free, line_crossings};
use crate::error::{Error, Result};
use crate::params::{Wall, finite};
use crate::poly::Complex;
use crate::roots::eigen::poly_roots;
use crate::stability::Checker;

/// An open interval `(lo, hi)` of stable parameter values; the ends are on the boundary.
///
/// `lo` may be `-inf` and `hi` may be `+inf` only in a degenerate plant where a whole
/// half-line is stable (the crate's model has none: large walls are always unstable).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Interval {
    /// Lower end (not itself stable: a root is on the unit circle there).
    pub lo: f64,
    /// Upper end (not itself stable).
    pub hi: f64,
}

impl Interval {
    /// Whether `x` lies strictly inside.
    pub fn contains(&self, x: f64) -> bool {
        self.lo < x && x < self.hi
    }

    /// Distance from `x` to the interval (0 inside).
    pub fn distance(&self, x: f64) -> f64 {
        if x < self.lo {
            self.lo - x
        } else if x > self.hi {
            x - self.hi
        } else {
            0.0
        }
    }
}

/// The stable stiffnesses `alpha` at fixed damping `beta`, as sorted disjoint open intervals.
///
/// Exact crossing search (module doc). Empty when no stiffness is stable at this damping
/// (for example `beta` below `-delta`, paper eq. 19). Every stable `alpha` is positive:
/// `alpha = 0` puts a root at `z = 1` (`docs/MODEL.md` section 4).
pub fn stable_alphas(checker: &Checker, beta: f64) -> Result<Vec<Interval>> {
    finite("beta", beta)?;
    crate::cancel::poll()?;
    stable_set(checker, Free::Alpha, beta)
}

/// The stable dampings `beta` at fixed stiffness `alpha`, as sorted disjoint open intervals.
///
/// Exact crossing search (module doc). Empty when no damping makes this stiffness stable
/// (`alpha <= 0`, or `alpha` at or above `alpha_max`).
pub fn stable_betas(checker: &Checker, alpha: f64) -> Result<Vec<Interval>> {
    finite("alpha", alpha)?;
    crate::cancel::poll()?;
    stable_set(checker, Free::Beta, alpha)
}

/// The largest stable stiffness at damping `beta`: the supremum of [`stable_alphas`], or
/// `None` if no stiffness is stable there.
pub fn alpha_limit(checker: &Checker, beta: f64) -> Result<Option<f64>> {
    Ok(stable_alphas(checker, beta)?.last().map(|i| i.hi))
}

fn wall(free: Free, s: f64, fixed: f64) -> Wall {
    match free {
        Free::Alpha => Wall {
            alpha: s,
            beta: fixed,
        },
        Free::Beta => Wall {
            alpha: fixed,
            beta: s,
        },
    }
}

fn eval(coeffs: &[f64], z: Complex) -> Complex {
    coeffs
        .iter()
        .rev()
        .fold(Complex::new(0.0, 0.0), |acc, &c| acc * z + c)
}

/// Roots of `S` within this distance of the unit circle are taken as crossings.
///
/// True crossings are simple roots on the circle and come out of the eigenvalue solver within
/// about `1e-13` of it; a tangency (double root) is perturbed by about `sqrt(eps) ~ 1e-8`. A
/// root accepted in error only adds one more piece to test, never a wrong answer, so the
/// band is generous.
const ON_CIRCLE: f64 = 1e-4;

/// Two crossings closer than this (relative) are the same crossing; the piece between them
/// would be too thin to sample.
const SAME_CROSSING: f64 = 1e-13;

/// A piece between crossings narrower than this (relative to its position) is thin: its
/// middle alone does not decide it (see [`pieces`]). Wedge tips near `alpha_max` are
/// `1e-7` to `1e-6` of it wide where the radius is a few `1e-9` below 1; an ordinary loop's
/// pieces are a sizable fraction of their position.
const THIN: f64 = 1e-4;

/// The fractions of a thin piece tried after its middle: both sides of it, nearer and
/// farther.
const THIN_PROBES: [f64; 6] = [0.375, 0.625, 0.25, 0.75, 0.4375, 0.5625];

/// The largest fixed wall parameter (normalized) the searches accept.
///
/// The stable region spans `beta` from `-delta` to a few times `delta` and `alpha` up to a few
/// times `delta` (eq. 22), with `delta <= 1e9`; beyond `1e12` the line misses the region by
/// orders of magnitude, and the crossing polynomial's coefficients (products of the fixed
/// value with order-one terms) no longer resolve anything in `f64`. A property test found
/// spurious intervals at `beta ~ 1e197`.
pub const MAX_FIXED: f64 = 1e12;

/// The paper's loop: the exact crossing search on its closed-form polynomial. A loop with
/// elements: the direct search on its D-decomposition ([`curve_stable_set`]).
fn stable_set(checker: &Checker, free: Free, fixed: f64) -> Result<Vec<Interval>> {
    if checker.is_paper() {
        let [q0, qa, qb] = checker.affine();
        // The paper's plant has a free integrator: Q0(1) = QB(1) = 0 exactly.
        return line_stable_set([&q0, &qa, &qb], free, fixed, true, &|w| {
            checker.is_stable(w)
        });
    }
    curve_stable_set(checker.loop_curve()?, free, fixed, &|w| {
        checker.is_stable(w)
    })
}

/// The stable set on the line of `free` at `fixed` of the D-decomposition `dec`, with
/// `stable` as the one point test per piece between crossings.
///
/// Method: the line's crossings with the curve of walls with a root `e^{i theta}` (scan of
/// the curve, Brent's method in `theta` where the fixed coordinate changes sign) and with the
/// lines of the roots `z = +-1` ([`crate::curve::line_crossings`]), then one point
/// test per piece (see the module documentation for why one suffices). No boundary is traced.
pub(crate) fn curve_stable_set(
    dec: &impl Decomposition,
    free: Free,
    fixed: f64,
    stable: &dyn Fn(&Wall) -> Result<bool>,
) -> Result<Vec<Interval>> {
    finite(free.fixed_name(), fixed)?;
    check_fixed(free, fixed)?;
    let mut cuts = line_crossings(dec, free, fixed);
    if free == Free::Alpha && dec.free_integrator() {
        // the crossing at z = 1 is alpha = 0 exactly; the curve's approach to z = 1 may add
        // a value within rounding of it
        cuts.retain(|v| v.abs() > SAME_CROSSING);
        let at = cuts.partition_point(|v| *v < 0.0);
        cuts.insert(at, 0.0);
    }
    cuts.dedup_by(|b, a| (*b - *a).abs() <= SAME_CROSSING * a.abs().max(b.abs()).max(1.0));
    let set = pieces(stable, free, fixed, cuts)?;
    if !set.is_empty() && set.iter().all(|i| i.lo.is_finite() && i.hi.is_finite()) {
        return Ok(set);
    }
    // An empty set, or a stable piece running to infinity: a crossing next to a pole of the
    // Cramer solution (where `QA` or `QB` vanishes on the circle, as at a moving average's
    // zeros) may have escaped the scan. The crossing polynomial's roots on the circle find
    // every crossing, at the cost of one root-finding of degree 2N.
    let [q0, qa, qb] = dec.affine();
    line_stable_set([&q0, &qa, &qb], free, fixed, dec.free_integrator(), stable)
}

/// Refuses a fixed wall parameter beyond [`MAX_FIXED`].
fn check_fixed(free: Free, fixed: f64) -> Result<()> {
    if fixed.abs() > MAX_FIXED {
        return Err(Error::InvalidParameter {
            name: free.fixed_name(),
            value: fixed,
            expected: format!(
                "the one-dimensional searches accept |value| <= {MAX_FIXED:e} (normalized); no stable wall lies that far out"
            ),
        });
    }
    Ok(())
}

/// The crossing search on the line `q = P + s D` built from `q = Q0 + alpha QA + beta QB`
/// (each lowest power first, of equal length). `free_integrator`: `Q0(1) = QB(1) = 0` exactly,
/// so the crossing through `z = 1` in `alpha` is `alpha = 0` exactly.
fn line_stable_set(
    [q0, qa, qb]: [&[f64]; 3],
    free: Free,
    fixed: f64,
    free_integrator: bool,
    stable: &dyn Fn(&Wall) -> Result<bool>,
) -> Result<Vec<Interval>> {
    check_fixed(free, fixed)?;
    let len = q0.len();
    // P and D, lowest power first; q = P + s D is monic of degree n, D has lower degree.
    let mut p = vec![0.0; len];
    let mut d = vec![0.0; len];
    for i in 0..len {
        let (fix, var) = match free {
            Free::Alpha => (qb[i], qa[i]),
            Free::Beta => (qa[i], qb[i]),
        };
        p[i] = q0[i] + fixed * fix;
        d[i] = var;
    }
    let mut candidates: Vec<f64> = crossings(&p, &d)?.into_iter().map(|c| c.0).collect();
    if free == Free::Alpha && free_integrator {
        // Q0(1) = QB(1) = 0 exactly (docs/MODEL.md section 4), so the crossing through z = 1 is
        // alpha = 0 exactly; the computed one carries rounding of P(1) ~ 1e-16. Put the
        // exact value in its place.
        candidates.retain(|v| v.abs() > SAME_CROSSING);
        let at = candidates.partition_point(|v| *v < 0.0);
        candidates.insert(at, 0.0);
    }
    pieces(stable, free, fixed, candidates)
}

/// The crossings of the line `q = P + s D` (`P` and `D` lowest power first, of equal
/// length): the values `s = -P(z)/D(z)` at the roots `z = e^{i theta}` of
/// `S = P D* - P* D` on the unit circle, as `(s, theta)` with `0 <= theta <= pi`, sorted by
/// `s`, deduplicated.
pub(crate) fn crossings(p: &[f64], d: &[f64]) -> Result<Vec<(f64, f64)>> {
    let n = p.len() - 1;
    // S = P D* - P* D, with X*_i = X_{n-i}; degree 2n.
    let mut s = vec![0.0; 2 * n + 1];
    for i in 0..p.len() {
        for j in 0..p.len() {
            s[i + j] += p[i] * d[n - j] - p[n - i] * d[j];
        }
    }
    let s = &s;
    let scale = s.iter().fold(0.0f64, |m, c| m.max(c.abs()));
    let mut out = Vec::new();
    if scale > 0.0 && scale.is_finite() {
        // Leading and trailing coefficients at rounding level of the largest are zeros that
        // rounding left behind: dropping one moves a root between 0 (or infinity) and a
        // point far off the circle, which cannot be a crossing.
        let tiny = 1e-14 * scale;
        let first = s.iter().position(|c| c.abs() > tiny).unwrap_or(0);
        let last = s.iter().rposition(|c| c.abs() > tiny).unwrap_or(0);
        let trimmed = &s[first..=last];
        if trimmed.len() > 1 {
            for r in poly_roots(trimmed)? {
                let m = r.norm();
                // `m == 0` only guards the division below (a root at 0 is off the circle anyway)
                if (m - 1.0).abs() > ON_CIRCLE || m == 0.0 {
                    continue;
                }
                let z = r / m;
                let dz = eval(d, z);
                // guards the division: where D vanishes exactly, no finite s crosses there
                if dz.norm() == 0.0 {
                    continue;
                }
                let v = -(eval(p, z) / dz).re;
                if v.is_finite() {
                    out.push((v, z.im.atan2(z.re).abs()));
                }
            }
        }
    } else if !scale.is_finite() {
        return Err(Error::Numerical(
            "crossing polynomial has non-finite coefficients".into(),
        ));
    }
    // S vanishes identically when P and D are proportional on the circle; then the crossings
    // at z = +-1 (always roots of S) are the only ones worth adding, and adding them in every
    // case costs nothing.
    for (z, theta) in [
        (Complex::new(1.0, 0.0), 0.0),
        (Complex::new(-1.0, 0.0), std::f64::consts::PI),
    ] {
        let dz = eval(d, z);
        if dz.norm() > 0.0 {
            let v = -(eval(p, z) / dz).re;
            if v.is_finite() {
                out.push((v, theta));
            }
        }
    }
    out.sort_by(|a, b| a.0.total_cmp(&b.0));
    out.dedup_by(|b, a| (b.0 - a.0).abs() <= SAME_CROSSING * a.0.abs().max(b.0.abs()).max(1.0));
    Ok(out)
}

/// Tests one point per piece between crossings and joins the stable pieces.
fn pieces(
    is_stable: &dyn Fn(&Wall) -> Result<bool>,
    free: Free,
    fixed: f64,
    cuts: Vec<f64>,
) -> Result<Vec<Interval>> {
    let stable = |s: f64| is_stable(&wall(free, s, fixed));
    if cuts.is_empty() {
        let all = Interval {
            lo: f64::NEG_INFINITY,
            hi: f64::INFINITY,
        };
        return Ok(if stable(0.0)? { vec![all] } else { Vec::new() });
    }
    // Pieces: (-inf, c0), (c0, c1), ..., (c_last, +inf), each with one sample point.
    let k = cuts.len();
    let mut out: Vec<Interval> = Vec::new();
    let mut previous_stable = false;
    for i in 0..=k {
        let lo = if i == 0 {
            f64::NEG_INFINITY
        } else {
            cuts[i - 1]
        };
        let hi = if i == k { f64::INFINITY } else { cuts[i] };
        let sample = if i == 0 {
            hi - hi.abs().max(1.0)
        } else if i == k {
            lo + lo.abs().max(1.0)
        } else {
            0.5 * (lo + hi)
        };
        let mut now = stable(sample)?;
        // A thin piece (a wedge's tip) whose middle the test cannot call stable may hold
        // walls it calls stable elsewhere: the middle is not where the radius is least when
        // the two edges leave at different rates, and near the band the test's verdict varies
        // from wall to wall. A few more points decide it; a wide piece is decided by its
        // middle alone.
        if !now && lo.is_finite() && hi.is_finite() && hi - lo <= THIN * lo.abs().max(hi.abs()) {
            for f in THIN_PROBES {
                if stable(lo + f * (hi - lo))? {
                    now = true;
                    break;
                }
            }
        }
        match out.last_mut() {
            // Stable on both sides of a cut: the cut was a tangency or a spurious candidate,
            // not a change of stability, so the two pieces are one interval.
            Some(last) if now && previous_stable => last.hi = hi,
            _ if now => out.push(Interval { lo, hi }),
            _ => {}
        }
        previous_stable = now;
    }
    Ok(out)
}

/// The intersection of two sorted lists of disjoint open intervals.
pub(crate) fn intersect(a: &[Interval], b: &[Interval]) -> Vec<Interval> {
    let (mut i, mut j, mut out) = (0, 0, Vec::new());
    while i < a.len() && j < b.len() {
        let lo = a[i].lo.max(b[j].lo);
        let hi = a[i].hi.min(b[j].hi);
        if lo < hi {
            out.push(Interval { lo, hi });
        }
        if a[i].hi < b[j].hi {
            i += 1;
        } else {
            j += 1;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::Plant;
    use crate::stability::{Method, Options, Verdict};

    fn checker(delta: f64, d: f64) -> Checker {
        Checker::new(Plant::new(delta, d).unwrap(), Options::default()).unwrap()
    }

    /// delta = 0, d = 0 at beta = 2 sqrt 2 - 2: the limit is alpha_max = 12 - 8 sqrt 2
    /// (paper Remark 4, docs/MODEL.md section 6).
    #[test]
    fn paper_anchor_d0() {
        let s2 = 2f64.sqrt();
        let c = checker(0.0, 0.0);
        let lim = alpha_limit(&c, 2.0 * s2 - 2.0).unwrap().unwrap();
        assert!((lim - (12.0 - 8.0 * s2)).abs() < 1e-9, "{lim}");
    }

    /// Every interval end is a boundary: stable just inside, not stable just outside, checked
    /// by eigenvalues (an independent method from the Schur-Cohn tests that built them).
    #[test]
    fn ends_are_boundaries() {
        let eig = |delta, d| {
            Checker::new(
                Plant::new(delta, d).unwrap(),
                Options {
                    method: Method::Eigen,
                    ..Options::default()
                },
            )
            .unwrap()
        };
        for &(delta, d) in &[(0.0, 1.0), (0.1, 1.0), (1.0, 1.0), (0.5, 2.5), (3.0, 0.0)] {
            let c = checker(delta, d);
            let e = eig(delta, d);
            for &beta in &[0.0, 0.2, 0.4, 1.0] {
                let set = stable_alphas(&c, beta).unwrap();
                for i in &set {
                    assert!(i.lo >= 0.0, "{delta} {d} {beta} {i:?}");
                    // Inside by 1e-6 of the width: far above the 1e-9 marginal band (a root near
                    // z = 1 moves off the circle in proportion to alpha).
                    for (x, want) in [
                        (i.lo + 1e-6 * (i.hi - i.lo), true),
                        (i.hi * (1.0 - 1e-6), true),
                        (i.hi * (1.0 + 1e-6), false),
                    ] {
                        let v = e.verdict(&Wall { alpha: x, beta }).unwrap();
                        assert_eq!(v == Verdict::Stable, want, "{delta} {d} {beta} {x} {i:?}");
                    }
                }
            }
            for &alpha in &[0.01, 0.05, 0.1] {
                for i in &stable_betas(&c, alpha).unwrap() {
                    let w = (i.hi - i.lo) * 1e-6;
                    for (x, want) in [
                        (i.lo - w, false),
                        (i.lo + w, true),
                        (i.hi - w, true),
                        (i.hi + w, false),
                    ] {
                        let v = e.verdict(&Wall { alpha, beta: x }).unwrap();
                        assert_eq!(v == Verdict::Stable, want, "{delta} {d} {alpha} {x} {i:?}");
                    }
                }
            }
        }
    }

    /// Paper eq. (19): the lowest stable beta as alpha -> 0 is -delta.
    #[test]
    fn lowest_beta_is_minus_delta() {
        for &delta in &[0.1, 0.5, 1.0] {
            let set = stable_betas(&checker(delta, 1.0), 1e-7).unwrap();
            let lo = set[0].lo;
            assert!((lo + delta).abs() < 1e-4, "{delta}: {lo}");
        }
    }

    /// Far below -delta no stiffness is stable; no alpha <= 0 ever is.
    #[test]
    fn empty_sets() {
        let c = checker(0.1, 1.0);
        assert!(stable_alphas(&c, -1.0).unwrap().is_empty());
        assert!(alpha_limit(&c, -1.0).unwrap().is_none());
        assert!(stable_betas(&c, 0.0).unwrap().is_empty());
        assert!(stable_betas(&c, -0.1).unwrap().is_empty());
        assert!(stable_betas(&c, 10.0).unwrap().is_empty());
        assert!(stable_alphas(&c, f64::NAN).is_err());
    }
}
