//! Parameters: the normalized quadruple `(alpha, beta, delta, d)` and physical units.
//!
//! The normalization is that of the paper (eqs. 14 and 16), see `docs/MODEL.md` section 1:
//!
//! | symbol | meaning | definition |
//! | --- | --- | --- |
//! | alpha | virtual stiffness | `K T^2 / m` |
//! | beta | virtual damping | `B T / m` |
//! | delta | physical damping | `b T / m` |
//! | d | delay factor | `t_delay / T` |

use crate::error::{Error, Result};

/// The longest delay factor `d` the crate accepts.
///
/// The characteristic polynomial has degree `floor(d) + 4`, so this caps the degree at 504.
/// Long teleoperation delays of a few hundred samples are inside; beyond that the eigenvalue
/// route costs seconds per point and the expanded polynomial is meaningless in `f64`.
pub const MAX_DELAY: f64 = 500.0;

/// Largest number of coefficients any characteristic polynomial has (degree + 1).
pub const MAX_COEFFS: usize = MAX_DELAY as usize + 5;

/// The largest physical damping `delta` the crate accepts.
///
/// The model itself is exact for any `delta`; above this the wall parameters that matter scale
/// with `delta` (eq. 22) and values of `alpha` beyond `1e12` lose meaning in `f64` arithmetic.
pub const MAX_DELTA: f64 = 1e9;

/// A delay in seconds is taken as a whole number of samples when it is within this many
/// samples of one.
///
/// `0.003 s / 0.001 s` is `2.9999999999999996` in floating point: taken literally, that is a
/// fractional delay with a polynomial of one degree more and a root near `z = 0`; stability
/// is the same to about `1e-15` but the reported degree and roots are not. `1e-9` samples is
/// far above division rounding (a few ulps, `1e-13` samples at `d = 500`) and far below any
/// delay a device could resolve.
pub const WHOLE_SAMPLE_TOL: f64 = 1e-9;

/// Units in the last place by which a range normalized from physical units is widened on
/// each side ([`outward`]): `alpha = K T^2 / m` and `beta = B T / m` round at most three
/// times (about 1.5 ulp), so 4 ulp hold every physical value of the range.
const WIDEN_ULPS: usize = 4;

/// The normalized range `[lo, hi]` of a physical range (of stiffness or damping, through
/// [`Device::normalize`]) widened outward by [`WIDEN_ULPS`] units in the last place on each
/// side, so that it holds the normalization of every physical value of the range.
///
/// ```
/// let (lo, hi) = stabound::params::outward(0.1, 0.2);
/// assert!(lo < 0.1 && hi > 0.2 && 0.1 - lo < 1e-15 && hi - 0.2 < 1e-15);
/// ```
pub fn outward(lo: f64, hi: f64) -> (f64, f64) {
    (0..WIDEN_ULPS).fold((lo, hi), |(lo, hi), _| (lo.next_down(), hi.next_up()))
}

/// Checks that `value` is finite, naming `name` otherwise.
pub(crate) fn finite(name: &'static str, value: f64) -> Result<f64> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(Error::InvalidParameter {
            name,
            value,
            expected: "must be a finite number".into(),
        })
    }
}

/// Checks `0 <= value <= max`.
pub(crate) fn in_range(name: &'static str, value: f64, min: f64, max: f64) -> Result<f64> {
    finite(name, value)?;
    if value < min || value > max {
        return Err(Error::InvalidParameter {
            name,
            value,
            expected: format!("accepted range is [{}, {}]", readable(min), readable(max)),
        });
    }
    Ok(value)
}

