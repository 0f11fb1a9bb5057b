//! The inputs a front end takes, by the library's names for them ([`Input`]), and the
//! refusals of a request that name them ([`RequestError`], with what a computation
//! [`Takes`] and a plane's [`PlaneFault`]), which the crate's error carries:
//! below the request layer ([`crate::request`]) that re-exports them, so that the error type
//! imports nothing above it.

use std::fmt;

/// One input a front end takes, by the library's name for it; each front end spells it its
/// own way (`--wall-damping-min`, `wall_damping_min=`) from [`Input::keyword`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum Input {
    /// The normalized lower damping limit `beta_min`.
    BetaMin,
    /// The normalized upper damping limit `beta_max`.
    BetaMax,
    /// The lower damping limit as a wall damping in N s/m.
    WallDampingMin,
    /// The upper damping limit as a wall damping in N s/m.
    WallDampingMax,
    /// The device's mass in kg.
    Mass,
    /// The sampling period in s.
    Period,
    /// The stiffness margin, a fraction of `alpha_max`.
    Margin,
    /// The refinement tolerance of an `alpha_max` search.
    ThetaTol,
    /// A first-order low-pass velocity filter's pole `a`, normalized.
    FilterPole,
    /// A parameter of the element list, by its keyword.
    Element(&'static str),
    /// The normalized virtual stiffness `alpha`.
    Alpha,
    /// The normalized virtual damping `beta`.
    Beta,
    /// The normalized physical damping `delta`.
    Delta,
    /// The delay factor `d`.
    D,
    /// The device's physical damping in N s/m.
    Damping,
    /// The delay in s.
    Delay,
    /// The delay in sampling periods.
    DelaySamples,
    /// The wall stiffness in N/m.
    Stiffness,
    /// The wall damping in N s/m.
    WallDamping,
}

impl Input {
    /// The input's keyword (`wall_damping_min`): the Python keyword, and the command-line
    /// flag with dashes for underscores.
    pub fn keyword(self) -> &'static str {
        match self {
            Input::BetaMin => "beta_min",
            Input::BetaMax => "beta_max",
            Input::WallDampingMin => "wall_damping_min",
            Input::WallDampingMax => "wall_damping_max",
            Input::Mass => "mass",
            Input::Period => "period",
            Input::Margin => "margin",
            Input::ThetaTol => "theta_tol",
            Input::FilterPole => "filter_pole",
            Input::Element(k) => k,
            Input::Alpha => "alpha",
            Input::Beta => "beta",
            Input::Delta => "delta",
            Input::D => "d",
            Input::Damping => "damping",
            Input::Delay => "delay",
            Input::DelaySamples => "delay_samples",
            Input::Stiffness => "stiffness",
            Input::WallDamping => "wall_damping",
        }
    }
}

/// A request refused as a whole (inputs given together that cannot be, one missing that
/// another needs) or one input's value refused; [`RequestError::message`] words it with a
/// front end's spelling of the inputs.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum RequestError {
    /// One quantity given in both its forms.
    Twice {
        /// The normalized form.
        normalized: Input,
        /// The physical form.
        physical: Input,
    },
    /// A physical quantity given without the device that converts it.
    NeedsDevice {
        /// The physical input.
        input: Input,
        /// Its normalized form, which needs no device.
        normalized: Input,
    },
    /// A physical input given without the sampling period that converts it.
    NeedsPeriod {
        /// The physical input.
        input: Input,
    },
    /// More than one of inputs of which one is taken.
    OneOf {
        /// What they name.
        what: &'static str,
        /// The inputs, all of which were given.
        inputs: Vec<Input>,
    },
    /// An input of an element the request does not model.
    NotModelled {
        /// The input.
        input: Input,
        /// What the request models.
        models: &'static str,
    },
    /// Two inputs of which one is taken (the delay in s and in sampling periods).
    Either {
        /// The first.
        first: Input,
        /// The second.
        second: Input,
        /// What they give.
        what: &'static str,
    },
    /// Inputs of the normalized form and of the physical form given together.
    Mixed {
        /// The normalized inputs given.
        normalized: Vec<Input>,
        /// The physical inputs given (the delay as its two spellings).
        physical: Vec<&'static [Input]>,
    },
    /// Inputs of the form given are missing (each entry: one input, or alternatives such as
    /// the delay in s or in samples).
    Missing {
        /// The inputs missing.
        missing: Vec<&'static [Input]>,
        /// The form the request was given in (physical when any physical input was given).
        physical: bool,
        /// What the computation takes.
        takes: Takes,
    },
    /// Inputs that only the physical form has (loop elements, intervals) given with the
    /// normalized form.
    NeedsPhysical {
        /// What was given (`loop elements`).
        what: &'static str,
        /// What the computation takes.
        takes: Takes,
    },
    /// Physical inputs given without the device's mass and period that convert them.
    Unconverted {
        /// The physical inputs given.
        inputs: Vec<Input>,
    },
    /// Inputs the (delta, beta) plane refuses or lacks ([`crate::request::DeviceInputs::delta_beta_plane`]).
    DeltaBeta {
        /// What is wrong with them.
        why: PlaneFault,
        /// The inputs concerned.
        inputs: Vec<Input>,
    },
    /// A value out of its accepted range.
    Refused {
        /// The input.
        input: Input,
        /// The value given.
        value: f64,
        /// What is accepted.
        expected: &'static str,
    },
}

