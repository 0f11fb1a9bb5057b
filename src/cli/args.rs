//! Argument types shared by the subcommands: lists, finite numbers, the grid of plants
//! (normalized or physical), the beta limits of alpha_max searches, shards and output paths.

use anyhow::Context;
use std::ops::Range;

use clap::ValueEnum;
use stabound::amax::{AmaxOptions, DEFAULT_THETA_TOL};
use stabound::elements::{Encoder, Loop, PhysicalElements};
use stabound::params::{Delay, Device, Plant};
use stabound::robust::{DeviceSet, Param};

use super::UsageError;

/// The most values one list may expand to.
pub const MAX_LIST: usize = 100_000;

/// The most boundary curves one run (or one shard) computes: each is written as soon as it
/// and those before it are done, so the bound is one of time (see the library's constant).
pub const MAX_CURVES: usize = stabound::boundary::MAX_STREAM_CURVES;

/// The most rows (table nodes) one run (or one shard) computes: about 100 bytes each in
/// memory and 20 us each to compute.
pub const MAX_ROWS: usize = stabound::amax::MAX_ROWS;

/// The most `alpha_max` rows one `amax` run (or shard) computes: streamed, so bounded by time.
pub const MAX_STREAM_ROWS: usize = stabound::amax::MAX_STREAM_ROWS;

/// The most work units a request may have in total, even split into shards.
pub const MAX_TOTAL_UNITS: usize = 1_000_000_000;

/// A parsed LIST (a newtype, so that clap takes one argument as one whole list).
#[derive(Debug, Clone, PartialEq)]
pub struct List(pub Vec<f64>);

/// clap value parser of a [`List`] (see [`parse_list`]).
pub fn list(s: &str) -> Result<List, String> {
    parse_list(s).map(List)
}

/// Parses a list of numbers: a comma list (`0,0.25,0.5`) or an inclusive range
/// `START:STOP:COUNT` of `COUNT` evenly spaced values.
pub fn parse_list(s: &str) -> Result<Vec<f64>, String> {
    let s = s.trim();
    if s.is_empty() {
        return Err("empty list; give values like 0,0.25,0.5 or a range START:STOP:COUNT".into());
    }
    if s.contains(':') {
        let parts: Vec<&str> = s.split(':').collect();
        if parts.len() != 3 {
            return Err(format!("range '{s}' must be START:STOP:COUNT, e.g. 0:1:11"));
        }
        let start = finite(parts[0])?;
        let stop = finite(parts[1])?;
        let count: usize = parts[2].trim().parse().map_err(|_| {
            format!(
                "COUNT '{}' in range '{s}' must be a whole number >= 1",
                parts[2]
            )
        })?;
        if count == 0 || count > MAX_LIST {
            return Err(format!(
                "COUNT in range '{s}' must be between 1 and {MAX_LIST}"
            ));
        }
        if stop < start {
            return Err(format!("range '{s}' is inverted: STOP must be >= START"));
        }
        if count == 1 {
            return Ok(vec![start]);
        }
        let step = (stop - start) / (count - 1) as f64;
        if !step.is_finite() {
            return Err(format!("range '{s}' is too wide for f64 steps"));
        }
        let mut v: Vec<f64> = (0..count)
            .map(|i| as_typed(start + step * i as f64))
            .collect();
        v[count - 1] = stop;
        return Ok(v);
    }
    let n = s.split(',').count();
    if n > MAX_LIST {
        return Err(format!(
            "list has {n} values; at most {MAX_LIST} are accepted"
        ));
    }
    s.split(',').map(finite).collect()
}

/// The value of a range step as a person would type it: `0.1 * 3` is `0.30000000000000004`
/// in `f64`; a range `0:1:11` means `0.3`. The nearest number of at most 15 significant
/// digits replaces `x` when it is within 2 ulps of it (the rounding of `start + step * i`),
/// so steps that are decimal print as typed and other values keep every digit.
fn as_typed(x: f64) -> f64 {
    let short: f64 = format!("{x:.14e}").parse().unwrap_or(x);
    let ulp = f64::EPSILON * x.abs().max(f64::MIN_POSITIVE);
    if (short - x).abs() <= 2.0 * ulp {
        short
    } else {
        x
    }
}

/// One number, or an interval `LO..HI` of a set of devices (`lo == hi` for one number).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Span {
    /// Low end (the value of a single number).
    pub lo: f64,
    /// High end.
    pub hi: f64,
}

