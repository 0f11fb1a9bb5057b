//! The passive region against the stable region of a loop with a velocity filter, in the
//! `(alpha, beta)` plane for given `delta` and in the `(delta, beta)` plane for given `alpha`.
//!
//! In the `(alpha, beta)` plane [`super::compare`] clips the exact stable boundary of the
//! filtered loop; this module is the second, independent route, and the one for the
//! `(delta, beta)` plane, where the stable set on any line of the wall plane is exact: along a line the characteristic polynomial of the
//! loop (the model document, docs/MODEL.md, section 8) is affine in the free parameter, and
//! its crossings of the unit circle are the roots on the circle of one polynomial (the
//! D-decomposition restricted to a line: Neimark 1948; Ackermann, *Robust Control*, 2nd ed.,
//! 2002, section 4.3), each piece between crossings decided by one point test of the loop
//! ([`Checker`]). The comparison therefore works on *columns*: lines of constant `beta`
//! (stable stiffnesses, `(alpha, beta)` plane) or of constant `delta` (stable dampings,
//! `(delta, beta)` plane), `2 columns + 1` of them evenly spaced over the regions' extent.
//! On each column both sets are exact: the passive set is the interval cut from the passive
//! region's edge (traced to its tolerance by [`Criterion`]), the stable set a union of open
//! intervals.
//!
//! - *Containment*: on every column the passive interval must lie in one stable interval, to
//!   the comparison's tolerance (twice the passive edge's tolerance plus `1e-9` of the region's
//!   size: the edge is inside the true region by up to its tolerance, and a corner where the
//!   regions touch, such as `(0, -delta)`, would otherwise count as a crossing). Exact along each
//!   column; between columns a protrusion narrower than the spacing can be missed.
//! - *Witnesses*: the middle of the longest uncovered piece of a passive interval (a passive,
//!   unstable candidate) and of the longest stable piece outside the passive interval (stable,
//!   not passive), each kept only when the certified criterion ([`Criterion::margin`]) and
//!   the loop's verdict confirm it.
//! - *Areas and fractions*: the trapezoidal rule over the columns of the lengths of the
//!   stable, passive and common sets. The same sum over every other column gives a second
//!   value; their difference is reported as the fraction's error estimate
//!   ([`ColumnComparison::fraction_error`]); `h` is the column spacing, and   the estimate is typical rather than safe (a kink of a length between columns makes the
//!   error depend on where the columns fall). [`ColumnComparison::fraction_bound`] is a
//!   bound instead: `h/2` times the total variation of the lengths, valid when each length is
//!   monotone between adjacent columns.

use rayon::prelude::*;

use super::delay::{Comparison, Criterion, PassiveRegion, Witness};
use crate::elements::Loop;
use crate::error::{Error, Result};
use crate::filter::VelocityFilter;
use crate::params::{MAX_DELTA, Plant, Wall, finite, in_range};
use crate::search::Interval;
use crate::stability::Checker;
use crate::stability::{Options, Verdict};

/// Columns per half of the default comparison (`2 * 128 + 1` lines): a fraction to about
/// `1e-4` for the regions tested, in well under a second.
pub const DEFAULT_COLUMNS: usize = 128;

/// The most columns one comparison accepts (each is one root-finding of degree `2 deg q`;
/// in the `(delta, beta)` plane also one discretization).
pub const MAX_COLUMNS: usize = 20_000;

/// Where a column comparison was made.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
#[non_exhaustive]
pub enum ComparePlane {
    /// The `(alpha, beta)` plane at physical damping `delta`; columns of constant `beta`.
    AlphaBeta {
        /// Physical damping.
        delta: f64,
    },
    /// The `(delta, beta)` plane at stiffness `alpha`, for `0 <= delta <= delta_max`;
    /// columns of constant `delta`.
    DeltaBeta {
        /// Stiffness.
        alpha: f64,
        /// The largest physical damping compared.
        delta_max: f64,
    },
}

