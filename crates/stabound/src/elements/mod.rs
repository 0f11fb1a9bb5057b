//! The loop a scene describes: the paper's device plus the parts a real loop adds, each
//! modelled only when it is named (the model document, docs/MODEL.md, section 8).
//!
//! A [`Loop`] starts as the paper's loop (a damped mass, delay `d`, the backward-difference
//! wall) and takes any of:
//!
//! - an operator [`Hand`] holding the handle rigidly (mass, damping, stiffness);
//! - a compliant [`Transmission`]: motor and handle as two masses joined by a spring-damper,
//!   with the encoder on either side;
//! - an [`Actuator`] lag (a first-order amplifier or current loop);
//! - a [`VelocityFilter`] on the wall's damping term.
//!
//! Normalization is the paper's: `m` is the device's total mass (the hand excluded) and `T`
//! the sampling period. Every element has a normalized constructor and one in physical units
//! (kg, N s/m, N/m, s) that takes the [`Device`] it belongs to.
//!
//! With no element named (or only a filter that is `F = 1`), [`crate::Checker`] of a loop
//! runs on the paper's closed-form polynomial: the same verdicts, the same speed. With elements, the device is discretized by the augmented matrix exponential
//! ([`crate::model::Discretization`]) and its characteristic polynomial built from it
//! ([`crate::poly::CharPoly`]); both types choose the closed forms inside for the paper's
//! loop.
//!
//! ```
//! use stabound::elements::{Hand, Loop};
//! use stabound::filter::VelocityFilter;
//! use stabound::params::{Plant, Wall};
//! use stabound::stability::{Checker, Options, Verdict};
//!
//! // delta = 0.1, one sample of delay, a hand of half the device's mass, a 30 Hz filter at 1 kHz.
//! let lp = Loop::new(Plant::new(0.1, 1.0)?)
//!     .with_hand(Hand::new(0.5, 0.05, 0.0)?)?
//!     .with_filter(VelocityFilter::low_pass_cutoff(30.0, 1e-3)?)?;
//! let checker = Checker::new(lp, Options::default())?;
//! assert_eq!(checker.verdict(&Wall::new(0.05, 0.1)?)?, Verdict::Stable);
//! assert_eq!(checker.verdict(&Wall::new(3.0, 0.1)?)?, Verdict::Unstable);
//! # Ok::<(), stabound::Error>(())
//! ```

mod discrete;
pub mod list;
mod poly;

pub use discrete::Continuous;
pub(crate) use discrete::GeneralDiscretization;
pub(crate) use poly::GeneralPoly;

use crate::error::{Error, Result};
use crate::filter::{FilterKind, VelocityFilter};
use crate::params::MAX_COEFFS;
use crate::params::{Device, Plant, finite};

/// The largest normalized mass ratio, damping or stiffness an element accepts.
///
/// A hand a million times the device's mass, or a damping or stiffness of `1e6` in units of
/// `m/T` and `m/T^2`, is far outside any haptic device; beyond it the device's modes are so
/// fast or so slow that the matrix exponential's scaling and squaring (about `log2` of the
/// norm squarings) loses digits that the stability verdict needs.
pub const MAX_ELEMENT: f64 = 1e6;

/// The stiffest transmission coupling accepted, `k_c T^2 / m` (normalized).
///
/// The device's exponential is computed in double-double above a 1-norm of `1e3`, with a
/// bound on its error that the checker folds into its coefficient error (docs/MODEL.md,
/// section 8.1): at `1e8` the bound is about `3e-11` of the largest entry (`r = 0.3`), so walls near
/// the boundary come out marginal rather than wrong. A coupling stiffer than this is rigid
/// to the sampled loop in all but the last digits: leave the transmission out.
pub const MAX_TRANSMISSION_STIFFNESS: f64 = 1e8;

/// The shortest actuator time constant accepted, in samples.
///
/// A lag this short changes the loop by about `tau` (the force reaches its value within
/// `e^{-1/tau}` of a period); below it the element is not worth a state: leave it out.
pub const MIN_ACTUATOR_TAU: f64 = 1e-6;

