//! Walls that hold for a set of devices, not one (the model document, docs/MODEL.md,
//! section 12).
//!
//! A [`DeviceSet`] is a device in physical units whose parameters may each be an interval
//! `lo..hi` or a finite list of values (mass, damping, delay, every element parameter), and,
//! when a hand is named, the same device with the hand let go. Its robust stable region is
//! the intersection of its members' stable regions; [`robust_alpha_max`] finds the largest
//! stiffness for which one damping is stable for every member, and [`robust_check`] says
//! whether one wall is.
//!
//! Walls are compared in one normalization for the whole set: the set's *reference* device
//! (every interval at its low end, every list at its smallest value), `alpha = K T^2 / m_ref`,
//! `beta = B T / m_ref`. A member of mass `m` sees the same physical wall as
//! `(m_ref / m) (alpha, beta)` in its own normalization. The sampling period is one value for
//! the whole set (firmware sets it).
//!
//! ```
//! use stabound::elements::PhysicalElements;
//! use stabound::params::{Delay, Device};
//! use stabound::robust::{DeviceSet, Quantity, robust_alpha_max};
//! use stabound::AmaxOptions;
//!
//! // the paper's device (normalized units: m = 1, T = 1), delay jittering between 1 and 2 samples
//! let device = Device::new(1.0, 1.0, 0.5, Delay::Samples(1.0))?;
//! let set = DeviceSet::new(&device, &PhysicalElements::default())?
//!     .with_interval(Quantity::Delay, 1.0, 2.0)?;
//! let r = robust_alpha_max(&set, &AmaxOptions::default())?;
//! // a longer delay lowers the stiffness: the robust wall is below the 1-sample one
//! let one = stabound::alpha_max(&device.plant()?, &AmaxOptions::default())?;
//! assert!(r.alpha_max < one.alpha_max && r.alpha_verified <= r.alpha_max);
//! # Ok::<(), stabound::Error>(())
//! ```

mod proof;
mod proof_elements;
mod region;
mod sample;
mod search;
mod table;

pub use proof::{PROOF_BUDGET, Proof, ProofCell, ProofStop, prove_wall};
pub use region::{
    FIRST_PASS_TOL, PROOF_POINTS, RegionSearch, RobustRegion, SEARCH_ROUNDS, robust_region,
};
pub use search::{RobustAmax, RobustCheck, Verification, robust_alpha_max, robust_check};

pub use crate::devices::{
    DeviceSet, MAX_INTERVALS, MAX_VARIANTS, Member, Quantity, Spread, hand_let_go,
};
pub(crate) use crate::devices::{Variant, grid};
pub(crate) use crate::search::intersect;
