//! The D-decomposition curve and lines of an affine polynomial
//! `q = Q0 + alpha QA + beta QB`, as the one exact engine ([`super::exact()`]) reads them.
//!
//! A [`Curve`] gives the engine what a loop provides (the model document, docs/MODEL.md,
//! sections 4 and 8): the wall with the root pair `e^{+-i theta}` (Cramer's rule on the
//! complex equation `alpha QA + beta QB = -Q0`, and at `theta = 0` and `pi` the double root
//! `q = q' = 0`), the lines of the real roots `z = 1` and `z = -1`, whether the device has a
//! free integrator (then the `z = 1` line is `alpha = 0` exactly), and the coefficients of
//! `q` for the deflated Schur-Cohn tests. Two implementations:
//!
//! - [`PaperCurve`]: the paper's loop, on the closed forms of [`PaperPoly`]
//!   (`W = -z^(n+2) (z - 1)(z - c) / M(z)`, docs/MODEL.md section 4): a fast evaluation of
//!   the same curve.
//! - [`LoopCurve`]: any loop, on its own polynomial (the one loop curve, shared with the
//!   direct searches).

use std::f64::consts::PI;

use super::{Piece, Plant};
use crate::curve::{Decomposition, LoopCurve, cramer};
use crate::params::Wall;
use crate::poly::{Complex, PaperPoly};

/// The line `a alpha + b beta = r` of walls with the real root `z = root`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Line {
    pub(crate) a: f64,
    pub(crate) b: f64,
    pub(crate) r: f64,
    pub(crate) root: f64,
    pub(crate) piece: Piece,
}

impl Line {
    /// Parametrized by `alpha` when it is closer to horizontal, else by `beta`.
    fn by_alpha(&self) -> bool {
        self.b.abs() >= self.a.abs()
    }

    /// The wall at parameter `t`.
    pub(crate) fn at(&self, t: f64) -> Wall {
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

    /// The parameter of the wall `w` (on or near the line).
    pub(crate) fn param(&self, w: &Wall) -> f64 {
        if self.by_alpha() { w.alpha } else { w.beta }
    }

    /// `a alpha + b beta - r`: zero on the line, of one sign on each side.
    pub(crate) fn residual(&self, w: &Wall) -> f64 {
        self.a * w.alpha + self.b * w.beta - self.r
    }

    /// Within `tol` of the line.
    pub(crate) fn near(&self, w: &Wall, tol: f64) -> bool {
        self.residual(w).abs() <= tol * self.a.hypot(self.b)
    }

    /// Where two lines meet (`None` if parallel to rounding). A vertical line (`b = 0`, the
    /// `z = 1` line of every loop) gives its `alpha` directly, and the other line the `beta`
    /// there, so that the `alpha = 0` line meets the other exactly at `alpha = 0`.
    pub(crate) fn meet(&self, o: &Line) -> Option<Wall> {
        let through = |v: &Line, w: &Line| {
            let alpha = v.r / v.a;
            let beta = (w.r - w.a * alpha) / w.b;
            (alpha.is_finite() && beta.is_finite()).then_some(Wall { alpha, beta })
        };
        match (self.b == 0.0, o.b == 0.0) {
            // exact zeros: the z = 1 line's b is the literal 0 (QB(1) = 0 for every loop)
            (true, false) => through(self, o),
            (false, true) => through(o, self),
            _ => cramer((self.a, self.b, self.r), (o.a, o.b, o.r)),
        }
    }
}

/// What the exact engine reads of a loop's affine polynomial (see the module documentation).
pub(crate) trait Curve: Sync {
    /// The plant (for messages and the result).
    fn plant(&self) -> &Plant;

    /// Coarse intervals of `theta` over `[0, pi]`: 64 per turn of the curve.
    fn coarse_steps(&self) -> usize;

    /// Whether the coarse samples are computed in parallel (when the engine runs in
    /// parallel at all): worth it for the general polynomial's dearer samples.
    fn parallel_scan(&self) -> bool;

    /// Whether the refinement predicts halves of smooth chords (see `refine::Refiner`).
    fn predict(&self) -> bool;

    /// Whether the curve may run off to infinity on the circle (a zero of the Cramer
    /// determinant there), so that the coarse scan must resolve its fast parts.
    fn fast_parts(&self) -> bool;

    /// The power `k` of `z` whose value `z^k` [`Curve::wall_at`] takes precomputed (the
    /// delay's power of `Q0`), so that refinement finds it by bisecting angles.
    fn circle_power(&self) -> usize;

