//! The sampled loop: exact discretization of the damped mass under a zero-order hold with
//! fractional delay (`docs/MODEL.md` section 2), and the closed loop's state-space matrix.
//!
//! Time is normalized by `T`, velocity by `1/T` and force by `m/T^2`. Over a normalized time
//! `tau` with constant force `f`, the damped mass `v' = f - delta v` gives exactly
//!
//! ```text
//! v(tau) = c(tau) v0 + phi1(tau) f
//! x(tau) = x0 + phi1(tau) v0 + phi2(tau) f
//! ```

use nalgebra::{DMatrix, DVector};

use crate::elements::{GeneralDiscretization, Loop};
use crate::error::Result;
use crate::params::{Plant, Wall};

/// `c(tau) = exp(-delta tau)`: how much velocity survives `tau` periods.
pub(crate) fn decay(delta: f64, tau: f64) -> f64 {
    (-delta * tau).exp()
}

/// `phi1(tau) = (1 - exp(-delta tau)) / delta`, and `tau` at `delta = 0`.
///
/// Computed as `tau * g(x)` with `x = delta tau` and `g(x) = -expm1(-x) / x`, so there is no
/// cancellation for small `delta`; below `x = 1e-8` the two-term series `1 - x/2` is exact to
/// `f64` (the next term is `x^2/6 < 2e-17`) and avoids `x` being subnormal.
pub(crate) fn phi1(delta: f64, tau: f64) -> f64 {
    let x = delta * tau;
    if x < 1e-8 {
        tau * (1.0 - 0.5 * x)
    } else {
        -(-x).exp_m1() / delta
    }
}

/// `phi2(tau) = (tau - phi1(tau)) / delta`, and `tau^2 / 2` at `delta = 0`.
///
/// Written as `tau^2 h(x)` with `h(x) = (x - 1 + exp(-x)) / x^2 = sum_k (-x)^k / (k+2)!`.
/// For `x <= 1` the series is summed (24 terms: the tail is below `1/26! < 1e-26`), because
/// `x + expm1(-x)` cancels there; above 1 the closed form loses less than two bits.
pub(crate) fn phi2(delta: f64, tau: f64) -> f64 {
    let x = delta * tau;
    if x <= 1.0 {
        // term_k = (-x)^k / (k+2)!, each from the previous by the factor -x / (k+3).
        let mut term = 0.5;
        let mut sum = 0.5;
        for k in 0..23 {
            term *= -x / (k as f64 + 3.0);
            sum += term;
        }
        tau * tau * sum
    } else {
        tau * tau * (x + (-x).exp_m1()) / (x * x)
    }
}

/// The one-period update of the damped mass with the delayed, held force.
///
/// With `d = n + eps`, the force `f_{k-n-1}` acts for the first `eps` of the period and
/// `f_{k-n}` for the remaining `1 - eps`:
///
/// ```text
/// x_{k+1} = x_k + p1 v_k + g0x f_{k-n} + g1x f_{k-n-1}
/// v_{k+1} = c v_k        + g0v f_{k-n} + g1v f_{k-n-1}
/// ```
///
/// The closed form of the paper's loop: the fast path inside [`Discretization`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct PaperDiscretization {
    /// `c = c(1) = exp(-delta)`.
    pub c: f64,
    /// `phi1(1)`: position gained per unit velocity over one period.
    pub p1: f64,
    /// Position gain of `f_{k-n}`: `phi2(1 - eps)`.
    pub g0x: f64,
    /// Velocity gain of `f_{k-n}`: `phi1(1 - eps)`.
    pub g0v: f64,
    /// Position gain of `f_{k-n-1}`: `phi2(eps) + phi1(1 - eps) phi1(eps)`.
    pub g1x: f64,
    /// Velocity gain of `f_{k-n-1}`: `c(1 - eps) phi1(eps)`.
    pub g1v: f64,
    /// Whole samples of delay `n`.
    pub n: usize,
    /// Whether the delay is fractional (`eps > 0`), which adds one state.
    pub fractional: bool,
}

