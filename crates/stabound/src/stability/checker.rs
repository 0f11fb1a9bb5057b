//! The one stability test of a [`Loop`]: the paper's loop on its closed-form fast path
//! ([`PaperChecker`]), any other loop on its general polynomial and closed-loop state matrix.

use std::sync::OnceLock;

use nalgebra::DMatrix;

use crate::curve::LoopCurve;
use crate::elements::{GeneralPoly, Loop};
use crate::error::{Error, Result};
use crate::params::Wall;
use crate::poly::Complex;
use crate::stability::certify::{DiskProof, disk_verdict};
use crate::stability::{
    Analysis, Decision, EIGEN_CHECK_DEGREE, MarginalReason, Method, Options, PaperChecker, Verdict,
    eigen, schur_cohn, schur_cohn_guarded, spectral_radius,
};

/// The error assumed on each coefficient of a general loop's polynomial, in units of
/// rounding of its largest coefficient, per degree: the matrix exponential (scaled Pade),
/// La Budde's characteristic polynomial and the Markov parameters each add tens of
/// roundings of the device's entries; `2^10 (n + 8)` is far above what the random-loop
/// tests measure and still far below the default marginal band. Eigenvalue verdicts count
/// only when inclusion discs around the roots decide for every polynomial within it.
const GENERAL_ERROR_ROUNDINGS: f64 = 1024.0;

/// The coefficient error of `poly` in roundings of its largest coefficient, per degree:
/// [`GENERAL_ERROR_ROUNDINGS`], which takes the device's entries as exact to about their
/// rounding, scaled by the stiff discretization's error bound in half-roundings of the
/// device's largest entry when that bound is larger
/// ([`crate::model::Discretization::exp_error_bound`]; the coefficients depend on
/// the entries' errors linearly to first order).
fn error_roundings(poly: &GeneralPoly) -> f64 {
    let bound = poly.discretization().exp_error_bound().unwrap_or(0.0);
    GENERAL_ERROR_ROUNDINGS * (bound / (f64::EPSILON / 2.0)).max(1.0)
}

/// Stability tests for one loop: builds its polynomial once, then tests any number of walls.
///
/// Anything that converts into a [`Loop`] is accepted: a [`crate::Plant`] (the paper's loop)
/// or a loop with elements. For the paper's loop ([`Loop::is_paper`]) the tests run on the
/// closed-form polynomial (`docs/MODEL.md` section 3) with the methods the module
/// documentation describes. For any other loop the methods are the same in kind, on the
/// general polynomial (section 8, both chosen inside [`crate::poly::CharPoly`]) and the closed
/// loop's state matrix ([`crate::model::Discretization::state_matrix`]):
///
/// - [`Method::Auto`]: Schur-Cohn with its rounding-error guard; when the guard cannot vouch
///   for the verdict, the argument-principle count, then the state-space eigenvalues, which
///   decide only where inclusion discs around them prove the verdict for the assumed
///   coefficient error (`2^10 (n + 8)` roundings of the largest); otherwise the verdict is marginal
///   with [`MarginalReason::Undecided`];
/// - the other methods as [`Method`] describes them, eigenvalue verdicts vouched for by the
///   same discs.
///
/// The guard and the count take the coefficients' error as the paper's loop does (their
/// expansion from the wall, `(m + 8) u` of the largest); the matrix exponential adds a few
/// roundings of the device's entries, which near the boundary the marginal band absorbs.
///
/// ```
/// use stabound::elements::{Hand, Loop};
/// use stabound::params::{Plant, Wall};
/// use stabound::stability::{Checker, Options, Verdict};
///
/// let plant = Plant::new(0.1, 1.0)?;
/// // the paper's loop: a plant is a loop with no element
/// let bare = Checker::new(&plant, Options::default())?;
/// assert!(bare.is_paper());
/// // the same device held by a hand of half its mass
/// let held = Checker::new(Loop::new(plant).with_hand(Hand::new(0.5, 0.05, 0.0)?)?, Options::default())?;
/// let wall = Wall::new(0.05, 0.1)?;
/// assert_eq!(bare.verdict(&wall)?, Verdict::Stable);
/// assert_eq!(held.verdict(&wall)?, Verdict::Stable);
/// assert_eq!(held.verdict(&Wall::new(3.0, 0.1)?)?, Verdict::Unstable);
/// # Ok::<(), stabound::Error>(())
/// ```
#[derive(Debug, Clone)]
pub struct Checker {
    inner: Inner,
}

