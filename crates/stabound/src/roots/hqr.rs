//! Eigenvalues of an upper Hessenberg matrix, without the Schur vectors.
//!
//! Method: the implicit double-shift (Francis) QR iteration with EISPACK's deflation test and
//! exceptional shifts, accumulating no transformations (EISPACK `hqr`; Golub and Van Loan,
//! *Matrix Computations*, 4th ed., algorithm 7.5.2; Press et al., *Numerical Recipes*, 3rd ed.,
//! section 11.6). A companion matrix is already upper Hessenberg, so its eigenvalues need
//! neither the reduction to Hessenberg form nor the orthogonal factor `Q` that a full Schur
//! decomposition (nalgebra's) computes and that root finding throws away.
//!
//! One iteration ([`hqr`]) serves two storages ([`Columns`]): the one column-major slice of a
//! heap matrix of any order ([`hessenberg_eigenvalues`]), its columns cut from it on demand,
//! and the fixed-size arrays of the small companion matrices (`[[f64; N]; N]`), whose
//! constant column length lets the compiler drop most bounds checks.

use super::Complex;
use std::ops::Range;

/// The eigenvalues of the `n x n` upper Hessenberg matrix stored column-major in `a`
/// (overwritten), or `None` when an eigenvalue has not converged after `max_iterations`
/// double-shift sweeps of its own (exceptional shifts every 10 of them), or on a non-finite
/// intermediate.
///
/// Entries below the first subdiagonal are ignored.
///
/// # Panics
///
/// If `a.len() < n * n` (a caller bug, not user input).
pub fn hessenberg_eigenvalues(
    a: &mut [f64],
    n: usize,
    max_iterations: usize,
) -> Option<Vec<Complex>> {
    let mut a = ColumnMajor {
        a: &mut a[..n * n],
        n,
    };
    let mut roots = vec![Complex::new(0.0, 0.0); n];
    hqr(&mut a, &mut roots, max_iterations)?;
    Some(roots)
}

/// The storage of a square matrix's columns as [`hqr`] reaches them: entries, runs of whole
/// columns, and a column with its next two.
pub(crate) trait Columns {
    /// The matrix's order.
    fn order(&self) -> usize;
    /// Row `i` of column `j` (zero-based).
    fn entry(&mut self, i: usize, j: usize) -> &mut f64;
    /// `f` on each of the columns `cols`, in order.
    fn each_column(&mut self, cols: Range<usize>, f: impl FnMut(&mut [f64]));
    /// Columns `j` and `j + 1`.
    fn pair(&mut self, j: usize) -> (&mut [f64], &mut [f64]);
    /// Columns `j`, `j + 1` and `j + 2` (the third may run on past its column: only its
    /// first entries, as many as the others have, are read).
    fn triple(&mut self, j: usize) -> (&mut [f64], &mut [f64], &mut [f64]);
}

/// One column-major slice of a heap matrix, its columns cut from it on demand: an entry by
/// index arithmetic, a run of columns by one subslice.
struct ColumnMajor<'a> {
    /// `n * n` entries, column after column.
    a: &'a mut [f64],
    /// The order.
    n: usize,
}

impl Columns for ColumnMajor<'_> {
    #[inline(always)]
    fn order(&self) -> usize {
        self.n
    }
    #[inline(always)]
    fn entry(&mut self, i: usize, j: usize) -> &mut f64 {
        &mut self.a[i + j * self.n]
    }
    #[inline(always)]
    fn each_column(&mut self, cols: Range<usize>, f: impl FnMut(&mut [f64])) {
        let n = self.n;
        self.a[cols.start * n..cols.end * n]
            .chunks_exact_mut(n)
            .for_each(f);
    }
    #[inline(always)]
    fn pair(&mut self, j: usize) -> (&mut [f64], &mut [f64]) {
        let (c0, c1, _) = self.triple(j);
        (c0, c1)
    }
    #[inline(always)]
    fn triple(&mut self, j: usize) -> (&mut [f64], &mut [f64], &mut [f64]) {
        let n = self.n;
        let (left, right) = self.a.split_at_mut((j + 1) * n);
        let (next, after) = right.split_at_mut(n);
        (&mut left[j * n..], next, after)
    }
}

