//! Scenes: a file of devices and the virtual walls each renders, checked wall by wall.
//!
//! A scene is TOML (or JSON with the same structure). Every number carries its unit in its
//! key name; a key without a unit (`mass = 0.1`) or with another unit (`mass_g = 100`) is an
//! error naming the line.
//!
//! ```toml
//! [[device]]
//! name = "PHANToM-like"        # optional
//! mass_kg = 0.1
//! period_s = 0.001
//! damping_Ns_per_m = 0.0       # physical damping b
//! delay_samples = 1            # or delay_s = 0.001 (exactly one of the two)
//!
//! [[device.wall]]
//! name = "table top"           # optional
//! stiffness_N_per_m = 5000.0
//! damping_Ns_per_m = 20.0      # virtual damping B
//! ```
//!
//! A device may name the parts of its loop, each in physical units with the unit in the
//! key; only what it names is modelled (the model document, docs/MODEL.md, section 8):
//!
//! ```toml
//! hand_mass_kg = 0.2                   # operator hand (any of its three)
//! hand_damping_Ns_per_m = 1.0
//! hand_stiffness_N_per_m = 50.0
//! handle_mass_kg = 0.03                # compliant transmission (mass and stiffness)
//! transmission_stiffness_N_per_m = 2e5
//! transmission_damping_Ns_per_m = 5.0
//! handle_damping_Ns_per_m = 0.5        # the handle's share of damping_Ns_per_m (or
//!                                      # motor_damping_Ns_per_m; the other side the rest)
//! encoder = "motor"                    # or "handle"
//! actuator_time_constant_s = 2e-4      # actuator lag
//! velocity_filter_cutoff_Hz = 30.0     # or velocity_filter_samples = 4 (moving average)
//! encoder_resolution_m = 1e-5          # quantizers and dry friction: each wall then gets
//! force_resolution_N = 0.01            # the buzz verdict (crate::buzz)
//! coulomb_friction_N = 0.05
//! static_friction_N = 0.08
//! ```
//!
//! A device may be a set of devices (the model document, section 12): every parameter the
//! command line takes as an interval `LO..HI` or a finite set `one-of:LIST` (the mass, the
//! damping, the delay, each number of an element) may be a two-element array `[lo, hi]`,
//! every number between in the set, or a table `{ one_of = [a, b, ...] }`, each of those
//! numbers and none between (a two-element array is always an interval; a list of two is
//! `{ one_of = [a, b] }`). Each wall is then judged for every member (stable for all, or a
//! member that fails),
//! and the device's optimum is the robust one with its binding member ([`SetReport`]); with
//! a hand, the device let go is a member unless `always_gripped = true`.
//!
//! ```toml
//! delay_samples = [1, 3]               # a delay that jitters between 1 and 3 samples
//! hand_mass_kg = [0.2, 0.5]            # hands of different users
//! velocity_filter_cutoff_Hz = { one_of = [30, 60] }  # a cutoff set per product
//! ```
//!
//! For each wall [`Scene::check`] computes, with point tests and exact one-dimensional
//! searches only (never a boundary or a grid):
//!
//! - the verdict (Schur-Cohn with the marginal band of [`crate::stability::Options`]) and the
//!   spectral radius (Schur-Cohn bisection on the radius);
//! - `K_lim(B)`, the largest stable stiffness at this wall's damping, and the stiffness margin
//!   `K / K_lim(B)` (below 1 is stable when the stable stiffnesses at `B` form one interval
//!   `(0, K_lim)`, which is the case in every plant we know of);
//! - the damping intervals that keep this stiffness stable;
//! - the suggested damping, `B*` = the damping at `alpha_max` (see [`WallReport::suggested`]);
//! - with quantizers or friction named, the buzz verdict (see [`WallReport::buzz`]).

mod check;
mod parse;
mod report;

use std::path::Path;

use serde::Serialize;

use crate::elements::PhysicalElements;
use crate::params::Device;
use crate::robust::DeviceSet;

fn is_bare(e: &PhysicalElements) -> bool {
    !e.any()
}

fn describe_set<S: serde::Serializer>(
    set: &Option<DeviceSet>,
    s: S,
) -> std::result::Result<S::Ok, S::Error> {
    s.collect_seq(set.iter().flat_map(DeviceSet::describe))
}
use crate::stability::Verdict;
/// The input format of a scene.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SceneFormat {
    /// TOML (the default).
    Toml,
    /// JSON with the same structure.
    Json,
}

