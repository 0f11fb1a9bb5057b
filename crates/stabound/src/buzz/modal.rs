//! The exact motion of a small linear system `x' = A x + g` (constant `g`) at any time, from
//! one eigen decomposition of `A` computed once: `A = V diag(lambda) V^-1`, so that
//! `x(t) = V (e^{lambda t} z0 + phi1(lambda, t) q)` with `z0 = V^-1 x0`, `q = V^-1 g` and
//! `phi1(lambda, t) = integral_0^t e^{lambda s} ds = expm1(lambda t) / lambda` (Moler and Van
//! Loan, "Nineteen dubious ways to compute the exponential of a matrix", SIAM Review 2003,
//! method 14, eigenvectors).
//!
//! Moler and Van Loan's warning about that method is its conditioning: the rounding grows
//! with the condition number of `V`. So the decomposition is kept only when `A` is
//! diagonalizable with eigenvectors of condition number at most [`MAX_CONDITION`], and the
//! caller falls back to the matrix exponential otherwise (a defective `A`, such as an
//! undamped free mass, or eigenvalues closer than [`SAME_EIGENVALUE`] without a full
//! eigenspace).
//!
//! The event location of the friction module evaluates the motion at many trial times of one
//! piece; with the decomposition each evaluation is `n` complex exponentials and `n^2`
//! products instead of a matrix exponential of the augmented matrix.

use nalgebra::{Complex, DMatrix, DVector};

/// The largest condition number of the (unit-column) eigenvector matrix accepted.
///
/// The motion's relative rounding is about this times the machine epsilon, `2e-12`: far
/// below the `1e-9` of a count at which an encoder's reading could change, and below the
/// accuracy of any independent integration the simulation is checked against.
pub(super) const MAX_CONDITION: f64 = 1e4;

/// Eigenvalues closer than this (relative to the largest magnitude, at least 1) are taken
/// as one, whose eigenspace must then have their multiplicity.
///
/// A relative `1e-8` is the square root of the machine epsilon: the spread the QR algorithm
/// leaves in a double eigenvalue of a defective matrix.
pub(super) const SAME_EIGENVALUE: f64 = 1e-8;

/// Iterations allowed to the Schur and singular value decompositions (0: until converged
/// would never end on a pathological input).
const MAX_ITER: usize = 10_000;

/// `A = V diag(lambda) V^-1`.
#[derive(Debug, Clone)]
pub(super) struct Modal {
    lambda: Vec<Complex<f64>>,
    v: DMatrix<Complex<f64>>,
    v_inv: DMatrix<Complex<f64>>,
}

/// The motion from one state under one constant input, in modal coordinates.
pub(super) struct Trajectory<'a> {
    modal: &'a Modal,
    z0: DVector<Complex<f64>>,
    q: DVector<Complex<f64>>,
}

impl Modal {
    /// The eigen decomposition of `a`, or `None` when it is not diagonalizable with
    /// well-conditioned eigenvectors (module doc) or not finite.
    pub(super) fn new(a: &DMatrix<f64>) -> Option<Self> {
        let n = a.nrows();
        if n == 0 || a.iter().any(|v| !v.is_finite()) {
            return None;
        }
        let lambda: Vec<Complex<f64>> = a
            .clone()
            .try_schur(f64::EPSILON, MAX_ITER)?
            .complex_eigenvalues()
            .iter()
            .copied()
            .collect();
        let scale = lambda.iter().fold(1.0f64, |m, l| m.max(l.norm()));
        let ac = a.map(|x| Complex::new(x, 0.0));
        let mut v = DMatrix::<Complex<f64>>::zeros(n, n);
        let mut done = vec![false; n];
        let mut col = 0;
        for i in 0..n {
            if done[i] {
                continue;
            }
            // the group of eigenvalues taken as lambda[i]
            let group: Vec<usize> = (i..n)
                .filter(|&j| !done[j] && (lambda[j] - lambda[i]).norm() <= SAME_EIGENVALUE * scale)
                .collect();
            let mean = group.iter().map(|&j| lambda[j]).sum::<Complex<f64>>() / group.len() as f64;
            let shifted = &ac - DMatrix::<Complex<f64>>::identity(n, n) * mean;
            let svd = shifted.try_svd(false, true, f64::EPSILON, MAX_ITER)?;
            let v_t = svd.v_t?;
            let mut order: Vec<usize> = (0..n).collect();
            order.sort_by(|&p, &r| svd.singular_values[p].total_cmp(&svd.singular_values[r]));
            // the eigenspace: as many null vectors as the group's multiplicity
            for &k in order.iter().take(group.len()) {
                if svd.singular_values[k] > SAME_EIGENVALUE * scale {
                    return None;
                }
                v.set_column(col, &v_t.row(k).adjoint());
                col += 1;
            }
            for &j in &group {
                done[j] = true;
            }
        }
        // the eigenvalue of each column: A v = lambda v, read back as v^H A v (unit v)
        let lambda: Vec<Complex<f64>> = (0..n)
            .map(|c| {
                let vc = v.column(c);
                (vc.adjoint() * &ac * vc)[(0, 0)]
            })
            .collect();
        let sv = v.clone().try_svd(false, false, f64::EPSILON, MAX_ITER)?;
        let (lo, hi) = sv
            .singular_values
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(l, h), &s| (l.min(s), h.max(s)));
        if !(lo > 0.0 && hi / lo <= MAX_CONDITION) {
            return None;
        }
        let v_inv = v.clone().try_inverse()?;
        Some(Self { lambda, v, v_inv })
    }

    /// The motion from `x0` under the constant input `g`.
    pub(super) fn start(&self, x0: &DVector<f64>, g: &DVector<f64>) -> Trajectory<'_> {
        let complex = |x: &DVector<f64>| x.map(|v| Complex::new(v, 0.0));
        Trajectory {
            modal: self,
            z0: &self.v_inv * complex(x0),
            q: &self.v_inv * complex(g),
        }
    }
}