/// The largest rate (1-norm of the continuous state matrix, per sampling period) a loop
/// with elements accepts.
///
/// Scaling and squaring takes about `log2` of it squarings, each adding rounding relative
/// to the norm; above a norm of `1e3` they run in double-double with an error bound the
/// checker folds into its coefficient error (docs/MODEL.md, section 8.1). The stiffest
/// transmission ([`MAX_TRANSMISSION_STIFFNESS`]) on a handle of `r = 0.01` has a rate of
/// `1e10`; a mode faster than that is rigid to the wall in all but the last digits.
pub const MAX_RATE: f64 = 1e10;

/// Checks `0 <= value <= MAX_ELEMENT` and finite, with a message naming `what`.
fn element_value(name: &'static str, value: f64, what: &str) -> Result<f64> {
    finite(name, value)?;
    if !(0.0..=MAX_ELEMENT).contains(&value) {
        return Err(Error::InvalidParameter {
            name,
            value,
            expected: format!("{what} must be between 0 and {MAX_ELEMENT} in normalized units"),
        });
    }
    Ok(value)
}

/// Converts a physical quantity to its normalized value, refusing negative ones.
fn physical(name: &'static str, value: f64, scale: f64, unit: &str) -> Result<f64> {
    finite(name, value)?;
    if value < 0.0 {
        return Err(Error::InvalidParameter {
            name,
            value,
            expected: format!("must be >= 0 {unit}"),
        });
    }
    Ok(value * scale)
}

/// The operator's hand holding the handle rigidly: it adds mass, damping and stiffness to
/// the mass it holds (the single mass, or the handle side of a [`Transmission`]).
///
/// Normalized: `mu_h = m_h / m`, `delta_h = b_h T / m`, `kappa_h = k_h T^2 / m`.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct Hand {
    mu: f64,
    delta: f64,
    kappa: f64,
}

impl Hand {
    /// A hand in normalized units, each value in `[0, MAX_ELEMENT]`. All zero is allowed
    /// (and changes nothing).
    pub fn new(mu: f64, delta: f64, kappa: f64) -> Result<Self> {
        Ok(Self {
            mu: element_value("hand mass ratio", mu, "the hand's mass over the device's")?,
            delta: element_value("hand damping", delta, "the hand's damping b_h T / m")?,
            kappa: element_value("hand stiffness", kappa, "the hand's stiffness k_h T^2 / m")?,
        })
    }

    /// A hand in physical units on `device`: mass in kg, damping in N s/m, stiffness in N/m.
    pub fn physical(device: &Device, mass: f64, damping: f64, stiffness: f64) -> Result<Self> {
        device.validate()?;
        let (m, t) = (device.mass(), device.period());
        Self::new(
            physical("hand mass", mass, 1.0 / m, "kg")?,
            physical("hand damping", damping, t / m, "N s/m")?,
            physical("hand stiffness", stiffness, t * t / m, "N/m")?,
        )
    }

    /// `mu_h = m_h / m`.
    pub fn mass_ratio(&self) -> f64 {
        self.mu
    }

    /// `delta_h = b_h T / m`.
    pub fn damping(&self) -> f64 {
        self.delta
    }

    /// `kappa_h = k_h T^2 / m`.
    pub fn stiffness(&self) -> f64 {
        self.kappa
    }
}

