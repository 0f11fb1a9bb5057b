//! Stability tests: is every root of the characteristic polynomial inside the unit circle?
//!
//! The methods behind one API ([`Checker`]):
//!
//! - [`Method::SchurCohn`]: the Schur-Cohn recursion with its rounding-error guard, a yes/no
//!   answer in `O(n^2)` without roots or allocation ([`Checker::unguarded_verdict`] is the
//!   division-free recursion without the guard, the fast path for sweeps);
//! - [`Method::Eigen`]: eigenvalues of the companion matrix of `q` (roots and spectral radius),
//!   the verdict proven by inclusion discs around them;
//! - [`Method::StateSpace`]: eigenvalues of the closed loop's state matrix built directly from
//!   the discretization, without expanding `q` (the well-conditioned route for long delays);
//! - [`Method::ArgumentPrinciple`]: proven counts of the roots inside the circles of the
//!   verdict (`zeros_inside`), about a microsecond per unit of degree because `q`
//!   has at most seven nonzero terms (eigenvalues cost the cube of the degree);
//! - [`Method::Certified`]: a coefficient bound that proves huge walls unstable and
//!   inclusion discs around the eigenvalues (`certify`), both valid for every polynomial
//!   within the rounding of the computed coefficients;
//! - [`Method::Auto`] (the default): Schur-Cohn with a running rounding-error bound
//!   (`schur_cohn_guarded`); when the bound cannot exclude a verdict changed by rounding
//!   (high degree, roots near the tested circle), the argument-principle count decides, and
//!   where no count can be proven either, [`Method::Certified`].
//!
//! Which method decided and whether a fallback happened is reported ([`Decision`],
//! [`Analysis::fallback`]).
//!
//! # What a verdict promises
//!
//! Every method returns [`Verdict::Stable`] or [`Verdict::Unstable`] only when it can vouch
//! for it: the guarded recursion's error bound, the proven count or the inclusion discs show
//! that the verdict holds for every polynomial whose coefficients lie within the error
//! bounds of the computed ones (`Enclosure`: the rounding of the discretization
//! and of the assembly of `q`). Otherwise the verdict is [`Verdict::Marginal`] with a
//! [`MarginalReason`]: [`MarginalReason::WithinMargin`] when a root was shown to be within the
//! band, [`MarginalReason::Undecided`] when rounding leaves both sides open (a root within
//! the coefficients' rounding of a circle of the verdict, such as the near-double roots of
//! walls with `beta` near `-delta` and `alpha` near 0, whose roots are known only to about
//! `sqrt(eps)`). NaN is never a root or a radius: a root finder whose result is not finite
//! has failed and another is tried.
//!
//! Points on the boundary have a root on the unit circle, where every method's answer is
//! decided by rounding. A stated band `margin` around the circle makes them
//! [`Verdict::Marginal`] instead of flip-flopping: stable means spectral radius `< 1 - margin`,
//! unstable means `> 1 + margin`. Margins below [`MIN_MARGIN`] are refused.

pub(crate) mod certify;
mod checker;
pub(crate) mod schur_cohn;
pub(crate) mod winding;

use crate::error::{Error, Result};
use crate::params::{Normalized, Plant, Wall};
use crate::poly::{Complex, MAX_COEFFS, PaperPoly, ScaledPoly};
use crate::roots::eigen;
pub use crate::roots::eigen::{aberth, eigenvalues_capped, poly_roots};
pub use checker::Checker;
pub(crate) use schur_cohn::schur_cohn_guarded;
pub use schur_cohn::{SchurCohn, schur_cohn};

/// The default width of the marginal band around the unit circle.
///
/// `1e-9` is far above the rounding of the roots of well-conditioned `q` (about `1e-14` for
/// the degrees of short delays) and far below any margin an engineer would design with.
pub const DEFAULT_MARGIN: f64 = 1e-9;

/// The smallest margin accepted: `256 eps`, about `5.7e-14`.
///
/// The circles of the verdict `1 - margin` and `1 + margin` are rounded to the grid of `f64`
/// near 1 (spacing `eps / 2` below 1, `eps` above); at `256 eps` that moves each by at most
/// 1/256 of the band's width. Below a few `eps` the band vanishes (`1 + 1e-16 == 1`) and a
/// verdict would claim a resolution that the arithmetic does not have.
pub const MIN_MARGIN: f64 = 256.0 * f64::EPSILON;

/// Above this degree the state matrix's eigenvalues are preferred to the companion
/// matrix's: for the roots of [`Checker::analyze`] (unless the companion decided) and first
/// in [`Method::Certified`].
///
/// Companion eigenvalues of `q` are backward stable for the companion matrix, not for the
/// coefficients; their error grows with the degree and with roots clustered near the circle,
/// which the `z^(n+2)` term of `q` produces for long delays (`docs/MODEL.md` section 7). Up to
/// degree 16 (delays below 13 samples) the tests find companion and state-space radii equal
/// to `1e-12`, far inside the default margin.
pub(crate) const EIGEN_CHECK_DEGREE: usize = 16;

