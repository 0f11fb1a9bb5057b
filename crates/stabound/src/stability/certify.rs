//! Verdicts that hold for every polynomial within the rounding of the computed coefficients.
//!
//! The coefficients of `q` carry rounding from the discretization (`exp`, `expm1`, the series
//! of `phi2`) and from their assembly out of the wall. [`Enclosure`] bounds that error for
//! every coefficient separately, so the exact polynomial of the model lies in the box
//! `|q_i - q~_i| <= e_i` around the computed one. The two tests here decide only what holds
//! for the whole box:
//!
//! - [`binomial_unstable`]: if every root of a monic polynomial of degree `n` lies in
//!   `|z| <= R`, then its coefficients are elementary symmetric functions of the roots and
//!   `|c_k| <= binom(n, k) R^(n-k)`. A coefficient above that bound (by more than its error)
//!   proves a root outside `R`. It costs a few operations and decides the walls whose
//!   coefficients are too large for any other test in `f64` (stiffness near `1e308`).
//! - [`disk_verdict`]: inclusion discs around approximate roots (Braess and Hadeler,
//!   "Simultaneous inclusion of the zeros of a polynomial", Numer. Math. 21, 1973; the
//!   Gerschgorin form of Carstensen, "Inclusion of the roots of a polynomial based on
//!   Gerschgorin's theorem", Numer. Math. 59, 1991). For distinct approximations `z_i` of the
//!   roots of a monic `p`, `p` is the characteristic polynomial of `diag(z) - W 1^T` with the
//!   Weierstrass corrections `W_i = p(z_i) / prod_{j != i} (z_i - z_j)`, so by Gerschgorin's
//!   theorem the discs `|z - z_i| <= n |W_i|` contain all roots, and each connected union of
//!   `k` discs exactly `k` of them. With `|p(z_i)|` bounded over the whole box (evaluation
//!   rounding plus `sum e_k |z_i|^k`) the discs hold for every polynomial in it. A near-double
//!   root has `|W_i|` near `sqrt(eps)`: its discs then straddle the band and the test gives up,
//!   which is the truth (the verdict there is decided by rounding).
//!
//! All bounds are upper bounds computed in round-to-nearest with explicit slack: every sum
//! or product below has at most a few thousand terms, each rounding adds at most `u = 2^-53`
//! relative, so a factor `1 + 1e-6` covers the rounding of the bounds themselves with room.

use crate::model::PaperDiscretization;
use crate::params::Wall;
use crate::poly::{Complex, PaperPoly};

/// Unit roundoff of `f64`.
const U: f64 = f64::EPSILON / 2.0;

/// Relative error bound of each discretization value (`c`, `p1`, `g0x`, `g0v`, `g1x`, `g1v`).
///
/// `exp` and `expm1` are within one ulp (`2 u`); `phi1` adds the rounding of `delta tau` and
/// one division (`4 u`); the 24-term series of `phi2` has at most `26 u` times the sum of the
/// terms' moduli, which is at most twice the sum, plus `tau^2` (`54 u` in all); `g1x` and
/// `g1v` are sums and products of those with positive terms (`60 u`). `64 u` covers each.
const RHO: f64 = 64.0 * U;

/// Absolute error allowed besides [`RHO`]: a value that underflows (`exp(-delta)` for
/// `delta > 745`, `phi2` of a tiny fraction) is off by a few subnormal units, not relatively.
const ETA: f64 = 16.0 * f64::from_bits(1);

/// Slack on a computed error bound for the rounding of the bound itself (module docs).
const SLACK: f64 = 1.0 + 1e-6;

