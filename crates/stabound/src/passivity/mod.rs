//! Colgate's passivity condition and how it compares with the exact stable region.
//!
//! Colgate and Schenkel ("Passivity of a class of sampled-data systems: application to haptic
//! interfaces", ACC 1994) showed that the undelayed loop (`d = 0`) is passive when
//! `b > K T / 2 + |B|`; in the normalized parameters (paper eq. 21, `docs/MODEL.md` section 5)
//!
//! ```text
//! delta > alpha / 2 + |beta|
//! ```
//!
//! In the `(alpha, beta)` plane the region is the open triangle with corners `(0, delta)`,
//! `(2 delta, 0)`, `(0, -delta)`; in the `(delta, beta)` plane at fixed `alpha` it is the
//! wedge `|beta| < delta - alpha / 2`. Hulin et al. (IROS 2006, Section VI) observe that it
//! lies inside the stable region for `d = 0` and crosses the stability boundary for `d > 0`;
//! [`contained_alpha_beta`] and [`contained_delta_beta`] decide that by point tests.
//!
//! [`PassiveRegion`] and [`compare`] generalize the condition to any whole-sample delay and velocity filter
//! (the model document, docs/MODEL.md, section 9): the exact passive region in both planes,
//! the largest passive stiffness, and the comparison with the exact stable region by areas
//! and witnesses, the stable region being the exact boundary of the loop with that filter;
//! [`compare_on_lines`] and [`compare_delta_beta`] compare the same regions on lines of the
//! plane (exact stable sets on each line), in both planes. [`figures`] draws the companions of Figs. 8 and 9 for `d = 1, 2, 4`.

mod columns;
mod delay;
mod quantized;

pub use columns::{
    AlphaBetaComparison, ColumnComparison, ComparePlane, DEFAULT_COLUMNS, MAX_COLUMNS, Summary,
    compare_alpha_beta, compare_delta_beta, compare_on_lines,
};
pub use delay::{
    Comparison, Criterion, Edge, MAX_EDGE_POINTS, MAX_TOL_REL, PassivePiece, PassiveRegion,
    ThetaMax, Witness, compare,
};
pub use quantized::{QuantizedPassivity, quantized};

use crate::error::{Error, Result};
use crate::params::{MAX_DELTA, Plant, Wall, finite, in_range};
use crate::poly::MAX_COEFFS;
use crate::stability::{Checker, DEFAULT_MARGIN, Options, Verdict, schur_cohn};

/// The verdict of `checker` for `wall`, except on the line `alpha = 0`, where the root `z = 1`
/// is always present and the verdict is that of the limit `alpha -> 0+` (`docs/MODEL.md` section
/// 4): the remaining roots, `q(z) / (z - 1)`, judged by Schur-Cohn with the default band.
fn point_verdict(checker: &Checker, wall: &Wall) -> Result<Verdict> {
    // Exact zero on purpose: only exactly alpha = 0 has the root z = 1 for every beta.
    if wall.alpha().abs() > 0.0 {
        return checker.verdict(wall);
    }
    let mut buf = [0.0; MAX_COEFFS];
    let q = checker.coefficients_into(wall, &mut buf);
    // Synthetic division by (z - 1), highest power down: r_{i-1} = a_i + r_i.
    let m = q.len() - 1;
    let mut r = [0.0; MAX_COEFFS];
    r[m - 1] = q[m];
    for i in (1..m).rev() {
        r[i - 1] = q[i] + r[i];
    }
    let r = &r[..m];
    Ok(if schur_cohn(r, 1.0 - DEFAULT_MARGIN).stable {
        Verdict::Stable
    } else if schur_cohn(r, 1.0 + DEFAULT_MARGIN).stable {
        Verdict::Marginal
    } else {
        Verdict::Unstable
    })
}

/// Whether `(alpha, beta)` satisfies Colgate's passivity condition `delta > alpha/2 + |beta|`
/// (eq. 21). Strict, as in the paper: the boundary itself is not passive.
pub fn is_passive(delta: f64, wall: &Wall) -> bool {
    delta > wall.alpha() / 2.0 + wall.beta().abs()
}

/// The boundary of the passive region in the `(alpha, beta)` plane for `delta`, as the
/// polyline `(0, delta) -> (2 delta, 0) -> (0, -delta)`; the region is the open triangle it
/// closes with the axis `alpha = 0`. Empty for `delta = 0` (no passive wall).
pub fn boundary_alpha_beta(delta: f64) -> Vec<(f64, f64)> {
    if delta > 0.0 {
        vec![(0.0, delta), (2.0 * delta, 0.0), (0.0, -delta)]
    } else {
        Vec::new()
    }
}

