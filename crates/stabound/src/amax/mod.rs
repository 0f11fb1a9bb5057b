//! The maximum stable stiffness `alpha_max(delta, d)` and the damping `beta` where it is
//! reached (paper Section VII, `docs/MODEL.md` section 5), the path of maximum stiffness (Fig. 5,
//! dashed), `alpha_max` against `delta` (Fig. 10) and the large-delta slope `g(d)` of eq. (22).
//!
//! # Method
//!
//! The stable region in the `(alpha, beta)` plane is bounded by pieces of three curves
//! (D-decomposition, `docs/MODEL.md` section 4): the line `alpha = 0` (root `z = 1`), the line of
//! walls with the root `z = -1` ([`crate::poly::CharPoly::line_minus_one`]), and the parametric curve of
//! walls with a root `e^{i theta}`, `0 < theta < pi` ([`crate::poly::CharPoly::wall_on_circle`]). The
//! rightmost point of the region is therefore either a smooth point of the curve where
//! `d alpha / d theta = 0`, or a corner where the curve meets the `z = -1` line (or, with beta
//! limits, the line `beta = beta_min` or `beta = beta_max`). [`alpha_max`] finds every such
//! candidate directly:
//!
//! 1. a coarse scan of `theta` with `32 (n + 2)` points, enough for the oscillating factor
//!    `e^{i (n+2) theta}` of the curve (16 samples per oscillation);
//! 2. Brent's root finder (R. P. Brent, *Algorithms for Minimization without Derivatives*,
//!    1973, ch. 4) on the exact derivative `d alpha / d theta` where it changes sign from `+`
//!    to `-`, and on the distance to the `z = -1` line (and to the beta limits) where that
//!    changes sign;
//! 3. the candidates sorted by `alpha`, largest first; the first one that has stable points
//!    immediately to its left (Schur-Cohn tests a relative `1e-8` away) is on the stability
//!    boundary and is the answer. Points of the curve have a root on the circle, so a
//!    candidate with stable neighbours is a boundary point of the stable region, and the
//!    rightmost boundary point is among the candidates.
//!
//! No boundary is traced and nothing is scanned in two dimensions: one `alpha_max` costs a
//! few hundred evaluations of the curve and a handful of Schur-Cohn tests.
//!
//! The search is written once against the D-decomposition of an affine polynomial
//! `q = Q0 + alpha QA + beta QB` (`crate::curve::Decomposition`) and serves every loop
//! ([`alpha_max`] of any loop): the paper's loop through its closed-form curve and
//! the rotating scan above, a loop with elements through its own polynomial (curve by
//! Cramer's rule, exact derivative from the polynomials' derivatives, a scan of
//! `32 (degree + 1)` intervals refined around roots of `Q0` and `QA` near the circle, but
//! the free integrator's `z = 1`, where the curve ends regularly at `theta = 0`). A
//! loop with elements has two more kinds of candidate: where two branches of the curve cross
//! (two root pairs on the circle at once; behind a velocity filter the region's rightmost
//! point can be such a wedge's tip: crossings of the scanned polyline refined by Newton's
//! method with the exact derivatives, or, where Newton's method does not converge (a
//! stretch beside a pole of the curve, bent far from its chord), by Brent's method along a
//! coordinate in which both stretches are monotone), and without a free integrator the
//! corners of the vertical `z = +1` line. Every tolerance is relative: Brent's in `theta` and the
//! neighbours' distance relative to the candidate's size, so a region of any size is
//! searched alike. For a loop the scan is also halved where the chord between two samples
//! points against the curve's exact tangent (the curve went out and back between them; the
//! intervals with the largest chords first, so that rounding noise near `z = 1` cannot spend
//! the halvings' budget), and a candidate is also confirmed by neighbours a step relative to
//! each coordinate's own size away in a fan of directions (a thin wedge, or a sliver a
//! million times longer in `beta` than in `alpha` behind a filter pole near `z = 1`), and as
//! a last resort by the stable dampings on the line just left of it. A candidate above the
//! answer confirmed only at the farther step (`1e-6`), with all its neighbours right of the
//! answer, proves the answer is not the rightmost point and replaces it (a wedge's tip whose
//! edges the nearest fans miss, behind a slow second-order filter); an answer with a
//! strictly stable wall right of it at its damping is refused. Where nothing is confirmed,
//! the rightmost point of the traced boundary with stable walls beside it is the answer, and
//! [`AmaxReport::fallback`] says so. Last, a loop's answer must hold by the closed loop's
//! state-matrix eigenvalues (a strictly stable wall a relative `1e-6` below it, at or beside
//! its damping): near a cluster of roots at `z = 1` the expanded polynomial's rounding
//! places the tip too far, and the answer is lowered along its damping to the stiffest
//! wall the eigenvalues call stable, or refused (`docs/MODEL.md` section 8).
//!
//! [`amax_report`] adds the stable stiffnesses at the optimum's damping and the best wall
//! with `beta >= 0`; [`margin_alpha_max`] the best wall whose whole range from a margin
//! fraction up to it is stable at its damping.

