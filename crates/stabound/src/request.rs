//! What a front end asks for, resolved and checked once, before any computation: the
//! device (and walls) in normalized or physical form ([`DeviceInputs`]), a set of devices
//! ([`device_set`]), the
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

pub use crate::inputs::{Input, PlaneFault, RequestError, Takes};

use crate::amax::AmaxOptions;
use crate::elements::PhysicalElements;
use crate::elements::list::{Element, PARAMS};
use crate::error::{Error, Result};
use crate::filter::VelocityFilter;
use crate::params::{Delay, Device, Normalized, Plant};
use crate::robust::{DeviceSet, Quantity, Spread};

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
        return match period {
            Some(t) => named.velocity_filter(t),
            // the period converts a cutoff only: a moving average (or none) is the same on any
            None if named.velocity_filter_cutoff.is_none() => named.velocity_filter(1.0),
            None => Err(RequestError::NeedsPeriod {
                input: Input::Element("velocity_filter_cutoff"),
            }
            .into()),
        };
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

/// The device (and, for point tests, the wall) as a user gives it: each input present or
/// not, in the normalized form (`delta`, `d`; `alpha`, `beta`) or the physical one (mass,
/// period, damping, the delay in s or in samples; the wall's stiffness and damping). `T` is
/// the front end's value (a number, a list, an array, an interval): [`DeviceInputs::resolve`]
/// decides the form and refuses a request that mixes the forms or lacks an input, the
/// values untouched; [`Given::plant`], [`Given::device`] and [`Given::normalized`] then
/// validate one device's numbers.
///
/// ```
/// use stabound::request::{DeviceInputs, Given, Takes};
///
/// let given = DeviceInputs { mass: Some(0.1), period: Some(1e-3), damping: Some(0.0),
///                            delay_samples: Some(1.0), ..Default::default() };
/// let g = given.resolve(Takes::Plants)?;
/// assert!(matches!(g, Given::Physical { in_samples: true, .. }));
/// assert_eq!(g.plant()?.d(), 1.0);
///
/// // mixing the forms, or missing an input, is refused naming the inputs
/// let mixed = DeviceInputs { delta: Some(0.0), ..given };
/// assert!(mixed.resolve(Takes::Plants).unwrap_err().to_string().starts_with("delta (normalized) and mass"));
/// let lacking = DeviceInputs { period: None, ..given };
/// assert!(lacking.resolve(Takes::Plants).unwrap_err().to_string().starts_with("missing period:"));
/// # Ok::<(), stabound::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DeviceInputs<T> {
    /// The normalized virtual stiffness (walls only).
    pub alpha: Option<T>,
    /// The normalized virtual damping (walls only).
    pub beta: Option<T>,
    /// The normalized physical damping.
    pub delta: Option<T>,
    /// The delay factor.
    pub d: Option<T>,
    /// The mass in kg.
    pub mass: Option<T>,
    /// The sampling period in s.
    pub period: Option<T>,
    /// The physical damping in N s/m.
    pub damping: Option<T>,
    /// The delay in s.
    pub delay: Option<T>,
    /// The delay in sampling periods.
    pub delay_samples: Option<T>,
    /// The wall stiffness in N/m (walls only).
    pub stiffness: Option<T>,
    /// The wall damping in N s/m (walls only).
    pub wall_damping: Option<T>,
}

/// The device (and wall) in the form given, every input of that form present.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Given<T> {
    /// Normalized.
    Normalized {
        /// `delta`.
        delta: T,
        /// `d`.
        d: T,
        /// `(alpha, beta)` of a computation that takes walls.
        wall: Option<(T, T)>,
    },
    /// In physical units.
    Physical {
        /// kg.
        mass: T,
        /// s.
        period: T,
        /// N s/m.
        damping: T,
        /// s, or sampling periods when `in_samples`.
        delay: T,
        /// Whether the delay is in sampling periods.
        in_samples: bool,
        /// `(stiffness, wall_damping)` (N/m, N s/m) of a computation that takes walls.
        wall: Option<(T, T)>,
    },
}

impl<T> Default for DeviceInputs<T> {
    /// No input given.
    fn default() -> Self {
        Self {
            alpha: None,
            beta: None,
            delta: None,
            d: None,
            mass: None,
            period: None,
            damping: None,
            delay: None,
            delay_samples: None,
            stiffness: None,
            wall_damping: None,
        }
    }
}

