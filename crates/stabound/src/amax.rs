//! The maximum stable stiffness `alpha_max(delta, d)` and the damping `beta` where it is
//! reached (paper Section VII, `MATH.md` section 5), the path of maximum stiffness (Fig. 5,
//! dashed), `alpha_max` against `delta` (Fig. 10) and the large-delta slope `g(d)` of eq. (22).
//!
//! # Method
//!
//! The stable region in the `(alpha, beta)` plane is bounded by pieces of three curves
//! (D-decomposition, `MATH.md` section 4): the line `alpha = 0` (root `z = 1`), the line of
//! walls with the root `z = -1` ([`CharPoly::line_minus_one`]), and the parametric curve of
//! walls with a root `e^{i theta}`, `0 < theta < pi` ([`CharPoly::wall_on_circle`]). The
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

use std::f64::consts::PI;

use rayon::prelude::*;
use serde::Serialize;

use crate::error::{Error, Result};
use crate::params::{Plant, Wall};
use crate::poly::{CharPoly, Complex, MAX_COEFFS};
use crate::stability::schur_cohn;

/// The default refinement tolerance of [`AmaxOptions::tol`].
///
/// `1e-12` rad in `theta`: Brent's method converges superlinearly, so the final step is far
/// below this; at a corner the relative error of `alpha_max` is at most about `(n + 2) tol`
/// (`alpha` varies like `e^{i (n+2) theta}`), below `1e-10` for delays up to about 100
/// samples, and at a smooth maximum it is quadratic in the `theta` error.
pub const DEFAULT_TOL: f64 = 1e-12;

/// Options of [`alpha_max`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AmaxOptions {
    /// Refinement tolerance in `theta` (radians), in `[1e-15, 1e-2]`; see [`DEFAULT_TOL`].
    /// Larger values are faster and less accurate.
    pub tol: f64,
    /// Smallest admissible virtual damping `beta` (e.g. `Some(0.0)` when the firmware cannot
    /// render negative damping); `None` for no limit.
    pub beta_min: Option<f64>,
    /// Largest admissible virtual damping `beta`; `None` for no limit.
    pub beta_max: Option<f64>,
}

impl Default for AmaxOptions {
    fn default() -> Self {
        Self {
            tol: DEFAULT_TOL,
            beta_min: None,
            beta_max: None,
        }
    }
}

impl AmaxOptions {
    /// Checks the tolerance and the beta limits (finite, `beta_min <= beta_max`).
    pub fn validate(&self) -> Result<()> {
        crate::params::in_range("tol", self.tol, 1e-15, 1e-2)?;
        if let Some(b) = self.beta_min {
            crate::params::finite("beta-min", b)?;
        }
        if let Some(b) = self.beta_max {
            crate::params::finite("beta-max", b)?;
        }
        if let (Some(lo), Some(hi)) = (self.beta_min, self.beta_max)
            && lo > hi
        {
            return Err(Error::InvalidRequest(format!(
                "beta-min = {lo} is above beta-max = {hi}; give beta-min <= beta-max"
            )));
        }
        Ok(())
    }
}

/// The rightmost point of the stable region: the largest stable stiffness and the damping
/// where it is reached.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Amax {
    /// Supremum of the stable `alpha` over all admissible `beta`.
    pub alpha_max: f64,
    /// The `beta` at which `alpha_max` is reached.
    pub beta_at_max: f64,
}

/// What bounds the stable region at its rightmost point.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum AmaxKind {
    /// A smooth point of the curve of complex roots on the circle (vertical tangent).
    Smooth,
    /// The corner where that curve meets the line of walls with the root `z = -1`.
    MinusOneCorner,
    /// On a beta limit (`beta_min` or `beta_max`).
    BetaLimit,
}

/// [`Amax`] with the piece of boundary it was found on and the frequency of the critical
/// root.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct AmaxDetail {
    /// The result.
    pub amax: Amax,
    /// The kind of boundary point.
    pub kind: AmaxKind,
    /// Angle `theta` of the critical root `e^{i theta}` (`pi` for a root at `z = -1`).
    pub theta: f64,
}

