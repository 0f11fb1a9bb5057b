//! The characteristic polynomial of a general [`Loop`] (the model document, docs/MODEL.md,
//! section 8), in the affine form `q = Q0 + alpha QA + beta QB`:
//!
//! ```text
//! q(z) = z^(n+2) D(z) Fd(z) + N(z) (alpha z Fd(z) + beta (z - 1) Fn(z))
//! D(z) = det(z I - Phi),   N(z) = c^T adj(z I - Phi) (G0 z + G1)
//! ```
//!
//! with the structural common powers of `z` divided out: one for a whole-sample delay
//! (`G1 = 0`), one for a first-order low-pass (`Fn = (1 - a) z`). The degree then equals the
//! closed loop's state dimension.
//!
//! Methods:
//!
//! - `D`: La Budde's method on the upper Hessenberg form of `Phi` (Rehman and Ipsen, "La
//!   Budde's method for computing characteristic polynomials", SIAM J. Matrix Anal. Appl.
//!   32(2), 2011): an orthogonal similarity (Householder) followed by a three-term-like
//!   recurrence over the leading principal submatrices, no division, no iteration.
//! - `N`: the adjugate's expansion `adj(z I - Phi) = sum_k B_k z^(s-1-k)` with
//!   `B_k = sum_{j<=k} a_j Phi^(k-j)` (Faddeev's recursion with `D`'s coefficients `a_j`
//!   taken from La Budde instead of traces), so `c^T B_k g = sum_{j<=k} a_j h_(k-j)` with the
//!   Markov parameters `h_i = c^T Phi^i g` (Kailath, *Linear Systems*, 1980, section 2.1).
//!   The state dimension is at most five, where this sum loses no more than the size of its
//!   terms times a few roundings.

use nalgebra::DMatrix;
use nalgebra::linalg::Hessenberg;

use super::Loop;
use super::discrete::GeneralDiscretization;
use crate::error::Result;
use crate::params::Wall;

/// The characteristic polynomial of a loop with elements, built through its discretization:
/// the general route inside [`crate::poly::CharPoly`] (for the paper's loop it gives the
/// closed form's polynomial to rounding, the route the tests compare).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct GeneralPoly {
    disc: GeneralDiscretization,
    q0: Vec<f64>,
    qa: Vec<f64>,
    qb: Vec<f64>,
}

/// Product of two polynomials (lowest power first).
fn conv(a: &[f64], b: &[f64]) -> Vec<f64> {
    // Zeros written after a plain allocation: `vec![0.0; n]` asks the allocator for zeroed
    // memory, about three and a half times a plain allocation's cost at these few
    // coefficients (258 against 74 instructions, callgrind).
    let mut out = Vec::with_capacity(a.len() + b.len() - 1);
    out.resize(a.len() + b.len() - 1, 0.0);
    for (i, ai) in a.iter().enumerate() {
        for (j, bj) in b.iter().enumerate() {
            out[i + j] += ai * bj;
        }
    }
    out
}

/// The characteristic polynomial `det(z I - m)` of a square matrix, lowest power first,
/// by La Budde's method on its Hessenberg form (see the module documentation).
pub(crate) fn char_poly(m: &DMatrix<f64>) -> Vec<f64> {
    let s = m.nrows();
    if s == 0 {
        return vec![1.0];
    }
    let h = Hessenberg::new(m.clone()).h();
    // p_i = characteristic polynomial of the leading i x i block, lowest power first, at
    // `p[i (i + 1) / 2..][..i + 1]` (one buffer for all of them).
    let at = |i: usize| i * (i + 1) / 2;
    let mut p: Vec<f64> = Vec::with_capacity(at(s + 1));
    p.push(1.0);
    for i in 0..s {
        // (z - h_ii) p_{i-1}
        let start = p.len();
        p.resize(start + i + 2, 0.0);
        let (done, next) = p.split_at_mut(start);
        for (k, c) in done[at(i)..].iter().enumerate() {
            next[k + 1] += c;
            next[k] -= h[(i, i)] * c;
        }
        // - sum_{m=1}^{i} h_{i-m, i} (prod of subdiagonals h_{j, j-1}, j = i-m+1..=i) p_{i-m-1}
        let mut sub = 1.0;
        for m in 1..=i {
            sub *= h[(i - m + 1, i - m)];
            let coef = h[(i - m, i)] * sub;
            for (k, c) in done[at(i - m)..at(i - m + 1)].iter().enumerate() {
                next[k] -= coef * c;
            }
        }
    }
    p.drain(..at(s));
    p
}

/// `c^T adj(z I - phi) g`, lowest power first (degree below `s`), from `d = det(z I - phi)`
/// and the Markov parameters (see the module documentation).
fn adjugate_numerator(
    phi: &DMatrix<f64>,
    d: &[f64],
    c: &nalgebra::DVector<f64>,
    g: &nalgebra::DVector<f64>,
) -> Vec<f64> {
    let s = phi.nrows();
    // h_i = c^T phi^i g for i < s
    // (`phi v` into a second buffer, the same products as `phi * v`)
    let mut markov = Vec::with_capacity(s);
    let mut v = g.clone();
    let mut next = g.clone();
    for _ in 0..s {
        markov.push(c.dot(&v));
        phi.mul_to(&v, &mut next);
        std::mem::swap(&mut v, &mut next);
    }
    // a_j: coefficient of z^(s-j) in d
    let a = |j: usize| d[s - j];
    // (zeros written after a plain allocation, as in `conv`)
    let mut out = Vec::with_capacity(s);
    out.resize(s, 0.0);
    for k in 0..s {
        let mut acc = 0.0;
        for j in 0..=k {
            acc += a(j) * markov[k - j];
        }
        out[s - 1 - k] = acc;
    }
    out
}