// The paper's checker stays inline (no indirection on the sweeps' hot path); the general
// one, used once per loop with elements, sits behind a box.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone)]
enum Inner {
    Paper(PaperChecker),
    General(Box<General>),
}

#[derive(Debug, Clone)]
struct General {
    poly: GeneralPoly,
    options: Options,
    /// The coefficients' error in roundings of the largest, per degree ([`error_roundings`]).
    roundings: f64,
    /// The loop's D-decomposition, built on the first one-dimensional search.
    curve: OnceLock<LoopCurve>,
}

impl Checker {
    /// A checker for the loop `lp` (a [`crate::Plant`] for the paper's loop) with `options`
    /// (validated).
    #[inline]
    pub fn new(lp: impl Into<Loop>, options: Options) -> Result<Self> {
        let lp = lp.into();
        options.validate()?;
        let inner = if lp.is_paper() {
            Inner::Paper(PaperChecker::new(lp.plant(), options))
        } else {
            let poly = GeneralPoly::new(&lp)?;
            Inner::General(Box::new(General {
                roundings: error_roundings(&poly),
                poly,
                options,
                curve: OnceLock::new(),
            }))
        };
        Ok(Self { inner })
    }

    /// Whether this checker tests the paper's loop (on its closed-form polynomial).
    pub fn is_paper(&self) -> bool {
        matches!(self.inner, Inner::Paper(_))
    }

    /// The D-decomposition of a loop with elements (built once, on first use): the curve the
    /// one-dimensional searches cross. `None` for the paper's loop, whose searches use its
    /// closed-form polynomial.
    pub(crate) fn loop_curve(&self) -> Result<&LoopCurve> {
        match &self.inner {
            Inner::Paper(_) => Err(Error::Numerical(
                "the paper's loop is searched on its closed-form polynomial".into(),
            )),
            Inner::General(g) => {
                if let Some(c) = g.curve.get() {
                    return Ok(c);
                }
                let built = LoopCurve::from_poly(g.poly.clone());
                Ok(g.curve.get_or_init(|| built))
            }
        }
    }

    /// Whether the device has a free integrator, so that `z = 1` is a root on the whole
    /// line `alpha = 0` (`docs/MODEL.md` sections 4 and 8).
    pub(crate) fn free_integrator(&self) -> bool {
        match &self.inner {
            Inner::Paper(_) => true,
            Inner::General(g) => g.poly.discretization().loop_model().free_integrator(),
        }
    }

    /// The affine form `q = Q0 + alpha QA + beta QB`: the three coefficient vectors, lowest
    /// power first, each `degree + 1` long.
    pub(crate) fn affine(&self) -> [Vec<f64>; 3] {
        match &self.inner {
            Inner::Paper(c) => {
                let poly = c.poly();
                let len = poly.degree() + 1;
                [
                    (0..len).map(|i| poly.q0(i)).collect(),
                    (0..len).map(|i| poly.qa(i)).collect(),
                    (0..len).map(|i| poly.qb(i)).collect(),
                ]
            }
            Inner::General(g) => [
                g.poly.q0().to_vec(),
                g.poly.qa().to_vec(),
                g.poly.qb().to_vec(),
            ],
        }
    }

    /// The options in use.
    pub fn options(&self) -> &Options {
        match &self.inner {
            Inner::Paper(c) => c.options(),
            Inner::General(g) => &g.options,
        }
    }

    /// Degree of the characteristic polynomial.
    pub fn degree(&self) -> usize {
        match &self.inner {
            Inner::Paper(c) => c.poly().degree(),
            Inner::General(g) => g.poly.degree(),
        }
    }

    /// The coefficients of `q` for `wall`, lowest power first.
    pub fn coefficients(&self, wall: &Wall) -> Vec<f64> {
        match &self.inner {
            Inner::Paper(c) => c.poly().coefficients(wall),
            Inner::General(g) => g.poly.coefficients(wall),
        }
    }

