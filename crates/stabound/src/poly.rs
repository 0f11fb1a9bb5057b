//! The characteristic polynomial of a loop in its affine form `q = Q0 + alpha QA + beta QB`
//! ([`CharPoly`]), for the paper's loop and for a loop with elements alike.
//!
//! For the paper's loop the form is closed (`docs/MODEL.md` section 3), the fast path that
//! [`CharPoly`] takes inside:
//!
//! ```text
//! q(z) = z^(n+2) (z - 1)(z - c) + ((alpha + beta) z - beta) (N0(z) z + N1(z))
//!      = Q0(z) + alpha QA(z) + beta QB(z)
//! ```
//!
//! with `N0 z + N1 = M(z) = m2 z^2 + m1 z + m0`, so `QA = z M` and `QB = (z - 1) M`. For an
//! integer delay `m0 = 0` and the common factor `z` is divided out. A loop with elements
//! takes the general route of section 8 (its device's discretization, La Budde's
//! characteristic polynomial and the adjugate's Markov parameters).
//!
//! Coefficients are stored lowest power first.

use std::f64::consts::PI;

use crate::curve::{Decomposition, LoopCurve};
use crate::elements::{GeneralPoly, Loop};
use crate::error::Result;
use crate::model::{Discretization, PaperDiscretization};
use crate::params::{Plant, Wall};

pub use crate::params::MAX_COEFFS;

/// A complex number as `(re, im)`; small and `Copy`, enough for evaluation on the circle.
pub type Complex = nalgebra::Complex<f64>;

/// The closed-form characteristic polynomial of the paper's loop on one plant, affine in
/// the wall parameters: the fast path inside [`CharPoly`].
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct PaperPoly {
    plant: Plant,
    disc: PaperDiscretization,
    /// `M(z)` coefficients `[m0, m1, m2]`.
    m: [f64; 3],
    /// `QA` and `QB` coefficients up to `z^3` (higher ones are zero).
    qa: [f64; 4],
    qb: [f64; 4],
    /// Index of the lowest nonzero coefficient of `Q0` (`c z^low - (1+c) z^(low+1) + z^(low+2)`).
    q0_low: usize,
    degree: usize,
}

impl PaperPoly {
    /// The characteristic polynomial of `plant` (inline: built in place inside [`CharPoly`]).
    #[inline]
    pub(crate) fn new(plant: &Plant) -> Self {
        let disc = PaperDiscretization::new(plant);
        let PaperDiscretization {
            c,
            p1,
            g0x,
            g0v,
            g1x,
            g1v,
            n,
            fractional,
        } = disc;
        // N0 z + N1 = ((z - c) g0x + p1 g0v) z + (z - c) g1x + p1 g1v
        let m2 = g0x;
        let m1 = p1 * g0v - c * g0x + g1x;
        let m0 = p1 * g1v - c * g1x;
        let (qa, qb, q0_low) = if fractional {
            // QA = z M, QB = (z - 1) M, Q0 = z^(n+2) (z - 1)(z - c).
            ([0.0, m0, m1, m2], [-m0, m0 - m1, m1 - m2, m2], n + 2)
        } else {
            // eps = 0 makes g1x = g1v = 0, so m0 = 0 and every term has the factor z.
            // Divided by z: QA = m2 z^2 + m1 z, QB = (z - 1)(m2 z + m1), Q0 = z^(n+1) (z-1)(z-c).
            ([0.0, m1, m2, 0.0], [-m1, m1 - m2, m2, 0.0], n + 1)
        };
        Self {
            plant: *plant,
            disc,
            m: [m0, m1, m2],
            qa,
            qb,
            q0_low,
            degree: plant.degree(),
        }
    }

    /// The plant this polynomial belongs to.
    pub(crate) fn plant(&self) -> &Plant {
        &self.plant
    }

    /// The discretization the coefficients were built from.
    pub(crate) fn discretization(&self) -> &PaperDiscretization {
        &self.disc
    }