impl<T> DeviceInputs<T> {
    /// The form the inputs were given in (module documentation of [`DeviceInputs`]).
    ///
    /// # Errors
    ///
    /// [`RequestError::Either`] for a delay in s and in samples, [`RequestError::Mixed`] for
    /// inputs of both forms, [`RequestError::Missing`] for an input of the form given
    /// missing (none given: the normalized form's).
    pub fn resolve(self, takes: Takes) -> Result<Given<T>> {
        self.resolve_as(takes, false)
    }

    /// [`DeviceInputs::resolve`] of a request that is in physical units whatever was given
    /// (it names loop elements, which are physical): a missing input is one of the
    /// physical form's.
    ///
    /// ```
    /// use stabound::request::{DeviceInputs, Takes};
    ///
    /// let none = DeviceInputs::<f64>::default();
    /// let e = none.resolve_physical(Takes::Plants).unwrap_err().to_string();
    /// assert!(e.starts_with("missing mass, period, damping and delay|delay_samples:"), "{e}");
    /// ```
    ///
    /// # Errors
    ///
    /// As [`DeviceInputs::resolve`].
    pub fn resolve_physical(self, takes: Takes) -> Result<Given<T>> {
        self.resolve_as(takes, true)
    }

    fn resolve_as(self, takes: Takes, physical_only: bool) -> Result<Given<T>> {
        let walls = takes == Takes::Walls;
        if self.delay.is_some() && self.delay_samples.is_some() {
            return Err(RequestError::Either {
                first: Input::Delay,
                second: Input::DelaySamples,
                what: "one delay, in s or in sampling periods",
            }
            .into());
        }
        let normalized: Vec<Input> = [
            (Input::Alpha, walls && self.alpha.is_some()),
            (Input::Beta, walls && self.beta.is_some()),
            (Input::Delta, self.delta.is_some()),
            (Input::D, self.d.is_some()),
        ]
        .into_iter()
        .filter_map(|(i, g)| g.then_some(i))
        .collect();
        let physical: Vec<Input> = [
            (Input::Mass, self.mass.is_some()),
            (Input::Period, self.period.is_some()),
            (Input::Damping, self.damping.is_some()),
            (Input::Delay, self.delay.is_some()),
            (Input::DelaySamples, self.delay_samples.is_some()),
            (Input::Stiffness, walls && self.stiffness.is_some()),
            (Input::WallDamping, walls && self.wall_damping.is_some()),
        ]
        .into_iter()
        .filter_map(|(i, g)| g.then_some(i))
        .collect();
        if !normalized.is_empty() && !physical.is_empty() {
            let given = takes
                .physical()
                .iter()
                .copied()
                .filter(|alt| alt.iter().any(|i| physical.contains(i)))
                .collect();
            return Err(RequestError::Mixed {
                normalized,
                physical: given,
            }
            .into());
        }
        let is_physical = physical_only || !physical.is_empty();
        let missing = |given: &[Input]| -> Vec<&'static [Input]> {
            let form = if is_physical {
                takes.physical()
            } else {
                takes.normalized()
            };
            form.iter()
                .copied()
                .filter(|alt| !alt.iter().any(|i| given.contains(i)))
                .collect()
        };
        let lacking = missing(if is_physical { &physical } else { &normalized });
        let wall = |a: Option<T>, b: Option<T>| a.zip(b);
        let given = if is_physical {
            let in_samples = self.delay_samples.is_some();
            match (
                self.mass,
                self.period,
                self.damping,
                self.delay.or(self.delay_samples),
            ) {
                (Some(mass), Some(period), Some(damping), Some(delay)) if lacking.is_empty() => {
                    Some(Given::Physical {
                        mass,
                        period,
                        damping,
                        delay,
                        in_samples,
                        wall: walls
                            .then(|| wall(self.stiffness, self.wall_damping))
                            .flatten(),
                    })
                }
                _ => None,
            }
        } else {
            match (self.delta, self.d) {
                (Some(delta), Some(d)) if lacking.is_empty() => Some(Given::Normalized {
                    delta,
                    d,
                    wall: walls.then(|| wall(self.alpha, self.beta)).flatten(),
                }),
                _ => None,
            }
        };
        given.ok_or_else(|| {
            RequestError::Missing {
                missing: lacking,
                physical: is_physical,
                takes,
            }
            .into()
        })
    }
}

