//! `stabound table`: a lookup table of alpha_max for firmware, as CSV, JSON, C or Rust.

use std::path::PathBuf;

use anyhow::Context;

use clap::ValueEnum;
use stabound::amax::{AmaxTable, Interpolation, Precision, TableOptions, amax_table};
use stabound::certificate::{CELL_BOXES_CAP, DEFAULT_CELL_BOXES, certify_table};
use stabound::elements::Loop;
use stabound::export::csv::to_csv_bytes;
use stabound::export::json::lookup_json;
use stabound::export::{DeviceScale, c::to_c_header, rust::to_rust};
use stabound::export::{lookup_header, lookup_rows};
use stabound::params::Device;

use super::UsageError;
use super::args::{
    ElementArgs, GridArgs, MAX_ROWS, NonlinearArgs, SHARD_HELP, SearchArgs, Shard, needs_physical,
    plan, shard,
};
use super::output::{Plan, Progress};

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Format {
    Csv,
    Json,
    C,
    Rust,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum PrecisionArg {
    Double,
    Float,
}

/// Grid of delta (--delta LIST) or physical damping (--mass --period --damping LIST) by
/// delay (--d LIST, or --delay LIST / --delay-samples LIST). Axes must be increasing. Loop
/// elements (physical units only) make every node, and every query --conservative checks,
/// that loop's.
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    grid: GridArgs,
    #[command(flatten)]
    search: SearchArgs,
    /// Lower alpha_max until every wall the table's lookup procedure yields is stable
    /// (checked densely: nodes, near-node points and 1/16 steps of every delta interval;
    /// with a fractional d also 1/8 steps across d). Whole delays are not interpolated.
    #[arg(long)]
    conservative: bool,
    /// With --conservative: prove every wall the lookup yields stable, for every delta of
    /// each interval (not samples) and within the rounding guard, by interval Schur-Cohn
    /// boxes; cells not proved are lowered until they are. Writes the certificate (JSON) to
    /// FILE, checked by tools/verify_certificate.py. One loop (the paper's, or with loop
    /// elements) or a finite set of devices (a hand that can let go, one-of lists of element
    /// parameters: each member proved; not intervals, not a list of masses), with whole
    /// delays (or one delay); nothing is written when a cell cannot be proved.
    #[arg(long, value_name = "FILE", requires = "conservative")]
    certify: Option<PathBuf>,
    /// With --certify: the most boxes each cell of the table is halved into before it is
    /// lowered (more boxes prove walls nearer the boundary, so lower less). A cell that no
    /// lowering proves within them (a wide cell) has its budget doubled, up to 16384 boxes,
    /// before its nodes are lowered; the command says so on stderr. The checker replays about 10 boxes a second
    /// on wide cells of a loop with elements.
    #[arg(long = "certify-boxes", default_value_t = DEFAULT_CELL_BOXES as u64, requires = "certify", value_parser = clap::value_parser!(u64).range(1..=MAX_CELL_BOXES_FLAG as u64))]
    certify_boxes: u64,
    /// Floating-point type of the C and Rust values and lookup: float rounds stiffness
    /// down (toward safety) and is checked after rounding.
    #[arg(long, value_enum, default_value = "double")]
    precision: PrecisionArg,
    /// Output format.
    #[arg(long, value_enum, default_value = "csv")]
    format: Format,
    /// Write to this file instead of stdout.
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Work units are the table's nodes, d outer, delta inner (the CSV's rows). With
    /// --conservative and a fractional d, a shard computes the whole table (its lowering
    /// is shared across d).
    #[arg(long, value_parser = shard, help = SHARD_HELP)]
    shard: Option<Shard>,
    #[command(flatten)]
    loop_elements: ElementArgs,
    /// Nodes at this fraction of alpha_max (e.g. 0.75 as in the paper's Section VIII), the
    /// damping left where the maximum is reached; --conservative checks these walls.
    #[arg(long, value_parser = super::args::finite, allow_hyphen_values = true)]
    margin: Option<f64>,
    /// The encoder, force output and dry friction: when any is named, the table gives each
    /// node's buzz-free stiffness beside the linear K_max (CSV or JSON).
    #[command(flatten)]
    nonlinear: NonlinearArgs,
}