    /// Degree of `q`: `n + 3` for integer delay, `n + 4` otherwise.
    pub(crate) fn degree(&self) -> usize {
        self.degree
    }

    /// Coefficient `i` of `Q0`.
    pub(crate) fn q0(&self, i: usize) -> f64 {
        let c = self.disc.c;
        match i.checked_sub(self.q0_low) {
            Some(0) => c,
            Some(1) => -(1.0 + c),
            Some(2) => 1.0,
            _ => 0.0,
        }
    }

    /// Coefficient `i` of `QA` (the part multiplying `alpha`).
    pub(crate) fn qa(&self, i: usize) -> f64 {
        self.qa.get(i).copied().unwrap_or(0.0)
    }

    /// Coefficient `i` of `QB` (the part multiplying `beta`).
    pub(crate) fn qb(&self, i: usize) -> f64 {
        self.qb.get(i).copied().unwrap_or(0.0)
    }

    /// Writes the `degree + 1` coefficients of `q` for `wall` into `out`, lowest power first,
    /// and returns that slice. `out` must hold at least `degree + 1` values.
    ///
    /// # Panics
    ///
    /// If `out` is shorter than `degree + 1` (a caller bug, not user input).
    pub(crate) fn coefficients_into<'a>(&self, wall: &Wall, out: &'a mut [f64]) -> &'a [f64] {
        let len = self.degree + 1;
        let out = &mut out[..len];
        out.fill(0.0);
        let low = self.q0_low;
        let c = self.disc.c;
        out[low] = c;
        out[low + 1] = -(1.0 + c);
        out[low + 2] = 1.0;
        for ((o, a), b) in out.iter_mut().zip(&self.qa).zip(&self.qb) {
            *o += wall.alpha() * a + wall.beta() * b;
        }
        out
    }

    /// The affine form of `q(radius z)`, whose roots are those of `q` divided by `radius`:
    /// a stability test against the circle of that radius needs no per-call rescaling.
    ///
    /// `radius` must be positive and finite (the stability margin keeps it in `(0.5, 1.5)`,
    /// where `radius^504` stays far inside the range of `f64`).
    pub(crate) fn scaled(&self, radius: f64) -> ScaledPoly {
        let low = self.q0_low;
        let len = self.degree + 1;
        let pow = |i: usize| radius.powi(i as i32);
        let mut qa = [0.0; 4];
        let mut qb = [0.0; 4];
        for i in 0..4.min(len) {
            qa[i] = self.qa[i] * pow(i);
            qb[i] = self.qb[i] * pow(i);
        }
        let q0 = [0.0, 1.0, 2.0].map(|k| self.q0(low + k as usize) * pow(low + k as usize));
        ScaledPoly {
            qa,
            qb,
            q0,
            q0_low: low,
            len,
        }
    }

    /// The coefficients of `q` for `wall` as a new vector, lowest power first.
    pub(crate) fn coefficients(&self, wall: &Wall) -> Vec<f64> {
        let mut v = vec![0.0; self.degree + 1];
        self.coefficients_into(wall, &mut v);
        v
    }

    /// `M(z) = m2 z^2 + m1 z + m0`, the factor shared by `QA = z M` and `QB = (z - 1) M`
    /// (before any division by `z`).
    pub(crate) fn m(&self, z: Complex) -> Complex {
        let [m0, m1, m2] = self.m;
        (z * m2 + m1) * z + m0
    }

    /// The coefficients `[m0, m1, m2]` of `M(z)`, for code that also needs its derivative.
    pub(crate) fn m_coefficients(&self) -> [f64; 3] {
        self.m
    }

    /// The wall for which `z = e^{i theta}` is a root of `q`, for `0 < theta < pi`
    /// (D-decomposition, docs/MODEL.md section 4).
    ///
    /// `alpha z + beta (z - 1) = W` with `W = -z^(n+2) (z - 1)(z - c) / M(z)`; its imaginary
    /// part gives `alpha + beta = Im W / sin theta` and its real part then gives `beta`.
    /// Returns `None` where `M(e^{i theta})` vanishes or `theta` is not in `(0, pi)`.
    pub(crate) fn wall_on_circle(&self, theta: f64) -> Option<Wall> {
        if !(theta > 0.0 && theta < PI) {
            return None;
        }
        let (s, co) = theta.sin_cos();
        let k = (self.disc.n + 2) as f64;
        self.wall_on_circle_at(Complex::new(co, s), Complex::from_polar(1.0, k * theta))
    }

    /// [`PaperPoly::wall_on_circle`] from `z = e^{i theta}` and `zk = z^(n+2)` given directly
    /// (for callers that get them without trigonometric functions, by bisecting angles).
    ///
    /// Both must have modulus 1 to rounding, with `Im z > 0`; returns `None` otherwise
    /// (`Im z <= 0`) or where `M(z)` vanishes.
    pub(crate) fn wall_on_circle_at(&self, z: Complex, zk: Complex) -> Option<Wall> {
        let (co, s) = (z.re, z.im);
        if s.is_nan() || s <= 0.0 {
            return None;
        }
        let mz = self.m(z);
        if vanishes(mz) {
            return None;
        }
        let w = -zk * (z - 1.0) * (z - self.disc.c) / mz;
        let sum = w.im / s;
        let beta = sum * co - w.re;
        let alpha = sum - beta;
        if alpha.is_finite() && beta.is_finite() {
            Some(Wall { alpha, beta })
        } else {
            None
        }
    }

    /// `n + 2`, the power of `z` in [`PaperPoly::wall_on_circle_at`]'s `zk`.
    pub(crate) fn circle_power(&self) -> usize {
        self.disc.n + 2
    }

    /// The line of walls with the root `z = -1`: `Q0(-1) + alpha QA(-1) + beta QB(-1) = 0`.
    ///
    /// Returned as `(a, b, r)` with `a alpha + b beta = r`, or `None` where `M(-1) = 0` (for
    /// `delta = 0, d = 0` the loop has the factor `z + 1` in its numerator and `z = -1` is a
    /// root for no wall).
    pub(crate) fn line_minus_one(&self) -> Option<(f64, f64, f64)> {
        // Using the undivided form: Q0 = z^(n+2)(z-1)(z-c), QA = z M, QB = (z-1) M at z = -1.
        let sign = if (self.disc.n + 2).is_multiple_of(2) {
            1.0
        } else {
            -1.0
        };
        let q0 = sign * (-2.0) * (-1.0 - self.disc.c);
        let [m0, m1, m2] = self.m;
        let m = m2 - m1 + m0;
        // M's coefficients are sums of terms of order phi2(1) <= 1/2, so a value at rounding
        // level of that is a zero of M.
        if m.abs() <= 1e-14 * (m2.abs() + m1.abs() + m0.abs()) {
            return None;
        }
        Some((-m, -2.0 * m, -q0))
    }
}

