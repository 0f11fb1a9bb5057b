//! The D-decomposition of an affine characteristic polynomial
//! `q = Q0 + alpha QA + beta QB` (`docs/MODEL.md` sections 4 and 8) as the direct searches
//! need it: the curve of walls with a root `e^{i theta}`, `0 < theta < pi`, with its exact
//! derivative along `theta`; the lines of the real roots `z = +1` and `z = -1`; and the point
//! test. Two implementations: the paper's closed-form curve ([`super::curve::PaperCurve`]) and
//! any loop's polynomial ([`LoopCurve`]).
//!
//! Method for [`LoopCurve`]: on `z = e^{i theta}` the complex equation
//! `alpha QA(z) + beta QB(z) = -Q0(z)` is two real linear equations, solved by Cramer's rule
//! (D-decomposition, Neimark 1948). Along the curve `q(e^{i theta}) = 0`, so
//! `alpha' QA + beta' QB = -i z q'(z)` (the derivative of `q(e^{i theta})` at the fixed wall),
//! the same two-by-two system with another right-hand side: the exact derivative, no finite
//! difference.

use std::f64::consts::PI;

use crate::elements::{Loop, LoopPoly};
use crate::params::Wall;
use crate::poly::Complex;
use crate::stability::eigen::poly_roots;
use crate::stability::schur_cohn;

/// A point of the D-decomposition curve with the derivatives along `theta`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct CurvePoint {
    pub(crate) alpha: f64,
    pub(crate) beta: f64,
    pub(crate) dalpha: f64,
    /// Checked against finite differences in the tests (with `dalpha`, same formula).
    #[cfg_attr(not(test), allow(dead_code))]
    pub(crate) dbeta: f64,
}

impl CurvePoint {
    /// The finite point, or `None`.
    pub(crate) fn finite(self) -> Option<Self> {
        (self.alpha.is_finite()
            && self.beta.is_finite()
            && self.dalpha.is_finite()
            && self.dbeta.is_finite())
        .then_some(self)
    }
}

/// The D-decomposition of `q = Q0 + alpha QA + beta QB` (see the module documentation).
pub(crate) trait Decomposition {
    /// Calls `f(theta, point)` for the scan's angles in increasing order, all inside
    /// `(0, pi)` (`None` where the curve has no finite point).
    fn scan(&self, f: &mut dyn FnMut(f64, Option<CurvePoint>));

    /// The curve at `theta` in `(0, pi)`.
    fn eval(&self, theta: f64) -> Option<CurvePoint>;

    /// The curve's end at `theta = pi`: the wall with a double root at `z = -1`, where
    /// `d alpha / d theta = 0` by the curve's symmetry about `pi`.
    fn eval_end(&self) -> Option<CurvePoint>;

    /// The curve's start at `theta = 0`: the wall with a double root at `z = 1`
    /// (`q(1) = q'(1) = 0`), where both derivatives along `theta` vanish by symmetry.
    fn eval_start(&self) -> Option<CurvePoint>;

    /// [`Decomposition::eval`] inside `(0, pi)`, [`Decomposition::eval_start`] and
    /// [`Decomposition::eval_end`] at and beyond the ends (a root finder may probe them).
    fn eval_or_end(&self, theta: f64) -> Option<CurvePoint> {
        if theta >= PI {
            self.eval_end()
        } else if theta <= 0.0 {
            self.eval_start()
        } else {
            self.eval(theta)
        }
    }

    /// The line of walls with the root `z = -1` as `(a, b, r)`, `a alpha + b beta = r`;
    /// `None` if `z = -1` is a root for no wall.
    fn line_minus_one(&self) -> Option<(f64, f64, f64)>;

    /// The line of walls with the root `z = +1`: `QB(1) = 0` for every loop, so it is the
    /// vertical line `alpha = -Q0(1) / QA(1)`, exactly `0` with a free integrator.
    fn alpha_plus_one(&self) -> Option<f64>;

    /// Whether `Q0(1) = 0` exactly (no hand stiffness): the line `alpha = 0` bounds every
    /// stable region on the left.
    fn free_integrator(&self) -> bool;

    /// Degree of `q`.
    fn degree(&self) -> usize;

    /// Whether two branches of the curve can meet at the region's boundary (a wedge's tip),
    /// so that the search must look for the curve's self-intersections. The paper's region
    /// has none (its boundary is the curve's one arc between the two lines).
    fn self_intersections(&self) -> bool {
        true
    }

