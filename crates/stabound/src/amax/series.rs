//! `alpha_max` over lists of `delta`: the path of maximum stiffness (Fig. 5, dashed),
//! `alpha_max` against `delta` (Fig. 10) and the large-delta slope `g(d)` of eq. (22).

use rayon::prelude::*;

use super::{AmaxOptions, alpha_max};
use crate::error::{Error, Result};
use crate::params::{Plant, Wall};

/// One point of the path of maximum stiffness or of `alpha_max` against `delta`.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
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

pub(super) fn check_rows(rows: usize) -> Result<()> {
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
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
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
    crate::params::finite("lowest delta", delta_lo)?;
    crate::params::finite("highest delta", delta_hi)?;
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
