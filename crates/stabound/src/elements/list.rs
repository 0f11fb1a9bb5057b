//! The element list: every parameter of the loop's elements declared once, with its scene
//! key, command-line flag, Python keyword, unit, normalized form, accepted values, help and
//! report label (the model document, docs/MODEL.md, section 8).
//!
//! The command line's flags, the scene's keys, the serde form of [`PhysicalElements`], the
//! Python keywords and the value checks are all read from [`PARAMS`]; the one check of each
//! value is [`Param::accept`].
//!
//! ```
//! use stabound::elements::list::{PARAMS, Value, param};
//! use stabound::elements::PhysicalElements;
//!
//! let p = param("hand_mass").unwrap();
//! assert_eq!((p.key, p.flag, p.unit), ("hand_mass_kg", "hand-mass", "kg"));
//! assert!(p.accept(Value::Number(-1.0)).is_err());
//! let mut e = PhysicalElements::default();
//! p.set(&mut e, p.accept(Value::Number(0.2))?);
//! assert_eq!(e.hand_mass, Some(0.2));
//! assert!(PARAMS.iter().all(|p| p.key.starts_with(p.keyword)));
//! # Ok::<(), stabound::Error>(())
//! ```

use super::{Encoder, Loop, PhysicalElements};
use crate::error::{Error, Result};
use crate::filter::{FilterKind, LOW_PASS_NAMES, MAX_MOVING_AVERAGE};

/// What values a parameter accepts.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub enum Accepts {
    /// A finite number `>= 0`.
    NonNegative,
    /// A finite number `> 0`.
    Positive,
    /// A whole number in `min..=max`.
    Count {
        /// The smallest accepted.
        min: usize,
        /// The largest accepted.
        max: usize,
    },
    /// One of these names.
    Choice(&'static [&'static str]),
}

/// One parameter's value as a front end reads it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Value {
    /// A number in the parameter's unit.
    Number(f64),
    /// A whole number.
    Count(usize),
    /// One of the parameter's names.
    Choice(&'static str),
}

/// One parameter's value as text gives it: one value, or, for a set of devices (the model
/// document, section 12), every number of an interval `LO..HI`.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub enum Form {
    /// One value.
    One(Value),
    /// Every number from `lo` to `hi` (`lo < hi`).
    Interval(f64, f64),
}

/// Reads an interval `LO..HI` of the quantity `name` (both ends finite numbers, `LO <= HI`;
/// equal ends are that one number, [`Form::One`]); `None` when `text` is no interval. The one
/// reading of intervals, for the list's parameters ([`Param::read_form`]) and for the
/// device's own (mass, damping, delay).
///
/// ```
/// use stabound::elements::list::{Form, Value, read_interval};
///
/// assert_eq!(read_interval("1..3", "delay").unwrap()?, Form::Interval(1.0, 3.0));
/// assert_eq!(read_interval("2..2", "delay").unwrap()?, Form::One(Value::Number(2.0)));
/// assert!(read_interval("3..1", "delay").unwrap().is_err());
/// assert!(read_interval("0.5", "delay").is_none());
/// # Ok::<(), stabound::Error>(())
/// ```
pub fn read_interval(text: &str, name: &str) -> Option<Result<Form>> {
    let (lo, hi) = text.split_once("..")?;
    let end = |t: &str| -> Result<f64> {
        t.trim()
            .parse::<f64>()
            .ok()
            .filter(|x| x.is_finite())
            .ok_or_else(|| {
                Error::InvalidRequest(format!(
                    "'{text}' is no interval of {name}: give LO..HI with two finite numbers, e.g. 1..3"
                ))
            })
    };
    Some((|| {
        let (lo, hi) = (end(lo)?, end(hi)?);
        if lo > hi {
            return Err(Error::InvalidRequest(format!(
                "the {name} interval '{text}' is inverted: give the low end first"
            )));
        }
        // exact: equal ends are one number
        Ok(if lo == hi {
            Form::One(Value::Number(lo))
        } else {
            Form::Interval(lo, hi)
        })
    })())
}

/// Which element a parameter belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum Element {
    /// The operator's hand.
    Hand,
    /// A compliant transmission.
    Transmission,
    /// An actuator lag.
    Actuator,
    /// A velocity filter.
    VelocityFilter,
    /// A quantizer (encoder or force output resolution; nonlinear, see [`crate::buzz`]).
    Quantizer,
    /// Dry friction on the device's mass (nonlinear, see [`crate::buzz`]).
    Friction,
}