/// How to decide stability.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
#[non_exhaustive]
pub enum Method {
    /// Schur-Cohn with a rounding-error guard; state-space eigenvalues when the guard cannot
    /// vouch for the verdict (see the module documentation). The default.
    #[default]
    Auto,
    /// Schur-Cohn (Jury) recursion on the coefficients of `q` with its rounding-error guard
    /// (`schur_cohn_guarded_with`); where the guard cannot vouch for the verdict, the
    /// same fallbacks as [`Method::Auto`] (reported as a fallback).
    /// [`Checker::unguarded_verdict`] is the recursion without the guard.
    SchurCohn,
    /// Eigenvalues of the companion matrix of `q`, the verdict proven by inclusion discs
    /// around them (`disk_verdict`); the state matrix's eigenvalues when those
    /// discs prove nothing.
    Eigen,
    /// Eigenvalues of the closed-loop state matrix (no polynomial expansion), the verdict
    /// proven by inclusion discs around them (`disk_verdict`).
    StateSpace,
    /// The number of roots inside each circle of the verdict, counted by the argument
    /// principle with proven steps (`zeros_inside`); [`Method::Certified`] when
    /// no count can be proven (a root within rounding of a circle).
    ArgumentPrinciple,
    /// Certificates that hold for every polynomial within the coefficients' rounding
    /// (`certify`): the coefficient bound `binomial_unstable`, then inclusion
    /// discs (`disk_verdict`) around the companion or state-space eigenvalues.
    Certified,
}

impl Method {
    /// The methods of the command line, in declaration order (for comparing them, as the
    /// tests do); [`Method::Certified`], the last stage of the others, is not among them.
    pub const ALL: [Method; 5] = [
        Method::Auto,
        Method::SchurCohn,
        Method::Eigen,
        Method::StateSpace,
        Method::ArgumentPrinciple,
    ];

    /// The name used on the command line and in JSON.
    pub fn name(&self) -> &'static str {
        match self {
            Method::Auto => "auto",
            Method::SchurCohn => "schur-cohn",
            Method::Eigen => "eigen",
            Method::StateSpace => "state-space",
            Method::ArgumentPrinciple => "argument-principle",
            Method::Certified => "certified",
        }
    }
}

/// Why a verdict is [`Verdict::Marginal`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
#[non_exhaustive]
pub enum MarginalReason {
    /// The spectral radius was shown to be within `margin` of 1 (a root in the band, none
    /// outside it).
    WithinMargin,
    /// The method could not vouch for either side: the rounding of the coefficients or of
    /// the arithmetic allows a root on both sides of a circle of the verdict, or no roots
    /// could be found.
    Undecided,
}

impl MarginalReason {
    /// Lower-case name (`within-margin`, `undecided`).
    pub fn name(self) -> &'static str {
        match self {
            MarginalReason::WithinMargin => "within-margin",
            MarginalReason::Undecided => "undecided",
        }
    }
}

/// The answer for one point.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
pub enum Verdict {
    /// Every root is inside the circle of radius `1 - margin`.
    Stable,
    /// The spectral radius is within `margin` of 1 (on the boundary to the stated tolerance),
    /// or the method cannot vouch for either side ([`MarginalReason`] says which).
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
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
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
    /// Checks the margin: finite, in `[MIN_MARGIN, 0.5)` (see [`MIN_MARGIN`]).
    pub fn validate(&self) -> Result<()> {
        crate::params::in_range("margin", self.margin, 0.0, 0.5 - f64::EPSILON)?;
        if self.margin < MIN_MARGIN {
            return Err(Error::InvalidParameter {
                name: "margin",
                value: self.margin,
                expected: format!(
                    "the smallest accepted margin is {MIN_MARGIN:e} (256 eps): a band narrower than that is below the resolution of f64 near 1"
                ),
            });
        }
        Ok(())
    }
}

/// The full answer for one point: verdict, spectral radius, roots.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub struct Analysis {
    /// The verdict of the chosen method.
    pub verdict: Verdict,
    /// Largest root modulus.
    pub spectral_radius: f64,
    /// All roots of `q` (from eigenvalues, whatever method decided).
    pub roots: Vec<Complex>,
    /// Degree of `q`.
    pub degree: usize,
    /// The method that decided (for [`Method::Auto`]: [`Method::SchurCohn`] or, after a
    /// fallback, [`Method::StateSpace`]).
    pub method: Method,
    /// The method requested in the options.
    pub requested: Method,
    /// Whether the requested method's verdict was not trusted and another method decided.
    pub fallback: bool,
    /// Why the verdict is [`Verdict::Marginal`]; `None` for the other verdicts.
    #[cfg_attr(feature = "serde", serde(default))]
    pub reason: Option<MarginalReason>,
}

