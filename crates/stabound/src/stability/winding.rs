//! A certified count of the zeros of a real polynomial inside a circle, by the argument
//! principle.
//!
//! Method: the argument principle with a step control that proves the argument's change
//! between samples (see e.g. Henrici, *Applied and Computational Complex Analysis*, vol. 1,
//! 1974, section 4.6, and the "winding number" root counters built on it), plus Rouché's
//! theorem for the uncertainty of the coefficients themselves.
//!
//! For a real polynomial the change of `arg p(r e^{i theta})` over `0 <= theta <= pi` is `pi`
//! times the number of zeros inside `|z| < r` (the lower half circle mirrors the upper one).
//! From a sample `z_k` the next one is placed where Taylor's theorem still bounds the change
//! of `p` below `|p(z_k)|`, after subtracting the rounding error of the evaluation and the
//! coefficients' own uncertainty:
//!
//! ```text
//! |p(z) - p(z_k)| <= |p'(z_k)| |z - z_k| + M2 |z - z_k|^2 / 2,   M2 = sum i (i-1) |p_i| r^(i-2)
//! ```
//!
//! On each arc `p` then stays in a disc that excludes 0, so the principal value of
//! `arg p(z_{k+1}) / p(z_k)` is the true change, and the coefficients' uncertainty is below
//! `|p|` on the whole circle, so by Rouché's theorem the exact polynomial has the same count.
//! Where a zero lies too close to the circle for that, no count is returned.
//!
//! The cost is a few evaluations of the polynomial's nonzero terms per step: the delay
//! polynomials of this crate have at most seven at any degree, so a count at degree 103
//! costs microseconds where eigenvalues cost milliseconds.

use crate::poly::Complex;

/// Unit roundoff of `f64`.
const U: f64 = f64::EPSILON / 2.0;

/// Most nonzero terms [`zeros_inside`] takes (the crate's polynomials have at most seven).
pub const MAX_TERMS: usize = 16;

/// Powers at most this far apart are reached by repeated multiplication, farther ones by a
/// new `sin_cos` (both within the error model below).
const MAX_GAP: usize = 4;