/// Componentwise error bounds of the characteristic polynomial's coefficients.
///
/// Built once per plant; [`Enclosure::errors_into`] gives the bounds for one wall. The wall
/// parameters are taken as exact (they are the inputs).
#[derive(Debug, Clone, PartialEq)]
pub struct Enclosure {
    /// Error bounds of the stored `QA`, `QB` coefficients (powers 0 to 3).
    eqa: [f64; 4],
    eqb: [f64; 4],
    /// Error bounds of the stored `Q0` coefficients at powers `low`, `low + 1`, `low + 2`.
    eq0: [f64; 3],
    qa: [f64; 4],
    qb: [f64; 4],
    q0: [f64; 3],
    low: usize,
    len: usize,
    /// `max_i (eqa_i + 4 u |qa_i|)`, the same for `QB`, and for `Q0`: the per-plant parts of
    /// [`Enclosure::max_error`].
    worst: [f64; 3],
}

impl Enclosure {
    /// The error bounds of `poly`'s plant-dependent parts (see the module documentation).
    pub fn new(poly: &PaperPoly) -> Self {
        let PaperDiscretization {
            c,
            p1,
            g0x,
            g0v,
            g1x,
            g1v,
            fractional,
            ..
        } = *poly.discretization();
        let err = |v: f64| RHO * v.abs() + ETA;
        // m2 = g0x, m1 = p1 g0v - c g0x + g1x, m0 = p1 g1v - c g1x: each product of two
        // values off by RHO is off by 2 RHO (+ RHO^2, in the slack), plus ETA times the other
        // factor (at most 1: c <= 1, p1 <= 1), plus three roundings of the sum.
        let e2 = err(g0x);
        let s1 = (p1 * g0v).abs() + (c * g0x).abs() + g1x.abs();
        let e1 = ((2.0 * RHO + 4.0 * U) * s1 + 5.0 * ETA) * SLACK;
        let s0 = (p1 * g1v).abs() + (c * g1x).abs();
        let e0 = ((2.0 * RHO + 4.0 * U) * s0 + 5.0 * ETA) * SLACK;
        let m = [poly.qa(1), poly.qa(2), poly.qa(3)];
        let (eqa, eqb) = if fractional {
            // QA = [0, m0, m1, m2], QB = [-m0, m0 - m1, m1 - m2, m2]
            let (m0, m1) = (m[0], m[1]);
            (
                [0.0, e0, e1, e2],
                [
                    e0,
                    (e0 + e1 + U * (m0 - m1).abs()) * SLACK,
                    (e1 + e2 + U * (m1 - m[2]).abs()) * SLACK,
                    e2,
                ],
            )
        } else {
            // QA = [0, m1, m2, 0], QB = [-m1, m1 - m2, m2, 0]
            let (m1, m2) = (m[0], m[1]);
            (
                [0.0, e1, e2, 0.0],
                [e1, (e1 + e2 + U * (m1 - m2).abs()) * SLACK, e2, 0.0],
            )
        };
        // Q0 = c z^low - (1 + c) z^(low+1) + z^(low+2); the 1 is exact.
        let ec = err(c);
        let eq0 = [ec, (ec + U * (1.0 + c).abs()) * SLACK, 0.0];
        // Q0 = z^low (z - 1)(z - c) has the top power: low = degree - 2 (degree >= 3).
        let low = poly.degree() - 2;
        let qa = [0, 1, 2, 3].map(|i| poly.qa(i));
        let qb = [0, 1, 2, 3].map(|i| poly.qb(i));
        let q0 = [0, 1, 2].map(|k| poly.q0(low + k));
        let worst_of = |e: &[f64], v: &[f64]| {
            e.iter()
                .zip(v)
                .fold(0.0f64, |m, (e, v)| m.max(e + 4.0 * U * v.abs()))
        };
        Self {
            worst: [
                worst_of(&eqa, &qa),
                worst_of(&eqb, &qb),
                worst_of(&eq0, &q0),
            ],
            eqa,
            eqb,
            eq0,
            qa,
            qb,
            q0,
            low,
            len: poly.degree() + 1,
        }
    }

