//! What the explorer shows of one device and wall: the state the page sends (its query
//! string), the scene it stands for, and the numbers and curves the page draws, each computed
//! by the library functions the command line calls for the same quantity.

use serde_json::{Value, json};
use stabound::VelocityFilter;
use stabound::amax::{AmaxOptions, alpha_max};
use stabound::boundary::{self, SweepOptions};
use stabound::elements::list::{Accepts, Element, PARAMS, Param, Value as ElementValue, param};
use stabound::elements::{Loop, PhysicalElements};
use stabound::export::DeviceScale;
use stabound::passivity::Criterion;
use stabound::scene::{Scene, SceneFormat};
use stabound::sim::{StepOptions, step_response};
use stabound::stability::Options;

use super::super::UsageError;
use super::super::boundary::thin;

/// The longest delay the explorer computes, in sampling periods: the boundary's cost grows
/// with the degree of the polynomial (about `d + 2`), and a request must stay well inside the
/// time limit of the server on a small machine.
pub const MAX_DELAY_SAMPLES: f64 = 100.0;

/// Tolerance of the drawn passive edge in normalized units, the default of `stabound
/// passivity`: far below a pixel of any drawing the page makes.
const PASSIVE_TOL: f64 = 1e-7;

/// The fraction of `K_max` of the suggested wall (the paper's Section VIII).
const MARGIN: f64 = 0.75;

/// The device, its loop's elements and the wall, in physical units: the page's state.
#[derive(Debug, Clone)]
pub struct State {
    mass: f64,
    period: f64,
    damping: f64,
    /// Delay in sampling periods.
    delay: f64,
    elements: PhysicalElements,
    stiffness: f64,
    wall_damping: f64,
}

/// The keys of the device and the wall (the elements' keys are their keywords in
/// [`PARAMS`]).
const DEVICE_KEYS: [&str; 6] = [
    "mass",
    "period",
    "damping",
    "delay",
    "stiffness",
    "wall_damping",
];

/// How the page shows an element's parameter: unit shown, factor (shown = SI * factor),
/// slider range in shown units, log slider, the value a newly named parameter starts at (SI),
/// and whether switching its element on names it. A parameter of the element list without
/// hints gets [`hints`]' generic ones, so a new element appears on the page by itself.
struct Hints {
    unit: &'static str,
    factor: f64,
    min: f64,
    max: f64,
    log: bool,
    start: f64,
    on: bool,
}

/// The page's hints for the parameter `p` (see [`Hints`]).
fn hints(p: &Param) -> Hints {
    let h = |unit, factor, min, max, log, start, on| Hints {
        unit,
        factor,
        min,
        max,
        log,
        start,
        on,
    };
    match p.keyword {
        "hand_mass" => h("kg", 1.0, 0.0, 1.0, false, 0.2, true),
        "hand_damping" => h("N s/m", 1.0, 0.0, 20.0, false, 1.0, true),
        "hand_stiffness" => h("N/m", 1.0, 0.0, 1000.0, false, 50.0, true),
        "handle_mass" => h("kg", 1.0, 0.001, 0.09, false, 0.03, true),
        "transmission_stiffness" => h("N/m", 1.0, 1e3, 1e6, true, 2e5, true),
        "transmission_damping" => h("N s/m", 1.0, 0.0, 50.0, false, 5.0, true),
        "motor_damping" | "handle_damping" => h("N s/m", 1.0, 0.0, 50.0, false, 0.0, false),
        "encoder" => h("", 1.0, 0.0, 0.0, false, 0.0, true),
        "actuator_time_constant" => h("ms", 1000.0, 0.01, 5.0, true, 2e-4, true),
        "velocity_filter_cutoff" => h("Hz", 1.0, 1.0, 500.0, true, 100.0, true),
        "velocity_filter_samples" => h("", 1.0, 1.0, 16.0, false, 4.0, false),
        "velocity_filter_order" => h("", 1.0, 1.0, 2.0, false, 2.0, false),
        _ => match p.accepts {
            Accepts::Count { min, max } => h(
                "",
                1.0,
                min as f64,
                max.min(100) as f64,
                false,
                min as f64,
                false,
            ),
            _ => h(p.unit, 1.0, 1e-3, 1e3, true, 1.0, false),
        },
    }
}

