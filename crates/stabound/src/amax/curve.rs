//! The D-decomposition curve of walls with a root `e^{i theta}` on the unit circle, with its
//! exact derivative along `theta` (`docs/MODEL.md` section 4), as the `alpha_max` search
//! needs it.

use std::borrow::Cow;
use std::f64::consts::PI;

pub(super) use crate::curve::ROTOR_RESEED;
use crate::curve::{CurvePoint, Decomposition, Rotor};
use crate::params::{Plant, Wall};
use crate::poly::{Complex, PaperPoly};

/// The curve of walls with a root `e^{i theta}` and its exact derivative.
pub(super) struct Curve {
    k: f64,
    c: f64,
    m: [f64; 3],
}

impl Curve {
    pub(super) fn new(poly: &PaperPoly) -> Self {
        let disc = poly.discretization();
        Self {
            k: (disc.n + 2) as f64,
            c: disc.c,
            m: poly.m_coefficients(),
        }
    }

    /// `alpha z + beta (z - 1) = W(z)`, `W = -z^k (z - 1)(z - c) / M(z)` on `z = e^{i theta}`
    /// (as [`PaperPoly::wall_on_circle`]), with `dW/dtheta = i z W (k/z + 1/(z-1) + 1/(z-c) -
    /// M'/M)`.
    pub(super) fn eval(&self, theta: f64) -> Option<CurvePoint> {
        let (s, co) = theta.sin_cos();
        self.eval_on_circle(Complex::new(co, s), self.zk(theta))
    }

    /// [`Curve::eval`] with `z = e^{i theta}` and `zk = e^{i (n+2) theta}` given (the scan
    /// gets them by rotation, see [`Rotor`]).
    pub(super) fn eval_on_circle(&self, z: Complex, zk: Complex) -> Option<CurvePoint> {
        if z.im <= 0.0 {
            return None;
        }
        self.eval_at(z, zk)
    }

    /// `e^{i (n+2) theta}` from the library's sine and cosine.
    fn zk(&self, theta: f64) -> Complex {
        Complex::from_polar(1.0, self.k * theta)
    }

    /// `n + 2`, the power of `z` in the curve's factor `z^(n+2)`.
    pub(super) fn power(&self) -> f64 {
        self.k
    }

    /// The end of the curve at `theta = pi` (`z = -1`, a double root there). `Im W` and
    /// `sin theta` both vanish; by l'Hopital `Im W / sin theta -> -d(Im W)/d theta`. The curve
    /// is symmetric about `theta = pi`, so `d alpha / d theta = 0` there.
    pub(super) fn eval_end(&self) -> Option<CurvePoint> {
        self.eval_at(Complex::new(-1.0, 0.0), self.zk(PI))
    }

    fn eval_at(&self, z: Complex, zk: Complex) -> Option<CurvePoint> {
        let (s, co) = (z.im, z.re);
        let [m0, m1, m2] = self.m;
        let mz = (z * m2 + m1) * z + m0;
        let dm = z * (2.0 * m2) + m1;
        // As in PaperPoly::wall_on_circle_at: a modulus of M this small is a zero of M (the
        // larger component, within a factor sqrt 2 of the modulus, without `hypot`).
        if crate::poly::vanishes(mz) {
            return None;
        }
        let zm1 = z - 1.0;
        let zmc = z - self.c;
        let w = -zk * zm1 * zmc / mz;
        let logd = Complex::new(self.k, 0.0) / z + zm1.inv() + zmc.inv() - dm / mz;
        let dw = w * logd * z * Complex::new(0.0, 1.0);
        let (sigma, dsigma) = if s > 0.0 {
            (w.im / s, (dw.im * s - w.im * co) / (s * s))
        } else {
            // theta = pi: sigma by l'Hopital; its derivative is 0 by symmetry.
            (-dw.im, 0.0)
        };
        let beta = sigma * co - w.re;
        let alpha = sigma - beta;
        let dbeta = dsigma * co - sigma * s - dw.re;
        let dalpha = dsigma - dbeta;
        CurvePoint {
            alpha,
            beta,
            dalpha,
            dbeta,
        }
        .finite()
    }
}

/// The paper's loop as a [`Decomposition`]: the closed-form curve, scanned on
/// `32 (n + 2)` intervals of `[0, pi]` by [`Rotor`] (16 samples per oscillation of the curve's
/// factor `e^{i (n+2) theta}`), and the closed-form polynomial.
pub(crate) struct PaperCurve {
    pub(super) poly: PaperPoly,
    curve: Curve,
    steps: usize,
    reseed: usize,
}

