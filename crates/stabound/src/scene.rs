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
//! For each wall [`Scene::check`] computes, with point tests and exact one-dimensional
//! searches only (never a boundary or a grid):
//!
//! - the verdict (Schur-Cohn with the marginal band of [`crate::stability::Options`]) and the
//!   spectral radius (Schur-Cohn bisection on the radius);
//! - `K_lim(B)`, the largest stable stiffness at this wall's damping, and the stiffness margin
//!   `K / K_lim(B)` (below 1 is stable when the stable stiffnesses at `B` form one interval
//!   `(0, K_lim)`, which is the case in every plant we know of);
//! - the damping intervals that keep this stiffness stable;
//! - the suggested damping, `B*` = the damping at `alpha_max` (see [`WallReport::suggested`]).

use std::path::Path;

use rayon::prelude::*;
use serde::{Deserialize, Deserializer, Serialize};

use crate::error::{Error, Result};
use crate::filter::VelocityFilter;
use crate::params::{Delay, Device, Plant, Wall};
use crate::passivity::Criterion;
use crate::search::{Interval, stable_alphas, stable_betas};
use crate::stability::{Checker, Options, Verdict};

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

// ---------------------------------------------------------------------------------------
// Parsing

/// A finite number that is `> 0`.
struct Positive(f64);
/// A finite number that is `>= 0`.
struct NonNegative(f64);
/// Any finite number.
struct Finite(f64);

fn number<'de, D: Deserializer<'de>>(de: D) -> std::result::Result<f64, D::Error> {
    let v = f64::deserialize(de)?;
    if v.is_finite() {
        Ok(v)
    } else {
        Err(serde::de::Error::custom(format!(
            "{v} is not a finite number"
        )))
    }
}

impl<'de> Deserialize<'de> for Positive {
    fn deserialize<D: Deserializer<'de>>(de: D) -> std::result::Result<Self, D::Error> {
        let v = number(de)?;
        if v > 0.0 {
            Ok(Positive(v))
        } else {
            Err(serde::de::Error::custom(format!(
                "{v} is not accepted: must be greater than 0"
            )))
        }
    }
}

impl<'de> Deserialize<'de> for NonNegative {
    fn deserialize<D: Deserializer<'de>>(de: D) -> std::result::Result<Self, D::Error> {
        let v = number(de)?;
        if v >= 0.0 {
            Ok(NonNegative(v))
        } else {
            Err(serde::de::Error::custom(format!(
                "{v} is not accepted: must be 0 or more"
            )))
        }
    }
}

impl<'de> Deserialize<'de> for Finite {
    fn deserialize<D: Deserializer<'de>>(de: D) -> std::result::Result<Self, D::Error> {
        number(de).map(Finite)
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawScene {
    device: Vec<RawDevice>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)] // the keys spell units: N (newton) is upper case
struct RawWall {
    name: Option<String>,
    stiffness_N_per_m: NonNegative,
    damping_Ns_per_m: Finite,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)] // the keys spell units: N (newton) is upper case
struct RawDevice {
    name: Option<String>,
    mass_kg: Positive,
    period_s: Positive,
    damping_Ns_per_m: NonNegative,
    delay_s: Option<NonNegative>,
    delay_samples: Option<NonNegative>,
    #[serde(default)]
    wall: Vec<RawWall>,
}

impl RawDevice {
    /// The checks that involve several keys: exactly one delay, delay within range.
    fn device(&self) -> std::result::Result<Device, String> {
        let period = self.period_s.0;
        let delay = match (&self.delay_s, &self.delay_samples) {
            (Some(s), None) => Delay::Seconds(s.0),
            (None, Some(n)) => Delay::Samples(n.0),
            (Some(_), Some(_)) => {
                return Err(
                    "both `delay_s` and `delay_samples` are given; give exactly one".into(),
                );
            }
            (None, None) => {
                return Err(
                    "missing delay: give `delay_s` (seconds) or `delay_samples` (sampling periods)"
                        .into(),
                );
            }
        };
        let device = Device {
            mass: self.mass_kg.0,
            period,
            damping: self.damping_Ns_per_m.0,
            delay,
        };
        device.plant().map_err(|e| e.to_string())?;
        Ok(device)
    }
}

