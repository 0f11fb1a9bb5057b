//! `stabound passivity`: the passive region for a whole-sample delay and a velocity filter,
//! the largest passive stiffness, and the comparison with the stable region.

use std::path::PathBuf;

use clap::ValueEnum;
use stabound::VelocityFilter;
use stabound::export::{Cell, DeviceScale, Table, csv::to_csv_bytes, json::to_json_bytes};
use stabound::figures::FigureData;
use stabound::figures::passivity::companions;
use stabound::passivity::{
    ColumnComparison, DEFAULT_COLUMNS, Summary, compare_alpha_beta, compare_delta_beta,
};
use stabound::passivity::{Criterion, PassiveRegion, Witness};
use stabound::plot::{Figure, Legend, LineStyle};
use stabound::request::DeviceInputs;

use super::UsageError;
use super::args::RowFormat as Format;
use super::args::finite;
use super::output::{Plan, Progress};

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum PlaneArg {
    /// Stiffness against virtual damping for one delta (paper Fig. 8).
    AlphaBeta,
    /// Physical damping against virtual damping for one alpha (paper Fig. 9).
    DeltaBeta,
}

/// The passive region (Colgate and Schenkel's condition with the delay and the velocity
/// filter in the virtual environment) and the stable region around it.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Physical damping delta; in the delta-beta plane the largest delta drawn [default 4].
    #[arg(long, value_parser = finite, allow_hyphen_values = true, conflicts_with = "damping")]
    delta: Option<f64>,
    /// Delay in whole samples, d = delay / T [default 0].
    #[arg(long, value_parser = finite, allow_hyphen_values = true,
          conflicts_with_all = ["delay_samples", "delay"])]
    d: Option<f64>,
    /// Physical damping b in N s/m (the physical --delta; needs --mass and --period).
    #[arg(long, value_parser = finite, allow_hyphen_values = true)]
    damping: Option<f64>,
    /// Delay in sampling periods (the physical --d; a whole number).
    #[arg(long = "delay-samples", value_parser = finite, allow_hyphen_values = true,
          conflicts_with = "delay")]
    delay_samples: Option<f64>,
    /// Delay in s (a whole number of periods; needs --period).
    #[arg(long, value_parser = finite, allow_hyphen_values = true)]
    delay: Option<f64>,
    /// The parameter plane.
    #[arg(long, value_enum, default_value = "alpha-beta")]
    plane: PlaneArg,
    /// Stiffness alpha, for the delta-beta plane.
    #[arg(long, value_parser = finite, allow_hyphen_values = true, conflicts_with = "stiffness")]
    alpha: Option<f64>,
    /// Also report the largest passive stiffness at this virtual damping beta.
    #[arg(long, value_parser = finite, allow_hyphen_values = true, conflicts_with = "wall_damping")]
    beta: Option<f64>,
    /// Wall stiffness K in N/m (the physical --alpha; needs --mass and --period).
    #[arg(long, value_parser = finite, allow_hyphen_values = true)]
    stiffness: Option<f64>,
    /// Wall damping B in N s/m (the physical --beta; needs --mass and --period).
    #[arg(long = "wall-damping", value_parser = finite, allow_hyphen_values = true)]
    wall_damping: Option<f64>,
    /// First-order low-pass velocity filter with this pole a = exp(-2 pi f_c T), 0 <= a < 1.
    #[arg(long, value_parser = finite, allow_hyphen_values = true,
          conflicts_with_all = ["velocity_filter_cutoff", "velocity_filter_samples"])]
    filter_pole: Option<f64>,
    /// The velocity filter in physical units (a cutoff needs --period), from the element list.
    #[command(flatten)]
    filter: super::args::FilterArgs,
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
    /// instead of the region's vertices; in the delta-beta plane the comparison at --alpha.
    #[arg(long)]
    summary: bool,
    /// Lines per half of the comparison with the stable region in the delta-beta plane (and
    /// in the alpha-beta plane where the exact boundary does not trace every piece of the
    /// stable region): the stable set is exact on each of 2 N + 1 lines, the area shares are
    /// sums over them.
    #[arg(long, default_value_t = DEFAULT_COLUMNS)]
    columns: usize,
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
    /// (fig08-d1.svg, fig08-d1.csv, ...) into this directory; --width, --height,
    /// --font-size and --no-markers apply to each drawing.
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
    /// The encoder, force output and dry friction: the largest passive spring with them
    /// (undelayed wall without a filter; needs --mass and --period).
    #[command(flatten)]
    nonlinear: super::args::NonlinearArgs,
    #[command(flatten)]
    draw: super::figure::SvgStyleArgs,
}