    /// `[Q0, QA, QB]`, lowest power first, each `degree + 1` long.
    fn affine(&self) -> [Vec<f64>; 3];

    /// Writes `q` for `wall` into `buf` (at least `degree + 1` long) and returns it.
    fn coefficients_into<'a>(&self, wall: &Wall, buf: &'a mut [f64]) -> &'a [f64];

    /// Schur-Cohn at radius exactly 1 on `q` for `wall` (`buf` as above): every root strictly
    /// inside the circle.
    fn strictly_stable(&self, wall: &Wall, buf: &mut [f64]) -> bool {
        schur_cohn(self.coefficients_into(wall, buf), 1.0).stable
    }
}

/// The D-decomposition of a loop's own polynomial ([`LoopPoly`]).
#[derive(Debug, Clone)]
pub(crate) struct LoopCurve {
    poly: LoopPoly,
    free_integrator: bool,
    /// Scan angles in `(0, pi)`, increasing.
    grid: Vec<f64>,
    /// `Q0`, `QA`, `QB` as `z^k s(z)` with `s` their coefficients from the lowest nonzero one.
    factored: [Factored; 3],
}

/// A polynomial `z^shift s(z)`: `Q0 = z^(n+2) D Fd` has a long delay's power of `z` as a
/// factor, so evaluating `s` and `z^shift` costs the device's order, not the delay's.
#[derive(Debug, Clone)]
struct Factored {
    shift: usize,
    short: Vec<f64>,
}

impl Factored {
    fn new(p: &[f64]) -> Self {
        let shift = p.iter().position(|c| *c != 0.0).unwrap_or(0);
        Self {
            shift,
            short: p[shift..].to_vec(),
        }
    }

    /// The value and the derivative at `z = e^{i theta}`.
    fn at(&self, z: Complex, theta: f64) -> (Complex, Complex) {
        let zero = Complex::new(0.0, 0.0);
        let (mut v, mut dv) = (zero, zero);
        for &c in self.short.iter().rev() {
            dv = dv * z + v;
            v = v * z + c;
        }
        if self.shift == 0 {
            return (v, dv);
        }
        // z^k from the angle (one rounding of k theta, as the paper's curve), and
        // (z^k s)' = z^k (k s / z + s'); 1 / z = conj(z) on the circle
        let k = self.shift as f64;
        let zk = Complex::from_polar(1.0, k * theta);
        (zk * v, zk * (v * z.conj() * k + dv))
    }
}

/// Uniform scan samples per degree of `q`: the curve turns about `degree` times as fast as
/// `theta` (`z^(n+2)` for the delay, a moving average's denominator, the device's modes), and
/// 32 samples per turn are what the paper's scan uses (`32 (n + 2)`).
const SAMPLES_PER_DEGREE: usize = 32;

/// Samples added around a root of `Q0` or `QA` close to the circle, each side of its angle.
///
/// Near such a root (a lightly damped mode, a filter pole near 1) the curve runs through a
/// loop of width about the root's distance `rho` to the circle in `theta`, however fine the
/// uniform grid; 16 samples over `4 rho` each side resolve it as the uniform grid resolves
/// one turn.
const SAMPLES_PER_RESONANCE: usize = 16;

/// A Cramer determinant below this fraction of the product of its columns' sizes is a
/// direction in which the curve runs off to infinity (the two equations dependent to
/// rounding): about a thousand roundings, above what Horner's evaluation on the circle
/// leaves of a degree-70 polynomial's terms.
const SINGULAR: f64 = 1e-13;

impl LoopCurve {
    /// The decomposition of `lp`'s polynomial.
    pub(crate) fn new(lp: &Loop) -> crate::error::Result<Self> {
        let poly = LoopPoly::new(lp)?;
        let grid = scan_grid(&poly);
        let factored = [poly.q0(), poly.qa(), poly.qb()].map(Factored::new);
        Ok(Self {
            free_integrator: lp.free_integrator(),
            poly,
            grid,
            factored,
        })
    }

    /// `(Q0, QA, QB)` and their derivatives at `z = e^{i theta}`, `theta` in `(0, pi)`.
    fn on_circle(&self, z: Complex, theta: f64) -> ([Complex; 3], [Complex; 3]) {
        let [(v0, d0), (va, da), (vb, db)] = [0, 1, 2].map(|k| self.factored[k].at(z, theta));
        ([v0, va, vb], [d0, da, db])
    }

