//! Roots by eigenvalues: of the companion matrix of `q`, or of the closed loop's state matrix.
//!
//! Method: balancing (Parlett-Reinsch, via nalgebra) followed by the implicit double-shift QR
//! algorithm (Golub and Van Loan, *Matrix Computations*, 7.5) with an iteration cap:
//!
//! - a companion matrix is already upper Hessenberg, so its eigenvalues come from the QR
//!   iteration alone, without Schur vectors ([`super::hqr`], EISPACK's `hqr`);
//! - a general matrix (the state-space route) goes through `nalgebra::Schur::try_new`, which
//!   reduces it to Hessenberg form first.
//!
//! nalgebra's uncapped `complex_eigenvalues()` can loop forever on companion matrices whose
//! roots share one modulus (nalgebra issue #611, `z^8 - 0.5`); it is never called on a raw
//! matrix. When the capped QR gives up, the polynomial's roots are found by the
//! Aberth-Ehrlich iteration instead (Aberth, *Math. Comp.* 27, 1973), which has no such stall.

use nalgebra::allocator::Allocator;
use nalgebra::{DMatrix, DefaultAllocator, Dim, DimDiff, DimSub, OMatrix, SMatrix, U1};

use crate::error::{Error, Result};
use crate::poly::Complex;

/// QR iterations allowed per eigenvalue; LAPACK's `dhseqr` allows 30, we allow a little more
/// because nalgebra has no exceptional shifts (`hqr` has them every 10 iterations).
const QR_ITERATIONS_PER_EIGENVALUE: usize = 40;

/// Aberth-Ehrlich iterations before giving up; it converges cubically once close, and from
/// the circle start in a few dozen steps for the degrees this crate builds.
const ABERTH_ITERATIONS: usize = 500;

/// The eigenvalues of a square matrix, with capped QR iterations. `None` if QR did not
/// converge, an eigenvalue is not finite, the matrix has a non-finite entry or is not
/// square.
pub fn eigenvalues_capped(m: DMatrix<f64>) -> Option<Vec<Complex>> {
    if !m.is_square() {
        return None;
    }
    schur_eigenvalues(m, Shape::General)
}

/// What a matrix handed to [`schur_eigenvalues`] is known to be.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Shape {
    /// Any square matrix: nalgebra's Schur decomposition (Hessenberg reduction, then QR).
    General,
    /// Upper Hessenberg (a companion matrix): the QR iteration alone, without Schur vectors
    /// ([`super::hqr`]).
    Hessenberg,
}

/// Balancing plus capped Schur for any matrix shape, fixed-size (no heap) or dynamic.
fn schur_eigenvalues<D>(mut m: OMatrix<f64, D, D>, shape: Shape) -> Option<Vec<Complex>>
where
    D: DimSub<U1>,
    DefaultAllocator:
        Allocator<D, DimDiff<D, U1>> + Allocator<DimDiff<D, U1>> + Allocator<D, D> + Allocator<D>,
{
    let n = m.nrows();
    if n == 0 {
        return Some(Vec::new());
    }
    if m.iter().any(|v| !v.is_finite()) {
        return None;
    }
    // Scale by the power of two nearest the largest entry (exact, and undone exactly below):
    // balancing sums squares of rows and columns, which overflow to infinity for entries
    // near 1e300, and its scaling loop then never ends.
    let amax = m.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let scale = if amax > 0.0 {
        2f64.powi(amax.log2().round() as i32)
    } else {
        1.0
    };
    m /= scale;
    nalgebra::linalg::balancing::balance_parlett_reinsch(&mut m);
    let cap = QR_ITERATIONS_PER_EIGENVALUE * n + 100;
    // `eps` decides when a subdiagonal entry counts as zero relative to its neighbours; machine
    // epsilon is the standard choice (the deflation criterion of Golub and Van Loan 7.5.1).
    let mut roots = match shape {
        // Balancing is a diagonal similarity, so the matrix is still Hessenberg.
        Shape::Hessenberg => {
            super::hqr::hessenberg_eigenvalues(m.as_mut_slice(), n, QR_ITERATIONS_PER_EIGENVALUE)?
        }
        // Householder reduction to Hessenberg form without accumulating its transformations,
        // then the same QR iteration: the eigenvalues are all that is wanted, and the Schur
        // vectors nalgebra's `Schur` accumulates cost most of its time (at d = 500, 99 % of
        // a `check`).
        Shape::General => {
            let _ = cap;
            let mut h = nalgebra::linalg::Hessenberg::new(m).unpack_h();
            super::hqr::hessenberg_eigenvalues(h.as_mut_slice(), n, QR_ITERATIONS_PER_EIGENVALUE)?
        }
    };
    roots.iter_mut().for_each(|z| *z *= scale);
    // QR on a matrix near the top of the range can overflow to NaN without failing: such a
    // result is no root.
    roots
        .iter()
        .all(|z| z.re.is_finite() && z.im.is_finite())
        .then_some(roots)
}