/// The loop elements in physical units, as a scene, a command line or a binding names them:
/// `None` is not modelled. Build it from `PhysicalElements::default()` and set the fields
/// named; [`Loop::with_physical`] validates them against a device.
///
/// With serde its keys carry their units (`hand_mass_kg`, `hand_damping_Ns_per_m`,
/// `hand_stiffness_N_per_m`, `handle_mass_kg`, `transmission_stiffness_N_per_m`,
/// `transmission_damping_Ns_per_m`, `motor_damping_Ns_per_m`, `handle_damping_Ns_per_m`,
/// `encoder = "motor" | "handle"`,
/// `actuator_time_constant_s`, `velocity_filter_cutoff_Hz`, `velocity_filter_order`,
/// `velocity_filter_samples`);
/// reading refuses what no device could accept (a negative or non-finite value, a zero
/// mass, stiffness, time constant, cutoff or window, two filters, half a transmission).
///
/// Every field is a parameter of the element list ([`list::PARAMS`]), which gives its key,
/// flag, keyword, unit, accepted values and help.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
#[non_exhaustive]
pub struct PhysicalElements {
    /// Operator hand mass, kg.
    pub hand_mass: Option<f64>,
    /// Operator hand damping, N s/m.
    pub hand_damping: Option<f64>,
    /// Operator hand stiffness, N/m.
    pub hand_stiffness: Option<f64>,
    /// Handle-side mass of a compliant transmission, kg (below the device mass).
    pub handle_mass: Option<f64>,
    /// Coupling stiffness of the transmission, N/m.
    pub transmission_stiffness: Option<f64>,
    /// Coupling damping of the transmission, N s/m.
    pub transmission_damping: Option<f64>,
    /// The motor side's share `b_1` of the device's damping, N s/m (the handle side takes
    /// the rest).
    pub motor_damping: Option<f64>,
    /// The handle side's share `b_2` of the device's damping, N s/m (the motor side takes
    /// the rest).
    pub handle_damping: Option<f64>,
    /// Which side the encoder reads (motor by default).
    pub encoder: Option<Encoder>,
    /// Actuator time constant, s.
    pub actuator_time_constant: Option<f64>,
    /// First-order low-pass velocity filter cutoff, Hz.
    pub velocity_filter_cutoff: Option<f64>,
    /// Moving-average velocity filter length, samples.
    pub velocity_filter_samples: Option<usize>,
    /// Order of the low-pass velocity filter: 1 (first order, the default) or above it a
    /// Butterworth filter of that order ([`VelocityFilter::low_pass_order`]).
    pub velocity_filter_order: Option<usize>,
    /// Encoder resolution, m per count (a quantizer, see [`crate::buzz`]).
    pub encoder_resolution: Option<f64>,
    /// Force output resolution (DAC step), N (a quantizer, see [`crate::buzz`]).
    pub force_resolution: Option<f64>,
    /// Coulomb (sliding) friction on the device's mass, N (see [`crate::buzz`]).
    pub coulomb_friction: Option<f64>,
    /// Static (breakaway) friction, N, at least the Coulomb friction (see [`crate::buzz`]).
    pub static_friction: Option<f64>,
}

impl PhysicalElements {
    /// Whether any linear element is named (the quantizers and friction, which
    /// [`crate::buzz::Nonlinear`] takes, leave the linear loop as it is).
    pub fn any(&self) -> bool {
        self.without_nonlinear() != Self::default()
    }

    /// These elements without the quantizers and friction: the linear loop's.
    pub fn without_nonlinear(&self) -> Self {
        Self {
            encoder_resolution: None,
            force_resolution: None,
            coulomb_friction: None,
            static_friction: None,
            ..*self
        }
    }

    /// The checks that need no device, from the element list: each value as its parameter
    /// accepts ([`list::Param::accept`]: finite, not negative, above zero, a window of at
    /// least one sample, ...), and the parameters named together (at most one filter, a
    /// transmission named by both its mass and its stiffness).
    pub fn validate(&self) -> Result<()> {
        self.check_list()?;
        list::friction_order(self.coulomb_friction, self.static_friction)
    }

    /// The velocity filter named (`F = 1` when none) on a loop sampled every `period` s,
    /// which a cutoff converts on.
    pub fn velocity_filter(&self, period: f64) -> Result<VelocityFilter> {
        match (self.velocity_filter_cutoff, self.velocity_filter_samples) {
            (Some(_), Some(_)) => Err(Error::InvalidRequest(
                "name one velocity filter: a low-pass cutoff or a moving average, not both".into(),
            )),
            (Some(fc), None) => {
                VelocityFilter::low_pass_order(self.velocity_filter_order.unwrap_or(1), fc, period)
            }
            (None, Some(n)) => VelocityFilter::moving_average(n),
            (None, None) => Ok(VelocityFilter::none()),
        }
    }

