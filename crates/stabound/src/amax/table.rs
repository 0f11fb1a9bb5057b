//! Lookup tables of `alpha_max` over a grid of `delta` by `d`, for firmware, and the one
//! procedure by which firmware reads them ([`AmaxTable::lookup`]).
//!
//! # The lookup procedure
//!
//! A query `(delta, d)` inside the table's range gives a wall `(alpha, beta)`:
//!
//! - `delta` is interpolated linearly: with `j` the first interval
//!   `delta[j] <= delta <= delta[j+1]` and `s = (delta - delta[j]) / (delta[j+1] - delta[j])`,
//!   a value `v` is read as `v[j] + s (v[j+1] - v[j])`.
//! - `d` is **not interpolated** when every `d` of the table is a whole number
//!   ([`Interpolation::Rows`]): the query's `d` must equal one of the table's delays and its
//!   row is read. Otherwise ([`Interpolation::Bilinear`]) `d` is interpolated the same way
//!   between the two rows around it (`u` as `s`, the two row values first, then across).
//! - `alpha` and `beta` are read with the same weights (both from the same nodes).
//! - A query outside the axes (or NaN) is refused, never clamped or extrapolated.
//!
//! Every operation is done in the table's [`Precision`] (`f32` arithmetic for
//! [`Precision::Float`]), in the order written above, as the generated C and Rust lookups do.
//!
//! # Conservative tables
//!
//! A conservative table promises that every wall the procedure yields is stable. The nodes'
//! `alpha` values are lowered (never `beta`) until the stability point test
//! ([`Checker::verdict`], Schur-Cohn with its rounding guard, default margin) finds the wall
//! stable at every query of a dense set: per `delta` interval the nodes, the points
//! `2^-20` inside each end and the 15 points `k/16` between; per `d` interval (bilinear
//! only) the nodes, `2^-20` inside each end and the 7 points `k/8`, in every combination.
//! Because firmware rounds differently (another compiler, fused multiply-adds, the
//! conversion to physical units), each query's wall must stay stable with `alpha` raised and
//! `beta` moved either way by [`GUARD_ULPS`] units of roundoff of the precision times the
//! largest magnitude among the nodes read.
//!
//! At a failing query the largest safe `alpha` at the interpolated `beta` comes from the
//! exact one-dimensional stable set ([`crate::search::stable_alphas`]); every node the query
//! reads is scaled by the ratio of that to the interpolated `alpha` (the lookup is linear in
//! the node values, so the interpolated value is scaled by it too; each node takes the
//! smallest factor asked of it, its lowering made [`CUSHION`] larger for the queries between
//! test points) and the check is repeated until no query fails. Lowering happens only where
//! some query needs it: never along `d` for [`Interpolation::Rows`], where each row is built
//! and checked alone. The test points are a dense sample, not a proof for every real
//! `delta` between them; the tests check the generated C lookup at other points.
//!
//! A table of a loop with elements ([`TableOptions::with_elements`]) is built the same way with that
//! loop's own point test ([`crate::stability::Checker::verdict`]) and stable sets
//! ([`crate::search::stable_alphas`]) at each query's plant.

use rayon::prelude::*;

use super::series::check_rows;
use super::{Amax, AmaxOptions, alpha_max};
use crate::devices::DeviceSet;
use crate::elements::Loop;
use crate::error::{Error, Result};
use crate::params::{Plant, Wall};
use crate::search::{Interval, intersect, stable_alphas};
use crate::stability::{Checker, Options, Verdict};

/// How a lookup reads the table between nodes (module documentation, "The lookup
/// procedure").
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
#[non_exhaustive]
pub enum Interpolation {
    /// Linear in `delta` within one row; `d` must be one of the table's delays. Chosen when
    /// every `d` is a whole number (whole samples of delay, as firmware has).
    Rows,
    /// Bilinear in `(delta, d)`. Chosen when some `d` is not a whole number.
    Bilinear,
}

impl Interpolation {
    /// The procedure for delay axis `ds`: [`Interpolation::Rows`] when every value is whole.
    pub fn for_delays(ds: &[f64]) -> Self {
        // fract() of a whole f64 is exactly 0
        if ds.iter().all(|d| d.fract() == 0.0) {
            Interpolation::Rows
        } else {
            Interpolation::Bilinear
        }
    }

    /// Lower-case name (`rows`, `bilinear`).
    pub fn name(self) -> &'static str {
        match self {
            Interpolation::Rows => "rows",
            Interpolation::Bilinear => "bilinear",
        }
    }
}

