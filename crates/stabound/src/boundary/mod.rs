//! Stability boundaries: the closed curve around the stable region of a parameter plane.
//!
//! Two engines:
//!
//! - [`exact()`]: the boundary in the `(alpha, beta)` plane for one plant `(delta, d)`, assembled
//!   from the D-decomposition curve, the line `alpha = 0` and the line of the root `z = -1`
//!   (`docs/MODEL.md` section 4). Only the pieces that bound the stable region are kept; every
//!   point is on the boundary to rounding and the polyline follows the curve within `tol`.
//! - [`bisect()`]: a general engine for any plane of two of `(alpha, beta, delta, d)`: a
//!   coarse parallel grid of point tests, bisection of every crossing, and adaptive
//!   refinement of the resulting closed polylines by bisection along chord normals. It serves
//!   the `(delta, beta)` plane (paper Figs. 6 and 9) and is the independent cross-check of the
//!   exact method.
//!
//! [`sweep`] runs either engine over lists of `delta` and `d` in parallel; the output order is
//! that of the lists, whatever the number of threads.
//!
//! ```
//! use stabound::boundary::{exact, ExactOptions, Piece};
//! use stabound::params::Plant;
//!
//! let b = exact(&Plant::new(0.0, 0.0)?, &ExactOptions::default())?;
//! // The rightmost point is the paper's alpha_max = 12 - 8 sqrt 2 (docs/MODEL.md section 6).
//! let (alpha_max, _beta) = b.rightmost();
//! assert!((alpha_max - (12.0 - 8.0 * 2f64.sqrt())).abs() < 1e-8);
//! assert!(b.points.iter().any(|p| p.piece == Piece::AlphaZero));
//! # Ok::<(), stabound::Error>(())
//! ```

pub(crate) mod bisect;
mod curve;
pub(crate) mod exact;
mod refine;

use crate::elements::Loop;
use crate::error::{Error, Result};
use crate::params::Plant;
pub(crate) use bisect::RightmostWall;
pub use bisect::{Axis, BisectOptions, Contour, Plane, bisect, bisect_alpha_beta};
pub use exact::{ExactOptions, exact};

/// The default tolerance of both engines: `1e-9` in the normalized parameters.
///
/// Every returned point is on the boundary to rounding (exact method) or to `tol` (bisection),
/// and the polyline deviates from the true curve by less than `tol` between points. `1e-9`
/// is three orders of magnitude below any difference visible in a plot or relevant to a
/// controller gain, and about five above the rounding of the point tests near the circle.
pub const DEFAULT_TOL: f64 = 1e-9;

/// The smallest tolerance accepted: below about `1e-12` the chord test and the point tests
/// are decided by rounding of quantities of order 1, and refinement would not terminate
/// meaningfully.
pub const MIN_TOL: f64 = 1e-12;

/// The largest tolerance accepted (coarser than this is not a boundary any more).
pub const MAX_TOL: f64 = 1e-2;

/// Checks a boundary tolerance: finite, in `[MIN_TOL, MAX_TOL]`. Every engine checks its
/// options this way; a caller may check early, before any work, with the same message.
pub fn check_tol(tol: f64) -> Result<f64> {
    crate::params::in_range("tol", tol, MIN_TOL, MAX_TOL)
}

/// Which piece of the boundary a point (and the segment that leaves it) lies on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
pub enum Piece {
    /// The D-decomposition curve: a complex pair of roots on the unit circle.
    Curve,
    /// The line `alpha = 0`: the root `z = 1`.
    AlphaZero,
    /// The line of the root `z = -1`.
    MinusOne,
    /// The line of the root `z = 1` where it is not `alpha = 0` (a loop whose device has no
    /// free integrator, such as one with a hand's stiffness).
    PlusOne,
    /// Found by the bisection engine (no piece identified).
    Bisection,
    /// The edge of the requested box of the bisection engine (not a stability boundary).
    Clipped,
}

