//! The exact boundary in the `(alpha, beta)` plane by D-decomposition: one engine for the
//! paper's loop and every loop with elements, written against the affine polynomial
//! `q = Q0 + alpha QA + beta QB` and what a loop provides of it ([`Curve`]).
//!
//! Method: D-decomposition (Neimark, 1948; see e.g. Gryazina, Polyak and Tremba, "D-decomposition
//! technique state-of-the-art", *Automation and Remote Control* 69, 2008) as laid out in
//! `docs/MODEL.md` sections 4 and 8. The plane is cut by three kinds of candidate boundary, on
//! which some root of `q` lies on the unit circle: the curve of walls with the root pair
//! `e^{+-i theta}`, the line of the root `z = 1` (`alpha = 0` when the device has a free
//! integrator) and the line of `z = -1`. The paper's loop evaluates the curve on its closed
//! forms ([`PaperCurve`]), a loop with elements by Cramer's rule on its own polynomial
//! ([`LoopCurve`]); the engine does not otherwise tell them apart.
//!
//! A point of a candidate is on the stability boundary exactly when every *other* root is
//! strictly inside the circle: then one side of the candidate is stable and the other is not.
//! That test is local: deflate `q` by the known factor (`z^2 - 2 cos theta z + 1`, `z - 1` or
//! `z + 1`, synthetic division) and run Schur-Cohn on the quotient. So:
//!
//! 1. sample `theta` on a grid of 64 steps per turn of the curve over `[0, pi]` (`64 (n + 2)`
//!    for the paper's loop, whose curve oscillates with `e^{i (n + 2) theta}`;
//!    `64 (degree + 1)` for a loop with elements), the ends being the limits where the pair
//!    merges at `z = +-1` (a double root, two linear equations);
//! 2. keep the `theta` intervals where the deflated test passes, their ends (the corners, where
//!    a second root reaches the circle) located by bisection to `tol / 4` in the plane;
//! 3. refine each kept interval until the chord deviates from the curve by less than `tol`;
//! 4. cut the two lines at every crossing of the curve (and of each other), keep the cut
//!    segments whose midpoint passes the deflated test (a segment running to infinity is never
//!    kept: a stable region is bounded);
//! 5. chain the kept pieces into closed polylines by nearest ends and return the one of
//!    largest area, counterclockwise from its lowest point on the `z = 1` line
//!    (`(0, -delta)` for the paper's loop).

use std::f64::consts::PI;

use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

use rayon::prelude::*;

use super::curve::{Curve, PaperCurve};
use super::refine::{Chain, Midpoint, Refiner, curve_sample, kept_knots, over_budget};
use super::{Boundary, Piece, Vertex, check_tol, too_many_vertices};
use crate::curve::LoopCurve;
use crate::elements::Loop;
use crate::error::{Error, Result};
use crate::geometry::{norm2, point_dist, polygon_area, seg_dist};
use crate::params::{Plant, Wall};
use crate::poly::{Complex, deflate_linear};
use crate::stability::schur_cohn;

/// Options of [`exact`].
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ExactOptions {
    /// Largest distance between the polyline and the true curve, and the accuracy of the
    /// corners (see [`super::DEFAULT_TOL`]).
    pub tol: f64,
}

impl Default for ExactOptions {
    fn default() -> Self {
        Self {
            tol: super::DEFAULT_TOL,
        }
    }
}

/// Neighbouring coarse samples near the region farther apart than its size over this are
/// split ([`Ctx::resolve_fast_parts`]): 128 steps across the region resolve a kept piece of a
/// hundredth of its size, as the uniform grid does where the curve turns at its usual pace.
const FAST_STEP: f64 = 128.0;

/// The most parts one coarse interval is split into (the split's cost is bounded by 64 times
/// the uniform grid's).
const MAX_FAST_SPLIT: f64 = 64.0;

/// Chords within this many of their own lengths of `theta = 0` or `pi` are split at the
/// midpoint in the squared angle from that end (see `Ctx::refine`).
const END_CHORDS: f64 = 8.0;

/// A coarse chord whose curve midpoint lies farther from it than this fraction of its length
/// is probed further ([`Ctx::resolve_hidden_turns`]). A smooth arc turning by `phi` between
/// its ends has its midpoint `tan(phi / 4) / 2` of the chord away, about `phi / 8`: the
/// uniform grid's chords turn by about `2 pi / 64` (a ratio near `0.012`), and `1/16` is an
/// arc turning by half a radian, five times that.
const HIDDEN_TURN: f64 = 1.0 / 16.0;

/// Depth cap of those probes: `pi / 2^40` is below `f64` resolution of `theta`.
const HIDDEN_DEPTH: u32 = 40;

/// Most probes one chord may add ([`Ctx::probe_turns`]). A turn is followed down one branch
/// (two probes a level, 80 to the depth cap) and a long chord is split into pieces of the
/// region's size over [`FAST_STEP`] (about 256 probes for a chord as long as the region);
/// four times the larger of those. Without a cap a region far smaller than its chords
/// (one within rounding of the unit circle, of size `1e-8`) would split every chord into
/// billions of pieces. A chord that runs out keeps the probes it has: a turn left inside it
/// is met by the refinement's midpoint test, and after [`HIDDEN_ROUNDS`] the bisection
/// engine draws the region.
const HIDDEN_PROBES: usize = 1024;

/// Most probes one round of [`Ctx::hidden_samples`] may add over all its chords: a tenth of
/// the vertex budget ([`super::MAX_VERTICES`]), so that the rounds together stay within
/// the memory and time a boundary may take. Chords beyond it are left to the next round's
/// refinement, and the rounds' cap to the bisection engine.
const HIDDEN_ROUND_PROBES: usize = super::MAX_VERTICES / 10;

/// Rounds of finer samples after a refinement met a wall off the region (each round adds
/// the walls met and the probes around them); beyond that the pieces are not trusted and
/// the bisection engine draws the region.
const HIDDEN_ROUNDS: usize = 8;

/// How far (in units of the chaining's join distance) a thin corner may lie from the ends of
/// its two edges ([`thin_corner`]): edges meeting at `1e-3` rad or more. Behind the slowest
/// filters measured the tip's edges meet at about `5e-3` rad.
const THIN_CORNER_SPAN: f64 = 1e3;