impl PaperCurve {
    /// The decomposition of `plant`'s loop, its scan re-seeded every `reseed` samples
    /// ([`ROTOR_RESEED`]; `1`: every sample from `sin_cos`).
    pub(crate) fn new(plant: &Plant, reseed: usize) -> Self {
        let poly = PaperPoly::new(plant);
        let curve = Curve::new(&poly);
        Self {
            poly,
            curve,
            steps: 32 * (plant.whole_samples() + 2),
            reseed,
        }
    }
}

impl Decomposition for PaperCurve {
    fn scan(&self, f: &mut dyn FnMut(f64, Option<CurvePoint>)) {
        let mut rotor = Rotor::<1, false>::new(self.steps, self.reseed, [self.curve.power()]);
        for j in 0..self.steps {
            let (th, z, [zk]) = rotor.at(j);
            if j == 0 {
                // theta = 0 is not on the curve (sin theta = 0); the rotor starts there
                continue;
            }
            f(th, self.curve.eval_on_circle(z, zk));
        }
    }

    fn eval(&self, theta: f64) -> Option<CurvePoint> {
        self.curve.eval(theta)
    }

    fn eval_end(&self) -> Option<CurvePoint> {
        self.curve.eval_end()
    }

    fn eval_start(&self) -> Option<CurvePoint> {
        // q(1) = alpha M(1) = 0 and q'(1) = (1 - c) + beta M(1) = 0, from the undivided
        // forms Q0 = z^(n+2) (z - 1)(z - c), QA = z M, QB = (z - 1) M (dividing by z keeps
        // both equations: Q0(1) = QB(1) = 0)
        let m1 = self.poly.m(Complex::new(1.0, 0.0)).re;
        let c = self.poly.discretization().c;
        CurvePoint {
            alpha: 0.0,
            beta: -(1.0 - c) / m1,
            dalpha: 0.0,
            dbeta: 0.0,
        }
        .finite()
    }

    fn line_minus_one(&self) -> Option<(f64, f64, f64)> {
        self.poly.line_minus_one()
    }

    fn alpha_plus_one(&self) -> Option<f64> {
        // Q0(1) = 0 exactly: the paper's device has a free integrator
        Some(0.0)
    }

    fn free_integrator(&self) -> bool {
        true
    }

    fn self_intersections(&self) -> bool {
        false
    }

    fn degree(&self) -> usize {
        self.poly.degree()
    }

    fn coefficients_into<'a>(&self, wall: &Wall, buf: &'a mut [f64]) -> &'a [f64] {
        self.poly.coefficients_into(wall, buf)
    }

    fn affine(&self) -> [Cow<'_, [f64]>; 3] {
        let len = self.poly.degree() + 1;
        [
            Cow::Owned((0..len).map(|i| self.poly.q0(i)).collect()),
            Cow::Owned((0..len).map(|i| self.poly.qa(i)).collect()),
            Cow::Owned((0..len).map(|i| self.poly.qb(i)).collect()),
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::Plant;

    /// The rotated `z` and `z^(n+2)` stay within the documented drift of the library's
    /// `sin_cos` of the same grid angle, over whole scans at short and long delays.
    #[test]
    fn rotor_drift_is_below_the_bound() {
        for (delta, d) in [(0.0, 0.0), (1.0, 1.0), (10.0, 4.0), (250.0, 0.5)] {
            let poly = PaperPoly::new(&Plant::new(delta, d).unwrap());
            let curve = Curve::new(&poly);
            let steps = 32 * poly.circle_power();
            let mut rotor = Rotor::<1, false>::new(steps, ROTOR_RESEED, [curve.power()]);
            let mut worst: f64 = 0.0;
            for j in 0..steps {
                let (theta, z, [zk]) = rotor.at(j);
                let (s, c) = theta.sin_cos();
                let k = curve.power();
                let (sk, ck) = (k * theta).sin_cos();
                worst = worst
                    .max((z - Complex::new(c, s)).norm())
                    .max((zk - Complex::new(ck, sk)).norm());
            }
            // 15 steps of at most 4 u each, plus the sin_cos of the rounded (n + 2) theta
            // that the comparison itself carries (about (n + 2) u).
            let bound = (60.0 + curve.power()) * f64::EPSILON / 2.0;
            assert!(worst <= bound, "({delta}, {d}): {worst:e} > {bound:e}");
        }
    }
}
