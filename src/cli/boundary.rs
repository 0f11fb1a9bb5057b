//! `stabound boundary`: stability boundaries for lists of plants, as CSV/JSON and SVG.

use std::io::IsTerminal;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use anyhow::Context;
use clap::ValueEnum;
use indicatif::{ProgressBar, ProgressDrawTarget};
use rayon::prelude::*;
use stabound::boundary::{self, Axis, BisectOptions, Boundary, DEFAULT_TOL, Plane, SweepOptions};
use stabound::export::csv::{boundaries_csv_chunks, to_csv_bytes};
use stabound::export::table::boundaries_table;
use stabound::export::{Cell, Table, json::to_json_bytes};
use stabound::params::{Normalized, Plant, Wall};
use stabound::plot::{Figure, LineStyle};

use super::UsageError;
use super::args::RowFormat as Format;
use super::args::{List, MAX_CURVES, SHARD_HELP, Shard, check_shard, finite, list, plan, shard};
use super::output::Plan;

/// The most vertices all the curves of one run may have together (each curve has at most
/// `boundary::MAX_VERTICES`): about 70 bytes each in memory while the CSV is built, so some
/// 1.4 GB at most.
const MAX_RUN_VERTICES: usize = 20_000_000;

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum PlaneArg {
    /// Stiffness against virtual damping, for each (delta, d) (paper Figs. 5, 7, 8).
    AlphaBeta,
    /// Physical damping against virtual damping, for each (alpha, d) (paper Figs. 6, 9).
    DeltaBeta,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum MethodArg {
    /// D-decomposition: exact curve pieces (alpha-beta plane only).
    Exact,
    /// Parallel grid of point tests, bisection of each crossing, adaptive refinement.
    Bisect,
}

/// Stability boundaries as closed polylines, one per (delta, d) in the alpha-beta plane or
/// one per (alpha, d) in the delta-beta plane.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Physical damping values (LIST: 0,0.25,0.5 or START:STOP:COUNT). In the delta-beta plane
    /// the range of the horizontal axis is from the smallest to the largest value [default 0,1].
    #[arg(long, value_parser = list, allow_hyphen_values = true)]
    delta: Option<List>,
    /// Delay factors d = delay / T (LIST).
    #[arg(long, value_parser = list, allow_hyphen_values = true)]
    d: Option<List>,
    /// The parameter plane.
    #[arg(long, value_enum, default_value = "alpha-beta")]
    plane: PlaneArg,
    /// Stiffness values (LIST), for the delta-beta plane.
    #[arg(long, value_parser = list, allow_hyphen_values = true)]
    alpha: Option<List>,
    /// Engine [default: exact in the alpha-beta plane, bisect in the delta-beta plane].
    #[arg(long, value_enum)]
    method: Option<MethodArg>,
    /// Accuracy of every point, and largest deviation of the polyline from the true curve,
    /// in normalized units.
    #[arg(long, default_value_t = DEFAULT_TOL, value_parser = finite, allow_hyphen_values = true)]
    tol: f64,
    /// Output format.
    #[arg(long, value_enum, default_value = "csv")]
    format: Format,
    /// Write the data to this file instead of stdout.
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Also draw every curve of the request into this file (.svg, .png or .pdf by its
    /// extension).
    #[arg(long)]
    svg: Option<PathBuf>,
    /// Work units are the curves, in output order.
    #[arg(long, value_parser = shard, help = SHARD_HELP)]
    shard: Option<Shard>,
}

/// A progress bar on stderr that appears only when stderr is a terminal and the work has
/// taken more than a second.
struct Progress {
    bar: ProgressBar,
    start: Instant,
    shown: AtomicBool,
    terminal: bool,
}

impl Progress {
    fn new(len: usize) -> Self {
        let bar = ProgressBar::hidden();
        bar.set_length(len as u64);
        Self {
            bar,
            start: Instant::now(),
            shown: AtomicBool::new(false),
            terminal: std::io::stderr().is_terminal(),
        }
    }

    fn tick(&self) {
        self.bar.inc(1);
        if self.terminal
            && self.start.elapsed() > Duration::from_secs(1)
            && !self.shown.swap(true, Ordering::Relaxed)
        {
            self.bar.set_draw_target(ProgressDrawTarget::stderr());
        }
    }

    fn finish(&self) {
        self.bar.finish_and_clear();
    }
}

pub fn run(a: Args) -> anyhow::Result<()> {
    // the library's own check, before any work or output-path check
    boundary::check_tol(a.tol).context("--tol")?;
    check_shard(a.shard, a.format == Format::Csv, a.svg.is_some())?;
    let mut outputs = Plan::new();
    let data = outputs.data("-o", a.output.as_deref());
    let svg_format = super::figure::option_format("--svg", a.svg.as_deref())?;
    let svg = a.svg.as_deref().map(|p| outputs.file("--svg", p));
    let mut out = outputs.check()?;
    let ds = match &a.d {
        Some(List(v)) => v.clone(),
        None => return Err(UsageError("missing --d LIST (delay factors)".into()).into()),
    };
    let (bytes, figure) = match a.plane {
        PlaneArg::AlphaBeta => alpha_beta(&a, &ds)?,
        PlaneArg::DeltaBeta => delta_beta(&a, &ds)?,
    };
    if let (Some(svg), Some(figure)) = (svg, &figure) {
        out.write(svg, &super::figure::render(figure, svg_format)?)?;
    }
    out.write_parts(data, &bytes)?;
    out.finish()
}

fn alpha_beta(a: &Args, ds: &[f64]) -> anyhow::Result<(Vec<Vec<u8>>, Option<Figure>)> {
    if a.alpha.is_some() {
        return Err(UsageError(
            "--alpha belongs to --plane delta-beta; in the alpha-beta plane give --delta and --d"
                .into(),
        )
        .into());
    }
    let deltas = &a
        .delta
        .as_ref()
        .ok_or_else(|| UsageError("missing --delta LIST (physical damping)".into()))?
        .0;
    let options = SweepOptions {
        method: match a.method.unwrap_or(MethodArg::Exact) {
            MethodArg::Exact => boundary::Method::Exact,
            MethodArg::Bisect => boundary::Method::Bisect,
        },
        tol: a.tol,
    };
    for &x in deltas {
        Plant::new(x, 0.0)?;
    }
    for &d in ds {
        Plant::new(0.0, d)?;
    }
    let what = format!("curves ({} delta x {} d)", deltas.len(), ds.len());
    let units = plan(
        deltas.len().saturating_mul(ds.len()),
        a.shard.unwrap_or(Shard::ALL),
        MAX_CURVES,
        &what,
    )?;
    // the plants of this run, delta outer and d inner as `boundary::sweep` orders them
    let plants: Vec<Plant> = units
        .map(|k| Plant::new(deltas[k / ds.len()], ds[k % ds.len()]))
        .collect::<Result<_, _>>()?;
    let progress = Progress::new(plants.len());
    let vertices = std::sync::atomic::AtomicUsize::new(0);
    let result: anyhow::Result<Vec<Boundary>> = plants
        .par_iter()
        .map(|p| {
            let b = boundary::boundary(p, &options)?;
            progress.tick();
            let total = vertices.fetch_add(b.points.len(), Ordering::Relaxed) + b.points.len();
            if total > MAX_RUN_VERTICES {
                return Err(UsageError(format!(
                    "the curves of this run have more than {MAX_RUN_VERTICES} vertices in all, more than fit in memory: split the run with --shard K/N or use a larger --tol"
                ))
                .into());
            }
            Ok(b)
        })
        .collect();
    progress.finish();
    let boundaries = result?;
    // The figure is built only when one is asked for (thinning 30k vertices per curve is not
    // free).
    let figure = a.svg.is_some().then(|| boundary_figure(&boundaries));
    let bytes = match a.format {
        // CSV straight from the boundaries: no intermediate table of 150,000 cells.
        Format::Csv => boundaries_csv_chunks(&boundaries),
        Format::Json => vec![to_json_bytes(&boundaries_table(&boundaries))],
    };
    Ok((bytes, figure))
}

/// Keeps the points of a polyline at least `step` apart (and the last), for drawing: a
/// boundary to 1e-9 has tens of thousands of vertices, far below a pixel apart.
fn thin(points: &[(f64, f64)], step: (f64, f64)) -> Vec<(f64, f64)> {
    let mut out: Vec<(f64, f64)> = Vec::new();
    for (i, &p) in points.iter().enumerate() {
        let far = out
            .last()
            .is_none_or(|q: &(f64, f64)| (p.0 - q.0).abs() > step.0 || (p.1 - q.1).abs() > step.1);
        if far || i + 1 == points.len() {
            out.push(p);
        }
    }
    out
}

fn span(all: &[(f64, f64)]) -> (f64, f64) {
    let f = |g: fn(&(f64, f64)) -> f64| {
        let (lo, hi) = all
            .iter()
            .map(g)
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| {
                (l.min(v), h.max(v))
            });
        ((hi - lo) / 1500.0).max(0.0)
    };
    (f(|p| p.0), f(|p| p.1))
}

