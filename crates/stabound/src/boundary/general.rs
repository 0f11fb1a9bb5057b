//! The exact boundary of any [`Loop`] in the `(alpha, beta)` plane, by D-decomposition of
//! the general affine polynomial (the model document, docs/MODEL.md, section 8):
//!
//! ```text
//! q(z) = Q0(z) + alpha QA(z) + beta QB(z)
//!      = z^(n+2) D(z) Fd(z) + N(z) (alpha z Fd(z) + beta (z - 1) Fn(z))
//! ```
//!
//! Method: D-decomposition (Neimark, 1948; Gryazina, Polyak and Tremba, "D-decomposition
//! technique state-of-the-art", *Automation and Remote Control* 69, 2008). A root crosses the
//! unit circle only on one of three candidate sets, each a linear system in `(alpha, beta)`:
//!
//! - `z = 1`: `alpha QA(1) = -Q0(1)` (`QB(1) = 0` for every loop), a vertical line. It is
//!   `alpha = 0` only when the device has a free integrator (no hand stiffness); with one the
//!   stable region reaches negative `alpha` and this engine does not assume otherwise.
//! - `z = -1`: `alpha QA(-1) + beta QB(-1) = -Q0(-1)`, a line of any slope.
//! - `z = e^{i theta}`, `theta in (0, pi)`: the complex equation `alpha QA + beta QB = -Q0`,
//!   two real equations solved by Cramer's rule; at `theta -> 0` and `pi` the pair merges
//!   into a double root at `z = +-1` (`q = q' = 0`, again two linear equations).
//!
//! Nothing else of the paper's loop is used: no closed forms, no lowest point at
//! `(0, -delta)`, no edge at `alpha = 0`. A point of a candidate bounds the stable region
//! (where no root is outside the unit circle) exactly when every other root is strictly
//! inside: deflate `q` by the known factor and run Schur-Cohn on the quotient. The steps:
//!
//! 1. sample the curve on `64 (degree + 1)` steps of `theta` over `[0, pi]` (the curve turns
//!    about `degree` times as fast as `theta`: `z^(n+2)` for the delay, `Fd` for a moving
//!    average, the device's modes);
//! 2. keep the intervals where the deflated test passes; locate their ends (corners, where a
//!    second root reaches the circle) by bisection in `theta` to `tol / 4` in the plane;
//! 3. refine each kept interval until every chord is within `tol` of the curve;
//! 4. cut both lines at their crossings with the curve, at each other and at the curve's
//!    ends, and keep the segments whose midpoint passes the deflated test (a segment running
//!    to infinity is never kept: the stable region of a loop is bounded);
//! 5. chain the pieces into closed polylines by nearest ends and return the one of largest
//!    area, counterclockwise.
//!
//! A loop whose pieces do not close (an unbounded or empty stable region, an element whose
//! resonance the sampling misses) is an [`Error::Numerical`], never a partial boundary.

use std::f64::consts::PI;
use std::sync::atomic::AtomicUsize;

use rayon::prelude::*;

use super::exact::{deflate_linear, deflate_quadratic, kept_segments};
use super::refine::{Chain, Midpoint, Refiner, curve_sample, kept_knots, over_budget};
use super::{Boundary, ExactOptions, Piece, Vertex, check_tol, too_many_vertices};
use crate::elements::{Loop, LoopPoly};
use crate::error::{Error, Result};
use crate::geometry::{point_dist, polygon_area};
use crate::params::Wall;
use crate::poly::Complex;
use crate::stability::schur_cohn;

/// Coarse samples of `theta` per degree of `q` (see the module documentation): as for the
/// paper's loop, 64 per turn of the curve.
const SAMPLES_PER_DEGREE: usize = 64;

/// A Cramer determinant below this fraction of the product of its columns' sizes is a
/// direction in which the curve runs off to infinity (the two equations are dependent to
/// rounding): about a thousand roundings, above what Horner's evaluation on the circle
/// leaves of a degree-70 polynomial's terms.
const SINGULAR: f64 = 1e-13;

