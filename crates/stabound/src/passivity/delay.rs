//! The passive region for any whole-sample delay and velocity filter, without a grid.
//!
//! Colgate and Schenkel ("Passivity of a class of sampled-data systems: application to haptic
//! interfaces", J. Robotic Systems 14(1), 1997) show that a damped mass coupled through a
//! sampler and a zero-order hold to a causal discrete environment `H(z)` is passive iff
//! `b > (T/2) Re{(1 - e^{-i w T}) H(e^{i w T})} / (1 - cos w T)` for `0 < w T <= pi`. With
//! `H(z) = z^{-n} (alpha + beta F(z) (1 - z^{-1}))` (the model document, docs/MODEL.md,
//! section 9), in normalized parameters:
//!
//! ```text
//! delta > (1/2) max over 0 <= theta <= pi of  alpha A(theta) + beta B(theta)
//! A(theta) = sin((n + 1/2) theta) / sin(theta / 2) = 1 + 2 sum_{k=1..n} cos(k theta)
//! B(theta) = -2 Re{ e^{-i (n + 1) theta} F(e^{i theta}) }
//! ```
//!
//! (`(1 - e^{-i theta})^2 = -4 sin^2(theta/2) e^{-i theta}` and `1 - cos theta = 2
//! sin^2(theta/2)` remove the apparent singularity at `theta = 0`; both functions are smooth on
//! `[0, pi]`, and the supremum over `0 < theta` is the maximum over the closed interval.)
//! At `theta = 0`, `A = 2n + 1` and `B = -2` (`F(1) = 1`): Diolaiti et al.'s delay bound.
//!
//! For each `theta` the condition is a half-plane in `(alpha, beta)` (and in `(delta, beta)`),
//! so the passive region is convex: an intersection of half-planes whose edge is their
//! envelope, with corners where the maximizing `theta` jumps.
//!
//! Methods:
//! - The maximum over `theta` is a certified global maximization: branch and bound on
//!   `[0, pi]` with a proven bound `M` on `|f''|` (from the Fourier coefficients of `A` and
//!   `B`), using `max over [t0, t1] <= max(f(t0), f(t1)) + M (t1 - t0)^2 / 8` (the error of
//!   linear interpolation of a function with `|f''| <= M`). It returns an interval
//!   `[value, upper]` holding the true maximum, `upper - value <= MAX_TOL_REL * scale`.
//! - The edge is traced by the sandwich algorithm for convex sets (Rote, "The convergence rate
//!   of the sandwich algorithm for approximating convex functions", Computing 48, 1992): each
//!   edge point comes with its supporting line (the active half-plane); between two edge
//!   points the edge lies in the triangle of the chord and the two supporting lines, so the
//!   distance of that triangle's apex to the chord bounds the polyline's error, and arcs are
//!   split (at the edge point towards the apex) until it is below `tol`. At a corner the apex
//!   is the corner itself and the split lands on it.
//!
//! Stiffness is restricted to `alpha >= 0`: a negative spring gives energy back at zero
//! frequency, which the condition over `0 < theta` does not see, and no wall with `alpha < 0`
//! is stable (the line `alpha = 0` bounds every stable region).

use std::f64::consts::PI;

use crate::boundary::{self, ExactOptions, MAX_TOL, MIN_TOL, Vertex};
use crate::elements::Loop;
use crate::error::{Error, Result};
use crate::filter::VelocityFilter;
use crate::geometry::{inside_polygon, seg_dist};
use crate::golden::golden_max;
use crate::params::{MAX_DELAY, MAX_DELTA, Plant, Wall, finite, in_range};
use crate::poly::Complex;
use crate::stability::{Checker, Options, Verdict};

/// Certified accuracy of every maximum over `theta`, relative to the scale `|c_A| (2n + 1) +
/// 2 |c_B|` that bounds `|c_A A + c_B B|`. `1e-12` is three orders above the rounding of the
/// sums (`n + N` terms of order 1, a few `1e-16` each) and three below the smallest edge
/// tolerance accepted, [`MIN_TOL`] scaled by the region's size.
pub const MAX_TOL_REL: f64 = 1e-12;

/// The most edge points one region may have: a region at [`MIN_TOL`] has a few thousand;
/// the cap stops a pathological request instead of exhausting memory.
pub const MAX_EDGE_POINTS: usize = 200_000;

/// Branch-and-bound steps allowed in one maximum before it is declared a numerical failure
/// (far above the few hundred a maximum needs; see the module documentation).
const MAX_BB_STEPS: usize = 2_000_000;

/// The passivity criterion of one loop: whole-sample delay `n` and velocity filter `F`.
#[derive(Debug, Clone, PartialEq)]
pub struct Criterion {
    n: usize,
    filter: VelocityFilter,
    num: Vec<f64>,
    den: Vec<f64>,
    /// Bounds on `|A''|` and `|B''|` over the real line.
    a2: f64,
    b2: f64,
}

/// A certified maximum over `theta` in `[0, pi]`.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub struct ThetaMax {
    /// The largest value found (attained at `theta`): a lower bound of the maximum.
    pub value: f64,
    /// An upper bound of the maximum.
    pub upper: f64,
    /// Where `value` is attained.
    pub theta: f64,
}