impl Analysis {
    /// The verdict, the method that reached it, whether that was a fallback and why a
    /// marginal verdict is marginal: what [`Checker::decide`] answers for the same wall.
    ///
    /// ```
    /// use stabound::params::{Plant, Wall};
    /// use stabound::stability::{Checker, Options};
    ///
    /// let c = Checker::new(&Plant::new(0.5, 1.0)?, Options::default())?;
    /// let wall = Wall::new(0.1, 0.3)?;
    /// assert_eq!(c.analyze(&wall)?.decision(), c.decide(&wall)?);
    /// # Ok::<(), stabound::Error>(())
    /// ```
    pub fn decision(&self) -> Decision {
        Decision {
            verdict: self.verdict,
            method: self.method,
            fallback: self.fallback,
            reason: self.reason,
        }
    }
}

/// A verdict with the method that reached it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub struct Decision {
    /// The verdict.
    pub verdict: Verdict,
    /// The method whose verdict it is.
    pub method: Method,
    /// Whether the requested method was overruled or not trusted (see [`Method::Auto`]).
    pub fallback: bool,
    /// Why the verdict is [`Verdict::Marginal`]; `None` for the other verdicts.
    #[cfg_attr(feature = "serde", serde(default))]
    pub reason: Option<MarginalReason>,
}

/// Stability tests for the paper's loop on one plant: builds the closed-form `q` once, then
/// tests any number of walls. The fast path of [`Checker`].
#[derive(Debug, Clone)]
pub(crate) struct PaperChecker {
    poly: PaperPoly,
    options: Options,
    /// `q(r z)` for `r = 1 - margin` and `r = 1 + margin`: the circles of the verdict.
    inner: ScaledPoly,
    outer: ScaledPoly,
    /// Error bounds of the coefficients (the rounding of the discretization).
    enclosure: certify::Enclosure,
}

/// A verdict and, when marginal, why.
type Reasoned = (Verdict, Option<MarginalReason>);

/// A confident verdict or a proven marginal one.
fn proven(v: Verdict) -> Reasoned {
    let reason = (v == Verdict::Marginal).then_some(MarginalReason::WithinMargin);
    (v, reason)
}

/// The verdict of a method that cannot vouch for either side.
const UNDECIDED: Reasoned = (Verdict::Marginal, Some(MarginalReason::Undecided));

impl PaperChecker {
    /// A checker for `plant` with `options` (validated).
    /// `options` are validated by [`Checker::new`], the only caller.
    #[inline]
    pub(crate) fn new(plant: &Plant, options: Options) -> Self {
        let poly = PaperPoly::new(plant);
        Self {
            inner: poly.scaled(1.0 - options.margin),
            outer: poly.scaled(1.0 + options.margin),
            enclosure: certify::Enclosure::new(&poly),
            poly,
            options,
        }
    }

    /// The characteristic polynomial in use.
    pub fn poly(&self) -> &PaperPoly {
        &self.poly
    }

    /// The options in use.
    pub fn options(&self) -> &Options {
        &self.options
    }

    /// The verdict for `wall` with the method that reached it, whether a fallback happened
    /// and, for a marginal verdict, why.
    ///
    /// A stable or unstable verdict is one the deciding method vouches for (module
    /// documentation); [`Verdict::Marginal`] with [`MarginalReason::Undecided`] otherwise.
    pub fn decide(&self, wall: &Wall) -> Result<Decision> {
        let requested = self.options.method;
        let decision = |(verdict, reason): Reasoned, method| Decision {
            verdict,
            method,
            // Auto's own first choice is Schur-Cohn: only another method means a fallback.
            fallback: method != requested
                && !(requested == Method::Auto && method == Method::SchurCohn),
            reason,
        };
        crate::cancel::poll()?;
        let decided = match requested {
            // Where the recursion's error bound cannot vouch for its verdict (high degree,
            // huge coefficients), the proven count and then the certificates decide, as for
            // auto: the count costs microseconds where eigenvalues cost milliseconds.
            Method::SchurCohn | Method::Auto => match self.guarded_verdict(wall) {
                Some(v) => decision(proven(v), Method::SchurCohn),
                None => match self.counted_verdict(wall) {
                    Some(v) => decision(proven(v), Method::ArgumentPrinciple),
                    None => decision(self.certified_verdict(wall), Method::Certified),
                },
            },
            Method::ArgumentPrinciple => match self.counted_verdict(wall) {
                Some(v) => decision(proven(v), Method::ArgumentPrinciple),
                None => decision(self.certified_verdict(wall), Method::Certified),
            },
            Method::Certified => decision(self.certified_verdict(wall), Method::Certified),
            Method::StateSpace => match self.eigen_verdict(wall, Method::StateSpace) {
                Some(v) => decision(proven(v), Method::StateSpace),
                None => self.undecided_or_huge(wall, Method::StateSpace, decision),
            },
            Method::Eigen => match self.eigen_verdict(wall, Method::Eigen) {
                Some(v) => decision(proven(v), Method::Eigen),
                // The companion eigenvalues could not be vouched for: the state matrix's
                // (the better-conditioned route for long delays) may be.
                None => match self.eigen_verdict(wall, Method::StateSpace) {
                    Some(v) => decision(proven(v), Method::StateSpace),
                    None => self.undecided_or_huge(wall, Method::Eigen, decision),
                },
            },
        };
        // an eigenvalue route cut short by a stop proves nothing: the stop, not its verdict
        crate::cancel::poll()?;
        Ok(decided)
    }