    /// Writes the `degree + 1` coefficients of `q` for `wall` into `out` (lowest power
    /// first) and returns that slice; `out` must hold at least `degree + 1` values (a
    /// caller's bug otherwise: [`crate::poly::MAX_COEFFS`] always suffices).
    pub(crate) fn coefficients_into<'a>(&self, wall: &Wall, out: &'a mut [f64]) -> &'a [f64] {
        match &self.inner {
            Inner::Paper(c) => c.poly().coefficients_into(wall, out),
            Inner::General(g) => g.poly.coefficients_into(wall, out),
        }
    }

    /// The closed loop's state matrix for `wall` (its eigenvalues are the roots of `q`).
    pub fn state_matrix(&self, wall: &Wall) -> DMatrix<f64> {
        match &self.inner {
            Inner::Paper(c) => c.poly().discretization().state_matrix(wall),
            Inner::General(g) => g.poly.discretization().state_matrix(wall),
        }
    }

    /// Schur-Cohn at radius exactly 1, no margin and no guard: the point test of the
    /// boundary engines, which locate where a root crosses the circle to rounding. At
    /// `alpha = 0` on a device with a free integrator, where `z = 1` is a root for every
    /// `beta`, the other roots decide (`q / (z - 1)`, the limit `alpha -> 0+`).
    pub(crate) fn unit_circle_stable(&self, wall: &Wall) -> bool {
        let free = self.free_integrator();
        schur_cohn::with_two_rows(self.degree() + 1, |q, out| {
            let q = self.coefficients_into(wall, q);
            // exactly zero on purpose: only there is z = 1 a root for every beta
            if free && wall.alpha == 0.0 {
                crate::stability::schur_cohn(crate::poly::deflate_linear(q, 1.0, out), 1.0).stable
            } else {
                crate::stability::schur_cohn(q, 1.0).stable
            }
        })
    }

    /// The verdict for `wall`.
    pub fn verdict(&self, wall: &Wall) -> Result<Verdict> {
        Ok(self.decide(wall)?.verdict)
    }

    /// Whether `wall` is stable (marginal counts as not stable).
    pub fn is_stable(&self, wall: &Wall) -> Result<bool> {
        Ok(self.verdict(wall)?.is_stable())
    }

    /// The verdict for `wall` with the method that reached it and whether a fallback
    /// happened.
    pub fn decide(&self, wall: &Wall) -> Result<Decision> {
        match &self.inner {
            Inner::Paper(c) => c.decide(wall),
            Inner::General(g) => g.decide(wall),
        }
    }

    /// The roots of `q` for `wall`: companion eigenvalues, or for [`Method::StateSpace`] the
    /// eigenvalues of the state matrix.
    pub fn roots(&self, wall: &Wall, method: Method) -> Result<Vec<Complex>> {
        match &self.inner {
            Inner::Paper(c) => c.roots(wall, method),
            Inner::General(g) => g.roots(wall, method),
        }
    }

    /// Verdict, spectral radius and roots for `wall`.
    ///
    /// The verdict is that of [`Checker::decide`]. The spectral radius is the deciding
    /// method's roots' (for the paper's loop the companion matrix's or the state matrix's,
    /// each falling back to the other; for a loop with elements always from the roots).
    pub fn analyze(&self, wall: &Wall) -> Result<Analysis> {
        match &self.inner {
            Inner::Paper(c) => c.analyze(wall),
            Inner::General(g) => g.analyze(wall),
        }
    }

    /// The decision of [`Checker::decide`] with the spectral radius [`Checker::analyze`]
    /// reports, without keeping the roots: for the paper's loop at a short delay nothing is
    /// collected on the heap, which makes this the call for many walls that print only the
    /// radius.
    ///
    /// ```
    /// use stabound::params::{Plant, Wall};
    /// use stabound::stability::{Checker, Options};
    ///
    /// let c = Checker::new(&Plant::new(0.5, 1.0)?, Options::default())?;
    /// let wall = Wall::new(0.1, 0.3)?;
    /// let (decision, radius) = c.decide_with_radius(&wall)?;
    /// let an = c.analyze(&wall)?;
    /// assert_eq!((decision.verdict, decision.method), (an.verdict, an.method));
    /// // the same number, bit for bit
    /// assert_eq!(radius.to_bits(), an.spectral_radius.to_bits());
    /// # Ok::<(), stabound::Error>(())
    /// ```
    ///
    /// # Errors
    ///
    /// As [`Checker::analyze`].
    pub fn decide_with_radius(&self, wall: &Wall) -> Result<(Decision, f64)> {
        match &self.inner {
            Inner::Paper(c) => c.decide_with_radius(wall),
            Inner::General(g) => {
                let an = g.analyze(wall)?;
                let decision = Decision {
                    verdict: an.verdict,
                    method: an.method,
                    fallback: an.fallback,
                    reason: an.reason,
                };
                Ok((decision, an.spectral_radius))
            }
        }
    }

    /// The decision of [`Checker::decide`] and, only when its verdict is marginal, the
    /// spectral radius [`Checker::decide_with_radius`] reports for the wall (its error where
    /// the roots fail): one decision, and no roots for a stable or unstable wall.
    pub(crate) fn decide_with_marginal_radius(
        &self,
        wall: &Wall,
    ) -> Result<(Decision, Option<Result<f64>>)> {
        match &self.inner {
            Inner::Paper(c) => c.decide_with_marginal_radius(wall),
            Inner::General(g) => {
                let decision = g.decide(wall)?;
                let radius = (decision.verdict == Verdict::Marginal).then(|| {
                    g.analyzed_roots(wall, &decision)
                        .map(|roots| spectral_radius(&roots))
                });
                Ok((decision, radius))
            }
        }
    }

    /// The verdict of the unguarded Schur-Cohn recursion at both circles of the verdict,
    /// without error bound: the fast test for sweeps that accept a verdict decided by
    /// rounding.
    pub fn unguarded_verdict(&self, wall: &Wall) -> Verdict {
        match &self.inner {
            Inner::Paper(c) => c.unguarded_verdict(wall),
            Inner::General(g) => g.schur_cohn_verdict(wall),
        }
    }

    /// The spectral radius of the closed loop for `wall`, as a report prints it: for the
    /// paper's loop by Schur-Cohn bisection on the radius (no roots,
    /// [`Checker::spectral_radius_schur_cohn`]), for a loop with elements from the roots of
    /// [`Checker::analyze`] (the same number `check` prints).
    ///
    /// # Errors
    ///
    /// As [`Checker::analyze`].
    pub fn spectral_radius(&self, wall: &Wall) -> Result<f64> {
        match &self.inner {
            Inner::Paper(c) => Ok(c.spectral_radius_schur_cohn(wall)),
            Inner::General(g) => Ok(g.analyze(wall)?.spectral_radius),
        }
    }

    /// The spectral radius without roots: the smallest `r` for which the Schur-Cohn test on
    /// the circle of radius `r` passes, by bisection to `1e-13` relative.
    ///
    /// Returns NaN when the coefficients are not finite (no radius can be bracketed).
    pub fn spectral_radius_schur_cohn(&self, wall: &Wall) -> f64 {
        match &self.inner {
            Inner::Paper(c) => c.spectral_radius_schur_cohn(wall),
            Inner::General(g) => {
                g.coefficients(wall, crate::stability::spectral_radius_of_coefficients)
            }
        }
    }
}