/// The line of the `k`-th (from 0) `[[device]]` header of a TOML text, if written that way.
fn device_header_line(text: &str, k: usize) -> Option<usize> {
    text.lines()
        .enumerate()
        .filter(|(_, l)| {
            let t = l.trim_start();
            t.starts_with("[[") && t[2..].trim_start().starts_with("device") && {
                let rest = t[2..].trim_start()["device".len()..].trim_start();
                rest.starts_with("]]")
            }
        })
        .nth(k)
        .map(|(i, _)| i + 1)
}

/// Accepted unit-bearing keys per quantity, to turn "unknown field `mass`" into advice.
const UNIT_KEYS: &[(&str, &str)] = &[
    ("mass", "`mass_kg` (kg)"),
    ("period", "`period_s` (s)"),
    ("sample", "`period_s` (s)"),
    ("sampling", "`period_s` (s)"),
    ("damping", "`damping_Ns_per_m` (N s/m)"),
    (
        "delay",
        "`delay_s` (s) or `delay_samples` (sampling periods)",
    ),
    ("stiffness", "`stiffness_N_per_m` (N/m)"),
];

/// Adds a hint to serde's messages where a key lacks its unit or a number came as a string.
fn advise(message: &str) -> String {
    let mut out = message.to_string();
    if let Some(rest) = message.strip_prefix("unknown field `")
        && let Some(end) = rest.find('`')
    {
        let key = &rest[..end];
        let stem = key.split('_').next().unwrap_or(key).to_ascii_lowercase();
        if let Some((_, accepted)) = UNIT_KEYS.iter().find(|(s, _)| *s == stem) {
            let what = if key.contains('_') {
                "has a unit this file format does not accept"
            } else {
                "has no unit"
            };
            out.push_str(&format!(
                "; `{key}` {what}: the unit is part of the key name, write {accepted}"
            ));
        }
    } else if message.starts_with("invalid type: string") {
        out.push_str("; write a plain number: the unit is part of the key name (`mass_kg = 0.1`)");
    }
    out
}

/// `(line, column)`, both from 1, of byte offset `at` in `text`.
fn line_col(text: &str, at: usize) -> (usize, usize) {
    let at = at.min(text.len());
    let before = &text.as_bytes()[..at];
    let line = before.iter().filter(|&&b| b == b'\n').count() + 1;
    let start = before
        .iter()
        .rposition(|&b| b == b'\n')
        .map_or(0, |p| p + 1);
    let col = text[start..at].chars().count() + 1;
    (line, col)
}

fn parse_error(text: &str, origin: &str, line: Option<(usize, usize)>, message: &str) -> Error {
    let at = match line {
        Some((l, c)) => {
            // Quote the line (it names the key, which serde's value errors do not).
            let src = text.lines().nth(l - 1).unwrap_or("").trim();
            if src.is_empty() || src.chars().count() > 80 {
                format!("{origin}: line {l}, column {c}")
            } else {
                format!("{origin}: line {l}, column {c} `{src}`")
            }
        }
        None => origin.to_string(),
    };
    Error::InvalidRequest(format!("{at}: {}", advise(message.trim())))
}

