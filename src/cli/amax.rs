//! `stabound amax`: maximum stable stiffness for lists of delta (or physical damping) and d.

use std::path::PathBuf;

use rayon::prelude::*;
use stabound::amax::{AmaxPoint, alpha_max_each};
use stabound::elements::Loop;
use stabound::export::DeviceScale;
use stabound::params::{Device, Plant};
use stabound::plot::{Figure, LineStyle};

use super::UsageError;
use super::args::Grid;
use super::args::RowFormat as Format;
use super::args::{
    ElementArgs, GridArgs, MAX_STREAM_ROWS, PHYSICAL_DEVICE, SHARD_HELP, SearchArgs, Shard,
    check_shard, finite, plan, shard,
};
use super::output::{Outputs, Plan, RowStream, Slot};
use stabound::robust::{DeviceSet, RobustAmax, robust_alpha_max};

/// Normalized (--delta LIST --d LIST) or physical (--mass --period --damping LIST and
/// --delay LIST | --delay-samples LIST). One row per (d, delta), d outer.
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    grid: GridArgs,
    #[command(flatten)]
    search: SearchArgs,
    /// Also report this fraction of alpha_max (e.g. 0.75 as in the paper's Section VIII).
    #[arg(long, value_parser = finite, allow_hyphen_values = true)]
    margin: Option<f64>,
    /// Output format.
    #[arg(long, value_enum, default_value = "csv")]
    format: Format,
    /// Write to this file instead of stdout.
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Also draw alpha_max against delta, one line per d (paper Fig. 10), to this file (.svg,
    /// .png or .pdf by its extension).
    #[arg(long)]
    svg: Option<PathBuf>,
    #[arg(long, value_parser = shard, help = SHARD_HELP)]
    shard: Option<Shard>,
    #[command(flatten)]
    loop_elements: ElementArgs,
    #[command(flatten)]
    draw: super::figure::SvgStyleArgs,
}

/// One row per device set (each (d, delta) of the grid, its intervals and its hand): the
/// robust optimum, the stiffness verified for every member, how it was verified, and the
/// binding members.
fn robust(
    elements: &ElementArgs,
    margin: Option<f64>,
    json: bool,
    g: &Grid,
    opts: &stabound::AmaxOptions,
    out: &mut Outputs,
    data: Slot,
) -> anyhow::Result<()> {
    let Some((m, t)) = g.device else {
        return Err(UsageError(format!(
            "a set of devices is given in physical units: give {PHYSICAL_DEVICE}"
        ))
        .into());
    };
    let u = DeviceScale { mass: m, period: t };
    let (bs, delays) = &g.physical;
    let mut cols = vec!["delta", "d", "alpha_max", "beta_at_max", "alpha_verified"];
    if margin.is_some() {
        cols.extend(["alpha_margin", "beta_margin"]);
    }
    cols.extend(["damping", "K_max", "B", "K_verified"]);
    if margin.is_some() {
        cols.push("K_margin");
    }
    cols.extend(["members_examined", "verification", "binding", "set"]);
    let total = g.ds.len().saturating_mul(g.deltas.len());
    let what = format!("rows ({} d x {} delta)", g.ds.len(), g.deltas.len());
    plan(total, Shard::ALL, MAX_STREAM_ROWS, &what)?;
    let nx = g.deltas.len();
    let found: Vec<(DeviceSet, RobustAmax)> = (0..total)
        .into_par_iter()
        .map(|k| -> anyhow::Result<_> {
            let (j, i) = (k % nx, k / nx);
            let device = Device::new(m, t, bs[j], delays[i])?;
            let set = elements
                .device_set(&device, &g.intervals, true)?
                .ok_or_else(|| anyhow::anyhow!("every row of a set of devices is a set"))?;
            let r = robust_alpha_max(&set, opts)?;
            Ok((set, r))
        })
        .collect::<anyhow::Result<_>>()?;
    let mut rows = RowStream::new(out, data, &cols, json)?;
    for (k, (set, r)) in found.iter().enumerate() {
        let (x, d) = (g.deltas[k % nx], g.ds[k / nx]);
        let mut nums = vec![x, d, r.alpha_max, r.beta_at_max, r.alpha_verified];
        if let Some(f) = margin {
            nums.extend([f * r.alpha_verified, r.beta_at_max]);
        }
        nums.extend([
            u.try_damping(x)?,
            u.try_k(r.alpha_max)?,
            u.try_b(r.beta_at_max)?,
            u.try_k(r.alpha_verified)?,
        ]);
        if let Some(f) = margin {
            nums.push(u.try_k(f * r.alpha_verified)?);
        }
        nums.push(r.examined as f64);
        nums.iter().for_each(|&v| rows.num(v));
        rows.text(&r.verification.describe());
        let binding: Vec<String> = r.binding.iter().map(|b| set.describe_member(b)).collect();
        rows.text(&binding.join(" | "));
        rows.text(&set.describe().join("; "));
        if !r.verification.holds() {
            eprintln!(
                "warning: the row at delta = {x}, d = {d} is not verified over its whole set: {}",
                r.verification.describe()
            );
        }
    }
    rows.flush()?;
    rows.finish(out)
}

