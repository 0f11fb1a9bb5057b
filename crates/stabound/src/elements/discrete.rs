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
//!
//! A stiff device (a 1-norm of the augmented matrix above [`STIFF_NORM`], a stiff
//! transmission's fast mode) is exponentiated in double-double arithmetic instead: scaling
//! and squaring done in double precision errs by about `2^s` roundings amplified by the
//! squared matrices' norms, which for a coupling of `5e5` moves the root of the free
//! integrator by more than the default marginal band. In double-double (Dekker, "A
//! floating-point technique for extending the available precision", Numer. Math. 18, 1971;
//! the `QD` library's algorithms, Hida, Li and Bailey, 2001) the same scaling and squaring
//! (on the matrix balanced by powers of two, Taylor polynomial of degree 24 at 1-norm at
//! most `1/2`, then `s` squarings) carries a componentwise bound on its error, propagated
//! through each squaring; the entries are then rounded to double, and the bound
//! ([`GeneralDiscretization::exp_error_bound`]) is what the checker folds into its coefficient
//! error (docs/MODEL.md, section 8.1).

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
        let (e, gamma, _) = self.exp_gamma_bounded(tau);
        (e, gamma)
    }

    /// As [`Continuous::exp_gamma`], with the bound of [`Continuous::exp_inputs_bounded`].
    fn exp_gamma_bounded(&self, tau: f64) -> (DMatrix<f64>, DVector<f64>, Option<f64>) {
        let (e, mut gammas, bound) = self.exp_inputs_bounded(&[&self.b], tau);
        (e, gammas.swap_remove(0), bound)
    }

    /// `e^{A tau}` and `integral_0^tau e^{A s} g ds` for each input vector `g`, from one
    /// augmented matrix exponential `exp([[A, G], [0, 0]] tau)` (Van Loan 1978). With the
    /// single input `b` this is exactly [`Continuous::exp_gamma`]'s matrix.
    pub(crate) fn exp_inputs(
        &self,
        inputs: &[&DVector<f64>],
        tau: f64,
    ) -> (DMatrix<f64>, Vec<DVector<f64>>) {
        let (e, gammas, _) = self.exp_inputs_bounded(inputs, tau);
        (e, gammas)
    }

    /// As [`Continuous::exp_inputs`], with the exponential's error bound relative to its
    /// largest entry (`None` on the double-precision route below [`STIFF_NORM`]).
    fn exp_inputs_bounded(
        &self,
        inputs: &[&DVector<f64>],
        tau: f64,
    ) -> (DMatrix<f64>, Vec<DVector<f64>>, Option<f64>) {
        let s = self.a.nrows();
        let p = inputs.len();
        let mut m = DMatrix::<f64>::zeros(s + p, s + p);
        m.view_mut((0, 0), (s, s)).copy_from(&(&self.a * tau));
        for (j, g) in inputs.iter().enumerate() {
            m.view_mut((0, s + j), (s, 1)).copy_from(&(*g * tau));
        }
        let (e, bound) = exponential(&m);
        let gammas = (0..p)
            .map(|j| e.column(s + j).rows(0, s).into_owned())
            .collect();
        (e.view((0, 0), (s, s)).into_owned(), gammas, bound)
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

/// The sampled device of a loop with elements and the closed loop's state matrix: the
/// general route inside [`crate::model::Discretization`].
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct GeneralDiscretization {
    lp: Loop,
    /// `Phi = e^A`.
    phi: DMatrix<f64>,
    /// Gain of `u_{k-n}`.
    g0: DVector<f64>,
    /// Gain of `u_{k-n-1}` (zero for a whole-sample delay).
    g1: DVector<f64>,
    /// The sensed position `y = c^T x`.
    c: DVector<f64>,
    /// The double-double exponentials' largest error bound, relative to their largest entry.
    bound: Option<f64>,
}

impl GeneralDiscretization {
    /// The exact discretization of `lp`'s device. Fails only if the matrix exponential is
    /// not finite (which the limits on the elements are there to exclude).
    pub(crate) fn new(lp: &Loop) -> Result<Self> {
        let cont = Continuous::new(lp);
        let eps = lp.plant().fraction();
        let (phi, whole, bound) = cont.exp_gamma_bounded(1.0);
        let (g0, g1, bound) = if lp.plant().is_integer_delay() {
            (whole, DVector::zeros(phi.nrows()), bound)
        } else {
            let (e_rest, g0, b0) = cont.exp_gamma_bounded(1.0 - eps);
            let (_, gamma_eps, b1) = cont.exp_gamma_bounded(eps);
            let worst = [bound, b0, b1].into_iter().flatten().reduce(f64::max);
            (g0, e_rest * gamma_eps, worst)
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
            bound,
        })
    }

    /// A bound on the error of the sampled device's entries beyond their rounding to double,
    /// relative to the largest entry of the exponential, when it was computed in
    /// double-double (a stiff device, 1-norm above [`STIFF_NORM`]); `None` on the
    /// double-precision route, whose error the checker's model covers.
    pub(crate) fn exp_error_bound(&self) -> Option<f64> {
        self.bound
    }

    /// The loop this discretizes.
    pub(crate) fn loop_model(&self) -> &Loop {
        &self.lp
    }

    /// `Phi = e^A`.
    pub(crate) fn phi(&self) -> &DMatrix<f64> {
        &self.phi
    }

    /// `G0 = Gamma(1 - eps)`, the gain of `u_{k-n}`.
    pub(crate) fn g0(&self) -> &DVector<f64> {
        &self.g0
    }

    /// `G1 = e^{A (1 - eps)} Gamma(eps)`, the gain of `u_{k-n-1}` (zero for integer `d`).
    pub(crate) fn g1(&self) -> &DVector<f64> {
        &self.g1
    }

    /// The output vector `c` (`y = c^T x`).
    pub(crate) fn output(&self) -> &DVector<f64> {
        &self.c
    }

    /// Dimension of the closed loop's state, equal to [`Loop::degree`].
    pub(crate) fn state_dim(&self) -> usize {
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
    pub(crate) fn state_matrix(&self, wall: &Wall) -> DMatrix<f64> {
        let s = self.phi.nrows();
        let n = self.lp.plant().whole_samples();
        let fractional = !self.lp.plant().is_integer_delay();
        let h = n + usize::from(fractional);
        let dim = self.state_dim();
        let mem = s + h;
        let (alpha, beta) = (wall.alpha(), wall.beta());
        let mut m = DMatrix::<f64>::zeros(dim, dim);
        // The rows y_k and w_k over the state, entry by entry (no vectors: this matrix is
        // built for every wall whose eigenvalues are asked for).
        let y = |col: usize| if col < s { self.c[col] } else { 0.0 };
        let kind = self.lp.filter().kind();
        let samples = match kind {
            crate::filter::FilterKind::MovingAverage { samples } if samples > 1 => samples,
            _ => 1,
        };
        let pole = self.lp.low_pass_pole();
        // any filter but the three with their own memory layout below: H = (z - 1) Fn /
        // (z Fd) = h0 + R / Q in the observable canonical form, xi_{k+1} = [-Q; I shifted]
        // xi_k + r y_k, w_k = xi_0 + h0 y_k
        let general = (!matches!(
            kind,
            crate::filter::FilterKind::None
                | crate::filter::FilterKind::LowPass { .. }
                | crate::filter::FilterKind::MovingAverage { .. }
        ))
        .then(|| velocity_realization(self.lp.filter()));
        let inv = 1.0 / samples as f64;
        let w = |col: usize| -> f64 {
            if col < s {
                return match (&general, pole) {
                    (Some((_, _, h0)), _) => h0 * y(col),
                    (None, Some(a)) => (1.0 - a) * y(col),
                    (None, None) => inv * y(col),
                };
            }
            match (&general, pole) {
                (Some(_), _) | (None, Some(_)) if col == mem => 1.0,
                // `0 - inv`, as the older sample's weight
                (None, None) if col == mem + samples - 1 => -inv,
                _ => 0.0,
            }
        };
        let u = |col: usize| -(alpha * y(col) + beta * w(col));
        // u_{k-j} at a column: j = 0 is the wall law, j >= 1 the held force at s + j - 1.
        let force = |j: usize, col: usize| -> f64 {
            if j == 0 {
                u(col)
            } else if col == s + j - 1 {
                1.0
            } else {
                0.0
            }
        };
        for i in 0..s {
            for j in 0..s {
                m[(i, j)] = self.phi[(i, j)];
            }
            for col in 0..dim {
                let f1 = if fractional { force(n + 1, col) } else { 0.0 };
                m[(i, col)] += self.g0[i] * force(n, col) + self.g1[i] * f1;
            }
        }
        if h > 0 {
            for col in 0..dim {
                m[(s, col)] = u(col);
            }
            for j in 1..h {
                m[(s + j, s + j - 1)] = 1.0;
            }
        }
        // The wall's memory:
        if let Some((rem, q, _)) = &general {
            let order = q.len() - 1;
            for i in 0..order {
                m[(mem + i, mem)] = -q[order - 1 - i];
                if i + 1 < order {
                    m[(mem + i, mem + i + 1)] = 1.0;
                }
                for j in 0..s {
                    // `0 +`: the row's entry added to, as the realization's sum
                    m[(mem + i, j)] = 0.0 + rem[order - 1 - i] * y(j);
                }
            }
        } else if let Some(a) = pole {
            for j in 0..s {
                m[(mem, j)] = -(1.0 - a) * (1.0 - a) * y(j);
            }
            m[(mem, mem)] = a;
        } else {
            // y_{k} moves into y_{(k+1)-1}, and each older one down by one.
            for col in 0..dim {
                m[(mem, col)] = y(col);
            }
            for i in 1..samples {
                m[(mem + i, mem + i - 1)] = 1.0;
            }
        }
        m
    }
}

/// The 1-norm of the augmented matrix above which the exponential is computed in
/// double-double (see the module documentation). Below it nalgebra's double-precision
/// scaling and squaring takes at most 11 squarings, and its error (a few roundings per
/// squaring, amplified by norms of at most `1e3`) stays within the `2^10 (n + 8)` roundings
/// of the largest coefficient that the checker assumes; the loops of moderate elements keep
/// their double-precision results bit for bit.
pub const STIFF_NORM: f64 = 1e3;

/// Degree of the Taylor polynomial in double-double: at 1-norm `theta <= 1/2` the remainder
/// `theta^25 / 25! / (1 - theta / 26)` is below `2e-33`, under the double-double unit
/// roundoff `2^-104 = 4.9e-32`.
const DD_TAYLOR_DEGREE: u32 = 24;

/// The exponential of `m` and a bound on its error relative to its largest entry: nalgebra's
/// Pade route up to [`STIFF_NORM`] (bound `None`: within the checker's error model),
/// double-double scaling and squaring above it, whose bound is that of [`exp_double_double`]
/// before the final rounding to double.
fn exponential(m: &DMatrix<f64>) -> (DMatrix<f64>, Option<f64>) {
    if norm1(m) <= STIFF_NORM {
        return (pade_exp(m), None);
    }
    let (e, bound) = exp_double_double(m);
    let largest = e.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    (e, Some(bound / largest))
}

/// nalgebra's Pade exponential of `m` ([`nalgebra::Matrix::exp`]), on a matrix of fixed
/// size for the augmented matrices of three to five rows (one mass with or without a lag,
/// two masses): the same algorithm and the same operations in the same order (nalgebra
/// multiplies matrices of at most five rows by the same column-by-column products whether
/// their size is fixed or not), without a heap allocation per intermediate matrix, which
/// were most of its cost at these sizes. Larger ones go through the dynamic matrix.
fn pade_exp(m: &DMatrix<f64>) -> DMatrix<f64> {
    // one function per size: nalgebra's exponential needs a concrete dimension
    macro_rules! fixed {
        ($n:literal) => {{
            let e = nalgebra::SMatrix::<f64, $n, $n>::from_fn(|i, j| m[(i, j)]).exp();
            DMatrix::from_fn($n, $n, |i, j| e[(i, j)])
        }};
    }
    match m.nrows() {
        3 => fixed!(3),
        4 => fixed!(4),
        5 => fixed!(5),
        _ => m.exp(),
    }
}

/// The 1-norm (largest column sum of moduli) of `m`.
fn norm1(m: &DMatrix<f64>) -> f64 {
    m.column_iter()
        .map(|c| c.iter().map(|v| v.abs()).sum::<f64>())
        .fold(0.0, f64::max)
}

/// A double-double number `hi + lo` with `|lo| <= ulp(hi) / 2` (Dekker 1971).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
struct Dd {
    hi: f64,
    lo: f64,
}

/// The unit roundoff of double-double arithmetic, `2^-104`.
const DD_EPS: f64 = 4.930_380_657_631_324e-32;

/// `a + b = s + e` exactly (Knuth's two-sum).
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

/// `a + b = s + e` exactly when `|a| >= |b|` (Dekker's fast two-sum).
fn quick_two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    (s, b - (s - a))
}