/// Writes the companion matrix of `coeffs` into the zeroed square matrix `c`.
fn fill_companion<D: Dim>(c: &mut OMatrix<f64, D, D>, coeffs: &[f64])
where
    DefaultAllocator: Allocator<D, D>,
{
    let m = coeffs.len() - 1;
    let lead = coeffs[m];
    for i in 0..m {
        if i + 1 < m {
            c[(i + 1, i)] = 1.0;
        }
        c[(i, m - 1)] = -coeffs[i] / lead;
    }
}

/// Companion eigenvalues, on the stack for the short delays most requests have.
fn companion_eigenvalues(coeffs: &[f64]) -> Option<Vec<Complex>> {
    macro_rules! fixed {
        ($($n:literal),*) => {
            match coeffs.len() - 1 {
                $($n => {
                    let mut c = SMatrix::<f64, $n, $n>::zeros();
                    fill_companion(&mut c, coeffs);
                    schur_eigenvalues(c, Shape::Hessenberg)
                })*
                _ => schur_eigenvalues(companion(coeffs), Shape::Hessenberg),
            }
        };
    }
    fixed!(3, 4, 5, 6, 7, 8)
}

/// The companion matrix of `coeffs` (lowest power first; leading coefficient nonzero).
pub fn companion(coeffs: &[f64]) -> DMatrix<f64> {
    let m = coeffs.len().saturating_sub(1);
    let mut c = DMatrix::<f64>::zeros(m, m);
    if m > 0 {
        fill_companion(&mut c, coeffs);
    }
    c
}

/// The roots of a real polynomial (lowest power first): companion-matrix eigenvalues, with
/// the Aberth-Ehrlich iteration as fallback when QR does not converge or returns a
/// non-finite value. Every root returned is finite.
pub fn poly_roots(coeffs: &[f64]) -> Result<Vec<Complex>> {
    let Some(m) = coeffs.len().checked_sub(1) else {
        return Err(Error::Numerical("the empty polynomial has no roots".into()));
    };
    let lead = coeffs[m];
    if !(lead.is_finite() && lead.abs() > 0.0) || coeffs.iter().any(|c| !c.is_finite()) {
        return Err(Error::Numerical(
            "polynomial coefficients must be finite with a nonzero leading coefficient".into(),
        ));
    }
    if m == 0 {
        return Ok(Vec::new());
    }
    crate::cancel::poll()?;
    if let Some(r) = companion_eigenvalues(coeffs) {
        return Ok(r);
    }
    crate::cancel::poll()?;
    aberth(coeffs).ok_or(Error::NoConvergence {
        method: "companion eigenvalues and the Aberth-Ehrlich fallback",
        iterations: ABERTH_ITERATIONS,
    })
}

/// Horner evaluation of `p` and `p'` at `z`.
fn eval_with_derivative(coeffs: &[f64], z: Complex) -> (Complex, Complex) {
    let mut p = Complex::new(0.0, 0.0);
    let mut dp = Complex::new(0.0, 0.0);
    for &c in coeffs.iter().rev() {
        dp = dp * z + p;
        p = p * z + c;
    }
    (p, dp)
}