impl Args {
    /// The delay in whole samples (after [`normalized`]).
    fn d(&self) -> f64 {
        self.d.unwrap_or(0.0)
    }
}

fn filter_of(a: &Args) -> anyhow::Result<VelocityFilter> {
    stabound::request::velocity_filter(&a.filter.named(), a.filter_pole, a.period)
        .map_err(super::args::as_flags)
}

/// The device's scale, when its mass and period are given (validated by [`normalized`]).
fn units_of(a: &Args) -> Option<DeviceScale> {
    a.mass
        .zip(a.period)
        .map(|(mass, period)| DeviceScale { mass, period })
}

/// The normalized parameters of `a`, each physical one (damping, delay, stiffness, wall
/// damping) converted by the library's request layer ([`DeviceInputs::resolve_parts`]).
fn normalized(mut a: Args) -> anyhow::Result<Args> {
    let parts = DeviceInputs {
        alpha: a.alpha,
        beta: a.beta,
        delta: a.delta,
        d: a.d,
        mass: a.mass,
        period: a.period,
        damping: a.damping,
        delay: a.delay,
        delay_samples: a.delay_samples,
        stiffness: a.stiffness,
        wall_damping: a.wall_damping,
    }
    .resolve_parts()
    .map_err(super::args::as_flags)?;
    (a.delta, a.alpha, a.beta, a.d) = (parts.delta, parts.alpha, parts.beta, Some(parts.d));
    Ok(a)
}

pub fn run(a: Args) -> anyhow::Result<()> {
    let a = normalized(a)?;
    if let Some(dir) = &a.figures {
        return write_figures(dir, &a.extensions, &a.draw);
    }
    let mut outputs = Plan::new();
    let data = outputs.data("-o", a.output.as_deref());
    let svg_format = super::figure::option_format("--svg", a.svg.as_deref())?;
    a.draw.check()?;
    let svg = a.svg.as_deref().map(|p| outputs.file("--svg", p));
    let mut out = outputs.check()?;
    let filter = filter_of(&a)?;
    let units = units_of(&a);
    let crit = Criterion::new(a.d(), filter)?;
    if a.nonlinear.named().any() {
        report_quantized(&a, filter)?;
    }
    let progress = Progress::spinner("passivity: the passive and the stable region".into());
    let (bytes, fig) = match a.plane {
        PlaneArg::AlphaBeta => alpha_beta(&a, &crit, units)?,
        PlaneArg::DeltaBeta => delta_beta(&a, &crit, units)?,
    };
    progress.finish();
    if let (Some(slot), Some(fig)) = (svg, fig) {
        let fig = a.draw.apply(fig)?;
        out.write(slot, &super::figure::render(&fig, svg_format)?)?;
    }
    out.write(data, &bytes)?;
    out.finish()
}

/// The largest passive spring with the encoder, force output and friction named (the
/// library's `passivity::quantized`), on stderr.
fn report_quantized(a: &Args, filter: VelocityFilter) -> anyhow::Result<()> {
    let (Some(m), Some(t)) = (a.mass, a.period) else {
        return Err(UsageError(
            "the encoder resolution, force resolution and friction are physical: give --mass and --period".into(),
        )
        .into());
    };
    let delta = a.delta.ok_or_else(|| {
        UsageError("missing --delta (or --damping in N s/m) for the passivity with quantizers and friction".into())
    })?;
    let device = stabound::Device::new(m, t, delta * m / t, stabound::Delay::Samples(a.d()))?;
    // the stiffness only sets the length unit without an encoder, where the condition does
    // not depend on it: Colgate's bound, or 1 N/m without damping
    let k_ref = if delta > 0.0 {
        2.0 * delta * m / (t * t)
    } else {
        1.0
    };
    let q = a
        .nonlinear
        .named()
        .normalize(&device, k_ref)
        .map_err(super::args::as_flags)?;
    let spring = stabound::Wall::new(0.0, 0.0)?;
    let p = stabound::passivity::quantized(delta, a.d(), filter, &spring, &q)?;
    eprintln!(
        "largest passive spring with the quantizers and friction: K = {} N/m (alpha = {}; 2 b / T gives alpha = {}{})",
        p.alpha_max * m / (t * t),
        p.alpha_max,
        p.viscous_bound,
        match (p.friction_bound, p.force_step_ok) {
            (Some(f), _) => format!(", 2 f_c / encoder resolution gives alpha = {f}"),
            (None, false) => ", and the force step is above twice the Coulomb friction".into(),
            (None, true) => String::new(),
        }
    );
    Ok(())
}