impl Criterion {
    /// The criterion for delay `d` samples and velocity filter `filter`.
    ///
    /// Errors: `d` not finite, negative or above [`MAX_DELAY`]; a fractional `d`. A
    /// fractional delay switches the held force inside the sampling period, so the force is
    /// no longer constant on the intervals where the sampled-data argument of Colgate and
    /// Schenkel holds the velocity's worst case; this condition is derived and tested for
    /// whole samples only.
    pub fn new(d: f64, filter: VelocityFilter) -> Result<Self> {
        in_range("d", d, 0.0, MAX_DELAY)?;
        // exact: floor is exact, so any nonzero fraction is caught
        if d.fract() != 0.0 {
            return Err(Error::InvalidParameter {
                name: "d",
                value: d,
                expected: "passivity is computed for whole-sample delays only: a fractional delay switches the held force inside the sampling period, outside the sampled-data condition used here; give a whole number of samples".into(),
            });
        }
        let n = d as usize;
        let m = (n + 1) as f64;
        let nf = n as f64;
        // |A''| <= 2 sum k^2 = n (n + 1) (2n + 1) / 3.
        let a2 = nf * (nf + 1.0) * (2.0 * nf + 1.0) / 3.0;
        // B = -2 sum_k h_k cos((n + 1 + k) theta), h the impulse response of F, so
        // |B''| <= 2 sum_k |h_k| (m + k)^2: each filter states that sum's bound with its
        // design ([`VelocityFilter::shifted_moment_bound`]).
        let b2 = 2.0 * filter.shifted_moment_bound(m);
        Ok(Self {
            n,
            filter,
            num: filter.numerator(),
            den: filter.denominator(),
            a2,
            b2,
        })
    }

    /// Whole samples of delay.
    pub fn delay(&self) -> usize {
        self.n
    }

    /// The velocity filter.
    pub fn filter(&self) -> VelocityFilter {
        self.filter
    }

    /// `A(theta) = 1 + 2 sum_{k=1..n} cos(k theta)` (the Dirichlet kernel), evaluated in
    /// O(1) as `sin((n + 1/2) theta) / sin(theta / 2)`: both sines are computed to a few ulps
    /// for every `theta > 0` (small arguments included), so the quotient is too; its limit
    /// `2n + 1` at `theta = 0`.
    pub fn a(&self, theta: f64) -> f64 {
        let half = 0.5 * theta;
        // exact zero on purpose: only theta = 0 itself needs the limit
        if half.abs() == 0.0 {
            return (2 * self.n + 1) as f64;
        }
        ((self.n as f64 + 0.5) * theta).sin() / half.sin()
    }

    /// `B(theta) = -2 Re{e^{-i (n + 1) theta} F(e^{i theta})}`.
    pub fn b(&self, theta: f64) -> f64 {
        let z = Complex::from_polar(1.0, theta);
        let f = horner(&self.num, z) / horner(&self.den, z);
        let shift = Complex::from_polar(1.0, -((self.n + 1) as f64) * theta);
        -2.0 * (shift * f).re
    }

    /// The criterion's right-hand side at one `theta` for a wall: `(alpha A + beta B) / 2`.
    pub fn value(&self, wall: &Wall, theta: f64) -> f64 {
        0.5 * (wall.alpha() * self.a(theta) + wall.beta() * self.b(theta))
    }

    /// The certified maximum of `ca A(theta) + cb B(theta)` over `[0, pi]` (branch and bound,
    /// see the module documentation).
    pub fn max_over_theta(&self, ca: f64, cb: f64) -> Result<ThetaMax> {
        self.max_between(ca, cb, 0.0, PI)
    }

    /// [`Criterion::max_over_theta`] over `[lo, hi]`, a sub-interval of `[0, pi]`.
    fn max_between(&self, ca: f64, cb: f64, lo: f64, hi: f64) -> Result<ThetaMax> {
        crate::cancel::poll()?;
        let f = |t: f64| ca * self.a(t) + cb * self.b(t);
        // the curvature bound on [t0, t1]: global, or local for a low-pass filter
        let m2 = |t0: f64| {
            let b2 = match self.filter.curvature_bound_from((self.n + 1) as f64, t0) {
                Some(local) => local.min(self.b2),
                None => self.b2,
            };
            ca.abs() * self.a2 + cb.abs() * b2
        };
        let scale = ca.abs() * (2 * self.n + 1) as f64 + 2.0 * cb.abs();
        let eps = MAX_TOL_REL * scale.max(f64::MIN_POSITIVE);
        // initial grid: 8 points per oscillation of the fastest term
        let cells = 8 * (self.n + 2 + self.filter.order().min(64));
        let mut best = (f64::NEG_INFINITY, 0.0);
        let mut stack: Vec<(f64, f64, f64, f64)> = Vec::with_capacity(4 * cells);
        let mut prev = (lo, f(lo));
        best = pick(best, prev.1, lo);
        for i in 1..=cells {
            let t = if i == cells {
                hi
            } else {
                lo + (hi - lo) * i as f64 / cells as f64
            };
            let v = f(t);
            best = pick(best, v, t);
            stack.push((prev.0, t, prev.1, v));
            prev = (t, v);
        }
        let mut upper = best.0;
        let mut steps = 0usize;
        while let Some((t0, t1, f0, f1)) = stack.pop() {
            steps += 1;
            if steps > MAX_BB_STEPS {
                return Err(Error::Numerical(format!(
                    "the maximum of the passivity condition over frequency did not converge in {MAX_BB_STEPS} steps"
                )));
            }
            let h = t1 - t0;
            let ub = f0.max(f1) + m2(t0) * h * h / 8.0;
            if ub <= best.0 + eps {
                upper = upper.max(ub);
                continue;
            }
            let tm = 0.5 * (t0 + t1);
            if tm <= t0 || tm >= t1 {
                // theta resolution exhausted: keep the interval's bound
                upper = upper.max(ub);
                continue;
            }
            let fm = f(tm);
            best = pick(best, fm, tm);
            stack.push((t0, tm, f0, fm));
            stack.push((tm, t1, fm, f1));
        }
        if !(best.0.is_finite() && upper.is_finite()) {
            return Err(Error::Numerical(
                "the passivity condition is not finite at some frequency".into(),
            ));
        }
        Ok(ThetaMax {
            value: best.0,
            upper: upper.max(best.0),
            theta: best.1,
        })
    }

    /// The passivity margin of a wall for physical damping `delta`: `delta - (1/2) max over
    /// theta (alpha A + beta B)`, as a certified interval `(lower, upper)`, and the worst
    /// `theta`. Passive iff the margin is positive (and `alpha >= 0`).
    pub fn margin(&self, delta: f64, wall: &Wall) -> Result<(f64, f64, f64)> {
        let m = self.max_over_theta(wall.alpha(), wall.beta())?;
        Ok((delta - 0.5 * m.upper, delta - 0.5 * m.value, m.theta))
    }