impl PaperDiscretization {
    /// The exact discretization of `plant` (docs/MODEL.md section 2).
    pub(crate) fn new(plant: &Plant) -> Self {
        let delta = plant.delta();
        let eps = plant.fraction();
        let rest = 1.0 - eps;
        Self {
            c: decay(delta, 1.0),
            p1: phi1(delta, 1.0),
            g0x: phi2(delta, rest),
            g0v: phi1(delta, rest),
            g1x: phi2(delta, eps) + phi1(delta, rest) * phi1(delta, eps),
            g1v: decay(delta, rest) * phi1(delta, eps),
            n: plant.whole_samples(),
            fractional: !plant.is_integer_delay(),
        }
    }

    /// Dimension of the closed loop's state: `n + 3`, plus one for a fractional delay.
    pub fn state_dim(&self) -> usize {
        self.n + 3 + usize::from(self.fractional)
    }

    /// The closed-loop state matrix `A` with `s_{k+1} = A s_k`.
    ///
    /// The state is `[x_k, v_k, x_{k-1}, f_{k-1}, ..., f_{k-h}]` with `h = n` force samples of
    /// history (`n + 1` for a fractional delay) and `f_k = -(alpha + beta) x_k + beta x_{k-1}`.
    /// Its eigenvalues are the roots of the characteristic polynomial, reached without
    /// expanding it: the independent route for tests and the well-conditioned route for long
    /// delays.
    pub fn state_matrix(&self, wall: &Wall) -> DMatrix<f64> {
        let dim = self.state_dim();
        let hist = dim - 3;
        let mut a = DMatrix::<f64>::zeros(dim, dim);
        // The row vector that produces f_k from the state.
        let mut f_now = vec![0.0; dim];
        f_now[0] = -(wall.alpha() + wall.beta());
        f_now[2] = wall.beta();
        let unit = |i: usize| {
            let mut r = vec![0.0; dim];
            r[i] = 1.0;
            r
        };
        // f_{k-j} for j >= 1 sits at index 2 + j.
        let force = |j: usize| if j == 0 { f_now.clone() } else { unit(2 + j) };
        let f0 = force(self.n);
        let f1 = if self.fractional {
            force(self.n + 1)
        } else {
            vec![0.0; dim]
        };
        for col in 0..dim {
            a[(0, col)] = self.g0x * f0[col] + self.g1x * f1[col];
            a[(1, col)] = self.g0v * f0[col] + self.g1v * f1[col];
        }
        a[(0, 0)] += 1.0;
        a[(0, 1)] += self.p1;
        a[(1, 1)] += self.c;
        a[(2, 0)] = 1.0;
        if hist > 0 {
            for col in 0..dim {
                a[(3, col)] = f_now[col];
            }
            for j in 1..hist {
                a[(3 + j, 2 + j)] = 1.0;
            }
        }
        a
    }
}

/// The exact discretization of a [`Loop`]'s device and the closed loop's state matrix.
///
/// The device `x' = A x + b u`, `y = c^T x` sampled with the delay `d = n + eps`:
///
/// ```text
/// x_{k+1} = Phi x_k + G0 u_{k-n} + G1 u_{k-n-1}
/// ```
///
/// For the paper's loop ([`Loop::is_paper`]: a damped mass, state `(x, v)`) the entries are
/// the closed forms of `docs/MODEL.md` section 2; for a loop with elements they come from the
/// augmented matrix exponential (section 8). The choice is made inside: build it from any
/// loop (a [`Plant`] is the paper's loop).
///
/// ```
/// use stabound::elements::{Hand, Loop};
/// use stabound::model::Discretization;
/// use stabound::params::{Plant, Wall};
///
/// let plant = Plant::new(0.5, 1.0)?;
/// let paper = Discretization::new(&plant)?;
/// // a damped mass: Phi = [[1, phi1(1)], [0, exp(-delta)]] (exact: the same exponential)
/// assert_eq!(paper.phi()[(1, 1)], (-0.5f64).exp());
/// assert_eq!(paper.state_matrix(&Wall::new(0.1, 0.3)?).nrows(), paper.state_dim());
/// // a hand adds nothing to the state of the device it holds
/// let held = Discretization::new(Loop::new(plant).with_hand(Hand::new(0.5, 0.1, 0.0)?)?)?;
/// assert_eq!(held.phi().nrows(), 2);
/// # Ok::<(), stabound::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Discretization(Sampled);