/// The exact stability boundary of the loop `lp` (a [`Plant`] for the paper's loop) in the
/// `(alpha, beta)` plane by D-decomposition of its affine polynomial (see the module
/// documentation): the paper's loop on its closed forms, a loop with elements on its own
/// polynomial (`docs/MODEL.md` section 8: the `z = 1` line, the `z = -1` line and the complex
/// curve); one engine for both.
///
/// ```
/// use stabound::boundary::{ExactOptions, exact};
/// use stabound::elements::{Hand, Loop};
/// use stabound::params::Plant;
///
/// let plant = Plant::new(0.2, 1.0)?;
/// let bare = exact(&plant, &ExactOptions { tol: 1e-7 })?;
/// assert!(bare.points.iter().all(|p| p.x >= 0.0));
/// // A hand with stiffness kappa_h = 0.01 makes walls down to alpha = -0.01 stable.
/// let lp = Loop::new(plant).with_hand(Hand::new(0.5, 0.1, 0.01)?)?;
/// let held = exact(&lp, &ExactOptions { tol: 1e-7 })?;
/// let left = held.points.iter().map(|p| p.x).fold(f64::INFINITY, f64::min);
/// assert!((left + 0.01).abs() < 1e-9);
/// # Ok::<(), stabound::Error>(())
/// ```
///
/// Where the kept pieces do not close into one polyline (a kept piece the scan missed), the
/// boundary is that of the bisection engine ([`super::bisect_alpha_beta`], pieces
/// [`Piece::Bisection`]) and [`Boundary::fallback`] says why.
///
/// Errors: `tol` outside `[MIN_TOL, MAX_TOL]` ([`Error::InvalidParameter`]); more than
/// [`MAX_VERTICES`](super::MAX_VERTICES) vertices needed ([`Error::InvalidRequest`], saying
/// which tolerance fits); the bisection engine's errors where it is the fallback.
pub fn exact(lp: impl Into<Loop>, options: &ExactOptions) -> Result<Boundary> {
    let lp = lp.into();
    let tol = check_tol(options.tol)?;
    if lp.is_paper() {
        return exact_on(lp.plant(), options, true);
    }
    or_bisection(&lp, tol, engine(&LoopCurve::new(&lp)?, tol, true))
}

/// [`exact`] of the paper's loop, refining the chords of a curve in parallel (rayon) when
/// `parallel`, else on the calling thread (sweeps run whole curves in parallel instead). The
/// result is the same, and so is the bisection engine's boundary where the pieces do not
/// close.
pub(crate) fn exact_on(plant: &Plant, options: &ExactOptions, parallel: bool) -> Result<Boundary> {
    let tol = check_tol(options.tol)?;
    or_bisection(
        &Loop::new(*plant),
        tol,
        engine(&PaperCurve::new(plant), tol, parallel),
    )
}

/// What the exact engine `found` for `lp`, or where its pieces did not close (a numerical
/// failure: a gap between pieces, or rounds of finer samples that do not settle) the
/// bisection engine's boundary at the same tolerance, with [`Boundary::fallback`] saying
/// why; where that engine fails too, its error carries both reasons.
fn or_bisection(lp: &Loop, tol: f64, found: Result<Boundary>) -> Result<Boundary> {
    match found {
        Err(Error::Numerical(why)) => {
            let mut b = super::bisect_alpha_beta(
                *lp,
                &super::BisectOptions {
                    tol,
                    ..super::BisectOptions::default()
                },
            )
            .map_err(|e| match e {
                // both engines' reasons: the exact one's says why the bisection ran
                Error::Numerical(found) => Error::Numerical(format!("{why}; {found}")),
                other => other,
            })?;
            b.fallback = Some(why);
            Ok(b)
        }
        other => other,
    }
}

/// The D-decomposition of `curve` (steps 1 to 5 of the module documentation).
///
/// Where `tol` would take more than [`MAX_VERTICES`](super::MAX_VERTICES) vertices on a large
/// region (size `s` above 1, its largest coordinate), the boundary is traced once more to
/// the same tolerance relative to the region, `tol s`, and [`Boundary::tol`] says so: a
/// region of size `1e3` to `1e-9` is then drawn to `1e-6`, the same `1e-9` of its size as a
/// region of size 1. Only a boundary that did not fit the budget changes.
fn engine<C: Curve>(curve: &C, tol: f64, parallel: bool) -> Result<Boundary> {
    match trace_at(curve, tol, parallel)? {
        Ok(b) => Ok(b),
        Err(size) => {
            let relative = tol * size;
            if relative > tol
                && relative <= super::MAX_TOL
                && let Ok(b) = trace_at(curve, relative, parallel)?
            {
                return Ok(b);
            }
            Err(too_many_vertices(curve.plant(), tol, size))
        }
    }
}

