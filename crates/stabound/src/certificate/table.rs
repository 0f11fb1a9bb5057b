//! Certified lookup tables: every wall a conservative table's lookup procedure yields, for
//! every `delta` of its range (not sampled queries), proved stable (`docs/MODEL.md`
//! section 11).
//!
//! A cell is one `delta` interval `[X[j], X[j+1]]` of one row `d`. A query at
//! `delta = X[j] + s (X[j+1] - X[j])`, `s` in `[0, 1]`, reads the wall
//! `(A[j] + s (A[j+1] - A[j]), B[j] + s (B[j+1] - B[j]))` ([`AmaxTable::lookup`]); firmware
//! rounds it, and the conservative check allows for that by a guard of [`GUARD_ULPS`] units
//! of roundoff of the table's precision times the largest node read. The cell's set of walls
//! is therefore the segment in `(delta, alpha, beta)` over `s` in `[0, 1]`, widened by the
//! guard either way in `alpha` and `beta` (times their largest node) and in `delta` (times
//! the larger axis value: the query's `delta` is rounded before `s` is computed, so the wall
//! read belongs to a `delta` a few units of roundoff away).
//!
//! That set is covered by boxes: for `s` in `[s0, s1]`, `delta` lies in
//! `[X[j] + s0 h, X[j] + s1 h]` and `alpha`, `beta` between their values at `s0` and `s1`
//! (linear in `s`), each widened by its guard. The paper's loop's coefficients are enclosed over
//! the `delta` interval (the discretization's values decrease in `delta`) and are affine in
//! the wall, so the box certificate's recursion (the `region` module) proves every wall of the
//! box stable. A loop with elements is enclosed over the `delta` interval by its sampled
//! device with `delta` an interval (the `device` module: the matrix exponential by Taylor with
//! a rigorous remainder, in interval arithmetic); the other elements' normalized values do not
//! depend on the damping. A box that the recursion leaves undecided is tried around its
//! centre wall (with the paper's loop, only in a cell that the recursion alone lowers by more
//! than 1 %: see below), as a box certificate's leaf (the `circle` module): the recursion on the loop
//! at the centre wall and the middle of the `delta` interval proves its count of roots
//! outside, and Rouché on arcs of the unit circle proves for each `delta` of the interval that
//! no wall of the box lets a root cross it. The interval recursion over a box loses the
//! coefficients' correlation at each of its steps, so it needs boxes the narrower the higher
//! the degree: at a delay of 10 samples (degree 13) a box of walls 6 % inside the unit circle
//! is decided at a relative width of `2e-4` in `alpha` (`delta` fixed), not at `2e-3`, and
//! 16,384 boxes did not prove a cell (the paper's loop over `delta` 0.5 to 1) even lowered
//! to 1/8. Rouché's bound grows only with the sum of the coefficients' widths, and proves
//! that cell with some 230 boxes lowered 3 %. At low degree the recursion decides the paper's
//! loop's boxes cheaply, and the centred test tried there as well lowers cells less but
//! proves walls nearer the boundary with many more boxes (the 101 x 2 table of `delta` 0.5
//! to 1.5 at one and two samples: lowered 0.02 % instead of 0.81 %, but 7 times the time and
//! 3 times the certificate), so a cell of the paper's loop takes the centred test only where
//! the recursion alone lowers it by more than 1 % (or fails it), and then only if the centred
//! test lowers it less (`RECURSION_KEPT`). Undecided boxes are halved in `s`, breadth
//! first, up to a budget of boxes per cell. A cell that is not proved is lowered: both its `alpha` nodes scaled by a factor from
//! `1 - 2^-40` down to 1/8 (a bisection over a ladder of factors for the least lowering that
//! proves it), rounded down to the table's precision. Lowering is not always easier: near
//! `alpha = 0` (`z = 1` a root) walls are hard to prove too, so the bisection's far end is
//! the first of 3/4, 1/2, 1/4, 1/8 that proves the cell. Where no factor proves the cell
//! (a wide cell, whose boxes' enclosures are wide at any wall), the budget grows before any
//! node is lowered: the cell's nodes as they are are tried with the budget doubled, up to
//! [`CELL_BOXES_CAP`], and only where that fails the ladder with the budget doubled again. A
//! table proved within the budget given is unchanged by this. A node
//! shared by two cells takes the lower value, and every cell is proved again with the
//! lowered nodes, until a round lowers nothing.
//!
//! The certificate holds the table (axes, nodes, precision and guard as hex floats, the
//! loop's elements as normalized values) and, for every cell, its boxes by their `s` range
//! with their coefficient and reflection enclosures (and a centred box's centre and arcs).
//! The checker recomputes each box from the nodes in exact arithmetic, checks that the boxes'
//! `s` ranges tile `[0, 1]`, recomputes the enclosures and replays the recursion and arcs.
//!
//! Covered: one loop, the paper's or with elements (hand, transmission, actuator lag,
//! velocity filter), or a finite set of devices of one mass (a hand that can let go, lists
//! of element values): every member's cells are proved with the one table, a node taking
//! the lowest value any member's cell asks for, and the certificate (kind `set`, the
//! `set` module) names the set as each element's alternatives and holds every member's
//! table certificate; tables whose delays are not interpolated (whole delays, or one row). Sets
//! with intervals or several masses, and delays interpolated between rows, are refused:
//! their enclosures over an interval of device parameters or of `d` are not built here.

