//! Stability tests: is every root of the characteristic polynomial inside the unit circle?
//!
//! Three methods behind one API ([`Checker`]):
//!
//! - [`Method::SchurCohn`]: the normalized Schur-Cohn recursion, a yes/no answer in `O(n^2)`
//!   without roots or allocation (the fast path for sweeps);
//! - [`Method::Eigen`]: eigenvalues of the companion matrix of `q` (roots and spectral radius);
//! - [`Method::StateSpace`]: eigenvalues of the closed loop's state matrix built directly from
//!   the discretization, without expanding `q` (the well-conditioned route for long delays).
//!
//! Points on the boundary have a root on the unit circle, where every method's answer is
//! decided by rounding. A stated band `margin` around the circle makes them
//! [`Verdict::Marginal`] instead of flip-flopping: stable means spectral radius `< 1 - margin`,
//! unstable means `> 1 + margin`.

pub mod eigen;
pub mod schur_cohn;

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::params::{Normalized, Plant, Wall};
use crate::poly::{CharPoly, Complex, MAX_COEFFS};
pub use schur_cohn::{SchurCohn, schur_cohn};

/// The default width of the marginal band around the unit circle.
///
/// `1e-9` is far above the rounding of the roots of well-conditioned `q` (about `1e-14` for
/// the degrees of short delays) and far below any margin an engineer would design with.
pub const DEFAULT_MARGIN: f64 = 1e-9;

/// How to decide stability.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
#[non_exhaustive]
pub enum Method {
    /// Normalized Schur-Cohn (Jury) recursion on the coefficients of `q`.
    #[default]
    SchurCohn,
    /// Eigenvalues of the companion matrix of `q`.
    Eigen,
    /// Eigenvalues of the closed-loop state matrix (no polynomial expansion).
    StateSpace,
}

impl Method {
    /// The name used on the command line and in JSON.
    pub fn name(&self) -> &'static str {
        match self {
            Method::SchurCohn => "schur-cohn",
            Method::Eigen => "eigen",
            Method::StateSpace => "state-space",
        }
    }
}

/// The answer for one point.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Verdict {
    /// Every root is inside the circle of radius `1 - margin`.
    Stable,
    /// The spectral radius is within `margin` of 1: on the boundary to the stated tolerance.
    Marginal,
    /// Some root has modulus above `1 + margin`.
    Unstable,
}

impl Verdict {
    /// `true` only for [`Verdict::Stable`].
    pub fn is_stable(self) -> bool {
        self == Verdict::Stable
    }

    /// Lower-case name (`stable`, `marginal`, `unstable`).
    pub fn name(self) -> &'static str {
        match self {
            Verdict::Stable => "stable",
            Verdict::Marginal => "marginal",
            Verdict::Unstable => "unstable",
        }
    }

    /// The verdict of a spectral radius against the band `margin`.
    pub fn from_radius(radius: f64, margin: f64) -> Self {
        if radius < 1.0 - margin {
            Verdict::Stable
        } else if radius > 1.0 + margin {
            Verdict::Unstable
        } else {
            Verdict::Marginal
        }
    }
}

/// Options of a stability test.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Options {
    /// Which method decides.
    pub method: Method,
    /// Half-width of the marginal band around the unit circle (see [`DEFAULT_MARGIN`]).
    pub margin: f64,
}

impl Default for Options {
    fn default() -> Self {
        Self {
            method: Method::default(),
            margin: DEFAULT_MARGIN,
        }
    }
}

impl Options {
    /// Checks the margin: finite, in `[0, 0.5)`.
    pub fn validate(&self) -> Result<()> {
        crate::params::in_range("margin", self.margin, 0.0, 0.5 - f64::EPSILON)?;
        Ok(())
    }
}

/// The full answer for one point: verdict, spectral radius, roots.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Analysis {
    /// The verdict of the chosen method.
    pub verdict: Verdict,
    /// Largest root modulus.
    pub spectral_radius: f64,
    /// All roots of `q` (from eigenvalues, whatever method decided).
    pub roots: Vec<Complex>,
    /// Degree of `q`.
    pub degree: usize,
    /// The method that decided.
    pub method: Method,
}

