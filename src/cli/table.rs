//! `stabound table`: a lookup table of alpha_max for firmware, as CSV, JSON, C or Rust.

use std::path::PathBuf;

use clap::ValueEnum;
use stabound::amax::{AmaxOptions, DEFAULT_TOL, amax_table};
use stabound::export::table_csv::{DeviceScale, to_csv, to_json};
use stabound::export::{c::to_c_header, rust::to_rust};

use super::amax::resolve;
use super::args::parse_list;
use super::output::emit;

/// A parsed LIST (an alias so that clap takes it as one value, not as repeated values).
type List = Vec<f64>;

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Format {
    Csv,
    Json,
    C,
    Rust,
}

/// Grid of delta (--delta LIST) or physical damping (--mass --period --damping LIST) by
/// delay (--d LIST, or --delay LIST / --delay-samples LIST). Axes must be increasing.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Normalized physical damping axis delta = b T / m (LIST, increasing).
    #[arg(long, value_parser = parse_list)]
    delta: Option<List>,
    /// Delay factor axis d = delay / T (LIST, increasing).
    #[arg(long, value_parser = parse_list)]
    d: Option<List>,
    /// Device mass m in kg.
    #[arg(long)]
    mass: Option<f64>,
    /// Sampling period T in s.
    #[arg(long)]
    period: Option<f64>,
    /// Physical damping axis b in N s/m (LIST).
    #[arg(long, value_parser = parse_list)]
    damping: Option<List>,
    /// Delay axis in s (LIST).
    #[arg(long, value_parser = parse_list, conflicts_with = "delay_samples")]
    delay: Option<List>,
    /// Delay axis in sampling periods (LIST).
    #[arg(long = "delay-samples", value_parser = parse_list)]
    delay_samples: Option<List>,
    /// Smallest admissible virtual damping beta.
    #[arg(long = "beta-min", allow_hyphen_values = true)]
    beta_min: Option<f64>,
    /// Largest admissible virtual damping beta.
    #[arg(long = "beta-max", allow_hyphen_values = true)]
    beta_max: Option<f64>,
    /// Lower alpha_max just enough that linear interpolation never exceeds the true value
    /// (checked at interval quarter points, d midpoints and cell centres).
    #[arg(long)]
    conservative: bool,
    /// Refinement tolerance in theta (rad).
    #[arg(long, default_value_t = DEFAULT_TOL)]
    tol: f64,
    /// Output format.
    #[arg(long, value_enum, default_value = "csv")]
    format: Format,
    /// Write to this file instead of stdout.
    #[arg(short, long)]
    output: Option<PathBuf>,
}

pub fn run(a: Args) -> anyhow::Result<()> {
    let opts = AmaxOptions {
        tol: a.tol,
        beta_min: a.beta_min,
        beta_max: a.beta_max,
    };
    let g = resolve(
        a.delta,
        a.d,
        a.mass,
        a.period,
        a.damping,
        a.delay,
        a.delay_samples,
    )?;
    let units = g.device.map(|(mass, period)| DeviceScale { mass, period });
    let t = amax_table(&g.deltas, &g.ds, &opts, a.conservative)?;
    let text = match a.format {
        Format::Csv => to_csv(&t, &units),
        Format::Json => to_json(&t, &units),
        Format::C => to_c_header(&t, &units),
        Format::Rust => to_rust(&t, &units),
    };
    emit(a.output.as_deref(), text.as_bytes())
}