use std::collections::VecDeque;
use std::fmt::Write as _;

use rayon::prelude::*;

use super::circle::around_centre;
use super::device::{DeviceSpread, parts_over};
use super::interval::Interval;
use super::schur::recursion;
use super::set::{Alternatives, product_order, set_json, set_loops};
use super::{balls, head, hex, list_json, paper_parts_over, reflection_balls, seal};
use crate::amax::{AmaxTable, GUARD_ULPS, Interpolation};
use crate::devices::DeviceSet;
use crate::elements::Loop;
use crate::error::{Error, Result};
use crate::params::Plant;

/// How much an enclosure over a range of `delta` is widened, relative to its width, before
/// a claim is made on it ([`super::Parts::widened`]).
const WRAPPING: f64 = 1.0 / 64.0;

/// The factors a cell's `alpha` nodes are scaled by when it is not proved, least lowering
/// first: `1 - 2^-k` (exact in `f64`) from about `1e-12`, the closest to the boundary the
/// enclosures decide, down to 3/4, then 1/2, 1/4 and 1/8. Boxes around walls that close to the boundary must be
/// small (a box's enclosure widens with its range of `delta`, and the recursion amplifies the
/// width near the unit circle), so a budget of boxes buys a lowering: the search bisects this
/// ladder for the first factor that proves the cell.
const LADDER: [f64; 16] = [
    1.0 - 1.0 / (1u64 << 40) as f64,
    1.0 - 1.0 / (1u64 << 30) as f64,
    1.0 - 1.0 / (1u64 << 20) as f64,
    1.0 - 1.0 / 4096.0,
    1.0 - 1.0 / 1024.0,
    1.0 - 1.0 / 512.0,
    1.0 - 1.0 / 256.0,
    1.0 - 1.0 / 128.0,
    1.0 - 1.0 / 64.0,
    1.0 - 1.0 / 32.0,
    1.0 - 1.0 / 16.0,
    1.0 - 1.0 / 8.0,
    1.0 - 1.0 / 4.0,
    0.5,
    0.25,
    0.125,
];

/// Rounds of proving and lowering: each round proves every cell with the nodes of the
/// round before; a node is lowered again only when a neighbouring cell asks for more.
const MAX_ROUNDS: usize = 8;

/// The boxes of one cell, by default. Measured on the paper's loop with a `delta` axis of
/// step 0.01: a cell near `delta = 0.5` (`d = 2`) is proved by 256 boxes lowered 1 %, by 39
/// lowered 5 %; near `delta = 0` it takes 256 boxes lowered 20 % (`docs/performance.md`).
pub const DEFAULT_CELL_BOXES: usize = 256;

/// The most boxes a cell's budget grows to where no lowering proves the cell within the
/// budget given (doubling from it; a budget given above this is not grown). A filtered
/// device's table of four cells over `delta` 0 to 2 (0.1 kg at 1 ms, one sample, a 30 Hz
/// low-pass) needs 361 to 2,697 boxes a cell, whichever its nodes' lowering; this leaves room
/// for cells some times wider. The standalone checker replays about 10 such boxes a second,
/// so a cell at this cap takes it about half an hour (`docs/performance.md`).
pub const CELL_BOXES_CAP: usize = 16384;