impl Span {
    /// The interval, when this is one (`lo < hi`).
    pub fn interval(self) -> Option<(f64, f64)> {
        (self.lo < self.hi).then_some((self.lo, self.hi))
    }
}

/// clap value parser of a [`Span`]: a finite number or `LO..HI` with `LO <= HI`; applies to
/// any number flag that may give a set of devices.
pub fn span(t: &str) -> Result<Span, String> {
    match t.split_once("..") {
        None => finite(t).map(|v| Span { lo: v, hi: v }),
        Some((lo, hi)) => {
            let (lo, hi) = (finite(lo)?, finite(hi)?);
            if lo > hi {
                return Err(format!(
                    "interval '{t}' is inverted: give LO..HI with LO <= HI"
                ));
            }
            Ok(Span { lo, hi })
        }
    }
}

/// A LIST (several devices, one row each) or one interval `LO..HI` (one set of devices).
#[derive(Debug, Clone, PartialEq)]
pub enum Spread {
    /// Values, one row each.
    List(Vec<f64>),
    /// One set of devices.
    Interval(Span),
}

impl Spread {
    /// The values of the rows: the list, or the interval's low end (the set's reference).
    fn values(&self) -> Vec<f64> {
        match self {
            Spread::List(v) => v.clone(),
            Spread::Interval(s) => vec![s.lo],
        }
    }

    fn interval(&self) -> Option<(f64, f64)> {
        match self {
            Spread::List(_) => None,
            Spread::Interval(s) => s.interval(),
        }
    }
}

impl From<List> for Spread {
    fn from(l: List) -> Self {
        Spread::List(l.0)
    }
}

/// clap value parser of a [`Spread`]: `LO..HI`, or a LIST as [`parse_list`] reads it.
pub fn spread(t: &str) -> Result<Spread, String> {
    if t.contains("..") {
        span(t).map(Spread::Interval)
    } else {
        parse_list(t).map(Spread::List)
    }
}

/// clap value parser of one finite number.
pub fn finite(t: &str) -> Result<f64, String> {
    let v: f64 = t
        .trim()
        .parse()
        .map_err(|_| format!("'{t}' is not a number"))?;
    if !v.is_finite() {
        return Err(format!("'{t}' is not a finite number"));
    }
    Ok(v)
}

/// Stability test method, as named on the command line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum MethodArg {
    /// Schur-Cohn with a rounding-error guard; where it cannot vouch, the argument-principle
    /// count, then state-space eigenvalues.
    Auto,
    /// Schur-Cohn (Jury) recursion alone (fastest, no roots, no error guard).
    SchurCohn,
    /// Companion-matrix eigenvalues.
    Eigen,
    /// Closed-loop state-matrix eigenvalues (best for long delays).
    StateSpace,
    /// Proven root counts by the argument principle (fast at any delay), state-space
    /// eigenvalues where no count can be proven.
    ArgumentPrinciple,
}

impl From<MethodArg> for stabound::stability::Method {
    fn from(m: MethodArg) -> Self {
        match m {
            MethodArg::Auto => Self::Auto,
            MethodArg::SchurCohn => Self::SchurCohn,
            MethodArg::Eigen => Self::Eigen,
            MethodArg::StateSpace => Self::StateSpace,
            MethodArg::ArgumentPrinciple => Self::ArgumentPrinciple,
        }
    }
}