    /// The wall with the root pair `e^{+-i theta}` from `z = e^{i theta}` and `zk = z^k`
    /// (`Im z > 0`); `None` where there is none (the curve runs off to infinity).
    fn wall_at(&self, z: Complex, zk: Complex) -> Option<Wall>;

    /// The wall at `theta` in `[0, pi]`; at the ends the limit where the pair merges into a
    /// double root at `z = +-1`.
    fn wall(&self, theta: f64) -> Option<Wall>;

    /// False when `wall` surely has a real root outside the circle (so no coarse sample
    /// there bounds the stable region and none is tested).
    fn may_bound(&self, wall: &Wall) -> bool;

    /// Degree of `q`.
    fn degree(&self) -> usize;

    /// Writes `q` for `wall` into `buf` (at least `degree + 1` long) and returns it.
    fn coefficients_into<'a>(&self, wall: &Wall, buf: &'a mut [f64]) -> &'a [f64];

    /// The line of the root `z = root` (`+1` or `-1`), if walls move that root.
    fn line(&self, root: f64) -> Option<Line>;
}

/// The paper's loop on its closed forms.
pub(crate) struct PaperCurve {
    cp: PaperPoly,
}

/// Coarse samples per turn of the curve: the curve turns about `n + 2` times as fast as
/// `theta` (the degree of `q` for a loop with elements), and 64 samples per turn keep every
/// kept interval found (the shortest kept intervals seen over the test family span hundreds
/// of samples).
const SAMPLES_PER_TURN: usize = 64;

impl PaperCurve {
    pub(crate) fn new(plant: &Plant) -> Self {
        Self {
            cp: PaperPoly::new(plant),
        }
    }

    /// The wall with a double root at `z0 = +-1`: `q(z0) = q'(z0) = 0`, linear in the wall.
    fn double_root(&self, z0: f64) -> Option<Wall> {
        if z0 > 0.0 {
            // q(1) = alpha QA(1) forces alpha = 0; q/(z - 1) at z = 1 is, in the undivided form,
            // (1 - c) + beta M(1). `1 - c = -expm1(-delta)` keeps full accuracy at small delta.
            let one_minus_c = -(-self.cp.plant().delta()).exp_m1();
            let m1 = self.cp.m(Complex::new(1.0, 0.0)).re;
            let beta = -one_minus_c / m1;
            return beta.is_finite().then_some(Wall { alpha: 0.0, beta });
        }
        let deg = self.cp.degree();
        let (mut p0, mut pa, mut pb) = ([0.0; 2], [0.0; 2], [0.0; 2]);
        // value and derivative at z0 by Horner
        for i in (0..=deg).rev() {
            for (acc, c) in [
                (&mut p0, self.cp.q0(i)),
                (&mut pa, self.cp.qa(i)),
                (&mut pb, self.cp.qb(i)),
            ] {
                acc[1] = acc[1] * z0 + acc[0];
                acc[0] = acc[0] * z0 + c;
            }
        }
        // pa[0] alpha + pb[0] beta = -p0[0]; pa[1] alpha + pb[1] beta = -p0[1]
        let det = pa[0] * pb[1] - pb[0] * pa[1];
        let scale = (pa[0].abs() + pb[0].abs()) * (pa[1].abs() + pb[1].abs());
        // A determinant at rounding level of its terms means the pair runs off to infinity.
        if det.is_nan() || det.abs() <= 1e-13 * scale {
            return None;
        }
        let alpha = (-p0[0] * pb[1] + pb[0] * p0[1]) / det;
        let beta = (-pa[0] * p0[1] + p0[0] * pa[1]) / det;
        (alpha.is_finite() && beta.is_finite()).then_some(Wall { alpha, beta })
    }
}

impl Curve for PaperCurve {
    fn plant(&self) -> &Plant {
        self.cp.plant()
    }

    fn coarse_steps(&self) -> usize {
        SAMPLES_PER_TURN * self.cp.circle_power()
    }

    fn parallel_scan(&self) -> bool {
        false
    }

    fn predict(&self) -> bool {
        true
    }

    /// `M(z)` vanishes on the circle at most at `z = -1` (`delta = d = 0`), the curve's end
    /// (docs/MODEL.md section 4): the curve's speed is bounded inside, and 64 samples per
    /// turn resolve it.
    fn fast_parts(&self) -> bool {
        false
    }

    fn circle_power(&self) -> usize {
        self.cp.circle_power()
    }

    // Inlined into the refinement's recursion, as the closed form was before the engine
    // took it through this trait: called out of line it cost 3 % more instructions.
    #[inline(always)]
    fn wall_at(&self, z: Complex, zk: Complex) -> Option<Wall> {
        self.cp.wall_on_circle_at(z, zk)
    }