/// The exact boundary of `lp` in the `(alpha, beta)` plane by the general D-decomposition
/// (see the module documentation): the route of [`super::exact()`] for a loop with elements.
///
/// # Errors
///
/// `tol` outside `[MIN_TOL, MAX_TOL]`; more than [`MAX_VERTICES`](super::MAX_VERTICES)
/// vertices; pieces that do not close into a polyline ([`Error::Numerical`]).
pub(crate) fn exact_loop(lp: &Loop, options: &ExactOptions) -> Result<Boundary> {
    let tol = check_tol(options.tol)?;
    let poly = LoopPoly::new(lp)?;
    let ctx = Ctx {
        poly: &poly,
        tol,
        free_integrator: lp.free_integrator(),
        vertices: AtomicUsize::new(0),
    };
    let plant = lp.plant();
    let n0 = SAMPLES_PER_DEGREE * (poly.degree() + 1);
    let samples: Vec<Sample> = (0..=n0)
        .into_par_iter()
        .map(|i| ctx.sample(PI * i as f64 / n0 as f64))
        .collect();

    let mut pieces: Vec<Chain> = Vec::new();
    let refiner = Refiner {
        tol,
        vertices: &ctx.vertices,
        midpoint: |a: &Sample, b: &Sample| ctx.midpoint(a, b),
        predict: false,
    };
    for knots in kept_knots(&samples, |inn, out| ctx.corner(*inn, *out)) {
        pieces.push(Chain {
            piece: Piece::Curve,
            pts: refiner.polyline(&knots, true),
        });
    }
    if let Some(size) = over_budget(&ctx.vertices, &samples) {
        return Err(too_many_vertices(plant, tol, size));
    }

    let plus = ctx.line(1.0);
    let minus = ctx.line(-1.0);
    let ends: Vec<Wall> = pieces
        .iter()
        .flat_map(|c| [c.pts[0], c.pts[c.pts.len() - 1]])
        .collect();
    for (line, other) in [(plus, minus), (minus, plus)] {
        let Some(line) = line else { continue };
        let mut cuts: Vec<f64> = Vec::new();
        for s in [samples[0], samples[n0]] {
            if s.valid && line.near(&s.wall, tol) {
                cuts.push(line.param(&s.wall));
            }
        }
        cuts.extend(
            ctx.crossings(&samples, |w| line.residual(w))
                .iter()
                .map(|w| line.param(w)),
        );
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

    let points = close(pieces, tol, lp)?;
    Ok(Boundary {
        delta: plant.delta(),
        d: plant.d(),
        tol,
        points,
    })
}

/// `(Q0(z), QA(z), QB(z))` and their derivatives, by Horner's rule, for a real `z`.
fn real_values(p: &LoopPoly, z: f64) -> ([f64; 3], [f64; 3]) {
    let (mut v, mut dv) = ([0.0; 3], [0.0; 3]);
    for i in (0..=p.degree()).rev() {
        for (k, c) in [p.q0()[i], p.qa()[i], p.qb()[i]].into_iter().enumerate() {
            dv[k] = dv[k] * z + v[k];
            v[k] = v[k] * z + c;
        }
    }
    (v, dv)
}

/// `(Q0(z), QA(z), QB(z))` by Horner's rule.
fn complex_values(p: &LoopPoly, z: Complex) -> [Complex; 3] {
    let mut v = [Complex::new(0.0, 0.0); 3];
    for i in (0..=p.degree()).rev() {
        for (k, c) in [p.q0()[i], p.qa()[i], p.qb()[i]].into_iter().enumerate() {
            v[k] = v[k] * z + c;
        }
    }
    v
}

/// Solves `alpha a1 + beta b1 = c1`, `alpha a2 + beta b2 = c2` by Cramer's rule; `None` when
/// the determinant is at rounding level of its terms (see [`SINGULAR`]).
fn cramer(a1: f64, b1: f64, c1: f64, a2: f64, b2: f64, c2: f64) -> Option<Wall> {
    let det = a1 * b2 - b1 * a2;
    let size = a1.hypot(b1) * a2.hypot(b2);
    if det.is_nan() || det.abs() <= SINGULAR * size {
        return None;
    }
    let alpha = (c1 * b2 - b1 * c2) / det;
    let beta = (a1 * c2 - c1 * a2) / det;
    (alpha.is_finite() && beta.is_finite()).then_some(Wall { alpha, beta })
}

/// The line `a alpha + b beta = r` of the real root `z = root`.
#[derive(Debug, Clone, Copy)]
struct Line {
    a: f64,
    b: f64,
    r: f64,
    root: f64,
    piece: Piece,
}

impl Line {
    /// Parametrized by `alpha` when it is closer to horizontal, else by `beta`.
    fn by_alpha(&self) -> bool {
        self.b.abs() >= self.a.abs()
    }

    fn at(&self, t: f64) -> Wall {
        if self.by_alpha() {
            Wall {
                alpha: t,
                beta: (self.r - self.a * t) / self.b,
            }
        } else {
            Wall {
                alpha: (self.r - self.b * t) / self.a,
                beta: t,
            }
        }
    }

    fn param(&self, w: &Wall) -> f64 {
        if self.by_alpha() { w.alpha } else { w.beta }
    }

    fn residual(&self, w: &Wall) -> f64 {
        self.a * w.alpha + self.b * w.beta - self.r
    }

    /// Within `tol` of the line.
    fn near(&self, w: &Wall, tol: f64) -> bool {
        self.residual(w).abs() <= tol * self.a.hypot(self.b)
    }

    /// Where two lines meet (`None` if parallel to rounding).
    fn meet(&self, o: &Line) -> Option<Wall> {
        cramer(self.a, self.b, self.r, o.a, o.b, o.r)
    }
}

/// One sample of the curve.
#[derive(Debug, Clone, Copy)]
struct Sample {
    theta: f64,
    wall: Wall,
    /// Every root other than the pair `e^{+-i theta}` strictly inside the circle.
    keep: bool,
    /// The wall exists (is finite).
    valid: bool,
}

struct Ctx<'a> {
    poly: &'a LoopPoly,
    tol: f64,
    /// `D(1) = 0` exactly in the model (no hand stiffness): the `z = 1` line is `alpha = 0`.
    free_integrator: bool,
    vertices: AtomicUsize,
}