/// One box of a cell: its range of `s`, its coefficients' and reflections' enclosures (for
/// a box decided around its centre: at the centre wall and the middle of its `delta`
/// range), and for such a box the centre wall, that `delta`, the ends of the arcs and the
/// enclosures at the centre wall over the box's `delta` range.
#[derive(Debug, Clone)]
struct Leaf {
    s: (f64, f64),
    coefficients: Vec<(f64, f64)>,
    reflections: Vec<(f64, f64)>,
    around: Option<Around>,
}

/// A box decided around its centre (see [`Leaf`]).
#[derive(Debug, Clone)]
struct Around {
    centre: (f64, f64),
    delta: f64,
    arcs: Vec<f64>,
    family: Vec<(f64, f64)>,
}

/// A cell's nodes: the `delta` ends, the `alpha` and `beta` values at them, and the row's `d`.
#[derive(Debug, Clone, Copy)]
struct Nodes {
    x: (f64, f64),
    a: (f64, f64),
    b: (f64, f64),
    d: f64,
}

/// A table whose every cell is proved stable, with its certificate (see the module
/// documentation).
///
/// ```
/// use stabound::amax::{AmaxOptions, TableOptions, amax_table};
/// use stabound::certificate::{DEFAULT_CELL_BOXES, certify_table};
///
/// let opts = TableOptions::new(AmaxOptions::default()).with_conservative(true);
/// let table = amax_table(&[0.5, 0.75, 1.0], &[1.0], &opts)?;
/// let cert = certify_table(&table, DEFAULT_CELL_BOXES)?;
/// assert!(cert.table().certified);
/// // lowering only where a proof needs it, never above the conservative values
/// assert!(cert.table().alpha_max[0][1] <= table.alpha_max[0][1]);
/// assert!(cert.to_json().contains("\"verdict\": \"stable\""));
/// # Ok::<(), stabound::Error>(())
/// ```
#[derive(Debug, Clone)]
pub struct TableCertificate {
    table: AmaxTable,
    /// Every member's loop at the table's first node (the model and elements the certificate
    /// names) with the `(row, column, boxes)` of every cell, row after row: one member for a
    /// table of one loop.
    members: Vec<(Loop, Vec<Cell>)>,
    /// For a table over a set of devices, the set: each element's alternatives as
    /// certificate inputs (`"none"` where a member lacks it), the members being every
    /// combination of them in order.
    set: Option<Alternatives>,
    guard: f64,
    /// The cells whose budget grew past the one given and the largest budget a cell had.
    grown: (usize, usize),
}

/// A cell's row, column and the boxes proving it.
type Cell = (usize, usize, Vec<Leaf>);