impl Dd {
    fn from(x: f64) -> Self {
        Self { hi: x, lo: 0.0 }
    }

    fn norm(hi: f64, lo: f64) -> Self {
        let (hi, lo) = quick_two_sum(hi, lo);
        Self { hi, lo }
    }

    /// The sum, to a few double-double roundings (QD's accurate addition).
    fn add(self, o: Self) -> Self {
        let (s, e) = two_sum(self.hi, o.hi);
        let (t, f) = two_sum(self.lo, o.lo);
        let (s, e) = quick_two_sum(s, e + t);
        Self::norm(s, e + f)
    }

    /// The product, to a few double-double roundings (the error of `hi * hi` exact by a
    /// fused multiply-add).
    fn mul(self, o: Self) -> Self {
        let p = self.hi * o.hi;
        let e = self.hi.mul_add(o.hi, -p) + (self.hi * o.lo + self.lo * o.hi);
        Self::norm(p, e)
    }

    /// The quotient by a double (QD's `dd / d`).
    fn div(self, d: f64) -> Self {
        let q1 = self.hi / d;
        let p1 = q1 * d;
        let p2 = q1.mul_add(d, -p1);
        let (s, e) = two_sum(self.hi, -p1);
        let q2 = (s + (e - p2 + self.lo)) / d;
        Self::norm(q1, q2)
    }
}