impl Ctx<'_> {
    /// The line of the root `z = root` (`+-1`); `None` if that root is a root of `q` for no
    /// wall or for every wall (`QA(root) = QB(root) = 0`).
    fn line(&self, root: f64) -> Option<Line> {
        let (v, _) = real_values(self.poly, root);
        if root > 0.0 {
            // QB(1) = 0 for every loop ((z - 1) is a factor): the line is vertical. With a free
            // integrator D(1) = 0 in the model, so Q0(1) = 0 and the line is alpha = 0 exactly.
            let r = if self.free_integrator { 0.0 } else { -v[0] };
            let a = v[1];
            return (a != 0.0 && a.is_finite()).then_some(Line {
                a,
                b: 0.0,
                r,
                root,
                piece: if r == 0.0 {
                    Piece::AlphaZero
                } else {
                    Piece::PlusOne
                },
            });
        }
        let (a, b, r) = (v[1], v[2], -v[0]);
        (self.poly.wall_moves_root(a, b) && r.is_finite()).then_some(Line {
            a,
            b,
            r,
            root,
            piece: Piece::MinusOne,
        })
    }

    /// The wall with the pair `e^{+-i theta}` on the circle; at `0` and `pi` the double root.
    fn wall(&self, theta: f64) -> Option<Wall> {
        if theta <= 0.0 || theta >= PI {
            let z0 = if theta <= 0.0 { 1.0 } else { -1.0 };
            let (v, dv) = real_values(self.poly, z0);
            // q(z0) = 0 and q'(z0) = 0; at z0 = 1 the first is the z = 1 line of `line`
            let first = if z0 > 0.0 {
                let r = if self.free_integrator { 0.0 } else { -v[0] };
                (v[1], 0.0, r)
            } else {
                (v[1], v[2], -v[0])
            };
            return cramer(first.0, first.1, first.2, dv[1], dv[2], -dv[0]);
        }
        let [q0, qa, qb] = complex_values(self.poly, Complex::from_polar(1.0, theta));
        cramer(qa.re, qb.re, -q0.re, qa.im, qb.im, -q0.im)
    }

    fn sample(&self, theta: f64) -> Sample {
        match self.wall(theta) {
            Some(wall) => Sample {
                theta,
                wall,
                keep: self.curve_keep(theta, &wall),
                valid: true,
            },
            None => Sample {
                theta,
                wall: Wall {
                    alpha: f64::NAN,
                    beta: f64::NAN,
                },
                keep: false,
                valid: false,
            },
        }
    }

    /// The other roots strictly inside: `q / (z^2 - 2 cos theta z + 1)` passes Schur-Cohn at
    /// radius exactly 1 (the boundary is where a root crosses the circle, so corners are
    /// located to rounding rather than shifted by a margin).
    fn curve_keep(&self, theta: f64, wall: &Wall) -> bool {
        self.with_two(|buf, out| {
            let q = self.poly.coefficients_into(wall, buf);
            schur_cohn(deflate_quadratic(q, theta.cos(), out), 1.0).stable
        })
    }

    /// On the line of `root`: `q / (z - root)` passes Schur-Cohn at radius 1.
    fn line_keep(&self, wall: &Wall, root: f64) -> bool {
        self.with_two(|buf, out| {
            let q = self.poly.coefficients_into(wall, buf);
            schur_cohn(deflate_linear(q, root, out), 1.0).stable
        })
    }

    /// Two scratch rows as long as the coefficients, only that length zeroed (two full
    /// `MAX_COEFFS` rows, 8 kB, per sample test cost more than the test at short delays).
    fn with_two<R>(&self, f: impl FnOnce(&mut [f64], &mut [f64]) -> R) -> R {
        crate::stability::schur_cohn::with_two_rows(self.poly.degree() + 1, f)
    }

    /// Bisection in `theta` between `yes` (where `side` holds) and `no` (where it does
    /// not) until the two walls are within `tol / 4` in the plane or `theta` stalls; both
    /// ends as they are then, `yes` first.
    fn narrow(
        &self,
        mut yes: Sample,
        mut no: Sample,
        side: impl Fn(&Sample) -> bool,
    ) -> (Sample, Sample) {
        for _ in 0..200 {
            if yes.valid && no.valid && dist(&yes.wall, &no.wall) <= 0.25 * self.tol {
                break;
            }
            let theta = 0.5 * (yes.theta + no.theta);
            if theta == yes.theta || theta == no.theta {
                break;
            }
            let s = self.sample(theta);
            if side(&s) {
                yes = s;
            } else {
                no = s;
            }
        }
        (yes, no)
    }

    /// The end of a kept interval between the kept sample `inn` and the rejected `out`.
    fn corner(&self, inn: Sample, out: Sample) -> Sample {
        self.narrow(inn, out, |s| s.keep).0
    }

    /// Points where the curve crosses the zero set of the linear `f`, between valid coarse
    /// samples of opposite sign: of the two ends of the narrowed bracket, the nearer.
    fn crossings(&self, samples: &[Sample], f: impl Fn(&Wall) -> f64) -> Vec<Wall> {
        samples
            .windows(2)
            .filter(|w| w[0].valid && w[1].valid && f(&w[0].wall) * f(&w[1].wall) < 0.0)
            .map(|w| {
                let sign = f(&w[0].wall);
                let (s, t) = self.narrow(w[0], w[1], |x| x.valid && f(&x.wall) * sign > 0.0);
                if t.valid && f(&t.wall).abs() < f(&s.wall).abs() {
                    t.wall
                } else {
                    s.wall
                }
            })
            .collect()
    }

    /// The midpoint in `theta` of the chord between `a` and `b`, for the shared refinement.
    fn midpoint(&self, a: &Sample, b: &Sample) -> Option<Midpoint<Sample>> {
        let theta = 0.5 * (a.theta + b.theta);
        let wall = self.wall(theta)?;
        Some(Midpoint {
            sample: Sample {
                theta,
                wall,
                keep: true,
                valid: true,
            },
            smooth: true,
        })
    }
}

