//! `stabound amax`: maximum stable stiffness for lists of delta (or physical damping) and d.

use std::path::PathBuf;

use clap::ValueEnum;
use rayon::prelude::*;
use serde_json::{Map, Value, json};
use stabound::amax::{AmaxOptions, DEFAULT_TOL, alpha_max};
use stabound::params::{Delay, Device, Plant};
use stabound::plot::{Figure, LineStyle};

use super::UsageError;
use super::args::parse_list;
use super::output::emit;

/// A parsed LIST (an alias so that clap takes it as one value, not as repeated values).
type List = Vec<f64>;

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Format {
    Csv,
    Json,
}

/// Normalized (--delta LIST --d LIST) or physical (--mass --period --damping LIST and
/// --delay LIST | --delay-samples LIST).
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Normalized physical damping values delta = b T / m (LIST: 0,0.5,1 or START:STOP:COUNT).
    #[arg(long, value_parser = parse_list)]
    delta: Option<List>,
    /// Delay factors d = delay / T (LIST).
    #[arg(long, value_parser = parse_list)]
    d: Option<List>,
    /// Device mass m in kg.
    #[arg(long)]
    mass: Option<f64>,
    /// Sampling period T in s.
    #[arg(long)]
    period: Option<f64>,
    /// Physical damping values b in N s/m (LIST).
    #[arg(long, value_parser = parse_list)]
    damping: Option<List>,
    /// Delays in s (LIST).
    #[arg(long, value_parser = parse_list, conflicts_with = "delay_samples")]
    delay: Option<List>,
    /// Delays in sampling periods (LIST).
    #[arg(long = "delay-samples", value_parser = parse_list)]
    delay_samples: Option<List>,
    /// Smallest admissible virtual damping beta (e.g. 0 when negative damping cannot be rendered).
    #[arg(long = "beta-min", allow_hyphen_values = true)]
    beta_min: Option<f64>,
    /// Largest admissible virtual damping beta.
    #[arg(long = "beta-max", allow_hyphen_values = true)]
    beta_max: Option<f64>,
    /// Also report this fraction of alpha_max (e.g. 0.75 as in the paper's Section VIII).
    #[arg(long)]
    margin: Option<f64>,
    /// Refinement tolerance in theta (rad); larger is faster.
    #[arg(long, default_value_t = DEFAULT_TOL)]
    tol: f64,
    /// Output format.
    #[arg(long, value_enum, default_value = "csv")]
    format: Format,
    /// Write to this file instead of stdout.
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Also draw alpha_max against delta, one line per d (paper Fig. 10), to this SVG file.
    #[arg(long)]
    svg: Option<PathBuf>,
}

/// The request resolved to normalized values, one row per (d, delta), plus the device.
pub(crate) struct Grid {
    pub deltas: Vec<f64>,
    pub ds: Vec<f64>,
    pub device: Option<(f64, f64)>,
}

pub(crate) fn resolve(
    delta: Option<List>,
    d: Option<List>,
    mass: Option<f64>,
    period: Option<f64>,
    damping: Option<List>,
    delay: Option<List>,
    delay_samples: Option<List>,
) -> anyhow::Result<Grid> {
    let physical = mass.is_some()
        || period.is_some()
        || damping.is_some()
        || delay.is_some()
        || delay_samples.is_some();
    if physical {
        if delta.is_some() || d.is_some() {
            return Err(UsageError("give either --delta and --d, or --mass --period --damping and --delay|--delay-samples, not both".into()).into());
        }
        let (Some(m), Some(t), Some(bs)) = (mass, period, damping) else {
            return Err(
                UsageError("physical units need --mass, --period and --damping".into()).into(),
            );
        };
        let delays: Vec<Delay> = match (delay, delay_samples) {
            (Some(s), None) => s.into_iter().map(Delay::Seconds).collect(),
            (None, Some(n)) => n.into_iter().map(Delay::Samples).collect(),
            _ => return Err(UsageError("missing --delay (s) or --delay-samples".into()).into()),
        };
        let mut deltas = Vec::new();
        for &b in &bs {
            let dev = Device {
                mass: m,
                period: t,
                damping: b,
                delay: delays[0],
            };
            deltas.push(dev.plant()?.delta());
        }
        let mut ds = Vec::new();
        for &dl in &delays {
            let dev = Device {
                mass: m,
                period: t,
                damping: bs[0],
                delay: dl,
            };
            ds.push(dev.plant()?.d());
        }
        Ok(Grid {
            deltas,
            ds,
            device: Some((m, t)),
        })
    } else {
        let (Some(deltas), Some(ds)) = (delta, d) else {
            return Err(UsageError("missing --delta LIST and --d LIST (or physical --mass --period --damping --delay|--delay-samples)".into()).into());
        };
        Ok(Grid {
            deltas,
            ds,
            device: None,
        })
    }
}

