//! `stabound check`: one stability test for one wall, or for every wall of a CSV.

mod batch;
mod certified_set;
mod delays;
mod region;
mod set;

use std::path::PathBuf;

use clap::ValueEnum;
use stabound::buzz::{BuzzOptions, buzz, describing_function};
use stabound::elements::{Loop, PhysicalElements};
use stabound::export::report::{CheckReport, check_json, check_text};
use stabound::params::Device;
use stabound::robust::Quantity;
use stabound::stability::Checker;
use stabound::stability::{DEFAULT_MARGIN, Options, Verdict};

use super::args::{
    ElementArgs, MethodArg, NonlinearArgs, Span, Spread, as_flags, finite, one_or_set, span,
};
use stabound::request::{DeviceInputs, Takes};

use super::output::Plan;
use super::{ExitWith, UsageError};

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Format {
    Text,
    Json,
}

/// Give the wall either in normalized form (--alpha --beta --delta --d) or in physical units
/// (--mass --period --damping --stiffness --wall-damping and --delay or --delay-samples).
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Normalized stiffness alpha = K T^2 / m (LO..HI with --certify: every wall of the box).
    #[arg(long, value_parser = span, allow_hyphen_values = true)]
    alpha: Option<Span>,
    /// Normalized virtual damping beta = B T / m (LO..HI with --certify).
    #[arg(long, value_parser = span, allow_hyphen_values = true)]
    beta: Option<Span>,
    /// Normalized physical damping delta = b T / m (>= 0).
    #[arg(long, value_parser = finite, allow_hyphen_values = true)]
    delta: Option<f64>,
    /// Delay factor d = delay / T (>= 0, may be fractional).
    #[arg(long, value_parser = finite, allow_hyphen_values = true)]
    d: Option<f64>,
    /// Device mass m in kg (LO..HI or one-of:A,B,C: the wall is checked for every device of
    /// the set).
    #[arg(long, value_parser = one_or_set, allow_hyphen_values = true)]
    mass: Option<Spread>,
    /// Sampling period T in s.
    #[arg(long, value_parser = finite, allow_hyphen_values = true)]
    period: Option<f64>,
    /// Physical damping b in N s/m (or LO..HI, or one-of:LIST).
    #[arg(long, value_parser = one_or_set, allow_hyphen_values = true)]
    damping: Option<Spread>,
    /// Wall stiffness K in N/m (LO..HI with --certify: every wall of the box).
    #[arg(long, value_parser = span, allow_hyphen_values = true)]
    stiffness: Option<Span>,
    /// Wall damping B in N s/m (LO..HI with --certify).
    #[arg(long = "wall-damping", value_parser = span, allow_hyphen_values = true)]
    wall_damping: Option<Span>,
    /// Delay in s (or LO..HI, or one-of:LIST).
    #[arg(long, value_parser = one_or_set, allow_hyphen_values = true, conflicts_with = "delay_samples")]
    delay: Option<Spread>,
    /// Delay in sampling periods (or LO..HI, e.g. 1..3, or one-of:LIST, e.g. one-of:1,2,3).
    #[arg(long = "delay-samples", value_parser = one_or_set, allow_hyphen_values = true)]
    delay_samples: Option<Spread>,
    #[command(flatten)]
    loop_elements: ElementArgs,
    /// The encoder, force output and dry friction: each modelled only when named, and then
    /// `check` adds the buzz verdict (the exact simulation from rest at 1, 3 and 10 counts
    /// and from an impact at 1 count per sample, 20,000 samples) and its describing-function
    /// estimate.
    #[command(flatten)]
    nonlinear: NonlinearArgs,
    /// How stability is decided.
    #[arg(long, value_enum, default_value = "auto")]
    method: MethodArg,
    /// Half-width of the marginal band around the unit circle: a spectral radius within this
    /// of 1 is reported as marginal.
    #[arg(long = "marginal-band", default_value_t = DEFAULT_MARGIN, value_parser = finite, allow_hyphen_values = true)]
    margin: f64,
    /// Output format (with --batch: CSV, or JSON for --format json).
    #[arg(long, value_enum, default_value = "text")]
    format: Format,
    /// Many walls in one run: a CSV file (`-` for stdin) with a header naming the columns
    /// alpha,beta,delta,d (normalized), or stiffness_N_per_m,wall_damping_Ns_per_m with the
    /// device given by --mass --period --damping --delay|--delay-samples. One output row per
    /// wall, in input order: the wall, verdict, method (with --radius also spectral_radius,
    /// before method).
    #[arg(long, value_name = "CSV")]
    batch: Option<PathBuf>,
    /// Also compute the spectral radius (the largest modulus of the characteristic
    /// polynomial's roots): for one wall the report adds it and lists every root, with --batch
    /// it adds the spectral_radius column. The verdict needs no roots; they cost about as much
    /// as everything else at d = 1 and nearly all the time at long delays (a polynomial of
    /// degree 503 at d = 500).
    #[arg(long)]
    radius: bool,
    /// With --batch: the default output, the verdict and the method without the
    /// spectral_radius column (accepted for scripts written when the radius was printed by
    /// default).
    #[arg(long = "verdict-only", requires = "batch", conflicts_with = "radius")]
    verdict_only: bool,
    /// Exit status by verdict, for scripts: 0 stable, 3 unstable, 4 marginal (with --batch:
    /// 3 if any wall is unstable, else 4 if any is marginal, else 0). Errors keep 1 and 2.
    #[arg(long = "exit-status")]
    exit_status: bool,
    /// Write to this file instead of stdout.
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Also write a certificate of the verdict (JSON) to this file: a proof in interval
    /// arithmetic that tools/verify_certificate.py checks with exact rationals. For one wall,
    /// with or without loop elements (not with --batch). With --alpha/--beta or
    /// --stiffness/--wall-damping given as LO..HI: a proof for every wall of that box. With
    /// --delay-samples LO..HI: a proof for the wall at every delay of that interval. Over a
    /// finite set of devices (one-of:LIST loop-element values): a proof for every member.
    #[arg(long, value_name = "FILE", conflicts_with = "batch")]
    certify: Option<PathBuf>,
    /// With --certify over a box of walls: the most leaves the box is halved into where it
    /// is undecided (each leaf costs one recursion; the checker replays each); over an
    /// interval of delays (--delay-samples LO..HI), the most cells of delay.
    #[arg(long = "certify-leaves", default_value_t = 1024, requires = "certify")]
    certify_leaves: usize,
}