/// A point of the D-decomposition curve with the derivatives along `theta`.
#[derive(Debug, Clone, Copy)]
struct CurvePoint {
    alpha: f64,
    beta: f64,
    dalpha: f64,
    /// Checked against finite differences in the tests (with `dalpha`, same formula).
    #[cfg_attr(not(test), allow(dead_code))]
    dbeta: f64,
}

/// The curve of walls with a root `e^{i theta}` and its exact derivative.
struct Curve {
    k: f64,
    c: f64,
    m: [f64; 3],
}

impl Curve {
    fn new(poly: &CharPoly) -> Self {
        let disc = poly.discretization();
        // The same M(z) = m2 z^2 + m1 z + m0 as CharPoly (N0 z + N1, MATH.md section 3),
        // needed here with its derivative.
        let m2 = disc.g0x;
        let m1 = disc.p1 * disc.g0v - disc.c * disc.g0x + disc.g1x;
        let m0 = disc.p1 * disc.g1v - disc.c * disc.g1x;
        Self {
            k: (disc.n + 2) as f64,
            c: disc.c,
            m: [m0, m1, m2],
        }
    }

    /// `alpha z + beta (z - 1) = W(z)`, `W = -z^k (z - 1)(z - c) / M(z)` on `z = e^{i theta}`
    /// (as [`CharPoly::wall_on_circle`]), with `dW/dtheta = i z W (k/z + 1/(z-1) + 1/(z-c) -
    /// M'/M)`.
    fn eval(&self, theta: f64) -> Option<CurvePoint> {
        let (s, co) = theta.sin_cos();
        if s <= 0.0 {
            return None;
        }
        self.eval_at(theta, Complex::new(co, s))
    }

    /// The end of the curve at `theta = pi` (`z = -1`, a double root there). `Im W` and
    /// `sin theta` both vanish; by l'Hopital `Im W / sin theta -> -d(Im W)/d theta`. The curve
    /// is symmetric about `theta = pi`, so `d alpha / d theta = 0` there.
    fn eval_end(&self) -> Option<CurvePoint> {
        self.eval_at(PI, Complex::new(-1.0, 0.0))
    }

    fn eval_at(&self, theta: f64, z: Complex) -> Option<CurvePoint> {
        let (s, co) = (z.im, z.re);
        let [m0, m1, m2] = self.m;
        let mz = (z * m2 + m1) * z + m0;
        let dm = z * (2.0 * m2) + m1;
        // As in CharPoly::wall_on_circle: a modulus of M this small is a zero of M.
        let norm = mz.norm();
        if norm.is_nan() || norm <= 1e-300 {
            return None;
        }
        let zk = Complex::from_polar(1.0, self.k * theta);
        let zm1 = z - 1.0;
        let zmc = z - self.c;
        let w = -zk * zm1 * zmc / mz;
        let logd = Complex::new(self.k, 0.0) / z + zm1.inv() + zmc.inv() - dm / mz;
        let dw = w * logd * z * Complex::new(0.0, 1.0);
        let (sigma, dsigma) = if s > 0.0 {
            (w.im / s, (dw.im * s - w.im * co) / (s * s))
        } else {
            // theta = pi: sigma by l'Hopital; its derivative is 0 by symmetry.
            (-dw.im, 0.0)
        };
        let beta = sigma * co - w.re;
        let alpha = sigma - beta;
        let dbeta = dsigma * co - sigma * s - dw.re;
        let dalpha = dsigma - dbeta;
        let p = CurvePoint {
            alpha,
            beta,
            dalpha,
            dbeta,
        };
        if alpha.is_finite() && beta.is_finite() && dalpha.is_finite() && dbeta.is_finite() {
            Some(p)
        } else {
            None
        }
    }
}

