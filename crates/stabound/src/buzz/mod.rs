//! Buzz: encoder resolution, force resolution and Coulomb friction on a wall the linear loop
//! calls stable (the model document, docs/MODEL.md, section 10).
//!
//! The linear loop says whether small motions grow. An encoder that reports whole counts, a
//! force output with finite resolution and dry friction can make a wall the linear loop
//! calls stable hold a sustained oscillation of a few counts (buzz), and make small motions
//! on a wall it calls unstable die out. Each is modelled only when named ([`Nonlinear`] in
//! physical units, [`Quantization`] normalized).
//!
//! Two computations:
//!
//! - [`buzz`]: the verdict, by the exact simulation of the nonlinear sampled loop
//!   ([`readings`]; section 10.1): the held force between samples, the quantizers at the
//!   samples, the velocity zeros of Coulomb friction located inside the period in closed
//!   form, stick and slip. The protocol starts from rest at 1, 3 and 10 counts inside the
//!   wall and from an impact, runs 20,000 samples and looks at the last 4,000.
//! - [`describing_function`]: the first-harmonic prediction of section 10.2 on the loop's own
//!   boundary (the ray margin `s*`, the crossing frequency, the amplitudes). A fast first
//!   estimate, never the verdict: its measured agreement with the simulation is in the model
//!   document.
//!
//! ```
//! use stabound::buzz::{BuzzOptions, Quantization, buzz};
//! use stabound::params::{Plant, Wall};
//!
//! // One sample of delay, delta = 0.1, an encoder and no friction.
//! let plant = Plant::new(0.1, 1.0)?;
//! let q = Quantization::new(true, 0.0, 0.0, 0.0)?;
//! // A soft, well-damped wall comes to rest; a wall near the boundary buzzes.
//! let soft = buzz(&plant, &Wall::new(0.02, 0.3)?, &q, &BuzzOptions::default())?;
//! assert!(!soft.sustained());
//! # Ok::<(), stabound::Error>(())
//! ```

mod describing;
mod free;
mod friction;
mod modal;
mod sim;

pub use describing::{
    Crossing, DescribingFunction, LimitCycle, describing_function, quantizer_gain,
};
pub use free::{
    BuzzFree, BuzzFreeMax, BuzzFreeOptions, DAMPING_GRID, MAX_SCAN_POINTS, SCAN_POINTS,
    buzz_free_alpha, buzz_free_alpha_max,
};
pub use sim::readings;

use crate::elements::{Loop, PhysicalElements};
use crate::error::{Error, Result};
use crate::params::{Device, Wall, finite};

/// The encoder, force output and dry friction of a device in physical units, as a scene, a
/// command line or a binding names them: `None` is not modelled.
///
/// With serde its keys carry their units: `encoder_resolution_m`, `force_resolution_N`,
/// `coulomb_friction_N`, `static_friction_N`; reading refuses a negative, zero or non-finite
/// resolution, negative friction, and static friction below the Coulomb friction.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(
    feature = "serde",
    serde(try_from = "NonlinearFields", into = "NonlinearFields")
)]
#[non_exhaustive]
pub struct Nonlinear {
    /// Encoder resolution, m per count.
    pub encoder_resolution: Option<f64>,
    /// Force output resolution (DAC step), N.
    pub force_resolution: Option<f64>,
    /// Coulomb (sliding) friction, N.
    pub coulomb_friction: Option<f64>,
    /// Static (breakaway) friction, N; at least the Coulomb friction (default: equal to it).
    pub static_friction: Option<f64>,
}

impl From<&PhysicalElements> for Nonlinear {
    /// The quantizers and friction `e` names (each `None` when not).
    ///
    /// ```
    /// use stabound::buzz::Nonlinear;
    /// use stabound::elements::PhysicalElements;
    ///
    /// let mut e = PhysicalElements::default();
    /// e.encoder_resolution = Some(1e-5);
    /// e.hand_mass = Some(0.2);
    /// let q = Nonlinear::from(&e);
    /// assert_eq!((q.encoder_resolution, q.force_resolution), (Some(1e-5), None));
    /// ```
    fn from(e: &PhysicalElements) -> Self {
        Self {
            encoder_resolution: e.encoder_resolution,
            force_resolution: e.force_resolution,
            coulomb_friction: e.coulomb_friction,
            static_friction: e.static_friction,
        }
    }
}