impl RequestError {
    /// The message, each input spelled by `spell` (a flag, a keyword).
    pub fn message(&self, spell: &dyn Fn(Input) -> String) -> String {
        match *self {
            RequestError::NeedsPeriod { input } => format!(
                "{} needs {} (the sampling period in s)",
                spell(input),
                spell(Input::Period)
            ),
            RequestError::OneOf { what, ref inputs } => {
                let names: Vec<String> = inputs.iter().map(|&i| spell(i)).collect();
                format!("name one {what}: {}, not more", names.join(" or "))
            }
            RequestError::NotModelled { input, models } => format!(
                "{} is not modelled here: this computation models {models} only",
                spell(input)
            ),
            RequestError::Twice {
                normalized,
                physical,
            } => format!(
                "give {} or {}, not both (they are the same limit)",
                spell(normalized),
                spell(physical)
            ),
            RequestError::NeedsDevice { input, normalized } => format!(
                "{} is a wall damping in N s/m and needs the device in physical units (its {} and {} convert it): give the device so, or the normalized {}",
                spell(input),
                spell(Input::Mass),
                spell(Input::Period),
                spell(normalized)
            ),
            RequestError::Refused {
                input,
                value,
                expected,
            } => format!("invalid {} {value}: {expected}", spell(input)),
            RequestError::Unconverted { ref inputs } => {
                let one = inputs.len() == 1;
                let names: Vec<String> = inputs.iter().map(|&i| spell(i)).collect();
                format!(
                    "{} {} in physical units and need{} the device: give {} and {}, or the normalized {}, {}, {}",
                    names.join(", "),
                    if one { "is" } else { "are" },
                    if one { "s" } else { "" },
                    spell(Input::Mass),
                    spell(Input::Period),
                    spell(Input::Delta),
                    spell(Input::Alpha),
                    spell(Input::Beta)
                )
            }
            RequestError::Either {
                first,
                second,
                what,
            } => format!(
                "give {} or {}, not both ({what})",
                spell(first),
                spell(second)
            ),
            RequestError::Mixed {
                ref normalized,
                ref physical,
            } => {
                let n: Vec<&[Input]> = normalized.iter().map(std::slice::from_ref).collect();
                format!(
                    "{} (normalized) and {} (physical units) were both given: give one kind, not both",
                    listed(&n, spell),
                    listed(physical, spell)
                )
            }
            RequestError::Missing {
                ref missing,
                physical,
                takes,
            } => {
                let (phys, what) = (listed(takes.physical(), spell), takes.what());
                let hint = if physical {
                    format!("{what} in physical units needs {phys}")
                } else {
                    format!(
                        "give {}, or {what} in physical units ({phys})",
                        listed(takes.normalized(), spell)
                    )
                };
                format!("missing {}: {hint}", listed(missing, spell))
            }
            RequestError::DeltaBeta { why, ref inputs } => {
                let each: Vec<&[Input]> = inputs.iter().map(std::slice::from_ref).collect();
                let (names, one) = (listed(&each, spell), inputs.len() == 1);
                let (m, t) = (spell(Input::Mass), spell(Input::Period));
                match why {
                    PlaneFault::NotTaken => format!(
                        "{names} {} not taken in the delta-beta plane: its axes stay normalized ({} gives the range of delta, {} and {} the curves); physical damping and delays are for the alpha-beta plane, and the loop elements need only {m} and {t}",
                        if one { "is" } else { "are" },
                        spell(Input::Delta),
                        spell(Input::Alpha),
                        spell(Input::D)
                    ),
                    PlaneFault::Missing => format!(
                        "missing {names}: the delta-beta plane draws one curve per stiffness {} and delay factor {}",
                        spell(Input::Alpha),
                        spell(Input::D)
                    ),
                    PlaneFault::Range => format!(
                        "in the delta-beta plane {names} gives the axis range: at least two different values, e.g. 0 and 1"
                    ),
                    PlaneFault::OneDevice => format!(
                        "with loop elements {names} {} one number (one device)",
                        if one { "is" } else { "are" }
                    ),
                    PlaneFault::DeviceWithoutElements => format!(
                        "{names} in the delta-beta plane {} the device of the loop elements, taken only with loop elements: name an element too, or leave {} out",
                        if one { "is" } else { "are" },
                        if one { "it" } else { "them" }
                    ),
                    PlaneFault::ElementsWithoutDevice => format!(
                        "missing {names}: loop elements are given in physical units; give the device's {m} and {t} (the delta-beta plane's axes stay normalized)"
                    ),
                }
            }
            RequestError::NeedsPhysical { what, takes } => format!(
                "{what} are given in physical units: give {} with {}",
                takes.what(),
                listed(takes.physical(), spell)
            ),
        }
    }
}