/// The device's parts as a computation that takes them one by one reads them (the passivity
/// bound: `delta` or `alpha` on an axis, `beta` optional), each normalized or converted from
/// its physical input ([`DeviceInputs::resolve_parts`]).
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct Parts {
    /// `delta`, given or converted from the damping (`b T / m`).
    pub delta: Option<f64>,
    /// The delay factor `d`, given, in sampling periods, or converted from s (`0` when none
    /// is given).
    pub d: f64,
    /// `alpha`, given or converted from the wall stiffness (`K T^2 / m`).
    pub alpha: Option<f64>,
    /// `beta`, given or converted from the wall damping (`B T / m`).
    pub beta: Option<f64>,
    /// The device's mass (kg) and period (s) when both are given, validated.
    pub device: Option<(f64, f64)>,
}

impl DeviceInputs<f64> {
    /// The parts of a request that takes the device's parts one by one ([`Parts`]): each of
    /// `delta`, `alpha`, `beta` and `d` in its normalized form or its physical one, not both;
    /// a delay in s needs only the period, the damping and the wall's stiffness and damping
    /// need the device's mass and period (converted as [`Device::plant`] and
    /// [`Device::normalize`]).
    ///
    /// ```
    /// use stabound::request::DeviceInputs;
    ///
    /// // b = 200 N s/m on 0.1 kg at 1 ms is delta = 2; 1 ms of delay is d = 1
    /// let given = DeviceInputs { damping: Some(200.0), mass: Some(0.1), period: Some(1e-3),
    ///                            delay: Some(1e-3), ..Default::default() };
    /// let parts = given.resolve_parts()?;
    /// assert_eq!((parts.delta, parts.d, parts.device), (Some(2.0), 1.0, Some((0.1, 1e-3))));
    /// let bare = DeviceInputs { damping: Some(200.0), ..Default::default() };
    /// let e = bare.resolve_parts().unwrap_err().to_string();
    /// assert!(e.starts_with("damping is in physical units and needs the device"), "{e}");
    /// # Ok::<(), stabound::Error>(())
    /// ```
    ///
    /// # Errors
    ///
    /// [`RequestError::Either`] for one part given in two forms, [`RequestError::NeedsPeriod`]
    /// for a delay in s or a mass without the period, [`RequestError::Unconverted`] for a
    /// physical part without the device; a value out of range as [`Device::new`] says.
    pub fn resolve_parts(&self) -> Result<Parts> {
        let given = |x: Option<f64>| x.is_some();
        for (first, a, second, b) in [
            (Input::Delta, self.delta, Input::Damping, self.damping),
            (Input::Alpha, self.alpha, Input::Stiffness, self.stiffness),
            (
                Input::Beta,
                self.beta,
                Input::WallDamping,
                self.wall_damping,
            ),
            (Input::D, self.d, Input::DelaySamples, self.delay_samples),
            (Input::D, self.d, Input::Delay, self.delay),
            (
                Input::DelaySamples,
                self.delay_samples,
                Input::Delay,
                self.delay,
            ),
        ] {
            if given(a) && given(b) {
                return Err(RequestError::Either {
                    first,
                    second,
                    what: "they are the same parameter",
                }
                .into());
            }
        }
        let d = match (self.d.or(self.delay_samples), self.delay, self.period) {
            (Some(d), _, _) => d,
            (None, None, _) => 0.0,
            // d = delay / T does not depend on the mass: any valid one will do
            (None, Some(s), Some(t)) => Device::new(1.0, t, 0.0, Delay::Seconds(s))?.plant()?.d(),
            (None, Some(_), None) => {
                return Err(RequestError::NeedsPeriod {
                    input: Input::Delay,
                }
                .into());
            }
        };
        let mut parts = Parts {
            delta: self.delta,
            d,
            alpha: self.alpha,
            beta: self.beta,
            device: None,
        };
        // a delay in s needs only the period; the others need the whole device
        if given(self.damping) || given(self.stiffness) || given(self.wall_damping) {
            let (Some(m), Some(t)) = (self.mass, self.period) else {
                let inputs = [
                    (Input::Damping, self.damping),
                    (Input::Delay, self.delay),
                    (Input::Stiffness, self.stiffness),
                    (Input::WallDamping, self.wall_damping),
                ]
                .into_iter()
                .filter_map(|(i, v)| v.map(|_| i))
                .collect();
                return Err(RequestError::Unconverted { inputs }.into());
            };
            let p = Device::new(m, t, self.damping.unwrap_or(0.0), Delay::Samples(0.0))?
                .normalize(
                    self.stiffness.unwrap_or(0.0),
                    self.wall_damping.unwrap_or(0.0),
                )?;
            parts.delta = self.damping.map_or(parts.delta, |_| Some(p.delta()));
            parts.alpha = self.stiffness.map_or(parts.alpha, |_| Some(p.alpha()));
            parts.beta = self.wall_damping.map_or(parts.beta, |_| Some(p.beta()));
        }
        parts.device = match (self.mass, self.period) {
            (Some(m), Some(t)) => {
                Device::new(m, t, 0.0, Delay::Samples(0.0))?;
                Some((m, t))
            }
            (Some(_), None) => {
                return Err(RequestError::NeedsPeriod { input: Input::Mass }.into());
            }
            _ => None,
        };
        Ok(parts)
    }
}