/// The characteristic polynomial of a [`Loop`], affine in the wall parameters:
/// `q = Q0 + alpha QA + beta QB`, lowest power first.
///
/// Build it once per loop and evaluate it for as many walls as needed:
/// [`CharPoly::coefficients_into`] writes `q` for one wall without allocating. For the
/// paper's loop ([`Loop::is_paper`]; a [`Plant`] is one) it runs on the closed forms of
/// `docs/MODEL.md` section 3, for a loop with elements on the general route of section 8;
/// the choice is made inside.
///
/// ```
/// use stabound::elements::{Actuator, Loop};
/// use stabound::params::{Plant, Wall};
/// use stabound::poly::{CharPoly, MAX_COEFFS};
///
/// let plant = Plant::new(0.5, 1.0)?;
/// let wall = Wall::new(0.1, 0.3)?;
/// let paper = CharPoly::new(&plant)?;
/// let mut buf = [0.0; MAX_COEFFS];
/// let q = paper.coefficients_into(&wall, &mut buf);
/// assert_eq!(q.len(), plant.degree() + 1);
/// // monic (exact: the leading coefficient is Q0's literal 1, which QA and QB do not reach),
/// // and q(1) = alpha QA(1): Q0 and QB vanish at z = 1
/// assert_eq!(q[q.len() - 1], 1.0);
/// let at_one: f64 = (0..q.len()).map(|i| paper.qa(i)).sum();
/// assert!((q.iter().sum::<f64>() - 0.1 * at_one).abs() < 1e-15);
/// // an actuator lag adds a state, so a degree
/// let lagged = CharPoly::new(Loop::new(plant).with_actuator(Actuator::new(0.5)?)?)?;
/// assert_eq!(lagged.degree(), paper.degree() + 1);
/// # Ok::<(), stabound::Error>(())
/// ```
#[derive(Debug, Clone)]
pub struct CharPoly {
    disc: Discretization,
    form: Form,
}