    /// The last word of an eigenvalue method whose roots prove nothing: unstable by the
    /// coefficient bound ([`certify::binomial_unstable`], reported as [`Method::Certified`])
    /// for walls too large for eigenvalues, undecided otherwise.
    fn undecided_or_huge(
        &self,
        wall: &Wall,
        method: Method,
        decision: impl Fn(Reasoned, Method) -> Decision,
    ) -> Decision {
        if certify::binomial_unstable(&self.enclosure, wall, 1.0 + self.options.margin) {
            decision((Verdict::Unstable, None), Method::Certified)
        } else {
            decision(UNDECIDED, method)
        }
    }

    /// The verdict that the inclusion discs around the roots found by `method` prove
    /// ([`certify::disk_verdict`]), or `None` when they prove none or no roots are found.
    fn eigen_verdict(&self, wall: &Wall, method: Method) -> Option<Verdict> {
        self.roots_by(wall, method, &|roots| self.disk_verdict(wall, roots))?
    }

    fn disk_verdict(&self, wall: &Wall, roots: &[Complex]) -> Option<Verdict> {
        let q = self.poly.coefficients(wall);
        let mut errs = vec![0.0; q.len()];
        let errs = self.enclosure.errors_into(wall, &mut errs);
        Some(
            match certify::disk_verdict(&q, errs, roots, self.options.margin)? {
                certify::DiskProof::Stable => Verdict::Stable,
                certify::DiskProof::Unstable => Verdict::Unstable,
                certify::DiskProof::Marginal => Verdict::Marginal,
            },
        )
    }

    /// [`Method::Certified`]: the coefficient bound, then inclusion discs around the
    /// eigenvalues of the companion matrix and of the state matrix (the state matrix first
    /// above degree [`EIGEN_CHECK_DEGREE`], where it is the better conditioned).
    fn certified_verdict(&self, wall: &Wall) -> Reasoned {
        if certify::binomial_unstable(&self.enclosure, wall, 1.0 + self.options.margin) {
            return (Verdict::Unstable, None);
        }
        let order = if self.poly.degree() > EIGEN_CHECK_DEGREE {
            [Method::StateSpace, Method::Eigen]
        } else {
            [Method::Eigen, Method::StateSpace]
        };
        order
            .iter()
            .find_map(|&m| self.eigen_verdict(wall, m))
            .map_or(UNDECIDED, proven)
    }

    /// The verdict of the unguarded Schur-Cohn recursion at both circles, without error
    /// bound: the fast test for sweeps that accept a verdict decided by rounding.
    pub fn unguarded_verdict(&self, wall: &Wall) -> Verdict {
        // One stack buffer for the recursion's two rows; the first starts as q(r z).
        schur_cohn::with_two_rows(self.poly.degree() + 1, |a, b| {
            if schur_cohn::unit_disc_stable(self.inner.coefficients_into(wall, a), b) {
                Verdict::Stable
            } else if schur_cohn::unit_disc_stable(self.outer.coefficients_into(wall, a), b) {
                Verdict::Marginal
            } else {
                Verdict::Unstable
            }
        })
    }

    /// The Schur-Cohn verdict when the running error bounds of both recursions that decide
    /// it exclude a change by rounding; `None` otherwise.
    ///
    /// Stable needs a trusted pass at `1 - margin`; unstable a trusted failure at
    /// `1 + margin` (roots outside `1 + margin` are outside `1 - margin` too); marginal a
    /// trusted failure at `1 - margin` and a trusted pass at `1 + margin`. The coefficients'
    /// own error bound ([`certify::Enclosure::max_error`]) enters the guard's.
    fn guarded_verdict(&self, wall: &Wall) -> Option<Verdict> {
        let m = self.options.margin;
        let err = self.enclosure.max_error(wall);
        schur_cohn::with_scratch(self.poly.degree() + 1, |buf| {
            let q = self.poly.coefficients_into(wall, buf);
            let inner = schur_cohn::schur_cohn_guarded_with(q, 1.0 - m, err);
            if inner.stable {
                return inner.trusted.then_some(Verdict::Stable);
            }
            let outer = schur_cohn::schur_cohn_guarded_with(q, 1.0 + m, err);
            if !outer.stable {
                return outer.trusted.then_some(Verdict::Unstable);
            }
            (inner.trusted && outer.trusted).then_some(Verdict::Marginal)
        })
    }