pub fn run(a: Args) -> anyhow::Result<()> {
    if a.shard.is_some() && a.format != Format::Csv {
        return Err(UsageError(
            "--shard needs --format csv: a JSON object, C header or Rust module is one whole table and cannot be joined from parts; shard the CSV, join it, or run unsharded".into(),
        )
        .into());
    }
    let precision = match a.precision {
        PrecisionArg::Double => Precision::Double,
        PrecisionArg::Float => Precision::Float,
    };
    if precision != Precision::Double && a.format == Format::Csv {
        return Err(UsageError(
            "--precision float needs --format c, rust or json: the CSV always holds double values"
                .into(),
        )
        .into());
    }
    let mut outputs = Plan::new();
    let data = outputs.data("-o", a.output.as_deref());
    let certify = a.certify.as_deref().map(|p| outputs.file("--certify", p));
    let mut out = outputs.check()?;
    let g = a.grid.resolve()?;
    if certify.is_some() && a.shard.is_some() {
        return Err(UsageError("--certify proves a whole table: leave out --shard".into()).into());
    }
    if a.nonlinear.named().any() {
        if a.conservative || a.shard.is_some() || !matches!(a.format, Format::Csv | Format::Json) {
            return Err(UsageError(
                "the buzz-free stiffness (--encoder-resolution, --force-resolution, --coulomb-friction, --static-friction) is a CSV or JSON table of the nodes: leave out --conservative and --shard, and use --format csv or json".into(),
            )
            .into());
        }
        return super::buzzfree::answer(
            &g,
            &a.loop_elements,
            &a.nonlinear.named(),
            a.format == Format::Json,
            out,
            data,
        );
    }
    let opts = a.search.options(g.device)?;
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
    // The elements depend on the device's mass and period only: the loop of the first node
    // carries them to every node and query (the library puts them on each one's plant).
    let elements: Option<Loop> = match (a.loop_elements.named().any(), g.device) {
        (false, _) => None,
        (true, Some((m, t))) => {
            let (bs, delays) = &g.physical;
            let device = Device::new(m, t, bs[0], delays[0])?;
            Some(a.loop_elements.loop_on(&device)?)
        }
        (true, None) => {
            return Err(needs_physical("loop elements"));
        }
    };
    // A set of devices (an interval, or a hand that can let go): every node holds for each
    // member; the set's damping and delay are the table's axes.
    let set = match g.device {
        Some((m, t)) => {
            let (bs, delays) = &g.physical;
            let first = Device::new(m, t, bs[0], delays[0])?;
            a.loop_elements.device_set(&first, &g.sets, true)?
        }
        None => None,
    };
    if let Some(set) = &set
        && a.format == Format::Csv
    {
        eprintln!("note: {}", set.describe().join("; "));
    }
    let mut base = TableOptions::new(opts)
        .with_conservative(a.conservative)
        .with_precision(precision);
    if let Some(f) = a.margin {
        base = base.with_margin(f).context("--margin")?;
    }
    let build = |ds: &[f64]| -> stabound::Result<AmaxTable> {
        let options = base.clone();
        let progress = Progress::spinner(format!(
            "table: {} nodes ({} d x {} delta)",
            ds.len() * g.deltas.len(),
            ds.len(),
            g.deltas.len()
        ));
        let t = match (&set, &elements) {
            (Some(set), _) => amax_table(&g.deltas, ds, &options.with_device_set(set.clone())),
            (None, None) => amax_table(&g.deltas, ds, &options),
            (None, Some(lp)) => amax_table(&g.deltas, ds, &options.with_elements(lp)),
        };
        progress.finish();
        t
    };
    let (nx, nd) = (g.deltas.len(), g.ds.len());
    let what = format!("nodes ({nd} d x {nx} delta)");
    let nodes = plan(
        nd.saturating_mul(nx),
        a.shard.unwrap_or(Shard::ALL),
        MAX_ROWS,
        &what,
    )?;
    if a.shard.is_none() {
        let mut t = build(&g.ds)?;
        let mut proof = None;
        if let Some(slot) = certify {
            let budget = a.certify_boxes as usize;
            let cert = certify_table(&t, budget).map_err(|e| match e {
                // not proved: the flags that help, in the user's units
                stabound::Error::Numerical(_) => {
                    anyhow::anyhow!("{e}: {}", not_proved_hint(&g, budget))
                }
                e => e.into(),
            })?;
            let (cells, boxes) = cert.counts();
            let of = match cert.members() {
                1 => String::new(),
                n => format!(" (over the set's {n} devices)"),
            };
            eprintln!("certified: {cells} cells proved stable by {boxes} boxes{of}");
            if let Some((grown, largest)) = cert.grown() {
                eprintln!(
                    "note: {grown} cells that no lowering proved within {budget} boxes a cell had their budget grown, up to {largest} boxes a cell, before any node was lowered; the checker replays about 10 boxes a second on wide cells of a loop with elements (a finer axis makes narrower cells that need fewer boxes)"
                );
            }
            proof = Some((slot, cert.to_json()));
            t = cert.into_table();
        }
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
        if let Some((slot, json)) = proof {
            out.write(slot, json.as_bytes())?;
        }
        return out.finish();
    }
    // The d rows the shard's nodes lie on. Rows of whole delays are built and checked
    // alone, so the sub-table gives these nodes the same values, bit for bit, as the whole
    // table; a conservative bilinear table shares lowering across d, so it is built whole.
    let bytes = if nodes.is_empty() {
        to_csv_bytes(&lookup_header(&units))
    } else {
        let (first, last) = (nodes.start / nx, (nodes.end - 1) / nx);
        let whole = a.conservative && Interpolation::for_delays(&g.ds) == Interpolation::Bilinear;
        let (lo, hi) = if whole { (0, nd - 1) } else { (first, last) };
        let t = build(&g.ds[lo..=hi])?;
        if let Some(u) = &units {
            u.check_table(&t)?;
        }
        let off = lo * nx;
        to_csv_bytes(&lookup_rows(&t, &units, nodes.start - off..nodes.end - off))
    };
    out.write(data, &bytes)?;
    out.finish()
}