/// A limit as a reader wants it: `1e-12`, not `0.000000000001`.
fn readable(x: f64) -> String {
    let a = x.abs();
    // exact zero on purpose: 0 prints as `0`
    if a == 0.0 || (1e-4..1e15).contains(&a) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// Checks `value > 0` and finite.
pub(crate) fn positive(name: &'static str, value: f64) -> Result<f64> {
    finite(name, value)?;
    if value <= 0.0 {
        return Err(Error::InvalidParameter {
            name,
            value,
            expected: "must be greater than 0".into(),
        });
    }
    Ok(value)
}

/// The device side of the loop in normalized form: physical damping `delta` and delay `d`.
///
/// These two fix the characteristic polynomial up to the wall parameters, so every sweep over
/// walls builds one [`Plant`] and reuses it.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(try_from = "PlantFields"))]
pub struct Plant {
    delta: f64,
    d: f64,
}

/// What deserialization reads before [`Plant::new`] checks it.
#[cfg(feature = "serde")]
#[derive(serde::Deserialize)]
struct PlantFields {
    delta: f64,
    d: f64,
}

#[cfg(feature = "serde")]
impl TryFrom<PlantFields> for Plant {
    type Error = Error;
    fn try_from(f: PlantFields) -> Result<Self> {
        Self::new(f.delta, f.d)
    }
}

impl Plant {
    /// A validated plant: `0 <= delta <= MAX_DELTA`, `0 <= d <= MAX_DELAY`, both finite.
    pub fn new(delta: f64, d: f64) -> Result<Self> {
        in_range("delta", delta, 0.0, MAX_DELTA)?;
        in_range("d", d, 0.0, MAX_DELAY)?;
        Ok(Self { delta, d })
    }

    /// Normalized physical damping `delta = b T / m`.
    pub fn delta(&self) -> f64 {
        self.delta
    }

    /// Delay factor `d = t_delay / T`.
    pub fn d(&self) -> f64 {
        self.d
    }

    /// Whole samples of delay, `n = floor(d)`.
    pub fn whole_samples(&self) -> usize {
        self.d.floor() as usize
    }

    /// The fractional part of the delay, `eps = d - floor(d)` in `[0, 1)`.
    pub fn fraction(&self) -> f64 {
        self.d - self.d.floor()
    }

    /// Whether the delay is a whole number of samples (the fraction is exactly zero).
    pub fn is_integer_delay(&self) -> bool {
        // Exact test on purpose: any nonzero fraction, however small, adds a root near z = 0
        // and raises the degree; `d.floor()` is exact so the comparison is too.
        self.fraction() <= 0.0
    }

    /// Degree of the characteristic polynomial: `n + 3` for integer `d`, `n + 4` otherwise.
    pub fn degree(&self) -> usize {
        self.whole_samples() + if self.is_integer_delay() { 3 } else { 4 }
    }
}

/// A virtual wall in normalized form: stiffness `alpha` and damping `beta`.
///
/// Any finite values are accepted: negative stiffness or damping are legitimate points of a
/// parameter plane (they are simply unstable or less stable).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(try_from = "WallFields"))]
pub struct Wall {
    /// Normalized stiffness `alpha = K T^2 / m`.
    pub(crate) alpha: f64,
    /// Normalized damping `beta = B T / m`.
    pub(crate) beta: f64,
}

/// What deserialization reads before [`Wall::new`] checks it.
#[cfg(feature = "serde")]
#[derive(serde::Deserialize)]
struct WallFields {
    alpha: f64,
    beta: f64,
}

#[cfg(feature = "serde")]
impl TryFrom<WallFields> for Wall {
    type Error = Error;
    fn try_from(f: WallFields) -> Result<Self> {
        Self::new(f.alpha, f.beta)
    }
}

impl Wall {
    /// A validated wall: both values finite.
    pub fn new(alpha: f64, beta: f64) -> Result<Self> {
        finite("alpha", alpha)?;
        finite("beta", beta)?;
        Ok(Self { alpha, beta })
    }

    /// Normalized stiffness `alpha = K T^2 / m`.
    pub fn alpha(&self) -> f64 {
        self.alpha
    }

    /// Normalized damping `beta = B T / m`.
    pub fn beta(&self) -> f64 {
        self.beta
    }

    /// The wall as a point `(alpha, beta)` of the wall plane.
    pub(crate) fn xy(&self) -> (f64, f64) {
        (self.alpha, self.beta)
    }
}

/// All four normalized parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(try_from = "NormalizedFields"))]
pub struct Normalized {
    /// Normalized stiffness `alpha = K T^2 / m`.
    pub(crate) alpha: f64,
    /// Normalized virtual damping `beta = B T / m`.
    pub(crate) beta: f64,
    /// Normalized physical damping `delta = b T / m`.
    pub(crate) delta: f64,
    /// Delay factor `d = t_delay / T`.
    pub(crate) d: f64,
}

/// What deserialization reads before [`Normalized::new`] checks it.
#[cfg(feature = "serde")]
#[derive(serde::Deserialize)]
struct NormalizedFields {
    alpha: f64,
    beta: f64,
    delta: f64,
    d: f64,
}

#[cfg(feature = "serde")]
impl TryFrom<NormalizedFields> for Normalized {
    type Error = Error;
    fn try_from(f: NormalizedFields) -> Result<Self> {
        Self::new(f.alpha, f.beta, f.delta, f.d)
    }
}

impl Normalized {
    /// All four normalized parameters, validated as [`Plant::new`] and [`Wall::new`] do.
    pub fn new(alpha: f64, beta: f64, delta: f64, d: f64) -> Result<Self> {
        Plant::new(delta, d)?;
        Wall::new(alpha, beta)?;
        Ok(Self {
            alpha,
            beta,
            delta,
            d,
        })
    }

    /// The plant `(delta, d)` of these parameters (valid by construction).
    pub fn plant(&self) -> Plant {
        Plant {
            delta: self.delta,
            d: self.d,
        }
    }

    /// Normalized stiffness `alpha`.
    pub fn alpha(&self) -> f64 {
        self.alpha
    }

    /// Normalized virtual damping `beta`.
    pub fn beta(&self) -> f64 {
        self.beta
    }

    /// Normalized physical damping `delta`.
    pub fn delta(&self) -> f64 {
        self.delta
    }

    /// Delay factor `d`.
    pub fn d(&self) -> f64 {
        self.d
    }

    /// The wall part.
    pub fn wall(&self) -> Wall {
        Wall {
            alpha: self.alpha,
            beta: self.beta,
        }
    }

    /// Validates and splits into the plant and the wall.
    pub fn split(&self) -> Result<(Plant, Wall)> {
        Ok((
            Plant::new(self.delta, self.d)?,
            Wall::new(self.alpha, self.beta)?,
        ))
    }
}

/// A delay given either in seconds or in samples.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum Delay {
    /// Delay in seconds; `d = seconds / T`.
    Seconds(f64),
    /// Delay in sampling periods; `d = samples`.
    Samples(f64),
}