    /// The error bound of coefficient `i` of `q` for `wall`, in units of `scale` (a power of
    /// two, so that walls near the top of the `f64` range give finite bounds): the stored
    /// parts' errors times the wall, plus the three roundings of `q0 + alpha a + beta b`.
    fn error_scaled(&self, wall: &Wall, i: usize, scale: f64) -> f64 {
        let (a, b) = ((wall.alpha() * scale).abs(), (wall.beta() * scale).abs());
        let (mut e, mut size) = (0.0, 0.0);
        if i < 4 {
            e += a * self.eqa[i] + b * self.eqb[i];
            size += a * self.qa[i].abs() + b * self.qb[i].abs();
        }
        if let Some(k) = i.checked_sub(self.low).filter(|&k| k < 3) {
            e += self.eq0[k] * scale;
            size += self.q0[k].abs() * scale;
        }
        (e + 4.0 * U * size) * SLACK
    }

    /// Writes the error bound of every coefficient of `q` for `wall` into `out[..len]` and
    /// returns that slice (infinite where a bound exceeds the range of `f64`).
    ///
    /// # Panics
    ///
    /// If `out` is shorter than the number of coefficients (a caller bug).
    pub fn errors_into<'a>(&self, wall: &Wall, out: &'a mut [f64]) -> &'a [f64] {
        let out = &mut out[..self.len];
        for (i, o) in out.iter_mut().enumerate() {
            *o = self.error_scaled(wall, i, 1.0);
        }
        out
    }

    /// An upper bound on every coefficient's error bound for `wall`, in a few operations
    /// (the hot path of the guarded recursion): the largest `QA`, `QB` and `Q0` parts summed,
    /// which is at least the largest sum.
    pub fn max_error(&self, wall: &Wall) -> f64 {
        let [a, b, c] = self.worst;
        (wall.alpha().abs() * a + wall.beta().abs() * b + c) * SLACK
    }

    /// Coefficient `i` of `q` for `wall` times `scale` (exact scaling by a power of two).
    fn coefficient_scaled(&self, wall: &Wall, i: usize, scale: f64) -> f64 {
        let mut v = 0.0;
        if i < 4 {
            v += (wall.alpha() * scale) * self.qa[i] + (wall.beta() * scale) * self.qb[i];
        }
        if let Some(k) = i.checked_sub(self.low).filter(|&k| k < 3) {
            v += self.q0[k] * scale;
        }
        v
    }
}

/// `2^-600`: coefficients scaled by it cannot overflow (`|alpha|, |beta| < 2^1024` and the
/// stored parts are below `2^10`) and the binomial bounds (below `2^520`) stay normal.
const TINY: f64 = f64::from_bits((1023 - 600) << 52);

/// Whether the coefficient bound proves a root of every polynomial in the enclosure outside
/// `|z| <= radius` (see the module documentation). Only the powers below 4 carry the wall, so
/// only they are tested; the rest of `q` is `Q0`, whose coefficients are at most 2.
pub fn binomial_unstable(enc: &Enclosure, wall: &Wall, radius: f64) -> bool {
    let n = enc.len - 1;
    if !(radius.is_finite() && radius > 0.0) {
        return false;
    }
    // binom(n, k) R^(n-k), built up from k = 0 with upward slack.
    let mut binom = 1.0f64;
    for k in 0..4.min(n) {
        if k > 0 {
            binom *= (n - k + 1) as f64 / k as f64;
        }
        let bound = binom * radius.powi((n - k) as i32) * SLACK * TINY;
        let c = enc.coefficient_scaled(wall, k, TINY).abs() * (1.0 - 1e-6);
        let e = enc.error_scaled(wall, k, TINY);
        // false for NaN
        if c - e > bound {
            return true;
        }
    }
    false
}

/// What the inclusion discs prove.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DiskProof {
    /// Every root of every polynomial in the enclosure is inside `|z| < 1 - margin`.
    Stable,
    /// Every polynomial in the enclosure has a root outside `|z| > 1 + margin`.
    Unstable,
    /// Every polynomial in the enclosure has its spectral radius within `margin` of 1.
    Marginal,
}