impl General {
    fn coefficients<R>(&self, wall: &Wall, f: impl FnOnce(&[f64]) -> R) -> R {
        let len = self.poly.degree() + 1;
        schur_cohn::with_scratch(len, |buf| f(self.poly.coefficients_into(wall, buf)))
    }

    fn decide(&self, wall: &Wall) -> Result<Decision> {
        let requested = self.options.method;
        let decision = |verdict: Verdict, method| Decision {
            verdict,
            method,
            fallback: method != requested
                && !(requested == Method::Auto && method == Method::SchurCohn),
            reason: (verdict == Verdict::Marginal).then_some(MarginalReason::WithinMargin),
        };
        let undecided = |method| Decision {
            verdict: Verdict::Marginal,
            method,
            fallback: method != requested,
            reason: Some(MarginalReason::Undecided),
        };
        let state_space = || -> Result<Decision> {
            Ok(match self.eigen_verdict(wall, Method::StateSpace)? {
                Some(v) => decision(v, Method::StateSpace),
                None => undecided(Method::StateSpace),
            })
        };
        match requested {
            Method::SchurCohn => Ok(decision(self.schur_cohn_verdict(wall), Method::SchurCohn)),
            Method::Auto => match self.guarded_verdict(wall) {
                Some(v) => Ok(decision(v, Method::SchurCohn)),
                None => match self.counted_verdict(wall) {
                    Some(v) => Ok(decision(v, Method::ArgumentPrinciple)),
                    None => state_space(),
                },
            },
            Method::ArgumentPrinciple => match self.counted_verdict(wall) {
                Some(v) => Ok(decision(v, Method::ArgumentPrinciple)),
                None => state_space(),
            },
            Method::StateSpace => state_space(),
            Method::Eigen => match self.eigen_verdict(wall, Method::Eigen)? {
                Some(v) => Ok(decision(v, Method::Eigen)),
                None => state_space(),
            },
            Method::Certified => state_space(),
        }
    }

    /// Schur-Cohn with the roots on the circle at `z = +-1` (free integrators, two-sample
    /// averages) deflated first, within the coefficients' error model.
    fn schur_cohn_verdict(&self, wall: &Wall) -> Verdict {
        let m = self.options.margin;
        self.coefficients(wall, |q| schur_cohn::deflated_verdict(q, m, self.roundings))
    }