/// The element list as the page builds its controls from it: each parameter with its
/// element, name, unit, what it accepts, help, the parameters it needs or excludes, and the
/// page's [`hints`].
pub fn params_json() -> Value {
    let params: Vec<Value> = PARAMS
        .iter()
        .map(|p| {
            let h = hints(p);
            let (kind, min, max, choices): (&str, Value, Value, &[&str]) = match p.accepts {
                Accepts::Count { min, max } => ("count", json!(min), json!(max), &[]),
                Accepts::Choice(names) => ("choice", Value::Null, Value::Null, names),
                Accepts::Positive => ("positive", Value::Null, Value::Null, &[]),
                _ => ("nonnegative", Value::Null, Value::Null, &[]),
            };
            let element = format!("{:?}", p.element);
            json!({
                "keyword": p.keyword,
                "name": p.name,
                "flag": p.flag,
                "element": element,
                "element_title": element_title(p.element),
                "help": p.help,
                "accepts": {"kind": kind, "min": min, "max": max, "choices": choices},
                "requires": p.requires.map_or(&[][..], |r| r.0),
                "conflicts": p.conflicts.map_or(&[][..], |c| c.0),
                "unit": h.unit,
                "factor": h.factor,
                "min": h.min,
                "max": h.max,
                "log": h.log,
                "start": h.start,
                "on": h.on,
            })
        })
        .collect();
    json!({ "params": params })
}

/// The title of an element's box on the page (an element new to the list shows its name).
fn element_title(e: Element) -> String {
    match e {
        Element::Hand => "Operator's hand".into(),
        Element::Transmission => "Compliant transmission".into(),
        Element::Actuator => "Actuator lag".into(),
        Element::VelocityFilter => "Velocity filter".into(),
        other => format!("{other:?}"),
    }
}

/// A parameter's value as the command line's flag takes it (the shortest decimal that reads
/// back the same number).
fn text(v: ElementValue) -> String {
    match v {
        ElementValue::Number(x) => x.to_string(),
        ElementValue::Count(n) => n.to_string(),
        ElementValue::Choice(c) => c.to_string(),
    }
}

/// `%XX` and `+` decoded (the page's `URLSearchParams`).
fn decode(s: &str) -> Result<String, UsageError> {
    let bytes = s.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        match bytes[i] {
            b'+' => out.push(b' '),
            b'%' => {
                let hex = s
                    .get(i + 1..i + 3)
                    .and_then(|h| u8::from_str_radix(h, 16).ok());
                out.push(hex.ok_or_else(|| UsageError(format!("bad escape in '{s}'")))?);
                i += 2;
            }
            b => out.push(b),
        }
        i += 1;
    }
    String::from_utf8(out).map_err(|_| UsageError(format!("'{s}' is not UTF-8")))
}

fn number(key: &str, v: &str) -> Result<f64, UsageError> {
    super::super::args::finite(v).map_err(|e| UsageError(format!("{key}: {e}")))
}

impl Default for State {
    /// The device of the paper's Section VIII (m = 0.1 kg, T = 1 ms, b = 0, one sample of
    /// delay) with its wall: 75 % of K_max at the damping of K_max.
    fn default() -> Self {
        Self {
            mass: 0.1,
            period: 0.001,
            damping: 0.0,
            delay: 1.0,
            elements: PhysicalElements::default(),
            stiffness: 10800.0,
            wall_damping: 42.5,
        }
    }
}