impl Piece {
    /// The name used in CSV and JSON output.
    pub fn name(self) -> &'static str {
        match self {
            Piece::Curve => "curve",
            Piece::AlphaZero => "alpha-zero",
            Piece::MinusOne => "minus-one",
            Piece::PlusOne => "plus-one",
            Piece::Bisection => "bisection",
            Piece::Clipped => "clipped",
        }
    }
}

/// One vertex of a region's edge, the one vertex type of every engine: a point `(x, y)` in
/// the plane of two parameters, and what the edge that leaves it lies on.
///
/// `x` and `y` are the plane's horizontal and vertical parameters: `(alpha, beta)` for a
/// [`Boundary`], the [`Plane`]'s axes for a [`Contour`], `(alpha, beta)` or `(delta, beta)`
/// for a passive region (`crate::passivity::PassiveRegion`). `piece` says what the segment
/// from this vertex to the next lies on (a corner belongs to the piece that leaves it): a
/// [`Piece`] of the stability boundary, or for the passive edge its piece and the active
/// frequency (`crate::passivity::PassivePiece`).
///
/// ```
/// use stabound::boundary::{ExactOptions, Piece, exact};
///
/// let b = exact(&stabound::Plant::new(0.5, 1.0)?, &ExactOptions::default())?;
/// // The exact boundary starts at its lowest point on alpha = 0, (0, -delta), and closes
/// // along alpha = 0 (the root z = 1).
/// let (start, last) = (b.points[0], b.points[b.points.len() - 2]);
/// assert!(start.x.abs() < 1e-12 && (start.y + 0.5).abs() < 1e-12);
/// assert_eq!(last.piece, Piece::AlphaZero);
/// # Ok::<(), stabound::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Vertex<K = Piece> {
    /// The horizontal parameter (`alpha` in the `(alpha, beta)` plane).
    pub x: f64,
    /// The vertical parameter (`beta` in the `(alpha, beta)` plane).
    pub y: f64,
    /// What the segment from this vertex to the next lies on.
    pub piece: K,
}

impl<K> Vertex<K> {
    /// The coordinates `(x, y)`.
    pub fn xy(&self) -> (f64, f64) {
        (self.x, self.y)
    }
}

impl Vertex {
    /// On the edge of a requested range ([`Piece::Clipped`]) rather than on the stability
    /// boundary.
    pub fn clipped(&self) -> bool {
        self.piece == Piece::Clipped
    }
}

/// The stability boundary in the `(alpha, beta)` plane of one plant.
///
/// `points` (`x = alpha`, `y = beta`) is a closed polyline: the last point repeats the first. It runs counterclockwise
/// (the stable region on the left) and starts at the lowest point on `alpha = 0`, which is
/// `(0, -delta)` (paper eq. 19).
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Boundary {
    /// Normalized physical damping of the plant.
    pub delta: f64,
    /// Delay factor of the plant.
    pub d: f64,
    /// The tolerance the boundary was computed to.
    pub tol: f64,
    /// The closed polyline.
    pub points: Vec<Vertex>,
    /// `None` when the engine asked for drew the boundary; else why the exact engine could
    /// not close it, and the bisection engine drew it instead ([`exact()`]).
    #[cfg_attr(
        feature = "serde",
        serde(default, skip_serializing_if = "Option::is_none")
    )]
    pub fallback: Option<String>,
}

impl Boundary {
    /// The rightmost point `(alpha_max, beta)` of the polyline. With the exact method this
    /// is `alpha_max` to about `tol` (a vertex is within `tol` of the true maximum's height).
    pub fn rightmost(&self) -> (f64, f64) {
        self.points
            .iter()
            .fold((f64::NEG_INFINITY, f64::NAN), |(a, b), p| {
                if p.x > a { (p.x, p.y) } else { (a, b) }
            })
    }

    /// The vertices as `(alpha, beta)` pairs.
    pub fn xy(&self) -> Vec<(f64, f64)> {
        self.points.iter().map(Vertex::xy).collect()
    }

    /// Signed area enclosed (positive for counterclockwise), by the shoelace formula.
    pub fn area(&self) -> f64 {
        crate::geometry::polygon_area(&self.xy())
    }
}