/// Flags of one way of giving a request, each with whether it was given.
pub type FlagSet<'a> = &'a [(&'static str, bool)];

fn names(flags: FlagSet, given: bool) -> Vec<&'static str> {
    flags.iter().filter(|f| f.1 == given).map(|f| f.0).collect()
}

fn join(names: &[&str]) -> String {
    match names {
        [] => String::new(),
        [one] => (*one).to_string(),
        [init @ .., last] => format!("{} and {last}", init.join(", ")),
    }
}

/// Refuses a request that mixes the normalized and the physical way of giving it, naming
/// the flags of each way that were given.
pub fn not_both(normalized: FlagSet, physical: FlagSet) -> Result<(), UsageError> {
    let (n, p) = (names(normalized, true), names(physical, true));
    if n.is_empty() || p.is_empty() {
        return Ok(());
    }
    Err(UsageError(format!(
        "{} (normalized) and {} (physical units) were both given: drop one kind",
        join(&n),
        join(&p)
    )))
}

/// The error for a request that lacks flags of the way it was given: names every missing
/// one, then says what that way needs (`hint`).
pub fn missing(flags: FlagSet, hint: &str) -> UsageError {
    UsageError(format!("missing {}: {hint}", join(&names(flags, false))))
}

/// What a device in physical units needs, for messages.
pub const PHYSICAL_DEVICE: &str = "--mass, --period, --damping and --delay|--delay-samples";

/// The plants of a sweep over `delta` and `d`: normalized (`--delta LIST --d LIST`) or
/// physical (`--mass --period --damping LIST` and `--delay LIST | --delay-samples LIST`).
#[derive(Debug, clap::Args)]
pub struct GridArgs {
    /// Normalized physical damping delta = b T / m (LIST: 0,0.5,1 or START:STOP:COUNT).
    #[arg(long, value_parser = list, allow_hyphen_values = true)]
    pub delta: Option<List>,
    /// Delay factors d = delay / T (LIST).
    #[arg(long, value_parser = list, allow_hyphen_values = true)]
    pub d: Option<List>,
    /// Device mass m in kg (LO..HI: a set of devices, normalized by LO).
    #[arg(long, value_parser = span, allow_hyphen_values = true)]
    pub mass: Option<Span>,
    /// Sampling period T in s.
    #[arg(long, value_parser = finite, allow_hyphen_values = true)]
    pub period: Option<f64>,
    /// Physical damping b in N s/m (LIST, or LO..HI: one set of devices).
    #[arg(long, value_parser = spread, allow_hyphen_values = true)]
    pub damping: Option<Spread>,
    /// Delays in s (LIST, or LO..HI: one set of devices).
    #[arg(long, value_parser = spread, allow_hyphen_values = true, conflicts_with = "delay_samples")]
    pub delay: Option<Spread>,
    /// Delays in sampling periods (LIST, or LO..HI: one set of devices, e.g. 1..3).
    #[arg(long = "delay-samples", value_parser = spread, allow_hyphen_values = true)]
    pub delay_samples: Option<Spread>,
}

/// [`GridArgs`] resolved to normalized values and validated.
pub struct Grid {
    /// The `delta` values, in the order given.
    pub deltas: Vec<f64>,
    /// The `d` values, in the order given.
    pub ds: Vec<f64>,
    /// `(mass, period)` when the request was in physical units.
    pub device: Option<(f64, f64)>,
    /// The physical dampings (N s/m) and delays as given, one per entry of `deltas` and
    /// `ds` (empty for a normalized request).
    pub physical: (Vec<f64>, Vec<Delay>),
    /// The device parameters given as intervals `LO..HI` (the rows hold `LO`).
    pub intervals: Vec<(Param, f64, f64)>,
}

impl GridArgs {
    /// Resolves the request to normalized `delta` and `d` lists, each value validated as a
    /// plant parameter.
    pub fn resolve(self) -> anyhow::Result<Grid> {
        let normalized = [("--delta", self.delta.is_some()), ("--d", self.d.is_some())];
        let delay_given = self.delay.is_some() || self.delay_samples.is_some();
        let physical = [
            ("--mass", self.mass.is_some()),
            ("--period", self.period.is_some()),
            ("--damping", self.damping.is_some()),
            ("--delay|--delay-samples", delay_given),
        ];
        not_both(&normalized, &physical)?;
        let mut intervals = Vec::new();
        let spans = [
            (Param::Mass, self.mass.and_then(Span::interval)),
            (
                Param::Damping,
                self.damping.as_ref().and_then(Spread::interval),
            ),
            (
                Param::Delay,
                self.delay
                    .as_ref()
                    .or(self.delay_samples.as_ref())
                    .and_then(Spread::interval),
            ),
        ];
        for (p, s) in spans {
            if let Some((lo, hi)) = s {
                intervals.push((p, lo, hi));
            }
        }
        let grid = if physical.iter().any(|f| f.1) {
            let delays: Option<Vec<Delay>> = match (&self.delay, &self.delay_samples) {
                (Some(s), _) => Some(s.values().into_iter().map(Delay::Seconds).collect()),
                (None, Some(n)) => Some(n.values().into_iter().map(Delay::Samples).collect()),
                (None, None) => None,
            };
            let (Some(m), Some(t), Some(bs), Some(delays)) = (
                self.mass.map(|s| s.lo),
                self.period,
                self.damping.as_ref().map(Spread::values),
                delays,
            ) else {
                return Err(
                    missing(&physical, &format!("physical units need {PHYSICAL_DEVICE}")).into(),
                );
            };
            let device = |damping, delay| Device::new(m, t, damping, delay);
            let deltas = bs
                .iter()
                .map(|&b| Ok(device(b, delays[0])?.plant()?.delta()))
                .collect::<anyhow::Result<_>>()?;
            let ds = delays
                .iter()
                .map(|&dl| Ok(device(bs[0], dl)?.plant()?.d()))
                .collect::<anyhow::Result<_>>()?;
            Grid {
                deltas,
                ds,
                device: Some((m, t)),
                physical: (bs, delays),
                intervals,
            }
        } else {
            let (Some(List(deltas)), Some(List(ds))) = (self.delta, self.d) else {
                return Err(missing(
                    &normalized,
                    &format!(
                        "give --delta LIST and --d LIST, or the device in physical units ({PHYSICAL_DEVICE})"
                    ),
                )
                .into());
            };
            Grid {
                deltas,
                ds,
                device: None,
                physical: (Vec::new(), Vec::new()),
                intervals,
            }
        };
        for &x in &grid.deltas {
            Plant::new(x, 0.0)?;
        }
        for &d in &grid.ds {
            Plant::new(0.0, d)?;
        }
        Ok(grid)
    }
}

/// The options of an alpha_max search: beta limits and tolerance.
#[derive(Debug, clap::Args)]
pub struct SearchArgs {
    /// Smallest admissible virtual damping beta (e.g. 0 when negative damping cannot be rendered).
    #[arg(long = "beta-min", value_parser = finite, allow_hyphen_values = true)]
    beta_min: Option<f64>,
    /// Largest admissible virtual damping beta.
    #[arg(long = "beta-max", value_parser = finite, allow_hyphen_values = true)]
    beta_max: Option<f64>,
    /// Smallest admissible wall damping B in N s/m (the physical --beta-min; needs the device
    /// in physical units).
    #[arg(long = "wall-damping-min", value_parser = finite, allow_hyphen_values = true, conflicts_with = "beta_min")]
    wall_damping_min: Option<f64>,
    /// Largest admissible wall damping B in N s/m (the physical --beta-max).
    #[arg(long = "wall-damping-max", value_parser = finite, allow_hyphen_values = true, conflicts_with = "beta_max")]
    wall_damping_max: Option<f64>,
    /// Refinement tolerance of the critical root's angle theta, in radians, in [1e-15, 1e-2]
    /// (the cost hardly depends on it). A loop with elements reads alpha_max off its exact
    /// boundary (to 1e-9) instead.
    #[arg(long = "theta-tol", default_value_t = DEFAULT_THETA_TOL, value_parser = finite, allow_hyphen_values = true)]
    theta_tol: f64,
}

impl SearchArgs {
    /// The validated options; `device` is `(mass, period)` when the device was given in
    /// physical units, which the wall-damping limits need (`beta = B T / m`).
    pub fn options(&self, device: Option<(f64, f64)>) -> anyhow::Result<AmaxOptions> {
        let opts = AmaxOptions::new(self.theta_tol).context("--theta-tol")?;
        let physical = |flag: &str, b: Option<f64>, normalized: Option<f64>| match (b, device) {
            (None, _) => Ok(normalized),
            (Some(b), Some((mass, period))) => Ok(Some(b * period / mass)),
            (Some(_), None) => Err(UsageError(format!(
                "{flag} is a wall damping in N s/m and needs the device in physical units: give {PHYSICAL_DEVICE}, or the normalized --beta-{}",
                if flag.ends_with("min") { "min" } else { "max" }
            ))),
        };
        let lo = physical("--wall-damping-min", self.wall_damping_min, self.beta_min)?;
        let hi = physical("--wall-damping-max", self.wall_damping_max, self.beta_max)?;
        Ok(opts.with_beta_limits(lo, hi)?)
    }
}

/// `--shard K/N`: the K-th of N contiguous blocks of a request's work units (1-based).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    /// Which block, `1..=n`.
    pub k: usize,
    /// How many blocks.
    pub n: usize,
}