/// The number of zeros inside `|z| < radius` of the real polynomial `sum c z^i` over the
/// nonzero `terms` `(i, c)` (each power at most once), proven as described in the module
/// documentation, or `None` when it cannot be: a zero within the uncertainty of the circle,
/// more than `max_steps` steps, a zero or non-finite leading term, or non-finite input.
///
/// `coeff_err` bounds the absolute error of every coefficient of the polynomial, including the
/// zero ones, up to the largest power in `terms`. At most [`MAX_TERMS`] terms, sorted by
/// power (else `None`): the method is for sparse polynomials, whose cost per step does not
/// grow with the degree.
pub fn zeros_inside(
    terms: &[(usize, f64)],
    radius: f64,
    coeff_err: f64,
    max_steps: usize,
) -> Option<usize> {
    let degree = terms.last()?.0;
    if terms.len() > MAX_TERMS || !terms.windows(2).all(|w| w[0].0 < w[1].0) {
        return None;
    }
    if !(radius > 0.0 && radius.is_finite() && coeff_err >= 0.0 && coeff_err.is_finite()) {
        return None;
    }
    // An exactly zero leading term means the degree is not what `terms` says: refused, not
    // a tolerance question.
    if terms.iter().any(|t| !t.1.is_finite()) || terms[terms.len() - 1].1 == 0.0 {
        return None;
    }
    let r = radius;
    let nterms = terms.len() as f64;
    // Per term: c r^i (for p) and i c r^(i-1) (for p'), computed once.
    let mut cp = [0.0f64; MAX_TERMS];
    let mut cd = [0.0f64; MAX_TERMS];
    // Size bounds on the circle: sum |p_i| r^i, and for p'' (Taylor's remainder).
    let (mut s0, mut s1, mut m2) = (0.0f64, 0.0f64, 0.0f64);
    // Evaluation error: z^i = r^i w^i with w^i from sin_cos of the rounded angle i theta
    // (absolute angle error up to i pi u) or from a few products by w (3 u each), the sum one
    // rounding per term: (i pi + 8 + nterms) u per unit of |p_i| r^i, doubled for the complex
    // products, bounds it; likewise for p'.
    let (mut h0, mut h1) = (0.0f64, 0.0f64);
    for (k, &(i, c)) in terms.iter().enumerate() {
        let fi = i as f64;
        let ri = r.powi(i as i32);
        let ri1 = if i >= 1 { r.powi(i as i32 - 1) } else { 0.0 };
        cp[k] = c * ri;
        cd[k] = fi * c * ri1;
        s0 += c.abs() * ri;
        s1 += fi * c.abs() * ri1;
        if i >= 2 {
            m2 += fi * (fi - 1.0) * c.abs() * r.powi(i as i32 - 2);
        }
        let w = 2.0 * (fi * std::f64::consts::PI + 8.0 + nterms + 3.0 * MAX_GAP as f64) * U;
        h0 += w * c.abs() * ri;
        h1 += w * fi * c.abs() * ri1;
    }
    // |p| <= s0 on the circle: below 1e150 the squares in `norm` cannot overflow.
    if !(s0 < 1e150 && s1 < 1e150 && m2.is_finite()) {
        return None;
    }
    // Rounding of these sums is a few ulps; 1e-12 relative covers it with room.
    let m2 = m2 * (1.0 + 1e-12);
    let (h0, h1) = (h0 * (1.0 + 1e-12), h1 * (1.0 + 1e-12));
    // Every coefficient uncertain by coeff_err: sum over all powers of coeff_err r^i.
    let mut e_in = 0.0;
    let mut ri = 1.0;
    for _ in 0..=degree {
        e_in += coeff_err * ri;
        ri *= r;
    }
    let e_in = e_in * (1.0 + 1e-12);

    // p and p' at r e^{i theta}: p' = conj(w) sum i c r^(i-1) w^i, as 1/w = conj(w).
    let eval = |theta: f64| -> (Complex, Complex) {
        let (s, co) = theta.sin_cos();
        let w = Complex::new(co, s);
        let (mut p, mut dp) = (Complex::new(0.0, 0.0), Complex::new(0.0, 0.0));
        let mut pw = Complex::new(1.0, 0.0);
        let mut at = 0usize;
        for (k, &(i, _)) in terms.iter().enumerate() {
            if i - at <= MAX_GAP {
                for _ in at..i {
                    pw *= w;
                }
            } else {
                let (s, co) = (i as f64 * theta).sin_cos();
                pw = Complex::new(co, s);
            }
            at = i;
            p += pw * cp[k];
            dp += pw * cd[k];
        }
        (p, dp * w.conj())
    };

    let mut theta = 0.0f64;
    let (mut val, mut der) = eval(0.0);
    let mut total = 0.0f64;
    let mut steps = 0usize;
    loop {
        // Room left above the evaluation error and the coefficients' uncertainty. The arc may
        // use all but 2 h0 of it: then the exact value at its far end is more than h0 from 0,
        // so the computed one (within h0) is not 0, and both lie in a disc around the exact
        // p(z_k) that excludes 0, where the principal argument is the true change.
        let room = norm(val) - h0 - e_in;
        if room.is_nan() || room <= 2.0 * h0 {
            return None;
        }
        let budget = (room - 2.0 * h0) * (1.0 - 1e-12);
        let a = norm(der) + h1;
        // largest chord x with a x + m2 x^2 / 2 <= budget
        let x = 2.0 * budget / (a + (a * a + 2.0 * m2 * budget).sqrt());
        // An arc of angle x / r from z_k has every point within chord 2 r sin(h/2) <= x of
        // z_k. Taking 1e-15 less covers the rounding of theta + h (theta + h <= 4, whose ulp
        // is 8.9e-16, so the sum is off by at most 4.5e-16), and 1e-12 relative the
        // rounding of x / r.
        let h = x / r * (1.0 - 1e-12) - 1e-15;
        if h.is_nan() || h < 1e-13 {
            return None;
        }
        steps += 1;
        if steps > max_steps {
            return None;
        }
        let next = (theta + h).min(std::f64::consts::PI);
        let (v, d) = eval(next);
        // the change of arg along the arc, exact up to rounding (both ends in a disc that
        // excludes 0)
        total += (v * val.conj()).arg();
        if next >= std::f64::consts::PI {
            break;
        }
        theta = next;
        val = v;
        der = d;
    }
    let n = total / std::f64::consts::PI;
    let k = n.round();
    // The count is an integer in exact arithmetic; the sum of steps' rounding is far below a
    // quarter turn. Anything else is a failure of the assumptions, not a count.
    if (n - k).abs() > 0.25 || k < 0.0 || k > degree as f64 {
        return None;
    }
    Some(k as usize)
}

