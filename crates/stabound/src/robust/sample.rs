//! The members of a set at one virtual damping: their stable stiffnesses (cached), the
//! search for the member with the least room, and the sampling argument that a wall holds
//! over a whole box of members.
//!
//! # The sampling argument
//!
//! For a wall `(a, beta)` and a member `p` of a box (coordinates in `[0, 1]^k`), the *room*
//! `r_p` is the signed distance in `alpha` from `a` to the edge of `p`'s stable set at
//! `beta` (positive inside: `min(a - lo, hi - a)` for the stable interval `(lo, hi)` holding
//! `a`; negative outside). The wall is stable for every member exactly when `r_p > 0` on the
//! whole box. The box is cut into cells; on a cell with corners `c` and widths `w_k`, if `r`
//! changes by at most `L_k |x_k - y_k|` along each coordinate, then for every `x` in the
//! cell and every corner `c`, `r(x) >= r(c) - sum_k L_k |x_k - c_k|`; averaging over the
//! `2^k` corners (where `|x_k - c_k|` averages to `w_k / 2`) gives
//!
//! ```text
//! min over the cell of r  >=  mean over the corners of r  -  sum_k L_k w_k / 2.
//! ```
//!
//! `L_k` is taken as [`SAFETY`] times the largest difference quotient of `r` along `k`
//! seen between any two adjacent samples of the box. Cells whose bound is not positive are
//! halved along the coordinate with the largest `L_k w_k`, until every cell's bound is
//! positive (the wall holds: *verified by sampling*), a sample has `r <= 0` (a member the
//! wall fails on), or [`MAX_SAMPLES`] samples are spent (unresolved, with the shortfall).
//! The assumption is stated, not proven: `r` is Lipschitz with at most twice the steepest
//! slope seen between samples. It fails only for a feature narrower than the cells that no
//! sample touches; the tests compare against far denser independent sampling.

use std::collections::HashMap;

use rayon::prelude::*;

use super::{DeviceSet, Member, Variant, grid};
use crate::error::Result;
use crate::golden::golden_max;
use crate::search::{Interval, stable_alphas};
use crate::stability::{Checker, Options};

/// The factor on the steepest slope seen between samples that the sampling argument assumes
/// bounds the slope anywhere in the box (module documentation). With 2, a quadratic minimum
/// between two samples (where the chord's slope is zero) is still covered by the slopes of
/// the neighbouring cells, which are at least the curvature times the width.
pub const SAFETY: f64 = 2.0;

/// The most members the sampling argument evaluates in one box before it reports the wall
/// unresolved: at tens of microseconds per member (one exact stable set each), a second.
pub const MAX_SAMPLES: usize = 20_000;

/// The narrowest cell, in the box's unit coordinates: `2^-30` of an interval is below any
/// tolerance a device is made to.
const MIN_WIDTH: f64 = 1.0 / (1u64 << 30) as f64;

/// A member's stable stiffnesses at a reference damping, in the set's reference
/// normalization (module documentation of [`super`]).
pub(crate) fn member_alphas(m: &Member, m_ref: f64, beta: f64) -> Result<Vec<Interval>> {
    let lp = m.to_loop()?;
    let s = m_ref / m.device.mass;
    let checker = Checker::new(lp, Options::default())?;
    Ok(stable_alphas(&checker, s * beta)?
        .into_iter()
        .map(|i| Interval {
            lo: i.lo / s,
            hi: i.hi / s,
        })
        .collect())
}

/// The room of stiffness `a` in the stable set `set` (module documentation).
pub(crate) fn room(set: &[Interval], a: f64) -> f64 {
    let mut best = f64::NEG_INFINITY;
    for i in set {
        let r = if i.contains(a) {
            (a - i.lo).min(i.hi - a)
        } else {
            -i.distance(a)
        };
        best = best.max(r);
    }
    if best == f64::NEG_INFINITY {
        // no stable stiffness at all: as far outside as the wall is from zero, and more
        -(a.abs() + 1.0)
    } else {
        best
    }
}

/// A member of the set by its box (the index of its variant) and its coordinates there.
pub(crate) type Point = (usize, Vec<f64>);

