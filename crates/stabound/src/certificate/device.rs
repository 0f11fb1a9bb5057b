//! Enclosures of the characteristic polynomial of a loop with elements (`docs/MODEL.md`
//! section 8), for the exact inputs:
//!
//! ```text
//! q(z) = z^(n+2) D(z) Fd(z) + N(z) (alpha z Fd(z) + beta (z - 1) Fn(z))
//! D(z) = det(z I - Phi),   N(z) = c^T adj(z I - Phi) (G0 z + G1)
//! ```
//!
//! with the structural common powers of `z` divided out (one for a whole-sample delay, one
//! for a first-order low-pass).
//!
//! Methods, all in the interval arithmetic of the `interval` module:
//!
//! - The continuous device `A, b, c` from the normalized element parameters (each division
//!   enclosed).
//! - `exp([[A, b], [0, 0]] tau) = [[e^{A tau}, Gamma(tau)], [0, 1]]` (Van Loan 1978) by
//!   scaling and squaring: the matrix `X` is halved `s` times until its infinity norm
//!   `theta` is at most `1/2`, its exponential is the Taylor polynomial of degree
//!   [`TAYLOR_DEGREE`] by Horner's rule plus the remainder, whose every entry is at most
//!   `||X^(K+1) / (K+1)! (1 + X/(K+2) + ...)|| <= theta^(K+1) / (K+1)! / (1 - theta / (K+2))`
//!   in modulus, and zero in the zero rows and columns of `X` (Moler and Van Loan, "Nineteen dubious ways to compute the exponential of a
//!   matrix, twenty-five years later", SIAM Review 45(1), 2003, method 3), and the result is
//!   squared `s` times.
//! - `D` and the adjugate by the Faddeev-LeVerrier recursion `B_0 = I`,
//!   `a_k = -tr(Phi B_(k-1)) / k`, `B_k = Phi B_(k-1) + a_k I`, so that
//!   `adj(z I - Phi) = sum_k B_k z^(s-1-k)` and `D = z^s + a_1 z^(s-1) + ... + a_s`
//!   (Gantmacher, "The Theory of Matrices", vol. 1, ch. IV, section 4). The state dimension is
//!   at most five.

use std::ops::{Add, Div, Mul, Neg, Sub};

use super::interval::{self, Interval};
use super::tangent::{Dual, Dual2, MeanValueForm, Slope};
use super::{FractionFamily, Parts};
use crate::elements::{Encoder, Loop};
use crate::filter::FilterKind;

/// Degree of the Taylor polynomial: at `theta <= 1/2` the remainder is below
/// `2^-19 / 19! / (1 - 1/40) < 2e-23`, far below the unit roundoff of entries near 1.
const TAYLOR_DEGREE: u32 = 18;

/// Degree of the Taylor polynomial of the exponential with second derivatives
/// ([`Scalar::exp_matrix`] for [`Dual2`]), which only the second-order form's second
/// derivatives use (its values and first derivatives are only the steps towards them): at
/// `theta <= 1/8` (`theta` the norm of `X / 2^s`) the remainder of the second derivatives
/// is below `b_k b_l E_7 + c_kl E_8 < 1e-10 b_k b_l + 2e-12 c_kl`, `b_k`, `c_kl` the norms of
/// the first and second derivatives of `X / 2^s` (`E_m = theta^m / m! / (1 - theta /
/// (m + 1))`), a relative `1e-10` at most of what they sum, which enters a cell's form times
/// the offsets squared, far below the second derivatives' own range over the cell.
const HESSIAN_TAYLOR_DEGREE: u32 = 8;

/// Degree of the Taylor polynomial of the exponential with derivatives
/// ([`Scalar::exp_matrix`] for [`Dual`]), which only the mean-value form's slopes use: at
/// `theta <= 1/2` the remainder is below `2^-13 / 13! / (1 - 1/28) < 2e-14`, a relative
/// `2e-14` of the entries near 1 and of the derivatives scaled to their size. A slope
/// enters a cell's form times the offset from the middle, so that width is a relative
/// `2e-14` of what the slope itself moves, far below the cell's own overestimation; and
/// the degree costs six products fewer per exponential than [`TAYLOR_DEGREE`].
const SLOPE_TAYLOR_DEGREE: u32 = 12;

fn p(x: f64) -> Interval {
    Interval::point(x)
}

/// `a / x`, an exact zero where `a` is one and `x` holds no zero: such a quotient is exact,
/// where the outward rounding of interval division would widen it to the subnormals on each
/// side. An entry of the exponential's Taylor polynomial that stays an exact zero keeps its
/// products out of the next one ([`Mat::mul`] leaves out the terms of exact zeros), so the
/// entries no power of `X` reaches stay out of every product ([`paths`]).
fn quotient(a: Interval, x: Interval) -> Interval {
    if a.is_zero() && x.mig() > 0.0 {
        a
    } else {
        a / x
    }
}

/// Which entries `(i, j)` (row-major) some power `X^m`, `m >= 1`, of a matrix with the
/// pattern of `x` may make nonzero: those joined by a path `i -> ... -> j` through entries
/// that are not [`Scalar::negligible`] (every entry of an [`Interval`] matrix counts). Where
/// there is none, `X^m` is zero there for every matrix of the cell and every `m >= 1`, and so
/// are its derivatives in the parameters (the entries on no path are zero over the whole
/// cell); so the exponential's entry there is the identity's, its Taylor polynomial's is
/// that (an exact `0` or `1` when its steps keep exact zeros), and the Taylor remainder is
/// zero. A device with a lag and no hand is upper triangular (the position is moved by the
/// velocity, the velocity by the force, the force by the command), and the augmented
/// exponential's last row is zero: six entries of sixteen are on no path, and the products
/// of the Taylor polynomial and of the squarings leave out their terms.
fn paths<T: Scalar>(x: &Mat<T>) -> Vec<bool> {
    let n = x.n;
    let mut reach: Vec<bool> = x.v.iter().map(|e| !e.negligible()).collect();
    // Warshall's transitive closure: paths through the vertices `0..=k`
    for k in 0..n {
        for i in 0..n {
            if reach[i * n + k] {
                for j in 0..n {
                    if reach[k * n + j] {
                        reach[i * n + j] = true;
                    }
                }
            }
        }
    }
    reach
}

/// The arithmetic the enclosure's steps run in: intervals, or intervals with the enclosure
/// of the derivatives in a few parameters ([`Dual`], for the mean-value form over a cell of
/// them).
pub(crate) trait Scalar:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    /// A quantity that does not depend on the parameter.
    fn constant(x: Interval) -> Self;
    /// The quantity with the lower end of its values raised to 0, for one known to be
    /// nonnegative ([`Interval::nonneg`]; a derivative keeps its enclosure).
    fn nonneg(self) -> Self;
    /// `f(x)` for a differentiable `f` whose range over an interval `f` encloses and whose
    /// derivative over it `df` encloses (the chain rule).
    fn chain(self, f: impl Fn(Interval) -> Interval, df: impl Fn(Interval) -> Interval) -> Self;
    /// [`Self::chain`] for a twice differentiable `f` whose second derivative over an
    /// interval `ddf` encloses; what carries no second derivatives ignores `ddf`.
    fn chain2(
        self,
        f: impl Fn(Interval) -> Interval,
        df: impl Fn(Interval) -> Interval,
        _ddf: impl Fn(Interval) -> Interval,
    ) -> Self {
        self.chain(f, df)
    }
    /// Whether a product with it may be left out of a sum: an exact zero with exact zero
    /// derivatives. Never for an [`Interval`], whose sums keep every term (so that its
    /// enclosures, which certificates print, stay as they are).
    fn negligible(&self) -> bool {
        false
    }
    /// The product with a quantity `x` that does not depend on the parameters.
    fn times(self, x: Interval) -> Self {
        self * Self::constant(x)
    }
    /// The quotient by a quantity `x` that does not depend on the parameters.
    fn over(self, x: Interval) -> Self {
        self / Self::constant(x)
    }
    /// `exp(-x)` for a nonnegative `x`.
    fn exp_neg(self) -> Self {
        self.chain2(
            interval::exp_neg,
            |x| -interval::exp_neg(x),
            interval::exp_neg,
        )
    }
    /// `e^X` enclosed.
    fn exp_matrix(x: &Mat<Self>) -> Mat<Self>;
}

impl Scalar for Interval {
    fn constant(x: Interval) -> Self {
        x
    }
    fn nonneg(self) -> Self {
        Interval::nonneg(self)
    }
    fn chain(self, f: impl Fn(Interval) -> Interval, _: impl Fn(Interval) -> Interval) -> Self {
        f(self)
    }
    fn exp_matrix(x: &Mat<Self>) -> Mat<Self> {
        exp(x)
    }
}