/// The boundary at `tol` (steps 1 to 5), or `Err(size)` when its refinement went over the
/// vertex budget on a curve of that size.
fn trace_at<C: Curve>(
    curve: &C,
    tol: f64,
    parallel: bool,
) -> Result<std::result::Result<Boundary, f64>> {
    let plant = curve.plant();
    let n0 = curve.coarse_steps();
    let ctx = Ctx {
        curve,
        tol,
        vertices: AtomicUsize::new(0),
        hidden: Mutex::new(Vec::new()),
    };

    // 1. coarse samples of the curve, with the limits at both ends.
    let theta = |i: usize| PI * i as f64 / n0 as f64;
    let samples: Vec<Sample> = if parallel && curve.parallel_scan() {
        (0..=n0)
            .into_par_iter()
            .map(|i| ctx.coarse_sample(theta(i)))
            .collect()
    } else {
        (0..=n0).map(|i| ctx.coarse_sample(theta(i))).collect()
    };
    let samples = if curve.fast_parts() {
        // twice: the first pass finds where the curve is fast, the second resolves the
        // fastest parts in it; then the turns hidden inside one chord
        let once = ctx.resolve_fast_parts(samples, parallel);
        let twice = ctx.resolve_fast_parts(once, parallel);
        ctx.resolve_hidden_turns(twice, parallel)
    } else {
        samples
    };
    crate::cancel::poll()?;
    let last = samples.len() - 1;

    // 2. + 3. kept intervals of the curve: located, then refined (in parallel over the
    // coarse chords when `parallel`). A refinement that meets a wall off the region (a turn
    // hidden inside a chord, see `Ctx::midpoint`) adds it and the probes around it to the
    // samples, and the kept intervals are found again.
    let mut samples = samples;
    let mut pieces: Vec<Chain>;
    let mut round = 0;
    let mut last_hidden = 0;
    loop {
        pieces = Vec::new();
        ctx.vertices.store(0, Ordering::Relaxed);
        let refiner = Refiner {
            tol,
            vertices: &ctx.vertices,
            midpoint: |a: &Sample, b: &Sample| ctx.midpoint(a, b),
            predict: curve.predict(),
        };
        for knots in kept_knots(&samples, |inn, out| ctx.corner(out, inn)) {
            pieces.push(Chain {
                piece: Piece::Curve,
                pts: refiner.polyline(&knots, parallel),
            });
        }
        let hidden = std::mem::take(&mut *ctx.hidden.lock().unwrap_or_else(|e| e.into_inner()));
        if hidden.is_empty() {
            break;
        }
        round += 1;
        // Finer samples settle a curve that turns off the region inside a few chords: each
        // round meets fewer such chords. Where a round meets as many as the one before (a
        // region within rounding of the unit circle, whose curve crosses it at every scale),
        // they double each round, and the pieces are not trusted.
        let unsettled = round > 1 && hidden.len() >= last_hidden;
        last_hidden = hidden.len();
        if round > HIDDEN_ROUNDS || unsettled {
            return Err(Error::Numerical(format!(
                "the curve of delta = {}, d = {} turns off the region inside {} of its chords after {round} rounds of finer samples",
                plant.delta(),
                plant.d(),
                hidden.len()
            )));
        }
        crate::cancel::poll()?;
        let size = region_size(&samples);
        samples.extend(ctx.hidden_samples(&hidden, size));
        samples.sort_by(|a, b| a.theta.total_cmp(&b.theta));
        samples.dedup_by(|a, b| a.theta == b.theta);
    }
    if let Some(size) = over_budget(&ctx.vertices, &samples) {
        return Ok(Err(size));
    }
    // Ends of curve pieces that lie on a line cut that line (corners, and the limits at
    // theta = 0 and pi); within tol, the accuracy they were located to.
    let ends: Vec<Wall> = pieces
        .iter()
        .flat_map(|c| [c.pts[0], c.pts[c.pts.len() - 1]])
        .collect();

    // 4. the lines of z = 1 and z = -1, each cut at the curve, at the other line, at the
    // curve's end on it (the double root) and at the ends of curve pieces on it.
    let plus = curve.line(1.0);
    let minus = curve.line(-1.0);
    for (line, other, end) in [(plus, minus, 0), (minus, plus, last)] {
        let Some(line) = line else { continue };
        let mut cuts: Vec<f64> = Vec::new();
        // the double root at the line's own root is on the line by construction
        if let Some(w) = samples[end].finite() {
            cuts.push(line.param(&w));
        }
        for s in ctx.crossings(&samples, |w| line.residual(w)) {
            cuts.push(line.param(&s));
        }
        if let Some(p) = other.and_then(|o| line.meet(&o)) {
            cuts.push(line.param(&p));
        }
        cuts.extend(
            ends.iter()
                .filter(|w| line.near(w, tol))
                .map(|w| line.param(w)),
        );
        for (lo, hi) in kept_segments(&mut cuts, tol, |t| ctx.line_keep(&line.at(t), line.root)) {
            pieces.push(Chain {
                piece: line.piece,
                pts: vec![line.at(lo), line.at(hi)],
            });
        }
    }

    // 5. chain, starting on the z = 1 line.
    let start_alpha = plus.map_or(f64::NAN, |l| l.at(0.0).alpha);
    let points = chain(pieces, tol, plant, start_alpha)?;
    Ok(Ok(Boundary {
        delta: plant.delta(),
        d: plant.d(),
        tol,
        points,
        fallback: None,
    }))
}

/// One sample of the curve: `theta`, the wall, and whether it is on the boundary.
#[derive(Debug, Clone, Copy)]
struct Sample {
    theta: f64,
    /// `e^{i theta}` and `e^{i k theta}` (`k` the curve's [`Curve::circle_power`]), so that
    /// refinement finds the midpoint's by bisecting angles instead of evaluating sines and
    /// cosines.
    z: Complex,
    zk: Complex,
    wall: Wall,
    /// The wall is finite and every root other than the pair `e^{+-i theta}` is inside.
    keep: bool,
    valid: bool,
}

impl Sample {
    fn finite(&self) -> Option<Wall> {
        self.valid.then_some(self.wall)
    }
}

struct Ctx<'a, C> {
    curve: &'a C,
    tol: f64,
    /// Vertices added by refinement so far, against [`MAX_VERTICES`](super::MAX_VERTICES).
    vertices: AtomicUsize,
    /// Chords `(a, m, b)` whose refinement met a midpoint `m` off the region (see
    /// [`Ctx::midpoint`]).
    hidden: Mutex<Vec<(Sample, Sample, Sample)>>,
}

