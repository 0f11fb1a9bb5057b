//! What a front end asks for, resolved and checked once, before any computation: the
//! damping limits of an `alpha_max` search (normalized, or as wall dampings in N s/m on a
//! device), a stiffness margin, and the loop elements of the element list
//! ([`crate::elements::list`]).
//!
//! The command line and the Python binding are adapters: they read their own syntax (flags,
//! keywords, arrays) into the types here and report a [`RequestError`] with their own
//! spelling of each [`Input`] ([`RequestError::message`]); the library's messages name no
//! flag and no keyword. Its `Display` spells inputs by their keyword.
//!
//! ```
//! use stabound::request::{DampingLimits, Input, RequestError};
//!
//! // 60 N s/m on a 0.1 kg device sampled at 1 kHz is beta = 60 * 1e-3 / 0.1 = 0.6
//! let limits = DampingLimits { wall_damping_min: Some(60.0), ..Default::default() };
//! let (lo, hi) = limits.resolve(Some((0.1, 1e-3)))?;
//! assert!((lo.unwrap() - 0.6).abs() < 1e-15 && hi.is_none());
//!
//! // without a device the wall damping cannot be converted
//! let err = limits.resolve(None).unwrap_err();
//! let stabound::Error::Request(r) = &err else { panic!("{err}") };
//! let flag = |i: Input| format!("--{}", i.keyword().replace('_', "-"));
//! assert!(r.message(&flag).starts_with("--wall-damping-min is a wall damping in N s/m"));
//! # Ok::<(), stabound::Error>(())
//! ```

use std::fmt;

use crate::amax::AmaxOptions;
use crate::elements::PhysicalElements;
use crate::elements::list::{Element, PARAMS};
use crate::error::{Error, Result};
use crate::filter::VelocityFilter;

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
        }
    }
}

impl fmt::Display for RequestError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message(&|i| i.keyword().to_string()))
    }
}

impl From<RequestError> for Error {
    fn from(e: RequestError) -> Self {
        Error::Request(e)
    }
}

/// The damping limits of an `alpha_max` search as given: each end normalized (`beta_min`)
/// or as a wall damping in N s/m (`wall_damping_min`), not both; the wall dampings need the
/// device's mass and period (`beta = B T / m`). Two ends in two forms: it will not grow.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct DampingLimits {
    /// The normalized lower limit.
    pub beta_min: Option<f64>,
    /// The normalized upper limit.
    pub beta_max: Option<f64>,
    /// The lower limit as a wall damping, N s/m.
    pub wall_damping_min: Option<f64>,
    /// The upper limit as a wall damping, N s/m.
    pub wall_damping_max: Option<f64>,
}

impl DampingLimits {
    /// The normalized limits `(beta_min, beta_max)`; `device` is `(mass, period)` when the
    /// device is given in physical units. A wall damping converts as `B * T / m` (these
    /// operations in this order, so that every front end gives the same bits).
    ///
    /// ```
    /// use stabound::request::DampingLimits;
    ///
    /// let both = DampingLimits { beta_min: Some(0.0), wall_damping_min: Some(0.0), ..Default::default() };
    /// assert!(both.resolve(Some((1.0, 1e-3))).is_err());
    /// let hi = DampingLimits { wall_damping_max: Some(30.0), ..Default::default() };
    /// assert_eq!(hi.resolve(Some((1.0, 1e-3)))?, (None, Some(30.0 * 1e-3 / 1.0)));
    /// # Ok::<(), stabound::Error>(())
    /// ```
    pub fn resolve(&self, device: Option<(f64, f64)>) -> Result<(Option<f64>, Option<f64>)> {
        let end = |beta: Option<f64>, wall: Option<f64>, normalized: Input, physical: Input| match (
            beta, wall, device,
        ) {
            (Some(_), Some(_), _) => Err(RequestError::Twice {
                normalized,
                physical,
            }
            .into()),
            (beta, None, _) => Ok(beta),
            (None, Some(b), Some((mass, period))) => Ok(Some(b * period / mass)),
            (None, Some(_), None) => Err(Error::from(RequestError::NeedsDevice {
                input: physical,
                normalized,
            })),
        };
        Ok((
            end(
                self.beta_min,
                self.wall_damping_min,
                Input::BetaMin,
                Input::WallDampingMin,
            )?,
            end(
                self.beta_max,
                self.wall_damping_max,
                Input::BetaMax,
                Input::WallDampingMax,
            )?,
        ))
    }