impl<const N: usize> Scalar for Dual<N> {
    fn constant(x: Interval) -> Self {
        Dual::constant(x)
    }
    fn nonneg(self) -> Self {
        Dual {
            v: self.v.nonneg(),
            d: self.d,
        }
    }
    fn chain(self, f: impl Fn(Interval) -> Interval, df: impl Fn(Interval) -> Interval) -> Self {
        Dual::chain(self, f, df)
    }
    fn negligible(&self) -> bool {
        self.v.is_zero() && self.d.iter().all(|d| d.is_zero())
    }
    fn times(self, x: Interval) -> Self {
        Dual {
            v: self.v * x,
            d: self.d.map(|d| d * x),
        }
    }
    fn over(self, x: Interval) -> Self {
        Dual {
            v: quotient(self.v, x),
            d: self.d.map(|d| quotient(d, x)),
        }
    }
    /// The partial derivative of `e^{X(p)}` in `p_k` is the top-right block of
    /// `exp([[X, X_k], [0, X]])`, `X_k` that of `X` (Van Loan, "Computing integrals
    /// involving the matrix exponential", IEEE TAC 23(3), 1978, Theorem 1: it is
    /// `int_0^1 e^{s X} X_k e^{(1 - s) X} ds`, the Frechet derivative in the direction
    /// `X_k`), and its diagonal blocks are `e^X`. Block upper-triangular matrices of that
    /// pattern multiply as `[[A1, B1], [0, A1]] [[A2, B2], [0, A2]] = [[A1 A2, A1 B2 + B1
    /// A2], [0, A1 A2]]`, which is the product rule of [`Dual`]: so the exponential's steps
    /// (scaling, Taylor by Horner's rule, squaring) run on the [`Dual`] matrix itself, one
    /// product of the small size for `e^X` and two per direction, where the block matrix of
    /// twice the size costs eight, and `e^X` is computed once for every direction. The
    /// Taylor remainder of the derivatives is bounded by the norm of the largest block
    /// matrix (see [`exp`]'s bound), and is zero where that block matrix's powers are (zero
    /// rows and columns of `[X, X_k]` and `[X_k; X]`); that of the value, the diagonal
    /// blocks, by the norm of `X` alone, so that the value is as narrow as [`exp`]'s up to
    /// rounding (the second-order form takes a cell's centre from it). Each derivative is linear in `X_k`, so `X_k` is scaled by
    /// a power of two (exact) to the size of `X` before and the block unscaled after, which
    /// keeps the squarings those of `X` alone.
    fn exp_matrix(x: &Mat<Self>) -> Mat<Self> {
        let moving = moving_directions::<N>(|k| x.v.iter().any(|e| !e.d[k].is_zero()));
        if let Some(e) = in_moving_directions(x, &moving) {
            return e;
        }
        let n = x.n;
        let value = Mat {
            n,
            v: x.v.iter().map(|e| e.v).collect(),
        };
        let target = value.norm().max(0.5);
        let scales: [f64; N] = std::array::from_fn(|k| {
            let size = Mat {
                n,
                v: x.v.iter().map(|e| e.d[k]).collect(),
            }
            .norm();
            // a power of two from 2^-64 to 2^64 (each step exact): an exact zero
            // derivative rounds outward to subnormals, which must not scale up to the size
            // of `X`
            let mut scale = 1.0f64;
            for _ in 0..64 {
                if size * scale > target {
                    scale *= 0.5;
                } else if size * scale * 2.0 <= target && size * scale > 1e-200 {
                    scale *= 2.0;
                }
            }
            scale
        });
        let scaled = x.map(|e| Dual {
            v: e.v,
            d: std::array::from_fn(|k| e.d[k] * p(scales[k])),
        });
        // the infinity norm of each block matrix [[X, s X_k], [0, X]]: its top rows carry
        // both blocks, its bottom rows X alone
        let norm = (0..n)
            .map(|i| {
                let row = |f: &dyn Fn(&Self) -> Interval| {
                    (0..n)
                        .fold(p(0.0), |s, j| s + p(f(&scaled.at(i, j)).mag()))
                        .mag()
                };
                let plain = row(&|e| e.v);
                (0..N)
                    .map(|k| (p(plain) + p(row(&|e| e.d[k]))).mag())
                    .fold(plain, f64::max)
            })
            .fold(0.0, f64::max);
        let zero = |f: &dyn Fn(&Self) -> Interval, row: bool, i: usize| {
            (0..n).all(|j| {
                let e = if row {
                    scaled.at(i, j)
                } else {
                    scaled.at(j, i)
                };
                f(&e).mag() == 0.0
            })
        };
        // the value's own remainder, `E_(K+1)` of the norm of `X / 2^s` alone (the value
        // block's powers are those of `X / 2^s`): the value is the centre of a cell's
        // second-order form, which it should enclose as narrowly as the plain exponential
        let plain = value.norm();
        let value_remainder = std::cell::OnceCell::new();
        let e = exp_with(
            &scaled,
            (norm, SLOPE_TAYLOR_DEGREE),
            |i, j, e, (rem, scale)| {
                let plain_row = zero(&|e| e.v, true, i);
                let plain_col = zero(&|e| e.v, false, j);
                let r = Interval::symmetric(rem);
                let own = *value_remainder.get_or_init(|| {
                    let theta = p(plain) * p(scale);
                    Interval::symmetric(tail(theta, SLOPE_TAYLOR_DEGREE + 1).mag())
                });
                Dual {
                    v: if plain_row || plain_col {
                        e.v
                    } else {
                        e.v + own
                    },
                    d: std::array::from_fn(|k| {
                        let row = plain_row && zero(&|e| e.d[k], true, i);
                        let col = plain_col && zero(&|e| e.d[k], false, j);
                        if row || col { e.d[k] } else { e.d[k] + r }
                    }),
                }
            },
        );
        e.map(|e| Dual {
            v: e.v,
            d: std::array::from_fn(|k| quotient(e.d[k], p(scales[k]))),
        })
    }
}

impl<const N: usize> Scalar for Dual2<N> {
    fn constant(x: Interval) -> Self {
        Dual2::constant(x)
    }
    fn nonneg(self) -> Self {
        Dual2 {
            v: self.v.nonneg(),
            ..self
        }
    }
    /// Without the second derivative of `f` the second derivatives are unknown: the whole
    /// line ([`Scalar::chain2`] carries them).
    fn chain(self, f: impl Fn(Interval) -> Interval, df: impl Fn(Interval) -> Interval) -> Self {
        Dual2::chain2(self, f, df, |_| Interval::ENTIRE)
    }
    fn chain2(
        self,
        f: impl Fn(Interval) -> Interval,
        df: impl Fn(Interval) -> Interval,
        ddf: impl Fn(Interval) -> Interval,
    ) -> Self {
        Dual2::chain2(self, f, df, ddf)
    }
    fn negligible(&self) -> bool {
        self.is_zero()
    }
    fn times(self, x: Interval) -> Self {
        self.scaled(x)
    }
    fn over(self, x: Interval) -> Self {
        Dual2 {
            v: quotient(self.v, x),
            d: self.d.map(|d| quotient(d, x)),
            h: self.h.map(|r| r.map(|h| quotient(h, x))),
        }
    }
    /// The exponential's steps (scaling, Taylor by Horner's rule, squaring) on the
    /// [`Dual2`] entries, which apply the rules of calculus to each product, with the Taylor
    /// remainder's value, first and second derivatives bounded each by its own size. For
    /// `Y = X / 2^s` (`Y_k`, `Y_kl` its derivatives, of infinity norms at most `a`, `b_k`,
    /// `c_kl`), the first derivative of `Y^j` in `p_k` is a sum of `j` products with `Y_k`
    /// once and `Y` elsewhere, of norm at most `j a^(j-1) b_k`, and its second derivative in
    /// `p_k`, `p_l` a sum of `j (j - 1)` products with `Y_k` and `Y_l` once each and of `j`
    /// with `Y_kl` once, of norm at most `j (j - 1) a^(j-2) b_k b_l + j a^(j-1) c_kl`. So
    /// every entry of the remainder `sum_{j > K} Y^j / j!` is at most `E_(K+1)(a)`, of its
    /// first derivatives at most `b_k E_K(a)` and of its second at most
    /// `b_k b_l E_(K-1)(a) + c_kl E_K(a)`, `E_m(a) = sum_{i >= m} a^i / i!
    /// <= a^m / m! / (1 - a / (m + 1))`: the squarings are those of `X` alone (`a <= 1/2`),
    /// and each part's remainder is relative to its own size whatever the parameters'
    /// units (the squarings halve until `a <= 1/8`, below). (A bound by one norm of `a + 2 sum_k b_k + sum_kl c_kl`, a part of whose
    /// terms each of these is, needs the parameters rescaled to `X`'s size, which scales
    /// `Y_kk` by the square: for a mass of 0.1 kg, whose `X_k` is small, `delta = b T / m`
    /// moving by `b T / m^2`, that sum was four orders above `X` and cost eleven squarings
    /// more.)
    fn exp_matrix(x: &Mat<Self>) -> Mat<Self> {
        let moving = moving_directions::<N>(|k| {
            x.v.iter()
                .any(|e| !e.d[k].is_zero() || e.h[k].iter().any(|h| !h.is_zero()))
        });
        if let Some(e) = in_moving_directions(x, &moving) {
            return e;
        }
        let n = x.n;
        let norm_of = |f: &dyn Fn(&Self) -> Interval| {
            Mat {
                n,
                v: x.v.iter().map(f).collect(),
            }
            .norm()
        };
        let a = norm_of(&|e| e.v);
        let b: [f64; N] = std::array::from_fn(|k| norm_of(&|e| e.d[k]));
        let c: [[f64; N]; N] =
            std::array::from_fn(|k| std::array::from_fn(|l| norm_of(&|e| e.h[k][l])));
        let degree = HESSIAN_TAYLOR_DEGREE;
        // halved until `a / 2^s <= 1/8`, two halvings more than `X` alone needs: the Taylor
        // polynomial's interval evaluation wraps less at the smaller argument, which narrows
        // the second derivatives' enclosures (a lag's interval behind a 1 ms loop closes in
        // 13 cells where `a / 2^s <= 1/2` took 14, and 12 at 1/32 at more squarings' cost)
        // the bounds depend on the scaling alone: computed at the first entry
        let bounds = std::cell::OnceCell::new();
        exp_with(x, (4.0 * a, degree), |_, _, e, (_, scale)| {
            let (rv, rd, rh): &(Interval, [Interval; N], [[Interval; N]; N]) =
                bounds.get_or_init(|| {
                    // the norms of Y, Y_k and Y_kl (the scaling by a power of two, rounded up)
                    let scaled = |x: f64| p(x) * p(scale);
                    let theta = scaled(a);
                    let (value, first, second) = (
                        tail(theta, degree + 1),
                        tail(theta, degree),
                        tail(theta, degree - 1),
                    );
                    let bound = |x: Interval| Interval::symmetric(x.mag());
                    (
                        bound(value),
                        std::array::from_fn(|k| bound(scaled(b[k]) * first)),
                        std::array::from_fn(|k| {
                            std::array::from_fn(|l| {
                                let r =
                                    scaled(b[k]) * scaled(b[l]) * second + scaled(c[k][l]) * first;
                                bound(r)
                            })
                        }),
                    )
                });
            Dual2 {
                v: e.v + *rv,
                d: std::array::from_fn(|k| e.d[k] + rd[k]),
                h: std::array::from_fn(|k| std::array::from_fn(|l| e.h[k][l] + rh[k][l])),
            }
        })
    }
}