    /// The names of the elements named, for reports: `hand`, `transmission (encoder on the
    /// motor)` or `(... handle)`, `actuator lag`, `low-pass velocity filter`,
    /// `second-order low-pass velocity filter`, `moving-average velocity filter`, and the
    /// nonlinear ones: `encoder resolution`, `force resolution`, `dry friction`.
    pub fn names(&self) -> Vec<&'static str> {
        list::Element::ALL
            .iter()
            .chain(&list::Element::NONLINEAR)
            .filter_map(|el| el.name(self))
            .collect()
    }
}

/// Which mass of a [`Transmission`] the position sensor reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "lowercase"))]
#[non_exhaustive]
pub enum Encoder {
    /// On the motor (`y = x1`): the usual case, the actuator and the sensor collocated.
    #[default]
    Motor,
    /// On the handle (`y = x2`): the compliance sits between the force and the sensor.
    Handle,
}

/// A compliant transmission: the device as two masses, the motor side `1 - r` (where the
/// force acts) and the handle side `r`, joined by a spring `kappa_c` and damper `delta_c`.
///
/// The device's physical damping `delta` (of the [`Plant`]) is split: `delta_2` acts on the
/// handle, `delta_1 = delta - delta_2` on the motor, so that as `kappa_c -> infinity` the
/// loop tends to the one-mass loop with the same `delta`.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct Transmission {
    r: f64,
    kappa: f64,
    delta_c: f64,
    delta_2: f64,
    encoder: Encoder,
}

impl Transmission {
    /// A transmission in normalized units: handle mass ratio `0 < r < 1`, coupling stiffness
    /// `0 < kappa_c <= MAX_TRANSMISSION_STIFFNESS`, coupling damping `delta_c` and handle-side damping
    /// `delta_2` in `[0, MAX_ELEMENT]`.
    pub fn new(r: f64, kappa_c: f64, delta_c: f64, delta_2: f64, encoder: Encoder) -> Result<Self> {
        finite("handle mass ratio", r)?;
        if !(r > 0.0 && r < 1.0) {
            return Err(Error::InvalidParameter {
                name: "handle mass ratio",
                value: r,
                expected: "the handle's mass must be above 0 and below the device's total mass (0 < r < 1)".into(),
            });
        }
        finite("transmission stiffness", kappa_c)?;
        if kappa_c > MAX_TRANSMISSION_STIFFNESS {
            return Err(Error::InvalidParameter {
                name: "transmission stiffness",
                value: kappa_c,
                expected: format!(
                    "the coupling stiffness k_c T^2 / m must be at most {MAX_TRANSMISSION_STIFFNESS:e} in normalized units; a stiffer coupling is rigid to the sampled loop: leave the transmission out (a rigid device)"
                ),
            });
        }
        if kappa_c <= 0.0 {
            return Err(Error::InvalidParameter {
                name: "transmission stiffness",
                value: kappa_c,
                expected: "a transmission needs a coupling stiffness above 0 (without one the handle is not driven)".into(),
            });
        }
        Ok(Self {
            r,
            kappa: kappa_c,
            delta_c: element_value(
                "transmission damping",
                delta_c,
                "the coupling damping b_c T / m",
            )?,
            delta_2: element_value(
                "handle damping",
                delta_2,
                "the handle-side damping b_2 T / m",
            )?,
            encoder,
        })
    }

