//! `stabound passivity`: the passive region for a whole-sample delay and a velocity filter,
//! the largest passive stiffness, and the comparison with the stable region.

use std::path::PathBuf;

use clap::ValueEnum;
use stabound::VelocityFilter;
use stabound::export::{Cell, DeviceScale, Table, csv::to_csv_bytes, json::to_json_bytes};
use stabound::figures::FigureData;
use stabound::passivity::delay::{Comparison, Criterion, PassiveRegion, compare};
use stabound::passivity::figures::companions;
use stabound::plot::{Figure, Legend, LineStyle};

use super::UsageError;
use super::args::RowFormat as Format;
use super::args::finite;
use super::output::Plan;

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum PlaneArg {
    /// Stiffness against virtual damping for one delta (paper Fig. 8).
    AlphaBeta,
    /// Physical damping against virtual damping for one alpha (paper Fig. 9).
    DeltaBeta,
}

/// The passive region (Colgate and Schenkel's condition with the delay and the velocity
/// filter in the virtual environment) and, without a filter, the stable region around it.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Physical damping delta; in the delta-beta plane the largest delta drawn [default 4].
    #[arg(long, value_parser = finite, allow_hyphen_values = true)]
    delta: Option<f64>,
    /// Delay in whole samples, d = delay / T.
    #[arg(long, value_parser = finite, allow_hyphen_values = true, default_value_t = 0.0)]
    d: f64,
    /// The parameter plane.
    #[arg(long, value_enum, default_value = "alpha-beta")]
    plane: PlaneArg,
    /// Stiffness alpha, for the delta-beta plane.
    #[arg(long, value_parser = finite, allow_hyphen_values = true)]
    alpha: Option<f64>,
    /// Also report the largest passive stiffness at this virtual damping beta.
    #[arg(long, value_parser = finite, allow_hyphen_values = true)]
    beta: Option<f64>,
    /// First-order low-pass velocity filter with this cutoff in Hz (needs --period).
    #[arg(long, value_parser = finite, allow_hyphen_values = true,
          conflicts_with_all = ["filter_pole", "velocity_filter_samples"])]
    velocity_filter_cutoff: Option<f64>,
    /// First-order low-pass velocity filter with this pole a = exp(-2 pi f_c T), 0 <= a < 1.
    #[arg(long, value_parser = finite, allow_hyphen_values = true,
          conflicts_with = "velocity_filter_samples")]
    filter_pole: Option<f64>,
    /// Moving-average velocity filter over this many samples.
    #[arg(long)]
    velocity_filter_samples: Option<usize>,
    /// Device mass in kg: with --period adds stiffness and damping in N/m and N s/m.
    #[arg(long, value_parser = finite, allow_hyphen_values = true)]
    mass: Option<f64>,
    /// Sampling period in s.
    #[arg(long, value_parser = finite, allow_hyphen_values = true)]
    period: Option<f64>,
    /// Largest distance between the drawn edge and the true edge, in normalized units.
    #[arg(long, default_value_t = 1e-7, value_parser = finite, allow_hyphen_values = true)]
    tol: f64,
    /// One row of results (largest passive stiffness, containment, area shares, witnesses)
    /// instead of the region's vertices.
    #[arg(long)]
    summary: bool,
    /// Output format.
    #[arg(long, value_enum, default_value = "csv")]
    format: Format,
    /// Write the data to this file instead of stdout.
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Also draw the passive region (dash-dotted) over the stable region into this file (.svg,
    /// .png or .pdf by its extension).
    #[arg(long)]
    svg: Option<PathBuf>,
    /// Instead, write the companions of the paper's Figs. 8 and 9 for d = 1, 2, 4
    /// (fig08-d1.svg, fig08-d1.csv, ...) into this directory.
    #[arg(long = "figures-dir", conflicts_with_all = ["summary", "output", "svg"])]
    figures: Option<PathBuf>,
    /// With --figures-dir: the file extensions of the drawings (svg, png, pdf; a list).
    #[arg(
        long = "extension",
        value_delimiter = ',',
        default_value = "svg",
        requires = "figures"
    )]
    extensions: Vec<String>,
}