/// The closed forms of the paper's loop, or the exponential of a loop with elements.
#[derive(Debug, Clone, PartialEq)]
enum Sampled {
    Paper(PaperDiscretization),
    General(Box<GeneralDiscretization>),
}

impl From<PaperDiscretization> for Discretization {
    fn from(d: PaperDiscretization) -> Self {
        Self(Sampled::Paper(d))
    }
}

impl From<GeneralDiscretization> for Discretization {
    fn from(d: GeneralDiscretization) -> Self {
        Self(Sampled::General(Box::new(d)))
    }
}

impl Discretization {
    /// The exact discretization of `lp`'s device (a [`Plant`] for the paper's loop).
    ///
    /// # Errors
    ///
    /// [`crate::Error::Numerical`] when the matrix exponential of a loop with elements is
    /// not finite (which the limits on the elements are there to exclude); the paper's loop
    /// never fails.
    pub fn new(lp: impl Into<Loop>) -> Result<Self> {
        let lp = lp.into();
        if lp.is_paper() {
            Ok(PaperDiscretization::new(lp.plant()).into())
        } else {
            GeneralDiscretization::new(&lp).map(Into::into)
        }
    }

    /// `Phi`, the device's state over one period without force.
    pub fn phi(&self) -> DMatrix<f64> {
        match &self.0 {
            Sampled::Paper(d) => DMatrix::from_row_slice(2, 2, &[1.0, d.p1, 0.0, d.c]),
            Sampled::General(g) => g.phi().clone(),
        }
    }

    /// `G0`, the gain of the force `u_{k-n}`.
    pub fn g0(&self) -> DVector<f64> {
        match &self.0 {
            Sampled::Paper(d) => DVector::from_column_slice(&[d.g0x, d.g0v]),
            Sampled::General(g) => g.g0().clone(),
        }
    }

    /// `G1`, the gain of the force `u_{k-n-1}` (zero for a whole-sample delay).
    pub fn g1(&self) -> DVector<f64> {
        match &self.0 {
            Sampled::Paper(d) => DVector::from_column_slice(&[d.g1x, d.g1v]),
            Sampled::General(g) => g.g1().clone(),
        }
    }

    /// The output vector `c` of the sensed position `y = c^T x`.
    pub fn output(&self) -> DVector<f64> {
        match &self.0 {
            Sampled::Paper(_) => DVector::from_column_slice(&[1.0, 0.0]),
            Sampled::General(g) => g.output().clone(),
        }
    }

    /// A bound on the error of the sampled device's entries beyond their rounding to double,
    /// relative to the largest entry of the exponential, when it was computed in
    /// double-double (a stiff device, 1-norm of the augmented matrix above `1e3`); `None`
    /// for the closed forms and the double-precision route, whose error the checker's model
    /// covers.
    ///
    /// ```
    /// use stabound::elements::{Encoder, Loop, Transmission};
    /// use stabound::model::Discretization;
    /// use stabound::params::Plant;
    ///
    /// let plant = Plant::new(0.01, 1.0)?;
    /// assert_eq!(Discretization::new(&plant)?.exp_error_bound(), None);
    /// let soft = Loop::new(plant).with_transmission(Transmission::new(0.3, 100.0, 0.0, 0.0, Encoder::Motor)?)?;
    /// assert_eq!(Discretization::new(soft)?.exp_error_bound(), None);
    /// let stiff = Loop::new(plant).with_transmission(Transmission::new(0.3, 5e5, 0.0, 0.0, Encoder::Motor)?)?;
    /// let bound = Discretization::new(stiff)?.exp_error_bound().unwrap();
    /// assert!(bound < f64::EPSILON / 2.0);
    /// # Ok::<(), stabound::Error>(())
    /// ```
    pub fn exp_error_bound(&self) -> Option<f64> {
        match &self.0 {
            Sampled::Paper(_) => None,
            Sampled::General(g) => g.exp_error_bound(),
        }
    }

