//! The chord refinement of the D-decomposition engine ([`super::exact()`], for the paper's
//! loop and any loop): the runs of kept coarse samples, their
//! knots, and the recursive midpoint test that refines each chord until the polyline is within
//! `tol` of the curve.
//!
//! Method: step 3 of the D-decomposition engines (Neimark, 1948; Gryazina, Polyak and Tremba,
//! "D-decomposition technique state-of-the-art", *Automation and Remote Control* 69, 2008;
//! see [`super::exact()`]): recursive halving of the parameter interval of every chord whose
//! curve midpoint lies more than `tol` from it.

use std::sync::atomic::{AtomicUsize, Ordering};

use rayon::prelude::*;

use super::{MAX_VERTICES, Piece};
use crate::geometry::seg_dist;
use crate::params::Wall;

/// Depth cap of the chord refinement: `pi / 2^40` is below `f64` resolution of `theta`.
const MAX_DEPTH: u32 = 40;

/// The observed ratio of a chord's midpoint deviation to its parent's for which the halves'
/// deviations are predicted rather than evaluated (see [`Refiner::refine`]).
///
/// Where the curve's curvature is smooth on the chord's scale, the midpoint deviation of a
/// chord is `L^2 kappa / 8` to leading order, so halving the chord divides it by 4. A ratio
/// within 20 % of `1/4` shows that this held from the parent to this chord (the curvature
/// changed by less than a fifth over the parent's length); anywhere else, near an inflection
/// point or where the deviation is still at rounding level, the halves are evaluated.
const SCALING: std::ops::RangeInclusive<f64> = 0.2..=0.3;

/// A split chord whose deviation is at most this many tolerances has halves predicted at
/// `1/4` of it, at most `tol / 2`: accepted without evaluating their midpoints. The factor 2
/// is the margin against the prediction: a half fails the midpoint test only if the
/// curvature doubles within the chord, while [`SCALING`] saw it change by less than a fifth
/// over twice that length. With it the paper's main job (`delta 0.5, d 1`, tol `1e-9`)
/// evaluates 1.30 midpoints per vertex instead of 2.00 and gives the same vertices (as do
/// 126 plants and tolerances compared while choosing it, and the figures).
const PREDICTED_SPLIT: f64 = 2.0;

/// A sample of a D-decomposition curve as the refinement needs it.
pub(crate) trait CurveSample: Copy + Send + Sync {
    /// The angle `theta` of the root `e^{i theta}`.
    fn theta(&self) -> f64;
    /// The wall with that root.
    fn wall(&self) -> &Wall;
    /// The wall bounds the stable region (every other root strictly inside).
    fn keep(&self) -> bool;
}

/// The knots of every run of consecutive kept samples, in order: the run's two ends located
/// by `corner(kept, rejected)` (a run that starts or ends at the grid's end keeps that
/// sample), and the run's samples strictly between them.
pub(crate) fn kept_knots<S: CurveSample>(
    samples: &[S],
    corner: impl Fn(&S, &S) -> S,
) -> Vec<Vec<S>> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < samples.len() {
        if !samples[i].keep() {
            i += 1;
            continue;
        }
        let mut j = i;
        while j + 1 < samples.len() && samples[j + 1].keep() {
            j += 1;
        }
        let first = if i == 0 {
            samples[0]
        } else {
            corner(&samples[i], &samples[i - 1])
        };
        let last = if j + 1 == samples.len() {
            samples[j]
        } else {
            corner(&samples[j], &samples[j + 1])
        };
        let mut knots = vec![first];
        knots.extend(
            samples[i..=j]
                .iter()
                .copied()
                .filter(|s| s.theta() > first.theta() && s.theta() < last.theta()),
        );
        knots.push(last);
        out.push(knots);
        i = j + 1;
    }
    out
}

/// The size of the kept samples' walls (largest coordinate) when refinement went over
/// [`MAX_VERTICES`], for the error that says which tolerance fits; `None` within the budget.
pub(crate) fn over_budget<S: CurveSample>(vertices: &AtomicUsize, samples: &[S]) -> Option<f64> {
    (vertices.load(Ordering::Relaxed) > MAX_VERTICES).then(|| {
        samples
            .iter()
            .filter(|s| s.keep())
            .map(|s| s.wall().alpha().abs().max(s.wall().beta().abs()))
            .fold(0.0, f64::max)
    })
}

/// A kept piece of the boundary before chaining.
pub(crate) struct Chain {
    pub(crate) piece: Piece,
    pub(crate) pts: Vec<Wall>,
}

/// [`CurveSample`] for an engine's sample struct with fields `theta`, `wall` and `keep`.
macro_rules! curve_sample {
    ($t:ty) => {
        impl $crate::boundary::refine::CurveSample for $t {
            fn theta(&self) -> f64 {
                self.theta
            }
            fn wall(&self) -> &$crate::params::Wall {
                &self.wall
            }
            fn keep(&self) -> bool {
                self.keep
            }
        }
    };
}
pub(crate) use curve_sample;