impl<C: Curve> Ctx<'_, C> {
    fn sample(&self, theta: f64) -> Sample {
        let (z, zk) = self.sample_z(theta);
        self.sample_with(theta, z, zk)
    }

    /// The coarse samples with more samples wherever two neighbours near the region lie far
    /// apart in the plane (see [`FAST_STEP`]), in order of `theta`.
    ///
    /// Near a zero of the Cramer determinant on the circle (a moving average's numerator
    /// vanishes at `z = e^{2 pi i k / N}`) the curve runs off to infinity and back, ever
    /// faster, and a kept piece between two self-intersections can be shorter than one
    /// coarse step in `theta` though long in the plane: missed, the boundary does not close.
    fn resolve_fast_parts(&self, samples: Vec<Sample>, parallel: bool) -> Vec<Sample> {
        let size = region_size(&samples);
        let step = size / FAST_STEP;
        let near = |s: &Sample| s.valid && s.wall.alpha.abs().max(s.wall.beta.abs()) <= 2.0 * size;
        let mut extra: Vec<f64> = Vec::new();
        for w in samples.windows(2) {
            let (a, b) = (&w[0], &w[1]);
            if !(near(a) || near(b)) {
                continue;
            }
            // next to a sample where the curve is at infinity, as finely as allowed
            let k = if a.valid && b.valid {
                (dist(&a.wall, &b.wall) / step).ceil().min(MAX_FAST_SPLIT)
            } else {
                MAX_FAST_SPLIT
            };
            for i in 1..k as usize {
                extra.push(a.theta + (b.theta - a.theta) * i as f64 / k);
            }
        }
        if extra.is_empty() {
            return samples;
        }
        let added: Vec<Sample> = if parallel {
            extra.par_iter().map(|&t| self.coarse_sample(t)).collect()
        } else {
            extra.iter().map(|&t| self.coarse_sample(t)).collect()
        };
        let mut all = samples;
        all.extend(added);
        all.sort_by(|a, b| a.theta.total_cmp(&b.theta));
        all
    }

    /// The samples with the probes of [`Ctx::probe_turns`] added in every chord where they
    /// show a change of the deflated test that its two ends do not, in order of `theta`.
    ///
    /// Refinement takes every point between two kept samples as kept. Where the curve runs
    /// far out and back within one chord (an excursion towards a near-zero of the Cramer
    /// determinant, as behind a slow second-order filter, where it reaches stiffnesses near
    /// `1e5` and back between two samples at the region's tip), the walls out there have
    /// other roots outside the circle, and drawn as boundary they are vertices outside the
    /// region; a kept piece out there (an edge of the region) is missed likewise. Such a
    /// chord's midpoint lies far off it, so probing each chord whose midpoint deviates by more
    /// than [`HIDDEN_TURN`] of its length finds them; a chord whose probes all agree with its
    /// ends keeps its old knots (the polyline of an ordinary curve does not change).
    fn resolve_hidden_turns(&self, samples: Vec<Sample>, parallel: bool) -> Vec<Sample> {
        let size = region_size(&samples);
        let probe = |w: &[Sample]| -> Vec<Sample> {
            let (a, b) = (&w[0], &w[1]);
            // A short chord between two kept samples is left to the refinement, which tests
            // every midpoint it meets far off its chord (see `Ctx::midpoint`) and computes that
            // midpoint anyway; only the others can turn off the region unseen.
            if !(a.valid && b.valid) || (a.keep && b.keep && !long_chord(a, b, size)) {
                return Vec::new();
            }
            let mut found = Vec::new();
            let mut left = HIDDEN_PROBES;
            self.probe_turns(a, b, size, 0, &mut left, &mut found);
            found.sort_by(|x, y| x.theta.total_cmp(&y.theta));
            let changes = std::iter::once(a)
                .chain(&found)
                .chain(std::iter::once(b))
                .collect::<Vec<_>>()
                .windows(2)
                .filter(|p| p[0].keep != p[1].keep)
                .count();
            if changes > usize::from(a.keep != b.keep) {
                found
            } else {
                Vec::new()
            }
        };
        let extra: Vec<Sample> = if parallel {
            samples.par_windows(2).flat_map_iter(probe).collect()
        } else {
            samples.windows(2).flat_map(probe).collect()
        };
        if extra.is_empty() {
            return samples;
        }
        let mut all = samples;
        all.extend(extra);
        all.sort_by(|a, b| a.theta.total_cmp(&b.theta));
        all
    }

    /// Samples (each tested) at the midpoints in `theta` of the chord from `a` to `b` and of
    /// its halves, recursively, wherever the midpoint lies farther than [`HIDDEN_TURN`] of
    /// the chord's length (and farther than `tol`) from it, at most `left` of them.
    fn probe_turns(
        &self,
        a: &Sample,
        b: &Sample,
        size: f64,
        depth: u32,
        left: &mut usize,
        out: &mut Vec<Sample>,
    ) {
        let mid = 0.5 * (a.theta + b.theta);
        if depth >= HIDDEN_DEPTH || *left == 0 || mid <= a.theta || mid >= b.theta {
            return;
        }
        let (z, zk) = self.sample_z(mid);
        // at infinity (the determinant vanishes exactly): the fast-part scan's business
        let Some(wall) = self.curve.wall_at(z, zk) else {
            return;
        };
        let dev = seg_dist(wall.xy(), a.wall.xy(), b.wall.xy());
        let len = dist(&a.wall, &b.wall);
        // a chord that turns, or a long chord next to the region (a straight run out of it
        // and back can hide the region's corner where it leaves)
        let long = long_chord(a, b, size);
        if !((dev > HIDDEN_TURN * len && dev > self.tol) || long) {
            return;
        }
        let m = self.sample_of(mid, z, zk, Some(wall), |w| self.curve.may_bound(w));
        out.push(m);
        *left -= 1;
        self.probe_turns(a, &m, size, depth + 1, left, out);
        self.probe_turns(&m, b, size, depth + 1, left, out);
    }

    /// Samples for the chords whose refinement met a wall off the region: each chord's ends
    /// and that wall, tested, and the probes of [`Ctx::probe_turns`] on both halves.
    fn hidden_samples(&self, hidden: &[(Sample, Sample, Sample)], size: f64) -> Vec<Sample> {
        let mut out = Vec::new();
        let mut round_left = HIDDEN_ROUND_PROBES;
        for (a, m, b) in hidden {
            let a = self.sample_with(a.theta, a.z, a.zk);
            let b = self.sample_with(b.theta, b.z, b.zk);
            let mut left = HIDDEN_PROBES.min(round_left);
            let before = left;
            self.probe_turns(&a, m, size, 0, &mut left, &mut out);
            self.probe_turns(m, &b, size, 0, &mut left, &mut out);
            round_left -= before - left;
            out.extend([a, *m, b]);
        }
        out
    }

    /// [`Ctx::sample`] for the coarse grid, where a wall that surely has a real root
    /// outside the circle is rejected without a test ([`Curve::may_bound`]).
    fn coarse_sample(&self, theta: f64) -> Sample {
        let (z, zk) = self.sample_z(theta);
        if theta <= 0.0 || theta >= PI {
            return self.sample_with(theta, z, zk);
        }
        let wall = self.curve.wall_at(z, zk);
        self.sample_of(theta, z, zk, wall, |w| self.curve.may_bound(w))
    }

    /// `e^{i theta}` and `e^{i k theta}`.
    fn sample_z(&self, theta: f64) -> (Complex, Complex) {
        let (sin, cos) = theta.sin_cos();
        let k = self.curve.circle_power() as f64;
        let (sin_k, cos_k) = (k * theta).sin_cos();
        (Complex::new(cos, sin), Complex::new(cos_k, sin_k))
    }

    /// The sample at `theta` with `z = e^{i theta}` and `zk = z^k` given.
    fn sample_with(&self, theta: f64, z: Complex, zk: Complex) -> Sample {
        let wall = if theta <= 0.0 || theta >= PI {
            self.curve.wall(theta)
        } else {
            self.curve.wall_at(z, zk)
        };
        self.sample_of(theta, z, zk, wall, |_| true)
    }
    /// The sample of `wall` at `theta`, tested only when `worth_testing` says it may bound
    /// the region.
    fn sample_of(
        &self,
        theta: f64,
        z: Complex,
        zk: Complex,
        wall: Option<Wall>,
        worth_testing: impl Fn(&Wall) -> bool,
    ) -> Sample {
        match wall {
            Some(wall) => Sample {
                theta,
                z,
                zk,
                wall,
                keep: worth_testing(&wall) && self.curve_keep(theta, &wall),
                valid: true,
            },
            None => Sample {
                theta,
                z,
                zk,
                wall: Wall {
                    alpha: f64::NAN,
                    beta: f64::NAN,
                },
                keep: false,
                valid: false,
            },
        }
    }

    /// Every root of `q` other than `e^{+-i theta}` strictly inside the unit circle.
    fn curve_keep(&self, theta: f64, wall: &Wall) -> bool {
        self.with_two(|buf, out| {
            let q = self.curve.coefficients_into(wall, buf);
            let s = deflate_quadratic(q, theta.cos(), out);
            // Radius exactly 1: the boundary is where a root crosses the circle, and the
            // corners are then located to rounding rather than shifted by a margin.
            schur_cohn(s, 1.0).stable
        })
    }

    /// On the line of the root `z = root` (`+-1`): every other root strictly inside.
    fn line_keep(&self, wall: &Wall, root: f64) -> bool {
        self.with_two(|buf, out| {
            let q = self.curve.coefficients_into(wall, buf);
            let s = deflate_linear(q, root, out);
            schur_cohn(s, 1.0).stable
        })
    }

    /// Two scratch rows as long as the coefficients, only that length zeroed (a full
    /// `MAX_COEFFS` pair per test cost more than the test itself at long delays).
    fn with_two<R>(&self, f: impl FnOnce(&mut [f64], &mut [f64]) -> R) -> R {
        crate::stability::schur_cohn::with_two_rows(self.curve.degree() + 1, f)
    }

    /// The corner between a rejected sample `out` and a kept sample `inn`, by bisection in
    /// `theta` until the two walls are within `tol / 4` (or `theta` stops changing).
    fn corner(&self, out: &Sample, inn: &Sample) -> Sample {
        let (mut o, mut i) = (*out, *inn);
        for _ in 0..200 {
            if o.valid && dist(&o.wall, &i.wall) <= 0.25 * self.tol {
                break;
            }
            let mid = 0.5 * (o.theta + i.theta);
            if mid == o.theta || mid == i.theta {
                break;
            }
            let s = self.sample(mid);
            if s.keep {
                i = s;
            } else {
                o = s;
            }
        }
        i
    }

    /// Points where the curve crosses the zero set of the linear function `f`, between coarse
    /// samples with opposite signs, by bisection in `theta` to `tol / 4` in the plane.
    fn crossings(&self, samples: &[Sample], f: impl Fn(&Wall) -> f64) -> Vec<Wall> {
        let mut out = Vec::new();
        for w in samples.windows(2) {
            let (a, b) = (&w[0], &w[1]);
            if !(a.valid && b.valid) {
                continue;
            }
            let (fa, fb) = (f(&a.wall), f(&b.wall));
            if (fa * fb).is_nan() || fa * fb >= 0.0 {
                continue;
            }
            // (theta, wall) of the two ends of the bracket
            let (mut lo, mut hi) = ((a.theta, a.wall), (b.theta, b.wall));
            let flo = fa;
            for _ in 0..200 {
                if dist(&lo.1, &hi.1) <= 0.25 * self.tol {
                    break;
                }
                let mid = 0.5 * (lo.0 + hi.0);
                if mid == lo.0 || mid == hi.0 {
                    break;
                }
                let Some(wall) = self.curve.wall(mid) else {
                    break;
                };
                if f(&wall) * flo > 0.0 {
                    lo = (mid, wall);
                } else {
                    hi = (mid, wall);
                }
            }
            // the point on the curve nearer the line
            out.push(if f(&lo.1).abs() < f(&hi.1).abs() {
                lo.1
            } else {
                hi.1
            });
        }
        out
    }

    /// The midpoint of the chord between `a` and `b` for the shared refinement: in `theta`,
    /// or next to `theta = 0` and `pi` in the squared angle from that end (not
    /// [`Midpoint::smooth`] there).
    // Inlined into the shared recursion: called out of line, its result (a whole sample)
    // went through memory and the main job took 6 % more instructions (32.2 M, not 30.6 M).
    #[inline(always)]
    fn midpoint(&self, a: &Sample, b: &Sample) -> Option<Midpoint<Sample>> {
        // Next to theta = 0 and pi the curve is an even function of the angle from that end
        // (q has real coefficients, so wall(-theta) = wall(theta)): smooth in u = theta^2, not
        // in theta, and a chord's largest deviation sits at the midpoint in u. The midpoint
        // in theta sits a quarter of the way in u on a chord that starts at the end, where
        // the deviation is only 3/4 of the largest, which let the polyline exceed tol there
        // by a third. So within 8 chord lengths of an end the midpoint is taken in u (on
        // the chord from r to r + 1 lengths from the end, the midpoint in theta sees
        // 4 s (1 - s) of the largest deviation, s = (r + 1/4) / (2 r + 1): 0.9991 at r = 8).
        let len = b.theta - a.theta;
        let (from_zero, from_pi) = (a.theta, PI - b.theta);
        let near_end = if from_zero <= END_CHORDS * len {
            Some(a.theta.hypot(b.theta) * std::f64::consts::FRAC_1_SQRT_2)
        } else if from_pi <= END_CHORDS * len {
            let (pa, pb) = (PI - a.theta, (PI - b.theta).max(0.0));
            Some(PI - pa.hypot(pb) * std::f64::consts::FRAC_1_SQRT_2)
        } else {
            None
        };
        let (mid, z, zk) = match near_end {
            Some(mid) => {
                let s = self.sample_z(mid);
                (mid, s.0, s.1)
            }
            None => {
                let mid = 0.5 * (a.theta + b.theta);
                // e^{i mid} is the normalized sum of e^{i a} and e^{i b}, and likewise for
                // the (n + 2)-th powers, whose angles differ by at most pi / 64 within a
                // coarse chord. Each level adds a few ulps of angle error, so after
                // 40 levels (the depth cap) a midpoint is off the exact curve by about 1e-14 of the
                // wall's size: far below MIN_TOL.
                match (mid_unit(a.z, b.z), mid_unit(a.zk, b.zk)) {
                    (Some(z), Some(zk)) => (mid, z, zk),
                    _ => {
                        let s = self.sample_z(mid);
                        (mid, s.0, s.1)
                    }
                }
            }
        };
        let m = self.curve.wall_at(z, zk)?;
        let sample = Sample {
            theta: mid,
            z,
            zk,
            wall: m,
            keep: true,
            valid: true,
        };
        // A midpoint far off its chord (relative to its length) is where the curve may turn
        // off the region inside the chord: tested, and where it is off, the chord is left to
        // the next round ([`Ctx::hidden_samples`]). Only curves that may run off to
        // infinity turn so; the paper's curve is not tested here.
        if self.curve.fast_parts()
            && far_off(m.xy(), a.wall.xy(), b.wall.xy(), HIDDEN_TURN)
            && !(self.curve.may_bound(&m) && self.curve_keep(mid, &m))
        {
            let mut hidden = self.hidden.lock().unwrap_or_else(|e| e.into_inner());
            hidden.push((
                *a,
                Sample {
                    keep: false,
                    ..sample
                },
                *b,
            ));
            return None;
        }
        Some(Midpoint {
            sample,
            smooth: near_end.is_none(),
        })
    }
}