curve_sample!(Sample);

fn dist(a: &Wall, b: &Wall) -> f64 {
    point_dist(a.xy(), b.xy())
}

/// Chains the pieces into closed polylines (each piece joins the piece with the nearest
/// free end, within `100 tol` of the boundary's size: the corners are located to `tol / 4`
/// from both sides), keeps the largest, orients it counterclockwise, starts it at its
/// lowest vertex on the `z = 1` line (lowest overall if the loop has none) and repeats the
/// first vertex at the end.
fn close(mut pieces: Vec<Chain>, tol: f64, lp: &Loop) -> Result<Vec<Vertex>> {
    let fail = |what: &str| {
        Error::Numerical(format!(
            "the boundary of this loop (delta = {}, d = {}) did not close ({what}); its stable region may be empty or unbounded, or an element's resonance narrower than the sampling: try a larger tolerance or the bisection engine",
            lp.plant().delta(),
            lp.plant().d()
        ))
    };
    if pieces.is_empty() {
        return Err(fail("no boundary piece found"));
    }
    let scale = pieces
        .iter()
        .flat_map(|c| &c.pts)
        .fold(1.0f64, |m, w| m.max(w.alpha.abs()).max(w.beta.abs()));
    let join = 100.0 * tol * scale;
    let mut loops: Vec<Vec<Vertex>> = Vec::new();
    while let Some(mut cur) = pieces.pop() {
        let start = cur.pts[0];
        let mut lp_pts: Vec<Vertex> = Vec::new();
        loop {
            let end = cur.pts[cur.pts.len() - 1];
            lp_pts.extend(cur.pts[..cur.pts.len() - 1].iter().map(|w| Vertex {
                x: w.alpha,
                y: w.beta,
                piece: cur.piece,
            }));
            let nearest = pieces
                .iter()
                .enumerate()
                .flat_map(|(k, c)| {
                    [
                        (dist(&end, &c.pts[0]), k, false),
                        (dist(&end, &c.pts[c.pts.len() - 1]), k, true),
                    ]
                })
                .min_by(|x, y| x.0.total_cmp(&y.0));
            let home = dist(&end, &start);
            match nearest {
                Some((gap, k, reversed)) if gap < home && gap <= join => {
                    let mut next = pieces.swap_remove(k);
                    if reversed {
                        next.pts.reverse();
                    }
                    // a line's end is exactly on its line: the corner takes it
                    if cur.piece != Piece::Curve && next.piece == Piece::Curve {
                        next.pts[0] = end;
                    }
                    cur = next;
                }
                _ if home <= join => {
                    if cur.piece != Piece::Curve
                        && let Some(first) = lp_pts.first_mut()
                        && first.piece == Piece::Curve
                    {
                        first.x = end.alpha;
                        first.y = end.beta;
                    }
                    break;
                }
                _ => return Err(fail(&format!("a gap of {home:e} between pieces"))),
            }
        }
        loops.push(lp_pts);
    }
    let area = |l: &[Vertex]| polygon_area(&l.iter().map(|p| (p.x, p.y)).collect::<Vec<_>>());
    let mut best = loops
        .into_iter()
        .filter(|l| l.len() >= 3)
        .max_by(|a, b| area(a).abs().total_cmp(&area(b).abs()))
        .ok_or_else(|| fail("no closed loop"))?;
    if area(&best) < 0.0 {
        // reversed, each segment's label moves to its other end
        let n = best.len();
        let labels: Vec<Piece> = (0..n).map(|i| best[(i + n - 1) % n].piece).collect();
        for (p, l) in best.iter_mut().zip(labels) {
            p.piece = l;
        }
        best.reverse();
    }
    // a vertex is on the z = 1 line when the segment leaving or entering it is
    let n = best.len();
    let z_one = |i: usize| {
        [best[i].piece, best[(i + n - 1) % n].piece]
            .iter()
            .any(|p| matches!(p, Piece::AlphaZero | Piece::PlusOne))
    };
    let lowest = |on_line: bool| {
        best.iter()
            .enumerate()
            .filter(|&(i, _)| !on_line || z_one(i))
            .min_by(|a, b| a.1.y.total_cmp(&b.1.y))
            .map(|(i, _)| i)
    };
    let start = lowest(true).or_else(|| lowest(false)).unwrap_or(0);
    best.rotate_left(start);
    best.push(best[0]);
    Ok(best)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Division by `z^2 - 2 cos t z + 1` recovers the other factor of a product formed here.
    #[test]
    fn pair_division_recovers_the_cofactor() {
        let c = 0.3f64.cos();
        let other = [0.2, -0.7, 1.5, 1.0];
        let pair = [1.0, -2.0 * c, 1.0];
        let mut q = [0.0; 6];
        for (i, x) in other.iter().enumerate() {
            for (j, y) in pair.iter().enumerate() {
                q[i + j] += x * y;
            }
        }
        let mut out = [0.0; 8];
        let got = deflate_quadratic(&q, c, &mut out);
        assert_eq!(got.len(), other.len());
        for (g, w) in got.iter().zip(&other) {
            assert!((g - w).abs() < 1e-14, "{got:?}");
        }
    }
}