/// A chord's midpoint found by [`Refiner`]'s `midpoint` function.
pub(crate) struct Midpoint<S> {
    /// The sample there.
    pub(crate) sample: S,
    /// The deviation scales as the squared chord length from this chord to its halves, so
    /// that they may be predicted ([`SCALING`]); false where the midpoint is not the middle
    /// of a smooth parametrization (next to the curve's ends).
    pub(crate) smooth: bool,
}

/// The recursive midpoint refinement of a curve's chords to `tol`.
pub(crate) struct Refiner<'a, M> {
    /// Largest distance between a chord and the curve.
    pub(crate) tol: f64,
    /// Vertices added so far, against [`MAX_VERTICES`] (shared by the chords of one curve).
    pub(crate) vertices: &'a AtomicUsize,
    /// The midpoint of the chord between two samples (`None`: no wall there; the chord
    /// stays).
    pub(crate) midpoint: M,
    /// Halves predicted within `tol / 2` are accepted untested ([`PREDICTED_SPLIT`]).
    pub(crate) predict: bool,
}

impl<M> Refiner<'_, M> {
    /// The polyline through `knots`, refined: the first knot's wall, then for each chord the
    /// refined points and the chord's end. Chords are refined in parallel (rayon, order
    /// kept) when `parallel`, else on the calling thread; the result is the same.
    pub(crate) fn polyline<S>(&self, knots: &[S], parallel: bool) -> Vec<Wall>
    where
        S: CurveSample,
        M: Fn(&S, &S) -> Option<Midpoint<S>> + Sync,
    {
        let mut pts = vec![*knots[0].wall()];
        if parallel {
            let parts: Vec<Vec<Wall>> = knots
                .par_windows(2)
                .map(|w| {
                    let mut pts = Vec::new();
                    self.refine(&w[0], &w[1], 0, &mut pts, 0, f64::INFINITY);
                    self.vertices.fetch_add(pts.len(), Ordering::Relaxed);
                    pts.push(*w[1].wall());
                    pts
                })
                .collect();
            pts.reserve(parts.iter().map(Vec::len).sum::<usize>());
            for p in parts {
                pts.extend(p);
            }
        } else {
            // straight into the curve's vector: no buffer per chord
            for w in knots.windows(2) {
                let before = pts.len();
                self.refine(&w[0], &w[1], 0, &mut pts, before, f64::INFINITY);
                self.vertices
                    .fetch_add(pts.len() - before, Ordering::Relaxed);
                pts.push(*w[1].wall());
            }
        }
        pts
    }

    /// Appends the points strictly between `a` and `b` that keep the polyline within `tol`
    /// of the curve (recursive midpoint test on the chord); the chord's points start at
    /// `pts[from]`. `parent_dev` is the midpoint deviation of the chord this one halves
    /// (infinite for a coarse chord and after a midpoint that is not [`Midpoint::smooth`]):
    /// with `predict`, where the deviation has scaled with the square of the length from
    /// there ([`SCALING`]), a split whose halves are predicted within `tol / 2`
    /// ([`PREDICTED_SPLIT`]) keeps the midpoint without testing them, two evaluations saved.
    fn refine<S>(&self, a: &S, b: &S, depth: u32, pts: &mut Vec<Wall>, from: usize, parent_dev: f64)
    where
        S: CurveSample,
        M: Fn(&S, &S) -> Option<Midpoint<S>>,
    {
        // the chord's own vertices, then what finished chords reported: a shared counter
        // written per vertex would bounce its cache line between the threads
        if depth >= MAX_DEPTH
            || pts.len() - from > MAX_VERTICES
            || self.vertices.load(Ordering::Relaxed) > MAX_VERTICES
        {
            return;
        }
        let Some(Midpoint { sample: ms, smooth }) = (self.midpoint)(a, b) else {
            return;
        };
        let m = *ms.wall();
        // Inflection points, where the midpoint may sit on the chord of a wavy piece, are
        // covered by the coarse samples: each chord spans at most 1/64 of a turn of the curve.
        let dev = seg_dist(m.xy(), a.wall().xy(), b.wall().xy());
        if dev <= self.tol {
            return;
        }
        if self.predict
            && smooth
            && SCALING.contains(&(dev / parent_dev))
            && dev <= PREDICTED_SPLIT * self.tol
        {
            pts.push(m);
            return;
        }
        let child = if smooth { dev } else { f64::INFINITY };
        self.refine(a, &ms, depth + 1, pts, from, child);
        pts.push(m);
        self.refine(&ms, b, depth + 1, pts, from, child);
    }
}