    fn wall(&self, theta: f64) -> Option<Wall> {
        if theta <= 0.0 {
            self.double_root(1.0)
        } else if theta >= PI {
            self.double_root(-1.0)
        } else {
            self.cp.wall_on_circle(theta)
        }
    }

    /// `q(1) = alpha QA(1)` with `QA(1) = M(1) > 0`: a wall with `alpha < 0` has a real root
    /// beyond 1 (docs/MODEL.md section 4). Most coarse samples of a long delay are there.
    fn may_bound(&self, wall: &Wall) -> bool {
        wall.alpha >= 0.0
    }

    fn degree(&self) -> usize {
        self.cp.degree()
    }

    fn coefficients_into<'a>(&self, wall: &Wall, buf: &'a mut [f64]) -> &'a [f64] {
        self.cp.coefficients_into(wall, buf)
    }

    fn line(&self, root: f64) -> Option<Line> {
        if root > 0.0 {
            // the free integrator: z = 1 is a root exactly when alpha = 0
            return Some(Line {
                a: 1.0,
                b: 0.0,
                r: 0.0,
                root,
                piece: Piece::AlphaZero,
            });
        }
        let (a, b, r) = self.cp.line_minus_one()?;
        Some(Line {
            a,
            b,
            r,
            root,
            piece: Piece::MinusOne,
        })
    }
}

impl Curve for LoopCurve {
    fn plant(&self) -> &Plant {
        LoopCurve::plant(self)
    }

    fn coarse_steps(&self) -> usize {
        // the curve turns about `degree` times as fast as theta: z^(n+2) for the delay, Fd
        // for a moving average, the device's modes
        SAMPLES_PER_TURN * (self.poly().degree() + 1)
    }

    fn parallel_scan(&self) -> bool {
        true
    }

    fn predict(&self) -> bool {
        false
    }

    fn fast_parts(&self) -> bool {
        true
    }

    fn circle_power(&self) -> usize {
        LoopCurve::circle_power(self)
    }

    fn wall_at(&self, z: Complex, zk: Complex) -> Option<Wall> {
        LoopCurve::wall_at(self, z, zk)
    }

    fn wall(&self, theta: f64) -> Option<Wall> {
        if theta <= 0.0 || theta >= PI {
            // q(z0) = 0 and q'(z0) = 0; at z0 = 1 the first is the z = 1 line
            let z0 = if theta <= 0.0 { 1.0 } else { -1.0 };
            return self.double_root(z0, -self.at_one().0);
        }
        let z = Complex::from_polar(1.0, theta);
        let zk = Complex::from_polar(1.0, self.circle_power() as f64 * theta);
        self.wall_at(z, zk)
    }

    /// `q(1) = Q0(1) + alpha QA(1)` (`QB(1) = 0`) of the other sign than the leading
    /// coefficient (1: `Q0` is monic and `QA`, `QB` are of lower degree) puts a real root
    /// beyond 1.
    fn may_bound(&self, wall: &Wall) -> bool {
        let (p, n) = (self.poly(), self.poly().degree());
        let lead = p.q0()[n] + wall.alpha * p.qa()[n] + wall.beta * p.qb()[n];
        let q1 = self.at_one().0 + wall.alpha * self.at_one().1;
        // NaN (a wall at infinity) is not rejected here: the deflated test decides
        (q1 * lead).is_nan() || q1 * lead >= 0.0
    }

    fn degree(&self) -> usize {
        self.poly().degree()
    }

    fn coefficients_into<'a>(&self, wall: &Wall, buf: &'a mut [f64]) -> &'a [f64] {
        self.poly().coefficients_into(wall, buf)
    }

    fn line(&self, root: f64) -> Option<Line> {
        if root > 0.0 {
            // QB(1) = 0 for every loop ((z - 1) is a factor): the line is vertical. With a free
            // integrator D(1) = 0 in the model, so Q0(1) = 0 and the line is alpha = 0 exactly.
            let (q0, a) = self.at_one();
            let free = Decomposition::free_integrator(self);
            // the literal 0 with a free integrator (not -0, which would print as "-0")
            let r = if free { 0.0 } else { -q0 };
            return (a != 0.0 && a.is_finite()).then_some(Line {
                a,
                b: 0.0,
                r,
                root,
                // exact: the free integrator's Q0(1) is the literal 0
                piece: if free {
                    Piece::AlphaZero
                } else {
                    Piece::PlusOne
                },
            });
        }
        let (a, b, r) = self.line_minus_one()?;
        Some(Line {
            a,
            b,
            r,
            root,
            piece: Piece::MinusOne,
        })
    }
}