impl Scene {
    /// Parses and validates a scene. `origin` names the input in error messages (a path).
    ///
    /// Errors are [`Error::InvalidRequest`] naming `origin`, the line and column, and what is
    /// accepted.
    pub fn parse(text: &str, format: SceneFormat, origin: &str) -> Result<Scene> {
        let raw: RawScene = match format {
            SceneFormat::Toml => toml::from_str(text).map_err(|e| {
                let pos = e.span().map(|s| line_col(text, s.start));
                parse_error(text, origin, pos, e.message())
            })?,
            SceneFormat::Json => serde_json::from_str(text).map_err(|e| {
                // serde_json appends " at line L column C" to its message; we put the
                // position first, like for TOML.
                let full = e.to_string();
                let suffix = format!(" at line {} column {}", e.line(), e.column());
                let msg = full.strip_suffix(&suffix).unwrap_or(&full);
                let pos = (e.line() > 0).then(|| (e.line(), e.column()));
                parse_error(text, origin, pos, msg)
            })?,
        };
        if raw.device.is_empty() {
            return Err(Error::InvalidRequest(format!(
                "{origin}: the scene has no device; add a [[device]] table"
            )));
        }
        let mut devices = Vec::with_capacity(raw.device.len());
        for (i, d) in raw.device.into_iter().enumerate() {
            let name = d
                .name
                .clone()
                .unwrap_or_else(|| format!("device {}", i + 1));
            let device = d.device().map_err(|msg| {
                let at = match format {
                    SceneFormat::Toml => device_header_line(text, i)
                        .map(|l| format!(" (line {l})"))
                        .unwrap_or_default(),
                    SceneFormat::Json => String::new(),
                };
                Error::InvalidRequest(format!("{origin}: device {} \"{name}\"{at}: {msg}", i + 1))
            })?;
            let walls = d
                .wall
                .into_iter()
                .enumerate()
                .map(|(j, w)| SceneWall {
                    name: w.name.unwrap_or_else(|| format!("wall {}", j + 1)),
                    stiffness: w.stiffness_N_per_m.0,
                    damping: w.damping_Ns_per_m.0,
                })
                .collect();
            devices.push(SceneDevice {
                name,
                device,
                walls,
            });
        }
        Ok(Scene { devices })
    }

    /// Reads and parses a scene file; `.json` files are JSON, anything else TOML. Only a
    /// regular file of at most [`MAX_SCENE_BYTES`] is read (a FIFO would block, a device
    /// such as `/dev/zero` never end).
    pub fn read(path: &Path) -> Result<Scene> {
        let text = read_regular(path, MAX_SCENE_BYTES)?;
        Scene::parse(
            &text,
            SceneFormat::from_path(path),
            &path.display().to_string(),
        )
    }

    /// The number of walls over all devices.
    pub fn wall_count(&self) -> usize {
        self.devices.iter().map(|d| d.walls.len()).sum()
    }

    /// Checks every wall (module doc): walls in parallel, results in file order whatever the
    /// number of threads.
    ///
    /// `limit` gives each device's maximum stable stiffness and the damping where it is
    /// reached, `(alpha_max, beta_at_max)` in normalized form, or `None` to leave the
    /// suggested damping out. The scene does not compute it itself: pass the crate's
    /// `alpha_max` ([`Scene::check`] does) or any other source.
    pub fn check_with<F>(&self, options: &Options, limit: F) -> Result<SceneReport>
    where
        F: Fn(&Plant) -> Result<Option<(f64, f64)>> + Sync,
    {
        options.validate()?;
        let mut checkers = Vec::with_capacity(self.devices.len());
        for d in &self.devices {
            let plant = d.device.plant()?;
            let checker = Checker::new(&plant, *options)?;
            let lim = limit(&plant)?;
            checkers.push((plant, checker, lim));
        }
        let jobs: Vec<(usize, &SceneWall)> = self
            .devices
            .iter()
            .enumerate()
            .flat_map(|(i, d)| d.walls.iter().map(move |w| (i, w)))
            .collect();
        let walls: Vec<WallReport> = jobs
            .par_iter()
            .map(|&(i, w)| {
                let (_, checker, lim) = &checkers[i];
                check_wall(&self.devices[i].device, checker, *lim, w)
            })
            .collect::<Result<_>>()?;
        let mut walls = walls.into_iter();
        let devices = self
            .devices
            .iter()
            .zip(&checkers)
            .map(|(d, (plant, _, lim))| DeviceReport {
                name: d.name.clone(),
                mass: d.device.mass(),
                period: d.device.period(),
                damping: d.device.damping(),
                delay: plant.d() * d.device.period(),
                delta: plant.delta(),
                d: plant.d(),
                max_stiffness: lim.map(|(a, b)| MaxStiffness {
                    stiffness: d.device.stiffness(a),
                    damping: d.device.wall_damping(b),
                    alpha: a,
                    beta: b,
                }),
                walls: walls.by_ref().take(d.walls.len()).collect(),
            })
            .collect();
        Ok(SceneReport {
            margin: options.margin,
            devices,
        })
    }
}