mod curve;
pub(crate) mod direct;
mod margin;
pub(crate) mod report;
mod series;
mod table;

pub use margin::{MarginWall, margin_wall, recommend};
pub use report::{
    AmaxReport, HOLD_STEP, alpha_max_with_marginal, amax_report, margin_alpha_max, marginal_below,
};
pub use series::{
    AmaxPoint, DEFAULT_SLOPE_RANGE, MAX_ROWS, MAX_STREAM_ROWS, SlopeFit, alpha_max_each,
    alpha_max_each_with_marginal, amax_series, max_stiffness_path, slope_g,
};
pub(crate) use table::RobustNode;
pub use table::{
    AmaxTable, CUSHION, GUARD_ULPS, Interpolation, Precision, RowLowering, TableOptions, amax_table,
};

use crate::elements::Loop;
use crate::error::{Error, Result};
use crate::params::Plant;
use curve::PaperCurve;

/// The default refinement tolerance in `theta` of [`AmaxOptions`].
///
/// `1e-12` rad in `theta`: Brent's method converges superlinearly, so the final step is far
/// below this; at a corner the relative error of `alpha_max` is at most about `(n + 2) tol`
/// (`alpha` varies like `e^{i (n+2) theta}`), below `1e-10` for delays up to about 100
/// samples, and at a smooth maximum it is quadratic in the `theta` error.
pub const DEFAULT_THETA_TOL: f64 = 1e-12;

/// The accepted range of the refinement tolerance in `theta`, in radians: below `1e-15` the
/// step is under the rounding of `theta` near `pi`; above `1e-2` a candidate can be off by
/// more than the region's features at long delays.
pub const THETA_TOL_RANGE: (f64, f64) = (1e-15, 1e-2);

/// Options of [`alpha_max`], valid by construction.
///
/// ```
/// use stabound::amax::AmaxOptions;
///
/// // firmware that cannot render negative damping
/// let opts = AmaxOptions::default().with_beta_limits(Some(0.0), None)?;
/// assert_eq!(opts.beta_min(), Some(0.0));
/// assert!(AmaxOptions::new(1.0).is_err()); // theta tolerance outside [1e-15, 1e-2]
/// # Ok::<(), stabound::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AmaxOptions {
    theta_tol: f64,
    beta_min: Option<f64>,
    beta_max: Option<f64>,
}

impl Default for AmaxOptions {
    fn default() -> Self {
        Self {
            theta_tol: DEFAULT_THETA_TOL,
            beta_min: None,
            beta_max: None,
        }
    }
}

impl AmaxOptions {
    /// Options with refinement tolerance `theta_tol` (radians, in [`THETA_TOL_RANGE`]; see
    /// [`DEFAULT_THETA_TOL`]) and no beta limits.
    pub fn new(theta_tol: f64) -> Result<Self> {
        let (lo, hi) = THETA_TOL_RANGE;
        crate::params::in_range("theta tolerance", theta_tol, lo, hi)?;
        Ok(Self {
            theta_tol,
            ..Self::default()
        })
    }