curve_sample!(Sample);

/// The sorted cut points of a line and the segments between consecutive cuts whose midpoint
/// passes `keep`. Unbounded end rays are never kept (the stable region is bounded).
///
/// Cuts closer than `tol` are one cut found twice (a corner is located from the curve side
/// and from the line side, each to `tol / 4`); they are merged.
pub(crate) fn kept_segments(
    cuts: &mut Vec<f64>,
    tol: f64,
    keep: impl Fn(f64) -> bool,
) -> Vec<(f64, f64)> {
    cuts.retain(|c| c.is_finite());
    cuts.sort_by(f64::total_cmp);
    cuts.dedup_by(|a, b| (*a - *b).abs() <= tol);
    let mut out: Vec<(f64, f64)> = Vec::new();
    for w in cuts.windows(2) {
        if keep(0.5 * (w[0] + w[1])) {
            match out.last_mut() {
                // adjacent kept segments (a spurious cut) merge into one
                Some(last) if last.1 == w[0] => last.1 = w[1],
                _ => out.push((w[0], w[1])),
            }
        }
    }
    out
}

/// `q / (z^2 - 2 cos(theta) z + 1)` by synthetic division from the top (the remainder,
/// zero up to rounding on the curve, is dropped). Lowest power first.
pub(crate) fn deflate_quadratic<'a>(q: &[f64], cos: f64, out: &'a mut [f64]) -> &'a [f64] {
    let m = q.len() - 1;
    let len = m - 1;
    let s = &mut out[..len];
    let two_c = 2.0 * cos;
    for j in (0..len).rev() {
        // q_{j+2} = s_j - 2c s_{j+1} + s_{j+2}
        let s1 = if j + 1 < len { s[j + 1] } else { 0.0 };
        let s2 = if j + 2 < len { s[j + 2] } else { 0.0 };
        s[j] = q[j + 2] + two_c * s1 - s2;
    }
    s
}