impl Element {
    /// Whether the element is nonlinear (a quantizer or friction): it enters the buzz
    /// verdict ([`crate::buzz`]), not the linear loop.
    pub fn nonlinear(self) -> bool {
        matches!(self, Element::Quantizer | Element::Friction)
    }
}

impl Element {
    /// The nonlinear elements, in the order reports list them after the linear ones.
    pub const NONLINEAR: [Element; 2] = [Element::Quantizer, Element::Friction];

    /// Every linear element, in the order reports list them.
    pub const ALL: [Element; 4] = [
        Element::Hand,
        Element::Transmission,
        Element::Actuator,
        Element::VelocityFilter,
    ];

    /// Its key in a JSON report's `elements` object (`hand`).
    pub fn key(self) -> &'static str {
        match self {
            Element::Hand => "hand",
            Element::Transmission => "transmission",
            Element::Actuator => "actuator",
            Element::VelocityFilter => "velocity_filter",
            Element::Quantizer => "quantizer",
            Element::Friction => "friction",
        }
    }

    /// Its title in a table's header for the loop `lp` (`operator hand`); a velocity
    /// filter's names its kind, which its readings (a pole, a cutoff, a count) do not say.
    pub fn title(self, lp: &Loop) -> &'static str {
        match self {
            Element::Hand => "operator hand",
            Element::Transmission => "compliant transmission",
            Element::Actuator => "actuator lag",
            Element::VelocityFilter => lp.filter().title(),
            Element::Quantizer => "quantizers",
            Element::Friction => "dry friction",
        }
    }

    /// Its name in a scene's report, as `e` names it (`transmission (encoder on the
    /// motor)`), or `None` when `e` names none of its parameters.
    pub fn name(self, e: &PhysicalElements) -> Option<&'static str> {
        if !self.params().any(|p| p.get(e).is_some()) {
            return None;
        }
        Some(match self {
            Element::Hand => "hand",
            // a transmission is named by its mass (the list refuses its other parameters alone)
            Element::Transmission => match (e.handle_mass, e.encoder.unwrap_or_default()) {
                (None, _) => return None,
                (_, Encoder::Motor) => "transmission (encoder on the motor)",
                (_, Encoder::Handle) => "transmission (encoder on the handle)",
            },
            Element::Actuator => "actuator lag",
            Element::VelocityFilter => match (
                e.velocity_filter_cutoff,
                e.velocity_filter_order,
                e.velocity_filter_samples,
            ) {
                (_, _, Some(_)) => "moving-average velocity filter",
                // the filter's design names each order it has (the first order by default)
                (Some(_), order, _) => LOW_PASS_NAMES
                    .get(order.unwrap_or(1).wrapping_sub(1))
                    .copied()
                    .unwrap_or(LOW_PASS_NAMES[0]),
                _ => return None,
            },
            Element::Quantizer => match (e.encoder_resolution, e.force_resolution) {
                (Some(_), None) => "encoder resolution",
                (None, Some(_)) => "force resolution",
                _ => "encoder and force resolution",
            },
            Element::Friction => "dry friction",
        })
    }

    /// Its parameters, in the list's order.
    pub fn params(self) -> impl Iterator<Item = &'static Param> {
        PARAMS.iter().filter(move |p| p.element == self)
    }

    /// The values a report shows of this element on `lp`, each with its parameter (empty
    /// when `lp` does not model it).
    ///
    /// ```
    /// use stabound::elements::list::{Element, Value};
    /// use stabound::elements::{Loop, PhysicalElements};
    /// use stabound::params::{Delay, Device};
    ///
    /// let device = Device::new(0.1, 1e-3, 0.0, Delay::Samples(1.0))?;
    /// let mut named = PhysicalElements::default();
    /// named.actuator_time_constant = Some(2e-4);
    /// let lp = Loop::physical(&device, &named)?;
    /// let shown = Element::Actuator.readings(&lp);
    /// let (p, r) = shown[0];
    /// assert_eq!((p.keyword, r.label, r.form), ("actuator_time_constant", "tau", "tau = tau_a / T"));
    /// assert_eq!(r.value, Value::Number(2e-4 / 1e-3));
    /// assert!((r.physical(0.1, 1e-3).unwrap() - 2e-4).abs() < 1e-18);
    /// assert!(Element::Hand.readings(&lp).is_empty());
    /// # Ok::<(), stabound::Error>(())
    /// ```
    pub fn readings(self, lp: &Loop) -> Vec<(&'static Param, Reading)> {
        self.params()
            .filter_map(|p| p.reading(lp).map(|r| (p, r)))
            .collect()
    }
}