    /// Whether `wall` is passive for physical damping `delta`: `alpha >= 0` and a margin
    /// proven positive. A wall within the certified accuracy of the edge counts as not
    /// passive (the condition is strict).
    pub fn is_passive(&self, delta: f64, wall: &Wall) -> Result<bool> {
        Ok(wall.alpha() >= 0.0 && self.margin(delta, wall)?.0 > 0.0)
    }
}

fn pick(best: (f64, f64), v: f64, t: f64) -> (f64, f64) {
    if v > best.0 { (v, t) } else { best }
}

fn horner(c: &[f64], z: Complex) -> Complex {
    c.iter()
        .rev()
        .fold(Complex::new(0.0, 0.0), |acc, &ck| acc * z + ck)
}

/// What a vertex of the passive edge lies on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
#[non_exhaustive]
pub enum Edge {
    /// The envelope of the half-planes; the active frequency is `theta`.
    Envelope,
    /// A corner: the active frequency jumps here.
    Corner,
    /// The axis `alpha = 0` (the segment that leaves this point lies on it).
    AlphaZero,
    /// Where the drawn `(delta, beta)` edge meets the requested largest `delta`.
    DeltaMax,
}

impl Edge {
    /// The name used in CSV and JSON output.
    pub fn name(self) -> &'static str {
        match self {
            Edge::Envelope => "envelope",
            Edge::Corner => "corner",
            Edge::AlphaZero => "alpha-zero",
            Edge::DeltaMax => "delta-max",
        }
    }
}

/// What a vertex of the passive edge lies on, and the frequency active there: the `piece`
/// of a passive region's [`Vertex`].
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub struct PassivePiece {
    /// What the vertex lies on.
    pub edge: Edge,
    /// The maximizing frequency `theta` in `[0, pi]` of the half-plane active here.
    pub theta: f64,
}

/// The passive region in one plane.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub struct PassiveRegion {
    /// The fixed parameter: `delta` in the `(alpha, beta)` plane, `alpha` in `(delta, beta)`.
    pub at: f64,
    /// Whole samples of delay.
    pub n: usize,
    /// The tolerance the edge was traced to: the requested one, raised to `1e-9` of the
    /// region's size where that is larger (the resolution of the certified maxima).
    pub tol: f64,
    /// In the `(alpha, beta)` plane a closed counterclockwise polygon starting at its lowest
    /// point on `alpha = 0` (the last point repeats the first); in the `(delta, beta)` plane
    /// the edge `delta = h(beta)` from the top end at the largest `delta` to the bottom end.
    /// Empty when no wall is passive (`delta = 0`).
    pub points: Vec<Vertex<PassivePiece>>,
}

impl PassiveRegion {
    /// The vertices as `(x, y)` pairs.
    pub fn xy(&self) -> Vec<(f64, f64)> {
        self.points.iter().map(Vertex::xy).collect()
    }

    /// The enclosed area by the shoelace formula (for the `(alpha, beta)` polygon). The
    /// polygon is inside the region (its vertices are on the edge, or inside by the certified
    /// accuracy), so this is a lower bound to about `tol` times the perimeter.
    pub fn area(&self) -> f64 {
        crate::geometry::polygon_area(&self.xy()).abs()
    }
}

/// A vertex of the sandwich: point, its supporting line `<g, x> = c` (region on the side
/// `<g, x> <= c`), parameter `s` of the shooting, and active `theta`.
#[derive(Debug, Clone, Copy)]
struct Vtx {
    p: (f64, f64),
    g: (f64, f64),
    c: f64,
    s: f64,
    theta: f64,
}

/// The sandwich refinement between `a` and `b` (see the module documentation): `shoot(s)`
/// gives the edge vertex of parameter `s`, `param(q)` the parameter of the edge point towards
/// the apex `q`. Appends the vertices strictly after `a` up to and including `b`.
fn sandwich(
    a: Vtx,
    b: Vtx,
    tol: f64,
    shoot: &dyn Fn(f64) -> Result<Vtx>,
    param: &dyn Fn((f64, f64)) -> f64,
    out: &mut Vec<Vtx>,
    depth: u32,
) -> Result<()> {
    crate::cancel::poll()?;
    if out.len() > MAX_EDGE_POINTS {
        return Err(Error::InvalidRequest(format!(
            "the passive edge needs more than {MAX_EDGE_POINTS} points at this tolerance; give a larger tolerance"
        )));
    }
    let chord = (b.p.0 - a.p.0, b.p.1 - a.p.1);
    let len = chord.0.hypot(chord.1);
    let det = a.g.0 * b.g.1 - a.g.1 * b.g.0;
    let gnorm = a.g.0.hypot(a.g.1) * b.g.0.hypot(b.g.1);
    // Both points on one supporting line (to tol / 10, well above the certified accuracy
    // of the points, see `effective_tol`): the edge between them is that segment, within
    // tol / 10 (a convex set between two points of a supporting line).
    let on_line = |v: &Vtx, p: (f64, f64)| {
        (v.g.0 * p.0 + v.g.1 * p.1 - v.c).abs() / v.g.0.hypot(v.g.1) <= 0.1 * tol
    };
    if len <= tol || (on_line(&a, b.p) && on_line(&b, a.p)) {
        out.push(b);
        return Ok(());
    }
    let mid_s = 0.5 * (a.s + b.s);
    let mut s_next = mid_s;
    // parallel lines (the arc turns by about 180 degrees): no apex, split at the middle
    if det.abs() > 1e-12 * gnorm {
        let q = (
            (a.c * b.g.1 - b.c * a.g.1) / det,
            (a.g.0 * b.c - b.g.0 * a.c) / det,
        );
        let err = seg_dist(q, a.p, b.p);
        if err <= tol {
            out.push(b);
            return Ok(());
        }
        let s = param(q);
        let (lo, hi) = (a.s.min(b.s), a.s.max(b.s));
        if s > lo && s < hi {
            s_next = s;
        }
    }
    if depth > 200 || !(s_next > a.s.min(b.s) && s_next < a.s.max(b.s)) {
        // parameter resolution exhausted: the chord is the best polyline
        out.push(b);
        return Ok(());
    }
    let v = shoot(s_next)?;
    sandwich(a, v, tol, shoot, param, out, depth + 1)?;
    sandwich(v, b, tol, shoot, param, out, depth + 1)
}

