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
use nalgebra::{DMatrix, DefaultAllocator, Dim, DimDiff, DimSub, OMatrix, U1};

use super::Complex;
use crate::error::{Error, Result};

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
    let scale = power_of_two_scale(m.iter());
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

/// The power of two nearest the largest magnitude among `entries` (1 when all are zero): the
/// matrix divided by it has its largest entry near 1, exactly (a power of two), so that
/// balancing's sums of squares cannot overflow; the eigenvalues are multiplied back by it.
fn power_of_two_scale<'a>(entries: impl Iterator<Item = &'a f64>) -> f64 {
    let amax = entries.fold(0.0f64, |a, v| a.max(v.abs()));
    // 2^round(log2 amax) read off the bits: the exponent, plus one when the significand
    // exceeds sqrt 2 (where log2 passes one half). The significand is never sqrt 2 itself
    // (irrational), but within 1e-12 of it the library's log2 (error below an ulp, at most
    // 2.3e-13 for |log2| < 1024) could round onto the half: there, and outside the normal
    // range, log2 and round decide, as they do for every value.
    let bits = amax.to_bits();
    let biased = (bits >> 52) as i32; // the sign bit is clear
    if (2..=2045).contains(&biased) {
        let significand = f64::from_bits((bits & ((1 << 52) - 1)) | (1023 << 52));
        if (significand - std::f64::consts::SQRT_2).abs() > 1e-12 {
            let rounded = biased + i32::from(significand > std::f64::consts::SQRT_2);
            return f64::from_bits((rounded as u64) << 52);
        }
    }
    power_of_two_scale_by_log2(amax)
}

/// `2^round(log2 amax)` by the library's `log2` (1 for zero).
fn power_of_two_scale_by_log2(amax: f64) -> f64 {
    if amax > 0.0 {
        2f64.powi(amax.log2().round() as i32)
    } else {
        1.0
    }
}

/// What `f` makes of the companion eigenvalues, found on the stack for the short delays most
/// requests have and for the elements' short factors (orders 1 and 2, whose roots place a
/// loop's scan samples).
fn companion_eigenvalues<T>(coeffs: &[f64], f: &impl Fn(&[Complex]) -> T) -> Option<T> {
    macro_rules! fixed {
        ($($n:literal),*) => {
            match coeffs.len() - 1 {
                $($n => small_companion_eigenvalues::<$n>(coeffs).map(|r| f(&r)),)*
                _ => schur_eigenvalues(companion(coeffs), Shape::Hessenberg).map(|r| f(&r)),
            }
        };
    }
    fixed!(1, 2, 3, 4, 5, 6, 7, 8)
}

/// The eigenvalues of the companion matrix of `coeffs` (`N + 1` of them, lowest power first)
/// as [`schur_eigenvalues`] computes them for a Hessenberg matrix, the same operations in the
/// same order, on a fixed-size array: scaled by a power of two, balanced
/// ([`balance_small`]), then the QR iteration ([`super::hqr::hqr`]).
fn small_companion_eigenvalues<const N: usize>(coeffs: &[f64]) -> Option<[Complex; N]> {
    // Column-major, as nalgebra stores it: `c[j][i]` is row i of column j.
    let mut c = [[0.0; N]; N];
    let lead = coeffs[N];
    for (i, &coeff) in coeffs[..N].iter().enumerate() {
        if i + 1 < N {
            c[i][i + 1] = 1.0;
        }
        c[N - 1][i] = -coeff / lead;
    }
    if c.iter().flatten().any(|v| !v.is_finite()) {
        return None;
    }
    let scale = power_of_two_scale(c.iter().flatten());
    c.iter_mut().flatten().for_each(|v| *v /= scale);
    balance_small(&mut c);
    let mut roots = [Complex::new(0.0, 0.0); N];
    super::hqr::hqr(&mut c[..], &mut roots, QR_ITERATIONS_PER_EIGENVALUE)?;
    roots.iter_mut().for_each(|z| *z *= scale);
    roots
        .iter()
        .all(|z| z.re.is_finite() && z.im.is_finite())
        .then_some(roots)
}