/// Proves every cell of the conservative table `table` stable, lowering the `alpha` nodes of
/// cells that are not proved (module documentation), with at most `max_boxes` boxes per
/// cell; a cell that no lowering proves within them has its budget doubled until one does,
/// up to [`CELL_BOXES_CAP`] ([`TableCertificate::grown`] says which). The table returned
/// ([`TableCertificate::table`]) is `table` with those nodes lowered and marked
/// [`AmaxTable::certified`].
///
/// # Errors
///
/// [`Error::InvalidRequest`] for a table that is not conservative, is built for a set of
/// devices with an interval or several masses, or interpolates its delays; [`Error::InvalidParameter`] for a budget of 0
/// boxes; [`Error::Numerical`] naming the cells that no lowering within the ladder proves
/// within the largest budget;
/// [`Error::Cancelled`] when cancelled.
pub fn certify_table(table: &AmaxTable, max_boxes: usize) -> Result<TableCertificate> {
    let refuse = |what: &str| {
        Err(Error::InvalidRequest(format!(
            "a certified table {what}; certify a conservative table of one loop or a finite set of devices, with whole delays (or one delay)"
        )))
    };
    if !table.conservative {
        return refuse("starts from a conservative table");
    }
    if table.interpolation != Interpolation::Rows && table.d.len() > 1 {
        return refuse("cannot interpolate between delays");
    }
    if max_boxes == 0 {
        return Err(Error::InvalidParameter {
            name: "max_boxes",
            value: 0.0,
            expected: "a budget of at least one box per cell".into(),
        });
    }
    let mut t = table.clone();
    let plant = Plant::new(t.delta[0], t.d[0])?;
    // every member's loop at the first node, and its name in messages
    let members: Vec<(Loop, String)> = match &t.set {
        None => vec![(
            match &t.elements {
                Some(e) => e.with_plant(plant)?,
                None => Loop::new(plant),
            },
            String::new(),
        )],
        Some(set) => set_members(set, &t)?,
    };
    // the elements each cell's loop carries (none for the paper's loop)
    let elements: Vec<Option<Loop>> = members
        .iter()
        .map(|(lp, _)| (!lp.is_paper()).then_some(*lp))
        .collect();
    let guard = GUARD_ULPS * t.precision.unit_roundoff();
    let columns = t.delta.len().saturating_sub(1).max(1);
    let cells: Vec<(usize, usize, usize)> = (0..members.len())
        .flat_map(|m| (0..t.d.len()).flat_map(move |i| (0..columns).map(move |j| (m, i, j))))
        .collect();
    let cap = max_boxes.max(CELL_BOXES_CAP);
    // every cell's budget: the one given, or the one it grew to when no lowering proved it
    let mut budgets = vec![max_boxes; cells.len()];
    // whether a cell's undecided boxes are tried around their centre: always with elements;
    // for the paper's loop only where the recursion alone lowers the cell by more than
    // `1 - RECURSION_KEPT` and the centred test lowers it less
    let mut centred: Vec<bool> = cells
        .iter()
        .map(|&(m, _, _)| elements[m].is_some())
        .collect();
    for _ in 0..MAX_ROUNDS {
        crate::cancel::poll()?;
        let proofs = cells
            .par_iter()
            .zip(budgets.par_iter())
            .zip(centred.par_iter())
            .map(|((&(m, i, j), &b), &c)| {
                prove(&nodes(&t, i, j), guard, b, elements[m].as_ref(), c)
            })
            .collect::<Result<Vec<_>>>()?;
        if proofs.iter().all(Option::is_some) {
            t.certified = true;
            let grown = (
                budgets.iter().filter(|&&b| b > max_boxes).count(),
                budgets.iter().copied().max().unwrap_or(max_boxes),
            );
            let mut proved: Vec<(Loop, Vec<Cell>)> = members
                .into_iter()
                .map(|(lp, _)| (lp, Vec::new()))
                .collect();
            for (&(m, i, j), p) in cells.iter().zip(proofs) {
                if let Some(leaves) = p {
                    proved[m].1.push((i, j, leaves));
                }
            }
            // a set of one member (a hand always on the handle) is that member's loop
            let set = match &t.set {
                Some(set) if !set.is_single() => {
                    Some(product_order(&mut proved, |(lp, _)| (*lp, None))?)
                }
                _ => None,
            };
            return Ok(TableCertificate {
                table: t,
                members: proved,
                set,
                guard,
                grown,
            });
        }
        let failing: Vec<usize> = (0..cells.len()).filter(|&c| proofs[c].is_none()).collect();
        let lowered = failing
            .par_iter()
            .map(|&c| {
                let (m, i, j) = cells[c];
                let settled = |around| {
                    settle(
                        &t,
                        i,
                        j,
                        guard,
                        (budgets[c], cap),
                        elements[m].as_ref(),
                        around,
                    )
                };
                let first = settled(centred[c])?;
                let own = nodes(&t, i, j).a;
                let kept = |low: &((f64, f64), usize)| {
                    low.0.0 >= RECURSION_KEPT * own.0 && low.0.1 >= RECURSION_KEPT * own.1
                };
                if centred[c] || first.as_ref().is_some_and(kept) {
                    return Ok(first.map(|low| (low, centred[c])));
                }
                // the higher nodes of the two routes, the recursion's where they tie
                Ok(match (first, settled(true)?) {
                    (Some(f), Some(o)) if o.0.0 + o.0.1 > f.0.0 + f.0.1 => Some((o, true)),
                    (Some(f), _) => Some((f, false)),
                    (None, o) => o.map(|o| (o, true)),
                })
            })
            .collect::<Result<Vec<_>>>()?;
        let stuck: Vec<String> = failing
            .iter()
            .zip(&lowered)
            .filter(|(_, l)| l.is_none())
            .map(|(&c, _)| {
                let (m, i, j) = cells[c];
                cell_name(&t, i, j, &members[m].1)
            })
            .collect();
        if !stuck.is_empty() {
            return Err(Error::Numerical(format!(
                "no lowering down to 1/8 of the nodes proves the cell{} {} within {cap} boxes a cell: the interpolated walls leave the stable region there, lie too close to the unit circle, or the delay is too long for enclosures in double precision (above about 35 samples); use a finer delta axis (narrower cells), or a budget above {cap} boxes a cell",
                if stuck.len() == 1 { "" } else { "s" },
                stuck.join(", ")
            )));
        }
        // a node takes the lowest value any member's cell asks for
        for (&c, low) in failing.iter().zip(lowered) {
            if let Some((((a0, a1), budget), around)) = low {
                let (_, i, j) = cells[c];
                centred[c] = around;
                let j1 = next(&t, j);
                t.alpha_max[i][j] = t.alpha_max[i][j].min(a0);
                t.alpha_max[i][j1] = t.alpha_max[i][j1].min(a1);
                budgets[c] = budget;
            }
        }
    }
    Err(Error::Numerical(format!(
        "the table's cells were not all proved in {MAX_ROUNDS} rounds of lowering; use a finer delta axis"
    )))
}