/// Stability tests for one plant: builds `q` once, then tests any number of walls.
#[derive(Debug, Clone)]
pub struct Checker {
    poly: CharPoly,
    options: Options,
}

impl Checker {
    /// A checker for `plant` with `options` (validated).
    pub fn new(plant: &Plant, options: Options) -> Result<Self> {
        options.validate()?;
        Ok(Self {
            poly: CharPoly::new(plant),
            options,
        })
    }

    /// The characteristic polynomial in use.
    pub fn poly(&self) -> &CharPoly {
        &self.poly
    }

    /// The options in use.
    pub fn options(&self) -> &Options {
        &self.options
    }

    /// The verdict for `wall`. With [`Method::SchurCohn`] this allocates nothing and costs
    /// one or two recursions.
    pub fn verdict(&self, wall: &Wall) -> Result<Verdict> {
        match self.options.method {
            Method::SchurCohn => Ok(self.schur_cohn_verdict(wall)),
            Method::Eigen | Method::StateSpace => {
                let roots = self.roots(wall, self.options.method)?;
                Ok(Verdict::from_radius(
                    spectral_radius(&roots),
                    self.options.margin,
                ))
            }
        }
    }

    /// Whether `wall` is stable (marginal counts as not stable).
    pub fn is_stable(&self, wall: &Wall) -> Result<bool> {
        Ok(self.verdict(wall)?.is_stable())
    }

    fn schur_cohn_verdict(&self, wall: &Wall) -> Verdict {
        let m = self.options.margin;
        schur_cohn::with_scratch(self.poly.degree() + 1, |buf| {
            let q = self.poly.coefficients_into(wall, buf);
            if schur_cohn(q, 1.0 - m).stable {
                Verdict::Stable
            } else if schur_cohn(q, 1.0 + m).stable {
                Verdict::Marginal
            } else {
                Verdict::Unstable
            }
        })
    }

    /// The roots of `q` for `wall`, by companion eigenvalues ([`Method::Eigen`] and
    /// [`Method::SchurCohn`]) or by the state matrix ([`Method::StateSpace`]).
    pub fn roots(&self, wall: &Wall, method: Method) -> Result<Vec<Complex>> {
        match method {
            Method::StateSpace => {
                let a = self.poly.discretization().state_matrix(wall);
                eigen::eigenvalues_capped(a).ok_or(Error::NoConvergence {
                    method: "state-space eigenvalues",
                    iterations: a_cap(self.poly.degree()),
                })
            }
            _ => eigen::poly_roots(&self.poly.coefficients(wall)),
        }
    }