    /// The same options with the smallest and largest admissible virtual damping `beta`
    /// (`None`: no limit; e.g. `Some(0.0)` as the smallest when the firmware cannot render
    /// negative damping). Both finite, `beta_min <= beta_max`.
    pub fn with_beta_limits(self, beta_min: Option<f64>, beta_max: Option<f64>) -> Result<Self> {
        if let Some(b) = beta_min {
            crate::params::finite("beta_min", b)?;
        }
        if let Some(b) = beta_max {
            crate::params::finite("beta_max", b)?;
        }
        if let (Some(lo), Some(hi)) = (beta_min, beta_max)
            && lo > hi
        {
            return Err(Error::InvalidRequest(format!(
                "beta_min = {lo} is above beta_max = {hi}; give beta_min <= beta_max"
            )));
        }
        Ok(Self {
            beta_min,
            beta_max,
            ..self
        })
    }

    /// Refinement tolerance in `theta`, radians.
    pub fn theta_tol(&self) -> f64 {
        self.theta_tol
    }

    /// Smallest admissible `beta`, if limited.
    pub fn beta_min(&self) -> Option<f64> {
        self.beta_min
    }

    /// Largest admissible `beta`, if limited.
    pub fn beta_max(&self) -> Option<f64> {
        self.beta_max
    }
}

/// The rightmost point of the stable region: the largest stable stiffness and the damping
/// where it is reached.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Amax {
    /// Supremum of the stable `alpha` over all admissible `beta`.
    pub alpha_max: f64,
    /// The `beta` at which `alpha_max` is reached.
    pub beta_at_max: f64,
}

/// What bounds the stable region at its rightmost point.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
pub enum AmaxKind {
    /// A smooth point of the curve of complex roots on the circle (vertical tangent).
    Smooth,
    /// The corner where that curve meets the line of walls with the root `z = -1`.
    MinusOneCorner,
    /// On a beta limit (`beta_min` or `beta_max`).
    BetaLimit,
    /// Where two branches of the curve meet: two pairs of roots on the circle at once (the
    /// tip of a wedge of the region, as behind a velocity filter; the paper's loop has none).
    CurveCorner,
}

/// [`Amax`] with the piece of boundary it was found on and the frequency of the critical
/// root.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct AmaxDetail {
    /// The result.
    pub amax: Amax,
    /// The kind of boundary point.
    pub kind: AmaxKind,
    /// Angle `theta` of the critical root `e^{i theta}` (`pi` for a root at `z = -1`).
    pub theta: f64,
}

/// `alpha_max` and the `beta` where it is reached, for the loop `lp` (a [`Plant`] for the
/// paper's loop), over all `beta` or within the limits of `opts`.
///
/// Method: for the paper's loop, direct search for the rightmost point of the stable region
/// among the smooth maxima of the D-decomposition curve and its corners with the `z = -1`
/// line and the beta limits (see the [module documentation](self); D-decomposition: Neimark
/// 1948, as used in the paper's Section V; refinement by Brent's method). For a loop with
/// elements, the same pieces of the loop's own polynomial (`docs/MODEL.md` section 8).
///
/// ```
/// use stabound::elements::Loop;
/// use stabound::filter::VelocityFilter;
/// use stabound::params::Plant;
/// use stabound::{AmaxOptions, alpha_max};
///
/// let plant = Plant::new(0.2, 1.0)?;
/// let bare = alpha_max(&plant, &AmaxOptions::default())?;
/// let filtered = Loop::new(plant).with_filter(VelocityFilter::low_pass(0.9)?)?;
/// // a velocity filter's lag lowers the largest stable stiffness
/// assert!(alpha_max(&filtered, &AmaxOptions::default())?.alpha_max < bare.alpha_max);
/// # Ok::<(), stabound::Error>(())
/// ```
///
/// # Errors
///
/// [`Error::InvalidParameter`]/[`Error::InvalidRequest`] for bad options or beta limits that
/// leave no stable wall. Where the direct search confirms no candidate, the rightmost point
/// of the loop's traced boundary is the answer ([`amax_report`] says so in its `fallback`);
/// [`Error::Numerical`] when a stable wall lies right of that point (the region runs
/// beyond the traced boundary; beta limits that cut it short give an answer), the
/// beta limits' refusal when no clearly stable wall is found within them; the same when no
/// wall a relative `1e-6` below the answer, nor on its damping down to a quarter of it, is
/// strictly stable by the state matrix's eigenvalues.
pub fn alpha_max(lp: impl Into<Loop>, opts: &AmaxOptions) -> Result<Amax> {
    let lp = lp.into();
    if lp.is_paper() {
        alpha_max_detail(lp.plant(), opts).map(|d| d.amax)
    } else {
        report::loop_alpha_max(&lp, opts)
    }
}

