//! The D-decomposition curve of walls with a root `e^{i theta}` on the unit circle, with its
//! exact derivative along `theta` (`docs/MODEL.md` section 4), as the `alpha_max` search
//! needs it.

use std::f64::consts::PI;

use crate::poly::{CharPoly, Complex};

/// A point of the D-decomposition curve with the derivatives along `theta`.
#[derive(Debug, Clone, Copy)]
pub(super) struct CurvePoint {
    pub(super) alpha: f64,
    pub(super) beta: f64,
    pub(super) dalpha: f64,
    /// Checked against finite differences in the tests (with `dalpha`, same formula).
    #[cfg_attr(not(test), allow(dead_code))]
    pub(super) dbeta: f64,
}

/// The curve of walls with a root `e^{i theta}` and its exact derivative.
pub(super) struct Curve {
    k: f64,
    c: f64,
    m: [f64; 3],
}

impl Curve {
    pub(super) fn new(poly: &CharPoly) -> Self {
        let disc = poly.discretization();
        Self {
            k: (disc.n + 2) as f64,
            c: disc.c,
            m: poly.m_coefficients(),
        }
    }

    /// `alpha z + beta (z - 1) = W(z)`, `W = -z^k (z - 1)(z - c) / M(z)` on `z = e^{i theta}`
    /// (as [`CharPoly::wall_on_circle`]), with `dW/dtheta = i z W (k/z + 1/(z-1) + 1/(z-c) -
    /// M'/M)`.
    pub(super) fn eval(&self, theta: f64) -> Option<CurvePoint> {
        let (s, co) = theta.sin_cos();
        if s <= 0.0 {
            return None;
        }
        self.eval_at(theta, Complex::new(co, s))
    }

    /// The end of the curve at `theta = pi` (`z = -1`, a double root there). `Im W` and
    /// `sin theta` both vanish; by l'Hopital `Im W / sin theta -> -d(Im W)/d theta`. The curve
    /// is symmetric about `theta = pi`, so `d alpha / d theta = 0` there.
    pub(super) fn eval_end(&self) -> Option<CurvePoint> {
        self.eval_at(PI, Complex::new(-1.0, 0.0))
    }

    /// [`Curve::eval`] below `pi`, [`Curve::eval_end`] from `pi` on (a root finder may probe
    /// the end point itself).
    pub(super) fn eval_or_end(&self, theta: f64) -> Option<CurvePoint> {
        if theta >= PI {
            self.eval_end()
        } else {
            self.eval(theta)
        }
    }

    fn eval_at(&self, theta: f64, z: Complex) -> Option<CurvePoint> {
        let (s, co) = (z.im, z.re);
        let [m0, m1, m2] = self.m;
        let mz = (z * m2 + m1) * z + m0;
        let dm = z * (2.0 * m2) + m1;
        // As in CharPoly::wall_on_circle: a modulus of M this small is a zero of M.
        let norm = mz.norm();
        if norm.is_nan() || norm <= 1e-300 {
            return None;
        }
        let zk = Complex::from_polar(1.0, self.k * theta);
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
        let p = CurvePoint {
            alpha,
            beta,
            dalpha,
            dbeta,
        };
        if alpha.is_finite() && beta.is_finite() && dalpha.is_finite() && dbeta.is_finite() {
            Some(p)
        } else {
            None
        }
    }
}