    /// A transmission in physical units on `device`: handle mass in kg (below the device's
    /// mass), coupling stiffness in N/m, coupling damping and handle-side damping in N s/m
    /// (the latter a share of the device's damping).
    pub fn physical(
        device: &Device,
        handle_mass: f64,
        stiffness: f64,
        damping: f64,
        handle_damping: f64,
        encoder: Encoder,
    ) -> Result<Self> {
        device.validate()?;
        let (m, t) = (device.mass(), device.period());
        finite("handle mass", handle_mass)?;
        if !(handle_mass > 0.0 && handle_mass < m) {
            return Err(Error::InvalidParameter {
                name: "handle mass",
                value: handle_mass,
                expected: format!(
                    "the handle's mass must be above 0 kg and below the device's mass {m} kg"
                ),
            });
        }
        if handle_damping > device.damping() {
            return Err(Error::InvalidParameter {
                name: "handle damping",
                value: handle_damping,
                expected: format!(
                    "the handle-side damping is a share of the device's damping {} N s/m and cannot exceed it",
                    device.damping()
                ),
            });
        }
        Self::new(
            handle_mass / m,
            physical("transmission stiffness", stiffness, t * t / m, "N/m")?,
            physical("transmission damping", damping, t / m, "N s/m")?,
            // in the order the device's delta = b T / m rounds, so that a share of all of
            // b is all of delta and a share below b stays below delta
            physical("handle damping", handle_damping, 1.0, "N s/m")? * t / m,
            encoder,
        )
    }

    /// `r = m_2 / m`, the handle's share of the device's mass.
    pub fn handle_ratio(&self) -> f64 {
        self.r
    }

    /// `kappa_c = k_c T^2 / m`.
    pub fn stiffness(&self) -> f64 {
        self.kappa
    }

    /// `delta_c = b_c T / m`.
    pub fn damping(&self) -> f64 {
        self.delta_c
    }

    /// `delta_2 = b_2 T / m`, the damping on the handle side.
    pub fn handle_damping(&self) -> f64 {
        self.delta_2
    }

    /// Where the position is sensed.
    pub fn encoder(&self) -> Encoder {
        self.encoder
    }
}

/// The handle side's share `b_2` of the device's damping `b` (N s/m) when the motor side's
/// share `b_1` and the handle side's `b_2` are named as given: none, `0` (all of `b` on the
/// motor); one, the other side takes the rest; both, they must add up to `b` (to the
/// rounding of one addition and one subtraction, `4 eps b`).
fn handle_share(b: f64, motor: Option<f64>, handle: Option<f64>) -> Result<f64> {
    let over = |name: &'static str, value: f64| Error::InvalidParameter {
        name,
        value,
        expected: format!(
            "the motor-side and handle-side dampers are shares of the device's damping {b} N s/m and cannot exceed it"
        ),
    };
    match (motor, handle) {
        (None, None) => Ok(0.0),
        // the handle's share is checked against b by the transmission itself
        (None, Some(b2)) => Ok(b2),
        (Some(b1), _) if b1 > b => Err(over("motor damping", b1)),
        (Some(b1), None) => Ok(b - b1),
        (Some(b1), Some(b2)) => {
            if (b1 + b2 - b).abs() > 4.0 * f64::EPSILON * b {
                return Err(Error::InvalidRequest(format!(
                    "the motor-side damping {b1} N s/m and the handle-side damping {b2} N s/m split the device's damping {b} N s/m and must add up to it: give one of them (the other side takes the rest), or both adding up to the device's damping"
                )));
            }
            Ok(b2)
        }
    }
}

/// Actuator lag: the force on the device follows the commanded (held, delayed) force through
/// `tau f' = u - f`, with `tau = tau_a / T`.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct Actuator {
    tau: f64,
}

impl Actuator {
    /// A lag of `tau` samples, `MIN_ACTUATOR_TAU <= tau <= MAX_ELEMENT`.
    pub fn new(tau: f64) -> Result<Self> {
        finite("actuator time constant", tau)?;
        if !(MIN_ACTUATOR_TAU..=MAX_ELEMENT).contains(&tau) {
            return Err(Error::InvalidParameter {
                name: "actuator time constant",
                value: tau,
                expected: format!(
                    "the lag tau_a / T must be between {MIN_ACTUATOR_TAU} and {MAX_ELEMENT} sampling periods; leave the element out for an actuator without lag"
                ),
            });
        }
        Ok(Self { tau })
    }