/// The parameters `k < N` in which `moves(k)`: those in which some entry of an exponential's
/// argument has a derivative that is not an exact zero.
fn moving_directions<const N: usize>(moves: impl Fn(usize) -> bool) -> Vec<usize> {
    (0..N).filter(|&k| moves(k)).collect()
}

/// Quantities with derivatives in `N` parameters that can be taken in a few of them, `M`,
/// and back: what [`in_moving_directions`] needs.
trait Directions: Scalar {
    /// How many parameters it carries derivatives in, `N`.
    const DIRECTIONS: usize;
    /// The same arithmetic in `M` parameters.
    type In<const M: usize>: Scalar;
    /// The value and the derivatives in the parameters `chosen` (in that order).
    fn project<const M: usize>(self, chosen: &[usize]) -> Self::In<M>;
    /// The quantity in `N` parameters whose derivatives in `chosen` are those of `x` and in
    /// the others exact zeros.
    fn embed<const M: usize>(x: Self::In<M>, chosen: &[usize]) -> Self;
}

impl<const N: usize> Directions for Dual<N> {
    const DIRECTIONS: usize = N;
    type In<const M: usize> = Dual<M>;
    fn project<const M: usize>(self, chosen: &[usize]) -> Dual<M> {
        Dual {
            v: self.v,
            d: std::array::from_fn(|j| self.d[chosen[j]]),
        }
    }
    fn embed<const M: usize>(x: Dual<M>, chosen: &[usize]) -> Self {
        let at = |k: usize| chosen.iter().position(|&c| c == k);
        Dual {
            v: x.v,
            d: std::array::from_fn(|k| at(k).map_or(p(0.0), |j| x.d[j])),
        }
    }
}

impl<const N: usize> Directions for Dual2<N> {
    const DIRECTIONS: usize = N;
    type In<const M: usize> = Dual2<M>;
    fn project<const M: usize>(self, chosen: &[usize]) -> Dual2<M> {
        Dual2 {
            v: self.v,
            d: std::array::from_fn(|j| self.d[chosen[j]]),
            h: std::array::from_fn(|i| std::array::from_fn(|j| self.h[chosen[i]][chosen[j]])),
        }
    }
    fn embed<const M: usize>(x: Dual2<M>, chosen: &[usize]) -> Self {
        let at = |k: usize| chosen.iter().position(|&c| c == k);
        let zero = p(0.0);
        Dual2 {
            v: x.v,
            d: std::array::from_fn(|k| at(k).map_or(zero, |j| x.d[j])),
            h: std::array::from_fn(|k| {
                std::array::from_fn(|l| match (at(k), at(l)) {
                    (Some(i), Some(j)) => x.h[i][j],
                    _ => zero,
                })
            }),
        }
    }
}

/// `e^X` taken in the parameters `moving` alone when they are fewer than `X`'s (at most
/// three), `None` otherwise. Where no entry of `X` moves with a parameter over the cell (its
/// derivatives in it enclosed by exact zeros: a low-pass pole, which enters the polynomial
/// through the filter alone), `e^X` does not move with it either, so its derivatives in it
/// are exact zeros; and each step of the exponential computes a derivative from the same
/// derivatives of its operands alone (the product rule) and its remainder's bound from their
/// own norms, so the derivatives in the moving parameters are the same numbers in fewer
/// parameters, at a fraction of the cost (behind a lag and a filter's cutoff, one parameter
/// of two).
fn in_moving_directions<T: Directions>(x: &Mat<T>, moving: &[usize]) -> Option<Mat<T>> {
    fn taken<T: Directions, const M: usize>(x: &Mat<T>, moving: &[usize]) -> Mat<T> {
        let inner = Mat {
            n: x.n,
            v: x.v.iter().map(|e| e.project::<M>(moving)).collect(),
        };
        let e = <T::In<M> as Scalar>::exp_matrix(&inner);
        Mat {
            n: x.n,
            v: e.v.into_iter().map(|e| T::embed::<M>(e, moving)).collect(),
        }
    }
    (moving.len() < T::DIRECTIONS && moving.len() <= 3).then(|| match moving.len() {
        0 => taken::<T, 0>(x, moving),
        1 => taken::<T, 1>(x, moving),
        2 => taken::<T, 2>(x, moving),
        _ => taken::<T, 3>(x, moving),
    })
}

/// A square matrix, row-major.
#[derive(Debug, Clone)]
pub(crate) struct Mat<T = Interval> {
    n: usize,
    v: Vec<T>,
}

impl<T: Scalar> Mat<T> {
    fn zeros(n: usize) -> Self {
        Self {
            n,
            v: vec![T::constant(p(0.0)); n * n],
        }
    }

    fn identity(n: usize) -> Self {
        let mut m = Self::zeros(n);
        for i in 0..n {
            m.v[i * n + i] = T::constant(p(1.0));
        }
        m
    }

    fn at(&self, i: usize, j: usize) -> T {
        self.v[i * self.n + j]
    }

    fn set(&mut self, i: usize, j: usize, x: T) {
        self.v[i * self.n + j] = x;
    }

    fn mul(&self, o: &Self) -> Self {
        let n = self.n;
        let mut m = Self::zeros(n);
        // which entries are not exact zeros, told once per entry instead of once per term,
        // as bits `i n + j` (every entry kept in a matrix larger than eight: the device's
        // augmented matrices are at most six)
        let kept = |x: &Self| -> u64 {
            if n > 8 {
                return u64::MAX;
            }
            x.v.iter()
                .enumerate()
                .fold(0, |bits, (i, e)| bits | (u64::from(!e.negligible()) << i))
        };
        let (left, right) = (kept(self), kept(o));
        let bit = |bits: u64, i: usize| n > 8 || bits >> i & 1 == 1;
        for i in 0..n {
            for j in 0..n {
                let mut acc = T::constant(p(0.0));
                for k in 0..n {
                    // an exact zero term adds nothing to the exact sum
                    if bit(left, i * n + k) && bit(right, k * n + j) {
                        acc = acc + self.at(i, k) * o.at(k, j);
                    }
                }
                m.set(i, j, acc);
            }
        }
        m
    }

    fn map(&self, f: impl Fn(T) -> T) -> Self {
        Self {
            n: self.n,
            v: self.v.iter().map(|&x| f(x)).collect(),
        }
    }

    /// `self + x I`.
    fn plus_diagonal(&self, x: T) -> Self {
        let mut m = self.clone();
        for i in 0..self.n {
            m.set(i, i, m.at(i, i) + x);
        }
        m
    }

    fn trace(&self) -> T {
        (0..self.n).fold(T::constant(p(0.0)), |s, i| s + self.at(i, i))
    }
}

impl Mat {
    /// An upper bound of the infinity norm (largest row sum of moduli).
    fn norm(&self) -> f64 {
        (0..self.n)
            .map(|i| {
                (0..self.n)
                    .fold(p(0.0), |s, j| s + p(self.at(i, j).mag()))
                    .mag()
            })
            .fold(0.0, f64::max)
    }
}

/// `e^X` enclosed by scaling, Taylor with its remainder, and squaring (module docs).
fn exp(x: &Mat) -> Mat {
    // every power of X keeps X's zero rows and zero columns: the remainder is zero there
    let zero_row = |i: usize| (0..x.n).all(|j| x.at(i, j).mag() == 0.0);
    let zero_col = |j: usize| (0..x.n).all(|i| x.at(i, j).mag() == 0.0);
    exp_with(x, (x.norm(), TAYLOR_DEGREE), |i, j, e, (rem, _)| {
        if zero_row(i) || zero_col(j) {
            e
        } else {
            e + Interval::symmetric(rem)
        }
    })
}