fn check_tol(tol: f64) -> Result<f64> {
    in_range("tol", tol, MIN_TOL, MAX_TOL)
}

impl Criterion {
    /// Which vertices are corners: where the active frequency jumps between the neighbours
    /// (by more than 0.05 rad) and, at the vertex, a second frequency at least half that
    /// jump away from the first attains the maximum to `1e-9` of its scale (two half-planes
    /// active at once). `wall` gives the vertex's `(alpha, beta)`.
    fn corners(&self, v: &[Vtx], wall: impl Fn(&Vtx) -> (f64, f64)) -> Result<Vec<bool>> {
        let mut out = vec![false; v.len()];
        for i in 1..v.len().saturating_sub(1) {
            let jump = (v[i - 1].theta - v[i + 1].theta).abs();
            if jump <= 0.05 {
                continue;
            }
            let (a, b) = wall(&v[i]);
            let m = self.max_over_theta(a, b)?;
            let gap = 0.5 * jump;
            let scale = a.abs() * (2 * self.n + 1) as f64 + 2.0 * b.abs();
            let mut other = f64::NEG_INFINITY;
            if m.theta - gap > 0.0 {
                other = other.max(self.max_between(a, b, 0.0, m.theta - gap)?.upper);
            }
            if m.theta + gap < PI {
                other = other.max(self.max_between(a, b, m.theta + gap, PI)?.upper);
            }
            out[i] = other >= m.value - 1e-9 * scale;
        }
        Ok(out)
    }
}

/// The tolerance actually used: `tol`, but at least `1e-9` of the region's size `size`, the
/// resolution the certified maxima (accurate to [`MAX_TOL_REL`] of their scale, the edge
/// points to about `1e-11` of the size) support with margin.
fn effective_tol(tol: f64, size: f64) -> f64 {
    tol.max(1e-9 * size)
}

/// Directions of the first edge points in the `(alpha, beta)` plane: enough that adjacent
/// supporting lines turn by much less than 180 degrees.
const START_DIRECTIONS: usize = 16;

impl Criterion {
    /// The edge point of the `(alpha, beta)` region in direction `phi` from the origin
    /// (`-pi/2 <= phi <= pi/2`): `r = 2 delta / max over theta of (cos phi A + sin phi B)`,
    /// with the certified upper bound of the maximum, so the point is on the passive side.
    fn shoot_ab(&self, delta: f64, phi: f64) -> Result<Vtx> {
        let (s, c) = phi.sin_cos();
        // exact: at +-pi/2 cos is rounded to 6e-17; use the exact axis direction
        let (c, s) = if (phi.abs() - PI / 2.0).abs() < 1e-15 {
            (0.0, phi.signum())
        } else {
            (c, s)
        };
        let m = self.max_over_theta(c, s)?;
        if m.value <= 0.0 {
            return Err(Error::Numerical(format!(
                "the passive region is unbounded in the direction {phi} rad; the filter's frequency response is not that of a causal filter with unit gain at zero frequency"
            )));
        }
        let r = 2.0 * delta / m.upper;
        let th = m.theta;
        Ok(Vtx {
            p: (r * c, r * s),
            g: (self.a(th), self.b(th)),
            c: 2.0 * delta,
            s: phi,
            theta: th,
        })
    }

    /// The passive region in the `(alpha, beta)` plane for physical damping `delta`: a convex
    /// polygon whose edge is within `tol` of the true edge (sandwich algorithm, see the module
    /// documentation), closed along `alpha = 0`.
    ///
    /// ```
    /// use stabound::VelocityFilter;
    /// use stabound::passivity::Criterion;
    ///
    /// // No delay, no filter: Colgate's triangle delta > alpha/2 + |beta| (eq. 21).
    /// let c = Criterion::new(0.0, VelocityFilter::none())?;
    /// let r = c.region_alpha_beta(1.0, 1e-9)?;
    /// assert!((r.area() - 2.0).abs() < 1e-8);
    /// # Ok::<(), stabound::Error>(())
    /// ```
    pub fn region_alpha_beta(&self, delta: f64, tol: f64) -> Result<PassiveRegion> {
        in_range("delta", delta, 0.0, MAX_DELTA)?;
        let tol = check_tol(tol)?;
        let mut region = PassiveRegion {
            at: delta,
            n: self.n,
            tol,
            points: Vec::new(),
        };
        if delta <= 0.0 {
            return Ok(region);
        }
        let shoot = |phi: f64| self.shoot_ab(delta, phi);
        let param = |q: (f64, f64)| q.1.atan2(q.0);
        let starts: Vec<Vtx> = (0..=START_DIRECTIONS)
            .map(|i| shoot(-PI / 2.0 + PI * i as f64 / START_DIRECTIONS as f64))
            .collect::<Result<_>>()?;
        // The tolerance is absolute in the plane; the region scales with delta, and with a
        // slow filter (a low-pass pole near 1) stretches far beyond it along beta: its size
        // is the farthest of the first edge points.
        let size = starts.iter().fold(delta, |m, v| m.max(v.p.0.hypot(v.p.1)));
        let tol = effective_tol(tol, size);
        region.tol = tol;
        let mut out: Vec<Vtx> = vec![starts[0]];
        for w in starts.windows(2) {
            sandwich(w[0], w[1], tol, &shoot, &param, &mut out, 0)?;
        }
        let corners = self.corners(&out, |v| (v.p.0, v.p.1))?;
        let last = out.len() - 1;
        region.points = out
            .iter()
            .enumerate()
            .map(|(i, v)| Vertex {
                x: v.p.0.max(0.0),
                y: v.p.1,
                piece: PassivePiece {
                    theta: v.theta,
                    edge: if i == last {
                        Edge::AlphaZero
                    } else if corners[i] {
                        Edge::Corner
                    } else {
                        Edge::Envelope
                    },
                },
            })
            .collect();
        let first = region.points[0];
        region.points.push(first);
        Ok(region)
    }