/// The closed forms of the paper's loop, or the general polynomial of a loop with elements
/// with its D-decomposition.
#[derive(Debug, Clone)]
enum Form {
    Paper(PaperPoly),
    General(Box<LoopCurve>),
}

impl CharPoly {
    /// The characteristic polynomial of `lp` (a [`Plant`] for the paper's loop).
    ///
    /// # Errors
    ///
    /// As [`Discretization::new`]: only a loop with elements can fail.
    #[inline]
    pub fn new(lp: impl Into<Loop>) -> Result<Self> {
        let lp = lp.into();
        if lp.is_paper() {
            let poly = PaperPoly::new(lp.plant());
            Ok(Self {
                disc: (*poly.discretization()).into(),
                form: Form::Paper(poly),
            })
        } else {
            let poly = GeneralPoly::new(&lp)?;
            Ok(Self {
                disc: poly.discretization().clone().into(),
                form: Form::General(Box::new(LoopCurve::from_poly(poly))),
            })
        }
    }

    /// The loop's plant: its physical damping and delay.
    pub fn plant(&self) -> &Plant {
        match &self.form {
            Form::Paper(p) => p.plant(),
            Form::General(c) => c.plant(),
        }
    }

    /// The discretization the coefficients were built from.
    pub fn discretization(&self) -> &Discretization {
        &self.disc
    }

    /// Degree of `q`, equal to the closed loop's state dimension ([`Loop::degree`]).
    pub fn degree(&self) -> usize {
        match &self.form {
            Form::Paper(p) => p.degree(),
            Form::General(c) => c.poly().degree(),
        }
    }

    /// Coefficient `i` of `Q0` (zero above the degree).
    pub fn q0(&self, i: usize) -> f64 {
        match &self.form {
            Form::Paper(p) => p.q0(i),
            Form::General(c) => coefficient(c.poly().q0(), i),
        }
    }

    /// Coefficient `i` of `QA`, the part multiplying `alpha` (zero above the degree).
    pub fn qa(&self, i: usize) -> f64 {
        match &self.form {
            Form::Paper(p) => p.qa(i),
            Form::General(c) => coefficient(c.poly().qa(), i),
        }
    }

    /// Coefficient `i` of `QB`, the part multiplying `beta` (zero above the degree).
    pub fn qb(&self, i: usize) -> f64 {
        match &self.form {
            Form::Paper(p) => p.qb(i),
            Form::General(c) => coefficient(c.poly().qb(), i),
        }
    }