/// Simultaneous root finding by the Aberth-Ehrlich iteration (coefficients lowest power
/// first). `None` if it does not converge, or for fewer than two coefficients, a zero or
/// non-finite coefficient where a finite leading one is needed, or a non-finite root.
pub fn aberth(coeffs: &[f64]) -> Option<Vec<Complex>> {
    let m = coeffs.len().checked_sub(1).filter(|&m| m > 0)?;
    let lead = coeffs[m];
    if !(lead.is_finite() && lead.abs() > 0.0) || coeffs.iter().any(|c| !c.is_finite()) {
        return None;
    }
    // Start on a circle of the Fujiwara-type radius bound, with an angle offset that breaks the
    // symmetry of real coefficients.
    let radius = coeffs[..m]
        .iter()
        .enumerate()
        .map(|(i, c)| (c / lead).abs().powf(1.0 / (m - i) as f64))
        .fold(0.0f64, f64::max)
        .max(1e-3);
    let mut z: Vec<Complex> = (0..m)
        .map(|k| {
            let angle = 2.0 * std::f64::consts::PI * k as f64 / m as f64 + 0.4;
            Complex::from_polar(radius, angle)
        })
        .collect();
    let mut done = vec![false; m];
    for _ in 0..ABERTH_ITERATIONS {
        let mut all_done = true;
        for i in 0..m {
            if done[i] {
                continue;
            }
            let (p, dp) = eval_with_derivative(coeffs, z[i]);
            // an exact root: the Newton ratio below would be 0 / p', nothing left to refine
            if p.norm() == 0.0 {
                done[i] = true;
                continue;
            }
            let ratio = p / dp;
            let mut sum = Complex::new(0.0, 0.0);
            for (j, zj) in z.iter().enumerate() {
                if j != i {
                    sum += 1.0 / (z[i] - zj);
                }
            }
            let step = ratio / (Complex::new(1.0, 0.0) - ratio * sum);
            if !(step.re.is_finite() && step.im.is_finite()) {
                return None;
            }
            z[i] -= step;
            // Converged when the step is at rounding level of the root's modulus.
            if step.norm() <= 4.0 * f64::EPSILON * z[i].norm().max(1e-300) {
                done[i] = true;
            } else {
                all_done = false;
            }
        }
        if all_done {
            return z
                .iter()
                .all(|r| r.re.is_finite() && r.im.is_finite())
                .then_some(z);
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::{Duration, Instant};

    /// nalgebra issue #611: `complex_eigenvalues()` never returns on this companion matrix.
    /// Here it must return promptly, with the eight roots of modulus 0.5^(1/8).
    #[test]
    fn hang_case_returns() {
        let start = Instant::now();
        let coeffs = [-0.5, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0];
        let roots = poly_roots(&coeffs).expect("roots of z^8 - 0.5");
        assert!(start.elapsed() < Duration::from_secs(1));
        assert_eq!(roots.len(), 8);
        let r = 0.5f64.powf(0.125);
        for z in roots {
            assert!((z.norm() - r).abs() < 1e-12, "{z}");
        }
    }

    #[test]
    fn aberth_finds_known_roots() {
        // (z - 0.5)(z + 0.25)(z^2 + 1) = z^4 - 0.25 z^3 + 0.875 z^2 - 0.25 z - 0.125
        let coeffs = [-0.125, -0.25, 0.875, -0.25, 1.0];
        let r = aberth(&coeffs).unwrap();
        assert_eq!(r.len(), 4);
        for (re, im) in [(-0.25, 0.0), (0.0, -1.0), (0.0, 1.0), (0.5, 0.0)] {
            let e = Complex::new(re, im);
            assert!(r.iter().any(|z| (z - e).norm() < 1e-13), "{e} not in {r:?}");
        }
    }

    /// Entries near 1e300 used to make balancing loop forever (its row and column norms
    /// overflow). With alpha = 1e300 the companion matrix has such entries.
    #[test]
    fn huge_coefficients_return() {
        let start = Instant::now();
        let roots = poly_roots(&[1e300, -3e300, 1.0]).unwrap();
        assert!(start.elapsed() < Duration::from_secs(1));
        // z^2 - 3e300 z + 1e300: roots about 3e300 and 1/3
        let big = roots.iter().map(|z| z.norm()).fold(0.0, f64::max);
        assert!((big / 3e300 - 1.0).abs() < 1e-12, "{roots:?}");
    }

    #[test]
    fn rejects_bad_polynomials() {
        assert!(poly_roots(&[]).is_err());
        assert!(poly_roots(&[1.0, 0.0]).is_err());
        assert!(poly_roots(&[1.0, f64::NAN, 1.0]).is_err());
    }
}