fn encode(a: &Args, t: &Table) -> Vec<u8> {
    match a.format {
        Format::Csv => to_csv_bytes(t),
        Format::Json => to_json_bytes(t),
    }
}

/// One plane's region as rows: the passive edge, then the stable region's points (named by
/// how they were found), `fixed` the plane's fixed parameter, `(x_name, y = beta)` the axes;
/// with units, the physical value of the horizontal axis (`to_x`) and of `beta`.
struct RegionRows<'a> {
    fixed: (&'a str, f64),
    x: &'a str,
    x_unit: (&'a str, fn(&DeviceScale, f64) -> f64),
    d: f64,
}

impl RegionRows<'_> {
    fn table(
        &self,
        region: &PassiveRegion,
        stable: Option<(&[(f64, f64)], &'static str)>,
        units: &Option<DeviceScale>,
    ) -> Table {
        let mut cols = vec!["region", self.fixed.0, "d", self.x, "beta", "theta", "edge"];
        if units.is_some() {
            cols.extend([self.x_unit.0, "wall_damping_Ns_per_m"]);
        }
        let mut t = Table::new(&cols);
        let mut row = |name: &'static str, x: f64, y: f64, theta: f64, edge: &'static str| {
            let base = [
                Cell::Static(name),
                Cell::Num(self.fixed.1),
                Cell::Num(self.d),
                Cell::Num(x),
                Cell::Num(y),
                Cell::Num(theta),
                Cell::Static(edge),
            ];
            match units {
                Some(u) => {
                    let [c0, c1, c2, c3, c4, c5, c6] = base;
                    let ux = Cell::Num((self.x_unit.1)(u, x));
                    t.push([c0, c1, c2, c3, c4, c5, c6, ux, Cell::Num(u.b(y))]);
                }
                None => t.push(base),
            }
        };
        for p in &region.points {
            row("passive", p.x, p.y, p.piece.theta, p.piece.edge.name());
        }
        if let Some((pts, how)) = stable {
            for &(x, y) in pts {
                row("stable", x, y, f64::NAN, how);
            }
        }
        t
    }
}

/// The passive region (dash-dotted) over the stable region.
fn overlay(
    fixed: String,
    d: f64,
    filter: &VelocityFilter,
    x_label: &str,
    stable: Option<&[(f64, f64)]>,
    region: &PassiveRegion,
) -> Figure {
    let mut fig = Figure::new(
        &format!(
            "Passive (dash-dotted) and stable regions, {fixed}, d = {d}, filter: {}",
            filter.name()
        ),
        x_label,
        "β (normalized damping)",
    );
    if let Some(s) = stable {
        fig.push("stable region", s.to_vec(), LineStyle::Solid, 1);
    }
    fig.push("passive region", region.xy(), LineStyle::DashDot, 2);
    fig
}

fn note_not_compared(why: &str) {
    eprintln!("note: {why}; the passive region is reported alone");
}

fn alpha_beta(
    a: &Args,
    crit: &Criterion,
    units: Option<DeviceScale>,
) -> anyhow::Result<(Vec<u8>, Option<Figure>)> {
    if a.alpha.is_some() {
        return Err(UsageError(
            "--alpha (--stiffness) belongs to --plane delta-beta; in the alpha-beta plane give --delta (or --damping)".into(),
        )
        .into());
    }
    let delta = a.delta.ok_or_else(|| {
        UsageError(
            "missing --delta (physical damping; or --damping in N s/m with --mass and --period)"
                .into(),
        )
    })?;
    let filter = crit.filter();
    // the exact stable boundary of the loop with its filter, or the columns where it does
    // not trace the piece holding the passive region
    let c = compare_alpha_beta(delta, a.d(), filter, a.columns, a.tol)?;
    if let Some(why) = &c.note {
        eprintln!("note: {why}");
    }
    let (region, stable, verdicts) = (c.region, (c.stable, c.summary.method), c.summary);
    let best = crit.max_stiffness(delta, a.tol)?;
    let at_beta = match a.beta {
        Some(b) => Some((b, crit.max_stiffness_at(delta, b, a.tol)?)),
        None => None,
    };
    report_best(&best, &at_beta);
    report(&verdicts, "alpha");
    let fig = a.svg.is_some().then(|| {
        let mut f = overlay(
            format!("δ = {delta}"),
            a.d(),
            &filter,
            "α (normalized stiffness)",
            Some(&stable.0),
            &region,
        );
        f.legend = Legend::UpperRight;
        f
    });
    let t = if a.summary {
        summary_table(delta, a.d(), &filter, &best, &at_beta, &verdicts, &units)?
    } else {
        RegionRows {
            fixed: ("delta", delta),
            x: "alpha",
            x_unit: ("stiffness_N_per_m", DeviceScale::k),
            d: a.d(),
        }
        .table(&region, Some((&stable.0, stable.1)), &units)
    };
    Ok((encode(a, &t), fig))
}

fn report_best(best: &Option<(f64, f64)>, at_beta: &Option<(f64, Option<f64>)>) {
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
}

/// The comparison's lines on stderr; `x` names the plane's horizontal axis.
fn report(v: &Summary, x: &str) {
    eprintln!(
        "passive region inside the stable region: {}; passive share of the stable region {:.6}",
        if v.inside { "yes" } else { "no" },
        v.passive_share
    );
    if let Some(w) = v.passive_unstable {
        let at = if x == "alpha" { w.alpha } else { w.delta };
        eprintln!("passive but unstable: {x} = {at}, beta = {}", w.beta);
    }
}

/// A one-row table of `N` columns from `(column, cell)` pairs.
fn one_row<const N: usize>(pairs: Vec<(&str, Cell)>) -> anyhow::Result<Table> {
    let names: Vec<&str> = pairs.iter().map(|p| p.0).collect();
    let mut t = Table::new(&names);
    let cells: [Cell; N] = pairs
        .into_iter()
        .map(|p| p.1)
        .collect::<Vec<_>>()
        .try_into()
        .map_err(|v: Vec<Cell>| {
            anyhow::anyhow!("summary row of {} cells, expected {N}", v.len())
        })?;
    t.push(cells);
    Ok(t)
}

/// The comparison's columns, shared by both planes; `x` names the witnesses' horizontal
/// coordinate (`alpha` or `delta`) and reads it.
fn comparison_cells(
    v: &Summary,
    x: (&'static str, fn(&Witness) -> f64),
) -> Vec<(&'static str, Cell)> {
    let nan = f64::NAN;
    let w = |w: &Option<Witness>, f: fn(&Witness) -> f64| Cell::Num(w.as_ref().map_or(nan, f));
    let (pu, snp) = (&v.passive_unstable, &v.stable_not_passive);
    let names: [&'static str; 4] = match x.0 {
        "alpha" => [
            "witness_alpha",
            "witness_beta",
            "stable_not_passive_alpha",
            "stable_not_passive_beta",
        ],
        _ => [
            "witness_delta",
            "witness_beta",
            "stable_not_passive_delta",
            "stable_not_passive_beta",
        ],
    };
    vec![
        ("passive_area", Cell::Num(v.passive_area)),
        ("stable_area", Cell::Num(v.stable_area)),
        ("inside", Cell::Static(if v.inside { "yes" } else { "no" })),
        ("passive_share_of_stable", Cell::Num(v.passive_share)),
        ("stable_share_of_passive", Cell::Num(v.stable_share)),
        (names[0], w(pu, x.1)),
        (names[1], w(pu, |w| w.beta)),
        ("passive_share_error", Cell::Num(v.share_error)),
        ("passive_share_bound", Cell::Num(v.share_bound)),
        ("stable_method", Cell::Static(v.method)),
        (names[2], w(snp, x.1)),
        (names[3], w(snp, |w| w.beta)),
    ]
}

fn summary_table(
    delta: f64,
    d: f64,
    filter: &VelocityFilter,
    best: &Option<(f64, f64)>,
    at_beta: &Option<(f64, Option<f64>)>,
    v: &Summary,
    units: &Option<DeviceScale>,
) -> anyhow::Result<Table> {
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
    let mut cmp = comparison_cells(v, ("alpha", |w| w.alpha));
    // the first columns as they were before the comparison grew, then the new ones
    let tail = cmp.split_off(7);
    let mut pairs = vec![
        ("delta", Cell::Num(delta)),
        ("d", Cell::Num(d)),
        ("filter", Cell::Text(filter.name())),
        ("alpha_max_passive", Cell::Num(am)),
        ("beta_at_max", Cell::Num(bm)),
        ("beta", Cell::Num(b)),
        ("alpha_max_at_beta", Cell::Num(ab)),
    ];
    pairs.extend(cmp);
    pairs.push(("K_max_N_per_m", Cell::Num(k)));
    pairs.push(("B_at_max_Ns_per_m", Cell::Num(bb)));
    pairs.extend(tail);
    one_row::<21>(pairs)
}

/// The summary of the `(delta, beta)` comparison at one stiffness.
fn summary_delta_beta(
    alpha: f64,
    d: f64,
    delta_max: f64,
    filter: &VelocityFilter,
    v: &Summary,
) -> anyhow::Result<Table> {
    let mut pairs = vec![
        ("alpha", Cell::Num(alpha)),
        ("d", Cell::Num(d)),
        ("filter", Cell::Text(filter.name())),
        ("delta_max", Cell::Num(delta_max)),
    ];
    pairs.extend(comparison_cells(v, ("delta", |w| w.delta)));
    one_row::<16>(pairs)
}

fn delta_beta(
    a: &Args,
    crit: &Criterion,
    units: Option<DeviceScale>,
) -> anyhow::Result<(Vec<u8>, Option<Figure>)> {
    let alpha = a
        .alpha
        .ok_or_else(|| UsageError("missing --alpha for --plane delta-beta (or --stiffness in N/m with --mass and --period)".into()))?;
    if a.beta.is_some() {
        return Err(UsageError(
            "--beta (--wall-damping) belongs to the alpha-beta plane (the largest passive stiffness at one delta)"
                .into(),
        )
        .into());
    }
    if a.summary && alpha <= 0.0 {
        return Err(UsageError(
            "--summary in the delta-beta plane compares with the stable region: give --alpha > 0"
                .into(),
        )
        .into());
    }
    let delta_max = a.delta.unwrap_or(4.0);
    let filter = crit.filter();
    let cmp: Option<ColumnComparison> = if alpha > 0.0 {
        Some(compare_delta_beta(
            alpha,
            a.d(),
            filter,
            delta_max,
            a.columns,
            a.tol,
        )?)
    } else {
        note_not_compared(
            "at alpha = 0 every wall has the root z = 1, so there is no stable region to compare with",
        );
        None
    };
    let region = match &cmp {
        Some(c) => c.region.clone(),
        None => crit.region_delta_beta(alpha, delta_max, a.tol)?,
    };
    // without a filter the stable region is drawn by the bisection engine, as in Fig. 9
    let stable: Option<(Vec<(f64, f64)>, &'static str)> = if filter.is_identity() {
        Some((
            stabound::figures::passivity::stable_delta_beta(alpha, a.d(), delta_max)?,
            "bisection",
        ))
    } else {
        cmp.as_ref().map(|c| (c.stable_outline.clone(), "columns"))
    };
    if region.points.is_empty() {
        eprintln!("no wall with alpha = {alpha} is passive for delta up to {delta_max}");
    }
    let verdicts = cmp.as_ref().map(Summary::from);
    if let Some(v) = &verdicts {
        report(v, "delta");
    }
    let fig = a.svg.is_some().then(|| {
        let mut f = overlay(
            format!("α = {alpha}"),
            a.d(),
            &filter,
            "δ (normalized physical damping)",
            stable.as_ref().map(|s| s.0.as_slice()),
            &region,
        );
        f.x_range = Some((0.0, delta_max));
        f.legend = Legend::LowerLeft;
        f
    });
    let t = match (&verdicts, a.summary) {
        (Some(v), true) => summary_delta_beta(alpha, a.d(), delta_max, &filter, v)?,
        _ => RegionRows {
            fixed: ("alpha", alpha),
            x: "delta",
            x_unit: ("damping_Ns_per_m", DeviceScale::damping),
            d: a.d(),
        }
        .table(
            &region,
            stable.as_ref().map(|s| (s.0.as_slice(), s.1)),
            &units,
        ),
    };
    Ok((encode(a, &t), fig))
}

/// The companions of Figs. 8 and 9, each panel drawn with the size and font options given.
fn write_figures(
    dir: &std::path::Path,
    extensions: &[String],
    draw: &super::figure::SvgStyleArgs,
) -> anyhow::Result<()> {
    let formats = super::figure::formats_of("--extension", extensions)?;
    draw.check()?;
    super::figure::output_dir("--figures-dir", dir)?;
    let names: Vec<String> = stabound::figures::passivity::companion_names();
    let (paths, slots, mut out) =
        super::figure::plan_figures(dir, &names, &formats, "--figures-dir")?;
    let mut data: Vec<FigureData> = companions()?;
    for fd in &mut data {
        for p in &mut fd.panels {
            *p = draw.apply(std::mem::replace(p, Figure::new("", "", "")))?;
        }
    }
    super::figure::write_figures(&mut out, &data, &formats, &slots)?;
    out.finish()?;
    super::figure::report(&paths);
    Ok(())
}
