//! Reading a scene: TOML or JSON, every number with its unit in its key, errors naming the
//! line.

use std::path::Path;

use serde::{Deserialize, Deserializer};

use super::{MAX_SCENE_BYTES, Scene, SceneDevice, SceneFormat, SceneWall};
use crate::elements::list::{self, Accepts, Value};
use crate::elements::{Loop, PhysicalElements};
use crate::error::{Error, Result};
use crate::params::{Delay, Device};
use crate::robust::{DeviceSet, Quantity, Spread};

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

/// `v` when it is `> 0`.
fn positive(v: f64) -> std::result::Result<f64, String> {
    if v > 0.0 {
        Ok(v)
    } else {
        Err(format!("{v} is not accepted: must be greater than 0"))
    }
}

/// `v` when it is `>= 0`.
fn non_negative(v: f64) -> std::result::Result<f64, String> {
    if v >= 0.0 {
        Ok(v)
    } else {
        Err(format!("{v} is not accepted: must be 0 or more"))
    }
}

impl<'de> Deserialize<'de> for NonNegative {
    fn deserialize<D: Deserializer<'de>>(de: D) -> std::result::Result<Self, D::Error> {
        non_negative(number(de)?)
            .map(NonNegative)
            .map_err(serde::de::Error::custom)
    }
}

/// A value of a set of devices (docs/MODEL.md section 12): one number, or a two-element
/// array `[lo, hi]` for every number from `lo` to `hi`, or a table `{ one_of = [a, b, ...] }`
/// for each of those numbers (a finite set), each number checked by `accept` (which returns
/// the message to show) where it is written. `[x, x]` and `{ one_of = [x] }` are the one
/// number `x`.
struct RangedSeed<'a> {
    /// The quantity's name, for the messages.
    name: &'a str,
    accept: &'a dyn Fn(f64) -> std::result::Result<f64, String>,
    /// Why this quantity takes one number only, when it does (an array is then refused).
    single: Option<&'a str>,
}

/// The key of a finite set in a scene: `delay_samples = { one_of = [1, 2, 3] }`.
const ONE_OF: &str = "one_of";

impl RangedSeed<'_> {
    /// `v` when it is finite and accepted.
    fn accepted(&self, v: f64) -> std::result::Result<f64, String> {
        if !v.is_finite() {
            return Err(format!("{v} is not a finite number"));
        }
        (self.accept)(v)
    }
}

impl<'de> serde::de::DeserializeSeed<'de> for RangedSeed<'_> {
    type Value = Spread;
    fn deserialize<D: Deserializer<'de>>(self, de: D) -> std::result::Result<Spread, D::Error> {
        de.deserialize_any(self)
    }
}