/// `x = m 2^e` with `m` in `[1, 2)` for finite nonzero `x` (exact), `(x, 0)` otherwise.
fn split(x: f64) -> (f64, i32) {
    if x == 0.0 || !x.is_finite() {
        return (x, 0);
    }
    let (x, bias) = if x.abs() < f64::MIN_POSITIVE {
        (x * 2f64.powi(64), -64)
    } else {
        (x, 0)
    };
    let bits = x.to_bits();
    let e = ((bits >> 52) & 0x7ff) as i32 - 1023;
    let m = f64::from_bits((bits & !(0x7ffu64 << 52)) | (1023u64 << 52));
    (m, e + bias)
}

/// `x 2^e` without intermediate overflow or underflow (each factor is a normal power of two).
fn ldexp(mut x: f64, mut e: i32) -> f64 {
    while e > 1000 {
        x *= 2f64.powi(1000);
        e -= 1000;
    }
    while e < -1000 {
        x *= 2f64.powi(-1000);
        e += 1000;
    }
    x * 2f64.powi(e)
}

/// A mantissa and a power of two, for products of hundreds of factors (all exact but the
/// products of mantissas, one rounding each).
#[derive(Clone, Copy)]
struct Scaled {
    m: f64,
    e: i32,
}

impl Scaled {
    fn mul(self, x: f64) -> Self {
        let (mx, ex) = split(x);
        let (m, e) = split(self.m * mx);
        Self {
            m,
            e: self.e + ex + e,
        }
    }
}