    /// `h(beta) = (1/2) max over theta of (alpha A + beta B)`: the least passive `delta` at
    /// `(alpha, beta)`, certified upper bound, with the supporting line of the epigraph.
    fn shoot_db(&self, alpha: f64, beta: f64) -> Result<Vtx> {
        let m = self.max_over_theta(alpha, beta)?;
        let th = m.theta;
        let (a, b) = (self.a(th), self.b(th));
        // epigraph delta >= (alpha A + beta B) / 2, written as <g, (delta, beta)> <= c with
        // g = (-2, B), c = -alpha A
        Ok(Vtx {
            p: (0.5 * m.upper, beta),
            g: (-2.0, b),
            c: -alpha * a,
            s: beta,
            theta: th,
        })
    }

    /// The least physical damping that makes `(alpha, beta)` passive: the wall is passive
    /// for every `delta` above it (certified upper bound of `(1/2) max (alpha A + beta B)`).
    pub fn least_passive_delta(&self, wall: &Wall) -> Result<f64> {
        Ok(self.shoot_db(wall.alpha(), wall.beta())?.p.0)
    }

    /// The passive region in the `(delta, beta)` plane for stiffness `alpha >= 0`, drawn up
    /// to `delta_max`: the convex edge `delta = h(beta)` within `tol`, from its upper end at
    /// `delta_max` down to its lower end. Empty when no wall of this stiffness is passive
    /// below `delta_max`.
    ///
    /// Method: the ends are bracketed by the `theta = 0` half-plane and that of the largest
    /// `B`, the minimum of the convex `h` found by golden-section search, the ends located by
    /// bisection to `tol / 4`, then the sandwich algorithm between them.
    pub fn region_delta_beta(&self, alpha: f64, delta_max: f64, tol: f64) -> Result<PassiveRegion> {
        finite("alpha", alpha)?;
        if alpha < 0.0 {
            return Err(Error::InvalidParameter {
                name: "alpha",
                value: alpha,
                expected: "a passive wall has stiffness >= 0".into(),
            });
        }
        in_range("delta_max", delta_max, 0.0, MAX_DELTA)?;
        let tol = check_tol(tol)?;
        let mut region = PassiveRegion {
            at: alpha,
            n: self.n,
            tol,
            points: Vec::new(),
        };
        let h = |beta: f64| -> Result<f64> { Ok(self.shoot_db(alpha, beta)?.p.0) };
        // Brackets: h >= ((2n + 1) alpha - 2 beta) / 2 (theta = 0), and
        // h >= (alpha A(t+) + beta B(t+)) / 2 with B(t+) = max B > 0.
        let lo = (2 * self.n + 1) as f64 * alpha / 2.0 - delta_max;
        let bm = self.max_over_theta(0.0, 1.0)?;
        if bm.value <= 0.0 {
            return Err(Error::Numerical(
                "the passive region is unbounded in beta; the filter's frequency response is not that of a causal filter with unit gain at zero frequency".into(),
            ));
        }
        let hi = (2.0 * delta_max - alpha * self.a(bm.theta)) / bm.value;
        if hi <= lo {
            return Ok(region);
        }
        // golden section for the minimum of the convex h on [lo, hi]: the maximum of -h
        let (a, b) =
            golden_max(|x| h(x).map(|v| -v), (lo, hi), |a, b, _| b - a > tol / 4.0)?.bracket;
        let bmin = 0.5 * (a + b);
        if h(bmin)? >= delta_max {
            return Ok(region);
        }
        // ends: h(beta) = delta_max on each side of the minimum, by bisection
        let cross = |mut inside: f64, mut outside: f64| -> Result<f64> {
            while (outside - inside).abs() > tol / 4.0 {
                let m = 0.5 * (inside + outside);
                if h(m)? < delta_max {
                    inside = m;
                } else {
                    outside = m;
                }
            }
            Ok(inside)
        };
        let b_lo = cross(bmin, lo)?;
        let b_hi = cross(bmin, hi)?;
        let tol = effective_tol(tol, delta_max.max(alpha));
        region.tol = tol;
        let shoot = |beta: f64| self.shoot_db(alpha, beta);
        let param = |q: (f64, f64)| q.1;
        let first = shoot(b_lo)?;
        let mut out: Vec<Vtx> = vec![first];
        // a few starting points, so each arc turns by less than 180 degrees
        let k = 8;
        let starts: Vec<Vtx> = (0..=k)
            .map(|i| shoot(b_lo + (b_hi - b_lo) * i as f64 / k as f64))
            .collect::<Result<_>>()?;
        for w in starts.windows(2) {
            sandwich(w[0], w[1], tol, &shoot, &param, &mut out, 0)?;
        }
        let corners = self.corners(&out, |v| (alpha, v.p.1))?;
        let last = out.len() - 1;
        region.points = out
            .iter()
            .enumerate()
            .map(|(i, v)| Vertex {
                x: v.p.0,
                y: v.p.1,
                piece: PassivePiece {
                    theta: v.theta,
                    edge: if i == 0 || i == last {
                        Edge::DeltaMax
                    } else if corners[i] {
                        Edge::Corner
                    } else {
                        Edge::Envelope
                    },
                },
            })
            .collect();
        region.points.reverse();
        Ok(region)
    }