/// How a report turns a normalized value back into its parameter's physical unit, given the
/// device's mass `m` and period `T`.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub enum Scale {
    /// No physical form (a count, a choice).
    None,
    /// `v m / T^p`: a mass (`p = 0`), a damping (1), a stiffness (2).
    Mass(i32),
    /// `v T`: a time.
    Period,
    /// A low-pass pole `a = exp(-2 pi f_c T)`, shown as its cutoff `-ln a / (2 pi T)`
    /// (none for `a = 0`).
    Pole,
    /// A cutoff in cycles per sample `f_c T`, shown as `f_c`.
    Frequency,
}

/// One value a report shows of a loop's element: the normalized value the loop holds, with
/// its label in JSON, its form in words and its physical scale.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct Reading {
    /// Its key in the element's JSON object (`mu_h`).
    pub label: &'static str,
    /// Its normalized form, as the model document writes it (`mu_h = m_h / m`).
    pub form: &'static str,
    /// The normalized value.
    pub value: Value,
    /// How it reads in physical units.
    pub scale: Scale,
}

impl Reading {
    fn number(label: &'static str, form: &'static str, x: f64, scale: Scale) -> Self {
        Self {
            label,
            form,
            value: Value::Number(x),
            scale,
        }
    }

    /// The value in its parameter's physical unit on a device of mass `mass` (kg) and period
    /// `period` (s), when it has one.
    pub fn physical(&self, mass: f64, period: f64) -> Option<f64> {
        let Value::Number(v) = self.value else {
            return None;
        };
        match self.scale {
            Scale::None => None,
            Scale::Mass(p) => Some(v * mass / period.powi(p)),
            Scale::Period => Some(v * period),
            Scale::Pole if v > 0.0 => Some(-v.ln() / (2.0 * std::f64::consts::PI * period)),
            Scale::Pole => None,
            Scale::Frequency => Some(v / period),
        }
    }
}

/// One parameter of an element, declared once.
#[derive(Debug, Clone, Copy)]
#[non_exhaustive]
pub struct Param {
    /// The key in a scene and in the serde form, with its unit (`hand_mass_kg`).
    pub key: &'static str,
    /// The command-line flag without its dashes (`hand-mass`).
    pub flag: &'static str,
    /// The Python keyword (`hand_mass`), also the name of the field of [`PhysicalElements`].
    pub keyword: &'static str,
    /// The name in messages (`hand mass`).
    pub name: &'static str,
    /// The physical unit (`kg`; empty for a count or a choice).
    pub unit: &'static str,
    /// Its normalized form, as reports label it (`mu_h = m_h / m`).
    pub normalized: &'static str,
    /// What values are accepted (before the checks that need the device).
    pub accepts: Accepts,
    /// The element it belongs to.
    pub element: Element,
    /// One line of help.
    pub help: &'static str,
    /// Other parameters (keywords) this one needs named with it, and the message saying so.
    pub requires: Option<(&'static [&'static str], &'static str)>,
    /// Parameters (keywords) this one cannot be named with, and the message saying so.
    pub conflicts: Option<(&'static [&'static str], &'static str)>,
    get: fn(&PhysicalElements) -> Option<Value>,
    set: fn(&mut PhysicalElements, Option<Value>),
    report: fn(&Loop) -> Option<Reading>,
}

const TRANSMISSION: &str = "a compliant transmission needs both the handle mass and the coupling stiffness (its damping and the encoder side are optional)";
const ONE_FILTER: &str =
    "name one velocity filter: a low-pass cutoff or a moving average, not both";
const ENCODERS: &[&str] = &["motor", "handle"];

fn number(v: Option<Value>) -> Option<f64> {
    match v {
        Some(Value::Number(x)) => Some(x),
        _ => None,
    }
}

fn count(v: Option<Value>) -> Option<usize> {
    match v {
        Some(Value::Count(n)) => Some(n),
        _ => None,
    }
}

fn encoder(v: Option<Value>) -> Option<Encoder> {
    match v {
        Some(Value::Choice("handle")) => Some(Encoder::Handle),
        Some(Value::Choice(_)) => Some(Encoder::Motor),
        _ => None,
    }
}

fn encoder_name(e: Encoder) -> &'static str {
    match e {
        Encoder::Motor => "motor",
        Encoder::Handle => "handle",
    }
}