impl Nonlinear {
    /// Whether any of the four is named.
    pub fn any(&self) -> bool {
        *self != Self::default()
    }

    /// The checks that need no device: resolutions finite and above zero, friction finite
    /// and not negative, static friction at least the Coulomb friction.
    pub fn validate(&self) -> Result<()> {
        for (name, v) in [
            ("encoder resolution", self.encoder_resolution),
            ("force resolution", self.force_resolution),
        ] {
            if let Some(v) = v {
                crate::params::positive(name, v)?;
            }
        }
        for (name, v) in [
            ("coulomb friction", self.coulomb_friction),
            ("static friction", self.static_friction),
        ] {
            if let Some(v) = v {
                not_negative(name, v)?;
            }
        }
        crate::elements::list::friction_order(self.coulomb_friction, self.static_friction)
    }

    /// The normalized form on `device` for a wall of `stiffness` N/m.
    ///
    /// The length unit (one "count") is the encoder resolution when one is named. Without an
    /// encoder the position is read exactly, and the unit is the deflection at which the
    /// wall's force equals the larger of the force step and the static friction (`F / K`):
    /// the length scale those two act on.
    ///
    /// # Errors
    ///
    /// As [`Nonlinear::validate`]; [`Error::InvalidRequest`] when nothing is named, or when
    /// no encoder is named and the stiffness is not positive (no length scale).
    pub fn normalize(&self, device: &Device, stiffness: f64) -> Result<Quantization> {
        self.validate()?;
        device.validate()?;
        finite("stiffness", stiffness)?;
        if !self.any() {
            return Err(Error::InvalidRequest(
                "name an encoder resolution, a force resolution or a friction to model buzz".into(),
            ));
        }
        let coulomb = self.coulomb_friction.unwrap_or(0.0);
        let stiction = self.static_friction.unwrap_or(coulomb);
        let unit = match self.encoder_resolution {
            Some(r) => r,
            None => {
                let force = self.force_resolution.unwrap_or(0.0).max(stiction);
                if !(stiffness > 0.0 && force > 0.0) {
                    return Err(Error::InvalidRequest(
                        "without an encoder resolution the buzz length scale is the deflection of one force step or the static friction on the wall: give a positive stiffness and a nonzero force resolution or friction, or name the encoder resolution".into(),
                    ));
                }
                force / stiffness
            }
        };
        // Normalized force in units of the count: F T^2 / (m unit).
        let scale = device.period() * device.period() / (device.mass() * unit);
        let mut q = Quantization::new(
            self.encoder_resolution.is_some(),
            self.force_resolution.unwrap_or(0.0) * scale,
            coulomb * scale,
            stiction * scale,
        )?;
        q.unit = unit;
        Ok(q)
    }
}

fn not_negative(name: &'static str, value: f64) -> Result<f64> {
    finite(name, value)?;
    if value < 0.0 {
        return Err(Error::InvalidParameter {
            name,
            value,
            expected: "must be >= 0".into(),
        });
    }
    Ok(value)
}

/// The serde form of [`Nonlinear`]: the unit in every key.
#[cfg(feature = "serde")]
#[derive(serde::Serialize, serde::Deserialize, Default)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)] // the keys spell units: N (newton) is upper case
struct NonlinearFields {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    encoder_resolution_m: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    force_resolution_N: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    coulomb_friction_N: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    static_friction_N: Option<f64>,
}

#[cfg(feature = "serde")]
impl TryFrom<NonlinearFields> for Nonlinear {
    type Error = Error;
    fn try_from(f: NonlinearFields) -> Result<Self> {
        let n = Nonlinear {
            encoder_resolution: f.encoder_resolution_m,
            force_resolution: f.force_resolution_N,
            coulomb_friction: f.coulomb_friction_N,
            static_friction: f.static_friction_N,
        };
        n.validate()?;
        Ok(n)
    }
}

