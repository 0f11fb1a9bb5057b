//! `stabound step`: step responses from operator force to position (paper Fig. 11).

use std::path::PathBuf;

use clap::ValueEnum;
use stabound::amax::{AmaxOptions, HOLD_STEP, recommend};
use stabound::buzz::{BuzzOptions, BuzzReport, Outcome, buzz, cycle};
use stabound::elements::Loop;
use stabound::export::report::buzz_verdict;
use stabound::export::{Table, csv::to_csv_bytes};
use stabound::figures::{limit_cycle_panel, step_figure, step_label};
use stabound::params::{Delay, Device};
use stabound::sim::{StepOptions, StepResponse, step_response};
use stabound::stability::Checker;
use stabound::stability::{Options, Verdict};

use super::UsageError;
use super::args::{ElementArgs, NonlinearArgs, finite, parse_list};
use super::output::Plan;

/// A parsed list; an alias so that clap takes it as one value, not repeated flags.
type List = Vec<f64>;

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Format {
    /// One row per point: damping_Ns_per_m, stiffness_N_per_m, wall_damping_Ns_per_m,
    /// time_s, position_m.
    Csv,
    /// One line per response: walls, stability, final value, peak, settling time.
    Summary,
}

/// Simulates the sampled loop for a step of operator force, exactly, with the position
/// between the samples too, for each physical damping in --damping. Give the wall as
/// --stiffness (and --wall-damping), or as --margin F: F x alpha_max with the damping at
/// alpha_max. The loop elements (hand, compliant transmission, actuator lag, velocity
/// filter) are modelled when named; the operator's force acts on the handle, and the
/// position is the one the encoder reads.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Device mass m in kg.
    #[arg(long, value_parser = finite)]
    mass: f64,
    /// Sampling period T in s.
    #[arg(long, value_parser = finite)]
    period: f64,
    /// Physical damping b in N s/m: one value or a list (0,10,100 or START:STOP:COUNT).
    #[arg(long, value_parser = parse_list)]
    damping: List,
    /// Delay in sampling periods (may be fractional).
    #[arg(long = "delay-samples", conflicts_with = "delay", value_parser = finite)]
    delay_samples: Option<f64>,
    /// Delay in s.
    #[arg(long, value_parser = finite)]
    delay: Option<f64>,
    /// Wall stiffness K in N/m.
    #[arg(long, allow_hyphen_values = true, conflicts_with = "margin")]
    stiffness: Option<f64>,
    /// Wall damping B in N s/m (with --stiffness; default 0).
    #[arg(long = "wall-damping", allow_hyphen_values = true)]
    wall_damping: Option<f64>,
    /// Stability margin: stiffness F x alpha_max (0 < F <= 1) with the virtual damping at
    /// alpha_max, for each damping (paper Section VIII uses 0.75); with loop elements, the
    /// alpha_max of that loop, and where the stable stiffnesses at its damping do not reach
    /// from F x alpha_max up to it, F times the stiffest wall whose do (a note says so).
    #[arg(long)]
    margin: Option<f64>,
    /// Operator force step F_H in N.
    #[arg(long, default_value_t = 1.0, allow_hyphen_values = true)]
    force: f64,
    /// Simulated time in s.
    #[arg(long, default_value_t = 0.05)]
    duration: f64,
    /// Points per sampling period (1: the sampling instants only).
    #[arg(long = "points-per-period", default_value_t = 10)]
    points_per_period: usize,
    /// Settling band for the summary, relative to F_H / K.
    #[arg(long = "settling-band", default_value_t = 0.02)]
    settling_band: f64,
    /// Output format.
    #[arg(long, value_enum, default_value = "csv")]
    format: Format,
    /// Also draw the responses into this file (.svg, .png or .pdf by its extension).
    #[arg(long)]
    svg: Option<PathBuf>,
    /// Write the data to this file instead of stdout.
    #[arg(short, long)]
    output: Option<PathBuf>,
    #[command(flatten)]
    loop_elements: ElementArgs,
    /// The encoder, force output and dry friction: when any is named, each wall also gets
    /// the buzz verdict (the exact simulation from rest at 1, 3 and 10 counts and from an
    /// impact, no operator force), shown in the summary, and --svg draws the limit cycles.
    #[command(flatten)]
    nonlinear: NonlinearArgs,
    #[command(flatten)]
    draw: super::figure::SvgStyleArgs,
}