fn filter_of(a: &Args) -> anyhow::Result<VelocityFilter> {
    Ok(if let Some(hz) = a.velocity_filter_cutoff {
        let t = a.period.ok_or_else(|| {
            UsageError("--velocity-filter-cutoff needs --period (the sampling period in s)".into())
        })?;
        VelocityFilter::low_pass_cutoff(hz, t)?
    } else if let Some(p) = a.filter_pole {
        VelocityFilter::low_pass(p)?
    } else if let Some(n) = a.velocity_filter_samples {
        VelocityFilter::moving_average(n)?
    } else {
        VelocityFilter::none()
    })
}

fn units_of(a: &Args) -> anyhow::Result<Option<DeviceScale>> {
    match (a.mass, a.period) {
        (Some(m), Some(t)) => {
            // validated by the library's device type
            stabound::Device {
                mass: m,
                damping: 0.0,
                period: t,
                delay: stabound::Delay::Samples(0.0),
            }
            .validate()?;
            Ok(Some(DeviceScale { mass: m, period: t }))
        }
        (Some(_), None) => Err(UsageError("--mass needs --period".into()).into()),
        _ => Ok(None),
    }
}

fn filter_name(f: &VelocityFilter) -> String {
    match f.kind() {
        stabound::FilterKind::LowPass { pole } if !f.is_identity() => {
            format!("low-pass a = {pole}")
        }
        stabound::FilterKind::MovingAverage { samples } if !f.is_identity() => {
            format!("moving average N = {samples}")
        }
        _ => "none".into(),
    }
}

pub fn run(a: Args) -> anyhow::Result<()> {
    if let Some(dir) = &a.figures {
        return write_figures(dir, &a.extensions);
    }
    let mut outputs = Plan::new();
    let data = outputs.data("-o", a.output.as_deref());
    let svg_format = super::figure::option_format("--svg", a.svg.as_deref())?;
    let svg = a.svg.as_deref().map(|p| outputs.file("--svg", p));
    let mut out = outputs.check()?;
    let filter = filter_of(&a)?;
    let units = units_of(&a)?;
    let crit = Criterion::new(a.d, filter)?;
    let (bytes, fig) = match a.plane {
        PlaneArg::AlphaBeta => alpha_beta(&a, &crit, units)?,
        PlaneArg::DeltaBeta => delta_beta(&a, &crit, units)?,
    };
    if let (Some(slot), Some(fig)) = (svg, fig) {
        out.write(slot, &super::figure::render(&fig, svg_format)?)?;
    }
    out.write(data, &bytes)?;
    out.finish()
}

fn encode(a: &Args, t: &Table) -> Vec<u8> {
    match a.format {
        Format::Csv => to_csv_bytes(t),
        Format::Json => to_json_bytes(t),
    }
}

fn alpha_beta(
    a: &Args,
    crit: &Criterion,
    units: Option<DeviceScale>,
) -> anyhow::Result<(Vec<u8>, Option<Figure>)> {
    if a.alpha.is_some() {
        return Err(UsageError(
            "--alpha belongs to --plane delta-beta; in the alpha-beta plane give --delta".into(),
        )
        .into());
    }
    let delta = a
        .delta
        .ok_or_else(|| UsageError("missing --delta (physical damping)".into()))?;
    let filter = crit.filter();
    let cmp: Option<Comparison> = if filter.is_identity() {
        Some(compare(delta, a.d, filter, a.tol)?)
    } else {
        eprintln!(
            "note: the stable region of a loop with a velocity filter is not computed by this version; the passive region is reported alone"
        );
        None
    };
    let region = match &cmp {
        Some(c) => c.region.clone(),
        None => crit.region_alpha_beta(delta, a.tol)?,
    };
    let best = crit.max_stiffness(delta, a.tol)?;
    let at_beta = match a.beta {
        Some(b) => Some((b, crit.max_stiffness_at(delta, b, a.tol)?)),
        None => None,
    };
    report(&best, &at_beta, &cmp);
    let fig = a
        .svg
        .is_some()
        .then(|| overlay_ab(&region, &cmp, a.d, &filter));
    let t = if a.summary {
        summary_table(delta, a.d, &filter, &best, &at_beta, &cmp, &units)
    } else {
        let mut cols = vec!["region", "delta", "d", "alpha", "beta", "theta", "edge"];
        if units.is_some() {
            cols.extend(["K_N_per_m", "B_Ns_per_m"]);
        }
        let mut t = Table::new(&cols);
        let mut row = |name: &'static str, x: f64, y: f64, theta: f64, edge: &'static str| {
            let base = [
                Cell::Static(name),
                Cell::Num(delta),
                Cell::Num(a.d),
                Cell::Num(x),
                Cell::Num(y),
                Cell::Num(theta),
                Cell::Static(edge),
            ];
            match &units {
                Some(u) => {
                    let [c0, c1, c2, c3, c4, c5, c6] = base;
                    t.push([
                        c0,
                        c1,
                        c2,
                        c3,
                        c4,
                        c5,
                        c6,
                        Cell::Num(u.k(x)),
                        Cell::Num(u.b(y)),
                    ]);
                }
                None => t.push(base),
            }
        };
        for p in &region.points {
            row("passive", p.x, p.y, p.theta, p.edge.name());
        }
        if let Some(c) = &cmp {
            for &(x, y) in &c.stable {
                row("stable", x, y, f64::NAN, "exact");
            }
        }
        t
    };
    Ok((encode(a, &t), fig))
}