/// The members of the table's finite set of devices as loops at its first node, with their
/// names ([`DeviceSet::describe_member`]). Each member's walls are the table's own only when
/// its mass is the set's reference mass, so sets spread over intervals, or over the mass,
/// are refused.
fn set_members(set: &DeviceSet, t: &AmaxTable) -> Result<Vec<(Loop, String)>> {
    if set.has_intervals() {
        return Err(Error::InvalidRequest(
            "a certified table covers a finite set of devices (a hand that can let go, one-of lists); an interval of a parameter is checked by the conservative sampling only: give its values as a list, or certify the table at its worst value".into(),
        ));
    }
    set_loops(&set.at_plant(t.delta[0], t.d[0])?)?
        .into_iter()
        .map(|m| match m.stated {
            (lp, None) => Ok((lp, m.name)),
            _ => Err(Error::InvalidRequest(
                "a certified table covers a finite set of devices of one mass (their walls are the table's): certify a table for each mass, or certify the set's walls one at a time".into(),
            )),
        })
        .collect()
}

/// The least share of a cell's `alpha` nodes that the recursion alone may keep for a cell
/// of the paper's loop to stay with it: a cell it proves lowered by at most 1 % is not tried
/// around the centres, which would prove walls a little higher (the 101 x 2 table of
/// `delta` 0.5 to 1.5 at one and two samples: lowered 0.02 % instead of 0.81 %) with many
/// more boxes (7 times the time, 3 times the certificate). A cell lowered by more (a wide
/// cell, a long delay: 12.5 % at one sample over `delta` 0.5 to 1, half at three samples)
/// takes the centred test's nodes where they are higher (0.8 % and 1.6 % there).
const RECURSION_KEPT: f64 = 0.99;

/// The column of the upper node of cell `j` (the same node for a one-node axis).
fn next(t: &AmaxTable, j: usize) -> usize {
    (j + 1).min(t.delta.len() - 1)
}

fn nodes(t: &AmaxTable, i: usize, j: usize) -> Nodes {
    let j1 = next(t, j);
    Nodes {
        x: (t.delta[j], t.delta[j1]),
        a: (t.alpha_max[i][j], t.alpha_max[i][j1]),
        b: (t.beta_at_max[i][j], t.beta_at_max[i][j1]),
        d: t.d[i],
    }
}

fn cell_name(t: &AmaxTable, i: usize, j: usize, member: &str) -> String {
    let of = if member.is_empty() {
        String::new()
    } else {
        format!(" for the member {member}")
    };
    format!(
        "d = {}, delta in [{}, {}]{of}",
        t.d[i],
        t.delta[j],
        t.delta[next(t, j)]
    )
}