/// `e^X` by scaling, Taylor of degree `degree` with its remainder, and squaring (module
/// docs) in the
/// arithmetic `T`, for an `X` whose exponential's entries are those of a matrix of infinity
/// norm at most `norm` (the matrix itself, or for [`Dual`] entries the block matrices of
/// [`Scalar::exp_matrix`]): `remainder(i, j, t, (r, 2^-s))` adds to the entry `t` of the
/// Taylor polynomial the remainder's bound `r` where that matrix's powers are not zero (or,
/// for [`Dual2`] entries, its own bounds from the scaling `2^-s` of `X`).
fn exp_with<T: Scalar>(
    x: &Mat<T>,
    (norm, degree): (f64, u32),
    remainder: impl Fn(usize, usize, T, (f64, f64)) -> T,
) -> Mat<T> {
    if !norm.is_finite() {
        return x.map(|_| T::constant(Interval::ENTIRE));
    }
    let (mut theta, mut scale, mut squarings) = (norm, 1.0f64, 0);
    while theta > 0.5 {
        // halving is exact (the norm stays far above the subnormal range here)
        theta *= 0.5;
        scale *= 0.5;
        squarings += 1;
    }
    let y = x.map(|e| e.times(p(scale)));
    let mut t = Mat::identity(x.n);
    for k in (1..=degree).rev() {
        let k = p(f64::from(k));
        // `I + Y t / k`, in place
        t = y.mul(&t);
        for e in &mut t.v {
            *e = e.over(k);
        }
        for i in 0..x.n {
            t.set(i, i, t.at(i, i) + T::constant(p(1.0)));
        }
    }
    let rem = tail(p(theta), degree + 1).mag();
    let reach = paths(x);
    let mut e = t.clone();
    for i in 0..x.n {
        for j in 0..x.n {
            // no remainder where no power of `X` reaches ([`paths`])
            if reach[i * x.n + j] {
                e.set(i, j, remainder(i, j, t.at(i, j), (rem, scale)));
            }
        }
    }
    for _ in 0..squarings {
        e = e.mul(&e);
    }
    e
}

/// `E_m(theta) = sum_{i >= m} theta^i / i! <= theta^m / m! / (1 - theta / (m + 1))` for
/// `0 <= theta < m + 1`, the Taylor remainder of the exponential series, every factor
/// rounded up.
fn tail(theta: Interval, m: u32) -> Interval {
    let mut t = p(1.0);
    for k in 1..=m {
        t = t * theta / p(f64::from(k));
    }
    t / (p(1.0) - theta / p(f64::from(m + 1)))
}

/// The normalized device parameters a set of devices may spread (`docs/MODEL.md` sections
/// 8 and 12): the damping `delta` and the hand's mass ratio `mu_h`, damping `delta_h` and
/// stiffness `kappa_h` (zero without a hand), each an interval.
#[derive(Debug, Clone, Copy)]
pub(crate) struct DeviceSpread<T = Interval> {
    /// `delta = b T / m`.
    pub(crate) delta: T,
    /// `[mu_h, delta_h, kappa_h]`.
    pub(crate) hand: [T; 3],
}

impl DeviceSpread {
    /// The exact values of `lp`.
    pub(super) fn of(lp: &Loop) -> Self {
        Self {
            delta: p(lp.plant().delta()),
            hand: lp.hand().map_or([p(0.0); 3], |h| {
                [p(h.mass_ratio()), p(h.damping()), p(h.stiffness())]
            }),
        }
    }
}

/// The rest of a loop's parameters over a cell of a set that spreads them (`docs/MODEL.md`
/// section 12), each an interval, `None` where the loop's own value holds.
#[derive(Debug, Clone, Copy)]
pub(crate) struct ElementSpread<T = Interval> {
    /// The transmission's `[r, kappa_c, delta_c, delta_1, delta_2]` (the motor side's
    /// damping `delta_1` given, not `delta - delta_2`, so that a cell keeps their sum).
    pub(crate) transmission: Option<[T; 5]>,
    /// The actuator lag's rate `1 / tau = T / tau_a` (the entries of the continuous model are
    /// linear in it, so a form in the rate carries no second derivative of `1 / tau`).
    pub(crate) rate: Option<T>,
    /// The first-order low-pass velocity filter's pole `a` (the loop's filter must be one).
    pub(crate) pole: Option<T>,
    /// The second-order filter's `K = tan(pi f_c T)` (the loop's filter
    /// must be prewarped, `VelocityFilter::is_prewarped`).
    pub(crate) prewarp: Option<T>,
    /// The hand's force gain `1 / (1 + mu_h)` where it is given in a variable of its own (on
    /// a loop without a transmission; the continuous model's entries are linear in it), so
    /// that it is not enclosed again from `mu_h`; `None`: from `mu_h`.
    pub(crate) hand_gain: Option<T>,
    /// `n` whole samples of delay and the fraction in a sub-interval of `[0, 1]`, in the
    /// fractional form for every fraction (at 0 it is `z` times the integer delay's
    /// polynomial, at 1 the delay `n + 1`'s).
    pub(crate) delay: Option<(usize, Interval)>,
}

impl<T> Default for ElementSpread<T> {
    fn default() -> Self {
        Self {
            transmission: None,
            rate: None,
            pole: None,
            prewarp: None,
            hand_gain: None,
            delay: None,
        }
    }
}

/// The continuous device `A, b, c` of `lp` (`docs/MODEL.md` section 8), enclosed, with
/// the damping and the hand's parameters over the intervals of `spread` and the
/// transmission's and the actuator's over those of `el`.
fn continuous<T: Scalar>(
    lp: &Loop,
    spread: &DeviceSpread<T>,
    el: &ElementSpread<T>,
) -> (Mat<T>, Vec<T>, Vec<T>) {
    let delta = spread.delta;
    let [mu, dh, kh] = spread.hand;
    let s = lp.device_order();
    let k = |x: f64| T::constant(p(x));
    let mut a = Mat::zeros(s);
    let mut b = vec![k(0.0); s];
    let mut c = vec![k(0.0); s];
    let one = k(1.0);
    let scale = match lp.transmission() {
        None => {
            a.set(0, 1, one);
            c[0] = one;
            match el.hand_gain {
                Some(g) => {
                    a.set(1, 0, -(kh * g));
                    a.set(1, 1, -((delta + dh) * g));
                    g
                }
                None => {
                    let m = one + mu;
                    a.set(1, 0, -(kh / m));
                    a.set(1, 1, -((delta + dh) / m));
                    one / m
                }
            }
        }
        Some(t) => {
            let [r, kc, dc, d1, d2] = el.transmission.unwrap_or_else(|| {
                let d2 = k(t.handle_damping());
                // delta_1 = delta - delta_2 >= 0 (checked when the loop was built)
                let d1 = (delta - d2).nonneg();
                [
                    k(t.handle_ratio()),
                    k(t.stiffness()),
                    k(t.damping()),
                    d1,
                    d2,
                ]
            });
            let (m1, m2) = (one - r, r + mu);
            a.set(0, 1, one);
            a.set(1, 0, -(kc / m1));
            a.set(1, 1, -((d1 + dc) / m1));
            a.set(1, 2, kc / m1);
            a.set(1, 3, dc / m1);
            a.set(2, 3, one);
            a.set(3, 0, kc / m2);
            a.set(3, 1, dc / m2);
            a.set(3, 2, -((kh + kc) / m2));
            a.set(3, 3, -((d2 + dh + dc) / m2));
            match t.encoder() {
                Encoder::Handle => c[2] = one,
                _ => c[0] = one,
            }
            one / m1
        }
    };
    match lp.actuator() {
        None => b[1] = scale,
        Some(act) => {
            let (f, rate) = (s - 1, el.rate.unwrap_or(one / k(act.tau())));
            a.set(1, f, scale);
            a.set(f, f, -rate);
            b[f] = rate;
        }
    }
    (a, b, c)
}

/// `(e^{A tau}, Gamma(tau))` from the augmented exponential.
fn exp_gamma<T: Scalar>(a: &Mat<T>, b: &[T], tau: Interval) -> (Mat<T>, Vec<T>) {
    let s = a.n;
    let tau = T::constant(tau);
    let mut m = Mat::zeros(s + 1);
    for (i, &bi) in b.iter().enumerate() {
        for j in 0..s {
            m.set(i, j, a.at(i, j) * tau);
        }
        m.set(i, s, bi * tau);
    }
    let e = T::exp_matrix(&m);
    let mut phi = Mat::zeros(s);
    for i in 0..s {
        for j in 0..s {
            phi.set(i, j, e.at(i, j));
        }
    }
    (phi, (0..s).map(|i| e.at(i, s)).collect())
}

fn conv<T: Scalar>(a: &[T], b: &[T]) -> Vec<T> {
    let mut out = vec![T::constant(p(0.0)); a.len() + b.len() - 1];
    for (i, &x) in a.iter().enumerate() {
        for (j, &y) in b.iter().enumerate() {
            out[i + j] = out[i + j] + x * y;
        }
    }
    out
}

fn dot<T: Scalar>(a: &[T], b: &[T]) -> T {
    a.iter()
        .zip(b)
        .fold(T::constant(p(0.0)), |s, (&x, &y)| s + x * y)
}

