//! First-order forward differentiation in interval arithmetic: a [`Dual`] holds the
//! enclosure of a quantity over a cell of `N` parameters `p_1, ..., p_N` and the enclosures
//! of its partial derivatives in each of them over the same cell, and each operation applies
//! the rule of calculus for its derivatives (sum, product and quotient rules) in
//! outward-rounded interval arithmetic (Rall, "Automatic Differentiation: Techniques and
//! Applications", LNCS 120, 1981; Moore, Kearfott and Cloud, "Introduction to Interval
//! Analysis", SIAM 2009, section 6.4). For every point of the cell each step's exact value
//! and partial derivatives there lie in its enclosures, so the last step's derivative
//! enclosures hold the partial derivatives of the whole map at every point of the cell: what
//! the mean-value form `f(p) in f(m) + sum_k D_k (p_k - m_k)` ([`MeanValueForm`]) needs.

use std::ops::{Add, Div, Mul, Neg, Sub};

use super::interval::Interval;

/// A quantity over a cell of `N` parameters: `v` encloses its values, `d[k]` its partial
/// derivatives in the parameter `k`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Dual<const N: usize = 1> {
    /// The values over the cell.
    pub(crate) v: Interval,
    /// The partial derivatives over the cell, one per parameter.
    pub(crate) d: [Interval; N],
}

impl<const N: usize> Dual<N> {
    /// A quantity that does not depend on the parameters.
    pub(crate) fn constant(v: Interval) -> Self {
        Self {
            v,
            d: [Interval::point(0.0); N],
        }
    }

    /// The parameter `k` itself over the cell `v` (derivative one in it, zero in the
    /// others).
    pub(crate) fn variable(v: Interval, k: usize) -> Self {
        let mut d = [Interval::point(0.0); N];
        d[k] = Interval::point(1.0);
        Self { v, d }
    }

    /// `f(self)` for a differentiable `f` whose range over an interval `f` encloses and whose
    /// derivative over it `df` encloses (the chain rule).
    pub(crate) fn chain(
        self,
        f: impl Fn(Interval) -> Interval,
        df: impl Fn(Interval) -> Interval,
    ) -> Self {
        let slope = df(self.v);
        Self {
            v: f(self.v),
            d: self.d.map(|d| slope * d),
        }
    }
}

impl<const N: usize> Add for Dual<N> {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Self {
            v: self.v + o.v,
            d: std::array::from_fn(|k| plus(self.d[k], o.d[k])),
        }
    }
}

impl<const N: usize> Sub for Dual<N> {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        Self {
            v: self.v - o.v,
            d: std::array::from_fn(|k| minus(self.d[k], o.d[k])),
        }
    }
}

/// `x + y` for two derivatives, the other one where one is an exact zero: such a sum is
/// exact, where the outward rounding of interval addition would widen it by a unit on each
/// side (and two exact zeros to subnormals). A derivative that stays an exact zero says that the quantity does not move
/// with that parameter, which the exponential uses to leave the parameter out
/// (`crate::certificate::device`'s `in_moving_directions`).
pub(crate) fn plus(x: Interval, y: Interval) -> Interval {
    if y.is_zero() {
        x
    } else if x.is_zero() {
        y
    } else {
        x + y
    }
}

/// `x - y` for two derivatives, exact where one is an exact zero (as [`plus`]).
fn minus(x: Interval, y: Interval) -> Interval {
    if y.is_zero() {
        x
    } else if x.is_zero() {
        -y
    } else {
        x - y
    }
}

impl<const N: usize> Neg for Dual<N> {
    type Output = Self;
    fn neg(self) -> Self {
        Self {
            v: -self.v,
            d: self.d.map(|d| -d),
        }
    }
}

impl<const N: usize> Mul for Dual<N> {
    type Output = Self;
    /// The product rule ([`product_rule`]).
    fn mul(self, o: Self) -> Self {
        Self {
            v: self.v * o.v,
            d: std::array::from_fn(|k| product_rule((self.v, self.d[k]), (o.v, o.d[k]))),
        }
    }
}

impl<const N: usize> Div for Dual<N> {
    type Output = Self;
    /// `(x / y)' = (x' - (x / y) y') / y`: at each point the quotient lies in `v`, so the
    /// derivatives lie in the enclosures.
    fn div(self, o: Self) -> Self {
        let v = self.v / o.v;
        Self {
            v,
            d: std::array::from_fn(|k| quotient_rule(self.d[k], (v, o.v, o.d[k]))),
        }
    }
}