    /// The largest passive stiffness at damping `beta` for physical damping `delta`: `None`
    /// when no wall with this damping is passive. Within `tol`, on the passive side.
    ///
    /// Method: bisection on `alpha` in `[0, 2 (delta + beta) / (2n + 1)]` (the `theta = 0`
    /// half-plane bounds it) of the certified test [`Criterion::is_passive`]; the set of
    /// passive `alpha` at fixed `beta` is an interval (convexity) starting at 0.
    pub fn max_stiffness_at(&self, delta: f64, beta: f64, tol: f64) -> Result<Option<f64>> {
        in_range("delta", delta, 0.0, MAX_DELTA)?;
        finite("beta", beta)?;
        let tol = check_tol(tol)?;
        let passive = |alpha: f64| self.is_passive(delta, &Wall { alpha, beta });
        if !passive(0.0)? {
            return Ok(None);
        }
        let mut lo = 0.0;
        let mut hi = 2.0 * (delta + beta) / (2 * self.n + 1) as f64;
        if passive(hi)? {
            return Ok(Some(hi));
        }
        while hi - lo > tol {
            let m = 0.5 * (lo + hi);
            if passive(m)? {
                lo = m;
            } else {
                hi = m;
            }
        }
        Ok(Some(lo))
    }

    /// The largest passive stiffness over all `beta` for physical damping `delta`, and the
    /// `beta` where it is reached: `None` for `delta = 0` (no passive wall).
    ///
    /// Method: golden-section search on the concave function `beta -> alpha_max(beta)`
    /// ([`Criterion::max_stiffness_at`]) over the passive range of `beta` on `alpha = 0`.
    pub fn max_stiffness(&self, delta: f64, tol: f64) -> Result<Option<(f64, f64)>> {
        in_range("delta", delta, 0.0, MAX_DELTA)?;
        let tol = check_tol(tol)?;
        if delta <= 0.0 {
            return Ok(None);
        }
        let top = self.shoot_ab(delta, PI / 2.0)?.p.1;
        let bot = self.shoot_ab(delta, -PI / 2.0)?.p.1;
        let f = |beta: f64| -> Result<f64> {
            Ok(self
                .max_stiffness_at(delta, beta, tol / 4.0)?
                .unwrap_or(0.0))
        };
        let (a, b) = golden_max(f, (bot, top), |a, b, _| b - a > tol)?.bracket;
        let beta = 0.5 * (a + b);
        Ok(Some((f(beta)?, beta)))
    }
}

/// A wall found by [`compare`], with the evidence.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub struct Witness {
    /// Stiffness.
    pub alpha: f64,
    /// Damping.
    pub beta: f64,
    /// Physical damping.
    pub delta: f64,
    /// The certified passivity margin interval's lower end (positive: passive) or upper end
    /// (negative: not passive).
    pub margin: f64,
    /// The stability verdict (Schur-Cohn with the default band).
    pub verdict: Verdict,
}

impl Witness {
    /// The witness `wall` at physical damping `delta` with its margin end and verdict.
    pub(crate) fn new(wall: &Wall, delta: f64, margin: f64, verdict: Verdict) -> Self {
        Self {
            alpha: wall.alpha(),
            beta: wall.beta(),
            delta,
            margin,
            verdict,
        }
    }
}

/// The passive region against the exact stable region, in the `(alpha, beta)` plane.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub struct Comparison {
    /// Physical damping.
    pub delta: f64,
    /// Whole samples of delay.
    pub n: usize,
    /// Area of the passive polygon.
    pub passive_area: f64,
    /// Area of the stable polygon.
    pub stable_area: f64,
    /// Area of their intersection.
    pub common_area: f64,
    /// The fraction of the stable region that is passive, `common / stable`.
    pub passive_fraction_of_stable: f64,
    /// The fraction of the passive region that is stable, `common / passive`.
    pub stable_fraction_of_passive: f64,
    /// Whether the passive region lies inside the stable one: the area outside is within
    /// the polygons' error bound (`tol` times the perimeters) and no passive unstable wall
    /// was found.
    pub inside: bool,
    /// A passive wall that is unstable, when one was found.
    pub passive_unstable: Option<Witness>,
    /// A stable wall that is not passive, when one was found.
    pub stable_not_passive: Option<Witness>,
    /// The passive region.
    pub region: PassiveRegion,
    /// The stable boundary (exact D-decomposition), as `(alpha, beta)` vertices.
    pub stable: Vec<(f64, f64)>,
    /// `None` when the exact engine drew the stable boundary; else why it could not close
    /// it, and the bisection engine drew it instead.
    pub stable_fallback: Option<String>,
}

/// Compares the passive region of `(delta, d, filter)` with the stable region of the loop
/// with that delay and velocity filter, in the `(alpha, beta)` plane.
///
/// Method: the stable region is the exact boundary of the loop (D-decomposition of its
/// affine polynomial, [`boundary::exact()`], `docs/MODEL.md` section 8) at `tol`; the passive
/// region is [`Criterion::region_alpha_beta`] at `tol` (section 9, which holds for any
/// causal linear environment, so for every filter the loop accepts: first-order low-pass,
/// moving average and second-order Butterworth); the common area is the stable polygon
/// clipped by the convex passive polygon (Sutherland and Hodgman, "Reentrant polygon
/// clipping", CACM 17(1), 1974, valid for a convex clip polygon and any simple subject
/// polygon); witnesses are vertices of the stable boundary strictly inside (or outside) the
/// passive region, moved off the boundary along its normal until a point test confirms them.
/// Where the exact engine could not close the boundary it is the bisection engine's
/// ([`Comparison::stable_fallback`] says why).
///
/// ```
/// use stabound::VelocityFilter;
/// use stabound::passivity::compare;
///
/// // One sample of delay and a first-order low-pass velocity filter.
/// let c = compare(1.0, 1.0, VelocityFilter::low_pass(0.5)?, 1e-7)?;
/// assert!(c.inside);
/// assert!(c.passive_fraction_of_stable > 0.0 && c.passive_fraction_of_stable < 1.0);
/// # Ok::<(), stabound::Error>(())
/// ```
///
/// Errors: those of [`Criterion::new`] (a fractional delay) and of the two regions;
/// [`Error::Numerical`] when the stable region has more than one piece and a stable passive
/// wall lies outside the largest (the only one the exact boundary traces): [`super::compare_on_lines`]
/// (on lines of the plane) compares such a loop.
pub fn compare(delta: f64, d: f64, filter: VelocityFilter, tol: f64) -> Result<Comparison> {
    compare_traced(delta, d, filter, tol)?.map_err(Error::Numerical)
}