/// A square matrix, row-major: double-double entries, or doubles for the error bounds.
#[derive(Debug, Clone)]
struct Square<T> {
    n: usize,
    v: Vec<T>,
}

impl<T: Copy> Square<T> {
    fn at(&self, i: usize, j: usize) -> T {
        self.v[i * self.n + j]
    }

    /// The product with `o`, from `zero`, the entry product `mul` and sum `add`.
    fn product(&self, o: &Self, zero: T, mul: impl Fn(T, T) -> T, add: impl Fn(T, T) -> T) -> Self {
        let n = self.n;
        let v = (0..n * n)
            .map(|ij| {
                let (i, j) = (ij / n, ij % n);
                (0..n).fold(zero, |acc, k| add(acc, mul(self.at(i, k), o.at(k, j))))
            })
            .collect();
        Self { n, v }
    }

    fn map<U>(&self, f: impl Fn(T) -> U) -> Square<U> {
        Square {
            n: self.n,
            v: self.v.iter().map(|&x| f(x)).collect(),
        }
    }
}

impl Square<Dd> {
    fn mul(&self, o: &Self) -> Self {
        self.product(o, Dd::default(), Dd::mul, Dd::add)
    }
}

impl Square<f64> {
    fn mul(&self, o: &Self) -> Self {
        self.product(o, 0.0, |a, b| a * b, |a, b| a + b)
    }