fn boundary_figure(bs: &[Boundary]) -> Figure {
    let mut fig = Figure::new(
        "Stability boundaries",
        "α (normalized stiffness)",
        "β (normalized damping)",
    );
    if bs.len() > 6 {
        fig.style = stabound::plot::FigureStyle::large();
    }
    let all: Vec<(f64, f64)> = bs.iter().flat_map(|b| b.xy()).collect();
    let step = span(&all);
    // one colour and marker per curve (70 distinct pairs)
    for (color, b) in bs.iter().enumerate() {
        fig.push(
            format!("d = {}, δ = {}", b.d, b.delta),
            thin(&b.xy(), step),
            LineStyle::Solid,
            color,
        );
    }
    fig
}

fn delta_beta(a: &Args, ds: &[f64]) -> anyhow::Result<(Vec<Vec<u8>>, Option<Figure>)> {
    if a.method == Some(MethodArg::Exact) {
        return Err(UsageError(
            "--method exact is for the alpha-beta plane; the delta-beta plane uses --method bisect"
                .into(),
        )
        .into());
    }
    let alphas = &a
        .alpha
        .as_ref()
        .ok_or_else(|| UsageError("missing --alpha LIST for --plane delta-beta".into()))?
        .0;
    let range = match &a.delta {
        None => (0.0, 1.0),
        Some(List(v)) => {
            let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            if hi <= lo {
                return Err(UsageError(
                    "in the delta-beta plane --delta gives the axis range: at least two different values, e.g. 0:1:2".into(),
                )
                .into());
            }
            (lo, hi)
        }
    };
    for &al in alphas {
        Wall::new(al, 0.0)?;
        if al < 0.0 {
            return Err(UsageError(format!(
                "--alpha {al}: stiffness must be >= 0 (no wall with alpha < 0 is stable)"
            ))
            .into());
        }
    }
    for &d in ds {
        Plant::new(range.0, d)?;
        Plant::new(range.1, d)?;
    }
    let what = format!("curves ({} alpha x {} d)", alphas.len(), ds.len());
    let units = plan(
        alphas.len().saturating_mul(ds.len()),
        a.shard.unwrap_or(Shard::ALL),
        MAX_CURVES,
        &what,
    )?;
    let requests: Vec<(f64, f64)> = units
        .map(|k| (alphas[k / ds.len()], ds[k % ds.len()]))
        .collect();
    let progress = Progress::new(requests.len());
    let result: Result<Vec<_>, _> = requests
        .par_iter()
        .map(|&(alpha, d)| {
            let plane = Plane {
                x: Axis::Delta,
                y: Axis::Beta,
                at: Normalized {
                    alpha,
                    beta: 0.0,
                    delta: 0.0,
                    d,
                },
            };
            let c = boundary::bisect(
                &plane,
                &BisectOptions {
                    tol: a.tol,
                    x_range: Some(range),
                    ..BisectOptions::default()
                },
            );
            progress.tick();
            c
        })
        .collect();
    progress.finish();
    let contours = result?;
    let mut t = Table::new(&["alpha", "d", "delta", "beta", "loop", "piece"]);
    let mut fig = Figure::new(
        "Stability boundaries",
        "δ (normalized physical damping)",
        "β (normalized damping)",
    );
    let all: Vec<(f64, f64)> = contours
        .iter()
        .flat_map(|c| c.loops.iter().flatten().map(|p| (p.x, p.y)))
        .collect();
    let step = span(&all);
    for (k, (c, &(alpha, d))) in contours.iter().zip(&requests).enumerate() {
        let mut xy: Vec<(f64, f64)> = Vec::new();
        for (li, lp) in c.loops.iter().enumerate() {
            for p in lp {
                t.push([
                    Cell::Num(alpha),
                    Cell::Num(d),
                    Cell::Num(p.x),
                    Cell::Num(p.y),
                    Cell::Num(li as f64),
                    Cell::Static(if p.clipped { "clipped" } else { "bisection" }),
                ]);
            }
            // the edges of the requested delta range are not boundaries: not drawn
            for piece in stabound::figures::boundary_lines(lp) {
                if !xy.is_empty() {
                    xy.push((f64::NAN, f64::NAN));
                }
                xy.extend(thin(&piece, step));
            }
        }
        fig.push(format!("α = {alpha}, d = {d}"), xy, LineStyle::Solid, k);
    }
    let bytes = match a.format {
        Format::Csv => vec![to_csv_bytes(&t)],
        Format::Json => vec![to_json_bytes(&t)],
    };
    Ok((bytes, Some(fig)))
}