#[cfg(feature = "serde")]
impl From<Nonlinear> for NonlinearFields {
    fn from(n: Nonlinear) -> Self {
        Self {
            encoder_resolution_m: n.encoder_resolution,
            force_resolution_N: n.force_resolution,
            coulomb_friction_N: n.coulomb_friction,
            static_friction_N: n.static_friction,
        }
    }
}

/// The quantizers and friction in normalized form, lengths in counts.
///
/// Positions are in units of one count (the encoder resolution `Delta_x`, or the length
/// unit [`Nonlinear::normalize`] chose), time in samples, forces as `F T^2 / (m Delta_x)`:
/// the force step `Delta_u T^2 / (m Delta_x)`, the Coulomb friction
/// `phi = f_c T^2 / (m Delta_x)` (the model document, section 10) and the static friction
/// `f_s T^2 / (m Delta_x)`.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct Quantization {
    encoder: bool,
    force_step: f64,
    coulomb: f64,
    stiction: f64,
    unit: f64,
}

/// The largest normalized force step or friction accepted.
///
/// In counts per sample squared; `1e9` is a friction that stops a billion-count motion in one
/// sample, far beyond any device; above it the closed-form velocity zero loses digits.
pub const MAX_NONLINEAR: f64 = 1e9;

impl Quantization {
    /// Normalized quantization: `encoder` reads the position in whole counts (mid-tread,
    /// `round(x)`), `force_step` (0: not quantized), Coulomb friction `coulomb` and static
    /// friction `stiction >= coulomb` (a value below `coulomb`, e.g. 0, means equal to it).
    ///
    /// # Errors
    ///
    /// A value negative, not finite or above [`MAX_NONLINEAR`].
    pub fn new(encoder: bool, force_step: f64, coulomb: f64, stiction: f64) -> Result<Self> {
        for (name, v) in [
            ("force resolution", force_step),
            ("coulomb friction", coulomb),
            ("static friction", stiction),
        ] {
            not_negative(name, v)?;
            if v > MAX_NONLINEAR {
                return Err(Error::InvalidParameter {
                    name,
                    value: v,
                    expected: format!(
                        "must be at most {MAX_NONLINEAR:e} in normalized units (F T^2 / (m Delta_x))"
                    ),
                });
            }
        }
        Ok(Self {
            encoder,
            force_step,
            coulomb,
            stiction: stiction.max(coulomb),
            unit: 1.0,
        })
    }

    /// Whether the position is read in whole counts.
    pub fn encoder(&self) -> bool {
        self.encoder
    }

    /// The force step, normalized (0: not quantized).
    pub fn force_step(&self) -> f64 {
        self.force_step
    }

    /// The Coulomb friction `phi`, normalized.
    pub fn coulomb(&self) -> f64 {
        self.coulomb
    }

    /// The static friction, normalized (at least [`Quantization::coulomb`]).
    pub fn stiction(&self) -> f64 {
        self.stiction
    }

    /// The length of one count in m (1 for a quantization built in normalized units).
    pub fn unit(&self) -> f64 {
        self.unit
    }

    /// Whether any friction acts.
    pub fn has_friction(&self) -> bool {
        self.stiction > 0.0
    }
}

/// Where a run of the protocol starts.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub enum Start {
    /// At rest this many counts inside the wall, no force applied before the start and the
    /// previous sample equal to the first.
    #[cfg_attr(feature = "serde", serde(rename = "rest_counts"))]
    Rest(f64),
    /// At the wall's surface moving into it at this many counts per sample
    /// (`v T / Delta_x`), no force before the start, the previous sample equal to the first.
    #[cfg_attr(feature = "serde", serde(rename = "impact_counts_per_sample"))]
    Impact(f64),
}

impl Start {
    /// Position (counts) and velocity (counts per sample) at the start.
    pub(crate) fn state(self) -> (f64, f64) {
        match self {
            Start::Rest(x) => (x, 0.0),
            Start::Impact(v) => (0.0, v),
        }
    }
}

/// The buzz protocol's settings.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct BuzzOptions {
    /// The starts, each one run.
    pub starts: Vec<Start>,
    /// Samples simulated per run.
    pub samples: usize,
    /// The last samples judged (peak, period, whether the reading still changes).
    pub window: usize,
}

