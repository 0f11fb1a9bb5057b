//! `stabound amax`: maximum stable stiffness for lists of delta (or physical damping) and d.

use std::path::PathBuf;

use rayon::prelude::*;
use stabound::amax::{
    Amax, AmaxOptions, AmaxPoint, AmaxReport, HOLD_STEP, alpha_max_each_with_marginal,
    alpha_max_with_marginal, amax_report, recommend,
};
use stabound::elements::Loop;
use stabound::export::DeviceScale;
use stabound::params::{Device, Plant};
use stabound::plot::{Figure, LineStyle};
use stabound::search::Interval;

use super::UsageError;
use super::args::Grid;
use super::args::RowFormat as Format;
use super::args::{
    ElementArgs, GridArgs, MAX_STREAM_ROWS, NonlinearArgs, PHYSICAL_DEVICE, SHARD_HELP, SearchArgs,
    Shard, check_shard, finite, needs_physical, plan, shard,
};
use super::output::{Outputs, Plan, Progress, RowStream, Slot};
use stabound::robust::{DeviceSet, RobustAmax, robust_alpha_max};

/// Normalized (--delta LIST --d LIST) or physical (--mass --period --damping LIST and
/// --delay LIST | --delay-samples LIST). One row per (d, delta), d outer.
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    grid: GridArgs,
    #[command(flatten)]
    search: SearchArgs,
    /// Also report the wall at this fraction of alpha_max (e.g. 0.75 as in the paper's Section
    /// VIII), checked stable; with loop elements, where the stable stiffnesses at the optimum's
    /// damping do not reach from it up to alpha_max, the fraction of the stiffest wall whose
    /// do, at that wall's damping (B_margin_Ns_per_m), with a note on stderr.
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
    /// The encoder, force output and dry friction: when any is named, each row gives the
    /// buzz-free stiffness beside the linear K_max (device in physical units; CSV or JSON).
    #[command(flatten)]
    nonlinear: NonlinearArgs,
    #[command(flatten)]
    draw: super::figure::SvgStyleArgs,
    /// Also write a certificate (JSON) of an enclosure of alpha_max to this file: a wall below
    /// it proved stable and, at a stiffness above it, every damping from --beta-min to
    /// --beta-max (or --wall-damping-min to --wall-damping-max) proved unstable; one proof per
    /// row, with or without loop elements (both limits). Over a finite set of devices (a hand
    /// that can let go, one-of:LIST loop-element values): the robust alpha_max, its wall
    /// proved stable for every member and the binding member's walls above proved unstable.
    #[arg(long, value_name = "FILE")]
    certify: Option<PathBuf>,
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
                .device_set(&device, &g.sets, true)?
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
    let certify = a.certify.as_deref().map(|p| outputs.file("--certify", p));
    let mut out = outputs.check()?;
    let g = a.grid.resolve()?;
    if let Some(slot) = certify {
        let unsupported =
            a.svg.is_some() || a.shard.is_some() || a.margin.is_some() || a.nonlinear.named().any();
        let (rows, cert) =
            super::amax_certify::run(&g, &a.search, &a.loop_elements, a.format, unsupported)?;
        out.write(data, rows.as_bytes())?;
        out.write(slot, cert.as_bytes())?;
        return out.finish();
    }
    if a.nonlinear.named().any() {
        if a.svg.is_some() || a.shard.is_some() || a.margin.is_some() {
            return Err(UsageError(
                "the buzz-free stiffness (--encoder-resolution, --force-resolution, --coulomb-friction, --static-friction) comes as rows only: leave out --svg, --shard and --margin".into(),
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
            return Err(needs_physical("loop elements"));
        }
    };
    let scale = g.device.map(|(mass, period)| DeviceScale { mass, period });
    if let Some(u) = &scale {
        u.check_scale()?;
    }
    if let Some((m, t)) = g.device {
        let (bs, delays) = &g.physical;
        let first = Device::new(m, t, bs[0], delays[0])?;
        match a.loop_elements.device_set(&first, &g.sets, true)? {
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
    } else if !g.sets.is_empty() {
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
        cols.extend(["damping_Ns_per_m", "K_max_N_per_m", "B_at_max_Ns_per_m"]);
        if a.margin.is_some() {
            cols.push("K_margin_N_per_m");
        }
    }
    if elements.is_some() && a.margin.is_some() {
        // the margin wall's damping need not be the optimum's behind a filter
        cols.push("B_margin_Ns_per_m");
    }
    let mut rows = RowStream::new(&mut out, data, &cols, a.format == Format::Json)?;
    // what --svg draws: (delta, alpha_max) per d, in the order of g.ds
    let mut drawn: Option<Vec<Vec<(f64, f64)>>> = svg.map(|_| vec![Vec::new(); g.ds.len()]);
    let mut notes = Notes::default();
    let mut row = Vec::with_capacity(cols.len());
    let progress = Progress::new(units.len());
    if !units.is_empty() {
        let first = units.start;
        // the rows in output order, d outer and delta inner, written chunk by chunk as soon
        // as each and every one before it is done
        let mut write = |_: usize, chunk: &[Recommended]| -> anyhow::Result<()> {
            for rec in chunk {
                let r = &rec.point;
                let (x, d) = (r.delta, r.d);
                row.clear();
                row.extend([x, d, r.alpha_max, r.beta_at_max]);
                // the paper's loop: the stable stiffnesses at every damping are one range
                // from 0, so the margin wall is the fraction of alpha_max at its damping
                let wall = a
                    .margin
                    .map(|f| rec.margin.unwrap_or((f * r.alpha_max, r.beta_at_max)));
                if let Some((am, bm)) = wall {
                    row.extend([am, bm]);
                }
                if let Some(u) = scale {
                    row.extend([
                        u.try_damping(x)?,
                        u.try_k(r.alpha_max)?,
                        u.try_b(r.beta_at_max)?,
                    ]);
                    if let Some((am, bm)) = wall {
                        row.push(u.try_k(am)?);
                        if elements.is_some() {
                            row.push(u.try_b(bm)?);
                        }
                    }
                }
                if let Some(why) = rec.notes.iter().find_map(Note::fallback) {
                    rows.json_field("fallback", why.to_owned());
                }
                row.iter().for_each(|&v| rows.num(v));
                // the paper's loop has no report: the best wall with beta >= 0, only when it
                // is needed, and whether the wall below it is marginal are found here
                let (nonnegative, below) = match (rec.nonnegative, r.beta_at_max < 0.0) {
                    (Some(n), _) => (Some(n), None),
                    (None, true) if elements.is_none() => {
                        let lo = opts.beta_min().map_or(0.0, |b| b.max(0.0));
                        match opts.beta_max() {
                            Some(h) if h < lo => (None, None),
                            hi => {
                                let o = opts.with_beta_limits(Some(lo), hi)?;
                                let (n, radius) = alpha_max_with_marginal(Plant::new(x, d)?, &o)?;
                                (
                                    Some(n),
                                    radius.map(|r| {
                                        Note::marginal_below(NONNEGATIVE, &n, r, PAPER_HINT)
                                    }),
                                )
                            }
                        }
                    }
                    (None, _) => (None, None),
                };
                let at = Place { delta: x, d, scale };
                if let Some(n) = nonnegative {
                    notes.push(at.negative_damping(r, &n)?);
                }
                for n in rec.notes.iter().chain(&below) {
                    notes.push(at.say(n)?);
                }
                // rows of loops with elements are counted as they are computed
                if elements.is_none() {
                    progress.tick();
                }
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
            None => {
                let mut chunk = Vec::new();
                alpha_max_each_with_marginal(
                    units.len(),
                    |i| Plant::new(g.deltas[(first + i) % nx], g.ds[(first + i) / nx]),
                    &opts,
                    |k, points: &[(AmaxPoint, Option<f64>)]| {
                        chunk.clear();
                        chunk.extend(
                            points
                                .iter()
                                .map(|&(point, below)| Recommended::bare(point, below)),
                        );
                        write(k, &chunk)
                    },
                )?
            }
            Some((named, m, t)) => {
                // the loop's alpha_max by direct search on its own curve, one device per row,
                // with the stable stiffnesses at its damping and the margin wall checked
                let (bs, delays) = &g.physical;
                let points: Vec<Recommended> = units
                    .clone()
                    .into_par_iter()
                    .map(|k| -> stabound::Result<Recommended> {
                        let (j, i) = (k % nx, k / nx);
                        let device = Device::new(*m, *t, bs[j], delays[i])?;
                        let lp = Loop::physical(&device, named)?;
                        let r = Recommended::of_loop(&lp, &opts, a.margin, g.deltas[j], g.ds[i]);
                        progress.tick();
                        r
                    })
                    .collect::<stabound::Result<_>>()?;
                write(0, &points)?;
            }
        }
    }
    progress.finish();
    notes.print();
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

/// One row's answer: `alpha_max`, the margin wall `(alpha, beta)` when it is not the fraction
/// of `alpha_max` at its damping, the best wall with `beta >= 0` when the optimum needs
/// negative damping, and what the stable set at the optimum's damping says.
struct Recommended {
    point: AmaxPoint,
    margin: Option<(f64, f64)>,
    nonnegative: Option<Amax>,
    notes: Vec<Note>,
}

/// What a row's output says about the stable set at the optimum's damping.
enum Note {
    /// The stable stiffnesses at the optimum's damping are not one range from 0 to it.
    Pieces { beta: f64, stable: Vec<Interval> },
    /// The margin wall is a fraction of a lower top at another damping, whose whole range
    /// from the margin wall up is stable.
    LowerTop { fraction: f64, top: Amax },
    /// The direct search confirmed no optimum; it is the traced boundary's rightmost point.
    Fallback(String),
    /// The optimum needs negative damping and no wall with `beta >= 0` is given: why.
    NoNonnegative(String),
    /// The checker calls the wall a relative [`HOLD_STEP`] below the optimum marginal: its
    /// radius.
    MarginalBelow {
        which: &'static str,
        alpha: f64,
        beta: f64,
        radius: f64,
        /// What moves such a wall out of the band, for this kind of loop.
        hint: &'static str,
    },
}

/// What moves the wall below a loop's optimum out of the marginal band when the loop has
/// elements: its slow mode comes from physical damping near 0 or a filter pole near `z = 1`.
const ELEMENTS_HINT: &str =
    "more physical damping, or a filter pole farther from z = 1, moves it out of the band";

/// The same for the paper's loop, whose wall below is marginal where the root on the circle
/// at the optimum barely moves inside a relative `1e-6` below it (much physical damping and
/// no delay: `2e-10` at `delta = 100`): softer walls at that damping are farther inside.
const PAPER_HINT: &str = "walls farther below the optimum at its damping are farther inside the circle: --margin gives one";

/// Which wall a [`Note::MarginalBelow`] speaks of: the one below the optimum, or below the
/// best wall with nonnegative damping beside it.
const TOP: &str = "the stiffest wall to render";
const NONNEGATIVE: &str = "the stiffest wall with nonnegative damping to render";

impl Note {
    /// The wall a relative [`HOLD_STEP`] below `a` at its damping, which the checker calls
    /// marginal with `radius`.
    fn marginal_below(which: &'static str, a: &Amax, radius: f64, hint: &'static str) -> Self {
        Note::MarginalBelow {
            which,
            alpha: a.alpha_max * (1.0 - HOLD_STEP),
            beta: a.beta_at_max,
            radius,
            hint,
        }
    }

    /// The sentence of a [`Note::Fallback`].
    fn fallback(&self) -> Option<&str> {
        match self {
            Note::Fallback(why) => Some(why),
            _ => None,
        }
    }
}

impl Recommended {
    /// The paper's loop (its margin wall, when asked, is the fraction at `beta_at_max`), and
    /// the radius of its wall below when the checker calls that wall marginal.
    fn bare(point: AmaxPoint, below: Option<f64>) -> Self {
        let top = Amax {
            alpha_max: point.alpha_max,
            beta_at_max: point.beta_at_max,
        };
        Self {
            point,
            margin: None,
            nonnegative: None,
            notes: below
                .map(|radius| Note::marginal_below(TOP, &top, radius, PAPER_HINT))
                .into_iter()
                .collect(),
        }
    }

    fn of_loop(
        lp: &Loop,
        opts: &AmaxOptions,
        margin: Option<f64>,
        delta: f64,
        d: f64,
    ) -> stabound::Result<Self> {
        let (report, wall): (AmaxReport, _) = match margin {
            None => (amax_report(lp, opts)?, None),
            Some(f) => {
                let m = recommend(lp, opts, f)?;
                let lower = (!m.at_optimum()).then_some(Note::LowerTop {
                    fraction: f,
                    top: m.top,
                });
                (m.report, Some(((m.wall.alpha(), m.wall.beta()), lower)))
            }
        };
        let a = report.amax;
        let mut notes: Vec<Note> = report
            .fallback
            .clone()
            .map(Note::Fallback)
            .into_iter()
            .collect();
        if let Some(why) = &report.no_nonnegative {
            notes.push(Note::NoNonnegative(why.clone()));
        }
        if let Some(radius) = report.marginal_below {
            notes.push(Note::marginal_below(TOP, &a, radius, ELEMENTS_HINT));
        }
        if let (Some(n), Some(radius)) = (report.nonnegative, report.nonnegative_marginal_below) {
            notes.push(Note::marginal_below(NONNEGATIVE, &n, radius, ELEMENTS_HINT));
        }
        if !report.one_range() {
            notes.push(Note::Pieces {
                beta: a.beta_at_max,
                stable: report.stable_alphas.clone(),
            });
        }
        let margin = wall.map(|(w, lower)| {
            notes.extend(lower);
            w
        });
        Ok(Self {
            point: AmaxPoint {
                delta,
                d,
                alpha_max: a.alpha_max,
                beta_at_max: a.beta_at_max,
            },
            margin,
            nonnegative: report.nonnegative,
            notes,
        })
    }
}

/// Where a row is, for its notes: normalized, or physical when the device was given.
struct Place {
    delta: f64,
    d: f64,
    scale: Option<DeviceScale>,
}

impl Place {
    fn head(&self) -> anyhow::Result<String> {
        Ok(match self.scale {
            Some(u) => format!("b = {} N s/m, d = {}", u.try_damping(self.delta)?, self.d),
            None => format!("delta = {}, d = {}", self.delta, self.d),
        })
    }

    /// A wall as `K = .. N/m, B = .. N s/m` (physical) or `alpha = .., beta = ..`.
    fn wall(&self, alpha: f64, beta: f64) -> anyhow::Result<String> {
        Ok(match self.scale {
            Some(u) => format!("K = {} N/m, B = {} N s/m", u.try_k(alpha)?, u.try_b(beta)?),
            None => format!("alpha = {alpha}, beta = {beta}"),
        })
    }

    fn negative_damping(&self, r: &AmaxPoint, n: &Amax) -> anyhow::Result<String> {
        Ok(format!(
            "note: {}: the stiffest wall ({}) needs negative virtual damping; the stiffest with nonnegative damping is {} (--nonnegative-wall-damping requires it)",
            self.head()?,
            self.wall(r.alpha_max, r.beta_at_max)?,
            self.wall(n.alpha_max, n.beta_at_max)?
        ))
    }

    fn say(&self, n: &Note) -> anyhow::Result<String> {
        Ok(match n {
            Note::Pieces { beta, stable } => {
                let ranges: Vec<String> = stable
                    .iter()
                    .map(|i| -> anyhow::Result<String> {
                        Ok(match self.scale {
                            Some(u) => format!("{} < K < {}", u.try_k(i.lo)?, u.try_k(i.hi)?),
                            None => format!("{} < alpha < {}", i.lo, i.hi),
                        })
                    })
                    .collect::<anyhow::Result<_>>()?;
                let at = match self.scale {
                    Some(u) => format!("B = {} N s/m", u.try_b(*beta)?),
                    None => format!("beta = {beta}"),
                };
                format!(
                    "note: {}: the stable stiffnesses at the optimum's damping {at} are not one range from 0 up to it: {}",
                    self.head()?,
                    if ranges.is_empty() {
                        "none (the optimum is the tip of a wedge tilted off this damping)"
                            .to_string()
                    } else {
                        ranges.join(" or ")
                    }
                )
            }
            Note::LowerTop { fraction, top } => format!(
                "note: {}: the margin wall is {fraction} of {}, the stiffest wall whose every stiffness from the margin wall up to it is stable at its damping",
                self.head()?,
                self.wall(top.alpha_max, top.beta_at_max)?
            ),
            Note::Fallback(why) => format!("note: {}: {why}", self.head()?),
            Note::NoNonnegative(why) => format!(
                "note: {}: the stiffest wall needs negative virtual damping, and no wall with nonnegative damping is given: {why} (--nonnegative-wall-damping asks for it alone)",
                self.head()?
            ),
            Note::MarginalBelow {
                which,
                alpha,
                beta,
                radius,
                hint,
            } => format!(
                "note: {}: {which} ({}, {HOLD_STEP:e} below its optimum) has spectral radius {radius}, within the marginal band of 1 ({:e}): `check` calls it marginal, not stable; {} ({hint})",
                self.head()?,
                self.wall(*alpha, *beta)?,
                stabound::stability::DEFAULT_MARGIN,
                slow_mode(*radius)
            ),
        })
    }
}

/// What a closed-loop root of modulus `radius` within the marginal band means for the wall.
pub(crate) fn slow_mode(radius: f64) -> String {
    if radius < 1.0 {
        format!(
            "its slowest mode decays by a factor e only every {:.3e} samples, so the loop barely settles",
            1.0 / (1.0 - radius)
        )
    } else {
        "its slowest mode is not shown to decay at all".into()
    }
}

/// The rows' notes on stderr: the first [`Notes::SHOWN`] in full, then how many more.
#[derive(Default)]
struct Notes {
    shown: Vec<String>,
    more: usize,
}

impl Notes {
    /// Enough to see what a table says without burying its data in messages.
    const SHOWN: usize = 20;

    fn push(&mut self, note: String) {
        if self.shown.len() < Self::SHOWN {
            self.shown.push(note);
        } else {
            self.more += 1;
        }
    }

    fn print(&self) {
        for n in &self.shown {
            eprintln!("{n}");
        }
        if self.more > 0 {
            eprintln!("note: {} more notes like these", self.more);
        }
    }
}