/// The boundary of the passive region in the `(delta, beta)` plane for stiffness `alpha`,
/// drawn up to `delta_max`: the polyline `(delta_max, delta_max - alpha/2) -> (alpha/2, 0) ->
/// (delta_max, -(delta_max - alpha/2))`. The region is the open wedge between its arms. Empty
/// when `delta_max <= alpha / 2`.
pub fn boundary_delta_beta(alpha: f64, delta_max: f64) -> Vec<(f64, f64)> {
    let apex = alpha.max(0.0) / 2.0;
    if delta_max > apex {
        let h = delta_max - apex;
        vec![(delta_max, h), (apex, 0.0), (delta_max, -h)]
    } else {
        Vec::new()
    }
}

/// The answer of a containment check.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Containment {
    /// No tested passive point was unstable.
    pub inside: bool,
    /// How many passive points were tested.
    pub tested: usize,
    /// How many of them were marginal (within the checker's band of the unit circle).
    pub marginal: usize,
    /// A passive point found unstable (as `(alpha, beta, delta)`), when `inside` is false.
    pub witness: Option<(f64, f64, f64)>,
}

/// Points per side of the test grids: the passive triangle or wedge is sampled on a
/// `GRID x GRID` lattice of interior points.
pub const GRID: usize = 48;

fn check_grid(grid: usize) -> Result<usize> {
    if !(2..=10_000).contains(&grid) {
        return Err(Error::InvalidRequest(format!(
            "grid of {grid} points per side: give between 2 and 10000"
        )));
    }
    Ok(grid)
}

/// Whether the passive region for `delta` lies inside the stable region of `(delta, d)`, in
/// the `(alpha, beta)` plane.
///
/// Method: point tests (Schur-Cohn, [`Checker::verdict`]) on a lattice of `grid x grid` points
/// strictly inside the passive triangle (`alpha_i = 2 delta i / (grid + 1)`, `beta` evenly
/// spaced strictly between the two arms). A marginal verdict counts as inside: the triangle's
/// corner `(0, -delta)` is also the stable region's lowest point (paper eq. 19), so lattice
/// points near it sit on the boundary within rounding. The first unstable point, scanning
/// `alpha` upward, is returned as the witness.
///
/// A lattice cannot prove containment between its points; with the default [`GRID`] a
/// protrusion narrower than `2 delta / 49` would be missed.
pub fn contained_alpha_beta(delta: f64, d: f64, grid: usize) -> Result<Containment> {
    in_range("delta", delta, 0.0, MAX_DELTA)?;
    let grid = check_grid(grid)?;
    let plant = Plant::new(delta, d)?;
    let checker = Checker::new(plant, Options::default())?;
    let mut scan = Scan::default();
    if delta > 0.0 {
        for i in 1..=grid {
            let alpha = 2.0 * delta * i as f64 / (grid + 1) as f64;
            let half = delta - alpha / 2.0;
            for j in 1..=grid {
                let beta = -half + 2.0 * half * j as f64 / (grid + 1) as f64;
                if let Some(found) = scan.test(&checker, alpha, beta, delta)? {
                    return Ok(found);
                }
            }
        }
    }
    Ok(scan.inside())
}

/// Point tests over a passive region, counting them and stopping at the first unstable one.
#[derive(Default)]
struct Scan {
    tested: usize,
    marginal: usize,
}

impl Scan {
    /// Tests one wall; `Some` ends the scan with an unstable passive witness.
    fn test(
        &mut self,
        checker: &Checker,
        alpha: f64,
        beta: f64,
        delta: f64,
    ) -> Result<Option<Containment>> {
        self.tested += 1;
        match point_verdict(checker, &Wall { alpha, beta })? {
            Verdict::Unstable => Ok(Some(Containment {
                inside: false,
                tested: self.tested,
                marginal: self.marginal,
                witness: Some((alpha, beta, delta)),
            })),
            Verdict::Marginal => {
                self.marginal += 1;
                Ok(None)
            }
            Verdict::Stable => Ok(None),
        }
    }

    /// The result when no tested point was unstable.
    fn inside(self) -> Containment {
        Containment {
            inside: true,
            tested: self.tested,
            marginal: self.marginal,
            witness: None,
        }
    }
}