/// As [`alpha_max`], also saying which piece of the boundary holds the maximum.
pub fn alpha_max_detail(plant: &Plant, opts: &AmaxOptions) -> Result<AmaxDetail> {
    search(plant, opts, curve::ROTOR_RESEED)
}

/// [`alpha_max_detail`] with the scan's `e^{i theta}` re-seeded from `sin_cos` every
/// `reseed` samples (`1`: every sample).
fn search(plant: &Plant, opts: &AmaxOptions, reseed: usize) -> Result<AmaxDetail> {
    let curve = PaperCurve::new(plant, reseed);
    match direct::rightmost(&curve, opts) {
        Some(c) => Ok(detail(c)),
        None => Err(no_rightmost(plant, opts)),
    }
}

/// [`search`] on `plant`'s curve already built (whose polynomial its caller uses again).
pub(crate) fn search_on(
    curve: &PaperCurve,
    plant: &Plant,
    opts: &AmaxOptions,
) -> Result<AmaxDetail> {
    match direct::rightmost(curve, opts) {
        Some(c) => Ok(detail(c)),
        None => Err(no_rightmost(plant, opts)),
    }
}

/// Why [`search`] has no answer: the cancellation if the search was cancelled (it confirms
/// nothing then), else the beta limits' refusal, or no rightmost point confirmed.
#[cold]
fn no_rightmost(plant: &Plant, opts: &AmaxOptions) -> Error {
    if let Err(cancelled) = crate::cancel::poll() {
        return cancelled;
    }
    let (bmin, bmax) = (
        opts.beta_min.unwrap_or(f64::NEG_INFINITY),
        opts.beta_max.unwrap_or(f64::INFINITY),
    );
    if opts.beta_min.is_some() || opts.beta_max.is_some() {
        Error::InvalidRequest(format!(
            "no stable wall has beta in [{bmin}, {bmax}] for delta = {}, d = {}; widen the beta limits (the stable region reaches down to beta = -delta)",
            plant.delta(),
            plant.d()
        ))
    } else {
        Error::Numerical(format!(
            "no rightmost point of the stable region could be confirmed for delta = {}, d = {}",
            plant.delta(),
            plant.d()
        ))
    }
}

/// The seed of the bisection engine's grid where the stable region is smaller than its
/// cells ([`crate::boundary::RightmostWall`]): this plant's [`alpha_max`] with the default
/// options.
impl crate::boundary::RightmostWall for Plant {
    fn rightmost_wall(&self) -> Result<(f64, f64)> {
        alpha_max(*self, &AmaxOptions::default()).map(|m| (m.alpha_max, m.beta_at_max))
    }
}

/// Relative step right of the traced boundary's answer at which [`traced_rightmost`] looks
/// for a clearly stable wall at any damping: `1e-3`, far above the traced polyline's
/// resolution near its rightmost point, so a stable wall there is the region's own.
const BEYOND_STEP: f64 = 1e-3;