    /// A lag with time constant `time_constant` seconds on a loop sampled every `period` s.
    pub fn physical(time_constant: f64, period: f64) -> Result<Self> {
        finite("actuator time constant", time_constant)?;
        crate::params::positive("period", period)?;
        Self::new(time_constant / period)
    }

    /// `tau = tau_a / T`.
    pub fn tau(&self) -> f64 {
        self.tau
    }
}

/// A validated loop: the paper's plant `(delta, d)` plus the elements named, and the
/// physical [`Device`] it describes when it was built in physical units.
///
/// Every engine of the crate takes a loop (`impl Into<Loop>`): a [`Plant`] converts into the
/// paper's loop, so `&plant` is accepted wherever a loop is. The paper's closed forms are
/// chosen inside the engines whenever [`Loop::is_paper`] holds.
///
/// ```
/// use stabound::elements::{Loop, PhysicalElements};
/// use stabound::params::{Delay, Device, Plant};
///
/// // normalized: the paper's loop on delta = 0.1, one sample of delay
/// let bare = Loop::from(Plant::new(0.1, 1.0)?);
/// assert!(bare.is_paper() && bare.device().is_none());
/// // physical: the paper's Section VIII device behind a 30 Hz velocity filter
/// let device = Device::new(0.1, 1e-3, 0.0, Delay::Samples(1.0))?;
/// let mut named = PhysicalElements::default();
/// named.velocity_filter_cutoff = Some(30.0);
/// let lp = Loop::physical(&device, &named)?;
/// assert_eq!(lp.device(), Some(&device));
/// assert!(!lp.is_paper());
/// # Ok::<(), stabound::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Loop {
    plant: Plant,
    device: Option<Device>,
    hand: Option<Hand>,
    transmission: Option<Transmission>,
    actuator: Option<Actuator>,
    filter: VelocityFilter,
}

impl From<Plant> for Loop {
    fn from(plant: Plant) -> Self {
        Self::new(plant)
    }
}

impl From<&Plant> for Loop {
    fn from(plant: &Plant) -> Self {
        Self::new(*plant)
    }
}

impl From<&Loop> for Loop {
    fn from(lp: &Loop) -> Self {
        *lp
    }
}

impl Loop {
    /// The paper's loop for `plant`, with no element (normalized: no device).
    pub fn new(plant: Plant) -> Self {
        Self {
            plant,
            device: None,
            hand: None,
            transmission: None,
            actuator: None,
            filter: VelocityFilter::none(),
        }
    }

    /// The loop of `device` in physical units with the elements `named` (none named: the
    /// paper's loop on the device's plant). The loop knows its device ([`Loop::device`]).
    ///
    /// # Errors
    ///
    /// As [`Device::plant`] and [`Loop::with_physical`].
    pub fn physical(device: &Device, named: &PhysicalElements) -> Result<Self> {
        let mut lp = Self::new(device.plant()?).with_physical(device, named)?;
        lp.device = Some(*device);
        Ok(lp)
    }

    /// This loop as the loop of `device`: the same elements, now knowing the physical device
    /// they belong to. The elements' normalized values are taken as they are.
    ///
    /// # Errors
    ///
    /// [`Error::InvalidRequest`] when the loop's plant is not `device`'s (build the loop on
    /// `device.plant()`); as [`Device::plant`].
    pub fn with_device(mut self, device: &Device) -> Result<Self> {
        let plant = device.plant()?;
        // exact: the same device gives the same plant bit for bit
        if self.plant != plant {
            return Err(Error::InvalidRequest(format!(
                "the loop's plant (delta = {}, d = {}) is not the device's (delta = {}, d = {}); build the loop on the device's plant",
                self.plant.delta(),
                self.plant.d(),
                plant.delta(),
                plant.d()
            )));
        }
        self.device = Some(*device);
        Ok(self)
    }