impl<'de> serde::de::Visitor<'de> for RangedSeed<'_> {
    type Value = Spread;
    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        write!(
            f,
            "a number, an interval of {} as two numbers [LO, HI], or a finite set {{ {ONE_OF} = [A, B, ...] }}",
            self.name
        )
    }
    fn visit_f64<E: serde::de::Error>(self, v: f64) -> std::result::Result<Spread, E> {
        let v = self.accepted(v).map_err(E::custom)?;
        Ok(Spread::Values(vec![v]))
    }
    fn visit_i64<E: serde::de::Error>(self, v: i64) -> std::result::Result<Spread, E> {
        self.visit_f64(v as f64)
    }
    fn visit_u64<E: serde::de::Error>(self, v: u64) -> std::result::Result<Spread, E> {
        self.visit_f64(v as f64)
    }
    fn visit_map<A: serde::de::MapAccess<'de>>(
        self,
        mut map: A,
    ) -> std::result::Result<Spread, A::Error> {
        use serde::de::Error as _;
        if let Some(why) = self.single {
            return Err(A::Error::custom(why));
        }
        let shape = || {
            A::Error::custom(format!(
                "a finite set of {} is a table with one key, {{ {ONE_OF} = [A, B, ...] }}, e.g. {{ {ONE_OF} = [1, 2, 3] }}",
                self.name
            ))
        };
        let key: String = map.next_key()?.ok_or_else(shape)?;
        if key != ONE_OF {
            return Err(shape());
        }
        let values: Vec<f64> = map.next_value()?;
        if map.next_key::<String>()?.is_some() {
            return Err(shape());
        }
        if values.is_empty() {
            return Err(A::Error::custom(format!(
                "the {} set is empty: give at least one value",
                self.name
            )));
        }
        let values = values
            .into_iter()
            .map(|v| self.accepted(v))
            .collect::<std::result::Result<Vec<f64>, String>>()
            .map_err(A::Error::custom)?;
        Ok(Spread::Values(values))
    }
    fn visit_seq<A: serde::de::SeqAccess<'de>>(
        self,
        mut seq: A,
    ) -> std::result::Result<Spread, A::Error> {
        use serde::de::Error as _;
        if let Some(why) = self.single {
            return Err(A::Error::custom(why));
        }
        let two = || {
            A::Error::custom(format!(
                "an interval of {} is two numbers [LO, HI], e.g. [1, 3]",
                self.name
            ))
        };
        let mut ends = [0.0; 2];
        for end in &mut ends {
            let v: f64 = seq.next_element()?.ok_or_else(two)?;
            *end = self.accepted(v).map_err(A::Error::custom)?;
        }
        if seq.next_element::<serde::de::IgnoredAny>()?.is_some() {
            return Err(two());
        }
        let [lo, hi] = ends;
        if lo > hi {
            return Err(A::Error::custom(format!(
                "the {} interval [{lo}, {hi}] is inverted: give the low end first",
                self.name
            )));
        }
        Ok(Spread::Interval(lo, hi))
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
    /// The loop's elements, each modelled only when named, read by the element list (a
    /// set's smallest value where the file gives `[lo, hi]` or `{ one_of = [...] }`).
    elements: PhysicalElements,
    /// The parameters the file spreads over sets (`[lo, hi]`, `lo < hi`, or
    /// `{ one_of = [...] }` with two values or more), in file order.
    spreads: Vec<(Quantity, Spread)>,
    /// `always_gripped = true`: the hand never lets go of the handle.
    always_gripped: bool,
    /// `nonnegative_wall_damping = true`: only walls with `B >= 0` may be recommended.
    nonnegative_wall_damping: bool,
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

/// The device key that requires recommended walls to have nonnegative virtual damping.
const NONNEGATIVE_KEY: &str = "nonnegative_wall_damping";

/// Every key of a `[[device]]` table, in the order messages list them.
fn device_keys() -> &'static [&'static str] {
    static KEYS: std::sync::LazyLock<Vec<&'static str>> = std::sync::LazyLock::new(|| {
        let mut k = DEVICE_KEYS.to_vec();
        k.extend(list::keys());
        k.push(ALWAYS_GRIPPED);
        k.push(NONNEGATIVE_KEY);
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
    Nonnegative,
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
        } else if key == NONNEGATIVE_KEY {
            Ok(DeviceKey::Nonnegative)
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
                let mut nonnegative = None;
                let mut spreads = Vec::new();
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
                        // the sampling period is one value for a whole set (firmware sets it)
                        DeviceKey::Own(2) => {
                            once(numbers[1].is_some(), DEVICE_KEYS[2])?;
                            let t = map.next_value_seed(RangedSeed {
                                name: "sampling period",
                                accept: &positive,
                                single: Some(
                                    "the sampling period is one number for a whole set of devices (the firmware sets it), not an interval",
                                ),
                            })?;
                            numbers[1] = Some(t.low());
                        }
                        DeviceKey::Own(i) => {
                            once(numbers[i - 1].is_some(), DEVICE_KEYS[i])?;
                            let (q, accept): (Quantity, &dyn Fn(f64) -> _) = match i {
                                1 => (Quantity::Mass, &positive),
                                3 => (Quantity::Damping, &non_negative),
                                _ => (Quantity::Delay, &non_negative),
                            };
                            let s = map.next_value_seed(RangedSeed {
                                name: q.name(),
                                accept,
                                single: None,
                            })?;
                            numbers[i - 1] = Some(s.low());
                            spread(&mut spreads, q, s);
                        }
                        DeviceKey::Element(p)
                            if matches!(p.accepts, Accepts::NonNegative | Accepts::Positive) =>
                        {
                            once(p.get(&elements).is_some(), p.key)?;
                            let accept = |x: f64| match p.accept(Value::Number(x)) {
                                Ok(_) => Ok(x),
                                Err(Error::InvalidParameter { expected, .. }) => {
                                    Err(format!("{x} is not accepted: {expected}"))
                                }
                                Err(e) => Err(e.to_string()),
                            };
                            let s = map.next_value_seed(RangedSeed {
                                name: p.name,
                                accept: &accept,
                                single: None,
                            })?;
                            p.set(&mut elements, Value::Number(s.low()));
                            spread(&mut spreads, Quantity::Element(p), s);
                        }
                        DeviceKey::Element(p) => list::read_entry(p, &mut map, &mut elements)?,
                        DeviceKey::AlwaysGripped => {
                            once(gripped.is_some(), ALWAYS_GRIPPED)?;
                            gripped = Some(map.next_value::<bool>()?);
                        }
                        DeviceKey::Nonnegative => {
                            once(nonnegative.is_some(), NONNEGATIVE_KEY)?;
                            nonnegative = Some(map.next_value::<bool>()?);
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
                    spreads,
                    always_gripped: gripped.unwrap_or(false),
                    nonnegative_wall_damping: nonnegative.unwrap_or(false),
                    wall: wall.unwrap_or_default(),
                })
            }
        }
        de.deserialize_map(Fields)
    }
}

/// Records `q` spread as `s` when it takes more than one value (exact: equal ends, or equal
/// values, are one value).
fn spread(spreads: &mut Vec<(Quantity, Spread)>, q: Quantity, s: Spread) {
    let several = match &s {
        Spread::Interval(lo, hi) => lo < hi,
        Spread::Values(v) => v.iter().any(|&x| x != v[0]),
    };
    if several {
        spreads.push((q, s));
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

    /// The set of devices the file's intervals and lists give (every member a valid loop,
    /// checked by [`DeviceSet`]), the hand let go unless `always_gripped`; `None` when
    /// nothing is spread (the device alone, and a hand's let-go twin, are checked as they
    /// always were).
    fn set(
        &self,
        device: &Device,
        elements: &PhysicalElements,
    ) -> std::result::Result<Option<DeviceSet>, String> {
        if self.spreads.is_empty() {
            return Ok(None);
        }
        let mut set = DeviceSet::new(device, elements).map_err(|e| e.to_string())?;
        for (q, s) in &self.spreads {
            let given = match s {
                Spread::Interval(lo, hi) => format!("interval [{lo}, {hi}]"),
                Spread::Values(v) => format!("set {v:?}"),
            };
            set = set
                .with_spread(*q, s)
                .map_err(|e| format!("the {} {given}: {e}", q.name()))?;
        }
        Ok(Some(set.always_gripped(self.always_gripped)))
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
            let device = d.device().and_then(|dev| {
                let e = d.elements(&dev)?;
                Ok((dev, e, d.set(&dev, &e)?))
            });
            let (device, elements, set) = device.map_err(|msg| {
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
                set,
                always_gripped: d.always_gripped,
                nonnegative_wall_damping: d.nonnegative_wall_damping,
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
