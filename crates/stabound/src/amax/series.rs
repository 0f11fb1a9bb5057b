//! `alpha_max` over lists of `delta`: the path of maximum stiffness (Fig. 5, dashed),
//! `alpha_max` against `delta` (Fig. 10) and the large-delta slope `g(d)` of eq. (22).

use super::{Amax, AmaxOptions, alpha_max, alpha_max_with_marginal};
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

impl AmaxPoint {
    /// The point of `plant` whose rightmost point is `a`.
    fn of(plant: &Plant, a: Amax) -> Self {
        Self {
            delta: plant.delta(),
            d: plant.d(),
            alpha_max: a.alpha_max,
            beta_at_max: a.beta_at_max,
        }
    }
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

/// The most `alpha_max` values one streamed call ([`alpha_max_each`]) computes. It holds only
/// a few chunks of rows at a time, so the bound is one of time: 10 to 40 us a value at short
/// delays (some 200 us at d = 50) make 10^8 values between 10 minutes and a few hours on two
/// cores, and some 8 GB of CSV.
pub const MAX_STREAM_ROWS: usize = 100_000_000;

/// Rows per chunk of [`alpha_max_each`]: enough that a chunk's bookkeeping costs nothing
/// beside a few milliseconds of searches, few enough that memory stays small.
const CHUNK_ROWS: usize = 256;

/// `alpha_max` for each `delta` at one delay `d`, in the order given (rayon, results
/// independent of the thread count).
///
/// Read as `(alpha_max, beta_at_max)` pairs this is the path of maximum stiffness in the
/// `(alpha, beta)` plane (paper Fig. 5, dashed); read as `(delta, alpha_max)` it is Fig. 10.
pub fn amax_series(deltas: &[f64], d: f64, opts: &AmaxOptions) -> Result<Vec<AmaxPoint>> {
    check_rows(deltas.len())?;
    let mut out = Vec::with_capacity(deltas.len());
    alpha_max_each(
        deltas.len(),
        |i| Plant::new(deltas[i], d),
        opts,
        |_, rows| {
            out.extend_from_slice(rows);
            Ok::<(), Error>(())
        },
    )?;
    Ok(out)
}

/// `alpha_max` of the plants `plant(0)`, ..., `plant(count - 1)`, handed to `sink` in
/// consecutive chunks (with the index of each chunk's first row) in that order, as soon as a
/// chunk and every one before it are computed (rayon; a few chunks per thread are computed
/// ahead, so memory does not grow with `count`). The chunks are the same whatever the number
/// of threads. At most [`MAX_STREAM_ROWS`] rows.
///
/// Stops at the first error in output order, from `plant`, a search or `sink`, and returns
/// it; nothing after it reaches the sink.
///
/// ```
/// use stabound::amax::{AmaxOptions, alpha_max_each};
/// use stabound::params::Plant;
///
/// let mut rows = Vec::new();
/// alpha_max_each(2, |i| Plant::new(0.0, i as f64), &AmaxOptions::default(), |_, chunk| {
///     rows.extend_from_slice(chunk);
///     Ok::<(), stabound::Error>(())
/// })?;
/// // no delay: the closed form 12 - 8 sqrt 2 (docs/MODEL.md section 6); a delay lowers it
/// assert!((rows[0].alpha_max - (12.0 - 8.0 * 2f64.sqrt())).abs() < 1e-12);
/// assert!(rows[1].alpha_max < rows[0].alpha_max);
/// # Ok::<(), stabound::Error>(())
/// ```
pub fn alpha_max_each<P, S, E>(
    count: usize,
    plant: P,
    opts: &AmaxOptions,
    sink: S,
) -> std::result::Result<(), E>
where
    P: Fn(usize) -> Result<Plant> + Sync,
    S: FnMut(usize, &[AmaxPoint]) -> std::result::Result<(), E> + Send,
    E: From<Error> + Send,
{
    each_row(
        count,
        |i| {
            let p = plant(i)?;
            alpha_max(p, opts).map(|a| AmaxPoint::of(&p, a))
        },
        sink,
    )
}

/// As [`alpha_max_each`], each row with the spectral radius of the wall a relative
/// [`super::HOLD_STEP`] below its `alpha_max` when the checker calls that wall marginal
/// ([`alpha_max_with_marginal`]: the discretization of each plant serves both).
///
/// ```
/// use stabound::amax::{AmaxOptions, alpha_max_each, alpha_max_each_with_marginal};
/// use stabound::params::Plant;
///
/// let plant = |i: usize| Plant::new([0.1, 100.0][i], 0.0);
/// let opts = AmaxOptions::default();
/// let (mut rows, mut bare) = (Vec::new(), Vec::new());
/// alpha_max_each_with_marginal(2, plant, &opts, |_, chunk| {
///     rows.extend_from_slice(chunk);
///     Ok::<(), stabound::Error>(())
/// })?;
/// alpha_max_each(2, plant, &opts, |_, chunk| {
///     bare.extend_from_slice(chunk);
///     Ok::<(), stabound::Error>(())
/// })?;
/// assert_eq!((rows[0].0, rows[1].0), (bare[0], bare[1]));
/// // much physical damping without delay: the wall just below the optimum barely settles
/// assert_eq!(rows[0].1, None);
/// assert!(rows[1].1.is_some_and(|radius| radius > 1.0 - 1e-9));
/// # Ok::<(), stabound::Error>(())
/// ```
pub fn alpha_max_each_with_marginal<P, S, E>(
    count: usize,
    plant: P,
    opts: &AmaxOptions,
    sink: S,
) -> std::result::Result<(), E>
where
    P: Fn(usize) -> Result<Plant> + Sync,
    S: FnMut(usize, &[(AmaxPoint, Option<f64>)]) -> std::result::Result<(), E> + Send,
    E: From<Error> + Send,
{
    each_row(
        count,
        |i| {
            let p = plant(i)?;
            let (a, below) = alpha_max_with_marginal(p, opts)?;
            Ok((AmaxPoint::of(&p, a), below))
        },
        sink,
    )
}

/// `row(0)`, ..., `row(count - 1)` in chunks of [`CHUNK_ROWS`], handed to `sink` in order
/// ([`alpha_max_each`]'s streaming).
fn each_row<T, R, S, E>(count: usize, row: R, mut sink: S) -> std::result::Result<(), E>
where
    T: Send,
    R: Fn(usize) -> Result<T> + Sync,
    S: FnMut(usize, &[T]) -> std::result::Result<(), E> + Send,
    E: From<Error> + Send,
{
    if count == 0 {
        return Err(Error::InvalidRequest("empty list: give at least one delta".into()).into());
    }
    if count > MAX_STREAM_ROWS {
        return Err(Error::InvalidRequest(format!(
            "{count} alpha_max values exceed the {MAX_STREAM_ROWS} one call computes; split the request"
        ))
        .into());
    }
    crate::ordered::for_each_ordered(
        count.div_ceil(CHUNK_ROWS),
        |c| {
            (c * CHUNK_ROWS..count.min((c + 1) * CHUNK_ROWS))
                .map(&row)
                .collect::<Result<Vec<T>>>()
                .map_err(E::from)
        },
        |c, rows| sink(c * CHUNK_ROWS, &rows),
    )
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