/// The (delta, beta) plane of a boundary request, checked: the curves' stiffnesses and delay
/// factors, the range of the `delta` axis, and the device `(mass, period)` of the loop
/// elements when there are any ([`DeviceInputs::delta_beta_plane`]).
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct DeltaBetaPlane<'a> {
    /// The stiffnesses `alpha`, one curve each (outer).
    pub alphas: &'a [f64],
    /// The delay factors `d`, one curve each (inner).
    pub ds: &'a [f64],
    /// The range of the `delta` axis, `lo < hi`.
    pub range: (f64, f64),
    /// The device `(mass, period)` of the loop elements, validated; `None` without elements.
    pub device: Option<(f64, f64)>,
}

impl<'a> DeviceInputs<&'a [f64]> {
    /// The (delta, beta) plane of a boundary request (paper Figs. 6, 9; `docs/MODEL.md`
    /// section 2 for the normalization): its axes stay normalized, so `delta` gives the range
    /// of the horizontal axis (from its smallest to its largest value; `[0, 1]` when not
    /// given), `alpha` and `d` the curves, and a device is taken only as the `mass` and
    /// `period` that convert the loop elements (`elements`: whether any is named). Every
    /// value is checked here, before any curve is drawn: each `alpha` a stiffness `>= 0` (no
    /// wall with `alpha < 0` is stable), each `d` a delay factor, the device as
    /// [`Device::new`].
    ///
    /// ```
    /// use stabound::request::DeviceInputs;
    ///
    /// let (alpha, d, delta) = ([0.0, 0.5], [1.0], [0.0, 2.0]);
    /// let given = DeviceInputs { alpha: Some(&alpha[..]), d: Some(&d[..]),
    ///                            delta: Some(&delta[..]), ..Default::default() };
    /// let plane = given.delta_beta_plane(false)?;
    /// assert_eq!((plane.alphas.len(), plane.range, plane.device), (2, (0.0, 2.0), None));
    ///
    /// // loop elements need the device's mass and period; the plant's damping is an axis
    /// let e = given.delta_beta_plane(true).unwrap_err().to_string();
    /// assert!(e.starts_with("missing mass and period: loop elements"), "{e}");
    /// let b = [1.0];
    /// let damped = DeviceInputs { damping: Some(&b[..]), ..given };
    /// assert!(damped.delta_beta_plane(false).is_err());
    /// # Ok::<(), stabound::Error>(())
    /// ```
    ///
    /// # Errors
    ///
    /// [`RequestError::DeltaBeta`] naming the inputs; a value out of range as
    /// [`Wall::new`](crate::Wall::new), [`Plant::new`] and [`Device::new`] say, or
    /// [`RequestError::Refused`] for a negative `alpha`.
    pub fn delta_beta_plane(&self, elements: bool) -> Result<DeltaBetaPlane<'a>> {
        let refuse = |why: PlaneFault, inputs: Vec<Input>| -> Error {
            RequestError::DeltaBeta { why, inputs }.into()
        };
        let present = |pairs: &[(Input, Option<&[f64]>)]| -> Vec<Input> {
            pairs.iter().filter_map(|&(i, v)| v.map(|_| i)).collect()
        };
        let not_taken = present(&[
            (Input::Damping, self.damping),
            (Input::Delay, self.delay),
            (Input::DelaySamples, self.delay_samples),
            (Input::Stiffness, self.stiffness),
            (Input::WallDamping, self.wall_damping),
            (Input::Beta, self.beta),
        ]);
        if !not_taken.is_empty() {
            return Err(refuse(PlaneFault::NotTaken, not_taken));
        }
        let absent = |pairs: [(Input, Option<&[f64]>); 2]| -> Vec<Input> {
            pairs
                .into_iter()
                .filter_map(|(i, v)| v.is_none().then_some(i))
                .collect()
        };
        let (Some(alphas), Some(ds)) = (self.alpha, self.d) else {
            let missing = absent([(Input::Alpha, self.alpha), (Input::D, self.d)]);
            return Err(refuse(PlaneFault::Missing, missing));
        };
        let range = match self.delta {
            None => (0.0, 1.0),
            Some(v) => {
                let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
                let hi = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
                // also refuses an empty list (lo = inf, hi = -inf)
                if lo.partial_cmp(&hi) != Some(std::cmp::Ordering::Less) {
                    return Err(refuse(PlaneFault::Range, vec![Input::Delta]));
                }
                (lo, hi)
            }
        };
        for &alpha in alphas {
            crate::params::Wall::new(alpha, 0.0)?;
            if alpha < 0.0 {
                return Err(RequestError::Refused {
                    input: Input::Alpha,
                    value: alpha,
                    expected: "stiffness must be >= 0 (no wall with alpha < 0 is stable)",
                }
                .into());
            }
        }
        for &d in ds {
            Plant::new(range.0, d)?;
            Plant::new(range.1, d)?;
        }
        let device = present(&[(Input::Mass, self.mass), (Input::Period, self.period)]);
        let device = match (elements, self.mass, self.period) {
            (false, None, None) => None,
            (false, _, _) => return Err(refuse(PlaneFault::DeviceWithoutElements, device)),
            (true, Some(&[m]), Some(&[t])) => {
                Device::new(m, t, 0.0, Delay::Samples(0.0))?;
                Some((m, t))
            }
            (true, Some(_), Some(_)) => {
                let several = present(&[
                    (Input::Mass, self.mass.filter(|v| v.len() != 1)),
                    (Input::Period, self.period.filter(|v| v.len() != 1)),
                ]);
                return Err(refuse(PlaneFault::OneDevice, several));
            }
            (true, _, _) => {
                let missing = absent([(Input::Mass, self.mass), (Input::Period, self.period)]);
                return Err(refuse(PlaneFault::ElementsWithoutDevice, missing));
            }
        };
        Ok(DeltaBetaPlane {
            alphas,
            ds,
            range,
            device,
        })
    }
}