impl SceneFormat {
    /// `Json` for a path ending in `.json` (any case), `Toml` otherwise.
    pub fn from_path(path: &Path) -> Self {
        match path.extension().and_then(|e| e.to_str()) {
            Some(e) if e.eq_ignore_ascii_case("json") => SceneFormat::Json,
            _ => SceneFormat::Toml,
        }
    }
}

/// A parsed, validated scene: devices with their walls, in file order.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Scene {
    /// The devices, in file order.
    pub devices: Vec<SceneDevice>,
}

/// One device of a scene.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SceneDevice {
    /// Its name (`device N`, counted from 1, when the file gives none).
    pub name: String,
    /// The device in physical units (validated; a delay in seconds within `1e-9` samples of
    /// a whole number of samples is stored as that whole number, see [`crate::params::WHOLE_SAMPLE_TOL`]).
    pub device: Device,
    /// The loop's elements the device names (none: the paper's loop; a set's smallest value
    /// where the file spreads a parameter).
    #[serde(skip_serializing_if = "is_bare")]
    pub elements: PhysicalElements,
    /// The set of devices the file gives when it spreads parameters over intervals (a
    /// two-element array `[lo, hi]`, e.g. `delay_samples = [1, 3]`) or finite sets
    /// (`delay_samples = { one_of = [1, 2, 3] }`): every wall is then
    /// judged for every member ([`SetReport`]). `None`: one device (and, with a hand, the
    /// device let go). Written as the set's description.
    #[serde(
        skip_serializing_if = "Option::is_none",
        serialize_with = "describe_set"
    )]
    pub set: Option<DeviceSet>,
    /// Whether the hand never lets go of the handle (`always_gripped = true`): otherwise a
    /// device that names a hand is also checked with the hand let go (the model document,
    /// section 12).
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub always_gripped: bool,
    /// Whether only walls with nonnegative virtual damping may be recommended (scene key
    /// `nonnegative_wall_damping = true`): `K_max` and `B*` are then over `B >= 0`.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub nonnegative_wall_damping: bool,
    /// Its walls, in file order.
    pub walls: Vec<SceneWall>,
}

/// One wall of a scene, in physical units.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SceneWall {
    /// Its name (`wall N`, counted from 1 within its device, when the file gives none).
    pub name: String,
    /// Stiffness `K` in N/m (`>= 0`).
    pub stiffness: f64,
    /// Virtual damping `B` in N s/m (any finite value; negative damping is legitimate).
    pub damping: f64,
}

/// The result of checking a scene, in file order.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SceneReport {
    /// The marginal band used for verdicts.
    #[serde(rename = "marginal_band")]
    pub margin: f64,
    /// One report per device.
    pub devices: Vec<DeviceReport>,
}

/// The maximum stable stiffness of a device over all dampings, and where it is reached.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct MaxStiffness {
    /// `K_max` in N/m.
    #[serde(rename = "K_max_N_per_m")]
    pub stiffness: f64,
    /// The damping `B*` in N s/m at which `K_max` is reached.
    #[serde(rename = "B_at_max_Ns_per_m")]
    pub damping: f64,
    /// `alpha_max`.
    #[serde(rename = "alpha_max")]
    pub alpha: f64,
    /// `beta` at `alpha_max`.
    #[serde(rename = "beta_at_max")]
    pub beta: f64,
    /// When `B*` is negative, the largest stable stiffness with `B >= 0` and where it is
    /// reached; `None` when `B* >= 0` (or the device requires `B >= 0`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub nonnegative: Option<Optimum>,
}

/// A stiffness and the damping where it is reached, physical and normalized.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Optimum {
    /// Stiffness in N/m.
    pub stiffness: f64,
    /// Damping in N s/m.
    pub damping: f64,
    /// `alpha`.
    pub alpha: f64,
    /// `beta`.
    pub beta: f64,
}