/// A number-valued parameter, its accessors on the field `$field` of [`PhysicalElements`].
macro_rules! number_param {
    ($field:ident, $key:literal, $flag:literal, $name:literal, $unit:literal, $norm:literal,
     $accepts:expr, $element:expr, $help:literal, $requires:expr, $conflicts:expr,
     $label:expr, $scale:expr, $on_loop:expr) => {
        Param {
            key: $key,
            flag: $flag,
            keyword: stringify!($field),
            name: $name,
            unit: $unit,
            normalized: $norm,
            accepts: $accepts,
            element: $element,
            help: $help,
            requires: $requires,
            conflicts: $conflicts,
            get: |e| e.$field.map(Value::Number),
            set: |e, v| e.$field = number(v),
            report: |lp| {
                let on_loop: fn(&Loop) -> Option<f64> = $on_loop;
                on_loop(lp).map(|x| Reading::number($label, $norm, x, $scale))
            },
        }
    };
}

/// A nonlinear parameter (a quantizer, friction): no part of the linear loop, so it has no
/// reading of it (the buzz report gives these); its label is its keyword.
macro_rules! nonlinear_param {
    ($field:ident, $key:literal, $flag:literal, $name:literal, $unit:literal, $norm:literal,
     $accepts:expr, $element:expr, $help:literal) => {
        number_param!(
            $field,
            $key,
            $flag,
            $name,
            $unit,
            $norm,
            $accepts,
            $element,
            $help,
            None,
            None,
            stringify!($field),
            Scale::None,
            |_| None
        )
    };
}