/// The verdict proven by inclusion discs around `roots` (approximations of the roots of the
/// monic `coeffs`, lowest power first, whose coefficients carry the error bounds `errs`), or
/// `None` when the discs do not decide.
///
/// Exactly zero coefficients with zero error below the lowest nonzero one are a factor
/// `z^j` of the exact polynomial: those `j` roots are zero, and the discs are built for the
/// remaining factor from the `n - j` largest approximations.
pub fn disk_verdict(
    coeffs: &[f64],
    errs: &[f64],
    roots: &[Complex],
    margin: f64,
) -> Option<DiskProof> {
    let n = coeffs.len().checked_sub(1)?;
    // Exact test on purpose: the model's polynomial is monic (its top power comes from Q0 only).
    if n == 0 || roots.len() != n || errs.len() != coeffs.len() || coeffs[n] != 1.0 {
        return None;
    }
    if roots
        .iter()
        .any(|z| !(z.re.is_finite() && z.im.is_finite()))
    {
        return None;
    }
    // Exact zeros with no error are structural: a power of z divides the model's polynomial.
    let j = coeffs
        .iter()
        .zip(errs)
        .take_while(|(c, e)| **c == 0.0 && **e == 0.0)
        .count();
    if j >= n {
        return Some(DiskProof::Stable);
    }
    let coeffs = &coeffs[j..];
    let errs = &errs[j..];
    let mut zs: Vec<Complex> = roots.to_vec();
    zs.sort_by(|a, b| b.norm().total_cmp(&a.norm()));
    zs.truncate(n - j);
    let n = n - j;
    // The thresholds as exact bounds on the real numbers 1 - margin and 1 + margin: one
    // epsilon covers the rounding of the subtraction and the addition.
    let inner = (1.0 - margin) - f64::EPSILON;
    let outer_lo = (1.0 + margin) - f64::EPSILON;
    let outer_hi = (1.0 + margin) + f64::EPSILON;
    let inner_hi = (1.0 - margin) + f64::EPSILON;
    let mut radius = vec![0.0f64; n];
    for (i, &z) in zs.iter().enumerate() {
        let az = z.norm() * (1.0 + 4.0 * U);
        // Horner for p(z), sum |c_k| |z|^k and sum e_k |z|^k.
        let (mut p, mut s, mut e) = (Complex::new(0.0, 0.0), 0.0f64, 0.0f64);
        for k in (0..=n).rev() {
            p = p * z + coeffs[k];
            s = s * az + coeffs[k].abs();
            e = e * az + errs[k];
        }
        // Complex Horner: each step's product is off by sqrt 2 * 2u and the sum by u
        // (Higham, Accuracy and Stability, 2nd ed., 3.6): 8 (n + 1) u of s covers it.
        let num = (p.norm() + 8.0 * (n as f64 + 1.0) * U * s + e) * SLACK;
        if !num.is_finite() {
            return None;
        }
        let mut den = Scaled { m: 1.0, e: 0 };
        for (k, &w) in zs.iter().enumerate() {
            if k != i {
                // |fl(z - w)| is within 4u of |z - w| (two roundings and the modulus).
                den = den.mul((z - w).norm() * (1.0 - 4.0 * U));
            }
        }
        if !(den.m > 0.0 && den.m.is_finite()) {
            return None;
        }
        // n |W_i| = n num / (den.m 2^den.e), rounded up by the slack; the smallest
        // subnormal covers a result that underflows.
        let r = ldexp(n as f64 * num / den.m * SLACK, -den.e) + f64::from_bits(1);
        if !r.is_finite() {
            return None;
        }
        radius[i] = r;
    }
    let far = |i: usize| zs[i].norm() * (1.0 + 4.0 * U) + radius[i];
    let near = |i: usize| zs[i].norm() * (1.0 - 4.0 * U) - radius[i];
    if (0..n).all(|i| far(i) < inner) {
        return Some(DiskProof::Stable);
    }
    // Connected components of the union of discs (discs that might touch are joined).
    let mut comp: Vec<usize> = (0..n).collect();
    fn root(comp: &mut [usize], mut i: usize) -> usize {
        while comp[i] != i {
            comp[i] = comp[comp[i]];
            i = comp[i];
        }
        i
    }
    for a in 0..n {
        for b in a + 1..n {
            let dist = (zs[a] - zs[b]).norm() * (1.0 - 4.0 * U);
            if dist <= (radius[a] + radius[b]) * (1.0 + 4.0 * U) {
                let (ra, rb) = (root(&mut comp, a), root(&mut comp, b));
                comp[ra] = rb;
            }
        }
    }
    let roots_of: Vec<usize> = (0..n).map(|i| root(&mut comp, i)).collect();
    let component_all = |pred: &dyn Fn(usize) -> bool| {
        (0..n).any(|r| roots_of[r] == r && (0..n).filter(|&i| roots_of[i] == r).all(pred))
    };
    // A component entirely outside 1 + margin holds at least one root there.
    if component_all(&|i| near(i) > outer_hi) {
        return Some(DiskProof::Unstable);
    }
    // No root beyond 1 + margin, and a component entirely beyond 1 - margin.
    if (0..n).all(|i| far(i) < outer_lo) && component_all(&|i| near(i) > inner_hi) {
        return Some(DiskProof::Marginal);
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    fn from_roots(roots: &[f64]) -> Vec<f64> {
        let mut p = vec![1.0];
        for &r in roots {
            let mut q = vec![0.0; p.len() + 1];
            for (i, &c) in p.iter().enumerate() {
                q[i + 1] += c;
                q[i] -= r * c;
            }
            p = q;
        }
        p
    }

    fn c(re: f64) -> Complex {
        Complex::new(re, 0.0)
    }

    /// Known roots, approximations slightly off: the discs decide by the known moduli.
    #[test]
    fn discs_decide_known_roots() {
        let p = from_roots(&[0.5, -0.9, 0.99]);
        let errs = vec![1e-16; p.len()];
        let approx = [c(0.5 + 1e-12), c(-0.9), c(0.99 - 1e-13)];
        assert_eq!(
            disk_verdict(&p, &errs, &approx, 1e-9),
            Some(DiskProof::Stable)
        );
        let p = from_roots(&[0.5, -0.9, 1.01]);
        let approx = [c(0.5), c(-0.9), c(1.01 + 1e-13)];
        assert_eq!(
            disk_verdict(&p, &errs, &approx, 1e-9),
            Some(DiskProof::Unstable)
        );
        // a root exactly on the circle, simple: proven within the band
        let p = from_roots(&[0.5, -0.9, 1.0]);
        let approx = [c(0.5), c(-0.9), c(1.0)];
        assert_eq!(
            disk_verdict(&p, &errs, &approx, 1e-9),
            Some(DiskProof::Marginal)
        );
        // coefficient errors too large for the margin: no verdict
        let big = vec![1e-6; p.len()];
        let p = from_roots(&[0.5, -0.9, 0.99999]);
        let approx = [c(0.5), c(-0.9), c(0.99999)];
        assert_eq!(disk_verdict(&p, &big, &approx, 1e-9), None);
    }

    /// A double root 1e-10 inside the circle: its discs are about sqrt(u) wide and straddle
    /// the band, so nothing is proven, whatever the approximations.
    #[test]
    fn near_double_root_is_not_decided() {
        let r = 1.0 - 1e-10;
        let p = from_roots(&[0.3, r, r]);
        let errs: Vec<f64> = p.iter().map(|c| 4.0 * U * c.abs()).collect();
        let approx = [c(0.3), c(r + 1e-8), c(r - 1e-8)];
        assert_eq!(disk_verdict(&p, &errs, &approx, 1e-9), None);
        // and NaN or coinciding approximations prove nothing either
        let approx = [c(0.3), c(r), c(r)];
        assert_eq!(disk_verdict(&p, &errs, &approx, 1e-9), None);
        let approx = [c(0.3), c(f64::NAN), c(r)];
        assert_eq!(disk_verdict(&p, &errs, &approx, 1e-9), None);
    }

    #[test]
    fn binomial_bound_proves_huge_walls_unstable() {
        let poly = PaperPoly::new(&crate::params::Plant::new(0.5, 1.0).unwrap());
        let enc = Enclosure::new(&poly);
        for alpha in [1e10, 1e163, f64::MAX] {
            let w = Wall::new(alpha, 0.0).unwrap();
            assert!(binomial_unstable(&enc, &w, 1.0 + 1e-9), "{alpha}");
        }
        // a stable wall's coefficients are below the bounds (every root is inside)
        let w = Wall::new(0.1, 0.3).unwrap();
        assert!(!binomial_unstable(&enc, &w, 1.0 + 1e-9));
    }

    /// The enclosure contains the polynomial rebuilt in a different order (the paper's
    /// eq. 17 form in `poly`'s tests is the reference there; here: `Q0 + alpha QA + beta QB`
    /// summed term by term), and its bounds are small relative to the coefficients' size.
    #[test]
    fn enclosure_bounds_are_small_and_positive() {
        for (delta, d) in [(0.5, 1.0), (0.0, 0.0), (2.0, 3.4), (1e6, 2.5)] {
            let poly = PaperPoly::new(&crate::params::Plant::new(delta, d).unwrap());
            let enc = Enclosure::new(&poly);
            let w = Wall::new(0.3, -0.2).unwrap();
            let q = poly.coefficients(&w);
            let mut e = vec![0.0; q.len()];
            let e = enc.errors_into(&w, &mut e);
            let size = q.iter().fold(0.0f64, |m, c| m.max(c.abs()));
            for (i, (&ei, &qi)) in e.iter().zip(&q).enumerate() {
                assert!(ei >= 0.0 && ei <= 1e-12 * size, "{delta} {d} {i}: {ei}");
                // a nonzero coefficient is never exact: its bound is positive
                if qi != 0.0 && i + 1 < q.len() {
                    assert!(ei > 0.0, "{delta} {d} {i}");
                }
            }
            let largest = e.iter().fold(0.0f64, |m, x| m.max(*x));
            assert!(enc.max_error(&w) >= largest && enc.max_error(&w) <= 3.0 * largest);
        }
    }
}