fn mat_vec<T: Scalar>(m: &Mat<T>, v: &[T]) -> Vec<T> {
    (0..m.n)
        .map(|i| (0..m.n).fold(T::constant(p(0.0)), |s, j| s + m.at(i, j) * v[j]))
        .collect()
}

/// The filter `Fn`, `Fd` (lowest power first) of `lp`, enclosed; a first-order low-pass
/// with its pole over `el.pole` when given, a second-order one with its `K` over
/// `el.prewarp`.
fn filter<T: Scalar>(lp: &Loop, el: &ElementSpread<T>) -> (Vec<T>, Vec<T>) {
    let f = lp.filter();
    let k = |x: f64| T::constant(p(x));
    match (f.kind(), el.prewarp) {
        (FilterKind::LowPass { pole: a }, _) => {
            let a = el.pole.unwrap_or(k(a));
            (vec![k(0.0), k(1.0) - a], vec![-a, k(1.0)])
        }
        (FilterKind::MovingAverage { samples }, _) => {
            let mut fd = vec![k(0.0); samples];
            fd[samples - 1] = k(1.0);
            (vec![k(1.0) / k(samples as f64); samples], fd)
        }
        // the prewarped design (`crate::filter::prewarped_design`), `sqrt 2` enclosed by
        // its correctly rounded square root; `el.prewarp` is given only for such a filter
        (_, Some(kk)) => {
            let (n, d) = crate::filter::prewarped_design(kk, k(1.0), T::constant(p(2.0).sqrt()));
            (n.to_vec(), d.to_vec())
        }
        // the stored coefficients are the filter (the second-order filter's design rounds)
        _ => (
            f.numerator().into_iter().map(k).collect(),
            f.denominator().into_iter().map(k).collect(),
        ),
    }
}

/// The enclosed parts of `q`, lowest power first, for a loop with elements.
pub(crate) fn parts(lp: &Loop) -> Parts {
    parts_over(lp, &DeviceSpread::of(lp))
}

/// The enclosed parts of `q` for every loop like `lp` whose damping and hand parameters
/// lie in `spread` (the rest of `lp` as it is): each step is interval arithmetic, so it
/// encloses the range over the intervals. A hand's intervals need `lp` to have a hand.
pub(crate) fn parts_over(lp: &Loop, spread: &DeviceSpread) -> Parts {
    parts_spread(lp, spread, &ElementSpread::default())
}

/// The enclosed parts of `q` for the loop `lp` with every value in units of the device's
/// mass (`delta`, the hand's and the transmission's) times the scale `s` (a member of a set of
/// devices in the set's reference normalization, `super::Masses`); the wall's parts are
/// `lp`'s, the caller scales them.
pub(crate) fn parts_scaled(lp: &Loop, s: Interval) -> Parts {
    let own = DeviceSpread::of(lp);
    let spread = DeviceSpread {
        delta: own.delta * s,
        hand: own.hand.map(|x| x * s),
    };
    let transmission = lp.transmission().map(|t| {
        let d2 = p(t.handle_damping());
        // delta_1 = delta - delta_2 >= 0 (checked when the loop was built)
        let d1 = (own.delta - d2).nonneg();
        [
            p(t.handle_ratio()),
            p(t.stiffness()),
            p(t.damping()),
            d1,
            d2,
        ]
        .map(|x| x * s)
    });
    let el = ElementSpread {
        transmission,
        ..ElementSpread::default()
    };
    parts_spread(lp, &spread, &el)
}

/// The enclosed parts of `q` for every loop like `lp` whose damping and hand parameters lie
/// in `spread` and whose transmission, actuator lag, low-pass pole and delay lie in `el`:
/// as [`parts_over`], each step interval arithmetic. The fraction of delay enters as the
/// sampling instant `eps` of the held force: `Gamma(1 - eps)` and `e^{A (1 - eps)}
/// Gamma(eps)`, each an exponential over the interval of its time (the dependency between
/// `eps` and `1 - eps` overestimated by a width proportional to the fraction's).
pub(crate) fn parts_spread(lp: &Loop, spread: &DeviceSpread, el: &ElementSpread) -> Parts {
    Parts(parts_of(lp, spread, el))
}

/// [`parts_spread`] in the arithmetic `T`.
fn parts_of<T: Scalar>(lp: &Loop, spread: &DeviceSpread<T>, el: &ElementSpread<T>) -> Vec<Part<T>> {
    let (a, b, c) = continuous(lp, spread, el);
    let s = a.n;
    let one = p(1.0);
    let (phi, g0) = exp_gamma(&a, &b, one);
    let (shape, eps) = Shape::of(lp, el);
    if !shape.fractional {
        return assemble(lp, &shape, el, &phi, &g0, &vec![T::constant(p(0.0)); s], &c);
    }
    let (e_rest, g0) = exp_gamma(&a, &b, (one - eps).nonneg());
    let (_, gamma_eps) = exp_gamma(&a, &b, eps);
    let g1 = mat_vec(&e_rest, &gamma_eps);
    assemble(lp, &shape, el, &phi, &g0, &g1, &c)
}

/// The centred form ([`FractionFamily`]) of the wall's polynomial under `(alpha, beta)` for
/// every loop like `lp` over `spread` and `el` (as [`parts_spread`]) and every fraction of
/// delay in `el.delay`'s interval; `None` when `el` spreads no delay.
///
/// # Method
///
/// The mean-value theorem in the fraction `eps` (the centred form: Moore, Kearfott and
/// Cloud, "Introduction to Interval Analysis", SIAM 2009, section 6.4), as for the paper's
/// loop: the centre encloses the coefficients at the cell's middle fraction `e_c` (one
/// point, so `eps` and `1 - eps` are no longer two independent intervals), the slope the
/// coefficients' derivatives in `eps` over the whole cell. The fraction enters only through
/// the held force's two input vectors `g0 = Gamma(1 - eps)` and `g1 = e^{A (1 - eps)}
/// Gamma(eps)` (`Gamma(t) = int_0^t e^{A s} b ds`); their sum is `Gamma(1)` (the two
/// integrals over `[0, 1 - eps]` and `[1 - eps, 1]`), and `d/dt Gamma(t) = e^{A t} b`, so
/// `g0' = -w` and `g1' = w` with `w = e^{A (1 - eps)} b`, enclosed over the cell by the
/// interval exponential over `1 - eps`. The coefficients are linear in `(g0, g1)` with
/// `Phi = e^A` fixed (`N = c^T adj(z I - Phi) (g0 z + g1)`, `D` and the filter free of
/// `eps`), so the slope is the same assembly from `(-w, w)` with the `Q0` part dropped.
pub(crate) fn fraction_family(
    lp: &Loop,
    spread: &DeviceSpread,
    el: &ElementSpread,
    alpha: Interval,
    beta: Interval,
) -> Option<FractionFamily> {
    let (n, e) = el.delay?;
    let mid = 0.5 * e.lo() + 0.5 * e.hi();
    let at_mid = ElementSpread {
        delay: Some((n, p(mid))),
        ..*el
    };
    let centre = parts_spread(lp, spread, &at_mid).at(alpha, beta);
    let (a, b, c) = continuous(lp, spread, el);
    let (phi, _) = exp_gamma(&a, &b, p(1.0));
    let (e_rest, _) = exp_gamma(&a, &b, (p(1.0) - e).nonneg());
    let w = mat_vec(&e_rest, &b);
    let minus_w: Vec<Interval> = w.iter().map(|&x| -x).collect();
    let (shape, _) = Shape::of(lp, el);
    let parts = assemble(lp, &shape, el, &phi, &minus_w, &w, &c);
    // `Q0 = z^(n+2) D Fd` does not depend on the fraction
    let slope = Parts(parts.into_iter().map(|(_, wall)| (p(0.0), wall)).collect());
    Some(FractionFamily {
        centre,
        slope: slope.at(alpha, beta),
        offset: e - p(mid),
    })
}

/// The mean-value form ([`MeanValueForm`]) of the wall's polynomial under `(alpha, beta)`
/// in `N` parameters `p_1, ..., p_N` of the continuous model over a cell of them: for every
/// point of the cell (and every value of the other parameters' intervals) each coefficient
/// of `q` lies in `centre_i + sum_k slope_k,i (p_k - m_k)`, `p_k - m_k` in `offset_k`.
///
/// `centre` is the enclosure at the cell's middle `m` (`at_centre`: the spreads and the
/// wall with every `p_k` at its middle); `slope_k` the enclosure of the coefficients'
/// partial derivatives in `p_k` over the whole cell (`over`: the spreads and the wall as
/// [`Dual`]s over the cell, carrying the partial derivatives of the normalized parameters).
/// The derivatives run through every step of [`parts_spread`] by the rules of calculus
/// ([`Dual`]); the discretization's exponential by Van Loan's block exponential in its
/// block-triangular form ([`Scalar::exp_matrix`]). `sides` names each parameter's side and
/// offset; `complete` says whether the cell spreads no other side.
///
/// # Method
///
/// The mean-value theorem along the segment from `m` to the member ([`MeanValueForm`]):
/// the overestimation is second order in the cell's width; the plain interval extension's,
/// which lets every occurrence of each `p_k` (in `e^{A(p)}`, in the adjugate, in the
/// filter) vary on its own, is first order.
pub(crate) fn parameter_family<const N: usize>(
    lp: &Loop,
    at_centre: (&DeviceSpread, &ElementSpread, Interval, Interval),
    over: (
        &DeviceSpread<Dual<N>>,
        &ElementSpread<Dual<N>>,
        Dual<N>,
        Dual<N>,
    ),
    sides: [(usize, Interval); N],
    complete: bool,
) -> MeanValueForm {
    let (spread, el, alpha, beta) = at_centre;
    let centre = parts_spread(lp, spread, el).at(alpha, beta);
    let (spread, el, alpha, beta) = over;
    let slopes: Vec<[Interval; N]> = parts_of(lp, spread, el)
        .into_iter()
        .map(|(v, wall)| match wall {
            Some((qa, qb)) => (v + (alpha * qa + beta * qb)).d,
            None => v.d,
        })
        .collect();
    MeanValueForm {
        centre,
        slopes: sides
            .iter()
            .enumerate()
            .map(|(k, &(side, offset))| Slope {
                side: Some(side),
                slope: slopes.iter().map(|d| d[k]).collect(),
                offset,
            })
            .collect(),
        complete,
    }
}