/// Every element parameter, in the order flags, keys and reports list them.
pub static PARAMS: &[Param] = &[
    number_param!(
        hand_mass,
        "hand_mass_kg",
        "hand-mass",
        "hand mass",
        "kg",
        "mu_h = m_h / m",
        Accepts::NonNegative,
        Element::Hand,
        "Operator's hand holding the handle: mass in kg (physical units only).",
        None,
        None,
        "mu_h",
        Scale::Mass(0),
        |lp| lp.hand().map(|h| h.mass_ratio())
    ),
    number_param!(
        hand_damping,
        "hand_damping_Ns_per_m",
        "hand-damping",
        "hand damping",
        "N s/m",
        "delta_h = b_h T / m",
        Accepts::NonNegative,
        Element::Hand,
        "Operator's hand: damping in N s/m.",
        None,
        None,
        "delta_h",
        Scale::Mass(1),
        |lp| lp.hand().map(|h| h.damping())
    ),
    number_param!(
        hand_stiffness,
        "hand_stiffness_N_per_m",
        "hand-stiffness",
        "hand stiffness",
        "N/m",
        "kappa_h = k_h T^2 / m",
        Accepts::NonNegative,
        Element::Hand,
        "Operator's hand: stiffness in N/m.",
        None,
        None,
        "kappa_h",
        Scale::Mass(2),
        |lp| lp.hand().map(|h| h.stiffness())
    ),
    Param {
        key: "velocity_filter_cutoff_Hz",
        flag: "velocity-filter-cutoff",
        keyword: "velocity_filter_cutoff",
        name: "velocity filter cutoff",
        unit: "Hz",
        normalized: "a = exp(-2 pi f_c T)",
        accepts: Accepts::Positive,
        element: Element::VelocityFilter,
        help: "First-order low-pass on the wall's velocity estimate: cutoff in Hz (at most Nyquist).",
        requires: None,
        conflicts: Some((&["velocity_filter_samples"], ONE_FILTER)),
        get: |e| e.velocity_filter_cutoff.map(Value::Number),
        set: |e, v| e.velocity_filter_cutoff = number(v),
        // the first-order filter by its pole, a higher order by its cutoff in cycles per
        // sample (its design's own parameter, under the label its design gives it)
        report: |lp| match lp.filter().kind() {
            FilterKind::LowPass { pole } => Some(Reading::number(
                "low_pass_pole",
                "a = exp(-2 pi f_c T)",
                pole,
                Scale::Pole,
            )),
            _ => lp
                .filter()
                .design_cutoff()
                .map(|(label, cutoff)| Reading::number(label, "f_c T", cutoff, Scale::Frequency)),
        },
    },
    Param {
        key: "velocity_filter_samples",
        flag: "velocity-filter-samples",
        keyword: "velocity_filter_samples",
        name: "velocity filter samples",
        unit: "",
        normalized: "N",
        accepts: Accepts::Count {
            min: 1,
            max: MAX_MOVING_AVERAGE,
        },
        element: Element::VelocityFilter,
        help: "Moving average of the wall's velocity estimate over this many samples.",
        requires: None,
        conflicts: Some((&["velocity_filter_cutoff"], ONE_FILTER)),
        get: |e| e.velocity_filter_samples.map(Value::Count),
        set: |e, v| e.velocity_filter_samples = count(v),
        report: |lp| match lp.filter().kind() {
            FilterKind::MovingAverage { samples } => Some(Reading {
                label: "moving_average_samples",
                form: "N",
                value: Value::Count(samples),
                scale: Scale::None,
            }),
            _ => None,
        },
    },
    Param {
        key: "velocity_filter_order",
        flag: "velocity-filter-order",
        keyword: "velocity_filter_order",
        name: "velocity filter order",
        unit: "",
        normalized: "order",
        accepts: Accepts::Count {
            min: 1,
            max: LOW_PASS_NAMES.len(),
        },
        element: Element::VelocityFilter,
        help: "Order of the low-pass on the wall's velocity estimate: 1 (default), or above it a Butterworth filter of that order by the bilinear transform prewarped at the cutoff (which must be below Nyquist).",
        requires: Some((
            &["velocity_filter_cutoff"],
            "the low-pass velocity filter's order needs its cutoff",
        )),
        conflicts: None,
        get: |e| e.velocity_filter_order.map(Value::Count),
        set: |e, v| e.velocity_filter_order = count(v),
        // the cutoff's reading names the filter's form
        report: |_| None,
    },
    number_param!(
        handle_mass,
        "handle_mass_kg",
        "handle-mass",
        "handle mass",
        "kg",
        "r = m_2 / m",
        Accepts::Positive,
        Element::Transmission,
        "Compliant transmission: the handle's mass in kg (below the device's mass; the motor side is the rest).",
        Some((&["transmission_stiffness"], TRANSMISSION)),
        None,
        "r",
        Scale::Mass(0),
        |lp| lp.transmission().map(|t| t.handle_ratio())
    ),
    number_param!(
        transmission_stiffness,
        "transmission_stiffness_N_per_m",
        "transmission-stiffness",
        "transmission stiffness",
        "N/m",
        "kappa_c = k_c T^2 / m",
        Accepts::Positive,
        Element::Transmission,
        "Compliant transmission: coupling stiffness in N/m.",
        Some((&["handle_mass"], TRANSMISSION)),
        None,
        "kappa_c",
        Scale::Mass(2),
        |lp| lp.transmission().map(|t| t.stiffness())
    ),
    number_param!(
        transmission_damping,
        "transmission_damping_Ns_per_m",
        "transmission-damping",
        "transmission damping",
        "N s/m",
        "delta_c = b_c T / m",
        Accepts::NonNegative,
        Element::Transmission,
        "Compliant transmission: coupling damping in N s/m (default 0).",
        Some((&["handle_mass"], TRANSMISSION)),
        None,
        "delta_c",
        Scale::Mass(1),
        |lp| lp.transmission().map(|t| t.damping())
    ),
    number_param!(
        motor_damping,
        "motor_damping_Ns_per_m",
        "motor-damping",
        "motor damping",
        "N s/m",
        "delta_1 = b_1 T / m",
        Accepts::NonNegative,
        Element::Transmission,
        "Compliant transmission: the motor side's share b_1 of the device's damping, in N s/m (default: all of it; the handle side takes the rest).",
        Some((&["handle_mass"], TRANSMISSION)),
        None,
        "delta_1",
        Scale::Mass(1),
        |_| None
    ),
    number_param!(
        handle_damping,
        "handle_damping_Ns_per_m",
        "handle-damping",
        "handle damping",
        "N s/m",
        "delta_2 = b_2 T / m",
        Accepts::NonNegative,
        Element::Transmission,
        "Compliant transmission: the handle side's share b_2 of the device's damping, in N s/m (default 0; the motor side takes the rest).",
        Some((&["handle_mass"], TRANSMISSION)),
        None,
        "delta_2",
        Scale::Mass(1),
        |lp| lp
            .transmission()
            .map(|t| t.handle_damping())
            .filter(|&d| d > 0.0)
    ),
    Param {
        key: "encoder",
        flag: "encoder",
        keyword: "encoder",
        name: "encoder",
        unit: "",
        normalized: "",
        accepts: Accepts::Choice(ENCODERS),
        element: Element::Transmission,
        help: "Compliant transmission: where the encoder sits (default motor).",
        requires: Some((&["handle_mass"], TRANSMISSION)),
        conflicts: None,
        get: |e| e.encoder.map(|x| Value::Choice(encoder_name(x))),
        set: |e, v| e.encoder = encoder(v),
        report: |lp| {
            lp.transmission().map(|t| Reading {
                label: "encoder",
                form: "encoder",
                value: Value::Choice(encoder_name(t.encoder())),
                scale: Scale::None,
            })
        },
    },
    number_param!(
        actuator_time_constant,
        "actuator_time_constant_s",
        "actuator-time-constant",
        "actuator time constant",
        "s",
        "tau = tau_a / T",
        Accepts::Positive,
        Element::Actuator,
        "Actuator lag (amplifier, current loop): time constant in s.",
        None,
        None,
        "tau",
        Scale::Period,
        |lp| lp.actuator().map(|a| a.tau())
    ),
    nonlinear_param!(
        encoder_resolution,
        "encoder_resolution_m",
        "encoder-resolution",
        "encoder resolution",
        "m",
        "one count",
        Accepts::Positive,
        Element::Quantizer,
        "Encoder resolution in m per count (the wall reads whole counts; adds the buzz verdict)."
    ),
    nonlinear_param!(
        force_resolution,
        "force_resolution_N",
        "force-resolution",
        "force resolution",
        "N",
        "Delta_u T^2 / (m Delta_x)",
        Accepts::Positive,
        Element::Quantizer,
        "Force output resolution (DAC step) in N (adds the buzz verdict)."
    ),
    nonlinear_param!(
        coulomb_friction,
        "coulomb_friction_N",
        "coulomb-friction",
        "coulomb friction",
        "N",
        "phi = f_c T^2 / (m Delta_x)",
        Accepts::NonNegative,
        Element::Friction,
        "Coulomb (sliding) friction in N, on the device's mass (adds the buzz verdict)."
    ),
    nonlinear_param!(
        static_friction,
        "static_friction_N",
        "static-friction",
        "static friction",
        "N",
        "f_s T^2 / (m Delta_x)",
        Accepts::NonNegative,
        Element::Friction,
        "Static (breakaway) friction in N, at least the Coulomb friction (default: equal)."
    ),
];