fn check_wall(
    device: &Device,
    checker: &Checker,
    limit: Option<(f64, f64)>,
    w: &SceneWall,
) -> Result<WallReport> {
    let wall: Wall = device.wall(w.stiffness, w.damping)?;
    let verdict = checker.verdict(&wall)?;
    let spectral_radius = checker.spectral_radius_schur_cohn(&wall);
    let plant = checker.poly().plant();
    // Colgate-Schenkel with the device's delay (docs/MODEL.md section 9); a fractional delay
    // is outside the criterion, so there is no answer rather than a guess
    let passive = match Criterion::new(plant.d(), VelocityFilter::none()) {
        Ok(crit) => Some(crit.is_passive(plant.delta(), &wall)?),
        Err(_) => None,
    };
    let alphas = stable_alphas(checker, wall.beta())?;
    let alpha_limit = alphas.last().map(|i| i.hi);
    let betas = stable_betas(checker, wall.alpha())?;
    let to_b = |i: &Interval| Range {
        lo: device.wall_damping(i.lo),
        hi: device.wall_damping(i.hi),
        lo_normalized: i.lo,
        hi_normalized: i.hi,
    };
    let suggested = limit.map(|(alpha_max, beta_at_max)| Suggestion {
        damping: device.wall_damping(beta_at_max),
        beta: beta_at_max,
        stiffness_margin: wall.alpha() / alpha_max,
    });
    Ok(WallReport {
        name: w.name.clone(),
        stiffness: w.stiffness,
        damping: w.damping,
        alpha: wall.alpha(),
        beta: wall.beta(),
        verdict,
        spectral_radius,
        stiffness_limit: alpha_limit.map(|a| device.stiffness(a)),
        alpha_limit,
        stiffness_margin: alpha_limit.map(|a| wall.alpha() / a),
        stable_stiffness_pieces: alphas.len(),
        damping_intervals: betas.iter().map(to_b).collect(),
        suggested,
        passive,
    })
}

// ---------------------------------------------------------------------------------------
// Report

/// The result of checking a scene, in file order.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SceneReport {
    /// The marginal band used for verdicts.
    pub margin: f64,
    /// One report per device.
    pub devices: Vec<DeviceReport>,
}

/// The maximum stable stiffness of a device over all dampings, and where it is reached.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct MaxStiffness {
    /// `K_max` in N/m.
    pub stiffness: f64,
    /// The damping `B*` in N s/m at which `K_max` is reached.
    pub damping: f64,
    /// `alpha_max`.
    pub alpha: f64,
    /// `beta` at `alpha_max`.
    pub beta: f64,
}

/// One device's results.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DeviceReport {
    /// The device's name.
    pub name: String,
    /// Mass in kg.
    pub mass: f64,
    /// Sampling period in s.
    pub period: f64,
    /// Physical damping in N s/m.
    pub damping: f64,
    /// Delay in s (`d T`).
    pub delay: f64,
    /// Normalized physical damping `delta = b T / m`.
    pub delta: f64,
    /// Delay factor `d`.
    pub d: f64,
    /// `K_max` and `B*`, when a limit source was given.
    pub max_stiffness: Option<MaxStiffness>,
    /// One report per wall, in file order.
    pub walls: Vec<WallReport>,
}

/// An open interval of dampings in N s/m, with its normalized form.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Range {
    /// Lower end in N s/m (not itself stable).
    pub lo: f64,
    /// Upper end in N s/m (not itself stable).
    pub hi: f64,
    /// Lower end as `beta`.
    pub lo_normalized: f64,
    /// Upper end as `beta`.
    pub hi_normalized: f64,
}

/// The damping that gives the largest stiffness margin.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Suggestion {
    /// `B*` in N s/m.
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
    pub stiffness: f64,
    /// Virtual damping `B` in N s/m.
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
}