/// The floating-point type of the table's values and of its lookup's arithmetic.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
#[non_exhaustive]
pub enum Precision {
    /// IEEE double (`f64`, C `double`).
    #[default]
    Double,
    /// IEEE single (`f32`, C `float`): `alpha` rounded down to `f32` (toward safety),
    /// `beta` and the axes to nearest, the lookup in `f32` arithmetic.
    Float,
}

impl Precision {
    /// Lower-case name (`double`, `float`).
    pub fn name(self) -> &'static str {
        match self {
            Precision::Double => "double",
            Precision::Float => "float",
        }
    }

    /// The unit roundoff `2^-53` or `2^-24`.
    pub fn unit_roundoff(self) -> f64 {
        match self {
            Precision::Double => f64::EPSILON / 2.0,
            Precision::Float => f64::from(f32::EPSILON) / 2.0,
        }
    }

    /// `x` rounded to this precision (to nearest).
    pub(crate) fn round(self, x: f64) -> f64 {
        match self {
            Precision::Double => x,
            Precision::Float => f64::from(x as f32),
        }
    }

    /// `x` rounded down to this precision (the largest representable value `<= x`).
    pub(crate) fn round_down(self, x: f64) -> f64 {
        let r = self.round(x);
        if r <= x {
            return r;
        }
        // one f32 step toward -inf (r is finite here: x is finite and below r)
        let f = r as f32;
        let below = if f > 0.0 {
            f32::from_bits(f.to_bits() - 1)
        } else if f == 0.0 {
            // (exact: zero of either sign; the step below it is the negative subnormal)
            -f32::from_bits(1)
        } else {
            f32::from_bits(f.to_bits() + 1)
        };
        f64::from(below)
    }
}

/// The guard of the conservative check, in units of roundoff of the table's precision: a
/// query's wall must stay stable with `alpha` raised and `beta` moved either way by this many
/// units of roundoff times the largest magnitude among the nodes read.
///
/// The lookup does at most 9 rounded operations per value (two subtractions and a division
/// for each weight, three for each linear step), the stored values are rounded once, and a
/// conversion to or from physical units adds two more; each changes the result by at most
/// one unit of roundoff of the magnitudes involved (the weights lie in `[0, 1]`), so 16
/// covers any order of evaluation a compiler picks, fused multiply-adds included.
pub const GUARD_ULPS: f64 = 16.0;

/// The largest lowering of one row of a conservative table.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[non_exhaustive]
pub struct RowLowering {
    /// The row's delay factor.
    pub d: f64,
    /// The largest `exact - table` value of `alpha_max` in the row.
    pub largest: f64,
    /// The `delta` of that node.
    pub at_delta: f64,
    /// The exact `alpha_max` there.
    pub exact: f64,
    /// The largest `(exact - table) / exact` in the row (0 where `exact` is 0).
    pub largest_relative: f64,
}

/// A lookup table of `alpha_max` and `beta_at_max` over a grid of `delta` by `d`, for
/// firmware (see [`amax_table`] and the module documentation).
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct AmaxTable {
    /// The `delta` axis (ascending).
    pub delta: Vec<f64>,
    /// The `d` axis (ascending).
    pub d: Vec<f64>,
    /// `alpha_max[i_d][i_delta]`; with `conservative`, the lowered values.
    pub alpha_max: Vec<Vec<f64>>,
    /// `beta_at_max[i_d][i_delta]` (never lowered; rounded to the precision).
    pub beta_at_max: Vec<Vec<f64>>,
    /// The exact `alpha_max[i_d][i_delta]` before lowering and rounding.
    pub exact_alpha_max: Vec<Vec<f64>>,
    /// Whether `alpha_max` was lowered so that every lookup yields a stable wall.
    pub conservative: bool,
    /// How the lookup reads between nodes.
    pub interpolation: Interpolation,
    /// The type of the values and of the lookup's arithmetic.
    pub precision: Precision,
    /// The options the values were computed with.
    #[cfg_attr(feature = "serde", serde(skip))]
    pub options: AmaxOptions,
    /// The refinement tolerance in theta used (copy of `options.theta_tol()`, for the record).
    pub tol: f64,
    /// The loop elements modelled (`None`: the paper's loop). Every node and every query of
    /// the conservative check is this loop's elements on that point's plant
    /// ([`Loop::with_plant`]); the loop's own plant is the table's first node.
    #[cfg_attr(feature = "serde", serde(skip))]
    pub elements: Option<Loop>,
    /// The set of devices every wall must hold for ([`TableOptions::with_device_set`]):
    /// `None` for one loop.
    #[cfg_attr(feature = "serde", serde(skip))]
    pub set: Option<DeviceSet>,
    /// The fraction of the (robust) `alpha_max` the nodes hold (`1` unless
    /// [`TableOptions::with_margin`]); the conservative check runs on these values. (The
    /// exports say it in words.)
    #[cfg_attr(feature = "serde", serde(skip))]
    pub margin: f64,
    /// Whether every cell of the table, with the lookup's interpolation and rounding guard,
    /// is proved stable by a table certificate ([`crate::certificate::certify_table`]).
    #[cfg_attr(feature = "serde", serde(skip))]
    pub certified: bool,
}