fn report(
    best: &Option<(f64, f64)>,
    at_beta: &Option<(f64, Option<f64>)>,
    cmp: &Option<Comparison>,
) {
    match best {
        Some((al, b)) => eprintln!("largest passive stiffness: alpha = {al} at beta = {b}"),
        None => eprintln!("no wall is passive without physical damping (delta = 0)"),
    }
    if let Some((b, v)) = at_beta {
        match v {
            Some(al) => eprintln!("largest passive stiffness at beta = {b}: alpha = {al}"),
            None => eprintln!("no wall with beta = {b} is passive"),
        }
    }
    if let Some(c) = cmp {
        eprintln!(
            "passive region inside the stable region: {}; passive share of the stable region {:.6}",
            if c.inside { "yes" } else { "no" },
            c.passive_fraction_of_stable
        );
        if let Some(w) = c.passive_unstable {
            eprintln!(
                "passive but unstable: alpha = {}, beta = {}",
                w.alpha, w.beta
            );
        }
    }
}

fn summary_table(
    delta: f64,
    d: f64,
    filter: &VelocityFilter,
    best: &Option<(f64, f64)>,
    at_beta: &Option<(f64, Option<f64>)>,
    cmp: &Option<Comparison>,
    units: &Option<DeviceScale>,
) -> Table {
    let mut t = Table::new(&[
        "delta",
        "d",
        "filter",
        "alpha_max_passive",
        "beta_at_max",
        "beta",
        "alpha_max_at_beta",
        "passive_area",
        "stable_area",
        "inside",
        "passive_share_of_stable",
        "stable_share_of_passive",
        "witness_alpha",
        "witness_beta",
        "K_max_N_per_m",
        "B_at_max_Ns_per_m",
    ]);
    let nan = f64::NAN;
    let (am, bm) = best.unwrap_or((nan, nan));
    let (b, ab) = match at_beta {
        Some((b, v)) => (*b, v.unwrap_or(nan)),
        None => (nan, nan),
    };
    let (k, bb) = match units {
        Some(u) => (u.k(am), u.b(bm)),
        None => (nan, nan),
    };
    let (pa, sa, inside, s1, s2, wa, wb) = match cmp {
        Some(c) => (
            c.passive_area,
            c.stable_area,
            if c.inside { "yes" } else { "no" },
            c.passive_fraction_of_stable,
            c.stable_fraction_of_passive,
            c.passive_unstable.map_or(nan, |w| w.alpha),
            c.passive_unstable.map_or(nan, |w| w.beta),
        ),
        None => (nan, nan, "not computed", nan, nan, nan, nan),
    };
    t.push([
        Cell::Num(delta),
        Cell::Num(d),
        Cell::Text(filter_name(filter)),
        Cell::Num(am),
        Cell::Num(bm),
        Cell::Num(b),
        Cell::Num(ab),
        Cell::Num(pa),
        Cell::Num(sa),
        Cell::Static(inside),
        Cell::Num(s1),
        Cell::Num(s2),
        Cell::Num(wa),
        Cell::Num(wb),
        Cell::Num(k),
        Cell::Num(bb),
    ]);
    t
}

