//! The device of a [`Loop`] in continuous time and its exact discretization under the
//! zero-order hold with fractional delay (the model document, docs/MODEL.md, section 8).
//!
//! Continuous model, normalized time: `x' = A x + b u`, sensed position `y = c^T x`. With
//! `d = n + eps` the sampled device is
//!
//! ```text
//! x_{k+1} = Phi x_k + G0 u_{k-n} + G1 u_{k-n-1}
//! Phi = e^A,  G0 = Gamma(1 - eps),  G1 = e^{A (1 - eps)} Gamma(eps),
//! Gamma(tau) = integral_0^tau e^{A s} b ds
//! ```
//!
//! Method: the augmented matrix exponential `exp([[A, b], [0, 0]] tau) = [[e^{A tau},
//! Gamma(tau)], [0, 1]]` (Van Loan, "Computing integrals involving the matrix exponential",
//! IEEE Trans. Automatic Control 23(3), 1978), which needs no inverse of `A` (singular for a
//! free mass). The exponential is nalgebra's `Matrix::exp`: Pade approximation of degree up
//! to 13 with scaling and squaring and backward-error-based choice of degree and scaling
//! (Al-Mohy and Higham, SIAM J. Matrix Anal. Appl. 31(3), 2009, as in SciPy's `expm`).

use nalgebra::{DMatrix, DVector};

use super::{Encoder, Loop};
use crate::error::{Error, Result};
use crate::params::Wall;

/// The device of a loop in continuous, normalized time: `x' = A x + b u`, `y = c^T x`.
#[derive(Debug, Clone, PartialEq)]
pub struct Continuous {
    /// The state matrix `A`.
    pub a: DMatrix<f64>,
    /// The input vector `b` (the commanded force).
    pub b: DVector<f64>,
    /// The output vector `c` (the sensed position).
    pub c: DVector<f64>,
}

impl Continuous {
    /// The continuous model of `lp`'s device (the model document, section 8).
    ///
    /// States: `(y, v)` for one mass, `(x1, v1, x2, v2)` for a transmission, then the
    /// actuator's force `f` when a lag is named.
    pub fn new(lp: &Loop) -> Self {
        let delta = lp.plant().delta();
        let (mu, dh, kh) = lp.hand().map_or((0.0, 0.0, 0.0), |h| {
            (h.mass_ratio(), h.damping(), h.stiffness())
        });
        let s = lp.device_order();
        let mut a = DMatrix::<f64>::zeros(s, s);
        let mut b = DVector::<f64>::zeros(s);
        let mut c = DVector::<f64>::zeros(s);
        // `force` is the index of the velocity the force acts on, `scale` 1 over that mass.
        let (force, scale) = match lp.transmission() {
            None => {
                let m = 1.0 + mu;
                a[(0, 1)] = 1.0;
                a[(1, 0)] = -kh / m;
                a[(1, 1)] = -(delta + dh) / m;
                c[0] = 1.0;
                (1, 1.0 / m)
            }
            Some(t) => {
                let (r, kc, dc, d2) = (
                    t.handle_ratio(),
                    t.stiffness(),
                    t.damping(),
                    t.handle_damping(),
                );
                // exact arithmetic is not needed: delta_2 <= delta is checked, so d1 >= 0
                let d1 = (delta - d2).max(0.0);
                let (m1, m2) = (1.0 - r, r + mu);
                a[(0, 1)] = 1.0;
                a[(1, 0)] = -kc / m1;
                a[(1, 1)] = -(d1 + dc) / m1;
                a[(1, 2)] = kc / m1;
                a[(1, 3)] = dc / m1;
                a[(2, 3)] = 1.0;
                a[(3, 0)] = kc / m2;
                a[(3, 1)] = dc / m2;
                a[(3, 2)] = -(kh + kc) / m2;
                a[(3, 3)] = -(d2 + dh + dc) / m2;
                match t.encoder() {
                    Encoder::Motor => c[0] = 1.0,
                    Encoder::Handle => c[2] = 1.0,
                }
                (1, 1.0 / m1)
            }
        };
        match lp.actuator() {
            None => b[force] = scale,
            Some(act) => {
                let f = s - 1;
                a[(force, f)] = scale;
                a[(f, f)] = -1.0 / act.tau();
                b[f] = 1.0 / act.tau();
            }
        }
        Self { a, b, c }
    }