/// Where a query lies: row `i`, column `j`, and the weights `u` (across rows) and `s`
/// (along the row), each in `[0, 1]`.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Cell {
    i: usize,
    j: usize,
    s: f64,
    u: f64,
}

/// The interval of `axis` holding `x` (the first when `x` is a node) and the weight,
/// computed in `p`; `None` outside the axis or for NaN.
fn locate(axis: &[f64], x: f64, p: Precision) -> Option<(usize, f64)> {
    let (&first, &last) = (axis.first()?, axis.last()?);
    if !(x >= first && x <= last) {
        return None;
    }
    if axis.len() == 1 {
        return Some((0, 0.0));
    }
    let mut j = 0;
    while j + 2 < axis.len() && x > axis[j + 1] {
        j += 1;
    }
    let num = p.round(x - axis[j]);
    let den = p.round(axis[j + 1] - axis[j]);
    Some((j, p.round(num / den)))
}

/// `a + w (b - a)` with every operation rounded to `p`.
fn lerp(a: f64, b: f64, w: f64, p: Precision) -> f64 {
    p.round(a + p.round(w * p.round(b - a)))
}

impl AmaxTable {
    fn cell(&self, delta: f64, d: f64) -> Option<Cell> {
        let p = self.precision;
        let (delta, d) = (p.round(delta), p.round(d));
        let (j, s) = locate(&self.delta, delta, p)?;
        let (i, u) = match self.interpolation {
            // exact comparison on purpose: the query names one of the table's delays
            Interpolation::Rows => (self.d.iter().position(|&x| x == d)?, 0.0),
            Interpolation::Bilinear => locate(&self.d, d, p)?,
        };
        Some(Cell { i, j, s, u })
    }

    fn read(&self, v: &[Vec<f64>], c: Cell) -> f64 {
        let p = self.precision;
        let j1 = (c.j + 1).min(self.delta.len() - 1);
        let i1 = (c.i + 1).min(self.d.len() - 1);
        let row = |i: usize| {
            if j1 == c.j {
                v[i][c.j]
            } else {
                lerp(v[i][c.j], v[i][j1], c.s, p)
            }
        };
        match self.interpolation {
            Interpolation::Rows => row(c.i),
            Interpolation::Bilinear if i1 == c.i => row(c.i),
            Interpolation::Bilinear => lerp(row(c.i), row(i1), c.u, p),
        }
    }

    /// The nodes `(row, column)` a lookup in cell `c` reads.
    fn nodes(&self, c: Cell) -> Vec<(usize, usize)> {
        let j1 = (c.j + 1).min(self.delta.len() - 1);
        let i1 = match self.interpolation {
            Interpolation::Rows => c.i,
            Interpolation::Bilinear => (c.i + 1).min(self.d.len() - 1),
        };
        let mut n = vec![(c.i, c.j), (c.i, j1), (i1, c.j), (i1, j1)];
        n.sort_unstable();
        n.dedup();
        n
    }

    /// The wall `(alpha, beta)` the table's lookup procedure yields at `(delta, d)` (module
    /// documentation), computed in the table's precision; `None` outside the table's range
    /// (and, for [`Interpolation::Rows`], for a `d` that is not one of the table's delays).
    ///
    /// For a conservative table the wall is stable.
    ///
    /// ```
    /// use stabound::amax::{AmaxOptions, TableOptions, amax_table};
    /// use stabound::{Checker, Plant, Verdict, Wall};
    ///
    /// let opts = TableOptions::new(AmaxOptions::default()).with_conservative(true);
    /// let t = amax_table(&[0.0, 0.5, 1.0], &[1.0], &opts)?;
    /// let (alpha, beta) = t.lookup(0.3, 1.0).unwrap();
    /// let checker = Checker::new(&Plant::new(0.3, 1.0)?, Default::default())?;
    /// assert_eq!(checker.verdict(&Wall::new(alpha, beta)?)?, Verdict::Stable);
    /// assert!(t.lookup(1.5, 1.0).is_none()); // outside the delta axis: refused
    /// # Ok::<(), stabound::Error>(())
    /// ```
    pub fn lookup(&self, delta: f64, d: f64) -> Option<(f64, f64)> {
        let c = self.cell(delta, d)?;
        Some((
            self.read(&self.alpha_max, c),
            self.read(&self.beta_at_max, c),
        ))
    }