fn overlay_ab(
    region: &PassiveRegion,
    cmp: &Option<Comparison>,
    d: f64,
    filter: &VelocityFilter,
) -> Figure {
    let mut fig = Figure::new(
        &format!(
            "Passive (dash-dotted) and stable regions, delta = {}, d = {d}, filter: {}",
            region.at,
            filter_name(filter)
        ),
        "α (normalized stiffness)",
        "β (normalized damping)",
    );
    if let Some(c) = cmp {
        fig.push("stable region", c.stable.clone(), LineStyle::Solid, 1);
    }
    fig.push("passive region", region.xy(), LineStyle::DashDot, 2);
    fig.legend = Legend::UpperRight;
    fig
}

fn delta_beta(
    a: &Args,
    crit: &Criterion,
    units: Option<DeviceScale>,
) -> anyhow::Result<(Vec<u8>, Option<Figure>)> {
    let alpha = a
        .alpha
        .ok_or_else(|| UsageError("missing --alpha for --plane delta-beta".into()))?;
    if a.summary || a.beta.is_some() {
        return Err(UsageError(
            "--summary and --beta belong to the alpha-beta plane (they are results at one delta)"
                .into(),
        )
        .into());
    }
    let delta_max = a.delta.unwrap_or(4.0);
    let region = crit.region_delta_beta(alpha, delta_max, a.tol)?;
    let filter = crit.filter();
    let stable: Option<Vec<(f64, f64)>> = if filter.is_identity() {
        Some(stabound::passivity::figures::stable_delta_beta(
            alpha, a.d, delta_max,
        )?)
    } else {
        eprintln!(
            "note: the stable region of a loop with a velocity filter is not computed by this version; the passive region is reported alone"
        );
        None
    };
    if region.points.is_empty() {
        eprintln!("no wall with alpha = {alpha} is passive for delta up to {delta_max}");
    }
    let mut cols = vec!["region", "alpha", "d", "delta", "beta", "theta", "edge"];
    if units.is_some() {
        cols.extend(["damping_Ns_per_m", "B_Ns_per_m"]);
    }
    let mut t = Table::new(&cols);
    let mut row = |name: &'static str, x: f64, y: f64, theta: f64, edge: &'static str| {
        let base = [
            Cell::Static(name),
            Cell::Num(alpha),
            Cell::Num(a.d),
            Cell::Num(x),
            Cell::Num(y),
            Cell::Num(theta),
            Cell::Static(edge),
        ];
        match &units {
            Some(u) => {
                let [c0, c1, c2, c3, c4, c5, c6] = base;
                t.push([
                    c0,
                    c1,
                    c2,
                    c3,
                    c4,
                    c5,
                    c6,
                    Cell::Num(u.damping(x)),
                    Cell::Num(u.b(y)),
                ]);
            }
            None => t.push(base),
        }
    };
    for p in &region.points {
        row("passive", p.x, p.y, p.theta, p.edge.name());
    }
    if let Some(s) = &stable {
        for &(x, y) in s {
            row("stable", x, y, f64::NAN, "bisection");
        }
    }
    let fig = a.svg.is_some().then(|| {
        let mut fig = Figure::new(
            &format!(
                "Passive (dash-dotted) and stable regions, alpha = {alpha}, d = {}, filter: {}",
                a.d,
                filter_name(&filter)
            ),
            "δ (normalized physical damping)",
            "β (normalized damping)",
        );
        if let Some(s) = &stable {
            fig.push("stable region", s.clone(), LineStyle::Solid, 1);
        }
        fig.push("passive region", region.xy(), LineStyle::DashDot, 2);
        fig.x_range = Some((0.0, delta_max));
        fig.legend = Legend::LowerLeft;
        fig
    });
    Ok((encode(a, &t), fig))
}

fn write_figures(dir: &std::path::Path, extensions: &[String]) -> anyhow::Result<()> {
    let formats = super::figure::formats_of("--extension", extensions)?;
    std::fs::create_dir_all(dir).map_err(|e| {
        anyhow::anyhow!("cannot create the output directory {}: {e}", dir.display())
    })?;
    let names: Vec<String> = stabound::passivity::figures::companion_names();
    let (paths, slots, mut out) =
        super::figure::plan_figures(dir, &names, &formats, "--figures-dir")?;
    let data: Vec<FigureData> = companions()?;
    super::figure::write_figures(&mut out, &data, &formats, &slots)?;
    out.finish()?;
    super::figure::report(&paths);
    Ok(())
}