impl Scene {
    /// Checks every wall, with each device's maximum stiffness and the suggested damping
    /// from [`crate::amax::alpha_max`] (one direct search per device).
    pub fn check(&self, options: &Options) -> Result<SceneReport> {
        self.check_with(options, |plant| {
            let a = crate::amax::alpha_max(plant, &crate::amax::AmaxOptions::default())?;
            Ok(Some((a.alpha_max, a.beta_at_max)))
        })
    }
}

// ---------------------------------------------------------------------------------------
// Text

/// `x` with 6 significant digits, trailing zeros dropped; `e` notation outside `[1e-4, 1e9)`.
pub(crate) fn sig6(x: f64) -> String {
    if !x.is_finite() {
        return if x.is_nan() {
            "nan".into()
        } else if x > 0.0 {
            "inf".into()
        } else {
            "-inf".into()
        };
    }
    let a = x.abs();
    // Values below 5e-13 in magnitude are zeros left by rounding in sums of order 1.
    if a < 5e-13 {
        return "0".into();
    }
    if !(1e-4..1e9).contains(&a) {
        let s = format!("{x:.5e}");
        let (m, e) = s.split_once('e').unwrap_or((&s, "0"));
        let m = trim_zeros(m);
        return format!("{m}e{e}");
    }
    let digits = a.log10().floor() as i32;
    if digits > 5 {
        // Integers of 7 to 9 digits: round away the digits past the sixth.
        let unit = 10f64.powi(digits - 5);
        return format!("{:.0}", (x / unit).round() * unit);
    }
    let decimals = (5 - digits) as usize;
    trim_zeros(&format!("{x:.decimals$}")).to_string()
}

fn trim_zeros(s: &str) -> &str {
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.')
    } else {
        s
    }
}

/// The largest scene file [`Scene::read`] reads: 16 MiB, about 100,000 walls, far more
/// than a haptic scene has.
pub const MAX_SCENE_BYTES: u64 = 16 << 20;

/// Reads `path` as UTF-8 text if it is a regular file of at most `cap` bytes.
fn read_regular(path: &Path, cap: u64) -> Result<String> {
    use std::io::Read;
    let bad =
        |why: String| Error::InvalidRequest(format!("cannot read scene {}: {why}", path.display()));
    // stat before open: opening a FIFO to read blocks until someone writes to it
    let regular = |m: std::fs::Metadata| {
        if m.is_file() {
            Ok(())
        } else {
            Err(bad("not a regular file; give a scene file".into()))
        }
    };
    regular(std::fs::metadata(path).map_err(|e| bad(format!("{e}; check the path")))?)?;
    let file = std::fs::File::open(path).map_err(|e| bad(format!("{e}; check the path")))?;
    regular(file.metadata().map_err(|e| bad(e.to_string()))?)?;
    let mut text = String::new();
    file.take(cap + 1)
        .read_to_string(&mut text)
        .map_err(|e| bad(e.to_string()))?;
    if text.len() as u64 > cap {
        return Err(bad(format!(
            "larger than {} MiB; split the scene into several files",
            cap >> 20
        )));
    }
    Ok(text)
}