/// Which engine computes the `(alpha, beta)` boundaries of a sweep.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
pub enum Engine {
    /// [`exact`]: D-decomposition.
    #[default]
    Exact,
    /// [`bisect_alpha_beta`]: grid and bisection.
    Bisect,
}

/// Options of a [`sweep`].
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct SweepOptions {
    /// The engine.
    pub engine: Engine,
    /// The tolerance (see [`DEFAULT_TOL`]).
    pub tol: f64,
}

impl Default for SweepOptions {
    fn default() -> Self {
        Self {
            engine: Engine::Exact,
            tol: DEFAULT_TOL,
        }
    }
}

/// The `(alpha, beta)` boundary of the loop `lp` (a [`Plant`] for the paper's loop) by the
/// chosen engine: [`exact()`] or [`bisect_alpha_beta`].
///
/// ```
/// use stabound::boundary::{Engine, SweepOptions, trace};
/// use stabound::elements::Loop;
/// use stabound::filter::VelocityFilter;
/// use stabound::params::Plant;
///
/// let plant = Plant::new(0.5, 1.0)?;
/// let opts = SweepOptions { engine: Engine::Exact, tol: 1e-6 };
/// let bare = trace(&plant, &opts)?;
/// let filtered = trace(Loop::new(plant).with_filter(VelocityFilter::low_pass(0.5)?)?, &opts)?;
/// // the filter's lag shrinks the region
/// assert!(filtered.area() < bare.area());
/// # Ok::<(), stabound::Error>(())
/// ```
///
/// # Errors
///
/// As the engine chosen.
pub fn trace(lp: impl Into<Loop>, options: &SweepOptions) -> Result<Boundary> {
    let lp = lp.into();
    match options.engine {
        Engine::Exact => exact(lp, &ExactOptions { tol: options.tol }),
        Engine::Bisect => bisect_alpha_beta(
            lp,
            &BisectOptions {
                tol: options.tol,
                ..BisectOptions::default()
            },
        ),
    }
}

/// The largest distance from a vertex of `a` to the polyline `b`, capped at `h`: a vertex
/// farther than `h` from every segment of `b` counts as `h`. With both directions this is
/// the Hausdorff distance used to compare the exact and bisection engines.
///
/// Method: `b`'s segments are cut below length `h` and filed in a grid of cells of size `h`;
/// each vertex of `a` is checked against the segments in its own and the eight neighbouring
/// cells, so the cost is linear in the number of vertices.
pub fn directed_distance(a: &[(f64, f64)], b: &[(f64, f64)], h: f64) -> f64 {
    use std::collections::HashMap;
    if a.is_empty() || b.is_empty() || h.is_nan() || h <= 0.0 {
        return f64::NAN;
    }
    let cell = |v: f64| (v / h).floor() as i64;
    let mut dense: Vec<(f64, f64)> = vec![b[0]];
    for w in b.windows(2) {
        let len = crate::geometry::point_dist(w[0], w[1]);
        let k = (len / h).ceil().max(1.0) as usize;
        for i in 1..=k {
            let t = i as f64 / k as f64;
            dense.push((
                w[0].0 + t * (w[1].0 - w[0].0),
                w[0].1 + t * (w[1].1 - w[0].1),
            ));
        }
    }
    let mut grid: HashMap<(i64, i64), Vec<usize>> = HashMap::new();
    for k in 0..dense.len().saturating_sub(1) {
        let (p, q) = (dense[k], dense[k + 1]);
        for i in cell(p.0.min(q.0))..=cell(p.0.max(q.0)) {
            for j in cell(p.1.min(q.1))..=cell(p.1.max(q.1)) {
                grid.entry((i, j)).or_default().push(k);
            }
        }
    }
    a.iter()
        .map(|&p| {
            let mut best = h;
            for i in cell(p.0) - 1..=cell(p.0) + 1 {
                for j in cell(p.1) - 1..=cell(p.1) + 1 {
                    for &k in grid.get(&(i, j)).map_or(&[][..], |v| &v[..]) {
                        let d = crate::geometry::seg_dist(p, dense[k], dense[k + 1]);
                        best = best.min(d);
                    }
                }
            }
            best
        })
        .fold(0.0, f64::max)
}