impl<T> Given<T> {
    /// Whether the form given is the physical one.
    pub fn is_physical(&self) -> bool {
        matches!(self, Given::Physical { .. })
    }

    /// The same form with each value mapped by `f`, which is told the input it maps.
    ///
    /// # Errors
    ///
    /// The first error of `f`.
    pub fn try_map<U, E>(
        self,
        mut f: impl FnMut(Input, T) -> std::result::Result<U, E>,
    ) -> std::result::Result<Given<U>, E> {
        Ok(match self {
            Given::Normalized { delta, d, wall } => Given::Normalized {
                delta: f(Input::Delta, delta)?,
                d: f(Input::D, d)?,
                wall: match wall {
                    Some((a, b)) => Some((f(Input::Alpha, a)?, f(Input::Beta, b)?)),
                    None => None,
                },
            },
            Given::Physical {
                mass,
                period,
                damping,
                delay,
                in_samples,
                wall,
            } => Given::Physical {
                mass: f(Input::Mass, mass)?,
                period: f(Input::Period, period)?,
                damping: f(Input::Damping, damping)?,
                delay: f(
                    if in_samples {
                        Input::DelaySamples
                    } else {
                        Input::Delay
                    },
                    delay,
                )?,
                in_samples,
                wall: match wall {
                    Some((k, b)) => Some((f(Input::Stiffness, k)?, f(Input::WallDamping, b)?)),
                    None => None,
                },
            },
        })
    }

    /// Refuses `what` (loop elements, intervals: inputs of the physical form only) when the
    /// form given is the normalized one; `present` says whether any was given.
    ///
    /// # Errors
    ///
    /// [`RequestError::NeedsPhysical`].
    pub fn physical_for(&self, what: &'static str, present: bool, takes: Takes) -> Result<()> {
        if present && !self.is_physical() {
            return Err(RequestError::NeedsPhysical { what, takes }.into());
        }
        Ok(())
    }
}