pub fn run(a: Args) -> anyhow::Result<()> {
    let opts = AmaxOptions {
        tol: a.tol,
        beta_min: a.beta_min,
        beta_max: a.beta_max,
    };
    opts.validate()?;
    if let Some(f) = a.margin
        && !(f > 0.0 && f <= 1.0)
    {
        return Err(UsageError(format!(
            "--margin {f} must be a fraction in (0, 1], e.g. 0.75"
        ))
        .into());
    }
    let g = resolve(
        a.delta,
        a.d,
        a.mass,
        a.period,
        a.damping,
        a.delay,
        a.delay_samples,
    )?;
    for &x in &g.deltas {
        Plant::new(x, 0.0)?;
    }
    for &d in &g.ds {
        Plant::new(0.0, d)?;
    }
    let pairs: Vec<(f64, f64)> =
        g.ds.iter()
            .flat_map(|&d| g.deltas.iter().map(move |&x| (d, x)))
            .collect();
    let res: Vec<_> = pairs
        .par_iter()
        .map(|&(d, x)| alpha_max(&Plant::new(x, d)?, &opts))
        .collect::<Result<_, _>>()?;
    let mut rows: Vec<Map<String, Value>> = Vec::new();
    let mut cols = vec!["delta", "d", "alpha_max", "beta_at_max"];
    if a.margin.is_some() {
        cols.extend(["alpha_margin", "beta_margin"]);
    }
    if g.device.is_some() {
        cols.extend(["damping", "K_max", "B"]);
        if a.margin.is_some() {
            cols.push("K_margin");
        }
    }
    for (&(d, x), r) in pairs.iter().zip(&res) {
        let mut m = Map::new();
        m.insert("delta".into(), json!(x));
        m.insert("d".into(), json!(d));
        m.insert("alpha_max".into(), json!(r.alpha_max));
        m.insert("beta_at_max".into(), json!(r.beta_at_max));
        if let Some(f) = a.margin {
            m.insert("alpha_margin".into(), json!(f * r.alpha_max));
            m.insert("beta_margin".into(), json!(r.beta_at_max));
        }
        if let Some((mass, t)) = g.device {
            m.insert("damping".into(), json!(x * mass / t));
            m.insert("K_max".into(), json!(r.alpha_max * mass / (t * t)));
            m.insert("B".into(), json!(r.beta_at_max * mass / t));
            if let Some(f) = a.margin {
                m.insert("K_margin".into(), json!(f * r.alpha_max * mass / (t * t)));
            }
        }
        rows.push(m);
    }
    let text = match a.format {
        Format::Json => format!("{}\n", serde_json::to_string_pretty(&rows)?),
        Format::Csv => {
            let mut s = cols.join(",");
            s.push('\n');
            for r in &rows {
                let line: Vec<String> = cols.iter().map(|c| r[*c].to_string()).collect();
                s.push_str(&line.join(","));
                s.push('\n');
            }
            s
        }
    };
    if let Some(p) = &a.svg {
        let mut fig = Figure::new(
            "Maximum stable stiffness (cf. paper Fig. 10)",
            "delta",
            "alpha_max",
        );
        for (i, &d) in g.ds.iter().enumerate() {
            let pts: Vec<(f64, f64)> = pairs
                .iter()
                .zip(&res)
                .filter(|((dd, _), _)| dd.to_bits() == d.to_bits())
                .map(|((_, x), r)| (*x, r.alpha_max))
                .collect();
            let style = if g.deltas.len() == 1 {
                LineStyle::Points
            } else {
                LineStyle::Solid
            };
            fig.push(format!("d = {d}"), pts, style, i);
        }
        stabound::export::write_atomic(p, fig.to_svg()?.as_bytes())?;
    }
    emit(a.output.as_deref(), text.as_bytes())
}
