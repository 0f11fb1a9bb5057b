//! First-order forward differentiation in interval arithmetic: a [`Dual`] holds the
//! enclosure of a quantity over a cell of one parameter `p` and the enclosure of its
//! derivative in `p` over the same cell, and each operation applies the rule of calculus
//! for its derivative (sum, product and quotient rules) in outward-rounded interval
//! arithmetic (Rall, "Automatic Differentiation: Techniques and Applications", LNCS 120,
//! 1981; Moore, Kearfott and Cloud, "Introduction to Interval Analysis", SIAM 2009, section
//! 6.4). For every `p` of the cell each step's exact value and derivative at `p` lie in its
//! two enclosures, so the last step's derivative enclosure holds the derivative of the whole
//! map at every `p` of the cell: what the mean-value form `f(p) in f(p_c) + D (p - p_c)`
//! needs.

use std::ops::{Add, Div, Mul, Neg, Sub};

use super::interval::Interval;

/// A quantity over a cell of one parameter: `v` encloses its values, `d` its derivatives in
/// the parameter.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Dual {
    /// The values over the cell.
    pub(crate) v: Interval,
    /// The derivatives over the cell.
    pub(crate) d: Interval,
}

impl Dual {
    /// A quantity that does not depend on the parameter.
    pub(crate) fn constant(v: Interval) -> Self {
        Self {
            v,
            d: Interval::point(0.0),
        }
    }

    /// The parameter itself over the cell `v` (derivative one).
    pub(crate) fn variable(v: Interval) -> Self {
        Self {
            v,
            d: Interval::point(1.0),
        }
    }
}

impl Add for Dual {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Self {
            v: self.v + o.v,
            d: self.d + o.d,
        }
    }
}

impl Sub for Dual {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        Self {
            v: self.v - o.v,
            d: self.d - o.d,
        }
    }
}

impl Neg for Dual {
    type Output = Self;
    fn neg(self) -> Self {
        Self {
            v: -self.v,
            d: -self.d,
        }
    }
}

impl Mul for Dual {
    type Output = Self;
    fn mul(self, o: Self) -> Self {
        Self {
            v: self.v * o.v,
            d: self.d * o.v + self.v * o.d,
        }
    }
}

impl Div for Dual {
    type Output = Self;
    /// `(x / y)' = (x' - (x / y) y') / y`: at each `p` the quotient lies in `v`, so the
    /// derivative lies in the enclosure.
    fn div(self, o: Self) -> Self {
        let v = self.v / o.v;
        Self {
            v,
            d: (self.d - v * o.d) / o.v,
        }
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
        let x = Dual::variable(cell);
        let one = Dual::constant(Interval::point(1.0));
        let two = Dual::constant(Interval::point(2.0));
        let f = x * x / (one + x) - (two * x).exp_neg();
        for k in 0..=40 {
            let p = 0.5 + 0.1 * f64::from(k) / 40.0;
            let value = p * p / (1.0 + p) - (-2.0 * p).exp();
            let slope = (p * p + 2.0 * p) / ((1.0 + p) * (1.0 + p)) + 2.0 * (-2.0 * p).exp();
            // the f64 closed forms round by a few units of 1
            assert!(f.v.contains(value, 1e-15), "{p}: {:?} {value}", f.v);
            assert!(f.d.contains(slope, 1e-15), "{p}: {:?} {slope}", f.d);
        }
        // the derivative's range over the cell is about [0.97, 1.0]; a loose enclosure would
        // be several times wider
        assert!(f.d.hi() - f.d.lo() < 0.5, "{:?}", f.d);
    }
}