    /// The spectral radius without roots: the smallest `r` for which the Schur-Cohn test on
    /// the circle of radius `r` passes, by bisection to `1e-13` relative.
    pub fn spectral_radius_schur_cohn(&self, wall: &Wall) -> f64 {
        let mut buf = [0.0; MAX_COEFFS];
        let q = self.poly.coefficients_into(wall, &mut buf);
        // Cauchy's bound: every root has modulus below 1 + max |a_i / a_m|.
        let lead = q[q.len() - 1];
        let mut hi = 1.0
            + q[..q.len() - 1]
                .iter()
                .fold(0.0f64, |m, c| m.max((c / lead).abs()));
        let mut lo = 0.0;
        // 1e-13 relative: a few hundred ulps, below what the recursion resolves near a root.
        while hi - lo > 1e-13 * hi {
            let mid = 0.5 * (lo + hi);
            if schur_cohn(q, mid).stable {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        hi
    }

    /// Verdict, spectral radius and roots for `wall`.
    ///
    /// The verdict is the chosen method's. The spectral radius is the method's own: for
    /// Schur-Cohn by bisection on the radius (no roots involved), otherwise from the roots.
    /// The roots always come from eigenvalues.
    pub fn analyze(&self, wall: &Wall) -> Result<Analysis> {
        let method = self.options.method;
        let roots_method = if method == Method::StateSpace {
            Method::StateSpace
        } else {
            Method::Eigen
        };
        let roots = self.roots(wall, roots_method)?;
        let (verdict, spectral_radius) = match method {
            Method::SchurCohn => (
                self.schur_cohn_verdict(wall),
                self.spectral_radius_schur_cohn(wall),
            ),
            _ => {
                let r = spectral_radius(&roots);
                (Verdict::from_radius(r, self.options.margin), r)
            }
        };
        Ok(Analysis {
            verdict,
            spectral_radius,
            roots,
            degree: self.poly.degree(),
            method,
        })
    }
}

fn a_cap(degree: usize) -> usize {
    degree * 40 + 100
}

/// Largest modulus among `roots` (0 for none).
pub fn spectral_radius(roots: &[Complex]) -> f64 {
    roots.iter().map(|z| z.norm()).fold(0.0, f64::max)
}

/// One-call analysis of a point given by all four normalized parameters.
///
/// ```
/// use stabound::{params::Normalized, stability::{check, Options, Verdict}};
/// // delta = 0, d = 0: alpha_max = 12 - 8 sqrt 2 at beta = 2 sqrt 2 - 2 (paper, Remark 4).
/// let s2 = 2f64.sqrt();
/// let inside = Normalized { alpha: 12.0 - 8.0 * s2 - 1e-6, beta: 2.0 * s2 - 2.0, delta: 0.0, d: 0.0 };
/// assert_eq!(check(&inside, &Options::default())?.verdict, Verdict::Stable);
/// # Ok::<(), stabound::Error>(())
/// ```
pub fn check(params: &Normalized, options: &Options) -> Result<Analysis> {
    let (plant, wall) = params.split()?;
    Checker::new(&plant, *options)?.analyze(&wall)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn checker(delta: f64, d: f64, method: Method) -> Checker {
        Checker::new(
            &Plant::new(delta, d).unwrap(),
            Options {
                method,
                margin: DEFAULT_MARGIN,
            },
        )
        .unwrap()
    }

    /// Paper's anchor (MATH.md section 6): alpha_max = 12 - 8 sqrt 2 at beta = 2 sqrt 2 - 2
    /// for delta = 0, d = 0, tested through every method.
    #[test]
    fn anchor_d0_delta0() {
        let s2 = 2f64.sqrt();
        let amax = 12.0 - 8.0 * s2;
        let beta = 2.0 * s2 - 2.0;
        for method in [Method::SchurCohn, Method::Eigen, Method::StateSpace] {
            let c = checker(0.0, 0.0, method);
            let inside = Wall::new(amax - 1e-6, beta).unwrap();
            let outside = Wall::new(amax + 1e-6, beta).unwrap();
            assert_eq!(c.verdict(&inside).unwrap(), Verdict::Stable, "{method:?}");
            assert_eq!(
                c.verdict(&outside).unwrap(),
                Verdict::Unstable,
                "{method:?}"
            );
        }
    }

    /// alpha = 0 puts a root at z = 1 exactly (MATH.md section 4): marginal.
    #[test]
    fn alpha_zero_is_marginal() {
        for method in [Method::SchurCohn, Method::Eigen, Method::StateSpace] {
            let c = checker(0.5, 1.0, method);
            let v = c.verdict(&Wall::new(0.0, 0.2).unwrap()).unwrap();
            assert_eq!(v, Verdict::Marginal, "{method:?}");
        }
    }

    #[test]
    fn schur_cohn_radius_matches_roots() {
        let c = checker(0.3, 1.5, Method::SchurCohn);
        let wall = Wall::new(0.1, 0.2).unwrap();
        let a = c.analyze(&wall).unwrap();
        let r_roots = spectral_radius(&a.roots);
        assert!((a.spectral_radius - r_roots).abs() < 1e-10, "{a:?}");
    }
}