/// `a, b and c|d`: inputs in a message, alternatives joined by `|`.
fn listed(inputs: &[&[Input]], spell: &dyn Fn(Input) -> String) -> String {
    let names: Vec<String> = inputs
        .iter()
        .map(|alt| alt.iter().map(|&i| spell(i)).collect::<Vec<_>>().join("|"))
        .collect();
    match names.as_slice() {
        [] => String::new(),
        [one] => one.clone(),
        [init @ .., last] => format!("{} and {last}", init.join(", ")),
    }
}

impl fmt::Display for RequestError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message(&|i| i.keyword().to_string()))
    }
}

/// What a computation takes of the loop: the plant (a device; `alpha_max`, tables,
/// boundaries) or walls on it (point tests).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Takes {
    /// The device: `delta` and `d`, or mass, period, damping and delay.
    Plants,
    /// Walls on the device: `alpha`, `beta`, `delta` and `d`, or the device with the wall's
    /// stiffness and damping.
    Walls,
}

const NORMALIZED_PLANT: [&[Input]; 2] = [&[Input::Delta], &[Input::D]];
const NORMALIZED_WALL: [&[Input]; 4] = [
    &[Input::Alpha],
    &[Input::Beta],
    &[Input::Delta],
    &[Input::D],
];
const PHYSICAL_PLANT: [&[Input]; 4] = [
    &[Input::Mass],
    &[Input::Period],
    &[Input::Damping],
    &[Input::Delay, Input::DelaySamples],
];
const PHYSICAL_WALL: [&[Input]; 6] = [
    &[Input::Mass],
    &[Input::Period],
    &[Input::Damping],
    &[Input::Delay, Input::DelaySamples],
    &[Input::Stiffness],
    &[Input::WallDamping],
];

impl Takes {
    /// The inputs of the normalized form.
    pub fn normalized(self) -> &'static [&'static [Input]] {
        match self {
            Takes::Plants => &NORMALIZED_PLANT,
            Takes::Walls => &NORMALIZED_WALL,
        }
    }

    /// The inputs of the physical form (the delay in s or in samples).
    pub fn physical(self) -> &'static [&'static [Input]] {
        match self {
            Takes::Plants => &PHYSICAL_PLANT,
            Takes::Walls => &PHYSICAL_WALL,
        }
    }

    fn what(self) -> &'static str {
        match self {
            Takes::Plants => "the device",
            Takes::Walls => "the wall",
        }
    }
}

/// What is wrong with the inputs of a (delta, beta) plane ([`RequestError::DeltaBeta`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum PlaneFault {
    /// Physical inputs of the plant (damping, delay) the plane's normalized axes do not take.
    NotTaken,
    /// The stiffnesses or delay factors of the curves are missing.
    Missing,
    /// The range of `delta` is not two different values.
    Range,
    /// The device of the loop elements is given as several values.
    OneDevice,
    /// A device given without loop elements (the axes stay normalized).
    DeviceWithoutElements,
    /// Loop elements given without the device's mass or period.
    ElementsWithoutDevice,
}