/// The passive region of a loop with a velocity filter against its stable region, by
/// columns (see the module documentation).
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct ColumnComparison {
    /// The plane and its fixed parameter.
    pub plane: ComparePlane,
    /// Whole samples of delay.
    pub n: usize,
    /// The velocity filter.
    pub filter: VelocityFilter,
    /// How many columns were tested (`2 columns + 1`).
    pub columns: usize,
    /// Whether every column's passive interval lies in one stable interval, to `tol`.
    pub inside: bool,
    /// The tolerance of the containment test along a column (normalized units).
    pub tol: f64,
    /// Area of the passive region (in the `(delta, beta)` plane: up to `delta_max`).
    pub passive_area: f64,
    /// Area of the stable region (in the `(delta, beta)` plane: up to `delta_max`).
    pub stable_area: f64,
    /// Area of their intersection.
    pub common_area: f64,
    /// The fraction of the stable region that is passive, `common / stable`.
    pub passive_fraction_of_stable: f64,
    /// The fraction of the passive region that is stable, `common / passive`.
    pub stable_fraction_of_passive: f64,
    /// Error estimate of [`ColumnComparison::passive_fraction_of_stable`]: its change when
    /// every other column is dropped. Typical, not a bound: against the exact engine (no
    /// filter) the true error was up to 6 times this estimate at 128 columns.
    pub fraction_error: f64,
    /// A bound on the error of [`ColumnComparison::passive_fraction_of_stable`]: the
    /// trapezoidal rule's error for a function monotone between adjacent columns is at most
    /// `h/2` times its change, so each area is within `h/2` times the total variation of its
    /// column lengths; the bound propagates both to the quotient. It holds when no length
    /// has a maximum or minimum strictly between two columns that the columns do not show;
    /// it is first order in `h`, so far above the typical error.
    pub fraction_bound: f64,
    /// A passive wall that is unstable, when one was found.
    pub passive_unstable: Option<Witness>,
    /// A stable wall that is not passive, when one was found.
    pub stable_not_passive: Option<Witness>,
    /// The passive region.
    pub region: PassiveRegion,
    /// The stable region's outline for drawing: the columns' outermost stable ends, in the
    /// plane's coordinates (`(alpha, beta)` or `(delta, beta)`), one way along the upper
    /// ends and back along the lower ones. Exact at the columns, straight between them.
    pub stable_outline: Vec<(f64, f64)>,
}

/// One column: its coordinate, the passive interval on it and the stable intervals.
struct Column {
    x: f64,
    passive: Option<(f64, f64)>,
    stable: Vec<Interval>,
}

impl Column {
    fn stable_len(&self) -> f64 {
        self.stable.iter().map(|i| i.hi - i.lo).sum()
    }

    fn passive_len(&self) -> f64 {
        self.passive.map_or(0.0, |(a, b)| b - a)
    }

    fn common_len(&self) -> f64 {
        let Some((a, b)) = self.passive else {
            return 0.0;
        };
        self.stable
            .iter()
            .map(|i| (i.hi.min(b) - i.lo.max(a)).max(0.0))
            .sum()
    }

    /// The longest piece of the passive interval no stable interval covers.
    fn uncovered(&self) -> Option<(f64, f64)> {
        let (a, b) = self.passive?;
        let mut best: Option<(f64, f64)> = None;
        let mut at = a;
        let mut consider = |lo: f64, hi: f64| {
            if hi > lo && best.is_none_or(|(x, y)| hi - lo > y - x) {
                best = Some((lo, hi));
            }
        };
        for i in &self.stable {
            if i.hi <= at {
                continue;
            }
            if i.lo >= b {
                break;
            }
            consider(at, i.lo.min(b));
            at = at.max(i.hi);
        }
        consider(at, b);
        best
    }

    /// The longest piece of a stable interval outside the passive interval.
    fn stable_outside(&self) -> Option<(f64, f64)> {
        let mut best: Option<(f64, f64)> = None;
        for i in &self.stable {
            let pieces = match self.passive {
                None => [(i.lo, i.hi), (0.0, 0.0)],
                Some((a, b)) => [(i.lo, i.hi.min(a)), (i.lo.max(b), i.hi)],
            };
            for (lo, hi) in pieces {
                if hi > lo && best.is_none_or(|(x, y)| hi - lo > y - x) {
                    best = Some((lo, hi));
                }
            }
        }
        best
    }
}