    /// `(Q0, QA, QB)` and their derivatives at `z` by Horner's rule.
    fn values(&self, z: Complex) -> ([Complex; 3], [Complex; 3]) {
        let zero = Complex::new(0.0, 0.0);
        let (mut v, mut dv) = ([zero; 3], [zero; 3]);
        let p = &self.poly;
        for i in (0..=p.degree()).rev() {
            for (k, c) in [p.q0()[i], p.qa()[i], p.qb()[i]].into_iter().enumerate() {
                dv[k] = dv[k] * z + v[k];
                v[k] = v[k] * z + c;
            }
        }
        (v, dv)
    }

    fn at(&self, theta: f64) -> Option<CurvePoint> {
        if !(theta > 0.0 && theta < PI) {
            return None;
        }
        let z = Complex::from_polar(1.0, theta);
        let ([q0, qa, qb], [d0, da, db]) = self.on_circle(z, theta);
        let (det, size) = (
            qa.re * qb.im - qb.re * qa.im,
            qa.norm() * qb.norm(), // the columns' sizes
        );
        if det.is_nan() || det.abs() <= SINGULAR * size {
            return None;
        }
        let solve = |c: Complex| {
            (
                (c.re * qb.im - qb.re * c.im) / det,
                (qa.re * c.im - c.re * qa.im) / det,
            )
        };
        let (alpha, beta) = solve(-q0);
        // d/dtheta of q(e^{i theta}) at this wall: i z q'(z)
        let dq = Complex::new(0.0, 1.0) * z * (d0 + da * alpha + db * beta);
        let (dalpha, dbeta) = solve(-dq);
        CurvePoint {
            alpha,
            beta,
            dalpha,
            dbeta,
        }
        .finite()
    }
}

/// The scan's angles for `poly`: the midpoints of a uniform grid of `32 (degree + 1)`
/// intervals over `[0, pi]`, refined around the angle of every root of `Q0` and `QA` within a grid step of
/// the circle (see [`SAMPLES_PER_RESONANCE`]).
fn scan_grid(poly: &LoopPoly) -> Vec<f64> {
    let steps = SAMPLES_PER_DEGREE * (poly.degree() + 1);
    let h = PI / steps as f64;
    // Midpoints of the uniform grid: the rational angles `pi j / steps` include the zeros a
    // moving average's numerator puts on the circle (`2 pi k / N`, where `QB` vanishes and
    // the curve runs off to infinity), which would cut the scan exactly there.
    let mut grid: Vec<f64> = (0..steps)
        .map(|j| PI * (j as f64 + 0.5) / steps as f64)
        .collect();
    for p in [poly.q0(), poly.qa()] {
        let Some(last) = p.iter().rposition(|c| *c != 0.0) else {
            continue;
        };
        let Some(first) = p.iter().position(|c| *c != 0.0) else {
            continue;
        };
        // a failure of the root finder leaves the uniform grid, which is still a scan
        let Ok(roots) = poly_roots(&p[first..=last]) else {
            continue;
        };
        for r in roots {
            let rho = (r.norm() - 1.0).abs();
            if rho >= 4.0 * h || r.im < 0.0 {
                continue;
            }
            // a root on the circle (the free integrator's z = 1): its neighbourhood at the
            // scale of rounding
            let rho = rho.max(1e-9);
            let centre = r.arg();
            let k = SAMPLES_PER_RESONANCE as f64;
            for i in 1..=SAMPLES_PER_RESONANCE {
                let off = 4.0 * rho * i as f64 / k;
                grid.extend([centre - off, centre + off]);
            }
        }
    }
    grid.retain(|t| *t > 0.0 && *t < PI);
    grid.sort_by(f64::total_cmp);
    grid.dedup();
    grid
}

/// The wall with a double real root: `a1 alpha + b1 beta = c1` (`q = 0`) and
/// `a2 alpha + b2 beta = c2` (`q' = 0`) by Cramer's rule; `None` where they are dependent to
/// rounding (see [`SINGULAR`]).
fn double_root((a1, b1, c1): (f64, f64, f64), (a2, b2, c2): (f64, f64, f64)) -> Option<CurvePoint> {
    let det = a1 * b2 - b1 * a2;
    if det.is_nan() || det.abs() <= SINGULAR * a1.hypot(b1) * a2.hypot(b2) {
        return None;
    }
    CurvePoint {
        alpha: (c1 * b2 - b1 * c2) / det,
        beta: (a1 * c2 - c1 * a2) / det,
        dalpha: 0.0,
        dbeta: 0.0,
    }
    .finite()
}