impl Default for BuzzOptions {
    /// Rest at 1, 3 and 10 counts and an impact at 1 count per sample; 20,000 samples, the
    /// last 4,000 judged.
    fn default() -> Self {
        Self {
            starts: vec![
                Start::Rest(1.0),
                Start::Rest(3.0),
                Start::Rest(10.0),
                Start::Impact(1.0),
            ],
            samples: 20_000,
            window: 4_000,
        }
    }
}

/// The most samples one run may take: 10 million (a few seconds of simulation).
pub const MAX_SAMPLES: usize = 10_000_000;

impl BuzzOptions {
    fn validate(&self) -> Result<()> {
        if self.starts.is_empty() {
            return Err(Error::InvalidRequest(
                "name at least one start for the buzz protocol".into(),
            ));
        }
        for s in &self.starts {
            let (x, v) = s.state();
            finite("start position", x)?;
            finite("impact velocity", v)?;
        }
        if self.window == 0 || self.window > self.samples || self.samples > MAX_SAMPLES {
            return Err(Error::InvalidRequest(format!(
                "the buzz protocol needs 1 <= window <= samples <= {MAX_SAMPLES} (got window {}, samples {})",
                self.window, self.samples
            )));
        }
        Ok(())
    }
}

/// How one run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
#[non_exhaustive]
pub enum Outcome {
    /// The reading no longer changes over the window (at rest, possibly stuck at an offset).
    Rest,
    /// The reading still changes at the end of the run: a sustained oscillation.
    Buzz,
    /// The motion grew beyond [`DIVERGED`] counts.
    Diverged,
}

impl Outcome {
    /// `rest`, `buzz` or `diverged`.
    pub fn name(self) -> &'static str {
        match self {
            Outcome::Rest => "rest",
            Outcome::Buzz => "buzz",
            Outcome::Diverged => "diverged",
        }
    }
}

/// A motion beyond this many counts has diverged: the run stops there.
pub const DIVERGED: f64 = 1e9;

/// Without an encoder the reading is continuous: it "still changes" when it moves by more
/// than this many units over the window.
///
/// The unit is the deflection of one force step or the breakaway force, so a motion a
/// millionth of it is far below anything those elements resolve; a decaying linear motion
/// falls below it within the run unless the wall is within about `1e-3` of the boundary.
pub const CONTINUOUS_CHANGE: f64 = 1e-6;

/// One run of the protocol.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub struct BuzzRun {
    /// Where it started.
    pub start: Start,
    /// How it ended.
    pub outcome: Outcome,
    /// The largest `|reading|` over the window, in counts.
    pub peak_counts: f64,
    /// The smallest period of the reading over the window, in samples (`None`: not
    /// periodic within the window, or at rest).
    pub period_samples: Option<usize>,
}

/// The buzz verdict of one wall: one run per start.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub struct BuzzReport {
    /// The runs, in the order of the starts.
    pub runs: Vec<BuzzRun>,
}

impl BuzzReport {
    /// Whether any run ends with the reading still changing (or diverged).
    pub fn sustained(&self) -> bool {
        self.runs.iter().any(|r| r.outcome != Outcome::Rest)
    }

    /// Whether any run diverged.
    pub fn diverged(&self) -> bool {
        self.runs.iter().any(|r| r.outcome == Outcome::Diverged)
    }

    /// The run with the largest sustained peak (the largest peak of all when none is
    /// sustained).
    pub fn worst(&self) -> Option<&BuzzRun> {
        let key = |r: &&BuzzRun| (r.outcome != Outcome::Rest, r.peak_counts);
        self.runs.iter().max_by(|a, b| {
            key(a)
                .partial_cmp(&key(b))
                .unwrap_or(std::cmp::Ordering::Equal)
        })
    }

    /// The largest peak over the window of the sustained runs, in counts (0 when none is).
    pub fn peak_counts(&self) -> f64 {
        self.runs
            .iter()
            .filter(|r| r.outcome != Outcome::Rest)
            .map(|r| r.peak_counts)
            .fold(0.0, f64::max)
    }