/// The trapezoidal sum of `f` over columns `0, step, 2 step, ...` spaced `h step`.
fn trapezoid(cols: &[Column], h: f64, step: usize, f: impl Fn(&Column) -> f64) -> f64 {
    let idx: Vec<usize> = (0..cols.len()).step_by(step).collect();
    let last = idx.len() - 1;
    idx.iter()
        .enumerate()
        .map(|(k, &i)| {
            let w = if k == 0 || k == last { 0.5 } else { 1.0 };
            w * f(&cols[i])
        })
        .sum::<f64>()
        * h
        * step as f64
}

fn check_columns(columns: usize) -> Result<usize> {
    if !(2..=MAX_COLUMNS).contains(&columns) {
        return Err(Error::InvalidRequest(format!(
            "{columns} columns: give between 2 and {MAX_COLUMNS}"
        )));
    }
    Ok(columns)
}

/// The checker of the loop of `(delta, d)` with `filter`.
fn loop_of(delta: f64, d: f64, filter: VelocityFilter) -> Result<Checker> {
    let lp = Loop::new(Plant::new(delta, d)?).with_filter(filter)?;
    Checker::new(lp, Options::default())
}

/// The stable stiffnesses of the loop at damping `beta` (the loop has a free integrator: no
/// hand stiffness is named).
fn stable_alphas(checker: &Checker, beta: f64) -> Result<Vec<Interval>> {
    let set = crate::search::stable_alphas(checker, beta)?;
    if set.iter().any(|i| !(i.lo.is_finite() && i.hi.is_finite())) {
        return Err(Error::Numerical(
            "a stable set of the filtered loop is unbounded; the loop is not the damped mass this comparison assumes".into(),
        ));
    }
    Ok(set)
}

/// The largest `x` of the closed convex polygon `p` at height `y`, if the line meets it.
fn polygon_right(p: &[(f64, f64)], y: f64) -> Option<f64> {
    let mut best: Option<f64> = None;
    for w in p.windows(2) {
        let ((x0, y0), (x1, y1)) = (w[0], w[1]);
        if (y0 - y) * (y1 - y) > 0.0 || (y0 - y1).abs() <= 0.0 {
            continue;
        }
        let x = x0 + (y - y0) / (y1 - y0) * (x1 - x0);
        best = Some(best.map_or(x, |b: f64| b.max(x)));
    }
    best
}

/// The range of `y` where the polyline `p` (the `(delta, beta)` edge `x = h(y)`, convex)
/// lies left of `x`: the passive dampings at physical damping `x`.
fn polyline_left(p: &[(f64, f64)], x: f64) -> Option<(f64, f64)> {
    // the vertices left of x (the ends sit a bisection tolerance inside `delta_max`) and
    // the crossings of x
    let mut lo = f64::INFINITY;
    let mut hi = f64::NEG_INFINITY;
    for q in p.iter().filter(|q| q.0 <= x) {
        lo = lo.min(q.1);
        hi = hi.max(q.1);
    }
    for w in p.windows(2) {
        let ((x0, y0), (x1, y1)) = (w[0], w[1]);
        if (x0 - x) * (x1 - x) > 0.0 {
            continue;
        }
        let y = if (x1 - x0).abs() > 0.0 {
            y0 + (x - x0) / (x1 - x0) * (y1 - y0)
        } else {
            y0
        };
        lo = lo.min(y);
        hi = hi.max(y);
    }
    (hi > lo).then_some((lo, hi))
}