/// The parameter with Python keyword (and field name) `keyword`.
pub fn param(keyword: &str) -> Option<&'static Param> {
    PARAMS.iter().find(|p| p.keyword == keyword)
}

/// The parameter with scene key `key`.
pub fn by_key(key: &str) -> Option<&'static Param> {
    PARAMS.iter().find(|p| p.key == key)
}

/// The parameter a library error names (in its physical or its normalized form), for
/// front ends that report it by their own spelling (a flag, a keyword).
pub fn named_in(error: &Error) -> Option<&'static Param> {
    let Error::InvalidParameter { name, .. } = error else {
        return None;
    };
    let stem = name
        .strip_suffix(" ratio")
        .or_else(|| name.strip_suffix(" pole"))
        .map_or(*name, |s| {
            if s.ends_with("filter") {
                "velocity filter cutoff"
            } else {
                s
            }
        });
    PARAMS.iter().find(|p| p.name == stem)
}

impl Param {
    /// The value named in `e`, if any.
    pub fn get(&self, e: &PhysicalElements) -> Option<Value> {
        (self.get)(e)
    }

    /// Names (or, with `None`, un-names) this parameter in `e`; the value is not checked
    /// (see [`Param::accept`]).
    pub fn set(&self, e: &mut PhysicalElements, v: Value) {
        (self.set)(e, Some(v))
    }

    /// What a report shows of this parameter on `lp` (normalized), if `lp` models it.
    pub fn reading(&self, lp: &Loop) -> Option<Reading> {
        (self.report)(lp)
    }

    /// Leaves this parameter out of `e`.
    pub fn clear(&self, e: &mut PhysicalElements) {
        (self.set)(e, None)
    }

    /// `v` if this parameter accepts it (the checks that need no device), else an error
    /// naming the parameter and what it accepts.
    pub fn accept(&self, v: Value) -> Result<Value> {
        let bad = |value: f64, expected: String| Error::InvalidParameter {
            name: self.name,
            value,
            expected,
        };
        match (self.accepts, v) {
            (Accepts::NonNegative | Accepts::Positive, Value::Number(x)) if !x.is_finite() => {
                Err(bad(x, "must be a finite number".into()))
            }
            (Accepts::NonNegative, Value::Number(x)) if x < 0.0 => {
                Err(bad(x, format!("must be 0 or more (in {})", self.unit)))
            }
            (Accepts::Positive, Value::Number(x)) if x <= 0.0 => {
                Err(bad(x, format!("must be greater than 0 (in {})", self.unit)))
            }
            (Accepts::NonNegative | Accepts::Positive, Value::Number(_)) => Ok(v),
            (Accepts::Count { min, max }, Value::Count(n)) => {
                if (min..=max).contains(&n) {
                    Ok(v)
                } else {
                    Err(bad(
                        n as f64,
                        format!("must be a whole number, at least {min} and at most {max}"),
                    ))
                }
            }
            (Accepts::Choice(names), Value::Choice(c)) if names.contains(&c) => Ok(v),
            _ => Err(Error::InvalidRequest(format!(
                "{} takes {}",
                self.name,
                self.expects()
            ))),
        }
    }