/// The squared 2-norm of a column of `N` entries, summed in the order nalgebra's `dotc`
/// sums a column of a fixed-size `N x N` matrix (special forms for 2, 3 and 4 entries,
/// eight accumulators over blocks of 8, one running sum for the rest), so that
/// [`balance_small`] balances exactly as nalgebra does.
fn column_norm_squared<const N: usize>(v: &[f64; N]) -> f64 {
    let sq = |i: usize| v[i] * v[i];
    match N {
        2 => sq(0) + sq(1),
        3 => sq(0) + sq(1) + sq(2),
        4 => (sq(0) + sq(2)) + (sq(1) + sq(3)),
        _ => {
            let mut res = 0.0;
            let blocks = N / 8 * 8;
            for b in (0..blocks).step_by(8) {
                res += sq(b) + sq(b + 4);
                res += sq(b + 1) + sq(b + 5);
                res += sq(b + 2) + sq(b + 6);
                res += sq(b + 3) + sq(b + 7);
            }
            (blocks..N).fold(res, |res, i| res + sq(i))
        }
    }
}

/// Parlett-Reinsch balancing with the 2-norm and radix 2 of the column-major `N x N` matrix
/// `c` (James, Langou and Lowery, "On matrix balancing and eigenvector computation",
/// arXiv:1401.5766, algorithm 3): nalgebra's `balance_parlett_reinsch` with the same
/// operations in the same order, on a fixed-size array (no views, no heap), so that the
/// eigenvalues are the same to the bit.
fn balance_small<const N: usize>(c: &mut [[f64; N]; N]) {
    const RADIX: f64 = 2.0;
    let mut converged = false;
    while !converged {
        converged = true;
        for i in 0..N {
            let mut n_col = column_norm_squared(&c[i]);
            // a row is summed entry by entry, from zero
            let mut n_row = c.iter().fold(0.0, |s, col| s + col[i] * col[i]);
            let mut f = 1.0;
            let s = n_col + n_row;
            n_col = n_col.sqrt();
            n_row = n_row.sqrt();
            // exact: a zero row or column has nothing to balance
            if n_col == 0.0 || n_row == 0.0 {
                continue;
            }
            while n_col < n_row / RADIX {
                n_col *= RADIX;
                n_row /= RADIX;
                f *= RADIX;
            }
            while n_col >= n_row * RADIX {
                n_col /= RADIX;
                n_row *= RADIX;
                f /= RADIX;
            }
            // 0.95: the algorithm's threshold for a step worth taking (nalgebra's)
            if n_col * n_col + n_row * n_row < 0.95 * s {
                converged = false;
                c[i].iter_mut().for_each(|v| *v *= f);
                c.iter_mut().for_each(|col| col[i] /= f);
            }
        }
    }
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
    poly_roots_with(coeffs, &<[Complex]>::to_vec)
}