/// Brent's root finder (zeroin; Brent 1973, ch. 4) for `f` on `[a, b]` with `f(a) f(b) <= 0`.
fn brent(mut f: impl FnMut(f64) -> f64, mut a: f64, mut b: f64, tol: f64) -> f64 {
    let mut fa = f(a);
    let mut fb = f(b);
    // Exact zeros on purpose (as in zeroin): an end point that is a root to the last bit ends
    // the search; anything else is bracketed and refined to `tol`.
    if fa == 0.0 {
        return a;
    }
    if fb == 0.0 {
        return b;
    }
    let mut c = a;
    let mut fc = fa;
    let mut d = b - a;
    let mut e = d;
    for _ in 0..200 {
        if (fb > 0.0) == (fc > 0.0) {
            c = a;
            fc = fa;
            d = b - a;
            e = d;
        }
        if fc.abs() < fb.abs() {
            a = b;
            b = c;
            c = a;
            fa = fb;
            fb = fc;
            fc = fa;
        }
        let tol1 = 2.0 * f64::EPSILON * b.abs() + 0.5 * tol;
        let xm = 0.5 * (c - b);
        if xm.abs() <= tol1 || fb == 0.0 {
            return b;
        }
        if e.abs() >= tol1 && fa.abs() > fb.abs() {
            let s = fb / fa;
            let (mut p, mut q);
            if a == c {
                p = 2.0 * xm * s;
                q = 1.0 - s;
            } else {
                let qq = fa / fc;
                let r = fb / fc;
                p = s * (2.0 * xm * qq * (qq - r) - (b - a) * (r - 1.0));
                q = (qq - 1.0) * (r - 1.0) * (s - 1.0);
            }
            if p > 0.0 {
                q = -q;
            }
            p = p.abs();
            if 2.0 * p < (3.0 * xm * q - (tol1 * q).abs()).min((e * q).abs()) {
                e = d;
                d = p / q;
            } else {
                d = xm;
                e = d;
            }
        } else {
            d = xm;
            e = d;
        }
        a = b;
        fa = fb;
        b += if d.abs() > tol1 { d } else { tol1.copysign(xm) };
        fb = f(b);
    }
    b
}

#[derive(Debug, Clone, Copy)]
struct Candidate {
    alpha: f64,
    beta: f64,
    kind: AmaxKind,
    theta: f64,
}

/// `alpha_max` and the `beta` where it is reached, for `plant`, over all `beta` or within
/// the limits of `opts`.
///
/// Method: direct search for the rightmost point of the stable region among the smooth
/// maxima of the D-decomposition curve and its corners with the `z = -1` line and the beta
/// limits (see the [module documentation](self); D-decomposition: Neimark 1948, as used in
/// the paper's Section V; refinement by Brent's method).
///
/// # Errors
///
/// [`Error::InvalidParameter`]/[`Error::InvalidRequest`] for bad options or beta limits that
/// leave no stable wall; [`Error::Numerical`] if no candidate could be confirmed.
pub fn alpha_max(plant: &Plant, opts: &AmaxOptions) -> Result<Amax> {
    alpha_max_detail(plant, opts).map(|d| d.amax)
}