pub fn run(a: Args) -> anyhow::Result<()> {
    if let Some(f) = a.margin {
        stabound::request::margin(f).map_err(super::args::as_flags)?;
    }
    check_shard(a.shard, a.format == Format::Csv, a.svg.is_some())?;
    let mut outputs = Plan::new();
    let data = outputs.data("-o", a.output.as_deref());
    let svg_format = super::figure::option_format("--svg", a.svg.as_deref())?;
    a.draw.check()?;
    let svg = a.svg.as_deref().map(|p| outputs.file("--svg", p));
    let mut out = outputs.check()?;
    let g = a.grid.resolve()?;
    if a.svg.is_some() && g.deltas.len() < 2 {
        return Err(UsageError(
            "--svg draws alpha_max against delta: give a range of deltas (e.g. --delta 0:4:41, or --damping 0:100:41 with a device); one delta makes no curve".into(),
        )
        .into());
    }
    let opts = a.search.options(g.device)?;
    let named = a.loop_elements.named();
    let elements = match (named.any(), g.device) {
        (false, _) => None,
        (true, Some((m, t))) => Some((named, m, t)),
        (true, None) => {
            return Err(UsageError(format!(
                "loop elements are given in physical units: give the device with {PHYSICAL_DEVICE}"
            ))
            .into());
        }
    };
    let scale = g.device.map(|(mass, period)| DeviceScale { mass, period });
    if let Some(u) = &scale {
        u.check_scale()?;
    }
    if let Some((m, t)) = g.device {
        let (bs, delays) = &g.physical;
        let first = Device::new(m, t, bs[0], delays[0])?;
        match a.loop_elements.device_set(&first, &g.intervals, true)? {
            Some(set) if !set.is_single() => {
                if a.svg.is_some() || a.shard.is_some() {
                    return Err(UsageError(
                        "a set of devices (an interval, or a hand that can let go) gives one robust row per device set: --svg and --shard are for single devices (add --always-gripped if the hand never lets go)".into(),
                    )
                    .into());
                }
                let json = a.format == Format::Json;
                return robust(&a.loop_elements, a.margin, json, &g, &opts, &mut out, data);
            }
            Some(set) => eprintln!("note: {}", set.describe().join("; ")),
            None => {}
        }
    } else if !g.intervals.is_empty() {
        return Err(UsageError(format!(
            "a set of devices is given in physical units: give {PHYSICAL_DEVICE}"
        ))
        .into());
    }
    let total = g.ds.len().saturating_mul(g.deltas.len());
    let what = format!("rows ({} d x {} delta)", g.ds.len(), g.deltas.len());
    let units = plan(total, a.shard.unwrap_or(Shard::ALL), MAX_STREAM_ROWS, &what)?;
    let nx = g.deltas.len();
    let mut cols = vec!["delta", "d", "alpha_max", "beta_at_max"];
    if a.margin.is_some() {
        cols.extend(["alpha_margin", "beta_margin"]);
    }
    if scale.is_some() {
        cols.extend(["damping", "K_max", "B"]);
        if a.margin.is_some() {
            cols.push("K_margin");
        }
    }
    let mut rows = RowStream::new(&mut out, data, &cols, a.format == Format::Json)?;
    // what --svg draws: (delta, alpha_max) per d, in the order of g.ds
    let mut drawn: Option<Vec<Vec<(f64, f64)>>> = svg.map(|_| vec![Vec::new(); g.ds.len()]);
    let mut row = Vec::with_capacity(cols.len());
    if !units.is_empty() {
        let first = units.start;
        // the rows in output order, d outer and delta inner, written chunk by chunk as soon
        // as each and every one before it is done
        let mut write = |_: usize, chunk: &[AmaxPoint]| -> anyhow::Result<()> {
            for r in chunk {
                let (x, d) = (r.delta, r.d);
                row.clear();
                row.extend([x, d, r.alpha_max, r.beta_at_max]);
                if let Some(f) = a.margin {
                    row.extend([f * r.alpha_max, r.beta_at_max]);
                }
                if let Some(u) = scale {
                    row.extend([
                        u.try_damping(x)?,
                        u.try_k(r.alpha_max)?,
                        u.try_b(r.beta_at_max)?,
                    ]);
                    if let Some(f) = a.margin {
                        row.push(u.try_k(f * r.alpha_max)?);
                    }
                }
                row.iter().for_each(|&v| rows.num(v));
                if let Some(lines) = &mut drawn {
                    // every line of this d (a list may repeat a value)
                    for (line, dd) in lines.iter_mut().zip(&g.ds) {
                        if dd.to_bits() == d.to_bits() {
                            line.push((x, r.alpha_max));
                        }
                    }
                }
            }
            rows.flush()?;
            Ok(())
        };
        match &elements {
            None => alpha_max_each(
                units.len(),
                |i| Plant::new(g.deltas[(first + i) % nx], g.ds[(first + i) / nx]),
                &opts,
                write,
            )?,
            Some((named, m, t)) => {
                // the loop's alpha_max by direct search on its own curve, one device per row
                let (bs, delays) = &g.physical;
                let points: Vec<AmaxPoint> = units
                    .clone()
                    .into_par_iter()
                    .map(|k| -> stabound::Result<AmaxPoint> {
                        let (j, i) = (k % nx, k / nx);
                        let device = Device::new(*m, *t, bs[j], delays[i])?;
                        let lp = Loop::physical(&device, named)?;
                        let r = stabound::alpha_max(lp, &opts)?;
                        Ok(AmaxPoint {
                            delta: g.deltas[j],
                            d: g.ds[i],
                            alpha_max: r.alpha_max,
                            beta_at_max: r.beta_at_max,
                        })
                    })
                    .collect::<stabound::Result<_>>()?;
                write(0, &points)?;
            }
        }
    }
    rows.finish(&mut out)?;
    if let (Some(svg), Some(lines)) = (svg, drawn) {
        let mut fig = Figure::new(
            "Maximum stable stiffness (cf. paper Fig. 10)",
            "δ (normalized physical damping)",
            "α_{max} (normalized stiffness)",
        );
        for (i, (&d, pts)) in g.ds.iter().zip(lines).enumerate() {
            fig.push(format!("d = {d}"), pts, LineStyle::Solid, i);
        }
        let fig = a.draw.apply(fig)?;
        out.write(svg, &super::figure::render(&fig, svg_format)?)?;
    }
    out.finish()
}
