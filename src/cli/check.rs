//! `stabound check`: one stability test for one wall.

use std::path::PathBuf;

use clap::ValueEnum;
use serde_json::json;
use stabound::params::{Delay, Device, Normalized};
use stabound::stability::{Checker, DEFAULT_MARGIN, Options};

use super::UsageError;
use super::args::{MethodArg, finite};
use super::output::Plan;

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Format {
    Text,
    Json,
}

/// Give the wall either in normalized form (--alpha --beta --delta --d) or in physical units
/// (--mass --period --damping --stiffness --wall-damping and --delay or --delay-samples).
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Normalized stiffness alpha = K T^2 / m.
    #[arg(long, value_parser = finite, allow_hyphen_values = true)]
    alpha: Option<f64>,
    /// Normalized virtual damping beta = B T / m.
    #[arg(long, value_parser = finite, allow_hyphen_values = true)]
    beta: Option<f64>,
    /// Normalized physical damping delta = b T / m (>= 0).
    #[arg(long, value_parser = finite, allow_hyphen_values = true)]
    delta: Option<f64>,
    /// Delay factor d = delay / T (>= 0, may be fractional).
    #[arg(long, value_parser = finite, allow_hyphen_values = true)]
    d: Option<f64>,
    /// Device mass m in kg.
    #[arg(long, value_parser = finite, allow_hyphen_values = true)]
    mass: Option<f64>,
    /// Sampling period T in s.
    #[arg(long, value_parser = finite, allow_hyphen_values = true)]
    period: Option<f64>,
    /// Physical damping b in N s/m.
    #[arg(long, value_parser = finite, allow_hyphen_values = true)]
    damping: Option<f64>,
    /// Wall stiffness K in N/m.
    #[arg(long, value_parser = finite, allow_hyphen_values = true)]
    stiffness: Option<f64>,
    /// Wall damping B in N s/m.
    #[arg(long = "wall-damping", value_parser = finite, allow_hyphen_values = true)]
    wall_damping: Option<f64>,
    /// Delay in s.
    #[arg(long, value_parser = finite, allow_hyphen_values = true, conflicts_with = "delay_samples")]
    delay: Option<f64>,
    /// Delay in sampling periods.
    #[arg(long = "delay-samples", value_parser = finite, allow_hyphen_values = true)]
    delay_samples: Option<f64>,
    /// How stability is decided.
    #[arg(long, value_enum, default_value = "auto")]
    method: MethodArg,
    /// Half-width of the marginal band around the unit circle: a spectral radius within this
    /// of 1 is reported as marginal.
    #[arg(long, default_value_t = DEFAULT_MARGIN, value_parser = finite, allow_hyphen_values = true)]
    margin: f64,
    /// Output format.
    #[arg(long, value_enum, default_value = "text")]
    format: Format,
    /// Write to this file instead of stdout.
    #[arg(short, long)]
    output: Option<PathBuf>,
}

fn require(name: &str, v: Option<f64>) -> Result<f64, UsageError> {
    v.ok_or_else(|| UsageError(format!("missing --{name}")))
}

pub fn run(a: Args) -> anyhow::Result<()> {
    let mut outputs = Plan::new();
    let data = outputs.data("-o", a.output.as_deref());
    let mut out = outputs.check()?;
    let physical = [a.mass, a.period, a.damping, a.stiffness, a.wall_damping]
        .iter()
        .any(Option::is_some)
        || a.delay.is_some()
        || a.delay_samples.is_some();
    let normalized_given = [a.alpha, a.beta, a.delta, a.d].iter().any(Option::is_some);
    let (params, device) = if physical {
        if normalized_given {
            return Err(UsageError(
                "give either normalized parameters (--alpha --beta --delta --d) or physical ones (--mass --period --damping --stiffness --wall-damping --delay|--delay-samples), not both".into(),
            )
            .into());
        }
        let delay = match (a.delay, a.delay_samples) {
            (Some(s), None) => Delay::Seconds(s),
            (None, Some(n)) => Delay::Samples(n),
            _ => return Err(UsageError("missing --delay (s) or --delay-samples".into()).into()),
        };
        let device = Device {
            mass: require("mass", a.mass)?,
            period: require("period", a.period)?,
            damping: require("damping", a.damping)?,
            delay,
        };
        let params = device.normalize(
            require("stiffness", a.stiffness)?,
            require("wall-damping", a.wall_damping)?,
        )?;
        (params, Some(device))
    } else {
        let params = Normalized {
            alpha: require("alpha", a.alpha)?,
            beta: require("beta", a.beta)?,
            delta: require("delta", a.delta)?,
            d: require("d", a.d)?,
        };
        (params, None)
    };
    let (plant, wall) = params.split()?;
    let options = Options {
        method: a.method.into(),
        margin: a.margin,
    };
    let analysis = Checker::new(&plant, options)?.analyze(&wall)?;
    let text = match a.format {
        Format::Json => {
            let roots: Vec<[f64; 2]> = analysis.roots.iter().map(|z| [z.re, z.im]).collect();
            let mut obj = json!({
                "stable": analysis.verdict.is_stable(),
                "verdict": analysis.verdict.name(),
                "spectral_radius": analysis.spectral_radius,
                "roots": roots,
                "degree": analysis.degree,
                "method": analysis.method.name(),
                "margin": a.margin,
                "alpha": params.alpha,
                "beta": params.beta,
                "delta": params.delta,
                "d": params.d,
            });
            if let Some(dev) = device {
                obj["physical"] = json!({
                    "mass": dev.mass,
                    "period": dev.period,
                    "damping": dev.damping,
                    "stiffness": dev.stiffness(params.alpha),
                    "wall_damping": dev.wall_damping(params.beta),
                    "delay_samples": params.d,
                });
            }
            format!("{}\n", serde_json::to_string_pretty(&obj)?)
        }
        Format::Text => {
            let mut s = format!(
                "{} (alpha = {}, beta = {}, delta = {}, d = {})\nspectral radius {}, verdict by {}, marginal band +-{:e}\ndegree {}, roots:\n",
                analysis.verdict.name(),
                short(params.alpha),
                short(params.beta),
                short(params.delta),
                short(params.d),
                short(analysis.spectral_radius),
                analysis.method.name(),
                a.margin,
                analysis.degree
            );
            for z in &analysis.roots {
                s.push_str(&format!(
                    "  {:+.12} {:+.12}i  |z| = {:.12}\n",
                    z.re,
                    z.im,
                    z.norm()
                ));
            }
            s
        }
    };
    out.write(data, text.as_bytes())?;
    out.finish()
}

/// A number as typed (`0.5`) in the everyday range, in exponent form (`1e300`) outside it,
/// so extreme inputs do not print hundreds of digits.
fn short(x: f64) -> String {
    let a = x.abs();
    if x.classify() == std::num::FpCategory::Zero || (1e-4..1e9).contains(&a) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}