/// As [`alpha_max`], also saying which piece of the boundary holds the maximum.
pub fn alpha_max_detail(plant: &Plant, opts: &AmaxOptions) -> Result<AmaxDetail> {
    opts.validate()?;
    let poly = CharPoly::new(plant);
    let curve = Curve::new(&poly);
    let line = poly.line_minus_one();
    let tol = opts.tol;
    let bmin = opts.beta_min.unwrap_or(f64::NEG_INFINITY);
    let bmax = opts.beta_max.unwrap_or(f64::INFINITY);

    let mut cands: Vec<Candidate> = Vec::with_capacity(16);
    let n_scan = 32 * (plant.whole_samples() + 2);
    let theta_at = |j: usize| PI * j as f64 / n_scan as f64;
    let line_dist = |p: &CurvePoint| line.map(|(a, b, r)| a * p.alpha + b * p.beta - r);

    let mut prev: Option<(f64, CurvePoint)> = None;
    for j in 1..n_scan {
        let th = theta_at(j);
        let Some(p) = curve.eval(th) else {
            prev = None;
            continue;
        };
        if let Some((th0, p0)) = prev {
            // Smooth maximum: d alpha / d theta goes from + to -.
            if p0.dalpha > 0.0 && p.dalpha <= 0.0 {
                let t = brent(
                    |t| curve.eval(t).map_or(f64::NAN, |q| q.dalpha),
                    th0,
                    th,
                    tol,
                );
                if let Some(q) = curve.eval(t) {
                    cands.push(Candidate {
                        alpha: q.alpha,
                        beta: q.beta,
                        kind: AmaxKind::Smooth,
                        theta: t,
                    });
                }
            }
            // Corner with the z = -1 line.
            if let (Some(g0), Some(g1)) = (line_dist(&p0), line_dist(&p))
                && (g0 > 0.0) != (g1 > 0.0)
            {
                let t = brent(
                    |t| {
                        curve
                            .eval(t)
                            .and_then(|q| line_dist(&q))
                            .unwrap_or(f64::NAN)
                    },
                    th0,
                    th,
                    tol,
                );
                if let Some(q) = curve.eval(t) {
                    cands.push(Candidate {
                        alpha: q.alpha,
                        beta: q.beta,
                        kind: AmaxKind::MinusOneCorner,
                        theta: t,
                    });
                }
            }
            // Crossings of the beta limits.
            for lim in [opts.beta_min, opts.beta_max].into_iter().flatten() {
                if (p0.beta > lim) != (p.beta > lim) {
                    let t = brent(
                        |t| curve.eval(t).map_or(f64::NAN, |q| q.beta - lim),
                        th0,
                        th,
                        tol,
                    );
                    if let Some(q) = curve.eval(t) {
                        cands.push(Candidate {
                            alpha: q.alpha,
                            beta: lim,
                            kind: AmaxKind::BetaLimit,
                            theta: t,
                        });
                    }
                }
            }
        }
        prev = Some((th, p));
    }
    // The end of the curve on the z = -1 line (a double root at -1): for d = 0 and large
    // delta alpha grows all the way to theta = pi and the maximum sits there.
    if line.is_some()
        && let Some(q) = curve.eval_end()
    {
        cands.push(Candidate {
            alpha: q.alpha,
            beta: q.beta,
            kind: AmaxKind::MinusOneCorner,
            theta: PI,
        });
        for lim in [opts.beta_min, opts.beta_max].into_iter().flatten() {
            // The curve's last stretch may cross a beta limit before pi: caught by the scan
            // only if a sample lies beyond; close the gap between the last sample and pi.
            let t0 = theta_at(n_scan - 1);
            if let Some(p0) = curve.eval(t0)
                && (p0.beta > lim) != (q.beta > lim)
            {
                let t = brent(
                    |t| {
                        let e = if t >= PI {
                            curve.eval_end()
                        } else {
                            curve.eval(t)
                        };
                        e.map_or(f64::NAN, |q| q.beta - lim)
                    },
                    t0,
                    PI,
                    tol,
                );
                if let Some(q) = curve.eval(t) {
                    cands.push(Candidate {
                        alpha: q.alpha,
                        beta: lim,
                        kind: AmaxKind::BetaLimit,
                        theta: t,
                    });
                }
            }
        }
    }
    // The z = -1 line meets the beta limits.
    if let Some((a, b, r)) = line {
        for lim in [opts.beta_min, opts.beta_max].into_iter().flatten() {
            cands.push(Candidate {
                alpha: (r - b * lim) / a,
                beta: lim,
                kind: AmaxKind::BetaLimit,
                theta: PI,
            });
        }
    }

    cands.retain(|c| {
        c.alpha.is_finite()
            && c.alpha > 0.0
            && c.beta.is_finite()
            && c.beta >= bmin
            && c.beta <= bmax
    });
    cands.sort_by(|x, y| y.alpha.total_cmp(&x.alpha));
    let mut buf = [0.0; MAX_COEFFS];
    // The nearest neighbours first; the farther ones only when no candidate has a stable
    // neighbour that near (see `has_stable_left_neighbour` for why that can happen).
    for step in NEIGHBOUR_STEPS {
        for c in &cands {
            if has_stable_left_neighbour(&poly, c, step, bmin, bmax, &mut buf) {
                return Ok(AmaxDetail {
                    amax: Amax {
                        alpha_max: c.alpha,
                        beta_at_max: c.beta,
                    },
                    kind: c.kind,
                    theta: c.theta,
                });
            }
        }
    }
    if opts.beta_min.is_some() || opts.beta_max.is_some() {
        Err(Error::InvalidRequest(format!(
            "no stable wall has beta in [{bmin}, {bmax}] for delta = {}, d = {}; widen the beta limits (the stable region reaches down to beta = -delta)",
            plant.delta(),
            plant.d()
        )))
    } else {
        Err(Error::Numerical(format!(
            "no rightmost point of the stable region could be confirmed for delta = {}, d = {}",
            plant.delta(),
            plant.d()
        )))
    }
}