/// Exit status of `--exit-status` for an unstable wall.
const EXIT_UNSTABLE: u8 = 3;
/// Exit status of `--exit-status` for a marginal wall.
const EXIT_MARGINAL: u8 = 4;

/// The exit status `--exit-status` asks for: the worst verdict wins (unstable before
/// marginal before stable).
pub(super) fn verdict_status(verdicts: impl IntoIterator<Item = Verdict>) -> anyhow::Result<()> {
    let mut marginal = false;
    for v in verdicts {
        match v {
            Verdict::Unstable => return Err(ExitWith(EXIT_UNSTABLE).into()),
            Verdict::Marginal => marginal = true,
            _ => {}
        }
    }
    if marginal {
        Err(ExitWith(EXIT_MARGINAL).into())
    } else {
        Ok(())
    }
}

impl Args {
    /// Whether a wall value is given as an interval (a box of walls).
    fn boxed(&self) -> bool {
        [self.alpha, self.beta, self.stiffness, self.wall_damping]
            .iter()
            .any(|s| s.and_then(Span::interval).is_some())
    }

    /// The device mass (an interval's low end).
    fn mass(&self) -> Option<f64> {
        self.mass.as_ref().map(Spread::low)
    }

    /// The device damping (an interval's low end).
    fn damping(&self) -> Option<f64> {
        self.damping.as_ref().map(Spread::low)
    }

    /// The delay in s (an interval's low end).
    fn delay(&self) -> Option<f64> {
        self.delay.as_ref().map(Spread::low)
    }

