//! The wall at a fraction of the maximum stiffness (paper Section VIII: "75 % of its maximum
//! stable value", the damping left at the value where `alpha_max` is reached), in physical
//! units.

use super::{Amax, AmaxOptions, alpha_max};
use crate::elements::Loop;
use crate::error::{Error, Result};

/// The wall at a fraction `margin` of the maximum stiffness of the loop `lp` (built in
/// physical units, [`Loop::physical`]), damping left at the value at `alpha_max`, in
/// physical units `(K, B)`.
///
/// Method: [`alpha_max`] of the loop.
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
/// [`alpha_max`].
pub fn margin_wall(lp: &Loop, margin: f64) -> Result<(f64, f64)> {
    check_margin(margin)?;
    let device = lp.device().ok_or_else(|| {
        Error::InvalidRequest(
            "a wall in physical units needs the loop's physical device: build the loop with Loop::physical".into(),
        )
    })?;
    let a: Amax = alpha_max(lp, &AmaxOptions::default())?;
    Ok((
        device.stiffness(margin * a.alpha_max),
        device.wall_damping(a.beta_at_max),
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