/// The rightmost point of a traced boundary of `lp` within the beta limits of `opts`, and a
/// sentence saying where it comes from: the fallback where the direct search confirms no
/// candidate.
///
/// Method: the exact boundary ([`crate::boundary::exact`], which itself falls back to the
/// bisection engine where its pieces do not close), or the bisection engine
/// ([`crate::boundary::bisect_alpha_beta`]) where the exact engine refuses; the largest
/// `alpha` over the polyline's vertices inside the beta limits and its edges' crossings of
/// them that have strictly stable walls a relative `1e-8` or `1e-6` to their left (the
/// direct search's neighbour tests), one of them clearly stable (every root inside the
/// marginal band, [`direct::clearly_stable_near`]). Accurate to the boundary's tolerance
/// and the spacing of its vertices (`Boundary::tol`), not to the direct search's.
///
/// # Errors
///
/// [`Error::Numerical`] (or [`Error::InvalidRequest`] with beta limits) when the polyline
/// has no such vertex of positive stiffness inside the limits, or the bisection engine
/// finds no stable point; [`Error::Numerical`] when a clearly stable wall lies a relative
/// [`BEYOND_STEP`] right of the polyline's rightmost point (the region runs beyond it).
pub(crate) fn traced_rightmost(lp: &Loop, opts: &AmaxOptions) -> Result<(Amax, String)> {
    use crate::boundary::{BisectOptions, ExactOptions, bisect_alpha_beta, exact};
    let (boundary, engine) = match exact(*lp, &ExactOptions::default()) {
        Ok(b) => {
            let engine = match &b.fallback {
                None => "the exact boundary".to_string(),
                Some(why) => {
                    format!("the bisection engine's boundary (the exact one did not close: {why})")
                }
            };
            (b, engine)
        }
        Err(why) => (
            // the bisection engine's grid holding no stable point is the direct search's
            // finding too: the refusal says so in terms of the request (its beta limits),
            // not of the engine's default ranges
            bisect_alpha_beta(*lp, &BisectOptions::default())
                .map_err(|_| report::no_candidate(opts))?,
            format!("the bisection engine's boundary (the exact engine refused: {why})"),
        ),
    };
    let (bmin, bmax) = (
        opts.beta_min.unwrap_or(f64::NEG_INFINITY),
        opts.beta_max.unwrap_or(f64::INFINITY),
    );
    let pts = &boundary.points;
    let mut offers: Vec<Amax> = Vec::with_capacity(pts.len());
    let mut offer = |alpha: f64, beta: f64| {
        if alpha.is_finite() && alpha > 0.0 && (bmin..=bmax).contains(&beta) {
            offers.push(Amax {
                alpha_max: alpha,
                beta_at_max: beta,
            });
        }
    };
    for (i, p) in pts.iter().enumerate() {
        offer(p.x, p.y);
        let q = &pts[(i + 1) % pts.len()];
        for lim in [opts.beta_min, opts.beta_max].into_iter().flatten() {
            if (p.y > lim) != (q.y > lim) {
                // the edge's crossing of the limit (its ends on both sides: no division by 0)
                let t = (lim - p.y) / (q.y - p.y);
                offer(p.x + t * (q.x - p.x), lim);
            }
        }
    }
    // The largest vertex with strictly stable walls beside it, by the direct search's own
    // neighbour tests: a traced polyline can carry pieces of the curve that do not bound the
    // region (an excursion near a near-singular Cramer determinant), whose vertices have no
    // stable wall near them and are passed over.
    offers.sort_by(|x, y| y.alpha_max.total_cmp(&x.alpha_max));
    let curve = crate::curve::LoopCurve::new(lp)?;
    let found = offers
        .into_iter()
        .find(|m| {
            let (a, b) = (m.alpha_max, m.beta_at_max);
            direct::has_stable_wall_near(&curve, a, b, bmin, bmax)
                && direct::clearly_stable_near(&curve, a, b, bmin, bmax)
        })
        .ok_or_else(|| report::no_candidate(opts))?;
    // Every wall right of the rightmost point is unstable: a clearly stable wall a relative
    // `BEYOND_STEP` right of the traced answer, at any damping within the limits, proves
    // that the region runs past the traced boundary (as a sliver along a filter pole near
    // `z = 1` runs out to dampings beyond the boundary's reach).
    let beyond = found.alpha_max * (1.0 + BEYOND_STEP);
    if let Some(beta) = direct::clearly_stable_on_line(&curve, beyond, bmin, bmax) {
        return Err(Error::Numerical(format!(
            "the direct search on the loop's curve confirmed no rightmost point, and the rightmost point of {engine} (alpha = {}, beta = {}) is not the region's: the wall alpha = {beyond}, beta = {beta} right of it is stable, the region runs beyond the traced boundary; give beta limits that cut it short of there",
            found.alpha_max, found.beta_at_max
        )));
    }
    let note = format!(
        "the direct search on the loop's curve confirmed no rightmost point; alpha_max is the rightmost point of {engine} with stable walls beside it (tolerance {}), below the region's tip by at most the polyline's resolution there",
        boundary.tol
    );
    Ok((found, note))
}