/// What `f` makes of the roots [`poly_roots`] finds (the same roots, in the same order),
/// without collecting them into a vector when they come from a small companion matrix.
pub(crate) fn poly_roots_with<T>(coeffs: &[f64], f: &impl Fn(&[Complex]) -> T) -> Result<T> {
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
        return Ok(f(&[]));
    }
    crate::cancel::poll()?;
    if let Some(r) = companion_eigenvalues(coeffs, f) {
        return Ok(r);
    }
    crate::cancel::poll()?;
    aberth(coeffs).map(|r| f(&r)).ok_or(Error::NoConvergence {
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
    use nalgebra::SMatrix;
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

    /// The fixed-size route (own balancing, the QR iteration on arrays) against nalgebra's
    /// balancing on a fixed-size matrix followed by the same QR iteration: the same roots to
    /// the bit, for every order it serves, on polynomials whose coefficients span six decades
    /// (so that balancing scales), with zero coefficients among them.
    #[test]
    fn small_companions_match_nalgebras_balancing_bit_for_bit() {
        let mut rnd = crate::stability::test_rng(0x2545_f491_4f6c_dd1d);
        let bits = |r: &[Complex]| -> Vec<(u64, u64)> {
            r.iter().map(|z| (z.re.to_bits(), z.im.to_bits())).collect()
        };
        macro_rules! check {
            ($($n:literal),*) => {$({
                let mut p: Vec<f64> = (0..=$n)
                    .map(|_| {
                        let mag = 10f64.powf(6.0 * rnd() - 3.0);
                        match rnd() {
                            u if u < 0.1 => 0.0,
                            u if u < 0.55 => -mag,
                            _ => mag,
                        }
                    })
                    .collect();
                if p[$n] == 0.0 {
                    p[$n] = 1.0;
                }
                let mut c = SMatrix::<f64, $n, $n>::zeros();
                fill_companion(&mut c, &p);
                let want = schur_eigenvalues(c, Shape::Hessenberg);
                let got = small_companion_eigenvalues::<$n>(&p);
                assert_eq!(want.as_deref().map(bits), got.as_ref().map(|r| bits(r)), "{p:?}");
            })*};
        }
        for _ in 0..500 {
            check!(1, 2, 3, 4, 5, 6, 7, 8);
        }
    }

    /// Orders 1 and 2 (the elements' short factors, whose roots place the scan's samples)
    /// went by the heap matrix before the fixed-size route served them: the same roots to the
    /// bit as that route (a column or row of one or two entries is summed the same way by
    /// both).
    #[test]
    fn orders_one_and_two_match_the_heap_route_bit_for_bit() {
        let mut rnd = crate::stability::test_rng(0x5eed_0f0f_1234_0002);
        let bits = |r: &[Complex]| -> Vec<(u64, u64)> {
            r.iter().map(|z| (z.re.to_bits(), z.im.to_bits())).collect()
        };
        for _ in 0..2000 {
            for n in [1usize, 2] {
                let mut p: Vec<f64> = (0..=n)
                    .map(|_| {
                        let mag = 10f64.powf(6.0 * rnd() - 3.0);
                        if rnd() < 0.5 { -mag } else { mag }
                    })
                    .collect();
                if rnd() < 0.1 {
                    p[0] = 0.0;
                }
                let want = schur_eigenvalues(companion(&p), Shape::Hessenberg);
                let got = match n {
                    1 => small_companion_eigenvalues::<1>(&p).map(|r| r.to_vec()),
                    _ => small_companion_eigenvalues::<2>(&p).map(|r| r.to_vec()),
                };
                assert!(want.is_some(), "{p:?}");
                assert_eq!(want.as_deref().map(bits), got.as_deref().map(bits), "{p:?}");
            }
        }
    }

    /// The scale read off the bits is the one `log2` and `round` give, on random magnitudes
    /// over the whole range and on significands next to sqrt 2, where the two meet.
    #[test]
    fn power_of_two_scale_matches_log2() {
        let mut rnd = crate::stability::test_rng(0x0bad_5eed_1234_5678);
        let near_sqrt2 = |k: i32, ulps: i64| {
            let m = std::f64::consts::SQRT_2.to_bits() as i64 + ulps;
            f64::from_bits(m as u64) * 2f64.powi(k)
        };
        let mut values: Vec<f64> = (0..20_000)
            .map(|_| 2f64.powf(2000.0 * rnd() - 1000.0) * (1.0 + rnd()))
            .collect();
        for k in [-1000, -300, -1, 0, 1, 7, 300, 1000] {
            // within 1e-12 (about 4,500 ulps) log2 decides; beyond, the bits
            values.extend((-20_000..20_000).step_by(7).map(|u| near_sqrt2(k, u)));
            values.extend((-5..=5).map(|u| near_sqrt2(k, u)));
        }
        values.extend([
            0.0,
            1.0,
            2.0,
            f64::MIN_POSITIVE,
            1e-310,
            f64::MAX,
            1e308,
            3e-308,
        ]);
        for v in values {
            let got = power_of_two_scale([v].iter());
            let want = power_of_two_scale_by_log2(v);
            assert_eq!(
                got.to_bits(),
                want.to_bits(),
                "{v:e}: {got:e} against {want:e}"
            );
        }
    }

    #[test]
    fn rejects_bad_polynomials() {
        assert!(poly_roots(&[]).is_err());
        assert!(poly_roots(&[1.0, 0.0]).is_err());
        assert!(poly_roots(&[1.0, f64::NAN, 1.0]).is_err());
    }
}
