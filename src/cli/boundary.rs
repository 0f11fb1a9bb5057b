//! `stabound boundary`: stability boundaries for lists of plants, as CSV/JSON and SVG.

use std::path::PathBuf;

use anyhow::Context;
use clap::ValueEnum;
use std::io::Write;

use stabound::boundary::{
    self, Axis, BisectOptions, Boundary, Contour, DEFAULT_TOL, Plane, SweepOptions,
};
use stabound::elements::Loop;
use stabound::export::BOUNDARY_COLUMNS;
use stabound::export::DeviceScale;
use stabound::export::csv::{CsvWriter, push_boundary_header};
use stabound::export::json::JsonRows;
use stabound::params::{Delay, Device, Normalized, Plant};
use stabound::plot::{Figure, LineStyle};
use stabound::request;
use stabound::robust::robust_region;

use super::UsageError;
use super::args::RowFormat as Format;
use super::args::{
    ElementArgs, GridArgs, List, MAX_CURVES, SHARD_HELP, Shard, Spread, as_flags, check_shard,
    damping_spread, delay_spread, finite, list, needs_physical, one_or_set, plan, shard,
};
use super::output::{Outputs, Plan, Progress, RowStream, Slot, Stream};

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
    /// Output format. Over a set of devices JSON is an object: `rows` and, per curve, how
    /// its robust region was found (`regions`); CSV holds the rows alone.
    #[arg(long, value_enum, default_value = "csv")]
    format: Format,
    /// Write the data to this file instead of stdout.
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Also draw every curve of the request into this file (.svg, .png or .pdf by its
    /// extension): one panel, or one panel per d past ten curves.
    #[arg(long)]
    svg: Option<PathBuf>,
    /// Work units are the curves, in output order.
    #[arg(long, value_parser = shard, help = SHARD_HELP)]
    shard: Option<Shard>,
    /// Device mass m in kg (physical units, alpha-beta plane: with --period, --damping and
    /// --delay|--delay-samples instead of --delta and --d; rows gain the physical columns).
    /// In the delta-beta plane, with --period, the device the loop elements are given for.
    /// LO..HI or one-of:LIST (alpha-beta plane): a set of devices, normalized by the smallest.
    #[arg(long, value_parser = one_or_set, allow_hyphen_values = true)]
    mass: Option<Spread>,
    /// Sampling period T in s.
    #[arg(long, value_parser = finite, allow_hyphen_values = true)]
    period: Option<f64>,
    /// Physical damping b in N s/m (LIST, or LO..HI or one-of:LIST: a set of devices).
    #[arg(long, value_parser = damping_spread, allow_hyphen_values = true)]
    damping: Option<Spread>,
    /// Delays in s (LIST, or LO..HI or one-of:LIST: a set of devices).
    #[arg(long, value_parser = delay_spread, allow_hyphen_values = true, conflicts_with = "delay_samples")]
    delay: Option<Spread>,
    /// Delays in sampling periods (LIST, or LO..HI or one-of:LIST: a set of devices, e.g. 1..3
    /// or one-of:1,2,3).
    #[arg(long = "delay-samples", value_parser = delay_spread, allow_hyphen_values = true)]
    delay_samples: Option<Spread>,
    /// With a set of devices (an interval LO..HI of the device or of an element; with a hand,
    /// the device let go is a member unless --always-gripped): draw each member's own
    /// boundary in the --svg figure beside the robust region (the walls stable for every
    /// member, which the rows give).
    #[arg(long)]
    members: bool,
    #[command(flatten)]
    loop_elements: ElementArgs,
    #[command(flatten)]
    draw: super::figure::SvgStyleArgs,
}

pub fn run(a: Args) -> anyhow::Result<()> {
    // the library's own check, before any work or output-path check
    boundary::check_tol(a.tol).context("--tol")?;
    check_shard(a.shard, a.format == Format::Csv, a.svg.is_some())?;
    let mut outputs = Plan::new();
    let data = outputs.data("-o", a.output.as_deref());
    let svg_format = super::figure::option_format("--svg", a.svg.as_deref())?;
    a.draw.check()?;
    let svg = a.svg.as_deref().map(|p| outputs.file("--svg", p));
    let mut out = outputs.check()?;
    let figure = match a.plane {
        PlaneArg::AlphaBeta => alpha_beta(&a, &mut out, data)?,
        PlaneArg::DeltaBeta => delta_beta(&a, &mut out, data)?,
    };
    if let (Some(svg), Some(panels)) = (svg, figure) {
        out.write(svg, &render_panels(&a.draw, panels, svg_format)?)?;
    }
    out.finish()
}