/// The most vertices one boundary curve may have: a curve at the default tolerance has tens
/// of thousands; a million (about 100 MB in memory and as CSV) is reached only when the
/// tolerance is tiny against the curve's size (a very large `delta`, say). Beyond it the
/// engines stop and return [`crate::Error::InvalidRequest`] saying how to reduce the work.
pub const MAX_VERTICES: usize = 1_000_000;

/// The error of a curve that would exceed [`MAX_VERTICES`]: `size` is the curve's extent in
/// normalized units, from which a tolerance that fits the budget is suggested (chord errors
/// fall as the square of the spacing, so `1e-10` of the size needs some 1e5 vertices on a
/// smooth loop).
pub(crate) fn too_many_vertices(plant: &Plant, tol: f64, size: f64) -> crate::Error {
    let suggest = size * 1e-10;
    let how = if suggest <= MAX_TOL {
        format!(
            "use a tolerance of at least {:.0e}",
            suggest.max(tol * 10.0)
        )
    } else {
        "the curve is too large for any accepted tolerance: use a smaller delta".into()
    };
    crate::Error::InvalidRequest(format!(
        "the boundary at delta = {}, d = {} needs more than {MAX_VERTICES} vertices to stay within tolerance {tol:e} of a curve of size {size:.3e}; {how}",
        plant.delta(),
        plant.d()
    ))
}

/// The most curves one [`sweep`] computes: a curve at the default tolerance has tens of
/// thousands of points, all held in memory until the caller writes them ([`sweep_each`]
/// holds only a few at a time).
pub const MAX_CURVES: usize = 1_000;

/// The most curves one streamed sweep ([`sweep_each`], [`sweep_planes_each`]) computes. Its
/// memory does not grow with the number of curves, so the bound is one of time: a curve at
/// the default tolerance costs 2 to 3 ms of one core and some 1.5 MB of CSV, so 100,000
/// curves are about two minutes on two cores and 150 GB of output, and even at the
/// per-curve cap of [`MAX_VERTICES`] a run stays within hours.
pub const MAX_STREAM_CURVES: usize = 100_000;

/// The boundaries of every `(delta, d)` with `delta` from `deltas` (outer) and `d` from `ds`
/// (inner), computed in parallel (rayon); the result is in that order whatever the number of
/// threads. `progress` is called once after each boundary (from worker threads). At most
/// [`MAX_CURVES`] curves (for more, hand each to a sink with [`sweep_each`]).
pub fn sweep(
    deltas: &[f64],
    ds: &[f64],
    options: &SweepOptions,
    progress: Option<&(dyn Fn() + Sync)>,
) -> Result<Vec<Boundary>> {
    if deltas.is_empty() || ds.is_empty() {
        return Err(Error::InvalidRequest(
            "empty list: give at least one delta and one d".into(),
        ));
    }
    let curves = deltas.len().saturating_mul(ds.len());
    if curves > MAX_CURVES {
        return Err(Error::InvalidRequest(format!(
            "{curves} curves ({} delta x {} d) exceed the {MAX_CURVES} one sweep holds in memory; split the request",
            deltas.len(),
            ds.len()
        )));
    }
    let mut out = Vec::with_capacity(curves);
    sweep_each(
        curves,
        |k| Plant::new(deltas[k / ds.len()], ds[k % ds.len()]),
        options,
        progress,
        |b| {
            out.push(b);
            Ok::<(), Error>(())
        },
    )?;
    Ok(out)
}