    fn plus(&self, o: &Self, scale: f64) -> Self {
        Self {
            n: self.n,
            v: self
                .v
                .iter()
                .zip(&o.v)
                .map(|(a, b)| a + scale * b)
                .collect(),
        }
    }
}

/// Powers of two `d` with `D^-1 m D` balanced: each row's and column's off-diagonal sums
/// within a factor of about 2 (Osborne's iteration as in LAPACK's `gebal`, without
/// permutations). Scaling by powers of two is exact, and the balanced exponential's
/// squarings lose far less than the raw one's to a stiff mode's position-velocity scales.
fn balance(m: &DMatrix<f64>) -> Vec<f64> {
    let n = m.nrows();
    let mut d = vec![1.0f64; n];
    let entry = |d: &[f64], i: usize, j: usize| (m[(i, j)] * d[j] / d[i]).abs();
    for _ in 0..64 {
        let mut changed = false;
        for i in 0..n {
            let c: f64 = (0..n).filter(|&j| j != i).map(|j| entry(&d, j, i)).sum();
            let r: f64 = (0..n).filter(|&j| j != i).map(|j| entry(&d, i, j)).sum();
            if c == 0.0 || r == 0.0 {
                continue;
            }
            let (mut f, mut cc) = (1.0, c);
            while cc < r / 2.0 {
                f *= 2.0;
                cc *= 4.0;
            }
            while cc >= r * 2.0 {
                f /= 2.0;
                cc /= 4.0;
            }
            // row i is divided by f, column i multiplied by it
            if (c * f + r / f) < 0.95 * (c + r) {
                d[i] *= f;
                changed = true;
            }
        }
        if !changed {
            break;
        }
    }
    d
}