    /// Writes the `degree + 1` coefficients of `q` for `wall` into `out`, lowest power first,
    /// and returns that slice. `out` must hold at least `degree + 1` values ([`MAX_COEFFS`]
    /// always do).
    ///
    /// # Panics
    ///
    /// If `out` is shorter than `degree + 1` (a caller bug, not user input).
    #[inline]
    pub fn coefficients_into<'a>(&self, wall: &Wall, out: &'a mut [f64]) -> &'a [f64] {
        match &self.form {
            Form::Paper(p) => p.coefficients_into(wall, out),
            Form::General(c) => c.poly().coefficients_into(wall, out),
        }
    }

    /// The coefficients of `q` for `wall` as a new vector, lowest power first.
    pub fn coefficients(&self, wall: &Wall) -> Vec<f64> {
        match &self.form {
            Form::Paper(p) => p.coefficients(wall),
            Form::General(c) => c.poly().coefficients(wall),
        }
    }

    /// The wall for which `z = e^{i theta}` is a root of `q`, for `0 < theta < pi`
    /// (D-decomposition, docs/MODEL.md sections 4 and 8): `alpha QA(z) + beta QB(z) = -Q0(z)`
    /// is two real linear equations. Returns `None` where they do not fix one finite wall
    /// (for the paper's loop: where `M(e^{i theta})` vanishes) or `theta` is not in `(0, pi)`.
    pub fn wall_on_circle(&self, theta: f64) -> Option<Wall> {
        match &self.form {
            Form::Paper(p) => p.wall_on_circle(theta),
            Form::General(c) => {
                if !(theta > 0.0 && theta < PI) {
                    return None;
                }
                let k = c.circle_power() as f64;
                c.wall_at(
                    Complex::from_polar(1.0, theta),
                    Complex::from_polar(1.0, k * theta),
                )
            }
        }
    }

    /// [`CharPoly::wall_on_circle`] from `z = e^{i theta}` and `zk = z^k`,
    /// `k = `[`CharPoly::circle_power`], given directly (for callers that get them without
    /// trigonometric functions, by rotating or bisecting angles).
    ///
    /// Both must have modulus 1 to rounding, with `Im z > 0`; returns `None` otherwise
    /// (`Im z <= 0`) or where the equations do not fix one finite wall.
    pub fn wall_on_circle_at(&self, z: Complex, zk: Complex) -> Option<Wall> {
        match &self.form {
            Form::Paper(p) => p.wall_on_circle_at(z, zk),
            Form::General(c) => {
                if z.im.is_nan() || z.im <= 0.0 {
                    return None;
                }
                c.wall_at(z, zk)
            }
        }
    }

    /// The power `k` of `z` that [`CharPoly::wall_on_circle_at`] takes precomputed as `zk`
    /// (the delay's: `n + 2` for the paper's loop).
    pub fn circle_power(&self) -> usize {
        match &self.form {
            Form::Paper(p) => p.circle_power(),
            Form::General(c) => c.circle_power(),
        }
    }

    /// The line of walls with the root `z = -1`: `Q0(-1) + alpha QA(-1) + beta QB(-1) = 0`.
    ///
    /// Returned as `(a, b, r)` with `a alpha + b beta = r`, or `None` where `z = -1` is a
    /// root for no wall (for `delta = 0, d = 0` the paper's loop has the factor `z + 1` in
    /// its numerator).
    pub fn line_minus_one(&self) -> Option<(f64, f64, f64)> {
        match &self.form {
            Form::Paper(p) => p.line_minus_one(),
            Form::General(c) => c.line_minus_one(),
        }
    }
}

/// Coefficient `i` of a polynomial stored lowest power first, zero above its degree.
fn coefficient(p: &[f64], i: usize) -> f64 {
    p.get(i).copied().unwrap_or(0.0)
}

/// Whether a value `M(z)` of the loop's quadratic `M` is a zero of `M` to working precision
/// (or NaN). `M` has coefficients of order `phi2(1) ~ 1/2` or larger; a modulus below `1e-300`
/// is far below their rounding. The larger component bounds the modulus within a factor
/// `sqrt 2`, which is all this test needs (and avoids `hypot`).
pub(crate) fn vanishes(mz: Complex) -> bool {
    let size = mz.re.abs().max(mz.im.abs());
    size.is_nan() || size <= 1e-300
}