    /// The physical device this loop was built from ([`Loop::physical`],
    /// [`Loop::with_device`]); `None` for a loop built in normalized units.
    pub fn device(&self) -> Option<&Device> {
        self.device.as_ref()
    }

    /// Adds (or replaces) the operator's hand.
    pub fn with_hand(mut self, hand: Hand) -> Result<Self> {
        self.hand = Some(hand);
        self.checked()
    }

    /// Adds (or replaces) a compliant transmission. Its handle-side damping must not exceed
    /// the plant's `delta` (it is a share of it).
    pub fn with_transmission(mut self, transmission: Transmission) -> Result<Self> {
        let delta = self.plant.delta();
        if transmission.delta_2 > delta {
            return Err(Error::InvalidParameter {
                name: "handle damping",
                value: transmission.delta_2,
                expected: format!(
                    "the handle-side damping is a share of the device's damping delta = {delta} and cannot exceed it"
                ),
            });
        }
        self.transmission = Some(transmission);
        self.checked()
    }

    /// This loop's elements on another plant (the checks of each element run again: a
    /// transmission's handle-side damping must not exceed the new `delta`). The result is
    /// normalized: it no longer describes this loop's physical device.
    pub fn with_plant(mut self, plant: Plant) -> Result<Self> {
        self.plant = plant;
        self.device = None;
        match self.transmission.take() {
            Some(t) => self.with_transmission(t),
            None => self.checked(),
        }
    }

    /// Adds (or replaces) an actuator lag.
    pub fn with_actuator(mut self, actuator: Actuator) -> Result<Self> {
        self.actuator = Some(actuator);
        self.checked()
    }

    /// Sets the velocity filter on the wall's damping term.
    pub fn with_filter(mut self, filter: VelocityFilter) -> Result<Self> {
        self.filter = filter;
        self.checked()
    }

    /// This loop with the elements `named` in physical units on `device` (whose plant this
    /// loop is); nothing named leaves it as it is.
    ///
    /// ```
    /// use stabound::elements::{Loop, PhysicalElements};
    /// use stabound::params::{Delay, Device};
    ///
    /// let device = Device::new(0.1, 1e-3, 0.0, Delay::Samples(1.0))?;
    /// let mut named = PhysicalElements::default();
    /// named.velocity_filter_cutoff = Some(30.0);
    /// let lp = Loop::new(device.plant()?).with_physical(&device, &named)?;
    /// assert!(!lp.is_paper());
    /// # Ok::<(), stabound::Error>(())
    /// ```
    ///
    /// # Errors
    ///
    /// A value out of range (as each element's constructor says), or a transmission named
    /// by only some of its parts (it needs both the handle mass and the coupling stiffness).
    pub fn with_physical(self, device: &Device, named: &PhysicalElements) -> Result<Self> {
        named.validate()?;
        let mut lp = self;
        let e = named;
        if e.hand_mass.is_some() || e.hand_damping.is_some() || e.hand_stiffness.is_some() {
            lp = lp.with_hand(Hand::physical(
                device,
                e.hand_mass.unwrap_or(0.0),
                e.hand_damping.unwrap_or(0.0),
                e.hand_stiffness.unwrap_or(0.0),
            )?)?;
        }
        match (e.handle_mass, e.transmission_stiffness) {
            (Some(m2), Some(k)) => {
                lp = lp.with_transmission(Transmission::physical(
                    device,
                    m2,
                    k,
                    e.transmission_damping.unwrap_or(0.0),
                    handle_share(device.damping(), e.motor_damping, e.handle_damping)?,
                    e.encoder.unwrap_or_default(),
                )?)?;
            }
            (None, None) if e.transmission_damping.is_none() && e.encoder.is_none() => {}
            _ => {
                return Err(Error::InvalidRequest(
                    "a compliant transmission needs both the handle mass and the coupling stiffness (its damping and the encoder side are optional)".into(),
                ));
            }
        }
        if let Some(t) = e.actuator_time_constant {
            lp = lp.with_actuator(Actuator::physical(t, device.period())?)?;
        }
        let filter = e.velocity_filter(device.period())?;
        if filter.kind() != FilterKind::None {
            lp = lp.with_filter(filter)?;
        }
        Ok(lp)
    }