/// `e^m` in double-double by scaling and squaring of the balanced matrix, rounded to double,
/// with a bound on the largest entry's error of the double-double result before that
/// rounding (see the module documentation).
///
/// The bound is componentwise, in matrices of moduli: the Taylor polynomial's remainder and
/// roundings, then through each squaring `|E^2 - F^2| <= |E| D + D |E| + D^2` plus the
/// product's roundings `4 (n + 2) u |E| |E|` (`D` the bound so far, `|E|` taken with it),
/// and back through the exact balancing.
fn exp_double_double(m: &DMatrix<f64>) -> (DMatrix<f64>, f64) {
    let n = m.nrows();
    let d = balance(m);
    let balanced = DMatrix::from_fn(n, n, |i, j| m[(i, j)] * d[j] / d[i]);
    let norm = norm1(&balanced);
    // the least s with norm / 2^s <= 1/2; scaling by a power of two is exact
    let mut squarings = 0i32;
    while norm * 0.5f64.powi(squarings) > 0.5 {
        squarings += 1;
    }
    let scale = 0.5f64.powi(squarings);
    let x = Square {
        n,
        v: (0..n * n)
            .map(|k| Dd::from(balanced[(k / n, k % n)] * scale))
            .collect(),
    };
    let theta = norm * scale;
    // Horner: T = I + X/1 (I + X/2 (I + ... (I + X/K)))
    let identity = |i: usize| i / n == i % n;
    let mut t = Square {
        n,
        v: (0..n * n)
            .map(|i| Dd::from(if identity(i) { 1.0 } else { 0.0 }))
            .collect(),
    };
    for k in (1..=DD_TAYLOR_DEGREE).rev() {
        let mut xt = x.mul(&t);
        for (i, v) in xt.v.iter_mut().enumerate() {
            *v = v.div(f64::from(k));
            if identity(i) {
                *v = v.add(Dd::from(1.0));
            }
        }
        t = xt;
    }
    let k1 = f64::from(DD_TAYLOR_DEGREE + 1);
    let fact: f64 = (1..=DD_TAYLOR_DEGREE + 1).map(f64::from).product();
    let remainder = theta.powf(k1) / fact / (1.0 - theta / (k1 + 1.0));
    // each Horner step: a product of n terms and a division, a few roundings of each
    // entry, each at most e^theta
    let nf = n as f64;
    let rounding = 4.0 * (nf + 2.0) * DD_EPS;
    let horner = rounding * f64::from(DD_TAYLOR_DEGREE) * theta.exp();
    let mut bound = t.map(|_| remainder + horner);
    for _ in 0..squarings {
        let modulus = t.map(|v| v.hi.abs()).plus(&bound, 1.0);
        let sq = modulus.mul(&modulus);
        bound = modulus
            .mul(&bound)
            .plus(&bound.mul(&modulus), 1.0)
            .plus(&bound.mul(&bound), 1.0)
            .plus(&sq, rounding);
        t = t.mul(&t);
    }
    let out = DMatrix::from_fn(n, n, |i, j| {
        let v = t.at(i, j);
        (v.hi + v.lo) * d[i] / d[j]
    });
    let worst = (0..n * n)
        .map(|k| bound.v[k] * d[k / n] / d[k % n])
        .fold(0.0, f64::max);
    // slack for the bound's own evaluation in double precision
    (out, worst * (1.0 + 1e-10))
}

#[cfg(test)]
mod tests {
    use super::pade_exp;
    use nalgebra::DMatrix;

    /// The exponential on fixed-size matrices is nalgebra's exponential on the dynamic
    /// matrix bit for bit, at every size it takes and over norms that pick each Pade
    /// degree and scaling (from 1e-3 to the double-precision route's limit).
    #[test]
    fn fixed_size_exponential_is_the_dynamic_one() {
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        for n in 2..=6 {
            for case in 0..60 {
                let scale = 10f64.powf(-3.0 + 6.0 * f64::from(case % 12) / 11.0) / n as f64;
                let m = DMatrix::from_fn(n, n, |_, _| scale * next());
                let (fast, reference) = (pade_exp(&m), m.exp());
                for (a, b) in fast.iter().zip(reference.iter()) {
                    assert_eq!(a.to_bits(), b.to_bits(), "{m}");
                }
            }
        }
    }
}