/// A haptic device in physical units: mass, sampling period, physical damping and delay.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(try_from = "DeviceFields"))]
pub struct Device {
    /// Moving mass `m` in kg.
    pub(crate) mass: f64,
    /// Sampling period `T` in s.
    pub(crate) period: f64,
    /// Physical viscous damping `b` in N s/m.
    pub(crate) damping: f64,
    /// Delay of the force, in seconds or samples.
    pub(crate) delay: Delay,
}

/// What deserialization reads before [`Device::new`] checks it.
#[cfg(feature = "serde")]
#[derive(serde::Deserialize)]
struct DeviceFields {
    mass: f64,
    period: f64,
    damping: f64,
    delay: Delay,
}

#[cfg(feature = "serde")]
impl TryFrom<DeviceFields> for Device {
    type Error = Error;
    fn try_from(f: DeviceFields) -> Result<Self> {
        Self::new(f.mass, f.period, f.damping, f.delay)
    }
}

impl Device {
    /// A validated device: mass `m` (kg) and period `T` (s) positive, damping `b` (N s/m)
    /// and delay non-negative, all finite.
    ///
    /// ```
    /// use stabound::params::{Delay, Device};
    /// // The paper's Section VIII device: 0.1 kg, 1 kHz, one sample of delay, with the
    /// // middle of its three physical dampings (0, 10 and 100 N s/m): delta = b T / m = 0.1.
    /// let device = Device::new(0.1, 1e-3, 10.0, Delay::Samples(1.0))?;
    /// assert_eq!(device.plant()?.delta(), 10.0 * 1e-3 / 0.1);
    /// assert!(Device::new(-0.1, 1e-3, 10.0, Delay::Samples(1.0)).is_err());
    /// # Ok::<(), stabound::Error>(())
    /// ```
    pub fn new(mass: f64, period: f64, damping: f64, delay: Delay) -> Result<Self> {
        let device = Self {
            mass,
            period,
            damping,
            delay,
        };
        device.validate()?;
        Ok(device)
    }

    /// Moving mass `m` in kg.
    pub fn mass(&self) -> f64 {
        self.mass
    }

    /// Sampling period `T` in s.
    pub fn period(&self) -> f64 {
        self.period
    }