impl State {
    /// Parses a query string `key=value&...`; absent keys keep the default, unknown keys and
    /// values that are not finite numbers are refused. Every other check is the library's,
    /// when the scene is read.
    pub fn parse(query: &str) -> Result<State, UsageError> {
        let mut s = State::default();
        let mut seen: Vec<String> = Vec::new();
        for pair in query.split('&').filter(|p| !p.is_empty()) {
            let (k, v) = pair.split_once('=').unwrap_or((pair, ""));
            let (k, v) = (decode(k)?, decode(v)?);
            let v = v.trim();
            if seen.contains(&k) {
                return Err(UsageError(format!("{k} is named twice")));
            }
            seen.push(k.clone());
            if v.is_empty() {
                return Err(UsageError(format!(
                    "{k} has no value: give a number, or leave the key out"
                )));
            }
            let field = match k.as_str() {
                "mass" => &mut s.mass,
                "period" => &mut s.period,
                "damping" => &mut s.damping,
                "delay" => &mut s.delay,
                "stiffness" => &mut s.stiffness,
                "wall_damping" => &mut s.wall_damping,
                key => {
                    let p = param(key).ok_or_else(|| {
                        let elements: Vec<&str> = PARAMS.iter().map(|p| p.keyword).collect();
                        UsageError(format!(
                            "unknown key '{key}': the device is {}; the elements {}",
                            DEVICE_KEYS.join(", "),
                            elements.join(", ")
                        ))
                    })?;
                    // the kind is read here, the value is checked by the library's scene
                    let v = p.read(v).map_err(|e| UsageError(format!("{key}: {e}")))?;
                    p.set(&mut s.elements, v);
                    continue;
                }
            };
            *field = number(&k, v)?;
        }
        if s.delay > MAX_DELAY_SAMPLES {
            return Err(UsageError(format!(
                "delay: {} samples is more than the {MAX_DELAY_SAMPLES} the explorer computes; use the command line for longer delays",
                s.delay
            )));
        }
        Ok(s)
    }

    /// The command-line flags of the device and its elements (`--mass 0.1 --period ...`).
    pub fn device_flags(&self) -> Vec<String> {
        let mut f: Vec<String> = [
            ("--mass", self.mass),
            ("--period", self.period),
            ("--damping", self.damping),
            ("--delay-samples", self.delay),
        ]
        .iter()
        .flat_map(|(k, v)| [k.to_string(), v.to_string()])
        .collect();
        for (p, v) in self.named() {
            f.extend([format!("--{}", p.flag), text(v)]);
        }
        f
    }