/// The most shards a request may be split into.
pub const MAX_SHARDS: usize = 1_000_000;

/// clap value parser of a [`Shard`].
pub fn shard(s: &str) -> Result<Shard, String> {
    let bad = || format!("shard '{s}' must be K/N with 1 <= K <= N <= {MAX_SHARDS}, e.g. 3/8");
    let (k, n) = s.trim().split_once('/').ok_or_else(bad)?;
    let k: usize = k.trim().parse().map_err(|_| bad())?;
    let n: usize = n.trim().parse().map_err(|_| bad())?;
    if k == 0 || n == 0 || k > n || n > MAX_SHARDS {
        return Err(bad());
    }
    Ok(Shard { k, n })
}

impl Shard {
    /// The whole request as one shard.
    pub const ALL: Shard = Shard { k: 1, n: 1 };

    /// The units `[floor((K-1) U / N), floor(K U / N))` of `units`: disjoint, contiguous,
    /// covering `0..units` in order over K = 1..N, sizes differing by at most one.
    pub fn range(self, units: usize) -> Range<usize> {
        let at = |k: usize| ((k as u128 * units as u128) / self.n as u128) as usize;
        at(self.k - 1)..at(self.k)
    }
}

/// The help text shared by every `--shard` option.
pub const SHARD_HELP: &str = "Compute only part K of N (1-based) of the request's work units, contiguous in output order; every shard prints the CSV header, so join as `head -n 1 part-1.csv; tail -q -n +2 part-{1..N}.csv` (CSV only; an empty shard prints only the header)";