    /// `(e^{A tau}, Gamma(tau))` by the augmented matrix exponential (Van Loan 1978).
    pub fn exp_gamma(&self, tau: f64) -> (DMatrix<f64>, DVector<f64>) {
        let (e, mut gammas) = self.exp_inputs(&[&self.b], tau);
        (e, gammas.swap_remove(0))
    }

    /// `e^{A tau}` and `integral_0^tau e^{A s} g ds` for each input vector `g`, from one
    /// augmented matrix exponential `exp([[A, G], [0, 0]] tau)` (Van Loan 1978). With the
    /// single input `b` this is exactly [`Continuous::exp_gamma`]'s matrix.
    pub(crate) fn exp_inputs(
        &self,
        inputs: &[&DVector<f64>],
        tau: f64,
    ) -> (DMatrix<f64>, Vec<DVector<f64>>) {
        let s = self.a.nrows();
        let p = inputs.len();
        let mut m = DMatrix::<f64>::zeros(s + p, s + p);
        m.view_mut((0, 0), (s, s)).copy_from(&(&self.a * tau));
        for (j, g) in inputs.iter().enumerate() {
            m.view_mut((0, s + j), (s, 1)).copy_from(&(*g * tau));
        }
        let e = m.exp();
        let gammas = (0..p)
            .map(|j| e.column(s + j).rows(0, s).into_owned())
            .collect();
        (e.view((0, 0), (s, s)).into_owned(), gammas)
    }

    /// Where the operator's constant force acts on `lp`'s device, in the state equation
    /// `x' = A x + b u + e f_H` (normalized force `f_H = F_H T^2 / m`): on the velocity of
    /// the mass the operator holds, one over that mass. That is the single mass (with the
    /// hand's mass when a hand is named: the hand holds the handle rigidly, so its muscle
    /// force acts on the same mass as its inertia, damping and stiffness), or the handle
    /// side `r + mu_h` of a transmission; never through the actuator's lag, which carries
    /// only the commanded force (the model document, docs/MODEL.md, section 8).
    pub(crate) fn operator_input(lp: &Loop) -> DVector<f64> {
        let mu = lp.hand().map_or(0.0, |h| h.mass_ratio());
        let mut e = DVector::<f64>::zeros(lp.device_order());
        match lp.transmission() {
            None => e[1] = 1.0 / (1.0 + mu),
            Some(t) => e[3] = 1.0 / (t.handle_ratio() + mu),
        }
        e
    }
}

/// `H = (z - 1) Fn / (z Fd) = h0 + R / Q` for `filter`: `(R, Q, h0)` with `Q = z Fd` monic
/// (lowest power first) and `R` of degree below `Q`'s, padded to `Q`'s degree.
fn velocity_realization(filter: &crate::filter::VelocityFilter) -> (Vec<f64>, Vec<f64>, f64) {
    let (fnum, fden) = (filter.numerator(), filter.denominator());
    let mut q = vec![0.0];
    q.extend(&fden);
    let m = q.len() - 1;
    // P = (z - 1) Fn, padded to degree m
    let mut p = vec![0.0; m + 1];
    for (i, c) in fnum.iter().enumerate() {
        p[i + 1] += c;
        p[i] -= c;
    }
    let h0 = p[m];
    let rem = (0..m).map(|i| p[i] - h0 * q[i]).collect();
    (rem, q, h0)
}