    /// The largest lowering of every row below the margin's share of the exact value (all
    /// zero for a table that is not conservative, except for the rounding of
    /// [`Precision::Float`]).
    pub fn lowering(&self) -> Vec<RowLowering> {
        self.d
            .iter()
            .zip(self.alpha_max.iter().zip(&self.exact_alpha_max))
            .map(|(&d, (row, exact))| {
                let mut out = RowLowering {
                    d,
                    largest: 0.0,
                    at_delta: self.delta[0],
                    exact: exact[0],
                    largest_relative: 0.0,
                };
                for ((&x, &v), &e) in self.delta.iter().zip(row).zip(exact) {
                    // the nodes' target is the margin's share of the exact value (exact for
                    // no margin: 1 x e is e)
                    let e = self.margin * e;
                    let low = e - v;
                    if low > out.largest {
                        (out.largest, out.at_delta, out.exact) = (low, x, e);
                    }
                    if e > 0.0 {
                        out.largest_relative = out.largest_relative.max(low / e);
                    }
                }
                out
            })
            .collect()
    }

    /// How many queries the conservative check tests (module documentation); 0 for a table
    /// that is not conservative.
    pub fn checked_queries(&self) -> usize {
        if self.conservative {
            self.test_points().len()
        } else {
            0
        }
    }

    /// The query points of the conservative check.
    fn test_points(&self) -> Vec<(f64, f64)> {
        let p = self.precision;
        let fine: Vec<f64> = weights(16);
        let coarse: Vec<f64> = weights(8);
        let along = |axis: &[f64], ws: &[f64]| -> Vec<f64> {
            if axis.len() == 1 {
                return axis.to_vec();
            }
            let mut out = Vec::new();
            for w in axis.windows(2) {
                for &t in ws {
                    out.push(p.round(w[0] + t * (w[1] - w[0])));
                }
            }
            out
        };
        let xs = along(&self.delta, &fine);
        let ds = match self.interpolation {
            Interpolation::Rows => self.d.clone(),
            Interpolation::Bilinear => along(&self.d, &coarse),
        };
        ds.iter()
            .flat_map(|&d| xs.iter().map(move |&x| (x, d)))
            .collect()
    }
}

/// `0`, `2^-20`, `k/n` for `0 < k < n`, `1 - 2^-20` and `1`.
fn weights(n: u32) -> Vec<f64> {
    let near = 2f64.powi(-20);
    let mut w = vec![0.0, near];
    w.extend((1..n).map(|k| f64::from(k) / f64::from(n)));
    w.extend([1.0 - near, 1.0]);
    w
}

/// The point test of one query: the [`Checker`] of the table's loop at the query's plant
/// (default options, as the module documentation says), with its exact stable sets; for a
/// set of devices, the checkers of its sampled members with their wall scales `m_ref / m`
/// (the set's reference normalization, docs/MODEL.md section 12).
// one per query, on the stack: the paper's checker stays inline as in `Checker` (no
// allocation per query of the paper's table)
#[allow(clippy::large_enum_variant)]
enum PointTest {
    One(Checker),
    Set(Vec<(Checker, f64)>),
}

impl PointTest {
    /// The test at `(delta, d)` of table `t`.
    fn at(t: &AmaxTable, delta: f64, d: f64) -> Result<Self> {
        let plant = Plant::new(delta, d)?;
        if let Some(set) = &t.set {
            let at = set.at_plant(delta, d)?;
            let m_ref = at.reference().device().mass();
            return Ok(PointTest::Set(
                at.sampled_members()
                    .into_iter()
                    .map(|m| {
                        let c = Checker::new(m.to_loop()?, Options::default())?;
                        Ok((c, m_ref / m.device().mass()))
                    })
                    .collect::<Result<_>>()?,
            ));
        }
        let checker = match &t.elements {
            None => Checker::new(plant, Options::default())?,
            Some(lp) => Checker::new(lp.with_plant(plant)?, Options::default())?,
        };
        Ok(PointTest::One(checker))
    }

    fn verdict(&self, wall: &Wall) -> Result<Verdict> {
        match self {
            PointTest::One(c) => c.verdict(wall),
            PointTest::Set(members) => {
                for (c, s) in members {
                    let v = c.verdict(&Wall::new(wall.alpha * s, wall.beta * s)?)?;
                    if v != Verdict::Stable {
                        return Ok(v);
                    }
                }
                Ok(Verdict::Stable)
            }
        }
    }