    /// The verdict from proven counts of the roots inside `1 - margin` and `1 + margin`
    /// ([`winding::zeros_inside`]), or `None` when a count cannot be proven.
    ///
    /// The coefficients' uncertainty is the larger of the Schur-Cohn guard's, `(m + 8) u` of
    /// the largest one, and the enclosure's largest bound ([`certify::Enclosure`]).
    /// At most `64 (m + 1) + 1000` steps: about eight times what a stable wall at `d = 100`
    /// needs, so a count near a circle gives up in about a millisecond.
    fn counted_verdict(&self, wall: &Wall) -> Option<Verdict> {
        let m = self.options.margin;
        let len = self.poly.degree() + 1;
        schur_cohn::with_scratch(len, |buf| {
            let q = self.poly.coefficients_into(wall, buf);
            count_verdict(q, m, self.enclosure.max_error(wall))
        })
    }

    /// What `f` makes of the roots by `method`'s route, `None` when it fails or returns a
    /// non-finite value.
    fn roots_by<T>(&self, wall: &Wall, method: Method, f: &impl Fn(&[Complex]) -> T) -> Option<T> {
        if crate::cancel::stopped() {
            return None;
        }
        let finite = |roots: &[Complex]| {
            roots
                .iter()
                .all(|z| z.re.is_finite() && z.im.is_finite())
                .then(|| f(roots))
        };
        match method {
            Method::StateSpace => finite(&eigen::eigenvalues_capped(
                self.poly.discretization().state_matrix(wall),
            )?),
            // the coefficients in a stack buffer, the roots of a short delay on the stack: no
            // allocation per wall
            _ => schur_cohn::with_scratch(self.poly.degree() + 1, |buf| {
                eigen::poly_roots_with(self.poly.coefficients_into(wall, buf), &finite)
            })
            .ok()?,
        }
    }

    /// The roots of `q` for `wall`, by the state matrix ([`Method::StateSpace`]) or by
    /// companion eigenvalues (every other method), each falling back to the other when it
    /// does not converge; every root returned is finite.
    ///
    /// Errors ([`Error::NoConvergence`]) only when neither route finds finite roots.
    pub fn roots(&self, wall: &Wall, method: Method) -> Result<Vec<Complex>> {
        self.roots_with(wall, method, &<[Complex]>::to_vec)
    }

    /// What `f` makes of the roots [`PaperChecker::roots`] finds.
    fn roots_with<T>(
        &self,
        wall: &Wall,
        method: Method,
        f: &impl Fn(&[Complex]) -> T,
    ) -> Result<T> {
        let other = if method == Method::StateSpace {
            Method::Eigen
        } else {
            Method::StateSpace
        };
        let found = self
            .roots_by(wall, method, f)
            .or_else(|| self.roots_by(wall, other, f));
        crate::cancel::poll()?;
        found.ok_or(Error::NoConvergence {
            method: "state-space and companion eigenvalues",
            iterations: a_cap(self.poly.degree()),
        })
    }

    /// The spectral radius without roots: the smallest `r` for which the Schur-Cohn test on
    /// the circle of radius `r` passes, by bisection to `1e-13` relative.
    ///
    /// Returns NaN when the coefficients are not finite (no radius can be bracketed).
    pub fn spectral_radius_schur_cohn(&self, wall: &Wall) -> f64 {
        let mut buf = [0.0; MAX_COEFFS];
        spectral_radius_of_coefficients(self.poly.coefficients_into(wall, &mut buf))
    }

    /// Verdict, spectral radius and roots for `wall`.
    ///
    /// The verdict is that of [`Checker::decide`]. The spectral radius is the deciding
    /// method's own: for [`Method::SchurCohn`] by bisection on the radius (no roots
    /// involved), otherwise from the roots. The roots always come from eigenvalues: of the
    /// state matrix when it decided, or above degree `EIGEN_CHECK_DEGREE`, otherwise of the
    /// companion matrix (each falling back to the other, [`Checker::roots`]). Neither the
    /// radius nor any root is NaN.
    pub fn analyze(&self, wall: &Wall) -> Result<Analysis> {
        let (decision, spectral_radius, roots) = self.analyzed(wall, &<[Complex]>::to_vec)?;
        Ok(Analysis {
            verdict: decision.verdict,
            spectral_radius,
            roots,
            degree: self.poly.degree(),
            method: decision.method,
            requested: self.options.method,
            fallback: decision.fallback,
            reason: decision.reason,
        })
    }