/// The second-order form of the wall's polynomial under `(alpha, beta)` in `N` parameters
/// over a cell of them, as a [`MeanValueForm`] whose terms [`super::robust`]'s Rouché test
/// reads alike: for every point of the cell each coefficient lies in
/// `centre_i + sum_k g_k,i t_k + sum_{k <= l} c_kl H_kl,i t_k t_l` with `|t_k| <= r_k`
/// (`t_k = p_k - m_k`, `offset_k` the sides' offsets), `g_k` the partial derivatives at the
/// middle `m`, `H_kl` the second partial derivatives over the whole cell, `c_kk = 1/2` and
/// `c_kl = 1` for `k < l` (the two equal terms `kl` and `lk`).
///
/// `at_middle` holds the spreads and the wall with the parameters as [`Dual`]s at the
/// middle `m`: the values of that one computation enclose the coefficients at `m` (the
/// centre; the exponential's value and its derivatives are one block-triangular exponential,
/// [`Scalar::exp_matrix`], so the centre needs no exponential of its own), its derivatives
/// the `g_k`, a point each up to rounding; `hessians` the `H_kl` of each coefficient over the cell or over a cell that
/// holds it ([`second_derivatives`]). Slopes: the `N` gradients with their
/// sides' offsets, then the `N (N + 1) / 2` second-order terms, each with the offset
/// `offset_k offset_l` (holds `t_k t_l`; for `k = l` it holds `t_k^2` too) and the side `k`.
///
/// # Method
///
/// Taylor's theorem with the Lagrange remainder along the segment from `m` to the member,
/// for each coefficient: `q_i(m + t) = q_i(m) + sum_k g_k,i t_k + 1/2 t^T H_i(xi_i) t`,
/// `xi_i` in the cell. The first-order term is now the gradient at one point, which
/// Rouché's test evaluates on the circle as a polynomial (its coefficients cancel there);
/// the enclosure's excess, which [`parameter_family`]'s slopes over the whole cell carry in
/// their radii times the offsets (second order in the width, summed coefficient by
/// coefficient), is now the second-order term's radii times the offsets squared: third
/// order.
pub(crate) fn second_order_family<const N: usize>(
    lp: &Loop,
    at_middle: (
        &DeviceSpread<Dual<N>>,
        &ElementSpread<Dual<N>>,
        Dual<N>,
        Dual<N>,
    ),
    hessians: &[[[Interval; N]; N]],
    sides: [(usize, Interval); N],
    complete: bool,
) -> MeanValueForm {
    let (spread, el, alpha, beta) = at_middle;
    let (centre, gradients): (Vec<Interval>, Vec<[Interval; N]>) = parts_of(lp, spread, el)
        .into_iter()
        .map(|(v, wall)| {
            let q = match wall {
                Some((qa, qb)) => v + (alpha * qa + beta * qb),
                None => v,
            };
            (q.v, q.d)
        })
        .unzip();
    let mut slopes: Vec<Slope> = sides
        .iter()
        .enumerate()
        .map(|(k, &(side, offset))| Slope {
            side: Some(side),
            slope: gradients.iter().map(|d| d[k]).collect(),
            offset,
        })
        .collect();
    for k in 0..N {
        for l in k..N {
            let c = p(if k == l { 0.5 } else { 1.0 });
            slopes.push(Slope {
                side: Some(sides[k].0),
                slope: hessians.iter().map(|h| h[k][l] * c).collect(),
                offset: sides[k].1 * sides[l].1,
            });
        }
    }
    MeanValueForm {
        centre,
        slopes,
        complete,
    }
}

/// The second partial derivatives of the wall's polynomial's coefficients (lowest power
/// first) under `(alpha, beta)` in `N` parameters over a cell of them, `over` as
/// [`Dual2`]s over the cell: the `H_kl` of [`second_order_family`], which holds over every
/// cell inside this one too.
pub(crate) fn second_derivatives<const N: usize>(
    lp: &Loop,
    over: (
        &DeviceSpread<Dual2<N>>,
        &ElementSpread<Dual2<N>>,
        Dual2<N>,
        Dual2<N>,
    ),
) -> Vec<[[Interval; N]; N]> {
    let (spread, el, alpha, beta) = over;
    parts_of(lp, spread, el)
        .into_iter()
        .map(|(v, wall)| match wall {
            Some((qa, qb)) => (v + (alpha * qa + beta * qb)).h,
            None => v.h,
        })
        .collect()
}

/// The form of `q`: `n` whole samples of delay, the fractional form or the integer one,
/// and the degree.
struct Shape {
    n: usize,
    fractional: bool,
    degree: usize,
}

impl Shape {
    /// The form of `lp`'s polynomial with the delay of `el` (the loop's own when `None`),
    /// and the fraction of delay.
    fn of<T>(lp: &Loop, el: &ElementSpread<T>) -> (Self, Interval) {
        let plant = lp.plant();
        let (n, eps, fractional) = match el.delay {
            Some((n, eps)) => (n, eps, true),
            None => (
                plant.whole_samples(),
                p(plant.fraction()),
                !plant.is_integer_delay(),
            ),
        };
        // the loop's own degree, moved to `n` whole samples and the fractional form
        let degree = lp.degree() + n + usize::from(plant.is_integer_delay() && fractional)
            - plant.whole_samples()
            - usize::from(!plant.is_integer_delay() && !fractional);
        (
            Self {
                n,
                fractional,
                degree,
            },
            eps,
        )
    }
}

/// The parts of `q` from the sampled device (Faddeev-LeVerrier, module docs), the filter's
/// low-pass pole over `pole` when given.
fn assemble<T: Scalar>(
    lp: &Loop,
    shape: &Shape,
    el: &ElementSpread<T>,
    phi: &Mat<T>,
    g0: &[T],
    g1: &[T],
    c: &[T],
) -> Vec<Part<T>> {
    let s = phi.n;
    let k = |x: f64| T::constant(p(x));
    // d[s - k] = a_k; n0[s - 1 - k] = c^T B_k g0, the same for g1
    let mut d = vec![k(0.0); s + 1];
    d[s] = k(1.0);
    let (mut n0, mut n1) = (vec![k(0.0); s], vec![k(0.0); s]);
    let mut bk = Mat::identity(s);
    for j in 1..=s {
        n0[s - j] = dot(c, &mat_vec(&bk, g0));
        n1[s - j] = dot(c, &mat_vec(&bk, g1));
        let ab = phi.mul(&bk);
        let aj = -(ab.trace() / k(j as f64));
        d[s - j] = aj;
        bk = ab.plus_diagonal(aj);
    }
    // N = z N0 + N1
    let mut num = vec![k(0.0); s + 1];
    for i in 0..s {
        num[i + 1] = num[i + 1] + n0[i];
        num[i] = num[i] + n1[i];
    }
    let (fnum, fden) = filter(lp, el);
    let n = shape.n;
    let mut q0 = vec![k(0.0); n + 2];
    q0.extend(conv(&d, &fden));
    let mut qa = vec![k(0.0)];
    qa.extend(conv(&fden, &num));
    let qb = conv(&[k(-1.0), k(1.0)], &conv(&fnum, &num));
    // the structural common powers of z: exact zeros of the exact polynomial
    let drop = usize::from(!shape.fractional)
        + usize::from(matches!(lp.filter().kind(), FilterKind::LowPass { pole } if pole != 0.0));
    (0..=shape.degree)
        .map(|i| {
            let at = |v: &[T]| v.get(i + drop).copied().unwrap_or(k(0.0));
            (at(&q0), Some((at(&qa), at(&qb))))
        })
        .collect()
}

/// One coefficient of `q = Q0 + alpha QA + beta QB`: its `Q0` part and its `QA` and `QB`
/// parts (as [`Parts`]).
type Part<T> = (T, Option<(T, T)>);

#[cfg(test)]
mod tests {
    use super::*;