impl GeneralPoly {
    /// The characteristic polynomial of `lp`.
    pub(crate) fn new(lp: &Loop) -> Result<Self> {
        let disc = GeneralDiscretization::new(lp)?;
        let (phi, c) = (disc.phi(), disc.output());
        let s = phi.nrows();
        let d = char_poly(phi);
        let n0 = adjugate_numerator(phi, &d, c, disc.g0());
        let n1 = adjugate_numerator(phi, &d, c, disc.g1());
        // N = z N0 + N1
        // (zeros written after a plain allocation, as in `conv`)
        let mut num = Vec::with_capacity(s + 1);
        num.resize(s + 1, 0.0);
        for i in 0..s {
            num[i + 1] += n0[i];
            num[i] += n1[i];
        }
        let (fnum, fden) = if lp.filter().is_identity() {
            (vec![1.0], vec![1.0])
        } else {
            (lp.filter().numerator(), lp.filter().denominator())
        };
        let n = lp.plant().whole_samples();
        let dfd = conv(&d, &fden);
        let mut q0 = Vec::with_capacity(n + 2 + dfd.len());
        q0.resize(n + 2, 0.0);
        q0.extend(dfd);
        let fdn = conv(&fden, &num);
        let mut qa = Vec::with_capacity(1 + fdn.len());
        qa.push(0.0);
        qa.extend(fdn);
        let qb = conv(&[-1.0, 1.0], &conv(&fnum, &num));
        // The structural common powers of z: exact zeros by construction (G1 = 0 makes
        // N1 = 0 exactly; the low-pass numerator's constant term is the literal 0).
        let drop =
            usize::from(lp.plant().is_integer_delay()) + usize::from(lp.low_pass_pole().is_some());
        let len = lp.degree() + 1;
        let shape = |v: Vec<f64>| -> Vec<f64> {
            let mut out: Vec<f64> = v.into_iter().skip(drop).collect();
            out.resize(len, 0.0);
            out
        };
        Ok(Self {
            q0: shape(q0),
            qa: shape(qa),
            qb: shape(qb),
            disc,
        })
    }

    /// The discretization the polynomial was built from.
    pub(crate) fn discretization(&self) -> &GeneralDiscretization {
        &self.disc
    }

    /// Degree of `q` (equal to the closed loop's state dimension).
    pub(crate) fn degree(&self) -> usize {
        self.q0.len() - 1
    }

    /// `Q0`, lowest power first (monic: its last coefficient is 1).
    pub(crate) fn q0(&self) -> &[f64] {
        &self.q0
    }

    /// Whether walls move a root at a real point `z` where `q(z) = 0` reads
    /// `a alpha + b beta = r`: the line's normal `(a, b)` is above the rounding of the
    /// coefficients of `QA` and `QB` (`1e-14` of the largest per degree), so the line exists.
    pub(crate) fn wall_moves_root(&self, a: f64, b: f64) -> bool {
        let scale = self
            .qa
            .iter()
            .chain(&self.qb)
            .fold(0.0f64, |m, c| m.max(c.abs()));
        a.hypot(b) > 1e-14 * scale * (self.degree() as f64 + 1.0)
    }

    /// `QA`, the part multiplying `alpha`, lowest power first.
    pub(crate) fn qa(&self) -> &[f64] {
        &self.qa
    }

    /// `QB`, the part multiplying `beta`, lowest power first.
    pub(crate) fn qb(&self) -> &[f64] {
        &self.qb
    }

    /// Writes the `degree + 1` coefficients of `q` for `wall` into `out`, lowest power
    /// first, and returns that slice.
    ///
    /// # Panics
    ///
    /// If `out` is shorter than `degree + 1` (a caller bug, not user input).
    pub(crate) fn coefficients_into<'a>(&self, wall: &Wall, out: &'a mut [f64]) -> &'a [f64] {
        let out = &mut out[..self.q0.len()];
        for (((o, z), a), b) in out.iter_mut().zip(&self.q0).zip(&self.qa).zip(&self.qb) {
            *o = z + wall.alpha() * a + wall.beta() * b;
        }
        out
    }

    /// The coefficients of `q` for `wall`, lowest power first.
    pub(crate) fn coefficients(&self, wall: &Wall) -> Vec<f64> {
        let mut v = vec![0.0; self.q0.len()];
        self.coefficients_into(wall, &mut v);
        v
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// La Budde against the characteristic polynomial of a companion matrix, whose
    /// coefficients are its last column (exact by construction).
    #[test]
    fn char_poly_of_companion() {
        let p = [0.3, -1.2, 0.7, 2.0, 1.0]; // monic, lowest first
        let m = crate::roots::eigen::companion(&p);
        let got = char_poly(&m);
        for (g, w) in got.iter().zip(&p) {
            assert!((g - w).abs() < 1e-14, "{got:?}");
        }
        // and of a dense matrix against the product of (z - lambda) for a triangular one
        // after a similarity: eigenvalues 1, 2, -0.5
        let t = DMatrix::from_row_slice(3, 3, &[1.0, 4.0, -2.0, 0.0, 2.0, 3.0, 0.0, 0.0, -0.5]);
        let v = DMatrix::from_row_slice(3, 3, &[1.0, 2.0, 0.0, 0.0, 1.0, 1.0, 1.0, 0.0, 1.0]);
        let m = &v * t * v.clone().try_inverse().unwrap();
        let got = char_poly(&m);
        // (z - 1)(z - 2)(z + 0.5) = z^3 - 2.5 z^2 + 0.5 z + 1
        let want = [1.0, 0.5, -2.5, 1.0];
        for (g, w) in got.iter().zip(&want) {
            assert!((g - w).abs() < 1e-13, "{got:?}");
        }
    }
}