/// Columns each of their own storage, such as the fixed-size arrays `[[f64; N]; N]` of the
/// small companion matrices, whose constant length lets the compiler drop bounds checks.
impl<C: AsMut<[f64]>> Columns for [C] {
    #[inline(always)]
    fn order(&self) -> usize {
        self.len()
    }
    #[inline(always)]
    fn entry(&mut self, i: usize, j: usize) -> &mut f64 {
        &mut self[j].as_mut()[i]
    }
    #[inline(always)]
    fn each_column(&mut self, cols: Range<usize>, mut f: impl FnMut(&mut [f64])) {
        for col in &mut self[cols] {
            f(col.as_mut());
        }
    }
    #[inline(always)]
    fn pair(&mut self, j: usize) -> (&mut [f64], &mut [f64]) {
        let (left, right) = self.split_at_mut(j + 1);
        (left[j].as_mut(), right[0].as_mut())
    }
    #[inline(always)]
    fn triple(&mut self, j: usize) -> (&mut [f64], &mut [f64], &mut [f64]) {
        let (left, right) = self.split_at_mut(j + 1);
        let (next, after) = right.split_at_mut(1);
        (left[j].as_mut(), next[0].as_mut(), after[0].as_mut())
    }
}

/// The QR iteration of [`hessenberg_eigenvalues`] on the columns `a` of an upper Hessenberg
/// matrix (overwritten), writing the eigenvalues into `roots` (as long as the order); `None`
/// as [`hessenberg_eigenvalues`].
///
/// # Panics
///
/// If `roots` is shorter than the order (a caller bug, not user input).
#[inline(always)]
pub(crate) fn hqr<M: Columns + ?Sized>(
    a: &mut M,
    roots: &mut [Complex],
    max_iterations: usize,
) -> Option<()> {
    let n = a.order();
    // One-based indices, as in the EISPACK and Numerical Recipes listings this follows:
    // `h!(i, j)` is row i of column j.
    macro_rules! h {
        ($i:expr, $j:expr) => {
            *a.entry($i - 1, $j - 1)
        };
    }
    let mut anorm = 0.0;
    for i in 1..n + 1 {
        for j in i.saturating_sub(1).max(1)..n + 1 {
            anorm += h!(i, j).abs();
        }
    }
    if !anorm.is_finite() {
        return None;
    }
    let mut nn = n;
    let mut t = 0.0; // accumulated exceptional shift
    while nn >= 1 {
        // never true (nn only falls from n): a guard that tells the compiler every index
        // below is within the columns, so that it checks no bound of its own
        if crate::cancel::stopped() || nn > n {
            return None;
        }
        let mut its = 0;
        loop {
            // Look for a single small subdiagonal element: where the matrix splits.
            let mut l = 1;
            for ll in (2..nn + 1).rev() {
                let mut s = h!(ll - 1, ll - 1).abs() + h!(ll, ll).abs();
                // Both neighbours exactly zero: compare with the matrix norm instead.
                if s == 0.0 {
                    s = anorm;
                }
                // EISPACK's test, |h| negligible beside its diagonal neighbours: below one
                // rounding unit of their size.
                if h!(ll, ll - 1).abs() <= 0.5 * f64::EPSILON * s {
                    h!(ll, ll - 1) = 0.0;
                    l = ll;
                    break;
                }
            }
            let mut x = h!(nn, nn);
            if l == nn {
                // One root found.
                roots[nn - 1] = Complex::new(x + t, 0.0);
                nn -= 1;
                break;
            }
            let mut y = h!(nn - 1, nn - 1);
            let mut w = h!(nn, nn - 1) * h!(nn - 1, nn);
            if l == nn - 1 {
                // Two roots: of the trailing 2 x 2 block.
                let p = 0.5 * (y - x);
                let q = p * p + w;
                let z = q.abs().sqrt();
                x += t;
                if q >= 0.0 {
                    let z = p + z.copysign(p);
                    let second = if z.abs() > 0.0 { x - w / z } else { x + z };
                    roots[nn - 2] = Complex::new(x + z, 0.0);
                    roots[nn - 1] = Complex::new(second, 0.0);
                } else {
                    roots[nn - 2] = Complex::new(x + p, -z);
                    roots[nn - 1] = Complex::new(x + p, z);
                }
                nn -= 2;
                break;
            }
            if its >= max_iterations {
                return None;
            }
            if its > 0 && its % 10 == 0 {
                // Exceptional shift: breaks the cycles of the standard shifts.
                t += x;
                for i in 1..=nn {
                    h!(i, i) -= x;
                }
                let s = h!(nn, nn - 1).abs() + h!(nn - 1, nn - 2).abs();
                x = 0.75 * s;
                y = x;
                w = -0.4375 * s * s;
            }
            its += 1;
            // Look for two consecutive small subdiagonal elements: where the sweep starts.
            let mut m = nn - 2;
            let (mut p, mut q, mut r);
            loop {
                let z = h!(m, m);
                let rr = x - z;
                let ss = y - z;
                p = (rr * ss - w) / h!(m + 1, m) + h!(m, m + 1);
                q = h!(m + 1, m + 1) - z - rr - ss;
                r = h!(m + 2, m + 1);
                // Scaled to avoid overflow; one reciprocal instead of three divisions, which
                // are on the iteration's critical path.
                let inv = 1.0 / (p.abs() + q.abs() + r.abs());
                p *= inv;
                q *= inv;
                r *= inv;
                if m == l {
                    break;
                }
                let u = h!(m, m - 1).abs() * (q.abs() + r.abs());
                let v = p.abs() * (h!(m - 1, m - 1).abs() + z.abs() + h!(m + 1, m + 1).abs());
                if u <= 0.5 * f64::EPSILON * v {
                    break;
                }
                m -= 1;
            }
            if !(p.is_finite() && q.is_finite() && r.is_finite()) {
                return None;
            }
            for i in m + 2..nn + 1 {
                h!(i, i - 2) = 0.0;
                if i != m + 2 {
                    h!(i, i - 3) = 0.0;
                }
            }
            // The double-shift QR sweep on rows and columns l..=nn, chasing the bulge.
            for k in m..nn {
                if k != m {
                    p = h!(k, k - 1);
                    q = h!(k + 1, k - 1);
                    r = if k != nn - 1 { h!(k + 2, k - 1) } else { 0.0 };
                    x = p.abs() + q.abs() + r.abs();
                    // An exact zero column means nothing to eliminate (a guard, not a tolerance).
                    if x != 0.0 {
                        let inv = 1.0 / x;
                        p *= inv;
                        q *= inv;
                        r *= inv;
                    }
                }
                let s = (p * p + q * q + r * r).sqrt().copysign(p);
                // Exactly zero only for a zero vector: no reflector to apply.
                if s == 0.0 {
                    continue;
                }
                if k == m {
                    if l != m {
                        h!(k, k - 1) = -h!(k, k - 1);
                    }
                } else {
                    h!(k, k - 1) = -s * x;
                }
                p += s;
                let (inv_s, inv_p) = (1.0 / s, 1.0 / p);
                x = p * inv_s;
                y = q * inv_s;
                let z = r * inv_s;
                q *= inv_p;
                r *= inv_p;
                // The reflector from the left on rows k..k+2 of columns k..=nn, then from the
                // right on columns k..k+2 of rows l..=min(nn, k + 3): the same operations in
                // the same order as the listings, on column slices (no index arithmetic or
                // bounds check per entry), the last reflector of a sweep with two rows.
                let three = k != nn - 1;
                if three {
                    a.each_column(k - 1..nn, |col| {
                        let c = &mut col[k - 1..k + 2];
                        let mut p = c[0] + q * c[1];
                        p += r * c[2];
                        c[2] -= p * z;
                        c[1] -= p * y;
                        c[0] -= p * x;
                    });
                } else {
                    a.each_column(k - 1..nn, |col| {
                        let c = &mut col[k - 1..k + 1];
                        let p = c[0] + q * c[1];
                        c[1] -= p * y;
                        c[0] -= p * x;
                    });
                }
                let rows = l - 1..nn.min(k + 3);
                if three {
                    let (c0, c1, c2) = a.triple(k - 1);
                    let (c0, c1, c2) =
                        (&mut c0[rows.clone()], &mut c1[rows.clone()], &mut c2[rows]);
                    for ((a0, a1), a2) in c0.iter_mut().zip(c1.iter_mut()).zip(c2.iter_mut()) {
                        let mut p = x * *a0 + y * *a1;
                        p += z * *a2;
                        *a2 -= p * r;
                        *a1 -= p * q;
                        *a0 -= p;
                    }
                } else {
                    let (c0, c1) = a.pair(k - 1);
                    let (c0, c1) = (&mut c0[rows.clone()], &mut c1[rows]);
                    for (a0, a1) in c0.iter_mut().zip(c1.iter_mut()) {
                        let p = x * *a0 + y * *a1;
                        *a1 -= p * q;
                        *a0 -= p;
                    }
                }
            }
            if l >= nn - 1 {
                break;
            }
        }
    }
    Some(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn companion(coeffs: &[f64]) -> Vec<f64> {
        let m = coeffs.len() - 1;
        let mut a = vec![0.0; m * m];
        for i in 0..m {
            if i + 1 < m {
                a[(i + 1) + i * m] = 1.0;
            }
            a[i + (m - 1) * m] = -coeffs[i] / coeffs[m];
        }
        a
    }

    fn sorted(mut v: Vec<Complex>) -> Vec<Complex> {
        v.sort_by(|a, b| a.re.total_cmp(&b.re).then(a.im.total_cmp(&b.im)));
        v
    }

    #[test]
    fn known_roots() {
        // (z - 0.5)(z + 0.9)(z^2 + 0.81): roots 0.5, -0.9, +-0.9i
        let p = [-0.3645, 0.324, 0.36, 0.4, 1.0];
        let roots = sorted(hessenberg_eigenvalues(&mut companion(&p), 4, 40).unwrap());
        let want = [(-0.9, 0.0), (0.0, -0.9), (0.0, 0.9), (0.5, 0.0)];
        for (r, (re, im)) in roots.iter().zip(want) {
            assert!(
                (r.re - re).abs() < 1e-12 && (r.im - im).abs() < 1e-12,
                "{r}"
            );
        }
    }

    #[test]
    fn general_hessenberg_matches_its_characteristic_polynomial() {
        // A full upper Hessenberg matrix, not a companion: each eigenvalue must make
        // det(A - z I) vanish, checked through the Hessenberg determinant recurrence.
        let n = 6;
        let mut a = vec![0.0; n * n];
        for j in 0..n {
            for i in 0..n.min(j + 2) {
                a[i + j * n] = ((i * 7 + j * 3) % 11) as f64 / 5.0 - 1.0;
            }
        }
        let orig = a.clone();
        let roots = hessenberg_eigenvalues(&mut a, n, 40).unwrap();
        assert_eq!(roots.len(), n);
        for z in roots {
            // Gaussian elimination without pivoting on the Hessenberg A - zI, complex.
            let mut m: Vec<Complex> = orig.iter().map(|&v| Complex::new(v, 0.0)).collect();
            for i in 0..n {
                m[i + i * n] -= z;
            }
            let mut det = Complex::new(1.0, 0.0);
            for k in 0..n {
                let piv = m[k + k * n];
                det *= piv;
                if k + 1 < n && piv.norm() > 0.0 {
                    let f = m[(k + 1) + k * n] / piv;
                    for j in k..n {
                        let v = m[k + j * n];
                        m[(k + 1) + j * n] -= f * v;
                    }
                }
            }
            assert!(det.norm() < 1e-10, "det(A - zI) = {det} at {z}");
        }
    }

    #[test]
    fn random_companions_give_roots_with_small_backward_error() {
        // 3000 random polynomials of degree 3 to 30, coefficients over six decades with
        // random signs: every eigenvalue must be a root of p to a small relative residual
        // |p(z)| / sum |p_i| |z|^i (independent of any other root finder), and all of them
        // must converge within the cap.
        let mut rnd = crate::stability::test_rng(0x9e37_79b9_7f4a_7c15_u64);
        for trial in 0..3000 {
            let m = 3 + trial % 28;
            let mut p: Vec<f64> = (0..m)
                .map(|_| {
                    let mag = 10f64.powf(6.0 * rnd() - 3.0);
                    if rnd() < 0.5 { -mag } else { mag }
                })
                .collect();
            p.push(1.0);
            // balanced first, as `eigen` does: unbalanced, the backward error is relative to
            // the norm of a matrix whose entries span six decades
            let mut a = nalgebra::DMatrix::from_column_slice(m, m, &companion(&p));
            nalgebra::linalg::balancing::balance_parlett_reinsch(&mut a);
            let roots = hessenberg_eigenvalues(a.as_mut_slice(), m, 40)
                .unwrap_or_else(|| panic!("no convergence, trial {trial}"));
            assert_eq!(roots.len(), m);
            for z in roots {
                let (mut val, mut size) = (Complex::new(0.0, 0.0), 0.0);
                for &c in p.iter().rev() {
                    val = val * z + c;
                    size = size * z.norm() + c.abs();
                }
                // 1e-8: eigenvalues are backward stable for the matrix, not coefficientwise for
                // the polynomial, so this ratio reaches 1e-9 here, for nalgebra's Schur as for
                // this code (8.7e-10 and 3.6e-10 worst over these trials); a wrong root has
                // a ratio of order 1.
                assert!(
                    val.norm() <= 1e-8 * size,
                    "trial {trial}: residual {:e}",
                    val.norm() / size
                );
            }
        }
    }

    #[test]
    fn non_finite_input_is_refused() {
        let mut a = companion(&[f64::NAN, 0.0, 1.0]);
        assert!(hessenberg_eigenvalues(&mut a, 2, 40).is_none());
    }
}