/// `(x y)' = x' y + x y'` from `(x, x')` and `(y, y')`; a term whose derivative is an exact
/// zero is left out (it is exactly zero).
fn product_rule((x, dx): (Interval, Interval), (y, dy): (Interval, Interval)) -> Interval {
    match (dx.is_zero(), dy.is_zero()) {
        (true, true) => Interval::point(0.0),
        (true, false) => x * dy,
        (false, true) => dx * y,
        (false, false) => dx * y + x * dy,
    }
}

/// `(x / y)' = (x' - q y') / y` from `x'` and the quotient `q = x / y`, `y` and `y'`; an
/// exact zero where `x'` and `y'` are.
fn quotient_rule(dx: Interval, (q, y, dy): (Interval, Interval, Interval)) -> Interval {
    if dx.is_zero() && dy.is_zero() {
        Interval::point(0.0)
    } else {
        (dx - q * dy) / y
    }
}

/// Second-order forward differentiation in interval arithmetic: the enclosures over a cell
/// of `N` parameters of a quantity, its partial derivatives `d[k]` and its second partial
/// derivatives `h[k][l]`, each operation by the rules of calculus (the product rule twice,
/// `(x y)_kl = x_kl y + x_k y_l + x_l y_k + x y_kl`, and the quotient's from `x = q y`) in
/// outward-rounded interval arithmetic (Rall 1981, as [`Dual`]). At every point of the cell
/// each step's exact value and derivatives lie in its enclosures, so the last step's `h`
/// holds the whole map's second derivatives over the cell: what the second-order form
/// `f(p) in f(m) + sum_k f_k(m) t_k + 1/2 sum_kl H_kl t_k t_l` (Taylor's theorem with the
/// Lagrange remainder along the segment from `m`) needs.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Dual2<const N: usize> {
    /// The values over the cell.
    pub(crate) v: Interval,
    /// The partial derivatives over the cell.
    pub(crate) d: [Interval; N],
    /// The second partial derivatives over the cell (symmetric).
    pub(crate) h: [[Interval; N]; N],
}

impl<const N: usize> Dual2<N> {
    /// A quantity that does not depend on the parameters.
    pub(crate) fn constant(v: Interval) -> Self {
        let z = Interval::point(0.0);
        Self {
            v,
            d: [z; N],
            h: [[z; N]; N],
        }
    }

    /// The parameter `k` itself over the cell `v`.
    pub(crate) fn variable(v: Interval, k: usize) -> Self {
        let mut x = Self::constant(v);
        x.d[k] = Interval::point(1.0);
        x
    }

    /// `f(self)` for a twice differentiable `f` whose range, derivative and second
    /// derivative over an interval `f`, `df` and `ddf` enclose (the chain rule twice:
    /// `(f o x)_kl = f''(x) x_k x_l + f'(x) x_kl`).
    pub(crate) fn chain2(
        self,
        f: impl Fn(Interval) -> Interval,
        df: impl Fn(Interval) -> Interval,
        ddf: impl Fn(Interval) -> Interval,
    ) -> Self {
        let (f1, f2) = (df(self.v), ddf(self.v));
        Self {
            v: f(self.v),
            d: self.d.map(|d| f1 * d),
            h: symmetric(|k, l| plus(f2 * self.d[k] * self.d[l], f1 * self.h[k][l])),
        }
    }

    /// Every component times the point or interval `x` (a constant factor).
    pub(crate) fn scaled(self, x: Interval) -> Self {
        Self {
            v: self.v * x,
            d: self.d.map(|d| d * x),
            h: self.h.map(|r| r.map(|h| h * x)),
        }
    }

    /// Whether it is an exact zero with exact zero derivatives.
    pub(crate) fn is_zero(&self) -> bool {
        self.v.is_zero()
            && self.d.iter().all(|d| d.is_zero())
            && self.h.iter().all(|r| r.iter().all(|h| h.is_zero()))
    }

    /// `value(v, o.v)` and `f` on each derivative.
    fn zip(
        self,
        o: Self,
        value: impl Fn(Interval, Interval) -> Interval,
        f: impl Fn(Interval, Interval) -> Interval,
    ) -> Self {
        Self {
            v: value(self.v, o.v),
            d: std::array::from_fn(|k| f(self.d[k], o.d[k])),
            h: symmetric(|k, l| f(self.h[k][l], o.h[k][l])),
        }
    }
}