/// The wall for one device and its loop: (stiffness, wall damping) in physical units. With
/// --margin the wall is checked stable before it is used, and a note on stderr says where it
/// is not the fraction of alpha_max at its damping or where alpha_max needs negative damping.
fn wall_for(a: &Args, device: &Device, lp: &Loop) -> anyhow::Result<(f64, f64)> {
    match (a.stiffness, a.margin) {
        (Some(k), None) => Ok((k, a.wall_damping.unwrap_or(0.0))),
        (None, Some(f)) => {
            if a.wall_damping.is_some() {
                return Err(UsageError(
                    "--wall-damping goes with --stiffness; with --margin the damping is the one at alpha_max".into(),
                )
                .into());
            }
            let m = recommend(lp, &AmaxOptions::default(), f)?;
            let top = m.report.amax;
            let b = device.damping();
            if !m.at_optimum() {
                eprintln!(
                    "note: b = {b} N s/m: the stable stiffnesses at the damping of K_max = {} N/m (B = {} N s/m) do not reach from {f} of it up to it; the wall is {f} of K = {} N/m at B = {} N s/m, the stiffest whose every stiffness from the wall up is stable",
                    device.stiffness(top.alpha_max),
                    device.wall_damping(top.beta_at_max),
                    device.stiffness(m.top.alpha_max),
                    device.wall_damping(m.top.beta_at_max)
                );
            }
            if let Some(n) = m.report.nonnegative
                && m.wall.beta() < 0.0
            {
                eprintln!(
                    "note: b = {b} N s/m: this wall needs negative virtual damping; the stiffest wall with nonnegative damping is K = {} N/m at B = {} N s/m",
                    device.stiffness(n.alpha_max),
                    device.wall_damping(n.beta_at_max)
                );
            }
            if let Some(radius) = m.report.marginal_below {
                let a = m.report.amax;
                eprintln!(
                    "note: b = {b} N s/m: the stiffest wall to render (K = {} N/m, B = {} N s/m, {HOLD_STEP:e} below K_max) has spectral radius {radius}, within the marginal band of 1 ({:e}): `check` calls it marginal, not stable; {}",
                    device.stiffness(a.alpha_max * (1.0 - HOLD_STEP)),
                    device.wall_damping(a.beta_at_max),
                    stabound::stability::DEFAULT_MARGIN,
                    super::amax::slow_mode(radius)
                );
            }
            if let Some(why) = &m.report.no_nonnegative
                && m.wall.beta() < 0.0
            {
                eprintln!(
                    "note: b = {b} N s/m: this wall needs negative virtual damping, and no wall with nonnegative damping is given: {why}"
                );
            }
            Ok((
                device.stiffness(m.wall.alpha()),
                device.wall_damping(m.wall.beta()),
            ))
        }
        _ => Err(UsageError("give --stiffness K or --margin F".into()).into()),
    }
}