/// The unit complex number halfway in angle between the unit numbers `u` and `v`:
/// `(u + v) / |u + v|`. `None` when they are more than about 150 degrees apart, where the sum
/// is short and the quotient loses accuracy (never for neighbouring samples).
fn mid_unit(u: Complex, v: Complex) -> Option<Complex> {
    let (re, im) = (u.re + v.re, u.im + v.im);
    let len = norm2(re, im);
    (len > 0.5).then(|| Complex::new(re / len, im / len))
}

/// A chord longer than `1 / FAST_STEP` of the region's `size` with an end next to the region
/// (within twice its size): a straight run out of the region and back can hide its corner.
fn long_chord(a: &Sample, b: &Sample, size: f64) -> bool {
    let near = |w: &Wall| w.alpha.abs().max(w.beta.abs()) <= 2.0 * size;
    dist(&a.wall, &b.wall) > size / FAST_STEP && (near(&a.wall) || near(&b.wall))
}

/// Whether `m` lies farther than `ratio` times the chord's length from the chord `[a, b]`
/// ([`seg_dist`] against `ratio |b - a|`), compared in squares: no square root or division,
/// as it runs at every refinement midpoint.
fn far_off(m: (f64, f64), a: (f64, f64), b: (f64, f64), ratio: f64) -> bool {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let (px, py) = (m.0 - a.0, m.1 - a.1);
    let len2 = dx * dx + dy * dy;
    let dot = px * dx + py * dy;
    let r2 = ratio * ratio * len2;
    if dot <= 0.0 {
        // nearest to `a` (and a chord of one point)
        px * px + py * py > r2
    } else if dot >= len2 {
        let (qx, qy) = (m.0 - b.0, m.1 - b.1);
        qx * qx + qy * qy > r2
    } else {
        // squared distance to the line is cross^2 / len2
        let cross = px * dy - py * dx;
        cross * cross > r2 * len2
    }
}