/// Compares the passive region of `(delta, d, filter)` with the stable region of the loop
/// with that filter, in the `(alpha, beta)` plane: containment, witnesses and fractions, on
/// `2 columns + 1` lines of constant `beta` (see the module documentation for the method and
/// its accuracy). The passive edge is traced to `tol`.
///
/// The columns span the union of both regions' `beta` ranges; the stable one is found by
/// growing from the passive region and bisecting to `tol` on whether a line has a stable
/// wall, so a stable region made of pieces separated in `beta` is covered only around the
/// piece that meets the passive region (with `delta = 0`: the piece met by a scan of
/// `beta` in `[-1, 4]`).
///
/// ```
/// use stabound::VelocityFilter;
/// use stabound::passivity::compare_on_lines;
///
/// // One sample of delay, a moving average over two samples.
/// let f = VelocityFilter::moving_average(2)?;
/// let c = compare_on_lines(1.0, 1.0, f, 64, 1e-7)?;
/// assert!(c.inside);
/// assert!(c.passive_fraction_of_stable > 0.0 && c.passive_fraction_of_stable < 1.0);
/// # Ok::<(), stabound::Error>(())
/// ```
pub fn compare_on_lines(
    delta: f64,
    d: f64,
    filter: VelocityFilter,
    columns: usize,
    tol: f64,
) -> Result<ColumnComparison> {
    in_range("delta", delta, 0.0, MAX_DELTA)?;
    let columns = check_columns(columns)?;
    let crit = Criterion::new(d, filter)?;
    let region = crit.region_alpha_beta(delta, tol)?;
    let checker = loop_of(delta, d, filter)?;
    let poly_xy = region.xy();
    let (pb_lo, pb_hi) = poly_xy
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), p| {
            (l.min(p.1), h.max(p.1))
        });
    let nonempty = |beta: f64| -> Result<bool> { Ok(!stable_alphas(&checker, beta)?.is_empty()) };
    let size = if poly_xy.is_empty() {
        1.0
    } else {
        (pb_hi - pb_lo).max(f64::MIN_POSITIVE)
    };
    // a line with a stable wall to grow the range from
    let seed = if poly_xy.is_empty() {
        None
    } else {
        Some(0.5 * (pb_lo + pb_hi))
    }
    .into_iter()
    .chain((0..=64).map(|i| -1.0 + 5.0 * i as f64 / 64.0))
    .map(|b| nonempty(b).map(|ok| ok.then_some(b)))
    .find_map(|r| r.transpose())
    .transpose()?;
    let (mut lo, mut hi) = if poly_xy.is_empty() {
        (f64::INFINITY, f64::NEG_INFINITY)
    } else {
        (pb_lo, pb_hi)
    };
    if let Some(seed) = seed {
        let end = |dir: f64| -> Result<f64> {
            // grow until a line has no stable wall, then bisect
            let mut inside = seed;
            let mut step = size;
            let mut outside = seed + dir * step;
            let mut grown = 0;
            while nonempty(outside)? {
                inside = outside;
                step *= 2.0;
                outside = seed + dir * step;
                grown += 1;
                if grown > 60 {
                    return Err(Error::Numerical(
                        "the stable region of the filtered loop seems unbounded in beta".into(),
                    ));
                }
            }
            // to tol, or to the last representable midpoint: far out (a slow filter's stable
            // region reaches beta ~ 1e10) the spacing of doubles exceeds tol
            while (outside - inside).abs() > tol {
                let m = 0.5 * (inside + outside);
                // exact on purpose: no double lies strictly between the ends
                if m == inside || m == outside {
                    break;
                }
                if nonempty(m)? {
                    inside = m;
                } else {
                    outside = m;
                }
            }
            Ok(outside)
        };
        lo = lo.min(end(-1.0)?);
        hi = hi.max(end(1.0)?);
    }
    let plane = ComparePlane::AlphaBeta { delta };
    if hi <= lo {
        // no passive wall and no stable one: nothing to compare
        return Ok(empty(plane, &crit, columns, tol, region));
    }
    let count = 2 * columns + 1;
    let h = (hi - lo) / (2 * columns) as f64;
    let cols: Vec<Column> = (0..count)
        .into_par_iter()
        .map(|j| {
            let beta = if j + 1 == count {
                hi
            } else {
                lo + h * j as f64
            };
            let passive = polygon_right(&poly_xy, beta)
                .filter(|&a| a > 0.0)
                .map(|a| (0.0, a));
            Ok(Column {
                x: beta,
                passive,
                stable: stable_alphas(&checker, beta)?,
            })
        })
        .collect::<Result<_>>()?;
    let wall_at = |x: f64, s: f64| Ok((Wall::new(s, x)?, delta));
    let checks = |w: &Wall, dl: f64| -> Result<(f64, f64, Verdict)> {
        let (mlo, mhi, _) = crit.margin(dl, w)?;
        Ok((mlo, mhi, checker.verdict(w)?))
    };
    finish(plane, &crit, cols, h, region, &wall_at, &checks, |x, s| {
        (s, x)
    })
}