    /// As [`Checker`]'s guarded verdict: stable needs a trusted pass at `1 - margin`,
    /// unstable a trusted failure at `1 + margin`, marginal both of the other kind.
    fn guarded_verdict(&self, wall: &Wall) -> Option<Verdict> {
        // the guard's error model is the rounding of the coefficients: not for a stiff
        // device whose discretization's bound is larger
        if self.roundings > GENERAL_ERROR_ROUNDINGS {
            return None;
        }
        let m = self.options.margin;
        self.coefficients(wall, |q| {
            let inner = schur_cohn_guarded(q, 1.0 - m);
            if inner.stable {
                return inner.trusted.then_some(Verdict::Stable);
            }
            let outer = schur_cohn_guarded(q, 1.0 + m);
            if !outer.stable {
                return outer.trusted.then_some(Verdict::Unstable);
            }
            (inner.trusted && outer.trusted).then_some(Verdict::Marginal)
        })
    }

    /// Proven root counts inside `1 - margin` and `1 + margin`, with the same coefficient
    /// error and step cap as [`Checker`]; `None` for more than [`crate::stability::winding::MAX_TERMS`]
    /// nonzero terms (long moving averages) or a root too near a circle (the counting stage
    /// shared with [`Checker`], with no enclosure to widen the coefficient error).
    fn counted_verdict(&self, wall: &Wall) -> Option<Verdict> {
        let m = self.options.margin;
        let stiff = self.roundings > GENERAL_ERROR_ROUNDINGS;
        self.coefficients(wall, |q| {
            let amax = q.iter().fold(0.0f64, |a, c| a.max(c.abs()));
            let err = if stiff {
                self.roundings * (q.len() as f64 + 7.0) * f64::EPSILON * amax
            } else {
                0.0
            };
            crate::stability::count_verdict(q, m, err)
        })
    }

    /// The verdict of `method`'s roots when inclusion discs around them prove it for every
    /// polynomial within [`GENERAL_ERROR_ROUNDINGS`] of the computed one; `None` otherwise.
    fn eigen_verdict(&self, wall: &Wall, method: Method) -> Result<Option<Verdict>> {
        let Ok(roots) = self.roots(wall, method) else {
            return Ok(None);
        };
        let q = self.poly.coefficients(wall);
        let amax = q.iter().fold(0.0f64, |m, c| m.max(c.abs()));
        let n = q.len() as f64 + 7.0;
        let err = self.roundings * n * f64::EPSILON * amax;
        // exact zeros are structural powers of z, known without error
        let errs: Vec<f64> = q
            .iter()
            .map(|&c| if c == 0.0 { 0.0 } else { err })
            .collect();
        Ok(
            disk_verdict(&q, &errs, &roots, self.options.margin).map(|p| match p {
                DiskProof::Stable => Verdict::Stable,
                DiskProof::Unstable => Verdict::Unstable,
                DiskProof::Marginal => Verdict::Marginal,
            }),
        )
    }

    fn roots(&self, wall: &Wall, method: Method) -> Result<Vec<Complex>> {
        match method {
            Method::StateSpace => {
                let a = self.poly.discretization().state_matrix(wall);
                eigen::eigenvalues_capped(a).ok_or(Error::NoConvergence {
                    method: "state-space eigenvalues",
                    iterations: self.poly.degree() * 40 + 100,
                })
            }
            _ => eigen::poly_roots(&self.poly.coefficients(wall)),
        }
    }

    fn analyze(&self, wall: &Wall) -> Result<Analysis> {
        let decision = self.decide(wall)?;
        let roots = self.analyzed_roots(wall, &decision)?;
        Ok(Analysis {
            verdict: decision.verdict,
            spectral_radius: spectral_radius(&roots),
            roots,
            degree: self.poly.degree(),
            method: decision.method,
            requested: self.options.method,
            fallback: decision.fallback,
            reason: decision.reason,
        })
    }

    /// The roots [`General::analyze`] reports once `decision` is made: the state matrix's
    /// where it decided or above [`EIGEN_CHECK_DEGREE`], else the companion matrix's.
    fn analyzed_roots(&self, wall: &Wall, decision: &Decision) -> Result<Vec<Complex>> {
        let long = self.poly.degree() > EIGEN_CHECK_DEGREE;
        let roots_method = if decision.method == Method::StateSpace || long {
            Method::StateSpace
        } else {
            Method::Eigen
        };
        self.roots(wall, roots_method)
    }
}