impl Decomposition for LoopCurve {
    fn scan(&self, f: &mut dyn FnMut(f64, Option<CurvePoint>)) {
        for &t in &self.grid {
            f(t, self.at(t));
        }
    }

    fn eval(&self, theta: f64) -> Option<CurvePoint> {
        self.at(theta)
    }

    fn eval_start(&self) -> Option<CurvePoint> {
        // q(1) = 0 and q'(1) = 0; QB(1) = 0 for every loop, and Q0(1) = 0 exactly with a free
        // integrator
        let ([q0, qa, _], [d0, da, db]) = self.values(Complex::new(1.0, 0.0));
        let r = if self.free_integrator { 0.0 } else { -q0.re };
        double_root((qa.re, 0.0, r), (da.re, db.re, -d0.re))
    }

    fn eval_end(&self) -> Option<CurvePoint> {
        // q(-1) = 0 and q'(-1) = 0: two real linear equations.
        let ([q0, qa, qb], [d0, da, db]) = self.values(Complex::new(-1.0, 0.0));
        double_root((qa.re, qb.re, -q0.re), (da.re, db.re, -d0.re))
    }

    fn line_minus_one(&self) -> Option<(f64, f64, f64)> {
        let ([q0, qa, qb], _) = self.values(Complex::new(-1.0, 0.0));
        let (a, b, r) = (qa.re, qb.re, -q0.re);
        (self.poly.wall_moves_root(a, b) && r.is_finite()).then_some((a, b, r))
    }

    fn alpha_plus_one(&self) -> Option<f64> {
        if self.free_integrator {
            return Some(0.0);
        }
        let ([q0, qa, _], _) = self.values(Complex::new(1.0, 0.0));
        let a = -q0.re / qa.re;
        a.is_finite().then_some(a)
    }

    fn free_integrator(&self) -> bool {
        self.free_integrator
    }

    fn degree(&self) -> usize {
        self.poly.degree()
    }

    fn coefficients_into<'a>(&self, wall: &Wall, buf: &'a mut [f64]) -> &'a [f64] {
        self.poly.coefficients_into(wall, buf)
    }

    fn affine(&self) -> [Vec<f64>; 3] {
        [self.poly.q0(), self.poly.qa(), self.poly.qb()].map(<[f64]>::to_vec)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::elements::Hand;
    use crate::filter::VelocityFilter;
    use crate::params::Plant;

    /// The curve's walls have the root `e^{i theta}`, and its derivative matches a central
    /// difference, for loops with a hand and a filter.
    #[test]
    fn curve_has_the_root_and_its_derivative() {
        let plant = Plant::new(0.7, 1.3).unwrap();
        let loops = [
            Loop::new(plant)
                .with_hand(Hand::new(0.5, 0.2, 0.01).unwrap())
                .unwrap(),
            Loop::new(plant)
                .with_filter(VelocityFilter::low_pass(0.8).unwrap())
                .unwrap(),
        ];
        for lp in loops {
            let c = LoopCurve::new(&lp).unwrap();
            for t in [0.2, 0.9, 1.7, 2.8] {
                let p = c.eval(t).unwrap();
                let q = c.poly.coefficients(&Wall {
                    alpha: p.alpha,
                    beta: p.beta,
                });
                let z = Complex::from_polar(1.0, t);
                let v = q
                    .iter()
                    .rev()
                    .fold(Complex::new(0.0, 0.0), |acc, &k| acc * z + k);
                let scale: f64 = q.iter().map(|k| k.abs()).sum();
                assert!(v.norm() < 1e-12 * scale, "{t}: {v}");
                let h = 1e-6;
                let (a, b) = (c.eval(t + h).unwrap(), c.eval(t - h).unwrap());
                // central difference: error O(h^2) times the third derivative
                let fd = |x: f64, y: f64| (x - y) / (2.0 * h);
                assert!((p.dalpha - fd(a.alpha, b.alpha)).abs() <= 1e-6 * (1.0 + p.dalpha.abs()));
                assert!((p.dbeta - fd(a.beta, b.beta)).abs() <= 1e-6 * (1.0 + p.dbeta.abs()));
            }
        }
    }
}