    /// `exp` of a diagonal and of a nilpotent matrix against their closed forms, and of a
    /// matrix that needs squarings.
    #[test]
    fn exponential_holds_closed_forms() {
        let mut m = Mat::zeros(2);
        m.set(0, 0, p(-3.0));
        m.set(0, 1, p(2.0));
        m.set(1, 1, p(0.25));
        // [[e^-3, 2 (e^0.25 - e^-3) / 3.25], [0, e^0.25]]
        let e = exp(&m);
        let want = [
            (-3.0f64).exp(),
            2.0 * (0.25f64.exp() - (-3.0f64).exp()) / 3.25,
            0.0,
            0.25f64.exp(),
        ];
        for (x, w) in e.v.iter().zip(want) {
            let slack = 4.0 * f64::EPSILON * w.abs();
            assert!(x.contains(w, slack), "{x:?} {w}");
            assert!(x.mag() - x.mig() <= 1e-13 * w.abs().max(1.0), "{x:?}");
        }
    }

    /// The exponential's partial derivatives in two parameters against closed forms:
    /// `X(p, r) = [[-p, r], [0, -2 p]]` has `e^X = [[e^-p, r g(p)], [0, e^-2p]]` with
    /// `g(p) = (e^-p - e^-2p) / p`, so `d/dp` is `[[-e^-p, r g'(p)], [0, -2 e^-2p]]` and `d/dr`
    /// is `[[0, g(p)], [0, 0]]`; over the cell `[1.0, 1.1] x [2.0, 2.2]` (a norm above 1/2, so
    /// squarings) the enclosures hold them at 11 x 11 points, and the value is narrow.
    #[test]
    fn exponential_derivatives_hold_closed_forms() {
        let (cp, cr) = (Interval::new(1.0, 1.1), Interval::new(2.0, 2.2));
        let (vp, vr) = (Dual::<2>::variable(cp, 0), Dual::<2>::variable(cr, 1));
        let mut m = Mat::<Dual<2>>::zeros(2);
        m.set(0, 0, -vp);
        m.set(0, 1, vr);
        m.set(1, 1, -(Dual::constant(p(2.0)) * vp));
        let e = Dual::exp_matrix(&m);
        for i in 0..=10 {
            for j in 0..=10 {
                let x = 1.0 + 0.1 * f64::from(i) / 10.0;
                let r = 2.0 + 0.2 * f64::from(j) / 10.0;
                let (e1, e2) = ((-x).exp(), (-2.0 * x).exp());
                let g = (e1 - e2) / x;
                let dg = (-e1 + 2.0 * e2) / x - (e1 - e2) / (x * x);
                let value = [e1, r * g, 0.0, e2];
                let by_p = [-e1, r * dg, 0.0, -2.0 * e2];
                let by_r = [0.0, g, 0.0, 0.0];
                for k in 0..4 {
                    let (a, b) = (k / 2, k % 2);
                    let at = e.at(a, b);
                    // the f64 closed forms round by a few units of their size, below 1e-15
                    assert!(at.v.contains(value[k], 1e-15), "{x} {r} {k}: {at:?}");
                    assert!(at.d[0].contains(by_p[k], 1e-15), "{x} {r} {k}: {at:?}");
                    assert!(at.d[1].contains(by_r[k], 1e-15), "{x} {r} {k}: {at:?}");
                }
            }
        }
        // the values' range over the cell is about 0.04 wide at most
        assert!(e.v.iter().all(|x| x.v.hi() - x.v.lo() < 0.2), "{e:?}");
    }

    /// The exponential's second partial derivatives against closed forms: for
    /// `X(p, r) = [[-p, r], [0, -2 p]]`, `e^X = [[e^-p, r g(p)], [0, e^-2p]]` with
    /// `g(p) = u(p) / p`, `u = e^-p - e^-2p`, so the second derivatives in `(p, p)` are
    /// `[[e^-p, r g''], [0, 4 e^-2p]]`, in `(p, r)` `[[0, g'], [0, 0]]` and in `(r, r)` zero,
    /// `g' = u' / p - u / p^2`, `g'' = u'' / p - 2 u' / p^2 + 2 u / p^3`; over the cell
    /// `[1.0, 1.1] x [2.0, 2.2]` (squarings) the [`Dual2`] enclosures hold them, and the
    /// gradient and value, at 11 x 11 points.
    #[test]
    fn exponential_second_derivatives_hold_closed_forms() {
        let (cp, cr) = (Interval::new(1.0, 1.1), Interval::new(2.0, 2.2));
        let (vp, vr) = (Dual2::<2>::variable(cp, 0), Dual2::<2>::variable(cr, 1));
        let mut m = Mat::<Dual2<2>>::zeros(2);
        m.set(0, 0, -vp);
        m.set(0, 1, vr);
        m.set(1, 1, -(Dual2::constant(p(2.0)) * vp));
        let e = Dual2::exp_matrix(&m);
        for (x, r) in cell_grid() {
            let [value, by_p, by_r, pp, pr] = closed_forms(x, r);
            let grad = [by_p, by_r];
            let hess = [[pp, pr], [pr, [0.0; 4]]];
            // the f64 closed forms round by a few units of 1
            let slack = 1e-14;
            for (n, x) in e.v.iter().enumerate() {
                assert!(x.v.contains(value[n], slack), "{n}: {x:?}");
                for a in 0..2 {
                    assert!(x.d[a].contains(grad[a][n], slack), "{n} {a}: {x:?}");
                    for (h, want) in x.h[a].iter().zip(&hess[a]) {
                        assert!(h.contains(want[n], slack), "{n}: {x:?}");
                    }
                }
            }
        }
        // the value over the cell is no wider than the plain enclosure's few hundredths
        assert!(e.v.iter().all(|x| x.v.hi() - x.v.lo() < 0.2), "{e:?}");
    }

    /// The 11 x 11 points `(p, r)` of the cell `[1.0, 1.1] x [2.0, 2.2]`.
    fn cell_grid() -> impl Iterator<Item = (f64, f64)> {
        (0..=10).flat_map(|i| {
            (0..=10).map(move |j| {
                (
                    1.0 + 0.1 * f64::from(i) / 10.0,
                    2.0 + 0.2 * f64::from(j) / 10.0,
                )
            })
        })
    }

    /// The closed forms of `e^X` for `X(p, r) = [[-p, r], [0, -2 p]]` at `p = x` and `r`,
    /// entries in row-major order: `[[e^-p, r g(p)], [0, e^-2p]]` with `g(p) = u(p) / p`,
    /// `u = e^-p - e^-2p`; its derivatives in `p` and in `r`; its second derivatives in
    /// `(p, p)`, `[[e^-p, r g''], [0, 4 e^-2p]]`, and in `(p, r)`, `[[0, g'], [0, 0]]` (in
    /// `(r, r)` it is zero), `g' = u' / p - u / p^2`, `g'' = u'' / p - 2 u' / p^2 + 2 u / p^3`.
    fn closed_forms(x: f64, r: f64) -> [[f64; 4]; 5] {
        let (e1, e2) = ((-x).exp(), (-2.0 * x).exp());
        let (u, u1, u2) = (e1 - e2, -e1 + 2.0 * e2, e1 - 4.0 * e2);
        let g = u / x;
        let g1 = u1 / x - u / (x * x);
        let g2 = u2 / x - 2.0 * u1 / (x * x) + 2.0 * u / (x * x * x);
        [
            [e1, r * g, 0.0, e2],
            [-e1, r * g1, 0.0, -2.0 * e2],
            [0.0, g, 0.0, 0.0],
            [e1, r * g2, 0.0, 4.0 * e2],
            [0.0, g1, 0.0, 0.0],
        ]
    }