    /// The element parameters named, with their values, in the list's order.
    fn named(&self) -> impl Iterator<Item = (&'static Param, ElementValue)> + '_ {
        PARAMS
            .iter()
            .filter_map(|p| p.get(&self.elements).map(|v| (p, v)))
    }

    /// The wall's flags (`--stiffness K --wall-damping B`).
    pub fn wall_flags(&self) -> Vec<String> {
        vec![
            "--stiffness".into(),
            self.stiffness.to_string(),
            "--wall-damping".into(),
            self.wall_damping.to_string(),
        ]
    }

    /// The scene file of the device and its wall (TOML, read by `stabound scene`).
    pub fn scene_toml(&self) -> String {
        use std::fmt::Write;
        let mut s = String::from(
            "# The device and wall shown by `stabound serve`; check it with `stabound scene FILE`.\n\n[[device]]\nname = \"explorer\"\n",
        );
        let _ = writeln!(s, "mass_kg = {:?}", self.mass);
        let _ = writeln!(s, "period_s = {:?}", self.period);
        let _ = writeln!(s, "damping_Ns_per_m = {:?}", self.damping);
        let _ = writeln!(s, "delay_samples = {:?}", self.delay);
        for (p, v) in self.named() {
            let _ = match v {
                ElementValue::Number(x) => writeln!(s, "{} = {x:?}", p.key),
                ElementValue::Choice(c) => writeln!(s, "{} = \"{c}\"", p.key),
                v => writeln!(s, "{} = {}", p.key, text(v)),
            };
        }
        let _ = write!(
            s,
            "\n[[device.wall]]\nname = \"wall\"\nstiffness_N_per_m = {:?}\ndamping_Ns_per_m = {:?}\n",
            self.stiffness, self.wall_damping
        );
        s
    }

    /// The scene, read by the library (which checks every value).
    pub fn scene(&self) -> anyhow::Result<Scene> {
        Ok(Scene::parse(
            &self.scene_toml(),
            SceneFormat::Toml,
            "the explorer's scene",
        )?)
    }

    /// Everything the page shows, as JSON.
    pub fn view(&self) -> anyhow::Result<Value> {
        let scene = self.scene()?;
        let dev = &scene.devices[0];
        let lp = Loop::physical(&dev.device, &dev.elements)?;
        let scale = DeviceScale {
            mass: self.mass,
            period: self.period,
        };
        scale.check_scale()?;
        let delta = dev.device.plant()?.delta();
        let kmax = |opts: AmaxOptions| -> anyhow::Result<Value> {
            let a = alpha_max(lp, &opts)?;
            Ok(json!({
                "alpha_max": a.alpha_max,
                "beta_at_max": a.beta_at_max,
                "K_max": scale.try_k(a.alpha_max)?,
                "B": scale.try_b(a.beta_at_max)?,
            }))
        };
        // the parts are independent: computed side by side (each as its command computes it)
        let ((report, b), ((free, positive), (step, passive))) = rayon::join(
            || {
                rayon::join(
                    || scene.check(&Options::default()),
                    // the exact boundary, as `stabound boundary` computes it
                    || boundary::trace(lp, &SweepOptions::default()),
                )
            },
            || {
                rayon::join(
                    || {
                        rayon::join(
                            || kmax(AmaxOptions::default()),
                            || {
                                AmaxOptions::default()
                                    .with_beta_limits(Some(0.0), None)
                                    .map_err(anyhow::Error::from)
                                    .and_then(kmax)
                            },
                        )
                    },
                    || {
                        rayon::join(
                            || {
                                step_response(
                                    &lp,
                                    self.stiffness,
                                    self.wall_damping,
                                    &StepOptions::default(),
                                )
                            },
                            || self.passive(&dev.elements, delta, &scale),
                        )
                    },
                )
            },
        );
        let (report, b, step) = (report?, b?, step?);
        let all = physical(&scale, &b.xy())?;
        let region = thin_extent(&all);
        let (free, positive) = (free?, positive?);
        Ok(json!({
            "device": {
                "mass": self.mass,
                "period": self.period,
                "damping": self.damping,
                "delay_samples": self.delay,
                "delta": dev.device.plant()?.delta(),
                "d": dev.device.plant()?.d(),
            },
            "region": region,
            "region_vertices": all.len(),
            "kmax": free,
            "kmax_positive_damping": positive,
            // the paper's Section VIII wall, as `stabound amax --margin 0.75` gives it
            "margin_wall": {
                "fraction": MARGIN,
                "stiffness": scale.try_k(MARGIN * free["alpha_max"].as_f64().unwrap_or(f64::NAN))?,
                "wall_damping": free["B"],
            },
            "wall": report.devices[0].walls[0],
            "step": {
                "time": step.time,
                "position": step.position,
                "final_value": step.final_value,
            },
            "passive": passive,
        }))
    }

    /// The passive region (paper Section VII) where the library has it: a whole-sample delay
    /// and at most a velocity filter; otherwise the reason it is not drawn.
    fn passive(&self, e: &PhysicalElements, delta: f64, scale: &DeviceScale) -> Value {
        let others = self
            .named()
            .any(|(p, _)| p.element != Element::VelocityFilter);
        if others {
            return json!({"note": "not drawn: it is modelled for a delay and a velocity filter only, without the other elements named"});
        }
        let region = || -> anyhow::Result<Vec<[f64; 2]>> {
            let filter = match (e.velocity_filter_cutoff, e.velocity_filter_samples) {
                (Some(hz), _) => VelocityFilter::low_pass_order(
                    e.velocity_filter_order.unwrap_or(1),
                    hz,
                    self.period,
                )?,
                (None, Some(n)) => VelocityFilter::moving_average(n)?,
                (None, None) => VelocityFilter::none(),
            };
            let crit = Criterion::new(self.delay, filter)?;
            let r = crit.region_alpha_beta(delta, PASSIVE_TOL)?;
            physical(scale, &r.xy())
        };
        match region() {
            Ok(pts) => json!({"region": thin_extent(&pts)}),
            Err(err) => json!({"note": format!("{err:#}")}),
        }
    }
}

/// Normalized `(alpha, beta)` points in physical units `(K, B)`, refusing any that overflow.
fn physical(scale: &DeviceScale, xy: &[(f64, f64)]) -> anyhow::Result<Vec<[f64; 2]>> {
    xy.iter()
        .map(|&(a, b)| Ok([scale.try_k(a)?, scale.try_b(b)?]))
        .collect()
}

/// The points of a closed polyline kept at least 1/1500 of its extent apart, as the command
/// line's drawings keep them: the page draws them, a few thousand at most.
fn thin_extent(points: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let ext = |i: usize| {
        let (lo, hi) = points
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), p| {
                (l.min(p[i]), h.max(p[i]))
            });
        ((hi - lo) / 1500.0).max(0.0)
    };
    let xy: Vec<(f64, f64)> = points.iter().map(|p| (p[0], p[1])).collect();
    thin(&xy, (ext(0), ext(1)))
        .into_iter()
        .map(|(x, y)| [x, y])
        .collect()
}