/// The delay `value` in sampling periods (`in_samples`) or in s.
pub fn delay(value: f64, in_samples: bool) -> Delay {
    if in_samples {
        Delay::Samples(value)
    } else {
        Delay::Seconds(value)
    }
}

impl Given<f64> {
    /// The device of a request in physical units, validated (`None` for a normalized one).
    ///
    /// # Errors
    ///
    /// As [`Device::new`].
    pub fn device(&self) -> Result<Option<Device>> {
        match *self {
            Given::Normalized { .. } => Ok(None),
            Given::Physical {
                mass,
                period,
                damping,
                delay: dl,
                in_samples,
                ..
            } => Device::new(mass, period, damping, delay(dl, in_samples)).map(Some),
        }
    }

    /// The plant, validated (a device's converted as [`Device::plant`]).
    ///
    /// # Errors
    ///
    /// A value out of range.
    pub fn plant(&self) -> Result<Plant> {
        match self.device()? {
            Some(dev) => dev.plant(),
            None => match *self {
                Given::Normalized { delta, d, .. } => Plant::new(delta, d),
                Given::Physical { .. } => Err(Error::InvalidRequest(
                    "a request in physical units without its device".into(),
                )),
            },
        }
    }

    /// The wall and plant of a request that takes walls, validated (a device's converted
    /// as [`Device::normalize`]).
    ///
    /// # Errors
    ///
    /// A value out of range, or a request without a wall.
    pub fn normalized(&self) -> Result<Normalized> {
        match (*self, self.device()?) {
            (
                Given::Normalized {
                    delta,
                    d,
                    wall: Some((a, b)),
                },
                _,
            ) => Normalized::new(a, b, delta, d),
            (
                Given::Physical {
                    wall: Some((k, b)), ..
                },
                Some(dev),
            ) => dev.normalize(k, b),
            _ => Err(Error::InvalidRequest(
                "this request takes no wall: resolve it as one that takes walls".into(),
            )),
        }
    }
}

/// The set of devices `device` with the elements `named`, spread as `spreads` (each a
/// quantity with its interval or its list of values), the hand let go unless `always_gripped` or the
/// computation does not let it go (`let_go`; a point test checks the device as given).
/// `None` when that set is the one device, unless a hand the computation could let go is
/// held (the set then says it is always gripped, for reports).
///
/// ```
/// use stabound::elements::PhysicalElements;
/// use stabound::request::device_set;
/// use stabound::robust::{Quantity, Spread};
/// use stabound::{Delay, Device};
///
/// let dev = Device::new(0.1, 1e-3, 0.0, Delay::Samples(1.0))?;
/// let none = PhysicalElements::default();
/// assert!(device_set(&dev, &none, &[], false, true)?.is_none());
/// let set = device_set(&dev, &none, &[(Quantity::Delay, Spread::Interval(1.0, 3.0))], false, true)?.unwrap();
/// assert!(!set.is_single());
/// // a finite set: the delays 1 and 3 samples, not those between
/// let two = Spread::Values(vec![1.0, 3.0]);
/// let set = device_set(&dev, &none, &[(Quantity::Delay, two)], false, true)?.unwrap();
/// assert!(!set.has_intervals());
/// let mut hand = none;
/// hand.hand_mass = Some(0.3);
/// assert!(device_set(&dev, &hand, &[], false, true)?.unwrap().hand_may_let_go());
/// assert!(!device_set(&dev, &hand, &[], true, true)?.unwrap().hand_may_let_go());
/// # Ok::<(), stabound::Error>(())
/// ```
///
/// # Errors
///
/// As [`DeviceSet::new`] and [`DeviceSet::with_spread`].
pub fn device_set(
    device: &Device,
    named: &PhysicalElements,
    spreads: &[(Quantity, Spread)],
    always_gripped: bool,
    let_go: bool,
) -> Result<Option<DeviceSet>> {
    let mut set = DeviceSet::new(device, named)?;
    for (q, s) in spreads {
        set = set.with_spread(*q, s)?;
    }
    let set = set.always_gripped(always_gripped || !let_go);
    // a held hand is reported (let go or always gripped) even on one device
    let held = set.reference().hand_held();
    Ok((!set.is_single() || (held && let_go)).then_some(set))
}