/// The least a hint's span is widened by in [`Probe::least_room_near`] (the box's unit
/// coordinates): a ten-thousandth of the interval, so that the golden section needs about
/// ten steps. Where the least room lies at an end of that bracket the binding member moved
/// further than the hints suggest and [`NEAR`] is searched; with a delay of 1 to 3 samples
/// on `delta = 2` (a delay near 2.9 binding over a fifth of the dampings) the region's rows
/// are within `4e-13` of those the search over the whole set gives.
const NEAR_MIN: f64 = 1e-4;

/// How far beyond the span of its hints [`Probe::least_room_near`] looks when the least
/// room lies at an end of the first bracket: a hundredth of the interval.
const NEAR: f64 = 1e-2;

/// The bracket [`Probe::least_room_near`]'s golden section ends with: as narrow as the full
/// search's (24 steps within a grid step of an eighth, `0.618^24 / 4 ~ 2.5e-6`).
const NEAR_WIDTH: f64 = 2.5e-6;

/// The golden ratio's inverse, by which each golden-section step shrinks the bracket.
const GOLDEN: f64 = 0.618_033_988_749_894_9;

/// Where a sample sits: its box and its coordinates (as bits, exact keys).
type Key = (usize, Vec<u64>);

fn key(v: usize, coords: &[f64]) -> Key {
    (v, coords.iter().map(|c| c.to_bits()).collect())
}

/// The members of a set at one reference damping `beta`, their stable sets computed once.
pub(crate) struct Probe {
    pub(crate) variants: Vec<Variant>,
    m_ref: f64,
    beta: f64,
    cache: HashMap<Key, Vec<Interval>>,
}

/// What the sampling argument found for one wall over every box.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Outcome {
    /// Every cell's bound is positive.
    Holds {
        /// Samples evaluated (all boxes).
        samples: usize,
        /// Cells at the end.
        cells: usize,
    },
    /// A sampled member on which the wall has no room.
    Fails(Box<Member>),
    /// The budget ran out with cells whose bound is not positive: the lowest bound.
    Short {
        /// Samples evaluated.
        samples: usize,
        /// The most negative bound of a cell (a negative room).
        shortfall: f64,
    },
}

#[derive(Debug, Clone)]
struct Cell {
    lo: Vec<f64>,
    hi: Vec<f64>,
}

impl Cell {
    fn corners(&self) -> Vec<Vec<f64>> {
        let k = self.lo.len();
        (0..1usize << k)
            .map(|c| {
                (0..k)
                    .map(|i| {
                        if (c >> i) & 1 == 1 {
                            self.hi[i]
                        } else {
                            self.lo[i]
                        }
                    })
                    .collect()
            })
            .collect()
    }
}

impl Probe {
    pub(crate) fn new(set: &DeviceSet, beta: f64) -> Self {
        Self {
            variants: set.variants(),
            m_ref: set.device.mass,
            beta,
            cache: HashMap::new(),
        }
    }

    /// Members evaluated so far.
    pub(crate) fn evaluated(&self) -> usize {
        self.cache.len()
    }

    /// Computes the stable sets of the samples not yet known, in parallel (each member is
    /// independent, so the results do not depend on the number of threads).
    fn fill(&mut self, points: &[(usize, Vec<f64>)]) -> Result<()> {
        let mut todo: Vec<&(usize, Vec<f64>)> = points
            .iter()
            .filter(|(v, c)| !self.cache.contains_key(&key(*v, c)))
            .collect();
        todo.dedup();
        let (vars, m_ref, beta) = (&self.variants, self.m_ref, self.beta);
        let found: Vec<Vec<Interval>> = todo
            .par_iter()
            .map(|(v, c)| member_alphas(&vars[*v].member(c), m_ref, beta))
            .collect::<Result<_>>()?;
        for ((v, c), f) in todo.into_iter().zip(found) {
            self.cache.insert(key(*v, c), f);
        }
        Ok(())
    }

    fn room_at(&mut self, v: usize, coords: &[f64], a: f64) -> Result<f64> {
        let k = key(v, coords);
        if !self.cache.contains_key(&k) {
            self.fill(&[(v, coords.to_vec())])?;
        }
        Ok(room(&self.cache[&k], a))
    }