impl Trajectory<'_> {
    /// The modal coordinates at time `t`.
    fn modes(&self, t: f64) -> DVector<Complex<f64>> {
        DVector::from_iterator(
            self.z0.len(),
            self.modal.lambda.iter().enumerate().map(|(i, &l)| {
                let (e, p) = exp_phi1(l, t);
                e * self.z0[i] + p * self.q[i]
            }),
        )
    }

    /// The state at time `t`.
    pub(super) fn at(&self, t: f64) -> DVector<f64> {
        let m = self.modes(t);
        DVector::from_fn(m.len(), |j, _| self.row(&m, j))
    }

    /// The state's component `j` at time `t`.
    pub(super) fn component(&self, t: f64, j: usize) -> f64 {
        self.row(&self.modes(t), j)
    }

    /// Component `j` of the state whose modal coordinates are `m` (real: the modes of a
    /// real system come in conjugate pairs).
    fn row(&self, m: &DVector<Complex<f64>>, j: usize) -> f64 {
        self.modal
            .v
            .row(j)
            .iter()
            .zip(m.iter())
            .map(|(a, b)| a * b)
            .sum::<Complex<f64>>()
            .re
    }
}

/// `e^{lambda t}` and `phi1(lambda, t) = expm1(lambda t) / lambda` (`t` at `lambda = 0`),
/// the latter without the cancellation of `e^{lambda t} - 1` for a small `lambda t`.
fn exp_phi1(l: Complex<f64>, t: f64) -> (Complex<f64>, Complex<f64>) {
    let z = l * t;
    let e = z.exp();
    // exact: a zero eigenvalue is integrated as the constant it is
    if l == Complex::new(0.0, 0.0) {
        return (e, Complex::new(t, 0.0));
    }
    // expm1(x + i y) = (expm1(x) cos y - 2 sin^2(y / 2)) + i e^x sin y: each part without
    // the difference of two numbers near 1
    let half = (0.5 * z.im).sin();
    let m1 = Complex::new(z.re.exp_m1() * z.im.cos() - 2.0 * half * half, e.im);
    (e, m1 / l)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The decomposition's motion equals the augmented matrix exponential's (Van Loan 1978,
    /// computed by nalgebra's Pade approximant: an independent method) on the device
    /// matrices of interest; a defective matrix is refused.
    #[test]
    fn motion_matches_the_matrix_exponential() {
        let cases = [
            // a mass with viscous damping (eigenvalues 0 and -0.1)
            DMatrix::from_row_slice(2, 2, &[0.0, 1.0, 0.0, -0.1]),
            // a hand's spring: a complex pair
            DMatrix::from_row_slice(2, 2, &[0.0, 1.0, -0.02, -0.1]),
            // two masses and a lag, zero rows of a stuck mass (a double zero eigenvalue
            // with a full eigenspace)
            DMatrix::from_row_slice(
                5,
                5,
                &[
                    0.0, 0.0, 0.0, 0.0, 0.0, //
                    0.0, 0.0, 0.0, 0.0, 0.0, //
                    0.0, 0.0, 0.0, 1.0, 0.0, //
                    4.0, 0.2, -4.0, -0.3, 0.0, //
                    0.0, 0.0, 0.0, 0.0, -5.0,
                ],
            ),
            DMatrix::zeros(3, 3),
        ];
        for a in &cases {
            let n = a.nrows();
            let m = Modal::new(a).expect("diagonalizable");
            let x0 = DVector::from_fn(n, |i, _| 1.0 + i as f64 * 0.7);
            let g = DVector::from_fn(n, |i, _| 0.3 - i as f64 * 0.2);
            let traj = m.start(&x0, &g);
            for &t in &[0.0, 1e-9, 0.013, 0.5, 1.0, 3.7] {
                let mut aug = DMatrix::<f64>::zeros(n + 1, n + 1);
                aug.view_mut((0, 0), (n, n)).copy_from(&(a * t));
                aug.view_mut((0, n), (n, 1)).copy_from(&(&g * t));
                let e = aug.exp();
                let want = e.view((0, 0), (n, n)) * &x0 + e.view((0, n), (n, 1));
                let got = traj.at(t);
                for j in 0..n {
                    // the rounding of a condition number below 1e2 on O(1) values
                    assert!(
                        (got[j] - want[j]).abs() < 1e-13 * want[j].abs().max(1.0),
                        "{a} t = {t}: {got} vs {want}"
                    );
                    assert_eq!(traj.component(t, j), got[j]);
                }
            }
        }
        // an undamped free mass is a Jordan block
        assert!(Modal::new(&DMatrix::from_row_slice(2, 2, &[0.0, 1.0, 0.0, 0.0])).is_none());
    }

    /// `phi1` near zero keeps its digits (against its Taylor series).
    #[test]
    fn phi1_of_a_small_argument() {
        let l = Complex::new(-1e-7, 2e-7);
        let t = 0.5;
        let z = l * t;
        let series = Complex::new(t, 0.0) * (Complex::new(1.0, 0.0) + z / 2.0 + z * z / 6.0);
        let (_, p) = exp_phi1(l, t);
        // a few roundings of O(t) values
        assert!((p - series).norm() < 4.0 * f64::EPSILON * t, "{p} {series}");
    }
}