/// The sampled device of a loop and the closed loop's state matrix.
#[derive(Debug, Clone, PartialEq)]
pub struct LoopDiscretization {
    lp: Loop,
    /// `Phi = e^A`.
    phi: DMatrix<f64>,
    /// Gain of `u_{k-n}`.
    g0: DVector<f64>,
    /// Gain of `u_{k-n-1}` (zero for a whole-sample delay).
    g1: DVector<f64>,
    /// The sensed position `y = c^T x`.
    c: DVector<f64>,
}

impl LoopDiscretization {
    /// The exact discretization of `lp`'s device. Fails only if the matrix exponential is
    /// not finite (which the limits on the elements are there to exclude).
    pub fn new(lp: &Loop) -> Result<Self> {
        let cont = Continuous::new(lp);
        let eps = lp.plant().fraction();
        let (phi, g0, g1) = if lp.plant().is_integer_delay() {
            let (phi, g0) = cont.exp_gamma(1.0);
            let g1 = DVector::zeros(phi.nrows());
            (phi, g0, g1)
        } else {
            let (phi, _) = cont.exp_gamma(1.0);
            let (e_rest, g0) = cont.exp_gamma(1.0 - eps);
            let (_, gamma_eps) = cont.exp_gamma(eps);
            (phi, g0, e_rest * gamma_eps)
        };
        if phi
            .iter()
            .chain(g0.iter())
            .chain(g1.iter())
            .any(|v| !v.is_finite())
        {
            return Err(Error::Numerical(
                "the device's matrix exponential is not finite; reduce the elements' stiffness or damping".into(),
            ));
        }
        Ok(Self {
            lp: *lp,
            phi,
            g0,
            g1,
            c: cont.c,
        })
    }

    /// The loop this discretizes.
    pub fn loop_model(&self) -> &Loop {
        &self.lp
    }

    /// `Phi = e^A`.
    pub fn phi(&self) -> &DMatrix<f64> {
        &self.phi
    }

    /// `G0 = Gamma(1 - eps)`, the gain of `u_{k-n}`.
    pub fn g0(&self) -> &DVector<f64> {
        &self.g0
    }

    /// `G1 = e^{A (1 - eps)} Gamma(eps)`, the gain of `u_{k-n-1}` (zero for integer `d`).
    pub fn g1(&self) -> &DVector<f64> {
        &self.g1
    }

    /// The output vector `c` (`y = c^T x`).
    pub fn output(&self) -> &DVector<f64> {
        &self.c
    }

    /// Dimension of the closed loop's state, equal to [`Loop::degree`].
    pub fn state_dim(&self) -> usize {
        self.lp.degree()
    }