/// The cell's `alpha` nodes lowered by the least factor of the ladder that proves it within
/// `budget.0` boxes ([`lower`]). Where none does (a cell too wide for that budget at any
/// wall), the budget grows before any node is lowered: the nodes as they are with the
/// budget doubled, up to `budget.1`, then the ladder with the budget doubled again from
/// `budget.0`. The nodes and the budget that proved the cell, or `None` when no lowering does
/// at the largest budget.
fn settle(
    t: &AmaxTable,
    i: usize,
    j: usize,
    guard: f64,
    (given, cap): (usize, usize),
    elements: Option<&Loop>,
    centred: bool,
) -> Result<Option<((f64, f64), usize)>> {
    if let Some(a) = lower(t, i, j, guard, given, elements, centred)? {
        return Ok(Some((a, given)));
    }
    let n = nodes(t, i, j);
    let doubled = std::iter::successors(Some(given), |&b| {
        (b < cap).then(|| b.saturating_mul(2).min(cap))
    });
    for budget in doubled.clone().skip(1) {
        crate::cancel::poll()?;
        if prove(&n, guard, budget, elements, centred)?.is_some() {
            return Ok(Some((n.a, budget)));
        }
    }
    for budget in doubled.skip(1) {
        if let Some(a) = lower(t, i, j, guard, budget, elements, centred)? {
            return Ok(Some((a, budget)));
        }
    }
    Ok(None)
}

/// The cell's `alpha` nodes lowered by a factor of the ladder that proves it (a bisection
/// over [`LADDER`] down to 3/4: a lower wall is nearly always easier to prove there), or
/// `None` when no factor does.
fn lower(
    t: &AmaxTable,
    i: usize,
    j: usize,
    guard: f64,
    budget: usize,
    elements: Option<&Loop>,
    centred: bool,
) -> Result<Option<(f64, f64)>> {
    let n = nodes(t, i, j);
    let p = t.precision;
    let scaled = |f: f64| (p.round_down(n.a.0 * f), p.round_down(n.a.1 * f));
    let proved = |k: usize| -> Result<bool> {
        crate::cancel::poll()?;
        let a = scaled(LADDER[k]);
        Ok(prove(&Nodes { a, ..n }, guard, budget, elements, centred)?.is_some())
    };
    // Lowering far can fail too (walls near alpha = 0, where z = 1 is a root, are as hard
    // to prove as walls near alpha_max): the bisection runs down to the first factor from
    // 3/4 on that proves the cell.
    let mut last = LADDER.len() - 4;
    while !proved(last)? {
        last += 1;
        if last == LADDER.len() {
            return Ok(None);
        }
    }
    // proved at hi; not at the indices below lo
    let (mut lo, mut hi) = (0, last);
    while lo < hi {
        let mid = (lo + hi) / 2;
        if proved(mid)? {
            hi = mid;
        } else {
            lo = mid + 1;
        }
    }
    Ok(Some(scaled(LADDER[hi])))
}

/// `v0 + s (v1 - v0)` over the interval `s`, rounded outward.
fn lerp((v0, v1): (f64, f64), s: Interval) -> Interval {
    let v0i = Interval::point(v0);
    v0i + s * (Interval::point(v1) - v0i)
}