/// Rows formatted per write: a few hundred kB through one reused buffer, however long the
/// curve.
const CHUNK_ROWS: usize = 4096;

/// The rows of a run as they are produced: CSV (header with the first rows) or one JSON
/// array, formatted into one reused buffer and written to the output's stream.
struct Rows {
    stream: Stream,
    buf: Vec<u8>,
    /// `None` for CSV.
    json: Option<JsonRows>,
    header: bool,
    /// With a device in physical units: the conversion, and (for CSV) the writer of the rows
    /// with their physical columns.
    physical: Option<(DeviceScale, Option<CsvWriter>)>,
    /// JSON over a set of devices: how each curve's robust region was found, written after
    /// the rows (the rows are then the object's `rows`, these its `regions`).
    regions: Option<Vec<serde_json::Value>>,
}

/// The columns of a boundary row in physical units: the normalized ones, then the device's
/// damping and the wall's stiffness and damping.
const PHYSICAL_COLUMNS: [&str; 8] = [
    "delta",
    "d",
    "alpha",
    "beta",
    "piece",
    "damping_Ns_per_m",
    "stiffness_N_per_m",
    "wall_damping_Ns_per_m",
];

impl Rows {
    /// The rows of one device or grid of curves (`set`: of sets of devices, whose JSON is an
    /// object with the rows and the regions' provenance, [`Rows::region`]).
    fn new(
        out: &mut Outputs,
        slot: Slot,
        format: Format,
        scale: Option<DeviceScale>,
        set: bool,
    ) -> anyhow::Result<Self> {
        let columns: &[&str] = if scale.is_some() {
            &PHYSICAL_COLUMNS
        } else {
            &BOUNDARY_COLUMNS
        };
        let regions = (set && format == Format::Json).then(Vec::new);
        let mut stream = out.stream(slot)?;
        if regions.is_some() {
            stream.write_all(b"{\"rows\":")?;
        }
        Ok(Self {
            regions,
            stream,
            buf: Vec::with_capacity(64 * CHUNK_ROWS),
            json: (format == Format::Json).then(|| JsonRows::new(columns)),
            header: format == Format::Csv && scale.is_none(),
            physical: scale.map(|s| {
                let csv =
                    (format == Format::Csv).then(|| CsvWriter::new(&PHYSICAL_COLUMNS, CHUNK_ROWS));
                (s, csv)
            }),
        })
    }

    /// How the next curve's robust region was found: an entry of the JSON object's
    /// `regions` (CSV keeps to the rows; the note on stderr says it there).
    fn region(&mut self, provenance: serde_json::Value) {
        if let Some(r) = &mut self.regions {
            r.push(provenance);
        }
    }

    fn boundary(&mut self, b: &Boundary) -> std::io::Result<()> {
        if self.physical.is_some() {
            return self.physical_rows(b);
        }
        for chunk in b.points.chunks(CHUNK_ROWS) {
            self.buf.clear();
            if std::mem::take(&mut self.header) {
                push_boundary_header(&mut self.buf);
            }
            match &mut self.json {
                None => stabound::export::csv::push_boundary_rows(&mut self.buf, b, chunk),
                Some(w) => stabound::export::json::push_boundary_rows(w, &mut self.buf, b, chunk),
            }
            self.stream.write_all(&self.buf)?;
        }
        Ok(())
    }

    /// The rows of `b` with their physical columns, CSV or JSON.
    fn physical_rows(&mut self, b: &Boundary) -> std::io::Result<()> {
        let Some((s, csv)) = &mut self.physical else {
            return Ok(());
        };
        for chunk in b.points.chunks(CHUNK_ROWS) {
            self.buf.clear();
            for p in chunk {
                let cells = [
                    b.delta,
                    b.d,
                    p.x,
                    p.y,
                    f64::NAN,
                    s.damping(b.delta),
                    s.k(p.x),
                    s.b(p.y),
                ];
                match (&mut self.json, csv.as_mut()) {
                    (None, Some(csv)) => {
                        for (i, &v) in cells.iter().enumerate() {
                            if i == 4 {
                                csv.text(p.piece.name());
                            } else {
                                csv.num(v);
                            }
                        }
                    }
                    (Some(w), _) => {
                        w.begin_row(&mut self.buf);
                        for (i, &v) in cells.iter().enumerate() {
                            if i == 4 {
                                w.text(&mut self.buf, i, p.piece.name());
                            } else {
                                w.num(&mut self.buf, i, v);
                            }
                        }
                        w.end_row(&mut self.buf);
                    }
                    (None, None) => {}
                }
            }
            match csv.as_mut() {
                Some(csv) => csv.write_to(&mut self.stream)?,
                None => self.stream.write_all(&self.buf)?,
            }
        }
        Ok(())
    }