/// Whether the passive wedge for stiffness `alpha` lies inside the stable region of delay `d`
/// in the `(delta, beta)` plane, for `delta` up to `delta_max`.
///
/// Method: point tests as in [`contained_alpha_beta`], on `grid` values of `delta` strictly
/// between `alpha/2` and `delta_max` (plus `delta_max`) and `grid` values of `beta` strictly
/// inside the wedge at each; one [`Checker`] per `delta`. At `alpha = 0` (paper Fig. 9's first
/// slice) the always-present root `z = 1` is divided out: the slice is the limit `alpha -> 0+`.
pub fn contained_delta_beta(
    alpha: f64,
    d: f64,
    delta_max: f64,
    grid: usize,
) -> Result<Containment> {
    finite("alpha", alpha)?;
    in_range("delta_max", delta_max, 0.0, MAX_DELTA)?;
    let grid = check_grid(grid)?;
    let apex = alpha.max(0.0) / 2.0;
    let mut scan = Scan::default();
    if delta_max > apex {
        for i in 1..=grid {
            let delta = apex + (delta_max - apex) * i as f64 / grid as f64;
            let checker = Checker::new(Plant::new(delta, d)?, Options::default())?;
            let half = delta - apex;
            for j in 1..=grid {
                let beta = -half + 2.0 * half * j as f64 / (grid + 1) as f64;
                if let Some(found) = scan.test(&checker, alpha, beta, delta)? {
                    return Ok(found);
                }
            }
        }
    }
    Ok(scan.inside())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stability::{Method, spectral_radius};

    #[test]
    fn condition_and_polylines() {
        // eq. (21) at a few points, including the open boundary.
        assert!(is_passive(1.0, &Wall::new(1.0, 0.4).unwrap()));
        assert!(!is_passive(1.0, &Wall::new(1.0, 0.5).unwrap()));
        assert!(!is_passive(1.0, &Wall::new(1.0, -0.6).unwrap()));
        assert!(!is_passive(0.0, &Wall::new(0.0, 0.0).unwrap()));
        // Every vertex of the polylines lies on the region's boundary
        // delta = alpha/2 + |beta| (exact in binary for these values).
        for &delta in &[0.25, 1.0, 3.0] {
            for (a, b) in boundary_alpha_beta(delta) {
                assert!((a / 2.0 + b.abs() - delta).abs() < 1e-15);
            }
        }
        for &alpha in &[0.0, 1.0, 4.0] {
            for (dl, b) in boundary_delta_beta(alpha, 5.0) {
                assert!((alpha / 2.0 + b.abs() - dl).abs() < 1e-15);
            }
        }
        assert!(boundary_alpha_beta(0.0).is_empty());
        assert!(boundary_delta_beta(4.0, 2.0).is_empty());
    }

    /// Paper Section VI: for d = 0 the passive region is a subset of the stable one, in both
    /// planes (Figs. 8 and 9), including large delta where the slope -1/2 line bounds the
    /// stable region (Fig. 7).
    #[test]
    fn passive_inside_stable_for_no_delay() {
        for &delta in &[0.25, 0.5, 0.75, 1.0, 3.0, 10.0] {
            let c = contained_alpha_beta(delta, 0.0, GRID).unwrap();
            assert!(c.inside, "delta {delta}: {c:?}");
            assert_eq!(c.tested, GRID * GRID);
            assert_eq!(c.marginal, 0, "delta {delta}");
        }
        for &alpha in &[0.0, 1.0, 2.0, 4.0] {
            let c = contained_delta_beta(alpha, 0.0, 8.0, GRID).unwrap();
            assert!(c.inside, "alpha {alpha}: {c:?}");
            assert_eq!(c.marginal, 0, "alpha {alpha}");
        }
    }

    /// Paper Section VI: for d > 0 the passive region crosses the stability boundary. The
    /// witness is confirmed passive by eq. (21) and unstable by state-space eigenvalues, a
    /// method independent of the Schur-Cohn test that found it.
    #[test]
    fn passive_not_inside_for_delay() {
        for &d in &[1.0, 2.0, 0.5] {
            let c = contained_alpha_beta(1.0, d, GRID).unwrap();
            assert!(!c.inside, "d {d}");
            let (a, b, dl) = c.witness.unwrap();
            let wall = Wall::new(a, b).unwrap();
            assert!(is_passive(dl, &wall));
            let plant = Plant::new(dl, d).unwrap();
            let checker = Checker::new(plant, Options::default()).unwrap();
            let r = spectral_radius(&checker.roots(&wall, Method::StateSpace).unwrap());
            assert!(r > 1.0, "d {d}: radius {r}");
        }
        let c = contained_delta_beta(2.0, 1.0, 8.0, GRID).unwrap();
        assert!(!c.inside);
    }

    #[test]
    fn bad_requests() {
        assert!(contained_alpha_beta(-1.0, 0.0, GRID).is_err());
        assert!(contained_alpha_beta(1.0, 0.0, 1).is_err());
        assert!(contained_delta_beta(f64::NAN, 0.0, 1.0, GRID).is_err());
    }
}