    /// The delay in samples (an interval's low end).
    fn delay_samples(&self) -> Option<f64> {
        self.delay_samples.as_ref().map(Spread::low)
    }

    /// The device's own parameters given as sets (intervals or lists).
    fn device_sets(&self) -> Vec<(Quantity, stabound::robust::Spread)> {
        [
            (Quantity::Mass, self.mass.as_ref()),
            (Quantity::Damping, self.damping.as_ref()),
            (
                Quantity::Delay,
                self.delay.as_ref().or(self.delay_samples.as_ref()),
            ),
        ]
        .into_iter()
        .filter_map(|(q, s)| s?.set().map(|s| (q, s)))
        .collect()
    }

    fn names_elements(&self) -> bool {
        self.loop_elements.named().any()
    }

    fn named(&self) -> PhysicalElements {
        self.loop_elements.named()
    }

    /// The loop of `device` with the elements named (none: the paper's loop); a value the
    /// library refuses is reported with the flag that gave it.
    fn elements(&self, device: &Device) -> anyhow::Result<Loop> {
        Loop::physical(device, &self.named()).map_err(super::args::flagged)
    }
}

pub fn run(a: Args) -> anyhow::Result<()> {
    let mut outputs = Plan::new();
    let data = outputs.data("-o", a.output.as_deref());
    if let Some(input) = a.batch.as_deref().filter(|p| p.as_os_str() != "-") {
        outputs.input(input);
    }
    let certify = a.certify.as_deref().map(|p| outputs.file("--certify", p));
    let mut out = outputs.check()?;
    if let Some(input) = &a.batch {
        a.loop_elements.one_device("check --batch")?;
        if !a.device_sets().is_empty() {
            return Err(UsageError(
                "check --batch judges each wall on one device: give the device's values as one number (sets, LO..HI or one-of:LIST, are for one wall)".into(),
            )
            .into());
        }
        if a.nonlinear.named().any() {
            return Err(UsageError(
                "the buzz verdict (--encoder-resolution, --force-resolution, --coulomb-friction, --static-friction) is for one wall: leave out --batch".into(),
            )
            .into());
        }
        let bytes = batch::run(&a, input)?;
        out.write(data, &bytes.0)?;
        out.finish()?;
        return bytes.1;
    }
    // the library decides the form and refuses mixed or missing inputs; a box of walls is
    // resolved at its low corner, and its high corner converted beside it
    let given = DeviceInputs {
        alpha: a.alpha.map(|s| s.lo),
        beta: a.beta.map(|s| s.lo),
        delta: a.delta,
        d: a.d,
        mass: a.mass(),
        period: a.period,
        damping: a.damping(),
        delay: a.delay(),
        delay_samples: a.delay_samples(),
        stiffness: a.stiffness.map(|s| s.lo),
        wall_damping: a.wall_damping.map(|s| s.lo),
    }
    .resolve(Takes::Walls)
    .map_err(as_flags)?;
    if !given.is_physical() && (a.names_elements() || a.nonlinear.named().any()) {
        return Err(UsageError(
            "loop elements (--hand-*, --velocity-filter-*, --handle-mass, --transmission-*, --encoder, --actuator-time-constant) and quantizers or friction (--encoder-resolution, --force-resolution, --coulomb-friction, --static-friction) are given in physical units: give the device with --mass --period --damping --stiffness --wall-damping and --delay or --delay-samples".into(),
        )
        .into());
    }
    let (params, device) = (given.normalized()?, given.device()?);
    // the box of walls (low and high corners in (alpha, beta)) when a wall value is LO..HI
    let corners = match (&device, a.stiffness, a.wall_damping, a.alpha, a.beta) {
        (Some(dev), Some(ks), Some(bs), _, _) => {
            let high = dev.normalize(ks.hi, bs.hi)?;
            Some(region::widen(&params, &high, ks, bs))
        }
        (None, _, _, Some(alpha), Some(beta)) => Some(((alpha.lo, beta.lo), (alpha.hi, beta.hi))),
        _ => None,
    };
    if a.boxed() && (certify.is_none() || a.nonlinear.named().any()) {
        return Err(UsageError(
            "a box of walls (--alpha/--beta or --stiffness/--wall-damping as LO..HI) is judged by a certificate: add --certify FILE, and leave out the quantizers and friction".into(),
        )
        .into());
    }
    if let (Some(dev), Some(k), Some(bw)) = (
        &device,
        a.stiffness.map(|s| s.lo),
        a.wall_damping.map(|s| s.lo),
    ) && let Some(set) = a.loop_elements.device_set(dev, &a.device_sets(), false)?
    {
        if let Some(slot) = certify {
            // an interval: of delays only; a finite set: every member, each by its own proof
            let (report, cert, status) = if set.has_intervals() || a.nonlinear.named().any() {
                let delays = delays::interval(&a)?;
                let (_, wall) = params.split()?;
                delays::run(&a, a.elements(dev)?, &wall, delays)?
            } else {
                certified_set::run(&a, &set, (k, bw), corners.filter(|_| a.boxed()))?
            };
            out.write(data, report.as_bytes())?;
            out.write(slot, cert.as_bytes())?;
            out.finish()?;
            return status;
        }
        if a.nonlinear.named().any() {
            return Err(UsageError(
                "the buzz verdict answers for one device: give every value as one number (no LO..HI, no one-of:LIST)".into(),
            )
            .into());
        }
        let (text, verdict) = set::report(&set, k, bw, a.format)?;
        out.write(data, text.as_bytes())?;
        out.finish()?;
        if a.exit_status {
            verdict_status([verdict])?;
        }
        return Ok(());
    }
    let (plant, wall) = params.split()?;
    let options = Options {
        method: a.method.into(),
        margin: a.margin,
    };
    let lp = match &device {
        Some(dev) => a.elements(dev)?,
        None => Loop::new(plant),
    };
    if let (Some(slot), Some((lo, hi)), true) = (certify, corners, a.boxed()) {
        let (report, cert, status) = region::run(&a, lp, lo, hi)?;
        out.write(data, report.as_bytes())?;
        out.write(slot, cert.as_bytes())?;
        out.finish()?;
        return status;
    }
    // the roots (nearly all the time at long delays) only when the radius is asked for
    let checker = Checker::new(lp, options)?;
    let analysis = if a.radius {
        Some(checker.analyze(&wall)?)
    } else {
        None
    };
    let decision = match &analysis {
        Some(an) => an.decision(),
        None => checker.decide(&wall)?,
    };
    let certificate = match certify {
        Some(slot) => Some((slot, stabound::certificate::certify(lp, &wall, a.margin)?)),
        None => None,
    };
    let verdict = decision.verdict;
    let nonlinear = a.nonlinear.named();
    let buzzing = match (&device, nonlinear.any()) {
        (Some(dev), true) => {
            // the stiffness as given, not back from alpha (whose round trip moves its last
            // bits, and with them the length unit when no encoder is named)
            let k = a
                .stiffness
                .map(|s| s.lo)
                .unwrap_or_else(|| dev.stiffness(wall.alpha()));
            let q = nonlinear.normalize(dev, k)?;
            Some((
                buzz(lp, &wall, &q, &BuzzOptions::default())?,
                describing_function(lp, &wall)?,
            ))
        }
        _ => None,
    };
    let report = CheckReport {
        decision,
        degree: checker.degree(),
        analysis: analysis.as_ref(),
        params: &params,
        band: a.margin,
        lp: &lp,
        device: device.as_ref(),
        buzz: buzzing.as_ref().map(|(b, df)| (b, df)),
        wall: a.stiffness.map(|s| s.lo).zip(a.wall_damping.map(|s| s.lo)),
    };
    let text = match a.format {
        Format::Json => check_json(&report),
        Format::Text => check_text(&report),
    };
    out.write(data, text.as_bytes())?;
    if let Some((slot, cert)) = certificate {
        out.write(slot, cert.to_json().as_bytes())?;
    }
    out.finish()?;
    if a.exit_status {
        verdict_status([verdict])?;
    }
    Ok(())
}