/// The boxes proving every wall of the cell stable (module documentation), ordered by `s`,
/// or `None` when a box is unstable or the budget leaves one undecided. With `elements`, the
/// cell's loop is those elements on the cell's plant, enclosed over the box's `delta`
/// interval by the sampled device (the `device` module). With `centred`, a box the
/// recursion leaves undecided is tried around its centre (the `circle` module) before it is
/// halved.
fn prove(
    n: &Nodes,
    guard: f64,
    budget: usize,
    elements: Option<&Loop>,
    centred: bool,
) -> Result<Option<Vec<Leaf>>> {
    let widen = |(v0, v1): (f64, f64)| {
        Interval::symmetric(
            (Interval::point(guard) * Interval::point(v0.abs().max(v1.abs()))).mag(),
        )
    };
    let (gx, ga, gb) = (widen(n.x), widen(n.a), widen(n.b));
    // the elements on the cell's plant; the device's delta is then the box's interval
    let lp = match elements {
        Some(e) => Some(e.with_plant(Plant::new(n.x.1, n.d)?)?),
        None => None,
    };
    let mut queue = VecDeque::from([(0.0f64, 1.0f64)]);
    let mut count = 1usize;
    let mut leaves = Vec::new();
    while let Some((s0, s1)) = queue.pop_front() {
        let s = Interval::new(s0, s1);
        let delta = (lerp(n.x, s) + gx).nonneg();
        let parts_at = |delta: Interval| match &lp {
            None => paper_parts_over(delta, n.d),
            Some(lp) => parts_over(
                lp,
                &DeviceSpread {
                    delta,
                    ..DeviceSpread::of(lp)
                },
            ),
        };
        // over a range of delta, the enclosures widened (`Parts::widened`) so that an
        // independent checker's own enclosure of the range lies inside the claimed one:
        // 1/64 of the width is some hundreds of times the difference seen between the two
        // (about 1e-5 of the width at a filtered table's widest cells, once the checker
        // splits the range as it does)
        let parts = match &lp {
            None => parts_at(delta),
            Some(_) => parts_at(delta).widened(WRAPPING),
        };
        let (alpha, beta) = (lerp(n.a, s) + ga, lerp(n.b, s) + gb);
        let Some((coefficients, q)) = balls(parts.at(alpha, beta)) else {
            return Ok(None);
        };
        let rec = recursion(&q);
        match rec.outside {
            Some(0) => leaves.push(Leaf {
                s: (s0, s1),
                coefficients,
                reflections: reflection_balls(&rec),
                around: None,
            }),
            // every wall of the box is unstable, some of the cell's among them
            Some(_) => return Ok(None),
            None => {
                let ends = |x: Interval| (x.lo(), x.hi());
                // the loop at the middle of the delta range: the member whose count of roots
                // outside the arcs carry to the whole box
                let mid = 0.5 * delta.lo() + 0.5 * delta.hi();
                let around = centred.then(|| {
                    let member = parts_at(Interval::point(mid));
                    around_centre(&parts, Some(&member), ends(alpha), ends(beta))
                });
                if let Some(c) = around.flatten() {
                    if c.outside > 0 {
                        return Ok(None);
                    }
                    leaves.push(Leaf {
                        s: (s0, s1),
                        coefficients: c.coefficients,
                        reflections: reflection_balls(&c.recursion),
                        around: Some(Around {
                            centre: c.centre,
                            delta: mid,
                            arcs: c.arcs,
                            family: c.family.unwrap_or_default(),
                        }),
                    });
                    continue;
                }
                let mid = 0.5 * (s0 + s1);
                if count >= budget || !(s0 < mid && mid < s1) {
                    return Ok(None);
                }
                count += 1;
                queue.push_back((s0, mid));
                queue.push_back((mid, s1));
            }
        }
    }
    leaves.sort_by(|x, y| x.s.0.total_cmp(&y.s.0));
    Ok(Some(leaves))
}

impl TableCertificate {
    /// The table, its nodes lowered where a proof needed it, marked certified.
    pub fn table(&self) -> &AmaxTable {
        &self.table
    }

    /// The table, consumed.
    pub fn into_table(self) -> AmaxTable {
        self.table
    }

    /// The number of cells and of boxes proving them (over every member, for a set).
    pub fn counts(&self) -> (usize, usize) {
        let cells = self.members.iter().flat_map(|(_, c)| c);
        (cells.clone().count(), cells.map(|(_, _, l)| l.len()).sum())
    }

    /// Where a cell's budget of boxes grew past the one given (no lowering proved it within
    /// that, [`certify_table`]): the number of such cells and the largest budget a cell was
    /// given; `None` when every cell was proved within the budget given.
    ///
    /// ```
    /// use stabound::amax::{AmaxOptions, TableOptions, amax_table};
    /// use stabound::certificate::{DEFAULT_CELL_BOXES, certify_table};
    ///
    /// let opts = TableOptions::new(AmaxOptions::default()).with_conservative(true);
    /// let table = amax_table(&[0.5, 1.0], &[1.0], &opts)?;
    /// assert_eq!(certify_table(&table, DEFAULT_CELL_BOXES)?.grown(), None);
    /// # Ok::<(), stabound::Error>(())
    /// ```
    pub fn grown(&self) -> Option<(usize, usize)> {
        (self.grown.0 > 0).then_some(self.grown)
    }

    /// The number of devices the table is proved for: 1 for one loop, else the set's members.
    pub fn members(&self) -> usize {
        self.members.len()
    }