    /// The decision and the spectral radius of [`PaperChecker::analyze`], without keeping
    /// the roots (none is collected into a vector for a short delay).
    pub fn decide_with_radius(&self, wall: &Wall) -> Result<(Decision, f64)> {
        let (decision, radius, ()) = self.analyzed(wall, &|_| ())?;
        Ok((decision, radius))
    }

    /// [`PaperChecker::analyze`]'s decision and spectral radius, and what `keep` makes of
    /// its roots.
    fn analyzed<T>(
        &self,
        wall: &Wall,
        keep: &impl Fn(&[Complex]) -> T,
    ) -> Result<(Decision, f64, T)> {
        let decision = self.decide(wall)?;
        let (radius, kept) = self.measured(wall, &decision, keep)?;
        Ok((decision, radius, kept))
    }

    /// The decision of [`PaperChecker::decide`] and, only when it is marginal, the spectral
    /// radius [`PaperChecker::decide_with_radius`] reports for it (its error where the roots
    /// fail): one decision, no roots for a stable or unstable wall.
    pub(crate) fn decide_with_marginal_radius(
        &self,
        wall: &Wall,
    ) -> Result<(Decision, Option<Result<f64>>)> {
        let decision = self.decide(wall)?;
        let radius = (decision.verdict == Verdict::Marginal)
            .then(|| self.measured(wall, &decision, &|_| ()).map(|(r, ())| r));
        Ok((decision, radius))
    }

    /// The spectral radius [`PaperChecker::analyze`] reports for `wall` once `decision` is
    /// made, and what `keep` makes of its roots.
    fn measured<T>(
        &self,
        wall: &Wall,
        decision: &Decision,
        keep: &impl Fn(&[Complex]) -> T,
    ) -> Result<(f64, T)> {
        let requested = self.options.method;
        let long = matches!(
            requested,
            Method::Auto | Method::ArgumentPrinciple | Method::Certified
        ) && self.poly.degree() > EIGEN_CHECK_DEGREE;
        let roots_method = if decision.method == Method::StateSpace || long {
            Method::StateSpace
        } else {
            Method::Eigen
        };
        let of_roots = |roots: &[Complex]| (spectral_radius(roots), keep(roots));
        // exact: alpha = 0 is the line where z = 1 is a root (docs/MODEL.md section 4)
        let (from_roots, kept) = if wall.alpha == 0.0 {
            of_roots(&roots_with_one(&self.poly.coefficients(wall))?)
        } else {
            self.roots_with(wall, roots_method, &of_roots)?
        };
        let spectral_radius = match decision.method {
            Method::SchurCohn if requested == Method::SchurCohn => {
                let r = self.spectral_radius_schur_cohn(wall);
                if r.is_finite() { r } else { from_roots }
            }
            _ => from_roots,
        };
        if spectral_radius.is_nan() {
            return Err(Error::Numerical(
                "the roots found are not finite numbers; try a wall nearer the stable region"
                    .into(),
            ));
        }
        Ok((spectral_radius, kept))
    }
}

/// The roots of `q` (lowest power first) where `z = 1` is a root, as at `alpha = 0`
/// (docs/MODEL.md section 4): `z - 1` divided out (synthetic division) as long as the
/// quotient still vanishes at 1 to within its rounding, at most twice (a double root at
/// `beta = delta = 0`), the rest by [`eigen::poly_roots`]. Eigenvalues of `q` itself split
/// the double root by the square root of the rounding (`1 +- 1e-8`), so the radius would
/// leave a marginal band of `1e-9`; divided out, the roots at 1 are exact.
fn roots_with_one(q: &[f64]) -> Result<Vec<Complex>> {
    let mut p = q.to_vec();
    let mut ones = 0;
    while ones < 2 && p.len() > 1 {
        // p(1) against the rounding of its sum: one half-rounding per term of sum |p_i|
        // (the bound of a recursive sum), doubled for the coefficients' own rounding
        let scale: f64 = p.iter().map(|c| c.abs()).sum();
        let at_one: f64 = p.iter().sum();
        if at_one.abs() > p.len() as f64 * f64::EPSILON * scale {
            break;
        }
        // p(z) = (z - 1) s(z) + p(1): s_{n-1} = p_n, s_{i-1} = p_i + s_i
        let mut carry = 0.0;
        let mut s: Vec<f64> = p[1..]
            .iter()
            .rev()
            .map(|c| {
                carry += c;
                carry
            })
            .collect();
        s.reverse();
        p = s;
        ones += 1;
    }
    let mut roots = eigen::poly_roots(&p)?;
    roots.extend(std::iter::repeat_n(Complex::new(1.0, 0.0), ones));
    Ok(roots)
}