    /// The member with the least room for stiffness `a`: every corner and a coarse grid of
    /// each box, then a coordinate search (golden section along each coordinate in turn,
    /// within one grid step of the best point, twice over). Returns the member and its room.
    pub(crate) fn least_room(&mut self, a: f64) -> Result<(Member, f64)> {
        let (p, r) = self.least_room_point(a, false)?;
        Ok((self.member(&p), r))
    }

    /// Of the members evaluated so far that `skip` does not rule out, the one with the least
    /// room for the stiffnesses `targets` (the least over them), and that room.
    pub(crate) fn least_evaluated(
        &self,
        targets: &[f64],
        skip: impl Fn(&Member) -> bool,
    ) -> Option<(Point, f64)> {
        let mut best: Option<(Point, f64)> = None;
        for ((v, bits), set) in &self.cache {
            let r = targets
                .iter()
                .map(|&a| room(set, a))
                .fold(f64::INFINITY, f64::min);
            if best.as_ref().is_some_and(|b| b.1 <= r) {
                continue;
            }
            let p: Point = (*v, bits.iter().map(|&b| f64::from_bits(b)).collect());
            if !skip(&self.member(&p)) {
                best = Some((p, r));
            }
        }
        best
    }

    /// The member at `p`.
    pub(crate) fn member(&self, p: &Point) -> Member {
        self.variants[p.0].member(&p.1)
    }

    /// The room of the member at `p` for stiffness `a`.
    pub(crate) fn room_of(&mut self, p: &Point, a: f64) -> Result<f64> {
        self.room_at(p.0, &p.1, a)
    }

    /// [`Probe::least_room`], the member by its box and coordinates; `once`: the coordinate
    /// search of a box with one interval runs once, not twice (the second pass searches the
    /// same line again around the point the first found).
    pub(crate) fn least_room_point(&mut self, a: f64, once: bool) -> Result<(Point, f64)> {
        let mut best: Option<(usize, Vec<f64>, f64)> = None;
        for v in 0..self.variants.len() {
            let k = self.variants[v].dims();
            let n = match k {
                0 => 1,
                1..=2 => 9,
                3..=4 => 3,
                _ => 2,
            };
            let grid = grid(k, n);
            let pts: Vec<(usize, Vec<f64>)> = grid.iter().map(|c| (v, c.clone())).collect();
            self.fill(&pts)?;
            let mut local: Option<(Vec<f64>, f64)> = None;
            for c in grid {
                let r = self.room_at(v, &c, a)?;
                if local.as_ref().is_none_or(|(_, b)| r < *b) {
                    local = Some((c, r));
                }
            }
            let Some((mut x, mut r)) = local else {
                continue;
            };
            let step = if n > 1 { 1.0 / (n - 1) as f64 } else { 0.0 };
            for _ in 0..if once && k == 1 { 1 } else { 2 } {
                for i in 0..k {
                    let (lo, hi) = ((x[i] - step).max(0.0), (x[i] + step).min(1.0));
                    let (t, rt) = self.golden_min(v, &x, i, (lo, hi), a, 24)?;
                    if rt < r {
                        x[i] = t;
                        r = rt;
                    }
                }
            }
            if best.as_ref().is_none_or(|b| r < b.2) {
                best = Some((v, x, r));
            }
        }
        let (v, x, r) = best.expect("a set has at least one box");
        Ok(((v, x), r))
    }