/// Compares the passive region of `(alpha, d, filter)` with the stable region of the loop
/// with that filter in the `(delta, beta)` plane for `0 <= delta <= delta_max`, on
/// `2 columns + 1` lines of constant `delta` (stable dampings at stiffness `alpha`; see the
/// module documentation). Works for `F = 1` too (the paper's loop).
///
/// Errors: `alpha <= 0` (at `alpha = 0` every wall has the root `z = 1`, and no wall with
/// `alpha < 0` is stable), `delta_max` out of range or 0.
pub fn compare_delta_beta(
    alpha: f64,
    d: f64,
    filter: VelocityFilter,
    delta_max: f64,
    columns: usize,
    tol: f64,
) -> Result<ColumnComparison> {
    finite("alpha", alpha)?;
    if alpha <= 0.0 {
        return Err(Error::InvalidParameter {
            name: "alpha",
            value: alpha,
            expected: "a stiffness > 0: at alpha = 0 every wall has the root z = 1 (on the stability boundary), and no wall with alpha < 0 is stable".into(),
        });
    }
    in_range("delta_max", delta_max, 0.0, MAX_DELTA)?;
    if delta_max <= 0.0 {
        return Err(Error::InvalidParameter {
            name: "delta_max",
            value: delta_max,
            expected: "a largest physical damping > 0".into(),
        });
    }
    let columns = check_columns(columns)?;
    let crit = Criterion::new(d, filter)?;
    let region = crit.region_delta_beta(alpha, delta_max, tol)?;
    let edge = region.xy();
    let count = 2 * columns + 1;
    let h = delta_max / (2 * columns) as f64;
    let deltas: Vec<f64> = (0..count)
        .map(|j| {
            if j + 1 == count {
                delta_max
            } else {
                h * j as f64
            }
        })
        .collect();
    let cols: Vec<Column> = deltas
        .par_iter()
        .map(|&delta| {
            let checker = loop_of(delta, d, filter)?;
            Ok(Column {
                x: delta,
                passive: polyline_left(&edge, delta),
                stable: crate::search::stable_betas(&checker, alpha)?,
            })
        })
        .collect::<Result<_>>()?;
    if cols
        .iter()
        .flat_map(|c| &c.stable)
        .any(|i| !(i.lo.is_finite() && i.hi.is_finite()))
    {
        return Err(Error::Numerical(
            "a stable set of dampings is unbounded; the loop is not the damped mass this comparison assumes".into(),
        ));
    }
    let wall_at = |x: f64, s: f64| Ok((Wall::new(alpha, s)?, x));
    let checks = |w: &Wall, dl: f64| -> Result<(f64, f64, Verdict)> {
        let (mlo, mhi, _) = crit.margin(dl, w)?;
        let checker = loop_of(dl, d, filter)?;
        Ok((mlo, mhi, checker.verdict(w)?))
    };
    finish(
        ComparePlane::DeltaBeta { alpha, delta_max },
        &crit,
        cols,
        h,
        region,
        &wall_at,
        &checks,
        |x, s| (x, s),
    )
}

fn empty(
    plane: ComparePlane,
    crit: &Criterion,
    columns: usize,
    tol: f64,
    region: PassiveRegion,
) -> ColumnComparison {
    ColumnComparison {
        plane,
        n: crit.delay(),
        filter: crit.filter(),
        columns: 2 * columns + 1,
        inside: true,
        tol,
        passive_area: 0.0,
        stable_area: 0.0,
        common_area: 0.0,
        passive_fraction_of_stable: 0.0,
        stable_fraction_of_passive: 0.0,
        fraction_error: 0.0,
        fraction_bound: 0.0,
        passive_unstable: None,
        stable_not_passive: None,
        region,
        stable_outline: Vec::new(),
    }
}

/// `(wall, delta)` of the point `s` on column `x`.
type WallAt<'a> = dyn Fn(f64, f64) -> Result<(Wall, f64)> + 'a;
/// `(margin lower end, margin upper end, verdict)` of a wall at a physical damping.
type Checks<'a> = dyn Fn(&Wall, f64) -> Result<(f64, f64, Verdict)> + 'a;