    /// The period of the worst run, in samples.
    pub fn period_samples(&self) -> Option<usize> {
        self.worst()
            .filter(|r| r.outcome != Outcome::Rest)
            .and_then(|r| r.period_samples)
    }
}

/// The buzz verdict of `wall` on the loop `lp` with the quantizers and friction `q`: the
/// exact simulation ([`readings`]) from each start of `options`, judged over the window.
///
/// Method: the exact piecewise solution of the sampled loop (the model document,
/// docs/MODEL.md, section 10.1). A run is [`Outcome::Buzz`] when the reading still changes
/// over the window (by any count with an encoder, by more than [`CONTINUOUS_CHANGE`] units
/// without), [`Outcome::Diverged`] beyond [`DIVERGED`] counts, else [`Outcome::Rest`]
/// (possibly stuck at an offset). The period is the smallest `p` with `y_k = y_{k-p}` over
/// the whole window (exact for the integer readings of an encoder; within
/// [`CONTINUOUS_CHANGE`] without one).
///
/// # Errors
///
/// As [`readings`]; invalid options.
pub fn buzz(
    lp: impl Into<Loop>,
    wall: &Wall,
    q: &Quantization,
    options: &BuzzOptions,
) -> Result<BuzzReport> {
    options.validate()?;
    let lp = lp.into();
    let runs = options
        .starts
        .iter()
        .map(|&start| {
            let y = readings(lp, wall, q, start, options.samples)?;
            Ok(judge(start, &y, options, q.encoder))
        })
        .collect::<Result<Vec<_>>>()?;
    Ok(BuzzReport { runs })
}

/// The readings of the run of the protocol from `start` over its judged window (the last
/// `options.window` samples, counts): the limit cycle when the run buzzes. Empty when the
/// run diverged.
///
/// ```
/// use stabound::buzz::{BuzzOptions, Quantization, Start, cycle};
/// use stabound::params::{Plant, Wall};
///
/// let q = Quantization::new(true, 0.0, 0.0, 0.0)?;
/// let w = cycle(&Plant::new(0.1, 1.0)?, &Wall::new(0.02, 0.3)?, &q, Start::Rest(3.0), &BuzzOptions::default())?;
/// assert_eq!(w.len(), 4_000);
/// # Ok::<(), stabound::Error>(())
/// ```
///
/// # Errors
///
/// As [`buzz`].
pub fn cycle(
    lp: impl Into<Loop>,
    wall: &Wall,
    q: &Quantization,
    start: Start,
    options: &BuzzOptions,
) -> Result<Vec<f64>> {
    options.validate()?;
    let mut y = readings(lp, wall, q, start, options.samples)?;
    if y.len() < options.samples + 1 {
        return Ok(Vec::new());
    }
    Ok(y.split_off(y.len() - options.window))
}

/// Outcome, peak and period of one run's readings (`y[0]` is the first sample).
fn judge(start: Start, y: &[f64], options: &BuzzOptions, encoder: bool) -> BuzzRun {
    let last = y.last().copied().unwrap_or(0.0);
    if y.len() < options.samples + 1 || !last.is_finite() || last.abs() > DIVERGED {
        return BuzzRun {
            start,
            outcome: Outcome::Diverged,
            peak_counts: DIVERGED,
            period_samples: None,
        };
    }
    let window = &y[y.len() - options.window..];
    // integer readings compare exactly; continuous ones within the stated change
    let tol = if encoder { 0.0 } else { CONTINUOUS_CHANGE };
    let same = |a: f64, b: f64| (a - b).abs() <= tol;
    let peak = window.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let (lo, hi) = window
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &v| {
            (l.min(v), h.max(v))
        });
    let changes = !same(lo, hi);
    let period = changes
        .then(|| {
            (1..=window.len() / 2)
                .find(|&p| (p..window.len()).all(|k| same(window[k], window[k - p])))
        })
        .flatten();
    BuzzRun {
        start,
        outcome: if changes {
            Outcome::Buzz
        } else {
            Outcome::Rest
        },
        peak_counts: peak,
        period_samples: period,
    }
}