/// One device's results.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DeviceReport {
    /// The device's name.
    pub name: String,
    /// Mass in kg.
    #[serde(rename = "mass_kg")]
    pub mass: f64,
    /// Sampling period in s.
    #[serde(rename = "period_s")]
    pub period: f64,
    /// Physical damping in N s/m.
    #[serde(rename = "damping_Ns_per_m")]
    pub damping: f64,
    /// Delay in s (`d T`).
    #[serde(rename = "delay_s")]
    pub delay: f64,
    /// Normalized physical damping `delta = b T / m`.
    pub delta: f64,
    /// Delay factor `d`.
    pub d: f64,
    /// The loop's elements modelled (empty: the paper's loop).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub elements: Vec<&'static str>,
    /// What was assumed about a hand the device names (`None`: no hand named): the device
    /// with the hand on the handle, then the same device with the hand let go, each with
    /// the file's walls; or the hand always on the handle (`always_gripped = true`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub hand: Option<&'static str>,
    /// `K_max` and `B*`, when a limit source was given.
    pub max_stiffness: Option<MaxStiffness>,
    /// Whether the device requires nonnegative wall damping (`K_max` and `B*` over `B >= 0`).
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub nonnegative_wall_damping: bool,
    /// One report per wall, in file order (empty for a set of devices: see `set`).
    pub walls: Vec<WallReport>,
    /// For a device whose file spreads parameters over intervals or lists, the answers for
    /// the whole set; the fields above then describe its reference member (every interval at
    /// its low end, every list at its smallest value), whose mass normalizes the set's
    /// `alpha` and `beta`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub set: Option<SetReport>,
}

/// The answers of a scene device that is a set of devices (docs/MODEL.md section 12), as
/// `check`, `amax` and `table` give them for a set: each wall stable for every member or the
/// member that fails, and the robust optimum with the members that bind it.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[non_exhaustive]
pub struct SetReport {
    /// The parameters spread and the hand's assumption ([`DeviceSet::describe`]).
    pub spread: Vec<String>,
    /// The robust optimum ([`crate::robust::robust_alpha_max`]): over `B >= 0` when the
    /// device requires nonnegative wall damping.
    pub optimum: RobustOptimum,
    /// One verdict per wall, in file order.
    pub walls: Vec<SetWallReport>,
}

/// The largest stiffness for which one damping is stable for every member of a set.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[non_exhaustive]
pub struct RobustOptimum {
    /// The robust `K_max` in N/m (the max-min the search found).
    #[serde(rename = "K_max_N_per_m")]
    pub stiffness: f64,
    /// The damping `B*` in N s/m where it is reached.
    #[serde(rename = "B_at_max_Ns_per_m")]
    pub damping: f64,
    /// The robust `alpha_max` (reference normalization).
    pub alpha_max: f64,
    /// `beta` at the optimum.
    pub beta_at_max: f64,
    /// The stiffness shown stable at `B*` for every member, N/m.
    #[serde(rename = "K_verified_N_per_m")]
    pub stiffness_verified: f64,
    /// The same as `alpha`.
    pub alpha_verified: f64,
    /// How it was shown ([`crate::robust::Verification::describe`]).
    pub verification: String,
    /// Whether it was shown (exactly, or by the sampling argument).
    pub verified: bool,
    /// The members that bind the optimum ([`DeviceSet::describe_member`]).
    pub binding: Vec<String>,
    /// How many members' stable sets were computed.
    pub members_examined: usize,
}

/// One wall judged for every member of a set.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[non_exhaustive]
pub struct SetWallReport {
    /// The wall's name.
    pub name: String,
    /// Stiffness `K` in N/m.
    #[serde(rename = "stiffness_N_per_m")]
    pub stiffness: f64,
    /// Virtual damping `B` in N s/m.
    #[serde(rename = "wall_damping_Ns_per_m")]
    pub damping: f64,
    /// `alpha` in the reference normalization.
    pub alpha: f64,
    /// `beta` in the reference normalization.
    pub beta: f64,
    /// The verdict for the set: stable when stable for every member, else the failing
    /// member's verdict (marginal when the sampling left it undecided).
    pub verdict: Verdict,
    /// Whether the wall was shown stable for every member.
    pub for_every_member: bool,
    /// How the verdict was reached ([`crate::robust::RobustCheck::describe`]).
    pub verification: String,
    /// A member on which the wall is not stable.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub failing_member: Option<String>,
}