fn a_cap(degree: usize) -> usize {
    degree * 40 + 100
}

/// The verdict from proven root counts of `q` (lowest power first) inside `1 - margin` and
/// `1 + margin` (the argument principle, [`winding::zeros_inside`]), each coefficient taken
/// with an error of `(degree + 8)` half-roundings of the largest, or `min_err` if larger;
/// at most `64 len + 1000` steps. `None` for more than [`winding::MAX_TERMS`] nonzero terms
/// or a root too near a circle to count. The counting stage of [`Checker`] for
/// every loop.
pub(crate) fn count_verdict(q: &[f64], margin: f64, min_err: f64) -> Option<Verdict> {
    let mut terms = [(0usize, 0.0f64); winding::MAX_TERMS];
    let mut count = 0;
    let mut amax = 0.0f64;
    for (i, &c) in q.iter().enumerate() {
        amax = amax.max(c.abs());
        // exact zeros are structural (powers q does not have), not small values
        if c != 0.0 {
            *terms.get_mut(count)? = (i, c);
            count += 1;
        }
    }
    let len = q.len();
    let degree = len - 1;
    let err = ((degree as f64 + 8.0) * (f64::EPSILON / 2.0) * amax).max(min_err);
    let cap = 64 * len + 1000;
    let terms = &terms[..count];
    if winding::zeros_inside(terms, 1.0 - margin, err, cap)? == degree {
        return Some(Verdict::Stable);
    }
    Some(
        if winding::zeros_inside(terms, 1.0 + margin, err, cap)? < degree {
            Verdict::Unstable
        } else {
            Verdict::Marginal
        },
    )
}