/// The symmetric matrix whose entry `(k, l)`, `k <= l`, is `f(k, l)`: each is computed once
/// and mirrored.
// the indices fill both triangles of the matrix from one computation each
#[allow(clippy::needless_range_loop)]
fn symmetric<const N: usize>(f: impl Fn(usize, usize) -> Interval) -> [[Interval; N]; N] {
    let mut h = [[Interval::point(0.0); N]; N];
    for k in 0..N {
        for l in k..N {
            h[k][l] = f(k, l);
            h[l][k] = h[k][l];
        }
    }
    h
}

impl<const N: usize> Add for Dual2<N> {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        self.zip(o, |a, b| a + b, plus)
    }
}

impl<const N: usize> Sub for Dual2<N> {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        self.zip(o, |a, b| a - b, minus)
    }
}

impl<const N: usize> Neg for Dual2<N> {
    type Output = Self;
    fn neg(self) -> Self {
        self.scaled(Interval::point(-1.0))
    }
}

impl<const N: usize> Mul for Dual2<N> {
    type Output = Self;
    fn mul(self, o: Self) -> Self {
        let (x, y) = (self, o);
        Self {
            v: x.v * y.v,
            d: std::array::from_fn(|k| product_rule((x.v, x.d[k]), (y.v, y.d[k]))),
            h: symmetric(|k, l| second_product(&x, &y, (k, l))),
        }
    }
}

impl<const N: usize> Div for Dual2<N> {
    type Output = Self;
    /// From `x = q y` differentiated twice: `q_k = (x_k - q y_k) / y` and
    /// `q_kl = (x_kl - q_k y_l - q_l y_k - q y_kl) / y`; at each point the quotient and its
    /// derivatives lie in the enclosures, so these do.
    fn div(self, o: Self) -> Self {
        let (x, y) = (self, o);
        let v = x.v / y.v;
        let d: [Interval; N] = std::array::from_fn(|k| quotient_rule(x.d[k], (v, y.v, y.d[k])));
        Self {
            v,
            d,
            h: symmetric(|k, l| second_quotient(&x, &y, (v, &d), (k, l))),
        }
    }
}

/// `(x y)_kl = x_kl y + x_k y_l + x_l y_k + x y_kl`.
fn second_product<const N: usize>(x: &Dual2<N>, y: &Dual2<N>, (k, l): (usize, usize)) -> Interval {
    let first = plus(
        product_rule((x.v, x.h[k][l]), (y.v, y.h[k][l])),
        x.d[k] * y.d[l],
    );
    plus(first, x.d[l] * y.d[k])
}

/// `q_kl = (x_kl - q_k y_l - q_l y_k - q y_kl) / y` for `q = x / y` and its gradient `d`.
fn second_quotient<const N: usize>(
    x: &Dual2<N>,
    y: &Dual2<N>,
    (q, d): (Interval, &[Interval; N]),
    (k, l): (usize, usize),
) -> Interval {
    let top = minus(
        minus(minus(x.h[k][l], d[k] * y.d[l]), d[l] * y.d[k]),
        q * y.h[k][l],
    );
    if top.is_zero() { top } else { top / y.v }
}

/// The mean-value form of a polynomial's coefficients over a cell (the centred form of
/// interval analysis: Moore, Kearfott and Cloud, "Introduction to Interval Analysis", SIAM
/// 2009, section 6.4): for every member of the cell each coefficient lies in
/// `centre_i + sum_k slope_k,i t_k` for some `t_k` in `offset_k`.
///
/// Each coefficient `q_i` is a smooth function of the cell's centred parameters `x`, so
/// `q_i(x) = q_i(m) + sum_k dq_i/dx_k(xi) (x_k - m_k)` for some `xi` on the segment from the
/// middle `m` to `x`, inside the cell (the mean-value theorem along that segment): `centre`
/// encloses the coefficients at `m` (the cell's other parameters as intervals), each
/// `slope_k` the partial derivatives over the whole cell, and `offset_k` holds `x_k - m_k`.
/// The overestimation of the form over the coefficients' true range is second order in the
/// cell's width, where the plain interval extension's is first order.
#[derive(Debug, Clone)]
pub(crate) struct MeanValueForm {
    /// The coefficients' enclosures at the middle, lowest power first.
    pub(crate) centre: Vec<Interval>,
    /// Per centred parameter: its side of the cell (`None` when it is not one the caller
    /// can halve alone, such as a delay's fraction), the enclosures of the coefficients'
    /// partial derivatives in it over the cell, and the offsets `x_k - m_k`.
    pub(crate) slopes: Vec<Slope>,
    /// Whether every side the cell spreads is centred: then [`Self::widest`] names the
    /// side whose halving narrows the form most.
    pub(crate) complete: bool,
}