    /// The member with the least room for stiffness `a` near the members `hints` (found at
    /// neighbouring dampings, where the binding member moves little): the hints themselves,
    /// then per box a hint lies in, a coordinate search by golden section along each
    /// coordinate within the hints' span widened by half of it (and by at least
    /// [`NEAR_MIN`]); where the least room found lies at an end of that bracket inside the
    /// box, again within the span widened by [`NEAR`] (the ends of the box included where a
    /// bracket reaches them). `None` without hints.
    pub(crate) fn least_room_near(
        &mut self,
        a: f64,
        hints: &[Point],
    ) -> Result<Option<(Point, f64)>> {
        let mut best: Option<(Point, f64)> = None;
        let mut boxes: Vec<usize> = hints.iter().map(|h| h.0).collect();
        boxes.sort_unstable();
        boxes.dedup();
        for v in boxes {
            let here: Vec<Vec<f64>> = hints
                .iter()
                .filter(|h| h.0 == v)
                .map(|h| h.1.clone())
                .collect();
            let pts: Vec<(usize, Vec<f64>)> = here.iter().map(|x| (v, x.clone())).collect();
            self.fill(&pts)?;
            let mut local: Option<(Vec<f64>, f64)> = None;
            for x in &here {
                let r = self.room_at(v, x, a)?;
                if local.as_ref().is_none_or(|(_, b)| r < *b) {
                    local = Some((x.clone(), r));
                }
            }
            let Some((mut x, mut r)) = local else {
                continue;
            };
            for i in 0..x.len() {
                let (lo, hi) = here
                    .iter()
                    .fold((1.0f64, 0.0f64), |(l, h), y| (l.min(y[i]), h.max(y[i])));
                let pad = (0.5 * (hi - lo)).max(NEAR_MIN);
                for pad in [pad, NEAR] {
                    let (l, h) = ((lo - pad).max(0.0), (hi + pad).min(1.0));
                    let (t, rt) = self.line_min(v, &x, i, (l, h), a)?;
                    if rt < r {
                        x[i] = t;
                        r = rt;
                    }
                    // inside the bracket, away from its ends within the box: found
                    let edge = 0.05 * (h - l);
                    if (t - l > edge || l == 0.0) && (h - t > edge || h == 1.0) {
                        break;
                    }
                }
            }
            if best.as_ref().is_none_or(|b| r < b.1) {
                best = Some(((v, x), r));
            }
        }
        Ok(best)
    }

    /// The least room along coordinate `i` from `x` over `[lo, hi]`: the ends of the box
    /// exactly where the bracket reaches them (a binding corner), and the golden section
    /// down to [`NEAR_WIDTH`].
    fn line_min(
        &mut self,
        v: usize,
        x: &[f64],
        i: usize,
        (lo, hi): (f64, f64),
        a: f64,
    ) -> Result<(f64, f64)> {
        let mut best: Option<(f64, f64)> = None;
        for t in [lo, hi] {
            // exact: the box's ends are 0 and 1 themselves
            if t == 0.0 || t == 1.0 {
                let mut y = x.to_vec();
                y[i] = t;
                let rt = self.room_at(v, &y, a)?;
                if best.is_none_or(|b| rt < b.1) {
                    best = Some((t, rt));
                }
            }
        }
        let steps = (((hi - lo) / NEAR_WIDTH).ln() / (1.0 / GOLDEN).ln()).ceil();
        let (t, rt) = self.golden_min(v, x, i, (lo, hi), a, steps.max(1.0) as usize)?;
        Ok(match best {
            Some(b) if b.1 <= rt => b,
            _ => (t, rt),
        })
    }

    /// Golden-section minimum of the room along coordinate `i` over `[lo, hi]` (Kiefer
    /// 1953) in `steps` steps: 24 shrink the bracket to `0.618^24 ~ 1e-5` of a grid step.
    fn golden_min(
        &mut self,
        v: usize,
        x: &[f64],
        i: usize,
        (lo, hi): (f64, f64),
        a: f64,
        steps: usize,
    ) -> Result<(f64, f64)> {
        let at = |t: f64, probe: &mut Self| -> Result<f64> {
            let mut y = x.to_vec();
            y[i] = t;
            probe.room_at(v, &y, a)
        };
        // the minimum of the room is the maximum of its negation (exact in floating point)
        let [(c, fc), (d, fd)] =
            golden_max(|t| at(t, self).map(|r| -r), (lo, hi), |_, _, k| k < steps)?.points;
        Ok(if fc > fd { (c, -fc) } else { (d, -fd) })
    }