    /// Reads this parameter's value from text (a flag's or a keyword's value) and checks it.
    pub fn parse(&self, text: &str) -> Result<Value> {
        self.accept(self.read(text)?)
    }

    /// Reads this parameter's value from text as its kind (a finite number, a whole number,
    /// one of its names) without the range check of [`Param::accept`], which
    /// [`PhysicalElements::validate`] makes.
    pub fn read(&self, text: &str) -> Result<Value> {
        let t = text.trim();
        let v = match self.accepts {
            Accepts::NonNegative | Accepts::Positive => Value::Number(t.parse().map_err(|_| {
                Error::InvalidRequest(format!("'{text}' is not a number ({})", self.name))
            })?),
            Accepts::Count { .. } => Value::Count(t.parse().map_err(|_| {
                Error::InvalidRequest(format!("'{text}' is not a whole number ({})", self.name))
            })?),
            Accepts::Choice(names) => match names.iter().find(|n| **n == t) {
                Some(n) => Value::Choice(n),
                None => {
                    return Err(Error::InvalidRequest(format!(
                        "'{text}' is not accepted: {} takes {}",
                        self.name,
                        self.expects()
                    )));
                }
            },
        };
        match v {
            Value::Number(x) if !x.is_finite() => Err(Error::InvalidRequest(format!(
                "'{text}' is not a finite number ({})",
                self.name
            ))),
            _ => Ok(v),
        }
    }

    /// Reads this parameter's value from text as [`Param::read`] does, or an interval
    /// `LO..HI` ([`read_interval`]) for a parameter that takes a number: the value forms of
    /// a set of devices. The ends' range checks are made on the set's members.
    ///
    /// ```
    /// use stabound::elements::list::{Form, param};
    ///
    /// let p = param("hand_mass").unwrap();
    /// assert_eq!(p.read_form("0.2..0.5")?, Form::Interval(0.2, 0.5));
    /// assert!(param("velocity_filter_samples").unwrap().read_form("2..4").is_err());
    /// # Ok::<(), stabound::Error>(())
    /// ```
    pub fn read_form(&self, text: &str) -> Result<Form> {
        match read_interval(text, self.name) {
            None => self.read(text).map(Form::One),
            Some(_) if !matches!(self.accepts, Accepts::NonNegative | Accepts::Positive) => {
                Err(Error::InvalidRequest(format!(
                    "'{text}': the {} takes {}, not an interval",
                    self.name,
                    self.expects()
                )))
            }
            Some(form) => form,
        }
    }

    /// What this parameter takes, in words.
    pub fn expects(&self) -> String {
        match self.accepts {
            Accepts::NonNegative => format!("a number of {} (0 or more)", self.unit),
            Accepts::Positive => format!("a number of {} (greater than 0)", self.unit),
            Accepts::Count { min, max } => format!("a whole number from {min} to {max}"),
            Accepts::Choice(names) => {
                let quoted: Vec<String> = names.iter().map(|n| format!("'{n}'")).collect();
                format!("one of {}", quoted.join(", "))
            }
        }
    }
}

/// Static (breakaway) friction `static_friction` is at least the Coulomb friction
/// `coulomb` (N; `None` is not named, and an unnamed Coulomb friction is zero): the one check
/// of the two named together, for [`PhysicalElements::validate`] and the buzz verdict's own
/// quantizers and friction.
pub(crate) fn friction_order(coulomb: Option<f64>, static_friction: Option<f64>) -> Result<()> {
    let coulomb = coulomb.unwrap_or(0.0);
    match static_friction {
        Some(s) if s < coulomb => Err(Error::InvalidParameter {
            name: "static friction",
            value: s,
            expected: format!(
                "the breakaway force must be at least the Coulomb friction {coulomb} N"
            ),
        }),
        _ => Ok(()),
    }
}

impl PhysicalElements {
    /// Checks every value named ([`Param::accept`]) and the parameters named together
    /// (each parameter's `requires` and `conflicts`).
    pub(crate) fn check_list(&self) -> Result<()> {
        for p in PARAMS {
            let Some(v) = p.get(self) else { continue };
            p.accept(v)?;
            let named = |k: &&str| param(k).is_some_and(|q| q.get(self).is_some());
            if let Some((keys, why)) = p.requires
                && !keys.iter().all(named)
            {
                return Err(Error::InvalidRequest(why.into()));
            }
            if let Some((keys, why)) = p.conflicts
                && keys.iter().any(named)
            {
                return Err(Error::InvalidRequest(why.into()));
            }
        }
        Ok(())
    }
}