/// [`compare`], with `Ok(Err(why))` where the stable region has a piece the exact boundary
/// does not trace holding the passive region.
pub(crate) fn compare_traced(
    delta: f64,
    d: f64,
    filter: VelocityFilter,
    tol: f64,
) -> Result<std::result::Result<Comparison, String>> {
    let crit = Criterion::new(d, filter)?;
    let region = crit.region_alpha_beta(delta, tol)?;
    let lp = Loop::new(Plant::new(delta, d)?).with_filter(filter)?;
    let b = boundary::exact(lp, &ExactOptions { tol })?;
    let mut stable = b.xy();
    stable.pop(); // the closing repeat
    let passive: Vec<(f64, f64)> = {
        let mut p = region.xy();
        p.pop();
        p
    };
    let stable_area = crate::geometry::polygon_area(&stable).abs();
    let passive_area = crate::geometry::polygon_area(&passive).abs();
    // The common area is at most either area. An empty passive region (delta = 0) clips
    // nothing away, and one too thin for the clip's orientation tests to resolve (delta near
    // the smallest subnormal, where every side product underflows to 0) keeps every point:
    // neither is common to both regions.
    let common_area = if passive_area > 0.0 {
        crate::geometry::polygon_area(&crate::geometry::clip(&stable, &passive))
            .abs()
            .min(passive_area)
            .min(stable_area)
    } else {
        0.0
    };
    crate::cancel::poll()?;
    let checker = Checker::new(lp, Options::default())?;
    // The exact engine traces the stable region's largest piece. Where the region has more
    // than one (a second-order filter at small delta and no delay has two), the passive
    // region may lie in another: a stable passive wall outside the polygon shows it. The
    // mean of the convex passive polygon's vertices is inside it.
    if passive_area > 0.0 {
        let k = passive.len() as f64;
        let (ma, mb) = passive
            .iter()
            .fold((0.0, 0.0), |(a, b), p| (a + p.0 / k, b + p.1 / k));
        let mean = Wall {
            alpha: ma,
            beta: mb,
        };
        if !inside_polygon((ma, mb), &stable) && checker.verdict(&mean)? == Verdict::Stable {
            return Ok(Err(format!(
                "the stable region of this loop has more than one piece and the passive region lies outside the largest one, the only one the exact boundary traces (the wall alpha = {ma}, beta = {mb} is passive and stable there); compare on lines of the plane instead (compare_on_lines), which finds every piece"
            )));
        }
    }
    let perimeter = |p: &[(f64, f64)]| -> f64 {
        (0..p.len())
            .map(|i| {
                let (a, c) = (p[i], p[(i + 1) % p.len()]);
                (c.0 - a.0).hypot(c.1 - a.1)
            })
            .sum()
    };
    let bound = 2.0 * tol * (perimeter(&stable) + perimeter(&passive));
    let (passive_unstable, stable_not_passive) = witnesses(&crit, &checker, delta, &b, tol)?;
    let inside = passive_unstable.is_none() && passive_area - common_area <= bound;
    let ratio = |a: f64, b: f64| if b > 0.0 { (a / b).min(1.0) } else { 0.0 };
    Ok(Ok(Comparison {
        delta,
        n: crit.n,
        passive_area,
        stable_area,
        common_area,
        passive_fraction_of_stable: ratio(common_area, stable_area),
        stable_fraction_of_passive: ratio(common_area, passive_area),
        inside,
        passive_unstable,
        stable_not_passive,
        region,
        stable: b.xy(),
        stable_fallback: b.fallback,
    }))
}