/// Containment, witnesses, areas and outline from the columns (module documentation).
#[allow(clippy::too_many_arguments)]
fn finish(
    plane: ComparePlane,
    crit: &Criterion,
    cols: Vec<Column>,
    h: f64,
    region: PassiveRegion,
    wall_at: &WallAt<'_>,
    checks: &Checks<'_>,
    to_plane: impl Fn(f64, f64) -> (f64, f64),
) -> Result<ColumnComparison> {
    let scale = cols
        .iter()
        .flat_map(|c| {
            c.stable
                .iter()
                .flat_map(|i| [i.lo.abs(), i.hi.abs()])
                .chain(c.passive.iter().flat_map(|p| [p.0.abs(), p.1.abs()]))
        })
        .fold(0.0f64, f64::max);
    let ctol = 2.0 * region.tol + 1e-9 * scale.max(f64::MIN_POSITIVE);
    // passive but unstable: the widest uncovered piece over all columns
    let widest = |f: &dyn Fn(&Column) -> Option<(f64, f64)>| {
        cols.iter()
            .filter_map(|c| f(c).map(|p| (c.x, p)))
            .max_by(|a, b| (a.1.1 - a.1.0).total_cmp(&(b.1.1 - b.1.0)))
    };
    let uncovered = widest(&|c: &Column| c.uncovered());
    let inside = uncovered.is_none_or(|(_, (a, b))| b - a <= ctol);
    let mut passive_unstable = None;
    if let Some((x, (a, b))) = uncovered.filter(|_| !inside) {
        let (wall, dl) = wall_at(x, 0.5 * (a + b))?;
        let (mlo, _, v) = checks(&wall, dl)?;
        if mlo > 0.0 && v == Verdict::Unstable {
            passive_unstable = Some(Witness::new(&wall, dl, mlo, v));
        }
    }
    let mut stable_not_passive = None;
    if let Some((x, (a, b))) = widest(&|c: &Column| c.stable_outside()) {
        let (wall, dl) = wall_at(x, 0.5 * (a + b))?;
        let (_, mhi, v) = checks(&wall, dl)?;
        if mhi < 0.0 && v == Verdict::Stable {
            stable_not_passive = Some(Witness::new(&wall, dl, mhi, v));
        }
    }
    let areas = |step: usize| {
        (
            trapezoid(&cols, h, step, Column::stable_len),
            trapezoid(&cols, h, step, Column::passive_len),
            trapezoid(&cols, h, step, Column::common_len),
        )
    };
    let ratio = |a: f64, b: f64| if b > 0.0 { (a / b).min(1.0) } else { 0.0 };
    let (stable_area, passive_area, common_area) = areas(1);
    let (s2, _, c2) = areas(2);
    let fraction = ratio(common_area, stable_area);
    let variation = |f: fn(&Column) -> f64| {
        0.5 * h
            * cols
                .windows(2)
                .map(|w| (f(&w[1]) - f(&w[0])).abs())
                .sum::<f64>()
    };
    let (es, ec) = (variation(Column::stable_len), variation(Column::common_len));
    let fraction_bound = if stable_area > es {
        (ec + fraction * es) / (stable_area - es)
    } else {
        1.0
    };
    let mut upper: Vec<(f64, f64)> = Vec::new();
    let mut lower: Vec<(f64, f64)> = Vec::new();
    for c in &cols {
        if let (Some(f), Some(l)) = (c.stable.first(), c.stable.last()) {
            upper.push(to_plane(c.x, l.hi));
            lower.push(to_plane(c.x, f.lo));
        }
    }
    lower.reverse();
    upper.extend(lower);
    if let Some(&p) = upper.first() {
        upper.push(p);
    }
    Ok(ColumnComparison {
        plane,
        n: crit.delay(),
        filter: crit.filter(),
        columns: cols.len(),
        inside,
        tol: ctol,
        passive_area,
        stable_area,
        common_area,
        passive_fraction_of_stable: fraction,
        stable_fraction_of_passive: ratio(common_area, passive_area),
        fraction_error: (fraction - ratio(c2, s2)).abs(),
        fraction_bound,
        passive_unstable,
        stable_not_passive,
        region,
        stable_outline: upper,
    })
}

/// The numbers of a comparison with the stable region, from either engine: the exact one
/// ([`super::delay::compare`], `(alpha, beta)` plane) or the columns.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct Summary {
    /// Whether the passive region lies inside the stable one.
    pub inside: bool,
    /// Area of the passive region.
    pub passive_area: f64,
    /// Area of the stable region.
    pub stable_area: f64,
    /// The fraction of the stable region that is passive.
    pub passive_share: f64,
    /// The fraction of the passive region that is stable.
    pub stable_share: f64,
    /// Error estimate of the passive share (NaN for the exact engine, whose polygons are
    /// within the tolerance of both edges).
    pub share_error: f64,
    /// A bound on that error (NaN for the exact engine).
    pub share_bound: f64,
    /// How the stable region was computed: `exact` (D-decomposition), `bisection` (where the
    /// exact engine could not close the boundary) or `columns`.
    pub method: &'static str,
    /// A passive wall that is unstable, when one was found.
    pub passive_unstable: Option<Witness>,
    /// A stable wall that is not passive, when one was found.
    pub stable_not_passive: Option<Witness>,
}