/// Relative distances of the neighbours that confirm a candidate, nearest first.
///
/// `1e-8`: far above the Schur-Cohn recursion's resolution near the circle for simple roots
/// (about `1e-13` for these degrees), so a confirmed neighbour is really stable; and small
/// enough that a candidate just outside a corner of the region (not on its boundary) can be
/// off by at most that much.
///
/// `1e-6`: where the corner is a double root at `z = -1` (the `z = -1` line meeting the
/// D-decomposition curve, e.g. `d = 0`, `delta = 11.25`), rounding moves the double root by
/// about `sqrt(u) = 1e-8`, while a neighbour `1e-8` inside has its roots only `4e-10` inside
/// the circle: no test resolves that. At `1e-6` the neighbour's roots are `4e-8` inside,
/// above the double root's resolution. Used only when no candidate is confirmed at `1e-8`,
/// so an ordinary corner is still confirmed to `1e-8`.
const NEIGHBOUR_STEPS: [f64; 2] = [1e-8, 1e-6];

/// Whether some wall a relative `step` to the left of the candidate (straight left or up to
/// 4:1 diagonally, inside the beta limits) is strictly stable.
fn has_stable_left_neighbour(
    poly: &CharPoly,
    c: &Candidate,
    step: f64,
    bmin: f64,
    bmax: f64,
    buf: &mut [f64],
) -> bool {
    let h = step * (c.alpha.abs() + c.beta.abs());
    for k in [0.0, 1.0, -1.0, 0.25, -0.25, 4.0, -4.0] {
        let wall = Wall {
            alpha: c.alpha - h,
            beta: c.beta + k * h,
        };
        if wall.beta < bmin || wall.beta > bmax {
            continue;
        }
        let q = poly.coefficients_into(&wall, buf);
        if schur_cohn(q, 1.0).stable {
            return true;
        }
    }
    false
}

/// One point of the path of maximum stiffness or of `alpha_max` against `delta`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct AmaxPoint {
    /// Normalized physical damping.
    pub delta: f64,
    /// Delay factor.
    pub d: f64,
    /// Maximum stable stiffness.
    pub alpha_max: f64,
    /// Damping at the maximum.
    pub beta_at_max: f64,
}

/// The most `alpha_max` values one series or table computes in one call: about 100 bytes
/// each in memory and 10 to 40 us each to compute (a larger request is split by the caller,
/// e.g. with the command line's `--shard`).
pub const MAX_ROWS: usize = 1_000_000;

fn check_rows(rows: usize) -> Result<()> {
    if rows == 0 {
        return Err(Error::InvalidRequest(
            "empty list: give at least one delta".into(),
        ));
    }
    if rows > MAX_ROWS {
        return Err(Error::InvalidRequest(format!(
            "{rows} alpha_max values exceed the {MAX_ROWS} one call holds in memory; split the request"
        )));
    }
    Ok(())
}

/// `alpha_max` for each `delta` at one delay `d`, in the order given (rayon, results
/// independent of the thread count).
///
/// Read as `(alpha_max, beta_at_max)` pairs this is the path of maximum stiffness in the
/// `(alpha, beta)` plane (paper Fig. 5, dashed); read as `(delta, alpha_max)` it is Fig. 10.
pub fn amax_series(deltas: &[f64], d: f64, opts: &AmaxOptions) -> Result<Vec<AmaxPoint>> {
    opts.validate()?;
    check_rows(deltas.len())?;
    deltas
        .par_iter()
        .map(|&delta| {
            let plant = Plant::new(delta, d)?;
            let a = alpha_max(&plant, opts)?;
            Ok(AmaxPoint {
                delta,
                d,
                alpha_max: a.alpha_max,
                beta_at_max: a.beta_at_max,
            })
        })
        .collect()
}

/// The path of maximum stiffness (paper Fig. 5, dashed) for delay `d`: the rightmost points
/// of the stable regions as `delta` runs over `deltas`. Same data as [`amax_series`].
pub fn max_stiffness_path(deltas: &[f64], d: f64, opts: &AmaxOptions) -> Result<Vec<Wall>> {
    Ok(amax_series(deltas, d, opts)?
        .into_iter()
        .map(|p| Wall {
            alpha: p.alpha_max,
            beta: p.beta_at_max,
        })
        .collect())
}