#[cfg(feature = "serde")]
mod serde_form {
    //! The serde form of [`PhysicalElements`]: a map from the list's keys to values.

    use serde::de::{self, DeserializeSeed, MapAccess, Visitor};
    use serde::ser::SerializeMap;
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    use super::{Accepts, PARAMS, Param, Value, by_key};
    use crate::elements::PhysicalElements;

    impl Serialize for PhysicalElements {
        fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
            let named: Vec<(&Param, Value)> = PARAMS
                .iter()
                .filter_map(|p| p.get(self).map(|v| (p, v)))
                .collect();
            let mut map = s.serialize_map(Some(named.len()))?;
            for (p, v) in named {
                match v {
                    Value::Number(x) => map.serialize_entry(p.key, &x)?,
                    Value::Count(n) => map.serialize_entry(p.key, &n)?,
                    Value::Choice(c) => map.serialize_entry(p.key, c)?,
                }
            }
            map.end()
        }
    }

    /// A key of [`PhysicalElements`]' serde form: read as an identifier, so that an unknown
    /// key is refused where it is written.
    pub(crate) struct ElementKey(pub(crate) &'static Param);

    impl<'de> Deserialize<'de> for ElementKey {
        fn deserialize<D: Deserializer<'de>>(de: D) -> Result<Self, D::Error> {
            let key = String::deserialize(de)?;
            by_key(&key)
                .map(ElementKey)
                .ok_or_else(|| de::Error::unknown_field(&key, keys()))
        }
    }

    /// Reads one parameter's value, checked by the list, where it is written (so that
    /// errors point at the value).
    pub(crate) struct ParamSeed(pub(crate) &'static Param);

    impl<'de> DeserializeSeed<'de> for ParamSeed {
        type Value = Value;
        fn deserialize<D: Deserializer<'de>>(self, de: D) -> Result<Value, D::Error> {
            let p = self.0;
            let v = match p.accepts {
                Accepts::NonNegative | Accepts::Positive => {
                    let x = f64::deserialize(de)?;
                    if !x.is_finite() {
                        return Err(de::Error::custom(format_args!(
                            "{x} is not a finite number"
                        )));
                    }
                    Value::Number(x)
                }
                Accepts::Count { .. } => Value::Count(usize::deserialize(de)?),
                Accepts::Choice(names) => {
                    let s = String::deserialize(de)?;
                    match names.iter().find(|n| **n == s) {
                        Some(n) => Value::Choice(n),
                        None => return Err(de::Error::unknown_variant(&s, names)),
                    }
                }
            };
            p.accept(v).map_err(|err| match (err, v) {
                (crate::Error::InvalidParameter { expected, .. }, Value::Number(x)) => {
                    de::Error::custom(format_args!("{x} is not accepted: {expected}"))
                }
                (err, _) => de::Error::custom(err),
            })
        }
    }

    /// Reads the value of `p` from `map` into `e`; a key named twice is an error.
    pub(crate) fn read_entry<'de, A: MapAccess<'de>>(
        p: &'static Param,
        map: &mut A,
        e: &mut PhysicalElements,
    ) -> Result<(), A::Error> {
        if p.get(e).is_some() {
            return Err(de::Error::custom(format_args!(
                "duplicate field `{}`",
                p.key
            )));
        }
        let v = map.next_value_seed(ParamSeed(p))?;
        p.set(e, v);
        Ok(())
    }

    /// Every element key, for messages naming the keys accepted.
    pub(crate) fn keys() -> &'static [&'static str] {
        static KEYS: std::sync::LazyLock<Vec<&'static str>> =
            std::sync::LazyLock::new(|| PARAMS.iter().map(|p| p.key).collect());
        KEYS.as_slice()
    }

    impl<'de> Deserialize<'de> for PhysicalElements {
        fn deserialize<D: Deserializer<'de>>(de: D) -> Result<Self, D::Error> {
            struct Elements;
            impl<'de> Visitor<'de> for Elements {
                type Value = PhysicalElements;
                fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                    f.write_str("a map of loop element keys (with their units) to values")
                }
                fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Self::Value, A::Error> {
                    let mut e = PhysicalElements::default();
                    while let Some(ElementKey(p)) = map.next_key()? {
                        read_entry(p, &mut map, &mut e)?;
                    }
                    e.validate().map_err(de::Error::custom)?;
                    Ok(e)
                }
            }
            de.deserialize_map(Elements)
        }
    }
}

#[cfg(feature = "serde")]
pub(crate) use serde_form::{keys, read_entry};