/// The affine form of `q(r z)` for a fixed radius `r`, built by [`PaperPoly::scaled`].
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct ScaledPoly {
    qa: [f64; 4],
    qb: [f64; 4],
    q0: [f64; 3],
    q0_low: usize,
    len: usize,
}

impl ScaledPoly {
    /// Writes the coefficients of `q(r z)` for `wall` into `out[..len]`, lowest power first.
    ///
    /// # Panics
    ///
    /// If `out` is shorter than the degree plus one (a caller bug, not user input).
    pub fn coefficients_into<'a>(&self, wall: &Wall, out: &'a mut [f64]) -> &'a mut [f64] {
        let out = &mut out[..self.len];
        out.fill(0.0);
        for ((o, a), b) in out.iter_mut().zip(&self.qa).zip(&self.qb) {
            *o = wall.alpha() * a + wall.beta() * b;
        }
        for (o, z) in out[self.q0_low..].iter_mut().zip(&self.q0) {
            *o += z;
        }
        out
    }
}

/// `q / (z - root)` by synthetic division from the top (coefficients lowest power first),
/// remainder dropped; `out` holds at least `q.len() - 1` numbers.
pub(crate) fn deflate_linear<'a>(q: &[f64], root: f64, out: &'a mut [f64]) -> &'a [f64] {
    let m = q.len() - 1;
    let s = &mut out[..m];
    let mut acc = 0.0;
    for j in (0..m).rev() {
        acc = q[j + 1] + root * acc;
        s[j] = acc;
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    /// Paper eq. (17) for integer d, lowest power first, built independently of `PaperPoly`.
    /// `1 - c` is taken as `-expm1(-delta)`, the one rewrite that keeps the oracle meaningful
    /// at delta = 1e-3 (with a naive `1 - exp(-delta)` the oracle itself is off by 1e-10).
    fn eq17(alpha: f64, beta: f64, delta: f64, d: usize) -> Vec<f64> {
        let one_minus_c = -(-delta).exp_m1();
        let c = 1.0 - one_minus_c;
        let mut p = vec![0.0; d + 4];
        p[2] += (one_minus_c - delta) * (alpha + beta);
        p[1] += (c * delta - one_minus_c) * alpha + ((1.0 + c) * delta - 2.0 * one_minus_c) * beta;
        p[0] += (one_minus_c - c * delta) * beta;
        // - delta^2 (z - c)(z - 1) z^(1+d) = -delta^2 (z^2 - (1+c) z + c) z^(1+d)
        p[d + 3] -= delta * delta;
        p[d + 2] += delta * delta * (1.0 + c);
        p[d + 1] -= delta * delta * c;
        p
    }

    /// `-delta^2 q = p` of eq. (17), coefficient by coefficient, to 1e-12 relative to the
    /// largest coefficient (individual coefficients of eq. (17) are differences of nearly
    /// equal terms, so relative to themselves they carry the oracle's own rounding).
    #[test]
    fn scaled_poly_is_q_of_r_z() {
        // q(r z) has the coefficients q_i r^i: compare with the unscaled polynomial.
        for (delta, d) in [(0.5, 1.0), (0.0, 0.0), (2.0, 3.4), (1e-3, 40.0)] {
            let poly = PaperPoly::new(&Plant::new(delta, d).unwrap());
            let wall = Wall::new(0.3, 0.2).unwrap();
            let q = poly.coefficients(&wall);
            for r in [0.9, 1.0 - 1e-9, 1.1] {
                let scaled = poly.scaled(r);
                let mut out = vec![f64::NAN; scaled.len];
                let s = scaled.coefficients_into(&wall, &mut out);
                assert_eq!(s.len(), q.len());
                let big = q.iter().fold(0.0f64, |m, c| m.max(c.abs()));
                for (i, (si, qi)) in s.iter().zip(&q).enumerate() {
                    // a few roundings of the largest coefficient times r^i
                    let want = qi * r.powi(i as i32);
                    assert!((si - want).abs() <= 1e-14 * big * r.powi(i as i32).max(1.0));
                }
            }
        }
    }

    #[test]
    fn matches_paper_eq17() {
        for &delta in &[1e-3, 0.01, 0.1, 0.5, 1.0, 3.0, 10.0, 50.0] {
            for d in 0..8usize {
                let plant = Plant::new(delta, d as f64).unwrap();
                let cp = PaperPoly::new(&plant);
                for &(alpha, beta) in &[(0.3, 0.1), (1.0, -0.2), (0.0, 2.0), (40.0, 3.0)] {
                    let q = cp.coefficients(&Wall { alpha, beta });
                    let p = eq17(alpha, beta, delta, d);
                    assert_eq!(q.len(), p.len());
                    let scale = p.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                    for (i, (&qi, &pi)) in q.iter().zip(&p).enumerate() {
                        let lhs = -delta * delta * qi;
                        assert!(
                            (lhs - pi).abs() <= 1e-12 * scale,
                            "delta {delta} d {d} coef {i}: {lhs} vs {pi}"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn structure_at_one() {
        // Q0(1) = QB(1) = 0, so q(1) = alpha QA(1).
        let cp = PaperPoly::new(&Plant::new(0.4, 1.3).unwrap());
        let q = cp.coefficients(&Wall {
            alpha: 0.0,
            beta: 0.7,
        });
        let at_one: f64 = q.iter().sum();
        assert!(at_one.abs() < 1e-14, "{at_one}");
    }

    #[test]
    fn wall_on_circle_has_that_root() {
        for &(delta, d) in &[(0.0, 0.0), (0.5, 1.0), (1.0, 2.5), (3.0, 0.25)] {
            let cp = PaperPoly::new(&Plant::new(delta, d).unwrap());
            for &theta in &[0.1, 0.7, 1.5, 2.9] {
                let wall = cp.wall_on_circle(theta).unwrap();
                let q = cp.coefficients(&wall);
                let z = Complex::from_polar(1.0, theta);
                let mut acc = Complex::new(0.0, 0.0);
                for &c in q.iter().rev() {
                    acc = acc * z + c;
                }
                let scale: f64 = q.iter().map(|c| c.abs()).sum();
                assert!(acc.norm() < 1e-12 * scale, "{delta} {d} {theta}: {acc}");
            }
        }
    }

    #[test]
    fn line_minus_one_is_a_root() {
        let cp = PaperPoly::new(&Plant::new(0.0, 0.0).unwrap());
        assert!(cp.line_minus_one().is_none());
        for &(delta, d) in &[(0.2, 1.0), (3.0, 0.0), (0.5, 1.0), (1.0, 2.5)] {
            let cp = PaperPoly::new(&Plant::new(delta, d).unwrap());
            let (a, b, r) = cp.line_minus_one().unwrap();
            // pick beta = 0.3, solve for alpha
            let beta = 0.3;
            let alpha = (r - b * beta) / a;
            let q = cp.coefficients(&Wall { alpha, beta });
            let val: f64 = q
                .iter()
                .enumerate()
                .map(|(i, c)| if i % 2 == 0 { *c } else { -*c })
                .sum();
            assert!(val.abs() < 1e-12, "{delta} {d}: {val}");
        }
        // d = 0: slope of the line in the (alpha, beta) plane is -1/2 (docs/MODEL.md section 4)
        let cp = PaperPoly::new(&Plant::new(3.0, 0.0).unwrap());
        let (a, b, _) = cp.line_minus_one().unwrap();
        assert_relative_eq!(-a / b, -0.5, max_relative = 1e-14);
    }
}