/// An open interval of dampings in N s/m, with its normalized form.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Range {
    /// Lower end in N s/m (not itself stable).
    #[serde(rename = "lo_Ns_per_m")]
    pub lo: f64,
    /// Upper end in N s/m (not itself stable).
    #[serde(rename = "hi_Ns_per_m")]
    pub hi: f64,
    /// Lower end as `beta`.
    #[serde(rename = "lo_beta")]
    pub lo_normalized: f64,
    /// Upper end as `beta`.
    #[serde(rename = "hi_beta")]
    pub hi_normalized: f64,
}

/// The damping that gives the largest stiffness margin.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Suggestion {
    /// `B*` in N s/m.
    #[serde(rename = "wall_damping_Ns_per_m")]
    pub damping: f64,
    /// `beta*`.
    pub beta: f64,
    /// The stiffness margin at `B*`: `K / K_lim(B*) = K / K_max`.
    pub stiffness_margin: f64,
}

/// One wall's results.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct WallReport {
    /// The wall's name.
    pub name: String,
    /// Stiffness `K` in N/m.
    #[serde(rename = "stiffness_N_per_m")]
    pub stiffness: f64,
    /// Virtual damping `B` in N s/m.
    #[serde(rename = "wall_damping_Ns_per_m")]
    pub damping: f64,
    /// `alpha = K T^2 / m`.
    pub alpha: f64,
    /// `beta = B T / m`.
    pub beta: f64,
    /// Stable, marginal or unstable.
    pub verdict: Verdict,
    /// Largest root modulus (Schur-Cohn bisection on the radius, `1e-13` relative).
    pub spectral_radius: f64,
    /// `K_lim(B)` in N/m: the largest stable stiffness at this damping; `None` if none is.
    #[serde(rename = "K_lim_N_per_m")]
    pub stiffness_limit: Option<f64>,
    /// `K_lim(B)` as `alpha`.
    pub alpha_limit: Option<f64>,
    /// `K / K_lim(B)`; below 1 means this stiffness is below the limit.
    pub stiffness_margin: Option<f64>,
    /// How many separate intervals the stable stiffnesses at this damping form (1 in every
    /// plant we know of; 0 when none is stable).
    pub stable_stiffness_pieces: usize,
    /// The dampings that keep this stiffness stable, sorted; empty if none does.
    pub damping_intervals: Vec<Range>,
    /// The damping with the largest stiffness margin (module doc), when the device's
    /// maximum stiffness was computed.
    ///
    /// Choice and justification: the margin `K / K_lim(B)` is smallest where `K_lim(B)` is
    /// largest, and the largest `K_lim(B)` over all `B` is by definition `K_max` =
    /// `alpha_max`, reached at `beta*`. So `B*` is the same for every wall of a device, and
    /// the margin there is `K / K_max`. When `K < K_max`, `B*` lies in the damping interval
    /// of this stiffness; when `K >= K_max` no damping makes the wall stable and `B*` is the
    /// damping that comes closest.
    pub suggested: Option<Suggestion>,
    /// Whether the wall is passive with the device's delay (Colgate and Schenkel's criterion,
    /// `docs/MODEL.md` section 9); `None` for a fractional delay, where the criterion does
    /// not apply.
    pub passive: Option<bool>,
    /// The buzz verdict (the exact simulation of [`crate::buzz::buzz`] under its default
    /// protocol) when the device names an encoder or force resolution or a friction.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub buzz: Option<WallBuzz>,
}

/// A wall's buzz verdict in a scene report.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[non_exhaustive]
pub struct WallBuzz {
    /// Whether any start ends with the reading still changing (or diverged).
    pub sustained: bool,
    /// Whether any start diverged.
    pub diverged: bool,
    /// The largest peak of the sustained runs over the window, counts (0 when none is).
    pub peak_counts: f64,
    /// The period of the worst run, samples.
    pub period_samples: Option<usize>,
    /// One run per start of the protocol.
    pub runs: Vec<crate::buzz::BuzzRun>,
}

impl From<crate::buzz::BuzzReport> for WallBuzz {
    fn from(b: crate::buzz::BuzzReport) -> Self {
        Self {
            sustained: b.sustained(),
            diverged: b.diverged(),
            peak_counts: b.peak_counts(),
            period_samples: b.period_samples(),
            runs: b.runs,
        }
    }
}

/// The largest scene file [`Scene::read`] reads: 16 MiB, about 100,000 walls, far more
/// than a haptic scene has.
pub const MAX_SCENE_BYTES: u64 = 16 << 20;
