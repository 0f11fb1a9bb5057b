//! `stabound table`: a lookup table of alpha_max for firmware, as CSV, JSON, C or Rust.

use std::path::PathBuf;

use clap::ValueEnum;
use stabound::amax::amax_table;
use stabound::export::csv::to_csv_bytes;
use stabound::export::json::lookup_json;
use stabound::export::table::{lookup_header, lookup_rows};
use stabound::export::{DeviceScale, c::to_c_header, rust::to_rust};

use super::UsageError;
use super::args::{GridArgs, MAX_ROWS, SHARD_HELP, SearchArgs, Shard, plan, shard};
use super::output::Plan;

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
    #[command(flatten)]
    grid: GridArgs,
    #[command(flatten)]
    search: SearchArgs,
    /// Lower alpha_max just enough that linear interpolation never exceeds the true value
    /// (checked at interval quarter points, d midpoints and cell centres).
    #[arg(long)]
    conservative: bool,
    /// Output format.
    #[arg(long, value_enum, default_value = "csv")]
    format: Format,
    /// Write to this file instead of stdout.
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Work units are the table's nodes, d outer, delta inner (the CSV's rows). With
    /// --conservative a shard also computes the neighbouring d rows its nodes depend on.
    #[arg(long, value_parser = shard, help = SHARD_HELP)]
    shard: Option<Shard>,
}

pub fn run(a: Args) -> anyhow::Result<()> {
    let opts = a.search.options()?;
    if a.shard.is_some() && a.format != Format::Csv {
        return Err(UsageError(
            "--shard needs --format csv: a JSON object, C header or Rust module is one whole table and cannot be joined from parts; shard the CSV, join it, or run unsharded".into(),
        )
        .into());
    }
    let mut outputs = Plan::new();
    let data = outputs.data("-o", a.output.as_deref());
    let mut out = outputs.check()?;
    let g = a.grid.resolve()?;
    for (name, axis) in [("--delta/--damping", &g.deltas), ("--d/--delay", &g.ds)] {
        if axis.windows(2).any(|w| w[1] <= w[0]) {
            return Err(UsageError(format!(
                "the {name} axis of a lookup table must be strictly increasing, e.g. 0:10:11"
            ))
            .into());
        }
    }
    let units = g.device.map(|(mass, period)| DeviceScale { mass, period });
    if let Some(u) = &units {
        u.check_scale()?;
    }
    let (nx, nd) = (g.deltas.len(), g.ds.len());
    let what = format!("nodes ({nd} d x {nx} delta)");
    let nodes = plan(
        nd.saturating_mul(nx),
        a.shard.unwrap_or(Shard::ALL),
        MAX_ROWS,
        &what,
    )?;
    if a.shard.is_none() {
        let t = amax_table(&g.deltas, &g.ds, &opts, a.conservative)?;
        if let Some(u) = &units {
            u.check_table(&t)?;
        }
        let text = match a.format {
            Format::Csv => to_csv_bytes(&lookup_rows(&t, &units, 0..nx * nd)),
            Format::Json => lookup_json(&t, &units).into_bytes(),
            Format::C => to_c_header(&t, &units).into_bytes(),
            Format::Rust => to_rust(&t, &units).into_bytes(),
        };
        out.write(data, &text)?;
        return out.finish();
    }
    // The d rows the shard's nodes lie on, and with --conservative one more on each side:
    // a node's lowering depends only on its own row and the neighbouring ones, so the
    // sub-table gives these nodes the same values, bit for bit, as the whole table.
    let bytes = if nodes.is_empty() {
        to_csv_bytes(&lookup_header(&units))
    } else {
        let (first, last) = (nodes.start / nx, (nodes.end - 1) / nx);
        let pad = usize::from(a.conservative);
        let lo = first.saturating_sub(pad);
        let hi = (last + pad).min(nd - 1);
        let t = amax_table(&g.deltas, &g.ds[lo..=hi], &opts, a.conservative)?;
        if let Some(u) = &units {
            u.check_table(&t)?;
        }
        let off = lo * nx;
        to_csv_bytes(&lookup_rows(&t, &units, nodes.start - off..nodes.end - off))
    };
    out.write(data, &bytes)?;
    out.finish()
}