/// The region's size: the largest coordinate of a kept sample (at least 1).
fn region_size(samples: &[Sample]) -> f64 {
    samples.iter().filter(|s| s.keep).fold(1.0f64, |m, s| {
        m.max(s.wall.alpha.abs()).max(s.wall.beta.abs())
    })
}

fn dist(a: &Wall, b: &Wall) -> f64 {
    point_dist(a.xy(), b.xy())
}

/// Chains the pieces into closed loops by nearest endpoints, keeps the loop of largest area,
/// orients it counterclockwise and starts it at its lowest point on the `z = 1` line
/// `alpha = start_alpha` (`alpha = 0` with a free integrator).
fn chain(mut pieces: Vec<Chain>, tol: f64, plant: &Plant, start_alpha: f64) -> Result<Vec<Vertex>> {
    let fail = |what: String| {
        Error::Numerical(format!(
            "the boundary of delta = {}, d = {} did not close ({what}); its stable region may be empty or unbounded: try a larger tolerance or the bisection engine",
            plant.delta(),
            plant.d()
        ))
    };
    if pieces.is_empty() {
        return Err(fail("no boundary piece found".into()));
    }
    let scale = pieces
        .iter()
        .flat_map(|c| c.pts.iter())
        .fold(1.0f64, |m, w| m.max(w.alpha().abs()).max(w.beta().abs()));
    // Corners are located to tol / 4 by two independent bisections (curve side and line
    // side), so ends that belong together are within about tol; 100 tol leaves room for
    // rounding of quantities of size `scale`.
    let join = 100.0 * tol * scale;
    let mut loops: Vec<Vec<Vertex>> = Vec::new();
    while !pieces.is_empty() {
        let first = pieces.remove(0);
        let start = first.pts[0];
        let after_start = first.pts[1.min(first.pts.len() - 1)];
        let mut lp: Vec<Vertex> = Vec::new();
        let mut cur = first;
        loop {
            let last = *cur.pts.last().unwrap_or(&start);
            for w in &cur.pts[..cur.pts.len() - 1] {
                lp.push(Vertex {
                    x: w.alpha(),
                    y: w.beta(),
                    piece: cur.piece,
                });
            }
            // nearest free end, or the loop's start
            let mut best: Option<(f64, usize, bool)> = None;
            for (idx, c) in pieces.iter().enumerate() {
                for (rev, end) in [
                    (false, c.pts[0]),
                    (true, *c.pts.last().unwrap_or(&c.pts[0])),
                ] {
                    let dd = dist(&last, &end);
                    if best.is_none_or(|b| dd < b.0) {
                        best = Some((dd, idx, rev));
                    }
                }
            }
            let close = dist(&last, &start);
            match best {
                Some((dd, idx, rev)) if dd < close && dd <= join => {
                    let mut next = pieces.remove(idx);
                    if rev {
                        next.pts.reverse();
                    }
                    // One vertex for the corner: a line's end lies exactly on its line.
                    if cur.piece != Piece::Curve && next.piece == Piece::Curve {
                        next.pts[0] = last;
                    }
                    cur = next;
                }
                _ if close > join => {
                    // no end within `join`: the two edges of a thin corner (see `thin_corner`)
                    let before = cur.pts[cur.pts.len().saturating_sub(2)];
                    let mut tip: Option<(f64, EndRef, Wall)> = None;
                    let mut consider = |dd: f64, which: EndRef, end: Wall, after: Wall| {
                        if tip.as_ref().is_none_or(|t| dd < t.0)
                            && let Some(p) = thin_corner(before, last, end, after, join)
                        {
                            tip = Some((dd, which, p));
                        }
                    };
                    for (idx, c) in pieces.iter().enumerate() {
                        let n = c.pts.len();
                        consider(
                            dist(&last, &c.pts[0]),
                            Some((idx, false)),
                            c.pts[0],
                            c.pts[1.min(n - 1)],
                        );
                        consider(
                            dist(&last, &c.pts[n - 1]),
                            Some((idx, true)),
                            c.pts[n - 1],
                            c.pts[n.saturating_sub(2)],
                        );
                    }
                    consider(close, None, start, after_start);
                    match tip {
                        Some((_, Some((idx, rev)), p)) => {
                            let mut next = pieces.remove(idx);
                            if rev {
                                next.pts.reverse();
                            }
                            next.pts[0] = p;
                            cur = next;
                        }
                        Some((_, None, p)) => {
                            if let Some(p0) = lp.first_mut() {
                                p0.x = p.alpha;
                                p0.y = p.beta;
                            }
                            break;
                        }
                        None => return Err(fail(format!("a gap of {close:e} between pieces"))),
                    }
                }
                _ => {
                    let end_piece = cur.piece;
                    if end_piece != Piece::Curve
                        && let Some(p0) = lp.first_mut()
                        && p0.piece == Piece::Curve
                    {
                        p0.x = last.alpha();
                        p0.y = last.beta();
                    }
                    break;
                }
            }
        }
        loops.push(lp);
    }
    let mut best = loops
        .into_iter()
        .max_by(|a, b| {
            let area = |l: &Vec<Vertex>| {
                polygon_area(&l.iter().map(|p| (p.x, p.y)).collect::<Vec<_>>()).abs()
            };
            area(a).total_cmp(&area(b))
        })
        .ok_or_else(|| fail("no loop".into()))?;
    orient_and_close(&mut best, tol * scale, start_alpha);
    Ok(best)
}

/// A free piece's end in the chaining: its index and whether it runs reversed (`None`: the
/// loop's own start).
type EndRef = Option<(usize, bool)>;