/// The boundaries of the plants `plant(0)`, ..., `plant(count - 1)`, each handed to `sink` in
/// that order as soon as it and every one before it are computed (rayon; a few curves per
/// thread are computed ahead, so memory stays proportional to the number of threads however
/// many curves there are). The sink sees the same sequence whatever the number of threads;
/// a single curve is computed on the calling thread.
///
/// Stops at the first error in output order, from `plant`, an engine or `sink`, and returns
/// it; nothing after it reaches the sink. `progress` is called once after each boundary
/// (from worker threads).
///
/// ```
/// use stabound::boundary::{SweepOptions, sweep_each};
/// use stabound::params::Plant;
///
/// let deltas = [0.0, 0.5, 1.0];
/// let mut rightmost = Vec::new();
/// sweep_each(3, |k| Plant::new(deltas[k], 1.0), &SweepOptions::default(), None, |b| {
///     rightmost.push(b.rightmost().0);
///     Ok::<(), stabound::Error>(())
/// })?;
/// // more physical damping allows a stiffer wall (paper Fig. 5)
/// assert!(rightmost[0] < rightmost[1] && rightmost[1] < rightmost[2]);
/// # Ok::<(), stabound::Error>(())
/// ```
pub fn sweep_each<P, S, E>(
    count: usize,
    plant: P,
    options: &SweepOptions,
    progress: Option<&(dyn Fn() + Sync)>,
    sink: S,
) -> std::result::Result<(), E>
where
    P: Fn(usize) -> Result<Plant> + Sync,
    S: FnMut(Boundary) -> std::result::Result<(), E> + Send,
    E: From<Error> + Send,
{
    check_tol(options.tol)?;
    each(
        count,
        |k| {
            let p = plant(k)?;
            // the curves run in parallel with each other, so each is computed on one thread
            match options.engine {
                Engine::Exact => exact::exact_on(&p, &ExactOptions { tol: options.tol }, false),
                Engine::Bisect => trace(p, options),
            }
        },
        progress,
        sink,
    )
}

/// The bisection engine's boundaries in the planes `plane(0)`, ..., `plane(count - 1)`,
/// handed to `sink` in that order as [`sweep_each`] does (same memory bound, same order
/// whatever the number of threads, same stop at the first error).
pub fn sweep_planes_each<P, S, E>(
    count: usize,
    plane: P,
    options: &BisectOptions,
    progress: Option<&(dyn Fn() + Sync)>,
    sink: S,
) -> std::result::Result<(), E>
where
    P: Fn(usize) -> Result<Plane> + Sync,
    S: FnMut(Contour) -> std::result::Result<(), E> + Send,
    E: From<Error> + Send,
{
    each(
        count,
        |k| {
            let plane = plane(k)?;
            bisect(plane.at.plant(), &plane, options)
        },
        progress,
        sink,
    )
}

/// The streamed sweeps' common part: the count checked, then `compute` of each index handed
/// to `sink` in order, with a `progress` call after each.
fn each<T, C, S, E>(
    count: usize,
    compute: C,
    progress: Option<&(dyn Fn() + Sync)>,
    mut sink: S,
) -> std::result::Result<(), E>
where
    T: Send,
    C: Fn(usize) -> Result<T> + Sync,
    S: FnMut(T) -> std::result::Result<(), E> + Send,
    E: From<Error> + Send,
{
    check_count(count)?;
    crate::ordered::for_each_ordered(
        count,
        |k| {
            crate::cancel::poll()?;
            let t = compute(k)?;
            if let Some(f) = progress {
                f();
            }
            Ok(t)
        },
        |_, t| sink(t),
    )
}

fn check_count(count: usize) -> Result<()> {
    if count == 0 {
        return Err(Error::InvalidRequest(
            "no curve requested: give at least one".into(),
        ));
    }
    if count > MAX_STREAM_CURVES {
        return Err(Error::InvalidRequest(format!(
            "{count} curves exceed the {MAX_STREAM_CURVES} one sweep computes; split the request"
        )));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A point one above a horizontal segment is at distance 1; the cap `h` bounds it.
    #[test]
    fn directed_distance_of_known_geometry() {
        let seg = [(-1.0, 0.0), (1.0, 0.0)];
        assert!((directed_distance(&[(0.0, 1.0)], &seg, 2.0) - 1.0).abs() < 1e-15);
        assert!((directed_distance(&[(0.0, 1.0)], &seg, 0.5) - 0.5).abs() < 1e-15);
        // beyond the segment's end the distance is to the end point: (2, 0) -> (1, 0)
        assert!((directed_distance(&[(2.0, 0.0), (0.0, 0.0)], &seg, 4.0) - 1.0).abs() < 1e-15);
    }
}