    fn checked(self) -> Result<Self> {
        let rate = discrete::Continuous::new(&self)
            .a
            .column_iter()
            .map(|c| c.lp_norm(1))
            .fold(0.0, f64::max);
        // the paper's loop keeps its closed forms, valid for every delta it accepts
        if !self.is_paper() && (rate.is_nan() || rate > MAX_RATE) {
            return Err(Error::InvalidRequest(format!(
                "the device's fastest mode ({rate:e} per sampling period) is beyond what the exact discretization resolves ({MAX_RATE:e}): lower the damping or stiffness relative to the sampling period, use a heavier motor side or a longer actuator lag, or leave out the element that makes the mode this fast"
            )));
        }
        let degree = self.degree();
        if degree + 1 > MAX_COEFFS {
            return Err(Error::InvalidRequest(format!(
                "the delay and the elements together give a characteristic polynomial of degree {degree}, above the supported {}; shorten the delay or the velocity filter",
                MAX_COEFFS - 1
            )));
        }
        Ok(self)
    }

    /// The paper's plant: physical damping (the device's total) and delay.
    pub fn plant(&self) -> &Plant {
        &self.plant
    }

    /// The hand, if named.
    pub fn hand(&self) -> Option<&Hand> {
        self.hand.as_ref()
    }

    /// The transmission, if named.
    pub fn transmission(&self) -> Option<&Transmission> {
        self.transmission.as_ref()
    }

    /// The actuator lag, if named.
    pub fn actuator(&self) -> Option<&Actuator> {
        self.actuator.as_ref()
    }

    /// The velocity filter (`F = 1` when none is named).
    pub fn filter(&self) -> &VelocityFilter {
        &self.filter
    }

    /// Whether this is the paper's loop: no hand, transmission or lag, and `F = 1`.
    pub fn is_paper(&self) -> bool {
        self.hand.is_none()
            && self.transmission.is_none()
            && self.actuator.is_none()
            && self.filter.is_identity()
    }

    /// Whether the device has a free integrator (`D(1) = 0`: no hand stiffness holds it),
    /// so that the root `z = 1` is on the line `alpha = 0`.
    pub(crate) fn free_integrator(&self) -> bool {
        // exact: a stiffness of exactly zero is no spring at all
        self.hand.is_none_or(|h| h.kappa == 0.0)
    }

    /// The device's continuous state dimension `s`: 2 for one mass, 4 for two, plus one for
    /// an actuator lag.
    pub fn device_order(&self) -> usize {
        let masses = if self.transmission.is_some() { 4 } else { 2 };
        masses + usize::from(self.actuator.is_some())
    }

    /// Whether the filter is a first-order low-pass with a nonzero pole (its numerator
    /// `(1 - a) z` gives `q` a common factor `z`).
    pub(crate) fn low_pass_pole(&self) -> Option<f64> {
        match self.filter.kind() {
            // exact: a zero pole is F = 1 identically
            FilterKind::LowPass { pole } if pole != 0.0 => Some(pole),
            _ => None,
        }
    }

    /// Degree of the characteristic polynomial, equal to the closed loop's state dimension:
    /// `n + 2 + s + f`, less one for a whole-sample delay and one for a low-pass filter.
    pub fn degree(&self) -> usize {
        if self.is_paper() {
            return self.plant.degree();
        }
        let n = self.plant.whole_samples();
        let f = if self.filter.is_identity() {
            0
        } else {
            self.filter.order()
        };
        n + 2 + self.device_order() + f
            - usize::from(self.plant.is_integer_delay())
            - usize::from(self.low_pass_pole().is_some())
    }
}