fn detail(c: direct::Candidate) -> AmaxDetail {
    AmaxDetail {
        amax: Amax {
            alpha_max: c.alpha,
            beta_at_max: c.beta,
        },
        kind: c.kind,
        theta: c.theta,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::Wall;
    use crate::poly::PaperPoly;
    use approx::assert_relative_eq;
    use curve::Curve;

    fn am(delta: f64, d: f64) -> Amax {
        alpha_max(Plant::new(delta, d).unwrap(), &AmaxOptions::default()).unwrap()
    }

    #[test]
    fn anchor_d0_delta0_exact() {
        let a = am(0.0, 0.0);
        let s2 = 2f64.sqrt();
        assert_relative_eq!(a.alpha_max, 12.0 - 8.0 * s2, max_relative = 1e-10);
        // beta is found from the root of d alpha/d theta: accurate to about 1e-8 relative.
        assert_relative_eq!(a.beta_at_max, 2.0 * s2 - 2.0, max_relative = 1e-8);
    }

    #[test]
    fn double_root_corner_is_confirmed() {
        // d = 0, delta = 11.25: the maximum is the corner where the z = -1 line meets the
        // D-decomposition curve, a double root at z = -1 that no test resolves 1e-8 inside.
        // The candidate must still be confirmed, and be the true corner: eigenvalues a
        // relative 1e-5 to its left are stable and 1e-5 to its right are not.
        let plant = Plant::new(11.25, 0.0).unwrap();
        let a = alpha_max(plant, &AmaxOptions::default()).unwrap();
        let checker = crate::stability::Checker::new(
            plant,
            crate::stability::Options {
                method: crate::stability::Method::Eigen,
                ..Default::default()
            },
        )
        .unwrap();
        let h = 1e-5 * a.alpha_max;
        let left = Wall::new(a.alpha_max - h, a.beta_at_max).unwrap();
        let right = Wall::new(a.alpha_max + h, a.beta_at_max).unwrap();
        assert!(checker.is_stable(&left).unwrap());
        assert!(!checker.is_stable(&right).unwrap());
    }

    #[test]
    fn anchor_d1_delta0() {
        let a = am(0.0, 1.0);
        assert!((a.alpha_max - 0.1445).abs() < 5e-5, "{a:?}");
    }

    /// Paper Section VIII: d = 1, delta = 0, 0.1, 1; 75 % of alpha_max and beta at the max.
    #[test]
    fn section_viii() {
        for (delta, alpha75, beta) in [
            (0.0, 0.108, 0.425),
            (0.1, 0.149, 0.416),
            (1.0, 0.656, 0.388),
        ] {
            let a = am(delta, 1.0);
            assert!(
                (0.75 * a.alpha_max - alpha75).abs() <= 5e-4,
                "{delta}: {a:?}"
            );
            assert!((a.beta_at_max - beta).abs() <= 5e-4, "{delta}: {a:?}");
        }
    }

    #[test]
    fn derivative_matches_finite_difference() {
        let plant = Plant::new(0.7, 2.3).unwrap();
        let poly = PaperPoly::new(&plant);
        let curve = Curve::new(&poly);
        for &t in &[0.2, 0.9, 1.7, 2.8] {
            let p = curve.eval(t).unwrap();
            let w = poly.wall_on_circle(t).unwrap();
            assert_relative_eq!(p.alpha, w.alpha, max_relative = 1e-12);
            assert_relative_eq!(p.beta, w.beta, max_relative = 1e-12);
            let h = 1e-6;
            let (a, b) = (curve.eval(t + h).unwrap(), curve.eval(t - h).unwrap());
            // central difference: error O(h^2) ~ 1e-12 times the third derivative
            assert_relative_eq!(
                p.dalpha,
                (a.alpha - b.alpha) / (2.0 * h),
                max_relative = 1e-6,
                epsilon = 1e-8
            );
            assert_relative_eq!(
                p.dbeta,
                (a.beta - b.beta) / (2.0 * h),
                max_relative = 1e-6,
                epsilon = 1e-8
            );
        }
    }

    /// The rotation only moves the scan's samples by rounding: the results are the same bits
    /// as with every sample from `sin_cos`, over delays short and long, with and without beta
    /// limits.
    #[test]
    fn rotated_scan_gives_the_same_bits() {
        let limited = AmaxOptions::default()
            .with_beta_limits(Some(0.0), Some(0.3))
            .unwrap();
        for opts in [AmaxOptions::default(), limited] {
            for d in [0.0, 0.25, 1.0, 4.0, 30.0] {
                for i in 0..60 {
                    let delta = 0.37 * f64::from(i) + 0.01 * f64::from(i * i);
                    let plant = Plant::new(delta, d).unwrap();
                    let rotated = search(&plant, &opts, curve::ROTOR_RESEED);
                    let direct = search(&plant, &opts, 1);
                    match (rotated, direct) {
                        (Ok(r), Ok(e)) => {
                            // bit equality is the claim: the same output bytes
                            assert!(r.amax.alpha_max.to_bits() == e.amax.alpha_max.to_bits());
                            assert!(r.amax.beta_at_max.to_bits() == e.amax.beta_at_max.to_bits());
                            assert_eq!(r.kind, e.kind);
                        }
                        (Err(_), Err(_)) => {}
                        (r, e) => panic!("({delta}, {d}): {r:?} vs {e:?}"),
                    }
                }
            }
        }
    }

    /// The fallback's answer, the traced boundary's rightmost point, is the direct search's
    /// to the boundary's tolerance, with and without a beta limit that cuts the region.
    #[test]
    fn traced_rightmost_matches_the_direct_search() {
        use crate::filter::VelocityFilter;
        let lp = Loop::new(Plant::new(1.0, 1.0).unwrap())
            .with_filter(VelocityFilter::low_pass(0.9).unwrap())
            .unwrap();
        let free = AmaxOptions::default();
        let direct = alpha_max(lp, &free).unwrap();
        let limited = free.with_beta_limits(Some(0.0), None).unwrap();
        let direct_limited = alpha_max(lp, &limited).unwrap();
        assert!(direct_limited.alpha_max < direct.alpha_max);
        for (opts, want) in [(free, direct), (limited, direct_limited)] {
            let (a, why) = traced_rightmost(&lp, &opts).unwrap();
            assert!(why.contains("exact boundary"), "{why}");
            // the polyline is within tol of the curve (1e-9), its vertices on it: the
            // rightmost vertex is within a few tol of the true maximum (the chord's sagitta
            // at a smooth maximum is far below tol)
            assert!(
                (a.alpha_max - want.alpha_max).abs() <= 1e-8,
                "{a:?} vs {want:?}"
            );
            assert!(a.beta_at_max >= opts.beta_min().unwrap_or(f64::NEG_INFINITY));
        }
    }

    #[test]
    fn beta_limits() {
        let plant = Plant::new(5.0, 0.0).unwrap();
        let free = alpha_max(plant, &AmaxOptions::default()).unwrap();
        assert!(free.beta_at_max < 0.0, "{free:?}");
        let opts = AmaxOptions::default()
            .with_beta_limits(Some(0.0), None)
            .unwrap();
        let lim = alpha_max(plant, &opts).unwrap();
        assert!(lim.alpha_max < free.alpha_max);
        assert!(lim.beta_at_max.abs() < 1e-12, "{lim:?}");
        // Limits that exclude every stable wall.
        let opts = AmaxOptions::default()
            .with_beta_limits(Some(1e3), None)
            .unwrap();
        assert!(matches!(
            alpha_max(plant, &opts),
            Err(Error::InvalidRequest(_))
        ));
        assert!(
            AmaxOptions::default()
                .with_beta_limits(Some(1.0), Some(0.0))
                .is_err()
        );
    }
}