/// Checks the size of a request and picks this run's units: `total` units in all, of which
/// the shard computes `shard.range(total)`; at most `cap` per run. `what` names the units
/// and how the total arises, e.g. `"curves (3 delta x 4 d)"`.
pub fn plan(
    total: usize,
    shard: Shard,
    cap: usize,
    what: &str,
) -> Result<Range<usize>, UsageError> {
    if total > MAX_TOTAL_UNITS {
        return Err(UsageError(format!(
            "the request has {total} {what}; at most {MAX_TOTAL_UNITS} are accepted even with --shard: use shorter lists"
        )));
    }
    let range = shard.range(total);
    if range.len() > cap {
        let need = total.div_ceil(cap);
        return Err(UsageError(format!(
            "the request has {total} {what}, {} in this run; at most {cap} per run are accepted: split it with --shard K/N, N >= {need}",
            range.len()
        )));
    }
    Ok(range)
}

/// Checks before any work that a shard is CSV without a picture (only CSV parts join into
/// the whole run).
pub fn check_shard(shard: Option<Shard>, csv: bool, svg: bool) -> Result<(), UsageError> {
    if shard.is_some() && (!csv || svg) {
        return Err(UsageError(
            "--shard needs --format csv and no --svg: only CSV parts join into the whole run (draw the picture from an unsharded run)".into(),
        ));
    }
    Ok(())
}

/// Output format of the row-producing commands (`boundary`, `amax`): CSV rows with a header,
/// or a JSON array of objects with the same keys.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum RowFormat {
    /// Comma-separated values with a header line.
    Csv,
    /// One JSON object per row.
    Json,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lists_and_ranges() {
        assert_eq!(parse_list("0,0.25, 0.5").unwrap(), vec![0.0, 0.25, 0.5]);
        assert_eq!(
            parse_list("0:1:5").unwrap(),
            vec![0.0, 0.25, 0.5, 0.75, 1.0]
        );
        assert_eq!(parse_list("2:2:1").unwrap(), vec![2.0]);
        for bad in [
            "",
            "a",
            "1,,2",
            "1:0:3",
            "0:1:0",
            "0:1",
            "nan",
            "inf",
            "0:1:1e9",
            "-1e308:1e308:3",
        ] {
            assert!(parse_list(bad).is_err(), "{bad}");
        }
    }

    /// Decimal steps come out as typed; steps that are not decimal keep their digits.
    #[test]
    fn ranges_print_as_typed() {
        let v = parse_list("0:1:11").unwrap();
        let printed: Vec<String> = v.iter().map(|x| x.to_string()).collect();
        assert_eq!(
            printed,
            [
                "0", "0.1", "0.2", "0.3", "0.4", "0.5", "0.6", "0.7", "0.8", "0.9", "1"
            ]
        );
        assert_eq!(parse_list("0:14:8").unwrap()[7], 14.0);
        assert_eq!(parse_list("0:0.7:8").unwrap()[3], 0.3);
        // 1/3 is no decimal: every digit of the nearest f64 stays
        assert_eq!(parse_list("0:1:4").unwrap()[1], 1.0 / 3.0);
        assert_eq!(parse_list("0:1:4").unwrap()[2], 2.0 / 3.0);
    }

    /// Shards are disjoint, contiguous, in order, and cover every unit, for N above and
    /// below the number of units.
    #[test]
    fn shards_partition_the_units() {
        for units in [0, 1, 2, 5, 7, 100] {
            for n in [1, 2, 3, 7, 200] {
                let mut next = 0;
                for k in 1..=n {
                    let r = Shard { k, n }.range(units);
                    assert_eq!(r.start, next, "{units} {k}/{n}");
                    assert!(r.len() <= units.div_ceil(n));
                    next = r.end;
                }
                assert_eq!(next, units);
            }
        }
        assert!(shard("0/3").is_err() && shard("4/3").is_err() && shard("1").is_err());
        assert_eq!(shard("2/3").unwrap(), Shard { k: 2, n: 3 });
    }
}

