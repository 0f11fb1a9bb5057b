//! The largest stable stiffness of a [`Loop`]: over all virtual dampings (`alpha_max`) and
//! at a given one.
//!
//! Method: the direct searches of [`crate::amax`] written once against the loop's affine
//! polynomial `q = Q0 + alpha QA + beta QB` (the model document, docs/MODEL.md, section 8):
//!
//! - `alpha_max` is the rightmost point of the stable region among the smooth maxima of the
//!   D-decomposition curve and its corners with the `z = -1` line and the beta limits (scan,
//!   Brent's method on the exact derivative, candidates confirmed by stable neighbours);
//! - at a fixed `beta`, the line's crossings with the same curve and lines, one point test
//!   per piece between them.
//!
//! No boundary is traced. For the paper's loop, [`crate::alpha_max`] (the same search on the
//! closed-form curve) is the faster route and agrees with these to rounding.

use super::{Loop, LoopChecker};
use crate::amax::decomposition::LoopCurve;
use crate::amax::{Amax, AmaxOptions};
use crate::error::Result;
use crate::params::finite;
use crate::search::{Free, Interval, curve_stable_set};
use crate::stability::Options;

/// `alpha_max` of `lp` and the `beta` where it is reached, within the beta limits of `opts`
/// (see the module documentation; `opts`'s theta tolerance is Brent's tolerance in the
/// critical root's angle, as for the paper's loop). Always on the loop's own polynomial,
/// for the paper's loop too.
///
/// ```
/// use stabound::elements::{Loop, loop_alpha_max};
/// use stabound::filter::VelocityFilter;
/// use stabound::params::Plant;
/// use stabound::AmaxOptions;
///
/// let plant = Plant::new(0.2, 1.0)?;
/// let bare = loop_alpha_max(&Loop::new(plant), &AmaxOptions::default())?;
/// let filtered = Loop::new(plant).with_filter(VelocityFilter::low_pass(0.9)?)?;
/// // a velocity filter's lag lowers the largest stable stiffness
/// assert!(loop_alpha_max(&filtered, &AmaxOptions::default())?.alpha_max < bare.alpha_max);
/// # Ok::<(), stabound::Error>(())
/// ```
///
/// # Errors
///
/// As [`super::LoopPoly::new`]; [`crate::Error::InvalidRequest`] when the beta limits leave
/// no stable wall; [`crate::Error::Numerical`] when no candidate could be confirmed.
pub fn loop_alpha_max(lp: &Loop, opts: &AmaxOptions) -> Result<Amax> {
    crate::amax::report::loop_alpha_max_detail(lp, opts).map(|d| d.amax)
}

/// The largest stable stiffness of `lp` at virtual damping `beta`, or `None` if no stiffness
/// is stable there (see the module documentation).
///
/// ```
/// use stabound::elements::{Hand, Loop, loop_alpha_limit};
/// use stabound::params::Plant;
///
/// let lp = Loop::new(Plant::new(0.2, 1.0)?).with_hand(Hand::new(0.5, 0.1, 0.0)?)?;
/// let a = loop_alpha_limit(&lp, 0.1)?.expect("stable walls at beta = 0.1");
/// assert!(a > 0.0 && a < 1.0);
/// assert_eq!(loop_alpha_limit(&lp, -5.0)?, None);
/// # Ok::<(), stabound::Error>(())
/// ```
///
/// # Errors
///
/// A non-finite `beta`; as [`super::LoopPoly::new`].
pub fn loop_alpha_limit(lp: &Loop, beta: f64) -> Result<Option<f64>> {
    finite("beta", beta)?;
    Ok(crate::amax::report::loop_stable_alphas(lp, beta)?
        .last()
        .map(|i| i.hi))
}

/// A loop's D-decomposition and point test, built once for any number of one-dimensional
/// questions (the scene's walls ask several each).
pub(crate) struct LoopEdges {
    checker: LoopChecker,
    curve: LoopCurve,
}

impl LoopEdges {
    /// `options` are the verdicts' ([`LoopEdges::checker`]); the edges themselves are found
    /// at radius exactly 1.
    pub(crate) fn new(lp: &Loop, options: Options) -> Result<Self> {
        Ok(Self {
            checker: LoopChecker::new(lp, options)?,
            curve: LoopCurve::new(lp)?,
        })
    }

    #[cfg(feature = "scene")]
    pub(crate) fn checker(&self) -> &LoopChecker {
        &self.checker
    }

    /// The stable `alpha` at `beta`, sorted open intervals.
    pub(crate) fn stable_alphas(&self, beta: f64) -> Result<Vec<Interval>> {
        self.intervals(Free::Alpha, beta)
    }

    /// The stable `beta` at `alpha`, sorted open intervals.
    #[cfg(feature = "scene")]
    pub(crate) fn stable_betas(&self, alpha: f64) -> Result<Vec<Interval>> {
        self.intervals(Free::Beta, alpha)
    }

    /// The direct search on the line, each piece decided at radius exactly 1 (the ends are
    /// where a root crosses the circle, not shifted by the verdicts' margin).
    fn intervals(&self, free: Free, fixed: f64) -> Result<Vec<Interval>> {
        curve_stable_set(&self.curve, free, fixed, &|w| {
            Ok(self.checker.unit_circle_stable(w))
        })
    }
}