    /// The certificate as JSON text, ending in a newline: the model, the table (precision,
    /// guard, axes and nodes as hex floats), every cell's boxes as leaves of the general
    /// shape (their box the `s` range, their claim, their coefficient and reflection balls),
    /// the claim and a CRC-32 of the text before it. Over a set of devices, a certificate of
    /// kind `"set"`: the set (each element's alternatives) and each member's table
    /// certificate, all with the one table.
    pub fn to_json(&self) -> String {
        let members: Vec<String> = self
            .members
            .iter()
            .map(|(lp, cells)| self.member_json(lp, cells))
            .collect();
        match &self.set {
            None => members.into_iter().next().unwrap_or_default(),
            Some(set) => {
                let claim = format!("\"verdict\": \"stable\", \"members\": {}", members.len());
                set_json(set, &members, "", &claim)
            }
        }
    }

    /// The table's certificate for the loop `lp` (the table's elements, of one member) proved
    /// by `cells`.
    fn member_json(&self, lp: &Loop, cells: &[Cell]) -> String {
        let t = &self.table;
        let (mut s, elements) = head("table", lp);
        let list = |v: &[f64]| {
            let items: Vec<String> = v.iter().map(|&x| format!("\"{}\"", hex(x))).collect();
            format!("[{}]", items.join(", "))
        };
        let grid = |v: &[Vec<f64>]| {
            let rows: Vec<String> = v.iter().map(|r| list(r)).collect();
            format!("[{}]", rows.join(",\n             "))
        };
        let _ = writeln!(
            s,
            "  \"table\": {{\"precision\": \"{}\", \"guard\": \"{}\",\n    \"delta\": {},\n    \"d\": {},\n    \"alpha\": {},\n    \"beta\": {}{}}},",
            t.precision.name(),
            hex(self.guard),
            list(&t.delta),
            list(&t.d),
            grid(&t.alpha_max),
            grid(&t.beta_at_max),
            elements
                .iter()
                .map(|(k, v)| format!(",\n    \"{k}\": {v}"))
                .collect::<String>()
        );
        cells_json(&mut s, cells);
        let boxes: usize = cells.iter().map(|(_, _, l)| l.len()).sum();
        let _ = writeln!(
            s,
            ",\n  \"claim\": {{\"verdict\": \"stable\", \"cells\": {}, \"leaves\": {boxes}}},",
            cells.len()
        );
        seal(s)
    }
}

/// The member `"cells"` of a table's certificate: every cell's boxes (see
/// [`TableCertificate::to_json`]), after two spaces, with no comma after it.
fn cells_json(s: &mut String, cells: &[Cell]) {
    s.push_str("  \"cells\": [");
    for (k, (i, j, leaves)) in cells.iter().enumerate() {
        s.push_str(if k == 0 { "\n" } else { ",\n" });
        let _ = write!(s, "    {{\"row\": {i}, \"column\": {j}, \"leaves\": [");
        for (m, leaf) in leaves.iter().enumerate() {
            s.push_str(if m == 0 { "\n" } else { ",\n" });
            let _ = write!(
                s,
                "      {{\"box\": {{\"s\": [\"{}\", \"{}\"]}}, \"claim\": \"stable\",",
                hex(leaf.s.0),
                hex(leaf.s.1)
            );
            if let Some(c) = &leaf.around {
                let _ = write!(
                    s,
                    " \"centre\": {{\"alpha\": \"{}\", \"beta\": \"{}\", \"delta\": \"{}\"}},",
                    hex(c.centre.0),
                    hex(c.centre.1),
                    hex(c.delta)
                );
            }
            s.push_str("\n       \"coefficients\": ");
            list_json(s, "        ", &leaf.coefficients);
            s.push_str(",\n       \"reflections\": ");
            list_json(s, "        ", &leaf.reflections);
            if let Some(c) = &leaf.around {
                s.push_str(",\n       \"family\": ");
                list_json(s, "        ", &c.family);
                let ends: Vec<String> = c.arcs.iter().map(|&u| format!("\"{}\"", hex(u))).collect();
                let _ = write!(s, ",\n       \"arcs\": [{}]", ends.join(", "));
            }
            s.push('}');
        }
        s.push_str("]}");
    }
    s.push(']');
}