/// The large-delta slope `g(d)` of the paper's eq. (22), `alpha_max ~ g delta`, with the
/// range it was fitted on.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SlopeFit {
    /// Delay factor.
    pub d: f64,
    /// Least-squares slope of `alpha_max` against `delta` on the range.
    pub g: f64,
    /// Intercept of the same fit (eq. (22) takes it as zero; it shows how far that holds).
    pub intercept: f64,
    /// `alpha_max(delta_hi) / delta_hi`, the ratio of eq. (22) taken literally.
    pub ratio_at_hi: f64,
    /// Lower end of the fitted `delta` range.
    pub delta_lo: f64,
    /// Upper end of the fitted `delta` range.
    pub delta_hi: f64,
    /// Number of `delta` values in the fit.
    pub points: usize,
    /// Largest absolute residual of the fit, relative to `alpha_max(delta_hi)`.
    pub max_rel_residual: f64,
}

/// Default `delta` range of the slope fit: the paper reads the slope for `delta > 6`
/// (Fig. 10 b); from 10 the curves are straight to plotting accuracy.
pub const DEFAULT_SLOPE_RANGE: (f64, f64) = (10.0, 100.0);

/// Estimates `g(d)` of eq. (22) by a least-squares line through `alpha_max(delta)` at `points`
/// evenly spaced `delta` in `[delta_lo, delta_hi]` (at least 2, at most [`MAX_ROWS`]).
pub fn slope_g(
    d: f64,
    delta_lo: f64,
    delta_hi: f64,
    points: usize,
    opts: &AmaxOptions,
) -> Result<SlopeFit> {
    crate::params::finite("delta-lo", delta_lo)?;
    crate::params::finite("delta-hi", delta_hi)?;
    if !(delta_lo >= 0.0 && delta_hi > delta_lo && (2..=MAX_ROWS).contains(&points)) {
        return Err(Error::InvalidRequest(format!(
            "slope fit needs 0 <= delta_lo < delta_hi and 2 to {MAX_ROWS} points, got [{delta_lo}, {delta_hi}] with {points}"
        )));
    }
    let deltas: Vec<f64> = (0..points)
        .map(|i| delta_lo + (delta_hi - delta_lo) * i as f64 / (points - 1) as f64)
        .collect();
    let series = amax_series(&deltas, d, opts)?;
    let nf = points as f64;
    let mx = deltas.iter().sum::<f64>() / nf;
    let my = series.iter().map(|p| p.alpha_max).sum::<f64>() / nf;
    let (mut sxy, mut sxx) = (0.0, 0.0);
    for p in &series {
        sxy += (p.delta - mx) * (p.alpha_max - my);
        sxx += (p.delta - mx) * (p.delta - mx);
    }
    let g = sxy / sxx;
    let intercept = my - g * mx;
    let last = series[points - 1].alpha_max;
    let max_res = series
        .iter()
        .map(|p| (p.alpha_max - (intercept + g * p.delta)).abs())
        .fold(0.0, f64::max);
    Ok(SlopeFit {
        d,
        g,
        intercept,
        ratio_at_hi: last / delta_hi,
        delta_lo,
        delta_hi,
        points,
        max_rel_residual: max_res / last,
    })
}

/// A lookup table of `alpha_max` and `beta_at_max` over a grid of `delta` by `d`, for
/// firmware (see [`amax_table`]).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AmaxTable {
    /// The `delta` axis (ascending).
    pub delta: Vec<f64>,
    /// The `d` axis (ascending).
    pub d: Vec<f64>,
    /// `alpha_max[i_d][i_delta]`; with `conservative`, the lowered values.
    pub alpha_max: Vec<Vec<f64>>,
    /// `beta_at_max[i_d][i_delta]` (never lowered).
    pub beta_at_max: Vec<Vec<f64>>,
    /// Whether `alpha_max` was lowered for safe interpolation.
    pub conservative: bool,
    /// The options the values were computed with.
    #[serde(skip)]
    pub options: AmaxOptions,
    /// The refinement tolerance used (copy of `options.tol`, for the record).
    pub tol: f64,
}