    /// The exponential in three parameters of which its argument moves with two:
    /// `X(p, q, r) = [[-p, r], [0, -2 p]]` ([`closed_forms`]) and `q` entering nowhere, as a
    /// low-pass pole does not enter the device. Over the cell `[1.0, 1.1] x [0, 1] x
    /// [2.0, 2.2]` the [`Dual`] and [`Dual2`] enclosures, computed in `p` and `r` alone,
    /// hold the closed forms' values, first and second derivatives at 11 x 11 points of
    /// `(p, r)`, and their derivatives in `q` are exact zeros; at a point, the [`Dual`]'s
    /// values (a cell's centre) are at most twice as wide as the plain interval
    /// exponential's (about `5e-15` here: the block matrix's norm may take a squaring more,
    /// whose rounding the width is; measured 1.7 times).
    #[test]
    fn exponential_in_the_moving_parameters_holds_closed_forms() {
        let (cp, cq, cr) = (
            Interval::new(1.0, 1.1),
            Interval::new(0.0, 1.0),
            Interval::new(2.0, 2.2),
        );
        let (vp, vr) = (Dual2::<3>::variable(cp, 0), Dual2::<3>::variable(cr, 2));
        // `q` is a variable of the cell that no entry depends on
        let q = Dual2::<3>::variable(cq, 1);
        assert!(!q.is_zero());
        let mut m = Mat::<Dual2<3>>::zeros(2);
        m.set(0, 0, -vp);
        m.set(0, 1, vr);
        m.set(1, 1, -(Dual2::constant(p(2.0)) * vp));
        let second = Dual2::exp_matrix(&m);
        let first_of = |cp: Interval, cr: Interval| {
            let mut m = Mat::<Dual<3>>::zeros(2);
            m.set(0, 0, -Dual::variable(cp, 0));
            m.set(0, 1, Dual::variable(cr, 2));
            m.set(1, 1, -(Dual::constant(p(2.0)) * Dual::variable(cp, 0)));
            Dual::exp_matrix(&m)
        };
        let first = first_of(cp, cr);
        for (e1, e2) in first.v.iter().zip(&second.v) {
            assert!(e1.d[1].is_zero() && e2.d[1].is_zero(), "{e1:?} {e2:?}");
            assert!((0..3).all(|k| e2.h[1][k].is_zero() && e2.h[k][1].is_zero()));
        }
        for (x, r) in cell_grid() {
            let [value, by_p, by_r, pp, pr] = closed_forms(x, r);
            // the f64 closed forms round by a few units of 1
            let slack = 1e-14;
            for n in 0..4 {
                let (a, b) = (&first.v[n], &second.v[n]);
                for (v, d) in [(a.v, a.d), (b.v, b.d)] {
                    assert!(v.contains(value[n], slack), "{n}: {a:?} {b:?}");
                    assert!(d[0].contains(by_p[n], slack), "{n}: {a:?} {b:?}");
                    assert!(d[2].contains(by_r[n], slack), "{n}: {a:?} {b:?}");
                }
                assert!(b.h[0][0].contains(pp[n], slack), "{n}: {b:?}");
                assert!(b.h[0][2].contains(pr[n], slack), "{n}: {b:?}");
                assert!(b.h[2][2].contains(0.0, slack), "{n}: {b:?}");
            }
        }
        // at one point the values are the plain exponential's up to rounding
        let at = first_of(p(1.05), p(2.1));
        let mut plain = Mat::zeros(2);
        plain.set(0, 0, p(-1.05));
        plain.set(0, 1, p(2.1));
        plain.set(1, 1, p(-2.1));
        for (d, e) in at.v.iter().zip(&exp(&plain).v) {
            let (wd, we) = (d.v.hi() - d.v.lo(), e.hi() - e.lo());
            // plus the remainder of degree 12 (below `1e-18` at this norm), which is the
            // whole width of the entry that is an exact zero
            assert!(wd <= 2.0 * we + 1e-17, "{d:?} {e:?}");
        }
    }

    /// `e^M` of a small `f64` matrix by its Taylor series summed to 80 terms without
    /// scaling (for `||M|| <= 16` the omitted terms are below `16^80 / 80! < 1e-22` of the
    /// sum's largest entries): an independent reference.
    fn series(m: &[Vec<f64>]) -> Vec<Vec<f64>> {
        let n = m.len();
        let mut term: Vec<Vec<f64>> = (0..n)
            .map(|i| (0..n).map(|j| f64::from(u8::from(i == j))).collect())
            .collect();
        let mut sum = term.clone();
        for k in 1..80 {
            term = (0..n)
                .map(|i| {
                    (0..n)
                        .map(|j| (0..n).map(|l| term[i][l] * m[l][j]).sum::<f64>() / f64::from(k))
                        .collect()
                })
                .collect();
            for i in 0..n {
                for j in 0..n {
                    sum[i][j] += term[i][j];
                }
            }
        }
        sum
    }

    #[test]
    fn exponentials_keep_the_zeros_no_power_reaches() {
        // a device with a lag, augmented by its input column: `x' = v`, `v' = -delta v + f`,
        // `f' = r (u - f)`, the rate `r` over a cell; no power of it reaches below the
        // diagonal or the last row, which stay exact zeros with exact zero derivatives
        let (delta, cell) = (0.005, Interval::new(1.6, 3.4));
        let build = |r: Dual<1>| {
            let mut m = Mat::<Dual<1>>::zeros(4);
            m.set(0, 1, Dual::constant(p(1.0)));
            m.set(1, 1, Dual::constant(p(-delta)));
            m.set(1, 2, Dual::constant(p(1.0)));
            m.set(2, 2, -r);
            m.set(2, 3, r);
            m
        };
        let reach = paths(&build(Dual::variable(cell, 0)));
        let on_a_path = |i: usize, j: usize| i < 3 && j >= i.max(1);
        for i in 0..4 {
            for j in 0..4 {
                assert_eq!(reach[i * 4 + j], on_a_path(i, j), "{i} {j}");
            }
        }
        let whole = Dual::exp_matrix(&build(Dual::variable(cell, 0)));
        let mut m2 = Mat::<Dual2<1>>::zeros(4);
        for (i, e) in build(Dual::variable(cell, 0)).v.iter().enumerate() {
            let mut x = Dual2::constant(e.v);
            x.d = e.d;
            m2.v[i] = x;
        }
        let second = Dual2::exp_matrix(&m2);
        for i in 0..4 {
            for j in 0..4 {
                if !on_a_path(i, j) && i != j {
                    assert!(whole.at(i, j).negligible(), "{i} {j}: {:?}", whole.at(i, j));
                    assert!(
                        second.at(i, j).negligible(),
                        "{i} {j}: {:?}",
                        second.at(i, j)
                    );
                }
            }
        }
        // at points of the cell the value and the derivative in `r` (Van Loan's block
        // exponential in f64) lie in the enclosures over the cell and at the point
        for step in 0..=8 {
            let r = 1.6 + 1.8 * f64::from(step) / 8.0;
            let x = [
                [0.0, 1.0, 0.0, 0.0],
                [0.0, -delta, 1.0, 0.0],
                [0.0, 0.0, -r, r],
                [0.0; 4],
            ];
            let dx = [[0.0; 4], [0.0; 4], [0.0, 0.0, -1.0, 1.0], [0.0; 4]];
            let block: Vec<Vec<f64>> = (0..8)
                .map(|i| {
                    (0..8)
                        .map(|j| match (i < 4, j < 4) {
                            (true, true) => x[i][j],
                            (true, false) => dx[i][j - 4],
                            (false, false) => x[i - 4][j - 4],
                            (false, true) => 0.0,
                        })
                        .collect()
                })
                .collect();
            let e = series(&block);
            let at = Dual::exp_matrix(&build(Dual::variable(p(r), 0)));
            for (i, row) in e.iter().take(4).enumerate() {
                for j in 0..4 {
                    let (value, slope) = (row[j], row[j + 4]);
                    // the f64 series rounds by a few units of its largest terms (below 20)
                    let slack = 1e-13;
                    for got in [whole.at(i, j), at.at(i, j)] {
                        assert!(got.v.contains(value, slack), "{r} {i} {j}: {got:?} {value}");
                        assert!(
                            got.d[0].contains(slope, slack),
                            "{r} {i} {j}: {got:?} {slope}"
                        );
                    }
                    assert!(second.at(i, j).v.contains(value, slack), "{r} {i} {j}");
                    assert!(second.at(i, j).d[0].contains(slope, slack), "{r} {i} {j}");
                }
            }
        }
    }

    /// The second derivatives in a parameter of small units (a mass of 0.1 kg, entering as
    /// `b T / m`): `X(p) = diag(-c / p, -10 p)`, `c = 5e-4`, whose exponential's entries
    /// `f = e^(-c / p)` and `g = e^(-10 p)` have `f' = c / p^2 f`,
    /// `f'' = (c^2 / p^4 - 2 c / p^3) f`, `g' = -10 g`, `g'' = 100 g`. Over a cell the
    /// enclosures hold them at 11 points; at one point they are a point each up to the
    /// rounding and the remainder, a relative `1e-9` at most whatever the parameter's units.
    #[test]
    fn exponential_second_derivatives_in_small_units() {
        let c = 5e-4;
        let at = |cell: Interval| {
            let v = Dual2::<1>::variable(cell, 0);
            let mut m = Mat::<Dual2<1>>::zeros(2);
            m.set(0, 0, -(Dual2::constant(p(c)) / v));
            m.set(1, 1, -(Dual2::constant(p(10.0)) * v));
            Dual2::exp_matrix(&m)
        };
        let closed = |x: f64| {
            let (f, g) = ((-c / x).exp(), (-10.0 * x).exp());
            let x2 = x * x;
            [
                (f, c / x2 * f, (c * c / (x2 * x2) - 2.0 * c / (x2 * x)) * f),
                (g, -10.0 * g, 100.0 * g),
            ]
        };
        let e = at(Interval::new(0.1, 0.1001));
        for i in 0..=10 {
            let x = 0.1 + 1e-4 * f64::from(i) / 10.0;
            for (entry, (v, d, h)) in [e.at(0, 0), e.at(1, 1)].into_iter().zip(closed(x)) {
                // the f64 closed forms round by a few units of 1
                assert!(entry.v.contains(v, 1e-14), "{x}: {entry:?}");
                assert!(entry.d[0].contains(d, 1e-14), "{x}: {entry:?}");
                assert!(entry.h[0][0].contains(h, 1e-14), "{x}: {entry:?}");
            }
            // the off-diagonal entries are zero, with their derivatives
            for entry in [e.at(0, 1), e.at(1, 0)] {
                let parts = [entry.v, entry.d[0], entry.h[0][0]];
                assert!(parts.iter().all(|x| x.contains(0.0, 0.0)), "{entry:?}");
            }
        }
        let e = at(Interval::point(0.1));
        for (entry, (_, _, h)) in [e.at(0, 0), e.at(1, 1)].into_iter().zip(closed(0.1)) {
            let width = entry.h[0][0].hi() - entry.h[0][0].lo();
            assert!(width < 1e-9 * h.abs(), "{entry:?}");
        }
    }
}