impl SceneReport {
    /// A plain-text report: one block per device, one per wall, physical units first and
    /// normalized values in parentheses, 6 significant digits.
    pub fn to_text(&self) -> String {
        use std::fmt::Write;
        let mut s = String::new();
        let walls: usize = self.devices.iter().map(|d| d.walls.len()).sum();
        let _ = writeln!(
            s,
            "scene: {} device(s), {} wall(s); verdicts by Schur-Cohn with marginal band +-{:e}",
            self.devices.len(),
            walls,
            self.margin
        );
        for d in &self.devices {
            let _ = writeln!(
                s,
                "\ndevice {}: m = {} kg, T = {} s, b = {} N s/m, delay {} samples = {} s",
                crate::export::text::quoted(&d.name),
                sig6(d.mass),
                sig6(d.period),
                sig6(d.damping),
                sig6(d.d),
                sig6(d.delay)
            );
            let _ = writeln!(
                s,
                "  normalized: delta = {}, d = {}",
                sig6(d.delta),
                sig6(d.d)
            );
            if let Some(m) = &d.max_stiffness {
                let _ = writeln!(
                    s,
                    "  K_max = {} N/m at B* = {} N s/m (alpha_max = {}, beta* = {})",
                    sig6(m.stiffness),
                    sig6(m.damping),
                    sig6(m.alpha),
                    sig6(m.beta)
                );
            }
            for w in &d.walls {
                let _ = writeln!(
                    s,
                    "\n  wall {}: {}",
                    crate::export::text::quoted(&w.name),
                    w.verdict.name()
                );
                let _ = writeln!(
                    s,
                    "    K = {} N/m, B = {} N s/m (alpha = {}, beta = {})",
                    sig6(w.stiffness),
                    sig6(w.damping),
                    sig6(w.alpha),
                    sig6(w.beta)
                );
                let _ = writeln!(s, "    spectral radius {:.9}", w.spectral_radius);
                let _ = writeln!(
                    s,
                    "    passive: {}",
                    match w.passive {
                        Some(true) => "yes",
                        Some(false) => "no",
                        None => "not defined for a fractional delay",
                    }
                );
                match (w.stiffness_limit, w.alpha_limit, w.stiffness_margin) {
                    (Some(k), Some(a), Some(m)) => {
                        let pieces = if w.stable_stiffness_pieces > 1 {
                            format!(
                                " [stable stiffnesses at this B form {} intervals]",
                                w.stable_stiffness_pieces
                            )
                        } else {
                            String::new()
                        };
                        let _ = writeln!(
                            s,
                            "    K_lim(B) = {} N/m (alpha {}); stiffness margin K/K_lim = {}{}",
                            sig6(k),
                            sig6(a),
                            sig6(m),
                            pieces
                        );
                    }
                    _ => {
                        let _ = writeln!(s, "    K_lim(B): no stiffness is stable at this B");
                    }
                }
                if w.damping_intervals.is_empty() {
                    let _ = writeln!(s, "    stable B for this K: none");
                } else {
                    let phys: Vec<String> = w
                        .damping_intervals
                        .iter()
                        .map(|r| format!("{} < B < {}", sig6(r.lo), sig6(r.hi)))
                        .collect();
                    let norm: Vec<String> = w
                        .damping_intervals
                        .iter()
                        .map(|r| {
                            format!(
                                "{} < beta < {}",
                                sig6(r.lo_normalized),
                                sig6(r.hi_normalized)
                            )
                        })
                        .collect();
                    let _ = writeln!(
                        s,
                        "    stable B for this K: {} N s/m ({})",
                        phys.join(" or "),
                        norm.join(" or ")
                    );
                }
                if let Some(g) = &w.suggested {
                    let _ = writeln!(
                        s,
                        "    suggested B* = {} N s/m (beta* = {}): K/K_max = {}{}",
                        sig6(g.damping),
                        sig6(g.beta),
                        sig6(g.stiffness_margin),
                        if g.stiffness_margin >= 1.0 {
                            " (no damping makes this K stable: lower K)"
                        } else {
                            ""
                        }
                    );
                }
            }
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn six_digits() {
        assert_eq!(sig6(14450.0), "14450");
        assert_eq!(sig6(0.1445), "0.1445");
        assert_eq!(sig6(1.0 / 3.0), "0.333333");
        assert_eq!(sig6(-42.5), "-42.5");
        assert_eq!(sig6(0.0), "0");
        assert_eq!(sig6(1e-17), "0");
        assert_eq!(sig6(2.5e-6), "2.5e-6");
        assert_eq!(sig6(123456789.0), "123457000");
        assert_eq!(sig6(f64::INFINITY), "inf");
    }

    #[test]
    fn line_and_column() {
        let t = "ab\ncd\nef";
        assert_eq!(line_col(t, 0), (1, 1));
        assert_eq!(line_col(t, 4), (2, 2));
        assert_eq!(line_col(t, 6), (3, 1));
    }
}