fn check_axis(name: &str, v: &[f64]) -> Result<()> {
    if v.is_empty() {
        return Err(Error::InvalidRequest(format!(
            "the {name} axis is empty; give at least one value"
        )));
    }
    if v.windows(2)
        .any(|w| w[1].partial_cmp(&w[0]) != Some(std::cmp::Ordering::Greater))
    {
        return Err(Error::InvalidRequest(format!(
            "the {name} axis must be strictly increasing for a lookup table"
        )));
    }
    Ok(())
}

/// Evaluates `alpha_max` on every `(d, delta)` of `points` in parallel, in order.
fn eval_points(points: &[(f64, f64)], opts: &AmaxOptions) -> Result<Vec<Amax>> {
    points
        .par_iter()
        .map(|&(d, delta)| alpha_max(&Plant::new(delta, d)?, opts))
        .collect()
}

/// `alpha_max` and `beta_at_max` on the grid `deltas x ds` (rayon; identical for any thread
/// count since every value is computed independently and collected in order).
///
/// With `conservative`, each `alpha_max` node is lowered just enough that linear
/// interpolation never exceeds the true `alpha_max` at the test points: in `delta` along
/// each row at 1/4, 1/2 and 3/4 of every interval, in `d` along each column at the midpoint,
/// and bilinearly at every cell centre. For each test point the excess of the interpolated
/// value over the true one is taken off every node that enters the interpolation there, and
/// every node is lowered by the largest excess it takes part in. Between test points the
/// guarantee is not proven (it holds when `alpha_max` is smooth on the scale of the grid).
pub fn amax_table(
    deltas: &[f64],
    ds: &[f64],
    opts: &AmaxOptions,
    conservative: bool,
) -> Result<AmaxTable> {
    opts.validate()?;
    check_axis("delta", deltas)?;
    check_axis("d", ds)?;
    check_rows(deltas.len().saturating_mul(ds.len()))?;
    for &d in ds {
        Plant::new(0.0, d)?;
    }
    for &delta in deltas {
        Plant::new(delta, 0.0)?;
    }
    let nx = deltas.len();
    let grid: Vec<(f64, f64)> = ds
        .iter()
        .flat_map(|&d| deltas.iter().map(move |&x| (d, x)))
        .collect();
    let vals = eval_points(&grid, opts)?;
    let mut alpha: Vec<Vec<f64>> = vals
        .chunks(nx)
        .map(|r| r.iter().map(|a| a.alpha_max).collect())
        .collect();
    let beta: Vec<Vec<f64>> = vals
        .chunks(nx)
        .map(|r| r.iter().map(|a| a.beta_at_max).collect())
        .collect();
    if conservative {
        // Each test: the point, and the nodes (row, col, weight) interpolated there.
        // (row, column, weight) of each node in one interpolation
        type Nodes = Vec<(usize, usize, f64)>;
        let mut tests: Vec<((f64, f64), Nodes)> = Vec::new();
        for (r, &d) in ds.iter().enumerate() {
            for c in 0..nx.saturating_sub(1) {
                for t in [0.25, 0.5, 0.75] {
                    let x = deltas[c] + t * (deltas[c + 1] - deltas[c]);
                    tests.push(((d, x), vec![(r, c, 1.0 - t), (r, c + 1, t)]));
                }
            }
        }
        for r in 0..ds.len().saturating_sub(1) {
            let dm = 0.5 * (ds[r] + ds[r + 1]);
            for c in 0..nx {
                tests.push(((dm, deltas[c]), vec![(r, c, 0.5), (r + 1, c, 0.5)]));
                if c + 1 < nx {
                    let xm = 0.5 * (deltas[c] + deltas[c + 1]);
                    tests.push((
                        (dm, xm),
                        vec![
                            (r, c, 0.25),
                            (r, c + 1, 0.25),
                            (r + 1, c, 0.25),
                            (r + 1, c + 1, 0.25),
                        ],
                    ));
                }
            }
        }
        let pts: Vec<(f64, f64)> = tests.iter().map(|t| t.0).collect();
        let truth = eval_points(&pts, opts)?;
        let mut lower = vec![vec![0.0f64; nx]; ds.len()];
        for ((_, nodes), t) in tests.iter().zip(&truth) {
            let interp: f64 = nodes.iter().map(|&(r, c, w)| w * alpha[r][c]).sum();
            // The weights sum to 1, so lowering every node by the excess lowers the
            // interpolated value by exactly the excess. A relative 1e-12 on top covers the
            // rounding of the interpolation itself and of alpha_max (DEFAULT_TOL).
            let excess = interp - t.alpha_max + 1e-12 * t.alpha_max.abs();
            if excess > 0.0 {
                for &(r, c, _) in nodes {
                    lower[r][c] = lower[r][c].max(excess);
                }
            }
        }
        for (row, low) in alpha.iter_mut().zip(&lower) {
            for (v, l) in row.iter_mut().zip(low) {
                // Never below 0: a coarse grid can ask for more lowering than the value has;
                // 0 is then the only safe value (every alpha in (0, alpha_max) is usable).
                *v = (*v - l).max(0.0);
            }
        }
    }
    Ok(AmaxTable {
        delta: deltas.to_vec(),
        d: ds.to_vec(),
        alpha_max: alpha,
        beta_at_max: beta,
        conservative,
        options: *opts,
        tol: opts.tol,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    fn am(delta: f64, d: f64) -> Amax {
        alpha_max(&Plant::new(delta, d).unwrap(), &AmaxOptions::default()).unwrap()
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
        let a = alpha_max(&plant, &AmaxOptions::default()).unwrap();
        let checker = crate::stability::Checker::new(
            &plant,
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
        let poly = CharPoly::new(&plant);
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

    #[test]
    fn beta_limits() {
        let plant = Plant::new(5.0, 0.0).unwrap();
        let free = alpha_max(&plant, &AmaxOptions::default()).unwrap();
        assert!(free.beta_at_max < 0.0, "{free:?}");
        let opts = AmaxOptions {
            beta_min: Some(0.0),
            ..AmaxOptions::default()
        };
        let lim = alpha_max(&plant, &opts).unwrap();
        assert!(lim.alpha_max < free.alpha_max);
        assert!(lim.beta_at_max.abs() < 1e-12, "{lim:?}");
        // Limits that exclude every stable wall.
        let opts = AmaxOptions {
            beta_min: Some(1e3),
            ..AmaxOptions::default()
        };
        assert!(matches!(
            alpha_max(&plant, &opts),
            Err(Error::InvalidRequest(_))
        ));
        let bad = AmaxOptions {
            beta_min: Some(1.0),
            beta_max: Some(0.0),
            ..AmaxOptions::default()
        };
        assert!(alpha_max(&plant, &bad).is_err());
    }
}

#[cfg(test)]
mod table_tests {
    use super::*;

    /// Conservative tables: linear interpolation at fresh points (1/3 of each interval, not
    /// a point the lowering used) stays below the true alpha_max, and the lowering is small.
    #[test]
    fn conservative_interpolation_is_below_truth() {
        let deltas: Vec<f64> = (0..9).map(|i| i as f64 * 0.5).collect();
        let ds = [0.0, 0.5, 1.0];
        let opts = AmaxOptions::default();
        let plain = amax_table(&deltas, &ds, &opts, false).unwrap();
        let cons = amax_table(&deltas, &ds, &opts, true).unwrap();
        let mut any_excess = false;
        for (r, &d) in ds.iter().enumerate() {
            for c in 0..deltas.len() - 1 {
                let t = 1.0 / 3.0;
                let x = deltas[c] + t * (deltas[c + 1] - deltas[c]);
                let truth = alpha_max(&Plant::new(x, d).unwrap(), &opts)
                    .unwrap()
                    .alpha_max;
                let lin_plain = (1.0 - t) * plain.alpha_max[r][c] + t * plain.alpha_max[r][c + 1];
                any_excess |= lin_plain > truth;
                let lin = (1.0 - t) * cons.alpha_max[r][c] + t * cons.alpha_max[r][c + 1];
                assert!(lin <= truth, "d {d} delta {x}: {lin} > {truth}");
                // lowered, never raised (interpolation across the coarse d axis can take a lot)
                assert!(cons.alpha_max[r][c] <= plain.alpha_max[r][c]);
            }
        }
        // alpha_max is convex in delta somewhere here, so the plain table did overshoot:
        // the conservative lowering was needed, and this test exercises it.
        assert!(any_excess);
    }
}