impl From<&Comparison> for Summary {
    fn from(c: &Comparison) -> Self {
        Self {
            inside: c.inside,
            passive_area: c.passive_area,
            stable_area: c.stable_area,
            passive_share: c.passive_fraction_of_stable,
            stable_share: c.stable_fraction_of_passive,
            share_error: f64::NAN,
            share_bound: f64::NAN,
            method: if c.stable_fallback.is_some() {
                "bisection"
            } else {
                "exact"
            },
            passive_unstable: c.passive_unstable,
            stable_not_passive: c.stable_not_passive,
        }
    }
}

impl From<&ColumnComparison> for Summary {
    fn from(c: &ColumnComparison) -> Self {
        Self {
            inside: c.inside,
            passive_area: c.passive_area,
            stable_area: c.stable_area,
            passive_share: c.passive_fraction_of_stable,
            stable_share: c.stable_fraction_of_passive,
            share_error: c.fraction_error,
            share_bound: c.fraction_bound,
            method: "columns",
            passive_unstable: c.passive_unstable,
            stable_not_passive: c.stable_not_passive,
        }
    }
}

/// The comparison in the `(alpha, beta)` plane as a report gives it: the passive region, the
/// stable region's outline, the numbers, and why the columns were used when they were.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct AlphaBetaComparison {
    /// The passive region.
    pub region: PassiveRegion,
    /// The stable region's outline: the exact boundary, or the columns' outline.
    pub stable: Vec<(f64, f64)>,
    /// The numbers ([`Summary::method`] says which engine).
    pub summary: Summary,
    /// Why the columns compared the regions instead of the exact boundary, or why the
    /// bisection engine drew the boundary; `None` when the exact boundary did.
    pub note: Option<String>,
}