/// `|z|` without `hypot`'s scaling, for values below 1e150 (checked by the caller).
fn norm(z: Complex) -> f64 {
    (z.re * z.re + z.im * z.im).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dense(coeffs: &[f64]) -> Vec<(usize, f64)> {
        coeffs
            .iter()
            .enumerate()
            .filter(|(_, c)| c.abs() > 0.0)
            .map(|(i, &c)| (i, c))
            .collect()
    }

    /// Coefficients (lowest first) of prod (z - r_k) over conjugate pairs and real roots.
    fn from_roots(pairs: &[(f64, f64)], reals: &[f64]) -> Vec<f64> {
        let mut p = vec![1.0];
        let mul = |p: &[f64], f: &[f64]| {
            let mut q = vec![0.0; p.len() + f.len() - 1];
            for (i, a) in p.iter().enumerate() {
                for (j, b) in f.iter().enumerate() {
                    q[i + j] += a * b;
                }
            }
            q
        };
        for &(m, t) in pairs {
            p = mul(&p, &[m * m, -2.0 * m * t.cos(), 1.0]);
        }
        for &r in reals {
            p = mul(&p, &[-r, 1.0]);
        }
        p
    }

    #[test]
    fn counts_random_known_roots() {
        // Degree up to 15 (16 terms), roots of modulus 0.1 to 1.9; circles of random radius
        // at least 2 % away from every root modulus. The count is known from the roots.
        let mut rnd = crate::stability::test_rng(0x1234_5678_9abc_def1_u64);
        let mut checked = 0;
        while checked < 2000 {
            let npairs = (rnd() * 7.0) as usize;
            let nreal = 1 + (rnd() * 2.0) as usize;
            let pairs: Vec<(f64, f64)> = (0..npairs)
                .map(|_| (0.1 + 1.8 * rnd(), std::f64::consts::PI * rnd()))
                .collect();
            let reals: Vec<f64> = (0..nreal)
                .map(|_| (0.1 + 1.8 * rnd()) * if rnd() < 0.5 { -1.0 } else { 1.0 })
                .collect();
            let r = 0.05 + 2.0 * rnd();
            let mods = pairs
                .iter()
                .map(|p| p.0)
                .chain(reals.iter().map(|x| x.abs()));
            if mods.clone().any(|m| (m - r).abs() < 0.02 * r) {
                continue;
            }
            let want = pairs.iter().filter(|p| p.0 < r).count() * 2
                + reals.iter().filter(|x| x.abs() < r).count();
            let p = dense(&from_roots(&pairs, &reals));
            let got = zeros_inside(&p, r, 1e-15, 100_000);
            assert_eq!(got, Some(want), "{pairs:?} {reals:?} r = {r}");
            checked += 1;
        }
    }

    #[test]
    fn sparse_high_degree() {
        // z^n - a^n: n zeros of modulus a, for n up to the crate's largest degree.
        for n in [5usize, 50, 200, 504] {
            for a in [0.5f64, 0.97, 1.3] {
                let p = [(0, -a.powi(n as i32)), (n, 1.0)];
                let cap = 64 * n + 1000;
                assert_eq!(zeros_inside(&p, a * 1.01, 0.0, cap), Some(n), "n {n} a {a}");
                assert_eq!(zeros_inside(&p, a * 0.99, 0.0, cap), Some(0), "n {n} a {a}");
            }
        }
    }

    #[test]
    fn uncertain_coefficients_refuse_a_count() {
        // z - 0.999 against the unit circle: the zero is 1e-3 inside. With coefficients
        // uncertain by 1e-2 the exact polynomial may have it outside: no count.
        let p = [(0, -0.999), (1, 1.0)];
        assert_eq!(zeros_inside(&p, 1.0, 1e-6, 10_000), Some(1));
        assert_eq!(zeros_inside(&p, 1.0, 1e-2, 10_000), None);
        // bad input
        assert_eq!(zeros_inside(&[], 1.0, 0.0, 10), None);
        assert_eq!(zeros_inside(&[(0, 1.0), (1, f64::NAN)], 1.0, 0.0, 10), None);
        assert_eq!(zeros_inside(&[(1, 1.0), (0, 1.0)], 1.0, 0.0, 10), None);
        assert_eq!(zeros_inside(&p, -1.0, 0.0, 10), None);
        // a step cap too small to go round
        assert_eq!(zeros_inside(&[(0, -0.5), (200, 1.0)], 1.0, 0.0, 10), None);
    }

    #[test]
    fn counts_known_roots() {
        // (z - 0.5)(z + 0.9)(z^2 + 0.81): roots 0.5, -0.9, +-0.9i
        let p = dense(&[-0.3645, 0.324, 0.36, 0.4, 1.0]);
        assert_eq!(zeros_inside(&p, 1.0, 0.0, 10_000), Some(4));
        assert_eq!(zeros_inside(&p, 0.7, 0.0, 10_000), Some(1));
        assert_eq!(zeros_inside(&p, 0.3, 0.0, 10_000), Some(0));
        // a zero on the circle: no count
        assert_eq!(zeros_inside(&p, 0.9, 0.0, 10_000), None);
        // z^100 - 0.5: all 100 zeros at radius 0.5^(1/100) = 0.99309
        let q = [(0, -0.5), (100, 1.0)];
        assert_eq!(zeros_inside(&q, 1.0, 1e-16, 100_000), Some(100));
        assert_eq!(zeros_inside(&q, 0.99, 1e-16, 100_000), Some(0));
    }
}