    /// Dimension of the closed loop's state, equal to [`Loop::degree`].
    pub fn state_dim(&self) -> usize {
        match &self.0 {
            Sampled::Paper(d) => d.state_dim(),
            Sampled::General(g) => g.state_dim(),
        }
    }

    /// The closed-loop state matrix with `s_{k+1} = S s_k`, built from the sampled device and
    /// the wall law directly, not from the characteristic polynomial: its eigenvalues are the
    /// roots of `q`, the independent route for tests and the well-conditioned one for long
    /// delays.
    ///
    /// The state begins with the device's (`x` and `v` for the paper's loop), then the held
    /// forces and the wall's memory: for the paper's loop `[x_k, v_k, x_{k-1}, f_{k-1}, ...,
    /// f_{k-h}]`, for a loop with elements `[x_k, u_{k-1}, ..., u_{k-h}, memory]` (the filter's
    /// states or the previous positions).
    pub fn state_matrix(&self, wall: &Wall) -> DMatrix<f64> {
        match &self.0 {
            Sampled::Paper(d) => d.state_matrix(wall),
            Sampled::General(g) => g.state_matrix(wall),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    /// Reference values by the closed forms, evaluated where they do not cancel.
    #[test]
    fn phi_matches_closed_form_away_from_zero() {
        for &delta in &[0.5f64, 1.0, 3.0, 50.0, 1e4] {
            for &tau in &[0.1, 0.5, 1.0] {
                let e = (-delta * tau).exp();
                let p1 = (1.0 - e) / delta;
                assert_relative_eq!(phi1(delta, tau), p1, max_relative = 1e-14);
                if delta * tau > 2.0 {
                    let p2 = (tau - p1) / delta;
                    assert_relative_eq!(phi2(delta, tau), p2, max_relative = 1e-13);
                }
            }
        }
    }

    /// Series limits: phi1 -> tau, phi2 -> tau^2/2 with first-order corrections
    /// -delta tau^2/2 and -delta tau^3/6 (Taylor expansion of the definitions).
    #[test]
    fn phi_small_delta_limits() {
        for &delta in &[0.0, 1e-300, 1e-12, 1e-6] {
            for &tau in &[0.0, 1e-9, 0.3, 1.0] {
                let p1 = tau - delta * tau * tau / 2.0;
                let p2 = tau * tau / 2.0 - delta * tau * tau * tau / 6.0;
                assert_relative_eq!(phi1(delta, tau), p1, max_relative = 1e-12, epsilon = 0.0);
                assert_relative_eq!(phi2(delta, tau), p2, max_relative = 1e-12, epsilon = 0.0);
            }
        }
    }

    /// Both branches of phi2 meet at x = 1 (continuity of the switch).
    #[test]
    fn phi2_branches_meet() {
        let below = phi2(1.0 - 1e-12, 1.0);
        let above = phi2(1.0 + 1e-12, 1.0);
        // h changes by |h'(1)| < 0.2 per unit x, so 2e-12 apart the true values differ by
        // under 4e-13 relative; the two formulas must agree to that plus rounding.
        assert_relative_eq!(below, above, max_relative = 1e-12);
        // and equal e^-1 at x = 1: h(1) = (1 - 1 + e^-1)/1
        assert_relative_eq!(phi2(1.0, 1.0), (-1.0f64).exp(), max_relative = 1e-15);
    }

    #[test]
    fn integer_delay_has_no_second_force() {
        let plant = Plant::new(0.7, 2.0).unwrap();
        let dz = PaperDiscretization::new(&plant);
        assert_eq!(dz.g1x, 0.0);
        assert_eq!(dz.g1v, 0.0);
        assert_eq!(dz.state_dim(), 5);
    }
}