/// The spectral radius of the polynomial `q` (lowest power first, leading coefficient
/// nonzero) without roots: the smallest `r` for which the Schur-Cohn test on the circle of
/// radius `r` passes, by bisection to `1e-13` relative; NaN when a coefficient is not finite
/// (no radius can be bracketed).
pub(crate) fn spectral_radius_of_coefficients(q: &[f64]) -> f64 {
    if q.iter().any(|c| !c.is_finite()) {
        return f64::NAN;
    }
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

/// Largest modulus among `roots` (0 for none); NaN when any root has a NaN part.
///
/// A NaN root is a failed root finder, never a small root: folding with `f64::max` would
/// drop it and report the largest of the others, so NaN propagates instead.
pub fn spectral_radius(roots: &[Complex]) -> f64 {
    let mut r = 0.0f64;
    for z in roots {
        let m = z.norm();
        if m.is_nan() {
            return f64::NAN;
        }
        r = r.max(m);
    }
    r
}

/// One-call analysis of a point given by all four normalized parameters.
///
/// ```
/// use stabound::{params::Normalized, stability::{check, Options, Verdict}};
/// // delta = 0, d = 0: alpha_max = 12 - 8 sqrt 2 at beta = 2 sqrt 2 - 2 (paper, Remark 4).
/// let s2 = 2f64.sqrt();
/// let inside = Normalized::new(12.0 - 8.0 * s2 - 1e-6, 2.0 * s2 - 2.0, 0.0, 0.0)?;
/// assert_eq!(check(&inside, &Options::default())?.verdict, Verdict::Stable);
/// # Ok::<(), stabound::Error>(())
/// ```
pub fn check(params: &Normalized, options: &Options) -> Result<Analysis> {
    let (plant, wall) = params.split()?;
    Checker::new(plant, *options)?.analyze(&wall)
}

/// Uniform numbers in `[0, 1)` from a fixed seed (xorshift64), for the randomized unit tests
/// of the methods in this module: deterministic, so a failure can be replayed.
#[cfg(test)]
pub(crate) fn test_rng(mut seed: u64) -> impl FnMut() -> f64 {
    move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn checker(delta: f64, d: f64, method: Method) -> Checker {
        Checker::new(
            Plant::new(delta, d).unwrap(),
            Options {
                method,
                margin: DEFAULT_MARGIN,
            },
        )
        .unwrap()
    }

    /// The radius without the roots is analyze's to the bit, with its decision, for every
    /// method, on walls of both verdicts (and alpha = 0) at delays whose companion matrices
    /// are small (on the stack) and large (on the heap), and on the state matrix's route.
    #[test]
    fn decide_with_radius_is_analyze_without_the_roots() {
        let mut rnd = test_rng(0x51_7cc1_b727_220a);
        for method in [
            Method::Auto,
            Method::SchurCohn,
            Method::Eigen,
            Method::StateSpace,
        ] {
            for d in [0.0, 0.5, 1.0, 2.0, 3.0, 5.0, 8.0, 20.0] {
                let c = checker(0.2 * rnd(), d, method);
                for i in 0..40 {
                    let alpha = if i % 10 == 0 { 0.0 } else { 3.0 * rnd() };
                    let wall = Wall::new(alpha, 4.0 * rnd() - 1.0).unwrap();
                    let an = c.analyze(&wall).unwrap();
                    let (decision, radius) = c.decide_with_radius(&wall).unwrap();
                    assert_eq!(decision, c.decide(&wall).unwrap());
                    assert_eq!(
                        (decision.verdict, decision.method, decision.reason),
                        (an.verdict, an.method, an.reason)
                    );
                    assert_eq!(radius.to_bits(), an.spectral_radius.to_bits(), "{wall:?}");
                }
            }
        }
    }

    /// At alpha = 0 the root z = 1 is divided out: the double root of the free mass
    /// (beta = delta = 0) is reported as exactly 1, twice, so the radius lies in the marginal
    /// band, and the roots rebuild q; with damping the other roots are those of the
    /// eigenvalues of q itself (simple roots, well conditioned).
    #[test]
    fn the_root_at_one_is_exact_at_zero_stiffness() {
        let c = checker(0.0, 2.5, Method::Auto);
        let a = c.analyze(&Wall::new(0.0, 0.0).unwrap()).unwrap();
        assert_eq!(a.verdict, Verdict::Marginal);
        // exact: the ones are appended, not computed
        assert_eq!(
            a.roots
                .iter()
                .filter(|z| **z == Complex::new(1.0, 0.0))
                .count(),
            2
        );
        assert!((a.spectral_radius - 1.0).abs() <= DEFAULT_MARGIN, "{a:?}");
        // the product of (z - root) is q up to rounding (the 4-fold root at 0 of q / (z - 1)^2
        // is found to within the fourth root of the rounding)
        let q = c.coefficients(&Wall::new(0.0, 0.0).unwrap());
        let mut prod = vec![Complex::new(q[q.len() - 1], 0.0)];
        for r in &a.roots {
            let mut next = vec![Complex::new(0.0, 0.0); prod.len() + 1];
            for (i, &p) in prod.iter().enumerate() {
                next[i + 1] += p;
                next[i] -= p * r;
            }
            prod = next;
        }
        for (p, &c) in prod.iter().zip(&q) {
            assert!(
                (p.re - c).abs() < 1e-12 && p.im.abs() < 1e-12,
                "{prod:?} vs {q:?}"
            );
        }
        let c = checker(0.5, 1.0, Method::Auto);
        let wall = Wall::new(0.0, 0.3).unwrap();
        let a = c.analyze(&wall).unwrap();
        assert_eq!(
            a.roots
                .iter()
                .filter(|z| **z == Complex::new(1.0, 0.0))
                .count(),
            1
        );
        let plain = c.roots(&wall, Method::Eigen).unwrap();
        for z in &a.roots {
            assert!(
                plain.iter().any(|p| (p - z).norm() < 1e-9),
                "{z} not in {plain:?}"
            );
        }
    }

    /// Paper's anchor (docs/MODEL.md section 6): alpha_max = 12 - 8 sqrt 2 at beta = 2 sqrt 2 - 2
    /// for delta = 0, d = 0, tested through every method.
    #[test]
    fn anchor_d0_delta0() {
        let s2 = 2f64.sqrt();
        let amax = 12.0 - 8.0 * s2;
        let beta = 2.0 * s2 - 2.0;
        for method in Method::ALL {
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

    /// alpha = 0 puts a root at z = 1 exactly (docs/MODEL.md section 4): marginal.
    #[test]
    fn alpha_zero_is_marginal() {
        for method in Method::ALL {
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

    /// Walls near the top of the f64 range must return (they used to hang in balancing) and
    /// be unstable: a stiffness of 1e300 is far outside every stable region.
    #[test]
    fn huge_walls_return_unstable() {
        for method in Method::ALL {
            let c = checker(0.5, 1.0, method);
            for (alpha, beta) in [(1e300, 0.0), (1.0, -1e300), (1e300, 1e300)] {
                let a = c.analyze(&Wall::new(alpha, beta).unwrap()).unwrap();
                assert_eq!(a.verdict, Verdict::Unstable, "{method:?} {alpha} {beta}");
            }
        }
    }

    /// The verdict's one stack buffer holds the recursion's two rows at the largest degree
    /// (d = MAX_DELAY) too; a soft wall there is stable by state-space eigenvalues.
    #[test]
    fn schur_cohn_verdict_at_the_largest_degree() {
        let d = crate::params::MAX_DELAY;
        let wall = Wall::new(1e-5, 1e-3).unwrap();
        let sc = checker(0.5, d, Method::SchurCohn).verdict(&wall).unwrap();
        let ss = checker(0.5, d, Method::StateSpace).verdict(&wall).unwrap();
        assert_eq!(sc, ss);
    }
}