/// Which mass of a compliant transmission the encoder reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum EncoderArg {
    Motor,
    Handle,
}

/// The loop elements a device may have, in physical units (flags shared by the commands
/// that model them).
#[derive(Debug, Clone, clap::Args)]
pub struct ElementArgs {
    /// Operator's hand holding the handle: mass in kg (physical units only).
    #[arg(long = "hand-mass", value_parser = span, allow_hyphen_values = true, help_heading = "Loop elements (physical units)")]
    hand_mass: Option<Span>,
    /// Operator's hand: damping in N s/m.
    #[arg(long = "hand-damping", value_parser = span, allow_hyphen_values = true, help_heading = "Loop elements (physical units)")]
    hand_damping: Option<Span>,
    /// Operator's hand: stiffness in N/m.
    #[arg(long = "hand-stiffness", value_parser = span, allow_hyphen_values = true, help_heading = "Loop elements (physical units)")]
    hand_stiffness: Option<Span>,
    /// First-order low-pass on the wall's velocity estimate: cutoff in Hz (at most Nyquist).
    #[arg(long = "velocity-filter-cutoff", value_parser = span, allow_hyphen_values = true, conflicts_with = "velocity_filter_samples", help_heading = "Loop elements (physical units)")]
    velocity_filter_cutoff: Option<Span>,
    /// Moving average of the wall's velocity estimate over this many samples.
    #[arg(
        long = "velocity-filter-samples",
        help_heading = "Loop elements (physical units)"
    )]
    velocity_filter_samples: Option<usize>,
    /// Compliant transmission: the handle's mass in kg (below --mass; the motor side is the rest).
    #[arg(long = "handle-mass", value_parser = span, allow_hyphen_values = true, requires = "transmission_stiffness", help_heading = "Loop elements (physical units)")]
    handle_mass: Option<Span>,
    /// Compliant transmission: coupling stiffness in N/m.
    #[arg(long = "transmission-stiffness", value_parser = span, allow_hyphen_values = true, requires = "handle_mass", help_heading = "Loop elements (physical units)")]
    transmission_stiffness: Option<Span>,
    /// Compliant transmission: coupling damping in N s/m (default 0).
    #[arg(long = "transmission-damping", value_parser = span, allow_hyphen_values = true, requires = "handle_mass", help_heading = "Loop elements (physical units)")]
    transmission_damping: Option<Span>,
    /// Compliant transmission: where the encoder sits (default motor). The device's --damping
    /// acts on the motor side.
    #[arg(
        long,
        value_enum,
        requires = "handle_mass",
        help_heading = "Loop elements (physical units)"
    )]
    encoder: Option<EncoderArg>,
    /// Actuator lag (amplifier, current loop): time constant in s.
    #[arg(long = "actuator-time-constant", value_parser = span, allow_hyphen_values = true, help_heading = "Loop elements (physical units)")]
    actuator_time_constant: Option<Span>,
    /// The hand never lets go of the handle: amax, table and scene leave the free device
    /// (no hand) out of the set. Without it, a named hand makes the set the device with the
    /// hand and without it.
    #[arg(
        long = "always-gripped",
        help_heading = "Loop elements (physical units)"
    )]
    always_gripped: bool,
}