/// The passive region of `(delta, d, filter)` against the stable region in the `(alpha,
/// beta)` plane: [`super::compare`] (the exact boundary of the loop with its filter), or,
/// where the stable region has a piece that boundary does not trace holding the passive
/// region, [`compare_on_lines`] on `2 columns + 1` lines.
///
/// ```
/// use stabound::VelocityFilter;
/// use stabound::passivity::compare_alpha_beta;
///
/// let c = compare_alpha_beta(1.0, 1.0, VelocityFilter::butterworth(0.1)?, 128, 1e-7)?;
/// assert_eq!(c.summary.method, "exact");
/// // two stable pieces, the passive region in the smaller: the columns see both
/// let c = compare_alpha_beta(0.1, 0.0, VelocityFilter::butterworth(0.1)?, 128, 1e-7)?;
/// assert_eq!(c.summary.method, "columns");
/// assert!(c.summary.inside && c.note.is_some());
/// # Ok::<(), stabound::Error>(())
/// ```
///
/// # Errors
///
/// As [`super::compare`] and [`compare_on_lines`] (a number of columns outside `2..=`
/// [`MAX_COLUMNS`] is refused whichever engine serves).
pub fn compare_alpha_beta(
    delta: f64,
    d: f64,
    filter: VelocityFilter,
    columns: usize,
    tol: f64,
) -> Result<AlphaBetaComparison> {
    // checked here too: the columns are used only where the exact boundary cannot serve
    let columns = check_columns(columns)?;
    Ok(match super::delay::compare_traced(delta, d, filter, tol)? {
        Ok(c) => AlphaBetaComparison {
            summary: Summary::from(&c),
            note: c
                .stable_fallback
                .map(|why| format!("the stable region is drawn by bisection: {why}")),
            region: c.region,
            stable: c.stable,
        },
        Err(why) => {
            let c = compare_on_lines(delta, d, filter, columns, tol)?;
            AlphaBetaComparison {
                summary: Summary::from(&c),
                note: Some(format!("{why}; compared on {} lines", c.columns)),
                region: c.region,
                stable: c.stable_outline,
            }
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn col(passive: Option<(f64, f64)>, stable: &[(f64, f64)]) -> Column {
        Column {
            x: 0.0,
            passive,
            stable: stable.iter().map(|&(lo, hi)| Interval { lo, hi }).collect(),
        }
    }

    #[test]
    fn interval_pieces() {
        let c = col(Some((0.0, 2.0)), &[(0.0, 0.5), (0.75, 3.0)]);
        assert_eq!(c.uncovered(), Some((0.5, 0.75)));
        assert_eq!(c.stable_outside(), Some((2.0, 3.0)));
        assert!((c.common_len() - 1.75).abs() < 1e-15);
        let c = col(Some((0.0, 1.0)), &[(0.0, 2.0)]);
        assert_eq!(c.uncovered(), None);
        let c = col(None, &[(0.0, 2.0)]);
        assert_eq!(c.stable_outside(), Some((0.0, 2.0)));
        let c = col(Some((0.0, 1.0)), &[]);
        assert_eq!(c.uncovered(), Some((0.0, 1.0)));
    }

    #[test]
    fn polygon_cuts() {
        let tri = [(0.0, -1.0), (2.0, 0.0), (0.0, 1.0), (0.0, -1.0)];
        assert!((polygon_right(&tri, 0.5).unwrap() - 1.0).abs() < 1e-15);
        assert!(polygon_right(&tri, 1.5).is_none());
        let edge = [(4.0, 3.0), (1.0, 0.0), (4.0, -3.0)];
        let (lo, hi) = polyline_left(&edge, 2.0).unwrap();
        assert!((lo + 1.0).abs() < 1e-15 && (hi - 1.0).abs() < 1e-15);
        assert!(polyline_left(&edge, 0.5).is_none());
    }

    /// The witness path on made-up columns (no filtered loop of the families searched has a
    /// passive unstable wall, see the library tests): a column whose passive interval sticks
    /// out of the stable set gives `inside = false` and, once the checks confirm it, the
    /// middle of the uncovered piece as the witness.
    #[test]
    fn witness_path_on_made_up_columns() {
        let crit = Criterion::new(0.0, VelocityFilter::none()).unwrap();
        let region = crit.region_alpha_beta(1.0, 1e-7).unwrap();
        let mut cols: Vec<Column> = (0..5)
            .map(|j| Column {
                x: j as f64 * 0.25,
                ..col(Some((0.0, 1.0)), &[(0.0, 2.0)])
            })
            .collect();
        cols[2].stable = vec![Interval { lo: 0.0, hi: 0.5 }];
        let wall_at = |x: f64, s: f64| Ok((Wall::new(s, x)?, 1.0));
        let checks = |_: &Wall, _: f64| Ok((0.1, 0.2, Verdict::Unstable));
        let plane = ComparePlane::AlphaBeta { delta: 1.0 };
        let c = finish(
            plane,
            &crit,
            cols,
            0.25,
            region,
            &wall_at,
            &checks,
            |x, s| (s, x),
        )
        .unwrap();
        assert!(!c.inside);
        let w = c.passive_unstable.unwrap();
        assert_eq!((w.alpha, w.beta), (0.75, 0.5));
        // the checks do not confirm a stable wall, so no stable-not-passive witness
        assert!(c.stable_not_passive.is_none());
        // stable 2 on four columns and 0.5 on one, trapezoid with h = 0.25
        let stable = 0.25 * (0.5 * 2.0 + 2.0 + 0.5 + 2.0 + 0.5 * 2.0);
        assert!((c.stable_area - stable).abs() < 1e-15);
    }

    #[test]
    fn refuses() {
        let f = VelocityFilter::low_pass(0.5).unwrap();
        assert!(compare_on_lines(1.0, 1.0, f, 1, 1e-7).is_err());
        assert!(compare_on_lines(-1.0, 1.0, f, 16, 1e-7).is_err());
        assert!(compare_on_lines(1.0, 0.5, f, 16, 1e-7).is_err());
        assert!(compare_delta_beta(0.0, 1.0, f, 2.0, 16, 1e-7).is_err());
        assert!(compare_delta_beta(0.5, 1.0, f, 0.0, 16, 1e-7).is_err());
    }
}
