//! The wall at a fraction of the maximum stiffness (paper Section VIII: "75 % of its maximum
//! stable value", the damping left at the value where `alpha_max` is reached), checked stable
//! before it is recommended, in normalized and physical units.

use super::report::{AmaxReport, amax_report, margin_alpha_max};
use super::{Amax, AmaxOptions};
use crate::elements::Loop;
use crate::error::{Error, Result};
use crate::params::Wall;
use crate::stability::{Checker, Options, Verdict};

/// A recommended wall: a fraction of the best stiffness whose whole range from the wall up to
/// it is stable at one damping, with the loop's `alpha_max` report beside it.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct MarginWall {
    /// The wall to render: `margin x top.alpha_max` at `top.beta_at_max`, stable by
    /// [`Checker::verdict`] with the default marginal band.
    pub wall: Wall,
    /// The best wall `(alpha, beta)` whose stiffnesses from `margin alpha` up to `alpha` at
    /// `beta` are all stable: `alpha_max` itself where the stable set at its damping holds that
    /// range ([`MarginWall::at_optimum`]), a lower wall at another damping otherwise.
    pub top: Amax,
    /// The loop's `alpha_max`, the stable stiffnesses at its damping and the best wall with
    /// `beta >= 0` when `alpha_max` needs negative damping.
    pub report: AmaxReport,
}

impl MarginWall {
    /// Whether the recommended wall is the margin of `alpha_max` itself (the paper's
    /// Section VIII rule); `false` when the stable stiffnesses at the optimum's damping do not
    /// reach from the margin wall up to `alpha_max`, so that a lower top at another damping
    /// was chosen.
    pub fn at_optimum(&self) -> bool {
        self.top == self.report.amax
    }

    /// Whether the stable stiffnesses at the optimum's damping are one range from `0` up to
    /// `alpha_max` (relative `1e-7`, far inside the 1-D search's accuracy), as in the paper's
    /// loop; `false` says that some softer wall at that damping is unstable.
    pub fn one_range(&self) -> bool {
        self.report.one_range()
    }
}

/// The wall to recommend at a fraction `margin` of the maximum stiffness of `lp`: the best
/// wall whose whole range from the margin wall up to it is stable at its damping
/// ([`margin_alpha_max`]), scaled by `margin`, and checked stable by [`Checker::verdict`]
/// before it is returned.
///
/// Method: [`amax_report`] and [`margin_alpha_max`] (direct searches on the loop's
/// D-decomposition), then the checker's verdict on the wall.
///
/// ```
/// use stabound::amax::{AmaxOptions, recommend};
/// use stabound::elements::Loop;
/// use stabound::params::Plant;
///
/// // the paper's loop: the stable stiffnesses at every damping are one range from 0, so
/// // the wall is 75 % of alpha_max at its damping (paper Section VIII)
/// let lp = Loop::new(Plant::new(0.0, 1.0)?);
/// let m = recommend(&lp, &AmaxOptions::default(), 0.75)?;
/// assert!(m.at_optimum() && m.one_range());
/// assert_eq!(m.wall.alpha(), 0.75 * m.report.amax.alpha_max);
/// # Ok::<(), stabound::Error>(())
/// ```
///
/// # Errors
///
/// A margin outside `(0, 1]`; as [`margin_alpha_max`]; [`Error::Numerical`] when the wall
/// found is not stable by the checker (it is not recommended then).
pub fn recommend(lp: &Loop, opts: &AmaxOptions, margin: f64) -> Result<MarginWall> {
    check_margin(margin)?;
    let report = amax_report(lp, opts)?;
    let top = if report.one_range() {
        report.amax
    } else {
        margin_alpha_max(lp, opts, margin)?
    };
    let wall = Wall::new(margin * top.alpha_max, top.beta_at_max)?;
    let verdict = Checker::new(*lp, Options::default())?.verdict(&wall)?;
    if verdict != Verdict::Stable {
        return Err(Error::Numerical(format!(
            "the wall at {margin} of the best stiffness (alpha = {}, beta = {}) is {} by the checker; no wall is recommended",
            wall.alpha(),
            wall.beta(),
            verdict.name()
        )));
    }
    Ok(MarginWall { wall, top, report })
}

/// The wall at a fraction `margin` of the maximum stiffness of the loop `lp` (built in
/// physical units, [`Loop::physical`]), in physical units `(K, B)`: [`recommend`] with the
/// default options (the damping at `alpha_max`, or another where the stable stiffnesses there
/// do not reach from the margin wall up to `alpha_max`).
///
/// Method: [`recommend`].
///
/// ```
/// use stabound::amax::margin_wall;
/// use stabound::elements::{Loop, PhysicalElements};
/// use stabound::params::{Delay, Device};
///
/// let device = Device::new(0.1, 1e-3, 1.0, Delay::Samples(1.0))?;
/// let free = Loop::physical(&device, &PhysicalElements::default())?;
/// let mut hand = PhysicalElements::default();
/// hand.hand_mass = Some(0.1);
/// let held = Loop::physical(&device, &hand)?;
/// // a hand's mass slows the device: a stiffer wall stays stable
/// assert!(margin_wall(&held, 0.75)?.0 > margin_wall(&free, 0.75)?.0);
/// # Ok::<(), stabound::Error>(())
/// ```
///
/// # Errors
///
/// A margin outside `(0, 1]`; a loop built in normalized units (it has no device); as
/// [`recommend`].
pub fn margin_wall(lp: &Loop, margin: f64) -> Result<(f64, f64)> {
    check_margin(margin)?;
    let device = lp.device().ok_or_else(|| {
        Error::InvalidRequest(
            "a wall in physical units needs the loop's physical device: build the loop with Loop::physical".into(),
        )
    })?;
    let m = recommend(lp, &AmaxOptions::default(), margin)?;
    Ok((
        device.stiffness(m.wall.alpha()),
        device.wall_damping(m.wall.beta()),
    ))
}

pub(super) fn check_margin(margin: f64) -> Result<()> {
    crate::params::finite("margin", margin)?;
    if !(margin > 0.0 && margin <= 1.0) {
        return Err(Error::InvalidParameter {
            name: "margin",
            value: margin,
            expected: "a fraction of alpha_max in (0, 1], e.g. 0.75".into(),
        });
    }
    Ok(())
}
