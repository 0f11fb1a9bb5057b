//! The nodes of an `alpha_max` lookup table ([`crate::amax::AmaxTable`]) as rows of a
//! [`Table`], and the device scale that adds their physical columns.

use super::table::{Cell, Table};
use crate::amax::AmaxTable;
use crate::{Error, Result};

/// A device in physical units for tables with physical columns: `None` for normalized only.
pub type TableUnits = Option<DeviceScale>;

/// Mass and period, enough to turn normalized `alpha`, `beta`, `delta` into N/m and N s/m.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DeviceScale {
    /// Moving mass in kg.
    pub mass: f64,
    /// Sampling period in s.
    pub period: f64,
}

impl DeviceScale {
    /// `K = alpha m / T^2` (N/m).
    pub fn k(&self, alpha: f64) -> f64 {
        alpha * (self.mass / (self.period * self.period))
    }

    /// `B = beta m / T` (N s/m).
    pub fn b(&self, beta: f64) -> f64 {
        beta * (self.mass / self.period)
    }

    /// The physical damping `b = delta m / T` (N s/m), as typed when `delta` came from a
    /// decimal damping ([`super::text::as_typed`]: 55 N s/m normalized and scaled back is 55,
    /// not `54.99999999999999`).
    pub fn damping(&self, delta: f64) -> f64 {
        super::text::as_typed(delta * self.mass / self.period)
    }

    /// [`Self::k`], refusing a result that is not a finite number.
    ///
    /// # Errors
    ///
    /// [`Error::InvalidRequest`] when `alpha m / T^2` overflows (or is NaN).
    pub fn try_k(&self, alpha: f64) -> Result<f64> {
        self.finite("stiffness K = alpha m / T^2", "alpha", alpha, self.k(alpha))
    }

    /// [`Self::b`], refusing a result that is not a finite number.
    ///
    /// # Errors
    ///
    /// [`Error::InvalidRequest`] when `beta m / T` overflows (or is NaN).
    pub fn try_b(&self, beta: f64) -> Result<f64> {
        self.finite("damping B = beta m / T", "beta", beta, self.b(beta))
    }

    /// [`Self::damping`], refusing a result that is not a finite number.
    ///
    /// # Errors
    ///
    /// [`Error::InvalidRequest`] when `delta m / T` overflows (or is NaN).
    pub fn try_damping(&self, delta: f64) -> Result<f64> {
        self.finite(
            "damping b = delta m / T",
            "delta",
            delta,
            self.damping(delta),
        )
    }

    /// Checks that every value of `t` converts to a finite physical number ([`Self::try_k`],
    /// [`Self::try_b`], [`Self::try_damping`]), so that no table in physical units holds
    /// `inf` or `NaN`.
    ///
    /// # Errors
    ///
    /// [`Error::InvalidRequest`] naming the first value that overflows.
    pub fn check_table(&self, t: &AmaxTable) -> Result<()> {
        for &x in &t.delta {
            self.try_damping(x)?;
        }
        for (ra, rb) in t.alpha_max.iter().zip(&t.beta_at_max) {
            for (&a, &b) in ra.iter().zip(rb) {
                self.try_k(a)?;
                self.try_b(b)?;
            }
        }
        Ok(())
    }

    fn finite(&self, what: &str, name: &str, normalized: f64, physical: f64) -> Result<f64> {
        if physical.is_finite() {
            return Ok(physical);
        }
        Err(Error::InvalidRequest(format!(
            "the {what} for {name} = {normalized} with mass {:e} kg and period {:e} s is not a finite number; give a device whose mass and period are closer in scale (a smaller mass or a longer period), or work in normalized units",
            self.mass, self.period
        )))
    }

    /// Checks before any work that the conversion factors `m / T^2` and `m / T` are finite
    /// numbers (every non-zero value would overflow otherwise).
    ///
    /// # Errors
    ///
    /// As [`Self::try_k`] and [`Self::try_b`] of 1.
    pub fn check_scale(&self) -> Result<()> {
        self.try_k(1.0)?;
        self.try_b(1.0)?;
        Ok(())
    }

    /// [`Self::k`] of every value.
    pub fn stiffness(&self, alpha: &[Vec<f64>]) -> Vec<Vec<f64>> {
        alpha
            .iter()
            .map(|r| r.iter().map(|&a| self.k(a)).collect())
            .collect()
    }

    /// [`Self::b`] of every value.
    pub fn wall_damping(&self, beta: &[Vec<f64>]) -> Vec<Vec<f64>> {
        beta.iter()
            .map(|r| r.iter().map(|&b| self.b(b)).collect())
            .collect()
    }
}

/// An empty table with the columns of [`lookup_rows`].
pub fn lookup_header(units: &TableUnits) -> Table {
    if units.is_some() {
        Table::new(&[
            "d",
            "delta",
            "alpha_max",
            "beta_at_max",
            "damping_Ns_per_m",
            "K_max_N_per_m",
            "B_at_max_Ns_per_m",
        ])
    } else {
        Table::new(&["d", "delta", "alpha_max", "beta_at_max"])
    }
}

/// The nodes of a lookup table as rows, `d` outer and `delta` inner: columns
/// `d,delta,alpha_max,beta_at_max` (and `damping_Ns_per_m,K_max_N_per_m,B_at_max_Ns_per_m` with units). `nodes` selects a
/// contiguous block of nodes in that order (all of them: `0..delta.len() * d.len()`).
pub fn lookup_rows(t: &AmaxTable, units: &TableUnits, nodes: std::ops::Range<usize>) -> Table {
    let mut out = lookup_header(units);
    let nx = t.delta.len().max(1);
    out.reserve(nodes.len());
    for k in nodes {
        let (i, j) = (k / nx, k % nx);
        let (Some(&d), Some(&x)) = (t.d.get(i), t.delta.get(j)) else {
            break;
        };
        let (a, b) = (t.alpha_max[i][j], t.beta_at_max[i][j]);
        let base = [Cell::Num(d), Cell::Num(x), Cell::Num(a), Cell::Num(b)];
        match units {
            Some(u) => {
                let [c0, c1, c2, c3] = base;
                out.push([
                    c0,
                    c1,
                    c2,
                    c3,
                    Cell::Num(u.damping(x)),
                    Cell::Num(u.k(a)),
                    Cell::Num(u.b(b)),
                ]);
            }
            None => out.push(base),
        }
    }
    out
}
