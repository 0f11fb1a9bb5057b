//! Reading a scene: TOML or JSON, every number with its unit in its key, errors naming the
//! line.

use std::path::Path;

use serde::{Deserialize, Deserializer};

use super::{MAX_SCENE_BYTES, Scene, SceneDevice, SceneFormat, SceneWall};
use crate::elements::{Loop, PhysicalElements, list};
use crate::error::{Error, Result};
use crate::params::{Delay, Device};

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

#[allow(non_snake_case)] // the keys spell units: N (newton) is upper case
struct RawDevice {
    name: Option<String>,
    mass_kg: Positive,
    period_s: Positive,
    damping_Ns_per_m: NonNegative,
    delay_s: Option<NonNegative>,
    delay_samples: Option<NonNegative>,
    /// The loop's elements, each modelled only when named, read by the element list.
    elements: PhysicalElements,
    /// `always_gripped = true`: the hand never lets go of the handle.
    always_gripped: bool,
    wall: Vec<RawWall>,
}

/// The key that keeps the free device out of a device's checks when a hand is named.
const ALWAYS_GRIPPED: &str = "always_gripped";

/// The device's own keys, before the element list's and `wall`.
const DEVICE_KEYS: [&str; 6] = [
    "name",
    "mass_kg",
    "period_s",
    "damping_Ns_per_m",
    "delay_s",
    "delay_samples",
];

/// Every key of a `[[device]]` table, in the order messages list them.
fn device_keys() -> &'static [&'static str] {
    static KEYS: std::sync::LazyLock<Vec<&'static str>> = std::sync::LazyLock::new(|| {
        let mut k = DEVICE_KEYS.to_vec();
        k.extend(list::keys());
        k.push(ALWAYS_GRIPPED);
        k.push("wall");
        k
    });
    KEYS.as_slice()
}

/// A key of a `[[device]]` table: one of [`DEVICE_KEYS`] (by index), an element key, or
/// `wall`; read as an identifier so that an unknown key is refused where it is written.
enum DeviceKey {
    Own(usize),
    Element(&'static list::Param),
    AlwaysGripped,
    Wall,
}

impl<'de> Deserialize<'de> for DeviceKey {
    fn deserialize<D: Deserializer<'de>>(de: D) -> std::result::Result<Self, D::Error> {
        let key = String::deserialize(de)?;
        if let Some(i) = DEVICE_KEYS.iter().position(|k| *k == key) {
            Ok(DeviceKey::Own(i))
        } else if key == "wall" {
            Ok(DeviceKey::Wall)
        } else if key == ALWAYS_GRIPPED {
            Ok(DeviceKey::AlwaysGripped)
        } else {
            list::by_key(&key)
                .map(DeviceKey::Element)
                .ok_or_else(|| serde::de::Error::unknown_field(&key, device_keys()))
        }
    }
}

impl<'de> Deserialize<'de> for RawDevice {
    fn deserialize<D: Deserializer<'de>>(de: D) -> std::result::Result<Self, D::Error> {
        struct Fields;
        impl<'de> serde::de::Visitor<'de> for Fields {
            type Value = RawDevice;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a device table")
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(
                self,
                mut map: A,
            ) -> std::result::Result<RawDevice, A::Error> {
                use serde::de::Error as _;
                let mut name = None;
                let mut numbers: [Option<f64>; 5] = [None; 5];
                let mut elements = PhysicalElements::default();
                let mut wall = None;
                let mut gripped = None;
                let once = |given: bool, key: &'static str| {
                    if given {
                        Err(A::Error::duplicate_field(key))
                    } else {
                        Ok(())
                    }
                };
                while let Some(key) = map.next_key::<DeviceKey>()? {
                    match key {
                        DeviceKey::Own(0) => {
                            once(name.is_some(), "name")?;
                            name = Some(map.next_value::<String>()?);
                        }
                        DeviceKey::Own(i) => {
                            once(numbers[i - 1].is_some(), DEVICE_KEYS[i])?;
                            numbers[i - 1] = Some(match i {
                                1 | 2 => map.next_value::<Positive>()?.0,
                                _ => map.next_value::<NonNegative>()?.0,
                            });
                        }
                        DeviceKey::Element(p) => list::read_entry(p, &mut map, &mut elements)?,
                        DeviceKey::AlwaysGripped => {
                            once(gripped.is_some(), ALWAYS_GRIPPED)?;
                            gripped = Some(map.next_value::<bool>()?);
                        }
                        DeviceKey::Wall => {
                            once(wall.is_some(), "wall")?;
                            wall = Some(map.next_value::<Vec<RawWall>>()?);
                        }
                    }
                }
                let need = |i: usize| {
                    numbers[i - 1].ok_or_else(|| A::Error::missing_field(DEVICE_KEYS[i]))
                };
                Ok(RawDevice {
                    name,
                    mass_kg: Positive(need(1)?),
                    period_s: Positive(need(2)?),
                    damping_Ns_per_m: NonNegative(need(3)?),
                    delay_s: numbers[3].map(NonNegative),
                    delay_samples: numbers[4].map(NonNegative),
                    elements,
                    always_gripped: gripped.unwrap_or(false),
                    wall: wall.unwrap_or_default(),
                })
            }
        }
        de.deserialize_map(Fields)
    }
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

    /// The elements named, checked against `device` (a handle lighter than the device, a
    /// cutoff below Nyquist, ...).
    fn elements(&self, device: &Device) -> std::result::Result<PhysicalElements, String> {
        let e = self.elements;
        e.validate().map_err(|e| e.to_string())?;
        let plant = device.plant().map_err(|e| e.to_string())?;
        Loop::new(plant)
            .with_physical(device, &e)
            .map_err(|e| e.to_string())?;
        Ok(e)
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
        // the accepted keys serde lists after the unknown one, each in backticks
        let same_but_case = rest[end + 1..]
            .split('`')
            .skip(1)
            .step_by(2)
            .find(|k| k.eq_ignore_ascii_case(key));
        if let Some(k) = same_but_case {
            out.push_str(&format!(
                "; did you mean `{k}`? keys are case-sensitive (units as written: `Hz`, `Ns_per_m`)"
            ));
        } else if let Some((_, accepted)) = UNIT_KEYS.iter().find(|(s, _)| *s == stem) {
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
            let device = d.device().and_then(|dev| Ok((dev, d.elements(&dev)?)));
            let (device, elements) = device.map_err(|msg| {
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
                elements,
                always_gripped: d.always_gripped,
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
}

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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_and_column() {
        let t = "ab\ncd\nef";
        assert_eq!(line_col(t, 0), (1, 1));
        assert_eq!(line_col(t, 4), (2, 2));
        assert_eq!(line_col(t, 6), (3, 1));
    }
}