/// Witnesses from the stable boundary's vertices (see [`compare`]).
fn witnesses(
    crit: &Criterion,
    checker: &Checker,
    delta: f64,
    b: &crate::boundary::Boundary,
    tol: f64,
) -> Result<(Option<Witness>, Option<Witness>)> {
    let pts = b.xy();
    let m = pts.len().saturating_sub(1);
    if m < 3 {
        return Ok((None, None));
    }
    // margins of the vertices off the axis alpha = 0, a thinned set (at most 400)
    let step = (m / 400).max(1);
    let mut cands: Vec<(f64, usize)> = Vec::new();
    for i in (0..m).step_by(step) {
        if pts[i].0 <= 0.0 {
            continue;
        }
        let w = Wall {
            alpha: pts[i].0,
            beta: pts[i].1,
        };
        let (lo, hi, _) = crit.margin(delta, &w)?;
        cands.push((if lo > 0.0 { lo } else { hi }, i));
    }
    let scale = pts
        .iter()
        .fold(0.0f64, |s, p| s.max(p.0.abs()).max(p.1.abs()));
    let normal = |i: usize| {
        let (p, q) = (pts[(i + m - 1) % m], pts[(i + 1) % m]);
        let e = (q.0 - p.0, q.1 - p.1);
        let l = e.0.hypot(e.1).max(f64::MIN_POSITIVE);
        (e.1 / l, -e.0 / l) // outward for a counterclockwise polygon
    };
    let found = |want_passive: bool| -> Result<Option<Witness>> {
        let mut c: Vec<(f64, usize)> = cands
            .iter()
            .copied()
            .filter(|&(mg, _)| (mg > 0.0) == want_passive)
            .collect();
        c.sort_by(|x, y| y.0.abs().total_cmp(&x.0.abs()));
        for &(_, i) in c.iter().take(40) {
            let nrm = normal(i);
            // outward for a passive unstable wall, inward for a stable non-passive one
            let sign = if want_passive { 1.0 } else { -1.0 };
            let mut eps = (10.0 * tol).max(1e-9 * scale);
            while eps < 1e-2 * scale {
                let w = Wall {
                    alpha: pts[i].0 + sign * eps * nrm.0,
                    beta: pts[i].1 + sign * eps * nrm.1,
                };
                if w.alpha() > 0.0 {
                    let (lo, hi, _) = crit.margin(delta, &w)?;
                    let v = checker.verdict(&w)?;
                    if want_passive && lo > 0.0 && v == Verdict::Unstable {
                        return Ok(Some(Witness::new(&w, delta, lo, v)));
                    }
                    if !want_passive && hi < 0.0 && v == Verdict::Stable {
                        return Ok(Some(Witness::new(&w, delta, hi, v)));
                    }
                }
                eps *= 4.0;
            }
        }
        Ok(None)
    };
    Ok((found(true)?, found(false)?))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn closed_forms_of_a_and_b() {
        // A against its defining sum 1 + 2 sum cos(k t); B for F = 1 is -2 cos((n + 1) t),
        // from the definition in the model document by hand.
        for n in [0usize, 1, 3, 7, 60] {
            let c = Criterion::new(n as f64, VelocityFilter::none()).unwrap();
            for t in [1e-9, 1e-4, 0.1, 0.7, 2.0, 3.1, PI] {
                let a = 1.0 + 2.0 * (1..=n).map(|k| (k as f64 * t).cos()).sum::<f64>();
                assert!(
                    (c.a(t) - a).abs() < 1e-12 * (2 * n + 1) as f64,
                    "n {n} t {t}"
                );
                let b = -2.0 * ((n as f64 + 1.0) * t).cos();
                assert!((c.b(t) - b).abs() < 1e-12);
            }
            assert!((c.a(0.0) - (2 * n + 1) as f64).abs() < 1e-12);
            assert!((c.b(0.0) + 2.0).abs() < 1e-12);
        }
    }

    #[test]
    fn curvature_bounds_hold() {
        // the second difference never exceeds the bound used by the branch and bound
        let filters = [
            VelocityFilter::none(),
            VelocityFilter::low_pass(0.9).unwrap(),
            VelocityFilter::moving_average(5).unwrap(),
            VelocityFilter::butterworth(0.05).unwrap(),
        ];
        for f in filters {
            let c = Criterion::new(3.0, f).unwrap();
            let h = 1e-3;
            for i in 1..3000 {
                let t = i as f64 * 1e-3;
                let d2a = (c.a(t + h) - 2.0 * c.a(t) + c.a(t - h)) / (h * h);
                let d2b = (c.b(t + h) - 2.0 * c.b(t) + c.b(t - h)) / (h * h);
                assert!(d2a.abs() <= c.a2 * (1.0 + 1e-3) + 1e-4, "{f:?}");
                assert!(d2b.abs() <= c.b2 * (1.0 + 1e-3) + 1e-4, "{f:?}");
            }
        }
        // the low-pass filter's local bound holds on [t, pi] (checked at the ends of
        // short steps after t, where the second difference is the curvature to O(h^2))
        for a in [0.0, 0.5, 0.9, 0.999] {
            let c = Criterion::new(2.0, VelocityFilter::low_pass(a).unwrap()).unwrap();
            let h = 1e-5;
            for i in 0..400 {
                let t = (PI - 0.1) * (i as f64 / 400.0).powi(3);
                let bound = VelocityFilter::low_pass(a)
                    .unwrap()
                    .curvature_bound_from(3.0, t)
                    .unwrap();
                assert!(
                    bound <= c.b2 * (1.0 + 1e-12),
                    "a {a}: local above global at {t}"
                );
                for k in 1..50 {
                    let s = t + k as f64 * 2e-3 * (1.0 - a).max(1e-3);
                    let d2b = (c.b(s + h) - 2.0 * c.b(s) + c.b(s - h)) / (h * h);
                    assert!(
                        d2b.abs() <= bound * (1.0 + 1e-3) + 1e-2,
                        "a {a} t {t} s {s}: {d2b} > {bound}"
                    );
                }
            }
        }
    }

    #[test]
    fn max_against_dense_scan() {
        let c = Criterion::new(2.0, VelocityFilter::low_pass(0.7).unwrap()).unwrap();
        for (ca, cb) in [(1.0, 0.0), (0.3, 0.8), (-0.2, 1.0), (0.0, -1.0)] {
            let m = c.max_over_theta(ca, cb).unwrap();
            let scan = (0..=200_000)
                .map(|i| {
                    let t = PI * i as f64 / 200_000.0;
                    ca * c.a(t) + cb * c.b(t)
                })
                .fold(f64::NEG_INFINITY, f64::max);
            // the scan is a lower bound of the maximum, within M h^2 / 8 < 1e-9 of it here
            assert!(scan <= m.upper + 1e-12, "{scan} {m:?}");
            assert!(m.value >= scan - 1e-9, "{scan} {m:?}");
            assert!(m.upper - m.value <= 1e-10);
        }
    }

    #[test]
    fn refuses() {
        assert!(Criterion::new(0.5, VelocityFilter::none()).is_err());
        assert!(Criterion::new(-1.0, VelocityFilter::none()).is_err());
        let c = Criterion::new(1.0, VelocityFilter::none()).unwrap();
        assert!(c.region_alpha_beta(1.0, 0.0).is_err());
        assert!(c.region_delta_beta(-1.0, 1.0, 1e-6).is_err());
        let f = VelocityFilter::low_pass(0.5).unwrap();
        assert!(compare(1.0, 0.5, f, 1e-6).is_err());
        // two stable pieces; the passive region is in the smaller
        let f = VelocityFilter::butterworth(0.1).unwrap();
        let e = compare(0.1, 0.0, f, 1e-7).unwrap_err();
        assert!(e.to_string().contains("more than one piece"), "{e}");
    }
}