    /// Physical viscous damping `b` in N s/m.
    pub fn damping(&self) -> f64 {
        self.damping
    }

    /// Delay of the force, in seconds or samples.
    pub fn delay(&self) -> Delay {
        self.delay
    }

    /// Checks the device: mass and period positive, damping and delay non-negative, all finite.
    pub fn validate(&self) -> Result<()> {
        positive("mass", self.mass)?;
        positive("period", self.period)?;
        finite("damping", self.damping)?;
        if self.damping < 0.0 {
            return Err(Error::InvalidParameter {
                name: "damping",
                value: self.damping,
                expected: "physical damping must be >= 0 N s/m".into(),
            });
        }
        match self.delay {
            Delay::Seconds(s) => {
                finite("delay", s)?;
                if s < 0.0 {
                    return Err(Error::InvalidParameter {
                        name: "delay",
                        value: s,
                        expected: "delay must be >= 0 s".into(),
                    });
                }
            }
            Delay::Samples(s) => {
                finite("delay", s)?;
                if s < 0.0 {
                    return Err(Error::InvalidParameter {
                        name: "delay",
                        value: s,
                        expected: "delay must be >= 0 samples".into(),
                    });
                }
            }
        }
        Ok(())
    }

    /// The delay factor `d = t_delay / T`.
    ///
    /// A delay in seconds within [`WHOLE_SAMPLE_TOL`] samples of a whole number of samples
    /// is taken as that whole number.
    pub fn delay_factor(&self) -> f64 {
        match self.delay {
            Delay::Seconds(s) => {
                let d = s / self.period;
                let whole = d.round();
                if (d - whole).abs() <= WHOLE_SAMPLE_TOL {
                    whole
                } else {
                    d
                }
            }
            Delay::Samples(n) => n,
        }
    }

    /// The normalized plant `(delta, d)` of this device, validated.
    pub fn plant(&self) -> Result<Plant> {
        self.validate()?;
        let delta = self.damping * self.period / self.mass;
        let d = self.delay_factor();
        if d > MAX_DELAY {
            return Err(Error::InvalidParameter {
                name: "delay",
                value: d,
                expected: format!(
                    "delay of {d} samples exceeds the supported {MAX_DELAY} samples (polynomial degree {}); shorten the delay or the sampling period",
                    MAX_DELAY as usize + 4
                ),
            });
        }
        Plant::new(delta, d)
    }

    /// Physical stiffness `K = alpha m / T^2` in N/m for a normalized `alpha`.
    pub fn stiffness(&self, alpha: f64) -> f64 {
        alpha * self.mass / (self.period * self.period)
    }

    /// Physical damping `B = beta m / T` in N s/m for a normalized `beta`.
    pub fn wall_damping(&self, beta: f64) -> f64 {
        beta * self.mass / self.period
    }

    /// Normalized `alpha = K T^2 / m` for a stiffness in N/m.
    pub fn alpha(&self, stiffness: f64) -> f64 {
        stiffness * self.period * self.period / self.mass
    }

    /// Normalized `beta = B T / m` for a wall damping in N s/m.
    pub fn beta(&self, wall_damping: f64) -> f64 {
        wall_damping * self.period / self.mass
    }

    /// Normalized wall of a physical wall, validated.
    pub fn wall(&self, stiffness: f64, wall_damping: f64) -> Result<Wall> {
        finite("stiffness", stiffness)?;
        finite("wall damping", wall_damping)?;
        Wall::new(self.alpha(stiffness), self.beta(wall_damping))
    }