    /// Writes what is left (the header of an empty run, the end of the JSON array) and
    /// closes the stream.
    fn finish(mut self, out: &mut Outputs) -> anyhow::Result<()> {
        if let Some((_, Some(csv))) = &mut self.physical {
            csv.write_to(&mut self.stream)?;
        }
        self.buf.clear();
        if self.header {
            push_boundary_header(&mut self.buf);
        }
        if let Some(w) = &self.json {
            w.finish(&mut self.buf);
        }
        if let Some(regions) = &self.regions {
            // the array's closing line ends the object's first field
            if self.buf.last() == Some(&b'\n') {
                self.buf.pop();
            }
            self.buf.extend_from_slice(b",\n\"regions\":");
            serde_json::to_writer(&mut self.buf, regions)?;
            self.buf.extend_from_slice(b"\n}\n");
        }
        self.stream.write_all(&self.buf)?;
        out.close(self.stream)
    }
}

fn alpha_beta(a: &Args, out: &mut Outputs, data: Slot) -> anyhow::Result<Option<Vec<Figure>>> {
    if a.alpha.is_some() {
        return Err(UsageError(
            "--alpha belongs to --plane delta-beta; in the alpha-beta plane give --delta and --d"
                .into(),
        )
        .into());
    }
    let grid = GridArgs {
        delta: a.delta.clone(),
        d: a.d.clone(),
        mass: a.mass.clone(),
        period: a.period,
        damping: a.damping.clone(),
        delay: a.delay.clone(),
        delay_samples: a.delay_samples.clone(),
    }
    .resolve()?;
    let (deltas, ds) = (&grid.deltas, &grid.ds[..]);
    let scale = grid
        .device
        .map(|(mass, period)| DeviceScale { mass, period });
    let options = SweepOptions {
        engine: match a.method.unwrap_or(MethodArg::Exact) {
            MethodArg::Exact => boundary::Engine::Exact,
            MethodArg::Bisect => boundary::Engine::Bisect,
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
    if let Some((m, t)) = grid.device {
        let (bs, delays) = &grid.physical;
        let first = Device::new(m, t, bs[0], delays[0])?;
        // a set is what an interval or a list gives; a hand alone keeps its one curve (held)
        if a.loop_elements
            .device_set(&first, &grid.sets, true)?
            .is_some_and(|s| s.is_spread())
        {
            return robust_curves(a, &grid, units, out, data, scale);
        }
    }
    if a.members {
        return Err(UsageError(
            "--members draws the members of a set of devices: give an interval LO..HI (e.g. --delay-samples 1..3)".into(),
        )
        .into());
    }
    a.loop_elements.one_device("boundary")?;
    let named = a.loop_elements.named();
    let elements = match (named.any(), grid.device) {
        (false, _) => None,
        (true, Some((m, t))) => Some((m, t)),
        (true, None) => {
            return Err(needs_physical("loop elements"));
        }
    };
    let progress = Progress::new(units.len());
    let tick = || progress.tick();
    let mut rows = Rows::new(out, data, a.format, scale, false)?;
    let mut drawing = a.svg.is_some().then(Drawing::default);
    if let Some((m, t)) = elements {
        // one loop per curve, in output order (each boundary uses every core itself)
        let (bs, delays) = &grid.physical;
        for k in units {
            let (j, i) = (k / ds.len(), k % ds.len());
            let device = Device::new(m, t, bs[j], delays[i])?;
            let lp = Loop::physical(&device, &named)?;
            let b = boundary::trace(lp, &options)?;
            warn_about(&b, options.tol);
            rows.boundary(&b)?;
            if let Some(dr) = &mut drawing {
                dr.boundary(&b);
            }
            tick();
        }
        progress.finish();
        rows.finish(out)?;
        return Ok(
            drawing.map(|dr| dr.figure("α (normalized stiffness)", "β (normalized damping)"))
        );
    }
    // the curves of this run in output order, delta outer and d inner; each is written as
    // soon as it and every one before it are done
    if !units.is_empty() {
        let first = units.start;
        let result = boundary::sweep_each(
            units.len(),
            |i| Plant::new(deltas[(first + i) / ds.len()], ds[(first + i) % ds.len()]),
            &options,
            Some(&tick),
            |b| -> anyhow::Result<()> {
                warn_about(&b, options.tol);
                rows.boundary(&b)?;
                if let Some(dr) = &mut drawing {
                    dr.boundary(&b);
                }
                Ok(())
            },
        );
        progress.finish();
        result?;
    }
    rows.finish(out)?;
    Ok(drawing.map(|dr| dr.figure("α (normalized stiffness)", "β (normalized damping)")))
}

/// The robust region of each curve's set of devices (the walls stable for every member,
/// [`robust_region`]) as rows, and in the figure with, under --members, each member's own
/// boundary.
fn robust_curves(
    a: &Args,
    grid: &super::args::Grid,
    units: std::ops::Range<usize>,
    out: &mut Outputs,
    data: Slot,
    scale: Option<DeviceScale>,
) -> anyhow::Result<Option<Vec<Figure>>> {
    if a.method.is_some() {
        return Err(UsageError(
            "the robust region of a set of devices is drawn by exact searches along lines of constant damping: leave out --method".into(),
        )
        .into());
    }
    let Some((m, t)) = grid.device else {
        return Ok(None);
    };
    let (bs, delays) = &grid.physical;
    let nd = grid.ds.len();
    let progress = Progress::new(units.len());
    let mut rows = Rows::new(out, data, a.format, scale, true)?;
    let mut drawing = a.svg.is_some().then(Drawing::default);
    for k in units {
        let (j, i) = (k / nd, k % nd);
        let device = Device::new(m, t, bs[j], delays[i])?;
        let set = a
            .loop_elements
            .device_set(&device, &grid.sets, true)?
            .ok_or_else(|| anyhow::anyhow!("every curve of a set of devices is a set"))?;
        let r = robust_region(&set, a.tol)?;
        let b = &r.boundary;
        let described = set.describe().join("; ");
        let how = match &r.search {
            Some(s) => s.describe(b.tol),
            None => format!(
                "the intersection of the exact stable sets of all {} members",
                r.members.len()
            ),
        };
        let how = match r.search.as_ref().and_then(|s| s.deepest.as_ref()) {
            Some((m, by)) => format!(
                "{how}; the member that cut deepest: {} (by {by:e} in alpha)",
                set.describe_member(m)
            ),
            None => how,
        };
        eprintln!(
            "note: delta = {}, d = {}: the robust region of {described} is {how}",
            b.delta, b.d
        );
        rows.region(provenance(&set, &r, &how));
        if r.pieces > 1 {
            eprintln!(
                "warning: delta = {}, d = {}: the walls stable for every member form {} pieces at some damping; the one reaching the largest stiffness is drawn",
                b.delta, b.d, r.pieces
            );
        }
        rows.boundary(b)?;
        if let Some(dr) = &mut drawing {
            // the region keeps the first colour but is drawn last, on top of the members'
            // curves it runs along
            let region = dr.lines.len();
            if a.members {
                for (i, (member, mb)) in r.members.iter().zip(&r.member_boundaries).enumerate() {
                    let label = set.describe_member(member);
                    dr.push([label.clone(), label], b.d, region + 1 + i, &[mb.xy()]);
                }
            }
            let label = match &r.search {
                Some(s) => format!(
                    "every member (searched; {} of {} walls proved)",
                    s.proved, s.proof_tried
                ),
                None => "every member (robust region)".to_string(),
            };
            dr.push([label.clone(), label], b.d, region, &[b.xy()]);
        }
        progress.tick();
    }
    progress.finish();
    rows.finish(out)?;
    Ok(drawing.map(|dr| dr.figure("α (normalized stiffness)", "β (normalized damping)")))
}

/// How the robust region `r` of `set` was found, for the JSON object's `regions`: the
/// curve, the set, the members intersected, the method (`exact` for a finite set, every
/// member intersected; `searched` with intervals) with the search's counts and what the box
/// recursion proved, and `how`, the note's sentence.
fn provenance(
    set: &stabound::robust::DeviceSet,
    r: &stabound::robust::RobustRegion,
    how: &str,
) -> serde_json::Value {
    let b = &r.boundary;
    let members: Vec<String> = r.members.iter().map(|m| set.describe_member(m)).collect();
    let search = r.search.as_ref().map(|s| {
        serde_json::json!({
            "dampings": s.dampings,
            "first_pass_tol": s.first_pass,
            "final_dampings": s.final_dampings,
            "final_searched": s.final_searched,
            "checked": s.checked,
            "caught": s.caught,
            "members_evaluated": s.evaluated,
            "members_found": s.found,
            "deepest": s.deepest.as_ref().map(|(m, by)| serde_json::json!({
                "member": set.describe_member(m),
                "cut_alpha": by,
            })),
            "unresolved": s.unresolved,
            "proof_tried": s.proof_tried,
            "proved": s.proved,
        })
    });
    serde_json::json!({
        "delta": b.delta,
        "d": b.d,
        "tol": b.tol,
        "set": set.describe(),
        "method": if r.exact { "exact" } else { "searched" },
        "members": members,
        "pieces": r.pieces,
        "search": search,
        "how": how,
    })
}

/// A warning on stderr when the boundary is not what was asked for: drawn by the bisection
/// engine because the exact one could not close it, or to a tolerance relative to a region
/// too large for the one requested.
fn warn_about(b: &Boundary, tol: f64) {
    if let Some(why) = &b.fallback {
        eprintln!(
            "warning: delta = {}, d = {}: the exact engine could not close this boundary ({why}); the bisection engine drew it",
            b.delta, b.d
        );
    }
    if b.tol > tol {
        eprintln!(
            "warning: delta = {}, d = {}: the region is too large for --tol {tol:e}; traced to {:e}, the same fraction of its size",
            b.delta, b.d, b.tol
        );
    }
}

/// Keeps the points of a polyline at least `step` apart (and the last), for drawing: a
/// boundary to 1e-9 has tens of thousands of vertices, far below a pixel apart.
pub(super) fn thin(points: &[(f64, f64)], step: (f64, f64)) -> Vec<(f64, f64)> {
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

/// The extent of a set of points, `(lo, hi)` per axis.
#[derive(Clone, Copy)]
struct Extent {
    x: (f64, f64),
    y: (f64, f64),
}

impl Default for Extent {
    fn default() -> Self {
        let empty = (f64::INFINITY, f64::NEG_INFINITY);
        Self { x: empty, y: empty }
    }
}

impl Extent {
    fn add(&mut self, p: (f64, f64)) {
        // NaN separators between loops leave the extent alone (min/max skip NaN)
        self.x = (self.x.0.min(p.0), self.x.1.max(p.0));
        self.y = (self.y.0.min(p.1), self.y.1.max(p.1));
    }

    /// 1/1500 of the extent per axis: the thinning step, well below a pixel.
    fn step(&self) -> (f64, f64) {
        let f = |(lo, hi): (f64, f64)| ((hi - lo) / 1500.0).max(0.0);
        (f(self.x), f(self.y))
    }
}

/// One drawn curve: its label in a panel of its own delay, its delay factor `d`, colour
/// index and points (loops separated by NaN).
struct Line {
    /// The label when every curve shares one panel.
    full: String,
    /// The label in a panel of its own `d`.
    label: String,
    d: f64,
    color: usize,
    xy: Vec<(f64, f64)>,
}

/// Most curves one panel draws: the palette's ten colours, so that no two curves of a panel
/// share one.
const CURVES_PER_PANEL: usize = 10;

/// What `--svg` draws, collected while the rows stream: each curve thinned at once to a
/// step of its own extent (never coarser than the final one, which depends on every curve),
/// then once more at the end with the step of the whole figure. Only the drawn points are
/// held, a few thousand per curve.
#[derive(Default)]
struct Drawing {
    lines: Vec<Line>,
    all: Extent,
}

impl Drawing {
    fn boundary(&mut self, b: &Boundary) {
        // one colour and marker per curve (70 distinct pairs)
        let color = self.lines.len();
        let (full, label) = (
            format!("d = {}, δ = {}", b.d, b.delta),
            format!("δ = {}", b.delta),
        );
        self.push([full, label], b.d, color, &[b.xy()]);
    }

    /// Adds a curve of delay `d` labelled `full` when every curve shares one panel and
    /// `label` in a panel of its own `d`.
    fn push(
        &mut self,
        [full, label]: [String; 2],
        d: f64,
        color: usize,
        loops: &[Vec<(f64, f64)>],
    ) {
        let mut own = Extent::default();
        loops.iter().flatten().for_each(|&p| own.add(p));
        loops.iter().flatten().for_each(|&p| self.all.add(p));
        let mut xy: Vec<(f64, f64)> = Vec::new();
        for lp in loops {
            if !xy.is_empty() {
                xy.push((f64::NAN, f64::NAN));
            }
            xy.extend(thin(lp, own.step()));
        }
        self.lines.push(Line {
            full,
            label,
            d,
            color,
            xy,
        });
    }

    /// The panels: one for up to [`CURVES_PER_PANEL`] curves, else one per delay factor `d`
    /// (split further where one `d` has more curves), all on the same axes so that they
    /// compare at a glance.
    fn figure(self, x: &str, y: &str) -> Vec<Figure> {
        let step = self.all.step();
        let thinned = |xy: &[(f64, f64)]| {
            let mut out: Vec<(f64, f64)> = Vec::new();
            for lp in xy.split(|p| p.0.is_nan()) {
                if !out.is_empty() {
                    out.push((f64::NAN, f64::NAN));
                }
                out.extend(thin(lp, step));
            }
            out
        };
        if self.lines.len() <= CURVES_PER_PANEL {
            let mut fig = Figure::new("Stability boundaries", x, y);
            if self.lines.len() > 6 {
                fig.style = stabound::plot::FigureStyle::large();
            }
            for l in &self.lines {
                fig.push(l.full.clone(), thinned(&l.xy), LineStyle::Solid, l.color);
            }
            return vec![fig];
        }
        // delays in order of first appearance; `d` values are compared by their bits, the
        // values the curves were computed at
        let mut ds: Vec<f64> = Vec::new();
        for l in &self.lines {
            if !ds.iter().any(|d| d.to_bits() == l.d.to_bits()) {
                ds.push(l.d);
            }
        }
        let mut panels = Vec::new();
        for d in ds {
            let own: Vec<&Line> = self
                .lines
                .iter()
                .filter(|l| l.d.to_bits() == d.to_bits())
                .collect();
            let parts = own.len().div_ceil(CURVES_PER_PANEL);
            for (part, chunk) in own.chunks(CURVES_PER_PANEL).enumerate() {
                let title = if parts > 1 {
                    format!("Stability boundaries, d = {d} ({}/{parts})", part + 1)
                } else {
                    format!("Stability boundaries, d = {d}")
                };
                let mut fig = Figure::new(&title, x, y);
                (fig.x_range, fig.y_range) = (Some(padded(self.all.x)), Some(padded(self.all.y)));
                for (color, l) in chunk.iter().enumerate() {
                    fig.push(l.label.clone(), thinned(&l.xy), LineStyle::Solid, color);
                }
                panels.push(fig);
            }
        }
        panels
    }
}

/// `(lo, hi)` widened by 5 % of its width on each side, as a figure fits its own data.
fn padded((lo, hi): (f64, f64)) -> (f64, f64) {
    let pad = 0.05 * (hi - lo);
    (lo - pad, hi + pad)
}

/// Panels per row when `--svg` draws several.
const PANEL_COLUMNS: usize = 3;

/// `panels` with the style options applied, as one document of `format`.
fn render_panels(
    draw: &super::figure::SvgStyleArgs,
    panels: Vec<Figure>,
    format: stabound::plot::Format,
) -> anyhow::Result<Vec<u8>> {
    let panels = panels
        .into_iter()
        .map(|p| draw.apply(p))
        .collect::<anyhow::Result<Vec<_>>>()?;
    let svg = stabound::figures::compose_svg(&panels, PANEL_COLUMNS)?;
    Ok(stabound::plot::render(&svg, format)?)
}

fn delta_beta(a: &Args, out: &mut Outputs, data: Slot) -> anyhow::Result<Option<Vec<Figure>>> {
    if a.method == Some(MethodArg::Exact) {
        return Err(UsageError(
            "--method exact is for the alpha-beta plane; the delta-beta plane uses --method bisect"
                .into(),
        )
        .into());
    }
    // the device's values; a set (LO..HI or one-of:LIST) is drawn in the alpha-beta plane only
    fn values(s: &Option<Spread>) -> Result<Option<&[f64]>, UsageError> {
        match s {
            None => Ok(None),
            Some(Spread::List(v)) => Ok(Some(v)),
            Some(_) => Err(UsageError(
                "a set of devices (LO..HI or one-of:LIST) is drawn in the alpha-beta plane".into(),
            )),
        }
    }
    a.loop_elements.one_device("boundary")?;
    if a.members {
        return Err(UsageError("--members belongs to the alpha-beta plane".into()).into());
    }
    let named = a.loop_elements.named();
    let plane = request::DeviceInputs {
        alpha: a.alpha.as_ref().map(|l| &l.0[..]),
        d: a.d.as_ref().map(|l| &l.0[..]),
        delta: a.delta.as_ref().map(|l| &l.0[..]),
        mass: values(&a.mass)?,
        period: a.period.as_ref().map(std::slice::from_ref),
        damping: values(&a.damping)?,
        delay: values(&a.delay)?,
        delay_samples: values(&a.delay_samples)?,
        ..Default::default()
    }
    .delta_beta_plane(named.any())
    .map_err(as_flags)?;
    let (alphas, ds, range) = (plane.alphas, plane.ds, plane.range);
    let what = format!("curves ({} alpha x {} d)", alphas.len(), ds.len());
    let units = plan(
        alphas.len().saturating_mul(ds.len()),
        a.shard.unwrap_or(Shard::ALL),
        MAX_CURVES,
        &what,
    )?;
    let at = |i: usize| {
        let k = units.start + i;
        (alphas[k / ds.len()], ds[k % ds.len()])
    };
    let elements = plane.device.map(|(m, t)| (named, m, t));
    const COLUMNS: [&str; 6] = ["alpha", "d", "delta", "beta", "loop", "piece"];
    let mut rows = RowStream::new(out, data, &COLUMNS, a.format == Format::Json)?;
    let mut drawing = a.svg.is_some().then(Drawing::default);
    let options = BisectOptions {
        tol: a.tol,
        x_range: Some(range),
        ..BisectOptions::default()
    };
    let progress = Progress::new(units.len());
    let tick = || progress.tick();
    let mut k = 0;
    let plane_of = |i: usize| -> stabound::Result<Plane> {
        let (alpha, d) = at(i);
        Ok(Plane {
            x: Axis::Delta,
            y: Axis::Beta,
            at: Normalized::new(alpha, 0.0, 0.0, d)?,
        })
    };
    let mut sink = |c: Contour| -> anyhow::Result<()> {
        let (alpha, d) = at(k);
        for (li, lp) in c.loops.iter().enumerate() {
            for p in lp {
                let piece = if p.clipped() { "clipped" } else { "bisection" };
                for v in [alpha, d, p.x, p.y, li as f64] {
                    rows.num(v);
                }
                rows.text(piece);
            }
        }
        rows.flush()?;
        if let Some(dr) = &mut drawing {
            // the edges of the requested delta range are not boundaries: not drawn
            let loops: Vec<Vec<(f64, f64)>> = c
                .loops
                .iter()
                .flat_map(|lp| stabound::figures::boundary_lines(lp))
                .collect();
            dr.push(
                [format!("α = {alpha}, d = {d}"), format!("α = {alpha}")],
                d,
                k,
                &loops,
            );
        }
        k += 1;
        Ok(())
    };
    if !units.is_empty() {
        let result = match &elements {
            None => {
                boundary::sweep_planes_each(units.len(), plane_of, &options, Some(&tick), &mut sink)
            }
            // one loop per curve, in output order (each contour uses every core itself)
            Some((named, m, t)) => (0..units.len()).try_for_each(|i| {
                let plane = plane_of(i)?;
                let device = Device::new(*m, *t, 0.0, Delay::Samples(plane.at.d()))?;
                let lp =
                    Loop::new(Plant::new(range.0, plane.at.d())?).with_physical(&device, named)?;
                let c = boundary::bisect(lp, &plane, &options)?;
                tick();
                sink(c)
            }),
        };
        progress.finish();
        result?;
    }
    rows.finish(out)?;
    Ok(drawing.map(|dr| dr.figure("δ (normalized physical damping)", "β (normalized damping)")))
}