impl ElementArgs {
    /// The loop of `device` with the elements named (none: the paper's loop); a value the
    /// library refuses is reported with the flag that gave it.
    pub fn loop_on(&self, device: &Device) -> anyhow::Result<Loop> {
        Loop::physical(device, &self.named()).map_err(|e| match element_flag(&e) {
            Some(flag) => anyhow::Error::new(e).context(flag),
            None => e.into(),
        })
    }

    /// The elements named on the command line.
    pub fn named(&self) -> PhysicalElements {
        let mut e = PhysicalElements::default();
        let lo = |s: Option<Span>| s.map(|s| s.lo);
        e.hand_mass = lo(self.hand_mass);
        e.hand_damping = lo(self.hand_damping);
        e.hand_stiffness = lo(self.hand_stiffness);
        e.handle_mass = lo(self.handle_mass);
        e.transmission_stiffness = lo(self.transmission_stiffness);
        e.transmission_damping = lo(self.transmission_damping);
        e.encoder = self.encoder.map(|x| match x {
            EncoderArg::Motor => Encoder::Motor,
            EncoderArg::Handle => Encoder::Handle,
        });
        e.actuator_time_constant = lo(self.actuator_time_constant);
        e.velocity_filter_cutoff = lo(self.velocity_filter_cutoff);
        e.velocity_filter_samples = self.velocity_filter_samples;
        e
    }
}

impl ElementArgs {
    /// The element parameters given as intervals `LO..HI` (the loop of [`Self::named`] holds
    /// `LO`).
    pub fn intervals(&self) -> Vec<(Param, f64, f64)> {
        [
            (Param::HandMass, self.hand_mass),
            (Param::HandDamping, self.hand_damping),
            (Param::HandStiffness, self.hand_stiffness),
            (Param::HandleMass, self.handle_mass),
            (Param::TransmissionStiffness, self.transmission_stiffness),
            (Param::TransmissionDamping, self.transmission_damping),
            (Param::ActuatorTimeConstant, self.actuator_time_constant),
            (Param::VelocityFilterCutoff, self.velocity_filter_cutoff),
        ]
        .into_iter()
        .filter_map(|(p, s)| s.and_then(Span::interval).map(|(lo, hi)| (p, lo, hi)))
        .collect()
    }

    /// Refuses intervals and --always-gripped where `command` answers for one device only.
    pub fn one_device(&self, command: &str) -> Result<(), UsageError> {
        if !self.intervals().is_empty() {
            return Err(UsageError(format!(
                "{command} answers for one device: give each element value as one number (LO..HI sets are for amax, table and check)"
            )));
        }
        Ok(())
    }

    /// The set of devices `device` (its damping and delay those of one row) with the elements
    /// named, the intervals of `extra` (the device's own) and of the element flags, and the
    /// hand let go unless --always-gripped; `None` when that set is the one device.
    pub fn device_set(
        &self,
        device: &Device,
        extra: &[(Param, f64, f64)],
    ) -> anyhow::Result<Option<DeviceSet>> {
        let mut set = DeviceSet::new(device, &self.named())?;
        for &(p, lo, hi) in extra.iter().chain(&self.intervals()) {
            set = set
                .with_interval(p, lo, hi)
                .with_context(|| format!("the {} interval", p.name()))?;
        }
        let set = set.always_gripped(self.always_gripped);
        Ok((!set.is_single()).then_some(set))
    }
}

/// The flag that gives the element value an error names (in physical or normalized form).
fn element_flag(e: &stabound::Error) -> Option<&'static str> {
    let stabound::Error::InvalidParameter { name, .. } = e else {
        return None;
    };
    Some(match *name {
        "hand mass" | "hand mass ratio" => "--hand-mass",
        "hand damping" => "--hand-damping",
        "hand stiffness" => "--hand-stiffness",
        "handle mass" | "handle mass ratio" => "--handle-mass",
        "transmission stiffness" => "--transmission-stiffness",
        "transmission damping" => "--transmission-damping",
        "actuator time constant" => "--actuator-time-constant",
        "velocity filter cutoff" | "velocity filter pole" => "--velocity-filter-cutoff",
        "velocity filter samples" => "--velocity-filter-samples",
        _ => return None,
    })
}
