//! What the explorer shows of one device and wall: the state the page sends (its query
//! string), the scene it stands for, and the numbers and curves the page draws, each computed
//! by the library functions the command line calls for the same quantity.

use serde_json::{Value, json};
use stabound::VelocityFilter;
use stabound::amax::{AmaxOptions, alpha_max};
use stabound::boundary::{self, SweepOptions};
use stabound::elements::{Encoder, Loop, PhysicalElements};
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

/// The state's numeric keys with the command-line flag (device and elements) each stands for.
const ELEMENT_KEYS: [(&str, &str); 9] = [
    ("hand_mass", "--hand-mass"),
    ("hand_damping", "--hand-damping"),
    ("hand_stiffness", "--hand-stiffness"),
    ("handle_mass", "--handle-mass"),
    ("transmission_stiffness", "--transmission-stiffness"),
    ("transmission_damping", "--transmission-damping"),
    ("actuator_time_constant", "--actuator-time-constant"),
    ("velocity_filter_cutoff", "--velocity-filter-cutoff"),
    ("velocity_filter_samples", "--velocity-filter-samples"),
];

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
        for pair in query.split('&').filter(|p| !p.is_empty()) {
            let (k, v) = pair.split_once('=').unwrap_or((pair, ""));
            let (k, v) = (decode(k)?, decode(v)?);
            let v = v.trim();
            if v.is_empty() {
                continue;
            }
            let e = &mut s.elements;
            match k.as_str() {
                "mass" => s.mass = number(&k, v)?,
                "period" => s.period = number(&k, v)?,
                "damping" => s.damping = number(&k, v)?,
                "delay" => s.delay = number(&k, v)?,
                "stiffness" => s.stiffness = number(&k, v)?,
                "wall_damping" => s.wall_damping = number(&k, v)?,
                "hand_mass" => e.hand_mass = Some(number(&k, v)?),
                "hand_damping" => e.hand_damping = Some(number(&k, v)?),
                "hand_stiffness" => e.hand_stiffness = Some(number(&k, v)?),
                "handle_mass" => e.handle_mass = Some(number(&k, v)?),
                "transmission_stiffness" => e.transmission_stiffness = Some(number(&k, v)?),
                "transmission_damping" => e.transmission_damping = Some(number(&k, v)?),
                "actuator_time_constant" => e.actuator_time_constant = Some(number(&k, v)?),
                "velocity_filter_cutoff" => e.velocity_filter_cutoff = Some(number(&k, v)?),
                "velocity_filter_samples" => {
                    e.velocity_filter_samples = Some(v.parse().map_err(|_| {
                        UsageError(format!("{k}: '{v}' is not a whole number of samples"))
                    })?)
                }
                "encoder" => {
                    e.encoder = Some(match v {
                        "motor" => Encoder::Motor,
                        "handle" => Encoder::Handle,
                        _ => {
                            return Err(UsageError(format!(
                                "encoder: '{v}' is neither motor nor handle"
                            )));
                        }
                    })
                }
                _ => {
                    return Err(UsageError(format!(
                        "unknown key '{k}': the device is mass, period, damping, delay (samples), the wall stiffness and wall_damping, the elements {}",
                        ELEMENT_KEYS.map(|k| k.0).join(", ")
                    )));
                }
            }
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
        let e = &self.elements;
        let values = [
            e.hand_mass,
            e.hand_damping,
            e.hand_stiffness,
            e.handle_mass,
            e.transmission_stiffness,
            e.transmission_damping,
            e.actuator_time_constant,
            e.velocity_filter_cutoff,
            e.velocity_filter_samples.map(|n| n as f64),
        ];
        for ((_, flag), v) in ELEMENT_KEYS.iter().zip(values) {
            if let Some(v) = v {
                f.extend([flag.to_string(), v.to_string()]);
            }
        }
        if let Some(enc) = e.encoder {
            let name = match enc {
                Encoder::Motor => "motor",
                _ => "handle",
            };
            f.extend(["--encoder".to_string(), name.to_string()]);
        }
        f
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
        let e = &self.elements;
        let keys = [
            ("hand_mass_kg", e.hand_mass),
            ("hand_damping_Ns_per_m", e.hand_damping),
            ("hand_stiffness_N_per_m", e.hand_stiffness),
            ("handle_mass_kg", e.handle_mass),
            ("transmission_stiffness_N_per_m", e.transmission_stiffness),
            ("transmission_damping_Ns_per_m", e.transmission_damping),
            ("actuator_time_constant_s", e.actuator_time_constant),
            ("velocity_filter_cutoff_Hz", e.velocity_filter_cutoff),
        ];
        for (k, v) in keys {
            if let Some(v) = v {
                let _ = writeln!(s, "{k} = {v:?}");
            }
        }
        if let Some(n) = e.velocity_filter_samples {
            let _ = writeln!(s, "velocity_filter_samples = {n}");
        }
        if let Some(enc) = e.encoder {
            let name = match enc {
                Encoder::Motor => "motor",
                _ => "handle",
            };
            let _ = writeln!(s, "encoder = \"{name}\"");
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
        // the margin wall checked stable, as `stabound amax --margin` gives it
        let m = stabound::amax::recommend(&lp, &AmaxOptions::default(), MARGIN)?;
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
                "stiffness": scale.try_k(m.wall.alpha())?,
                "wall_damping": scale.try_b(m.wall.beta())?,
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
        let others = e.hand_mass.is_some()
            || e.hand_damping.is_some()
            || e.hand_stiffness.is_some()
            || e.handle_mass.is_some()
            || e.actuator_time_constant.is_some();
        if others {
            return json!({"note": "the passive region is modelled for a delay and a velocity filter only, without hand, transmission or actuator"});
        }
        let region = || -> anyhow::Result<Vec<[f64; 2]>> {
            let filter = match (e.velocity_filter_cutoff, e.velocity_filter_samples) {
                (Some(hz), _) => VelocityFilter::low_pass_cutoff(hz, self.period)?,
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