    /// All four normalized parameters for a physical wall on this device.
    pub fn normalize(&self, stiffness: f64, wall_damping: f64) -> Result<Normalized> {
        let plant = self.plant()?;
        let wall = self.wall(stiffness, wall_damping)?;
        Ok(Normalized {
            alpha: wall.alpha,
            beta: wall.beta,
            delta: plant.delta(),
            d: plant.d(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn physical_round_trip() {
        let dev = Device {
            mass: 0.1,
            period: 1e-3,
            damping: 10.0,
            delay: Delay::Seconds(2e-3),
        };
        let n = dev.normalize(2000.0, 5.0).unwrap();
        // paper Section VIII: b = 10 N s/m on m = 0.1 kg, T = 1 ms is delta = 0.1
        assert_relative_eq!(n.delta, 0.1, max_relative = 1e-15);
        assert_relative_eq!(n.d, 2.0, max_relative = 1e-15);
        assert_relative_eq!(n.alpha, 2000.0 * 1e-6 / 0.1, max_relative = 1e-15);
        assert_relative_eq!(dev.stiffness(n.alpha), 2000.0, max_relative = 1e-14);
        assert_relative_eq!(dev.wall_damping(n.beta), 5.0, max_relative = 1e-14);
    }

    #[test]
    fn rejects_bad_input() {
        assert!(Plant::new(f64::NAN, 0.0).is_err());
        assert!(Plant::new(-1e-3, 0.0).is_err());
        assert!(Plant::new(0.0, -1.0).is_err());
        assert!(Plant::new(0.0, MAX_DELAY + 1.0).is_err());
        assert!(Wall::new(f64::INFINITY, 0.0).is_err());
        let dev = Device {
            mass: 0.0,
            period: 1e-3,
            damping: 0.0,
            delay: Delay::Samples(1.0),
        };
        let err = dev.plant().unwrap_err().to_string();
        assert!(err.contains("mass"), "{err}");
        let dev = Device {
            mass: 1.0,
            period: 1e-3,
            damping: 0.0,
            delay: Delay::Seconds(1.0),
        };
        let err = dev.plant().unwrap_err().to_string();
        assert!(err.contains("exceeds"), "{err}");
    }

    #[test]
    fn delay_in_seconds_snaps_to_whole_samples() {
        let dev = |s| Device {
            mass: 0.1,
            period: 0.001,
            damping: 0.0,
            delay: Delay::Seconds(s),
        };
        // 0.003 / 0.001 = 2.9999999999999996 in f64
        assert_eq!(dev(0.003).plant().unwrap().degree(), 6);
        assert!(dev(0.003).plant().unwrap().is_integer_delay());
        // a real fraction stays
        assert!((dev(0.0025).delay_factor() - 2.5).abs() < 1e-12);
    }

    #[cfg(feature = "serde")]
    #[test]
    fn deserialization_validates() {
        // serde goes through the constructors: an out-of-range plant is refused with the
        // constructor's message instead of reaching the engines
        let err = serde_json::from_str::<Plant>(r#"{"delta": -5, "d": 100000}"#).unwrap_err();
        assert!(err.to_string().contains("delta"), "{err}");
        let ok: Plant = serde_json::from_str(r#"{"delta": 0.5, "d": 1}"#).unwrap();
        assert_eq!(ok, Plant::new(0.5, 1.0).unwrap());
        let wall: Wall = serde_json::from_str(r#"{"alpha": 0.1, "beta": 0.3}"#).unwrap();
        assert_eq!(wall, Wall::new(0.1, 0.3).unwrap());
        // a number beyond f64 never becomes a wall (the reader or the constructor refuses it)
        assert!(serde_json::from_str::<Wall>(r#"{"alpha": 1e999, "beta": 0}"#).is_err());
        // devices and four-parameter points too
        let dev = r#"{"mass": -1, "period": 1e-3, "damping": 0, "delay": {"samples": 1}}"#;
        let err = serde_json::from_str::<Device>(dev).unwrap_err();
        assert!(err.to_string().contains("mass"), "{err}");
        let dev = r#"{"mass": 1, "period": 1e-3, "damping": 0, "delay": {"samples": 1}}"#;
        let ok: Device = serde_json::from_str(dev).unwrap();
        assert_eq!(
            ok,
            Device::new(1.0, 1e-3, 0.0, Delay::Samples(1.0)).unwrap()
        );
        let n = r#"{"alpha": 0.1, "beta": 0.3, "delta": -5, "d": 1}"#;
        assert!(serde_json::from_str::<Normalized>(n).is_err());
    }

    #[test]
    fn degree_and_split() {
        assert_eq!(Plant::new(0.5, 0.0).unwrap().degree(), 3);
        assert_eq!(Plant::new(0.5, 1.0).unwrap().degree(), 4);
        assert_eq!(Plant::new(0.5, 1.5).unwrap().degree(), 5);
        assert_eq!(Plant::new(0.5, 0.25).unwrap().degree(), 4);
    }
}
