//! The node of a lookup table over a set of devices ([`crate::amax::TableOptions::with_device_set`]):
//! the table's construction is `alpha_max`'s, below this layer; what a node is for a set
//! is this layer's.

use super::{DeviceSet, robust_alpha_max};
use crate::amax::{Amax, AmaxOptions, RobustNode};
use crate::error::Result;

/// The set's robust `alpha_max` with its verified stiffness: the wall shown stable for every
/// member (docs/MODEL.md section 12).
impl RobustNode for DeviceSet {
    fn robust_node(&self, opts: &AmaxOptions) -> Result<Amax> {
        let r = robust_alpha_max(self, opts)?;
        Ok(Amax {
            alpha_max: r.alpha_verified,
            beta_at_max: r.beta_at_max,
        })
    }
}