/// The corner where a piece ending at `a` (its last segment from `a0`) meets a piece starting
/// at `b` (its first segment towards `b1`) when the two ends are farther apart than `join`
/// but are the two edges of a thin corner: the intersection `p` of the two segments' lines,
/// when each end lies within `join` of the other's line and `p` within [`THIN_CORNER_SPAN`]
/// `join` of both ends.
///
/// Each end is located to about `tol` across its own edge, but a corner is where the edge
/// meets the other one, and where the two meet at an angle `phi` an error `e` across one edge
/// moves the corner by `e / sin phi` along the other: behind a slow second-order filter the
/// region's tip is a wedge of about `0.005` rad and its two ends lie `1.4e-7` apart at `tol =
/// 1e-9`. The distance from `a` to the other line is exactly `|p - a| sin phi`, so the test
/// asks what the plain join asks, across the edges instead of between the ends; `p` lies on
/// both lines, so both root pairs are on the circle there to the edges' accuracy.
fn thin_corner(a0: Wall, a: Wall, b: Wall, b1: Wall, join: f64) -> Option<Wall> {
    let u = (a.alpha - a0.alpha, a.beta - a0.beta);
    let v = (b1.alpha - b.alpha, b1.beta - b.beta);
    let cross = u.0 * v.1 - u.1 * v.0;
    let (lu, lv) = (norm2(u.0, u.1), norm2(v.0, v.1));
    // `cross / (lu lv)` is `sin phi`: edges meeting at less than `1 / THIN_CORNER_SPAN` rad
    // are nearly one line (a gap along it is a missing piece, not a corner), and parallel
    // ones or a one-point segment have no corner
    if cross.abs() <= lu * lv / THIN_CORNER_SPAN || cross.is_nan() {
        return None;
    }
    let w = (b.alpha - a.alpha, b.beta - a.beta);
    let t = (w.0 * v.1 - w.1 * v.0) / cross;
    let p = Wall {
        alpha: a.alpha + t * u.0,
        beta: a.beta + t * u.1,
    };
    // distance from a point to the line through `o` along `d`
    let off = |q: &Wall, o: &Wall, d: (f64, f64), ld: f64| {
        ((q.alpha - o.alpha) * d.1 - (q.beta - o.beta) * d.0).abs() / ld
    };
    let near = off(&a, &b, v, lv) <= join && off(&b, &a, u, lu) <= join;
    let span = THIN_CORNER_SPAN * join;
    (near
        && dist(&p, &a) <= span
        && dist(&p, &b) <= span
        && p.alpha.is_finite()
        && p.beta.is_finite())
    .then_some(p)
}

/// Orients a loop counterclockwise, starts it at its lowest vertex within `eps` of the line
/// `alpha = start_alpha` (lowest vertex overall if none is there) and repeats the first
/// vertex at the end. The piece label of each vertex is the piece of its outgoing segment in
/// the new direction.
pub(crate) fn orient_and_close(lp: &mut Vec<Vertex>, eps: f64, start_alpha: f64) {
    let xy: Vec<(f64, f64)> = lp.iter().map(|p| (p.x, p.y)).collect();
    if polygon_area(&xy) < 0.0 {
        // reversing moves each segment's label to its other end
        let n = lp.len();
        let labels: Vec<Piece> = (0..n).map(|i| lp[(i + n - 1) % n].piece).collect();
        for (p, l) in lp.iter_mut().zip(labels) {
            p.piece = l;
        }
        lp.reverse();
    }
    let on_axis = |p: &Vertex| (p.x - start_alpha).abs() <= eps;
    let pick = |only_axis: bool| {
        lp.iter()
            .enumerate()
            .filter(|(_, p)| !only_axis || on_axis(p))
            .min_by(|a, b| a.1.y.total_cmp(&b.1.y))
            .map(|(i, _)| i)
    };
    let start = pick(true).or_else(|| pick(false)).unwrap_or(0);
    lp.rotate_left(start);
    if let Some(&p0) = lp.first() {
        lp.push(p0);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn far_off_agrees_with_the_segment_distance() {
        // points before, beside and past the chord from (0, 0) to (4, 3) (length 5), and a
        // chord of one point
        let (a, b) = ((0.0, 0.0), (4.0, 3.0));
        // the threshold is 5 / 16 = 0.3125; distances 0.2 and 0.4 from a, 0 and 0.4 and
        // 0.096 from the line inside the chord, 0.2 and 0.4 from b
        let points = [
            (-0.2, 0.0),
            (-0.4, 0.0),
            (2.0, 1.5),
            (2.0, 1.0),
            (2.0, 1.38),
            (4.2, 3.0),
            (4.4, 3.0),
        ];
        let mut far = 0;
        for m in points {
            let expect = seg_dist(m, a, b) > HIDDEN_TURN * 5.0;
            far += usize::from(expect);
            assert_eq!(far_off(m, a, b, HIDDEN_TURN), expect, "{m:?}");
        }
        // both answers occur
        assert_eq!(far, 3);
        assert!(far_off((1.0, 0.0), (0.0, 0.0), (0.0, 0.0), HIDDEN_TURN));
        assert!(!far_off((0.0, 0.0), (0.0, 0.0), (0.0, 0.0), HIDDEN_TURN));
    }

    #[test]
    fn deflation_recovers_factors() {
        // (z^2 - 2 cos t z + 1)(z - 0.5)(z + 0.25) and (z - 1)(z - 0.5)
        let t: f64 = 0.7;
        let c = t.cos();
        // (z - 0.5)(z + 0.25) = z^2 - 0.25 z - 0.125
        let s = [-0.125, -0.25, 1.0];
        let quad = [1.0, -2.0 * c, 1.0];
        let mut q = [0.0; 5];
        for (i, a) in s.iter().enumerate() {
            for (j, b) in quad.iter().enumerate() {
                q[i + j] += a * b;
            }
        }
        let mut out = [0.0; 8];
        let got = deflate_quadratic(&q, c, &mut out);
        for (g, e) in got.iter().zip(&s) {
            assert!((g - e).abs() < 1e-15);
        }
        let mut out = [0.0; 8];
        let got = deflate_linear(&[0.5, -1.5, 1.0], 1.0, &mut out);
        assert_eq!(got.len(), 2);
        assert!((got[0] + 0.5).abs() < 1e-15 && (got[1] - 1.0).abs() < 1e-15);
    }
}