pub fn run(a: Args) -> anyhow::Result<()> {
    let delay = match (a.delay, a.delay_samples) {
        (Some(s), None) => Delay::Seconds(s),
        (None, Some(n)) => Delay::Samples(n),
        _ => return Err(UsageError("missing --delay (s) or --delay-samples".into()).into()),
    };
    if !(a.settling_band > 0.0 && a.settling_band.is_finite()) {
        return Err(UsageError("--settling-band must be a positive number".into()).into());
    }
    let mut outputs = Plan::new();
    let data = outputs.data("-o", a.output.as_deref());
    let svg_format = super::figure::option_format("--svg", a.svg.as_deref())?;
    a.draw.check()?;
    let svg_slot = a.svg.as_deref().map(|p| outputs.file("--svg", p));
    let mut out = outputs.check()?;
    let options = StepOptions {
        force: a.force,
        duration: a.duration,
        points_per_period: a.points_per_period,
    };
    a.loop_elements.one_device("step")?;
    let named = a.loop_elements.named();
    // "; elements: hand, actuator lag" in the summary and the title, when any is named
    let modelled = match named.names() {
        names if names.is_empty() => String::new(),
        names => format!("; elements: {}", names.join(", ")),
    };
    let nonlinear = a.nonlinear.named();
    let buzz_options = BuzzOptions::default();
    let mut runs: Vec<(Device, f64, f64, StepResponse, Verdict)> = Vec::new();
    // per wall: the buzz verdict and the worst run's limit cycle (empty when none)
    let mut buzzing: Vec<(BuzzReport, Vec<f64>)> = Vec::new();
    for &b in &a.damping {
        let device = Device::new(a.mass, a.period, b, delay)?;
        let plant = device.plant()?;
        let lp = a.loop_elements.loop_on(&device)?;
        let (k, bw) = wall_for(&a, &device, &lp)?;
        let wall = device.wall(k, bw)?;
        // with no element this is the paper's checker, verdict for verdict
        let verdict = Checker::new(lp, Options::default())?.verdict(&wall)?;
        if verdict != Verdict::Stable {
            eprintln!(
                "warning: b = {b} N s/m, K = {k} N/m, B = {bw} N s/m is {} (alpha = {}, beta = {}, delta = {}, d = {}); its response does not settle",
                verdict.name(),
                wall.alpha(),
                wall.beta(),
                plant.delta(),
                plant.d()
            );
        }
        let r = step_response(&lp, k, bw, &options)?;
        if nonlinear.any() {
            let q = nonlinear.normalize(&device, k)?;
            let report = buzz(lp, &wall, &q, &buzz_options)?;
            let cycle = match report.worst() {
                Some(w) if w.outcome == Outcome::Buzz && a.svg.is_some() => {
                    let y = cycle(lp, &wall, &q, w.start, &buzz_options)?;
                    // two periods, at most the last 120 samples (a readable trace)
                    let shown = w.period_samples.map_or(120, |p| 2 * p).clamp(8, 120);
                    let shown = shown.min(y.len());
                    y[y.len() - shown..].to_vec()
                }
                _ => Vec::new(),
            };
            buzzing.push((report, cycle));
        }
        runs.push((device, k, bw, r, verdict));
    }
    if let Some(svg_slot) = svg_slot {
        let labelled: Vec<(String, StepResponse)> = runs
            .iter()
            .map(|(dev, k, bw, r, _)| (step_label(dev, *k, *bw), r.clone()))
            .collect();
        let title = format!(
            "Step responses, F_H = {} N, m = {} kg, T = {} s, d = {}{modelled}",
            a.force,
            a.mass,
            a.period,
            runs[0].0.delay_factor()
        );
        let mut fig = step_figure("step", &title, &labelled);
        let cycles: Vec<(String, Vec<f64>)> = labelled
            .iter()
            .zip(&buzzing)
            .filter(|(_, (_, y))| !y.is_empty())
            .map(|((label, _), (_, y))| (label.clone(), y.clone()))
            .collect();
        if !cycles.is_empty() {
            fig.panels.push(limit_cycle_panel(
                "Limit cycles (buzz, no operator force)",
                &cycles,
            ));
        }
        fig.panels = fig
            .panels
            .into_iter()
            .map(|p| a.draw.apply(p))
            .collect::<anyhow::Result<_>>()?;
        out.write(svg_slot, &fig.render(svg_format)?)?;
    }
    let mut text = String::new();
    match a.format {
        Format::Csv => {
            // the data is the step response; the buzz verdict is a message beside it
            for ((dev, k, bw, _, _), (b, _)) in runs.iter().zip(&buzzing) {
                eprintln!("buzz ({}): {}", step_label(dev, *k, *bw), buzz_verdict(b));
            }
            let mut table = Table::new(&[
                "damping_Ns_per_m",
                "stiffness_N_per_m",
                "wall_damping_Ns_per_m",
                "time_s",
                "position_m",
            ]);
            for (dev, k, bw, r, _) in &runs {
                table.reserve(r.time.len());
                for (t, x) in r.time.iter().zip(&r.position) {
                    table.push_numbers(&[dev.damping(), *k, *bw, *t, *x]);
                }
            }
            out.write(data, &to_csv_bytes(&table))?;
            return out.finish();
        }
        Format::Summary => {
            for (i, (dev, k, bw, r, verdict)) in runs.iter().enumerate() {
                let buzzed = buzzing.get(i).map_or(String::new(), |(b, _)| {
                    format!("; buzz: {}", buzz_verdict(b))
                });
                let plant = dev.plant()?;
                let settle = r
                    .settling_time(a.settling_band)
                    .map_or("not settled".to_string(), |t| format!("{t:.6} s"));
                text.push_str(&format!(
                    "b = {} N s/m (delta = {:.6}): K = {k:.6} N/m (alpha = {:.6}), B = {bw:.6} N s/m (beta = {:.6}), {}; final {} m, peak {:.6e} m, settling ({} band) {settle}{modelled}{buzzed}\n",
                    dev.damping(),
                    plant.delta(),
                    dev.alpha(*k),
                    dev.beta(*bw),
                    verdict.name(),
                    r.final_value.map_or("none".to_string(), |v| format!("{v:.6e}")),
                    r.peak(),
                    a.settling_band,
                ));
            }
        }
    }
    out.write(data, text.as_bytes())?;
    out.finish()
}