    /// The closed-loop state matrix `S` with `z_{k+1} = S z_k`, built from the sampled device
    /// and the wall law directly (not from the characteristic polynomial).
    ///
    /// The state is `[x_k, u_{k-1}, ..., u_{k-h}, memory]` with `h = n` held past forces
    /// (`n + 1` for a fractional delay) and the wall's memory:
    ///
    /// - no filter: `y_{k-1}`, with `w_k = y_k - y_{k-1}`;
    /// - low-pass with pole `a`: `p_k = a w_{k-1} - (1 - a) y_{k-1}`, one state, so that
    ///   `w_k = (1 - a) y_k + p_k` and `p_{k+1} = a p_k - (1 - a)^2 y_k` (the recursion
    ///   `w_k = a w_{k-1} + (1 - a)(y_k - y_{k-1})` with `y_{k-1}` and `w_{k-1}` merged);
    /// - moving average over `N`: `y_{k-1}, ..., y_{k-N}`, with `w_k = (y_k - y_{k-N}) / N`;
    /// - any other filter (the second-order low-pass): the transfer `H = (z - 1) Fn / (z Fd)`
    ///   from `y` to `w` in
    ///   observable canonical form, `f + 1` states (Kailath, *Linear Systems*, 1980,
    ///   section 2.1).
    ///
    /// The force is `u_k = -(alpha y_k + beta w_k)`.
    pub fn state_matrix(&self, wall: &Wall) -> DMatrix<f64> {
        let s = self.phi.nrows();
        let n = self.lp.plant().whole_samples();
        let fractional = !self.lp.plant().is_integer_delay();
        let h = n + usize::from(fractional);
        let dim = self.state_dim();
        let mem = s + h;
        let (alpha, beta) = (wall.alpha(), wall.beta());
        // Row vectors over the state: y_k and w_k.
        let mut y = vec![0.0; dim];
        for (yi, ci) in y.iter_mut().zip(self.c.iter()) {
            *yi = *ci;
        }
        let mut w = vec![0.0; dim];
        let mut memory_rows: Vec<(usize, Vec<f64>)> = Vec::new();
        let pole = self.lp.low_pass_pole();
        let samples = match self.lp.filter().kind() {
            crate::filter::FilterKind::MovingAverage { samples } if samples > 1 => samples,
            _ => 1,
        };
        // any filter but the three with their own memory layout below
        let general = !matches!(
            self.lp.filter().kind(),
            crate::filter::FilterKind::None
                | crate::filter::FilterKind::LowPass { .. }
                | crate::filter::FilterKind::MovingAverage { .. }
        );
        if general {
            // H = (z - 1) Fn / (z Fd) = h0 + R / Q in the observable canonical form:
            // xi_{k+1} = [-Q; I shifted] xi_k + r y_k, w_k = xi_0 + h0 y_k
            let (rem, q, h0) = velocity_realization(self.lp.filter());
            let m = q.len() - 1;
            for j in 0..s {
                w[j] = h0 * y[j];
            }
            w[mem] = 1.0;
            for i in 0..m {
                let mut row = vec![0.0; dim];
                row[mem] = -q[m - 1 - i];
                if i + 1 < m {
                    row[mem + i + 1] = 1.0;
                }
                for j in 0..s {
                    row[j] += rem[m - 1 - i] * y[j];
                }
                memory_rows.push((mem + i, row));
            }
        } else if let Some(a) = pole {
            for j in 0..s {
                w[j] = (1.0 - a) * y[j];
            }
            w[mem] = 1.0;
            let mut row = vec![0.0; dim];
            for j in 0..s {
                row[j] = -(1.0 - a) * (1.0 - a) * y[j];
            }
            row[mem] = a;
            memory_rows.push((mem, row));
        } else {
            let inv = 1.0 / samples as f64;
            for j in 0..s {
                w[j] = inv * y[j];
            }
            w[mem + samples - 1] -= inv;
            // y_{k} moves into y_{(k+1)-1}, and each older one down by one.
            memory_rows.push((mem, y.clone()));
            for i in 1..samples {
                let mut row = vec![0.0; dim];
                row[mem + i - 1] = 1.0;
                memory_rows.push((mem + i, row));
            }
        }
        let u: Vec<f64> = y
            .iter()
            .zip(&w)
            .map(|(yi, wi)| -(alpha * yi + beta * wi))
            .collect();
        // u_{k-j} as a row: j = 0 is the wall law, j >= 1 the held force at s + j - 1.
        let force = |j: usize| -> Vec<f64> {
            if j == 0 {
                u.clone()
            } else {
                let mut r = vec![0.0; dim];
                r[s + j - 1] = 1.0;
                r
            }
        };
        let f0 = force(n);
        let f1 = if fractional {
            force(n + 1)
        } else {
            vec![0.0; dim]
        };
        let mut m = DMatrix::<f64>::zeros(dim, dim);
        for i in 0..s {
            for j in 0..s {
                m[(i, j)] = self.phi[(i, j)];
            }
            for col in 0..dim {
                m[(i, col)] += self.g0[i] * f0[col] + self.g1[i] * f1[col];
            }
        }
        if h > 0 {
            for col in 0..dim {
                m[(s, col)] = u[col];
            }
            for j in 1..h {
                m[(s + j, s + j - 1)] = 1.0;
            }
        }
        for (i, row) in memory_rows {
            for col in 0..dim {
                m[(i, col)] = row[col];
            }
        }
        m
    }
}