    /// The options of an `alpha_max` search with these limits and the refinement tolerance
    /// `theta_tol` (checked by [`AmaxOptions::new`]).
    ///
    /// ```
    /// use stabound::request::DampingLimits;
    ///
    /// let lo = DampingLimits { beta_min: Some(0.0), ..Default::default() };
    /// let opts = lo.options(stabound::amax::DEFAULT_THETA_TOL, None)?;
    /// assert_eq!((opts.beta_min(), opts.beta_max()), (Some(0.0), None));
    /// # Ok::<(), stabound::Error>(())
    /// ```
    pub fn options(&self, theta_tol: f64, device: Option<(f64, f64)>) -> Result<AmaxOptions> {
        let (lo, hi) = self.resolve(device)?;
        AmaxOptions::new(theta_tol)?.with_beta_limits(lo, hi)
    }
}

/// A stiffness margin `F`, the fraction of `alpha_max` a wall is given: in `(0, 1]`.
///
/// ```
/// use stabound::request::margin;
///
/// assert_eq!(margin(0.75)?, 0.75);
/// assert!(margin(0.0).is_err() && margin(1.5).is_err() && margin(f64::NAN).is_err());
/// # Ok::<(), stabound::Error>(())
/// ```
pub fn margin(fraction: f64) -> Result<f64> {
    if fraction > 0.0 && fraction <= 1.0 {
        Ok(fraction)
    } else {
        Err(RequestError::Refused {
            input: Input::Margin,
            value: fraction,
            expected: "must be a fraction in (0, 1], e.g. 0.75",
        }
        .into())
    }
}

/// The velocity filter of a computation that models a filter and no other element (the
/// passivity bound and its comparison with the stable region): a normalized low-pass `pole`,
/// or the filter parameters of the element list named in `named`, a cutoff converted on the
/// sampling period `period` (s); none is `F = 1`.
///
/// ```
/// use stabound::elements::PhysicalElements;
/// use stabound::filter::FilterKind;
/// use stabound::request::velocity_filter;
///
/// let mut named = PhysicalElements::default();
/// named.velocity_filter_samples = Some(3);
/// let f = velocity_filter(&named, None, None)?;
/// assert_eq!(f.kind(), FilterKind::MovingAverage { samples: 3 });
/// named.hand_mass = Some(0.1);
/// assert!(velocity_filter(&named, None, None).is_err());
/// # Ok::<(), stabound::Error>(())
/// ```
pub fn velocity_filter(
    named: &PhysicalElements,
    pole: Option<f64>,
    period: Option<f64>,
) -> Result<VelocityFilter> {
    named.validate()?;
    if let Some(p) = PARAMS
        .iter()
        .find(|p| p.element != Element::VelocityFilter && p.get(named).is_some())
    {
        return Err(RequestError::NotModelled {
            input: Input::Element(p.keyword),
            models: "a velocity filter",
        }
        .into());
    }
    let Some(a) = pole else {
        return named.velocity_filter(period);
    };
    let filters: Vec<Input> = Element::VelocityFilter
        .params()
        .filter(|p| p.get(named).is_some())
        .map(|p| Input::Element(p.keyword))
        .collect();
    if !filters.is_empty() {
        return Err(RequestError::OneOf {
            what: "velocity filter",
            inputs: [vec![Input::FilterPole], filters].concat(),
        }
        .into());
    }
    VelocityFilter::low_pass(a)
}