    /// The sampling argument (module documentation) for stiffness `a` over every box.
    pub(crate) fn verify(&mut self, a: f64) -> Result<Outcome> {
        let mut cells_total = 0;
        let mut shortfall = f64::INFINITY;
        for v in 0..self.variants.len() {
            let k = self.variants[v].dims();
            if k == 0 {
                if self.room_at(v, &[], a)? <= 0.0 {
                    return Ok(Outcome::Fails(Box::new(self.variants[v].member(&[]))));
                }
                cells_total += 1;
                continue;
            }
            // about 64 cells to start: 64 along one interval, 8 x 8 along two, ...
            let n = (64f64.powf(1.0 / k as f64).ceil() as usize).max(1);
            let mut cells = cells_of(k, n);
            let start = self.evaluated();
            loop {
                let pts: Vec<(usize, Vec<f64>)> = cells
                    .iter()
                    .flat_map(|c| c.corners().into_iter().map(|x| (v, x)))
                    .collect();
                self.fill(&pts)?;
                // every corner's room, and the steepest slope along each coordinate
                let mut slope = vec![0.0f64; k];
                let mut means = Vec::with_capacity(cells.len());
                for c in &cells {
                    let cs = c.corners();
                    let r: Vec<f64> = cs
                        .iter()
                        .map(|x| self.room_at(v, x, a))
                        .collect::<Result<_>>()?;
                    for (j, &rj) in r.iter().enumerate() {
                        if rj <= 0.0 {
                            return Ok(Outcome::Fails(Box::new(self.variants[v].member(&cs[j]))));
                        }
                        for (i, s) in slope.iter_mut().enumerate() {
                            if (j >> i) & 1 == 0 {
                                let w = c.hi[i] - c.lo[i];
                                *s = s.max((r[j | (1 << i)] - rj).abs() / w);
                            }
                        }
                    }
                    means.push(r.iter().sum::<f64>() / r.len() as f64);
                }
                let lip: Vec<f64> = slope.iter().map(|s| SAFETY * s).collect();
                let reach = |c: &Cell, i: usize| lip[i] * (c.hi[i] - c.lo[i]);
                // each cell's lower bound on the room (module documentation); the cells that
                // hold are judged again with the slopes of the next round's samples
                let mut held: Vec<Cell> = Vec::new();
                let mut split: Vec<Cell> = Vec::new();
                let mut short = f64::INFINITY;
                let mut stuck = false;
                for (c, mean) in cells.iter().zip(&means) {
                    let bound = mean - (0..k).map(|i| reach(c, i) / 2.0).sum::<f64>();
                    if bound > 0.0 {
                        held.push(c.clone());
                        continue;
                    }
                    short = short.min(bound);
                    // halve along the coordinate that contributes most
                    let i = (0..k)
                        .max_by(|&x, &y| reach(c, x).total_cmp(&reach(c, y)))
                        .unwrap_or(0);
                    if c.hi[i] - c.lo[i] <= MIN_WIDTH {
                        stuck = true;
                        continue;
                    }
                    let mid = 0.5 * (c.lo[i] + c.hi[i]);
                    let (mut left, mut right) = (c.clone(), c.clone());
                    left.hi[i] = mid;
                    right.lo[i] = mid;
                    split.extend([left, right]);
                }
                if short == f64::INFINITY {
                    cells_total += held.len();
                    break;
                }
                if stuck || split.is_empty() || self.evaluated() - start >= MAX_SAMPLES {
                    shortfall = shortfall.min(short);
                    cells_total += cells.len();
                    break;
                }
                held.extend(split);
                cells = held;
            }
        }
        if shortfall.is_finite() {
            return Ok(Outcome::Short {
                samples: self.evaluated(),
                shortfall,
            });
        }
        Ok(Outcome::Holds {
            samples: self.evaluated(),
            cells: cells_total,
        })
    }
}

/// The `n^k` cells of an even grid of `[0, 1]^k`, their corners at `i / n` exactly (so that
/// neighbours share their samples).
fn cells_of(k: usize, n: usize) -> Vec<Cell> {
    let mut out: Vec<(Vec<f64>, Vec<f64>)> = vec![(Vec::new(), Vec::new())];
    for _ in 0..k {
        out = out
            .into_iter()
            .flat_map(|(lo, hi)| {
                (0..n).map(move |i| {
                    let (mut l, mut h) = (lo.clone(), hi.clone());
                    l.push(i as f64 / n as f64);
                    h.push((i + 1) as f64 / n as f64);
                    (l, h)
                })
            })
            .collect();
    }
    out.into_iter().map(|(lo, hi)| Cell { lo, hi }).collect()
}