    /// The stable `alpha` at `beta`, sorted open intervals ([`stable_alphas`]; for a set,
    /// the intersection over its sampled members).
    fn stable_alphas(&self, beta: f64) -> Result<Vec<Interval>> {
        match self {
            PointTest::One(c) => stable_alphas(c, beta),
            PointTest::Set(members) => {
                let mut common: Option<Vec<Interval>> = None;
                for (c, s) in members {
                    let mine: Vec<Interval> = stable_alphas(c, beta * s)?
                        .into_iter()
                        .map(|i| Interval {
                            lo: i.lo / s,
                            hi: i.hi / s,
                        })
                        .collect();
                    common = Some(match common {
                        None => mine,
                        Some(c) => intersect(&c, &mine),
                    });
                }
                Ok(common.unwrap_or_default())
            }
        }
    }
}

/// Whether the wall and its guard walls are stable (module documentation).
fn guarded_stable(checker: &PointTest, alpha: f64, beta: f64, ga: f64, gb: f64) -> Result<bool> {
    for (a, b) in [
        (alpha, beta),
        (alpha + ga, beta - gb),
        (alpha + ga, beta + gb),
    ] {
        if checker.verdict(&Wall::new(a, b)?)? != Verdict::Stable {
            return Ok(false);
        }
    }
    Ok(true)
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

/// Evaluates `alpha_max` on every `(d, delta)` of `points` in parallel, in order: of the
/// paper's loop or, with `elements`, of that loop on each point's plant ([`alpha_max`]).
fn eval_points(
    points: &[(f64, f64)],
    opts: &AmaxOptions,
    elements: Option<&Loop>,
    set: Option<&DeviceSet>,
) -> Result<Vec<Amax>> {
    points
        .par_iter()
        .map(|&(d, delta)| {
            crate::cancel::poll()?;
            let plant = Plant::new(delta, d)?;
            if let Some(set) = set {
                // the wall shown stable for every member (docs/MODEL.md section 12)
                return set.at_plant(delta, d)?.robust_node(opts);
            }
            match elements {
                None => alpha_max(plant, opts),
                Some(lp) => alpha_max(lp.with_plant(plant)?, opts),
            }
        })
        .collect()
}

/// A node of a table over a set of devices: the set's robust `alpha_max` on the node's plant,
/// its verified stiffness ([`crate::robust::robust_alpha_max`], docs/MODEL.md section 12).
/// The robust layer implements it (`robust/table.rs`): that layer builds on `alpha_max`, so
/// the table names the set ([`DeviceSet`], a description below both) and takes its robust
/// solver through this interface rather than import it.
pub(crate) trait RobustNode {
    /// The node's wall, shown stable for every member of the set.
    fn robust_node(&self, opts: &AmaxOptions) -> Result<Amax>;
}

/// The most rounds of lowering before the construction gives up: the first round takes off
/// what the exact stable sets ask for, later ones only the rounding of the lowered values.
const MAX_ROUNDS: usize = 12;

/// Each lowering is made this fraction larger than the failing test point asks for, for the
/// queries between test points.
///
/// The shortfall of a linear interpolation under a curved stable limit is largest between
/// test points; for a smooth limit the largest value between two of the 17 points of an
/// interval exceeds the largest sampled one by well under 1 % of the lowering, but where the
/// rightmost point of the stable region changes kind inside an interval (a smooth maximum
/// turning into a corner) the limit has a kink, and queries at 37 steps per interval found
/// shortfalls 0.1 % above the sampled ones. 10 % covers that with room.
pub const CUSHION: f64 = 0.1;

/// What an [`amax_table`] is built from besides its axes: the `alpha_max` options, whether
/// the table is conservative (module documentation), the precision of its values and lookup,
/// and the elements every node's loop carries. Built with [`TableOptions::new`] and the
/// `with_` methods; valid by construction.
///
/// ```
/// use stabound::amax::{AmaxOptions, Precision, TableOptions};
///
/// let opts = TableOptions::new(AmaxOptions::default())
///     .with_conservative(true)
///     .with_precision(Precision::Float);
/// assert!(opts.conservative() && opts.elements().is_none());
/// ```
#[derive(Debug, Clone, PartialEq, Default)]
#[non_exhaustive]
pub struct TableOptions {
    amax: AmaxOptions,
    conservative: bool,
    precision: Precision,
    elements: Option<Loop>,
    set: Option<DeviceSet>,
    margin: Option<f64>,
}

impl TableOptions {
    /// A plain table of the paper's loop in [`Precision::Double`] with the `alpha_max`
    /// options `amax`.
    pub fn new(amax: AmaxOptions) -> Self {
        Self {
            amax,
            ..Self::default()
        }
    }

    /// The same options, conservative or not (module documentation).
    pub fn with_conservative(mut self, conservative: bool) -> Self {
        self.conservative = conservative;
        self
    }

    /// The same options in `precision`.
    pub fn with_precision(mut self, precision: Precision) -> Self {
        self.precision = precision;
        self
    }

    /// The same options with the elements of `lp` on every node: each node's loop is `lp` on
    /// that node's plant ([`Loop::with_plant`]); `lp`'s own plant is not used. A loop with no
    /// element leaves the paper's loop.
    pub fn with_elements(mut self, lp: impl Into<Loop>) -> Self {
        let lp = lp.into();
        self.elements = (!lp.is_paper()).then_some(lp);
        self
    }

    /// The same options for a set of devices: every node is the set's robust `alpha_max`
    /// ([`crate::robust::robust_alpha_max`], its verified stiffness) on that node's plant
    /// ([`DeviceSet::at_plant`]: the table's axes give the damping and the delay), and a
    /// conservative table's every query is tested on a sample of the set's members
    /// ([`DeviceSet::sampled_members`]: every member of a finite set; three values of each
    /// interval in every combination, or its corners beyond three intervals). Replaces
    /// [`TableOptions::with_elements`] (the reference member's elements are recorded).
    pub fn with_device_set(mut self, set: DeviceSet) -> Self {
        self.set = Some(set);
        self
    }

    /// The same options with the nodes at `margin` (in `(0, 1]`) of `alpha_max` (the damping
    /// left where the maximum is reached, as [`super::margin_wall`] does); the conservative
    /// check runs on these walls.
    ///
    /// # Errors
    ///
    /// A margin outside `(0, 1]`.
    pub fn with_margin(mut self, margin: f64) -> Result<Self> {
        super::margin::check_margin(margin)?;
        self.margin = Some(margin);
        Ok(self)
    }

    /// The set of devices, if any.
    pub fn device_set(&self) -> Option<&DeviceSet> {
        self.set.as_ref()
    }

    /// The `alpha_max` options.
    pub fn amax(&self) -> &AmaxOptions {
        &self.amax
    }

    /// Whether the table is conservative.
    pub fn conservative(&self) -> bool {
        self.conservative
    }

    /// The precision of the values and the lookup.
    pub fn precision(&self) -> Precision {
        self.precision
    }

    /// The elements every node carries; `None` for the paper's loop.
    pub fn elements(&self) -> Option<&Loop> {
        self.elements.as_ref()
    }
}

/// `alpha_max` and `beta_at_max` on the grid `deltas x ds` (rayon; identical for any thread
/// count since every value is computed independently and collected in order), in the
/// precision of `options`, read by the procedure [`Interpolation::for_delays`] picks.
///
/// With elements ([`TableOptions::with_elements`]) every node is `alpha_max` of the loop on
/// that node's plant (the theta tolerance of the options is the paper engine's), and a
/// conservative table's every query is tested with that loop's own point test
/// ([`crate::stability::Checker::verdict`], default options) and lowered by its stable sets
/// ([`crate::search::stable_alphas`]). Only the elements of the loop are used.
///
/// ```
/// use stabound::amax::{AmaxOptions, TableOptions, amax_table};
/// use stabound::elements::Loop;
/// use stabound::stability::Checker;
/// use stabound::filter::VelocityFilter;
/// use stabound::{Plant, Verdict, Wall};
///
/// let opts = TableOptions::new(AmaxOptions::default()).with_conservative(true);
/// let lp = Loop::new(Plant::new(0.0, 1.0)?).with_filter(VelocityFilter::low_pass(0.8)?)?;
/// let t = amax_table(&[0.0, 0.5], &[1.0], &opts.clone().with_elements(lp))?;
/// let bare = amax_table(&[0.0, 0.5], &[1.0], &opts)?;
/// // the filter's lag lowers the largest stable stiffness
/// assert!(t.alpha_max[0][1] < bare.alpha_max[0][1]);
/// let (alpha, beta) = t.lookup(0.25, 1.0).unwrap();
/// let at = Checker::new(&lp.with_plant(Plant::new(0.25, 1.0)?)?, Default::default())?;
/// assert_eq!(at.verdict(&Wall::new(alpha, beta)?)?, Verdict::Stable);
/// # Ok::<(), stabound::Error>(())
/// ```
///
/// # Errors
///
/// An axis that is empty, unsorted, repeated or outside the plant's ranges; more than
/// [`super::MAX_ROWS`] nodes; the errors of `alpha_max` at a node and of
/// [`Loop::with_plant`] at a node or query (a polynomial of too high a degree for a long
/// delay).
pub fn amax_table(deltas: &[f64], ds: &[f64], options: &TableOptions) -> Result<AmaxTable> {
    check_axis("delta", deltas)?;
    check_axis("d", ds)?;
    let reference = match &options.set {
        Some(set) => Some(set.at_plant(deltas[0], ds[0])?.reference().to_loop()?),
        None => None,
    };
    let elements = match &reference {
        Some(lp) => (!lp.is_paper()).then_some(lp),
        None => options.elements.as_ref(),
    };
    build(deltas, ds, options, elements)
}

fn build(
    deltas: &[f64],
    ds: &[f64],
    options: &TableOptions,
    elements: Option<&Loop>,
) -> Result<AmaxTable> {
    let (opts, conservative, precision) = (&options.amax, options.conservative, options.precision);
    let margin = options.margin.unwrap_or(1.0);
    check_axis("delta", deltas)?;
    check_axis("d", ds)?;
    check_rows(deltas.len().saturating_mul(ds.len()))?;
    for &d in ds {
        Plant::new(0.0, d)?;
    }
    for &delta in deltas {
        Plant::new(delta, 0.0)?;
    }
    let p = precision;
    let nx = deltas.len();
    let grid: Vec<(f64, f64)> = ds
        .iter()
        .flat_map(|&d| deltas.iter().map(move |&x| (d, x)))
        .collect();
    let vals = eval_points(&grid, opts, elements, options.set.as_ref())?;
    let exact: Vec<Vec<f64>> = vals
        .chunks(nx)
        .map(|r| r.iter().map(|a| a.alpha_max).collect())
        .collect();
    let round_all = |v: &[Vec<f64>], f: &dyn Fn(f64) -> f64| -> Vec<Vec<f64>> {
        v.iter()
            .map(|r| r.iter().map(|&x| f(x)).collect())
            .collect()
    };
    let beta: Vec<Vec<f64>> = vals
        .chunks(nx)
        .map(|r| r.iter().map(|a| p.round(a.beta_at_max)).collect())
        .collect();
    let alpha = if conservative {
        round_all(&exact, &|x| p.round_down(margin * x))
    } else {
        round_all(&exact, &|x| p.round(margin * x))
    };
    let mut t = AmaxTable {
        delta: deltas.iter().map(|&x| p.round(x)).collect(),
        d: ds.iter().map(|&x| p.round(x)).collect(),
        alpha_max: alpha,
        beta_at_max: beta,
        exact_alpha_max: exact,
        conservative,
        interpolation: Interpolation::for_delays(ds),
        precision,
        options: *opts,
        tol: opts.theta_tol(),
        elements: match elements {
            Some(lp) => Some(lp.with_plant(Plant::new(deltas[0], ds[0])?)?),
            None => None,
        },
        set: options.set.clone(),
        margin,
        certified: false,
    };
    if p == Precision::Float {
        check_axis("delta (in single precision)", &t.delta)?;
        check_axis("d (in single precision)", &t.d)?;
    }
    if conservative {
        make_conservative(&mut t)?;
    }
    Ok(t)
}

/// Lowers `t.alpha_max` until every test point's wall passes [`guarded_stable`].
fn make_conservative(t: &mut AmaxTable) -> Result<()> {
    let p = t.precision;
    let points = t.test_points();
    let g = GUARD_ULPS * p.unit_roundoff();
    for _ in 0..MAX_ROUNDS {
        crate::cancel::poll()?;
        let table = &*t;
        // (nodes, factor) of every failing query
        let short: Vec<Lowering> = points
            .par_iter()
            .map(|&(x, d)| shortfall(table, x, d, g))
            .collect::<Result<Vec<_>>>()?
            .into_iter()
            .flatten()
            .collect();
        if short.is_empty() {
            return Ok(());
        }
        let mut scale = vec![vec![1.0f64; t.delta.len()]; t.d.len()];
        for (nodes, f) in &short {
            for &(r, c) in nodes {
                scale[r][c] = scale[r][c].min(*f);
            }
        }
        for (row, sc) in t.alpha_max.iter_mut().zip(&scale) {
            for (v, &f) in row.iter_mut().zip(sc) {
                if f < 1.0 {
                    *v = p.round_down(*v * (1.0 - (1.0 - f) * (1.0 + CUSHION)));
                }
            }
        }
    }
    Err(Error::Numerical(format!(
        "the lookup table could not be made conservative in {MAX_ROUNDS} rounds of lowering; use a finer delta axis"
    )))
}

/// The nodes `(row, column)` one failing query reads, and the factor they must be scaled by.
type Lowering = (Vec<(usize, usize)>, f64);

/// `None` when the query's wall passes the guarded check; otherwise the nodes it reads and
/// the factor in `(0, 1)` its `alpha` must be scaled by. Scaling every node read by that
/// factor scales the interpolated value by it (the lookup is linear in the node values), so
/// the lowering is shared in proportion to the nodes' values and never makes one negative.
fn shortfall(t: &AmaxTable, x: f64, d: f64, g: f64) -> Result<Option<Lowering>> {
    let Some(c) = t.cell(x, d) else {
        return Err(Error::Numerical(format!(
            "a test point (delta = {x}, d = {d}) of the lookup table is outside its range"
        )));
    };
    let (alpha, beta) = (t.read(&t.alpha_max, c), t.read(&t.beta_at_max, c));
    let nodes = t.nodes(c);
    let ga = g * nodes
        .iter()
        .map(|&(r, k)| t.alpha_max[r][k].abs())
        .fold(0.0, f64::max);
    let gb = g * nodes
        .iter()
        .map(|&(r, k)| t.beta_at_max[r][k].abs())
        .fold(0.0, f64::max);
    let checker = PointTest::at(t, x, d)?;
    if guarded_stable(&checker, alpha, beta, ga, gb)? {
        return Ok(None);
    }
    let too_coarse = || {
        Error::InvalidRequest(format!(
            "the lookup table cannot be made conservative at delta = {x}, d = {d}: no stiffness is stable at the interpolated damping beta = {beta}; use a finer grid"
        ))
    };
    // also refuses NaN
    if alpha.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
        return Err(too_coarse());
    }
    let safe = |a: f64| guarded_stable(&checker, a, beta, ga, gb);
    // The exact end of the stable interval that lowering alpha reaches (the last one
    // starting below alpha), then a step down from it until the guarded check passes: the
    // end itself is marginal, and the verdict's margin and the guard need a little room.
    let top = checker
        .stable_alphas(beta)?
        .iter()
        .rev()
        .find(|i| i.lo < alpha)
        .map(|i| (i.lo, i.hi));
    if let Some((lo, hi)) = top {
        let hi = hi.min(alpha);
        let mut step = (hi.abs() * 1e-10).max(ga).max(f64::MIN_POSITIVE);
        while hi - ga - step > lo.max(0.0) {
            let a = hi - ga - step;
            if safe(a)? {
                // a little more than the difference: the lowered nodes are rounded again
                return Ok(Some((nodes, (a - 2.0 * ga) / alpha)));
            }
            step *= 2.0;
        }
    }
    // The exact search found no usable end (it can miss the interval where the crossing
    // polynomial is ill-conditioned, as for delays a tiny fraction of a sample): bisection
    // with the point test between a stable stiffness, found by halving, and alpha.
    let mut lo = alpha;
    for _ in 0..60 {
        lo *= 0.5;
        if safe(lo)? {
            break;
        }
    }
    if lo.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) || !safe(lo)? {
        return Err(too_coarse());
    }
    let mut hi = alpha;
    // 60 halvings of a bracket no wider than alpha reach the spacing of f64 near alpha
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if safe(mid)? {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Ok(Some((nodes, (lo - 2.0 * ga) / alpha)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_down_is_below_and_adjacent() {
        for x in [0.1, 1.0 / 3.0, 14446.934922605, -0.7, 1e-30, 0.0] {
            let r = Precision::Float.round_down(x);
            assert!(r <= x, "{x}: {r}");
            // the next f32 up is above x: r is the largest f32 not above x
            let f = r as f32;
            // exact comparisons: stepping one f32 representation up
            let up = if f >= 0.0 {
                f32::from_bits(if f == 0.0 { 1 } else { f.to_bits() + 1 })
            } else {
                f32::from_bits(f.to_bits() - 1)
            };
            assert!(f64::from(up) > x, "{x}: {r} {up}");
            // exact: a double is its own double rounding
            assert_eq!(Precision::Double.round_down(x), x);
        }
    }

    #[test]
    fn delay_axis_picks_procedure() {
        assert_eq!(Interpolation::for_delays(&[1.0, 2.0]), Interpolation::Rows);
        assert_eq!(
            Interpolation::for_delays(&[0.0, 0.5, 1.0]),
            Interpolation::Bilinear
        );
    }
}