/// What helps where a certified table's cell is not proved: a larger `--certify-boxes`
/// (while below its limit) and the damping axis (or `delta` axis) with a node halfway in
/// every interval, written in the units it was given in.
fn not_proved_hint(g: &super::args::Grid, budget: usize) -> String {
    let (flag, axis) = match g.device {
        Some(_) => ("--damping", &g.physical.0),
        None => ("--delta", &g.deltas),
    };
    let grown = budget.max(CELL_BOXES_CAP);
    let boxes = if grown < MAX_CELL_BOXES_FLAG {
        format!(
            "--certify-boxes {MAX_CELL_BOXES_FLAG} (the budget grew to {grown} boxes a cell), or "
        )
    } else {
        String::new()
    };
    format!("try {boxes}a finer axis, {flag} {}", finer(axis))
}

/// The largest `--certify-boxes`.
const MAX_CELL_BOXES_FLAG: usize = 65536;

/// The axis with a node halfway in each interval: `START:STOP:COUNT` when the axis is evenly
/// spaced (to a relative 1e-9 of its span, far above the rounding of a `START:STOP:COUNT`
/// axis's values), else the list.
fn finer(axis: &[f64]) -> String {
    let n = axis.len();
    let (first, last) = (axis[0], axis[n - 1]);
    let step = (last - first) / (n - 1).max(1) as f64;
    let even = axis
        .iter()
        .enumerate()
        .all(|(k, &v)| (v - (first + k as f64 * step)).abs() <= 1e-9 * (last - first).abs());
    if even && n > 1 {
        return format!("{first}:{last}:{}", 2 * n - 1);
    }
    let mut values = vec![first];
    for w in axis.windows(2) {
        values.extend([0.5 * (w[0] + w[1]), w[1]]);
    }
    let shown: Vec<String> = values.iter().map(f64::to_string).collect();
    shown.join(",")
}

#[cfg(test)]
mod tests {
    use super::finer;

    #[test]
    fn a_finer_axis_has_a_node_halfway_in_each_interval() {
        // evenly spaced: twice the intervals, as START:STOP:COUNT
        assert_eq!(finer(&[0.0, 50.0, 100.0, 150.0, 200.0]), "0:200:9");
        // uneven: the list with each midpoint
        assert_eq!(finer(&[0.0, 10.0, 30.0]), "0,5,10,20,30");
        assert_eq!(finer(&[0.5]), "0.5");
    }
}