/// One centred parameter of a [`MeanValueForm`].
#[derive(Debug, Clone)]
pub(crate) struct Slope {
    /// The side of the cell it is, when the caller has one for it.
    pub(crate) side: Option<usize>,
    /// The coefficients' partial derivatives in it over the cell.
    pub(crate) slope: Vec<Interval>,
    /// `[x_lo - m, x_hi - m]`, rounded outward.
    pub(crate) offset: Interval,
}

impl MeanValueForm {
    /// The enclosures of the coefficients over the cell, `centre + sum_k slope_k offset_k`.
    pub(crate) fn coefficients(&self) -> Vec<Interval> {
        let mut out = self.centre.clone();
        for s in &self.slopes {
            for (c, &d) in out.iter_mut().zip(&s.slope) {
                *c = *c + d * s.offset;
            }
        }
        out
    }

    /// For a complete form, the side whose halving narrows the form most: halving a side
    /// halves its offset, which takes half of `|offset_k| sum_i |slope_k,i|` off the form's
    /// width (the centre does not move, and every slope only narrows); the largest of those
    /// wins. `None` for an incomplete form, or one of a side the caller cannot halve.
    pub(crate) fn widest(&self) -> Option<usize> {
        if !self.complete {
            return None;
        }
        let weight = |s: &Slope| s.offset.mag() * s.slope.iter().map(|d| d.mag()).sum::<f64>();
        self.slopes
            .iter()
            .max_by(|a, b| weight(a).total_cmp(&weight(b)))
            .and_then(|s| s.side)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::certificate::Scalar;

    /// The rules against closed forms over a cell: `f(p) = p^2 / (1 + p) - exp(-2 p)` on
    /// `[0.5, 0.6]`, whose derivative `(p^2 + 2 p) / (1 + p)^2 + 2 exp(-2 p)` is enclosed at
    /// 41 points of the cell, as are the values.
    #[test]
    fn rules_enclose_the_derivative_over_the_cell() {
        let cell = Interval::new(0.5, 0.6);
        let x = Dual::<1>::variable(cell, 0);
        let one = Dual::constant(Interval::point(1.0));
        let two = Dual::constant(Interval::point(2.0));
        let f = x * x / (one + x) - (two * x).exp_neg();
        for k in 0..=40 {
            let p = 0.5 + 0.1 * f64::from(k) / 40.0;
            let value = p * p / (1.0 + p) - (-2.0 * p).exp();
            let slope = (p * p + 2.0 * p) / ((1.0 + p) * (1.0 + p)) + 2.0 * (-2.0 * p).exp();
            // the f64 closed forms round by a few units of 1
            assert!(f.v.contains(value, 1e-15), "{p}: {:?} {value}", f.v);
            assert!(f.d[0].contains(slope, 1e-15), "{p}: {:?} {slope}", f.d);
        }
        // the derivative's range over the cell is about [0.97, 1.0]; a loose enclosure would
        // be several times wider
        assert!(f.d[0].hi() - f.d[0].lo() < 0.5, "{:?}", f.d);
    }

    /// The second-order rules against closed forms over a cell of two parameters:
    /// `f(p, q) = p^2 q / (1 + q) - exp(-(2 p + q))` on `[0.5, 0.6] x [1, 1.2]`, its value,
    /// gradient and Hessian enclosed at the 11 x 11 grid of the cell.
    #[test]
    fn second_order_rules_enclose_the_hessian_over_the_cell() {
        let x = Dual2::<2>::variable(Interval::new(0.5, 0.6), 0);
        let y = Dual2::<2>::variable(Interval::new(1.0, 1.2), 1);
        let k = |c: f64| Dual2::constant(Interval::point(c));
        let f = x * x * y / (k(1.0) + y) - (k(2.0) * x + y).exp_neg();
        for i in 0..=10 {
            for j in 0..=10 {
                let p = 0.5 + 0.1 * f64::from(i) / 10.0;
                let q = 1.0 + 0.2 * f64::from(j) / 10.0;
                let e = (-(2.0 * p + q)).exp();
                let s = 1.0 + q;
                let value = p * p * q / s - e;
                let grad = [2.0 * p * q / s + 2.0 * e, p * p / (s * s) + e];
                let hess = [
                    [2.0 * q / s - 4.0 * e, 2.0 * p / (s * s) - 2.0 * e],
                    [2.0 * p / (s * s) - 2.0 * e, -2.0 * p * p / (s * s * s) - e],
                ];
                // the f64 closed forms round by a few units of 1
                assert!(f.v.contains(value, 1e-14), "{p} {q}: {:?} {value}", f.v);
                for a in 0..2 {
                    assert!(f.d[a].contains(grad[a], 1e-14), "{p} {q}: {:?}", f.d);
                    for (h, &want) in f.h[a].iter().zip(&hess[a]) {
                        assert!(h.contains(want, 1e-14), "{p} {q}: {:?}", f.h);
                    }
                }
            }
        }
        // at one point the enclosures are a point each up to rounding
        let x = Dual2::<2>::variable(Interval::point(0.55), 0);
        let y = Dual2::<2>::variable(Interval::point(1.1), 1);
        let g = x * x * y / (k(1.0) + y) - (k(2.0) * x + y).exp_neg();
        assert!(
            g.h.iter().flatten().all(|h| h.hi() - h.lo() < 1e-13),
            "{g:?}"
        );
    }

    /// Two parameters at once: `f(p, r) = p r / (1 + p) - exp(-2 r)` over `[0.5, 0.6] x
    /// [1.0, 1.2]`, whose partial derivatives `r / (1 + p)^2` and `p / (1 + p) + 2 exp(-2 r)`
    /// are enclosed at 11 x 11 points of the cell, as are the values; the mean-value form
    /// `f(m) + D_p (p - m_p) + D_r (r - m_r)` holds every value at those points.
    #[test]
    fn rules_enclose_two_partial_derivatives() {
        let (cp, cr) = (Interval::new(0.5, 0.6), Interval::new(1.0, 1.2));
        let one = Dual::<2>::constant(Interval::point(1.0));
        let two = Dual::<2>::constant(Interval::point(2.0));
        let f = |p: Dual<2>, r: Dual<2>| p * r / (one + p) - (two * r).exp_neg();
        let over = f(Dual::variable(cp, 0), Dual::variable(cr, 1));
        let mid = f(
            Dual::constant(Interval::point(0.55)),
            Dual::constant(Interval::point(1.1)),
        );
        for i in 0..=10 {
            for j in 0..=10 {
                let p = 0.5 + 0.1 * f64::from(i) / 10.0;
                let r = 1.0 + 0.2 * f64::from(j) / 10.0;
                let value = p * r / (1.0 + p) - (-2.0 * r).exp();
                let dp = r / ((1.0 + p) * (1.0 + p));
                let dr = p / (1.0 + p) + 2.0 * (-2.0 * r).exp();
                // the f64 closed forms round by a few units of 1
                assert!(over.v.contains(value, 1e-15), "{p} {r}");
                assert!(over.d[0].contains(dp, 1e-15), "{p} {r}: {:?}", over.d[0]);
                assert!(over.d[1].contains(dr, 1e-15), "{p} {r}: {:?}", over.d[1]);
                let form = MeanValueForm {
                    centre: vec![mid.v],
                    slopes: [(over.d[0], p - 0.55), (over.d[1], r - 1.1)]
                        .into_iter()
                        .enumerate()
                        .map(|(k, (slope, t))| Slope {
                            side: Some(k),
                            slope: vec![slope],
                            offset: Interval::new(t, t),
                        })
                        .collect(),
                    complete: true,
                };
                assert!(form.coefficients()[0].contains(value, 1e-15), "{p} {r}");
            }
        }
        // d/dr is about 0.6 over the cell against 0.06 for d/dp, and r's side is twice p's:
        // halving r narrows the form most
        let form = MeanValueForm {
            centre: vec![mid.v],
            slopes: vec![
                Slope {
                    side: Some(0),
                    slope: vec![over.d[0]],
                    offset: Interval::new(-0.05, 0.05),
                },
                Slope {
                    side: Some(1),
                    slope: vec![over.d[1]],
                    offset: Interval::new(-0.1, 0.1),
                },
            ],
            complete: true,
        };
        assert_eq!(form.widest(), Some(1));
    }
}
