//! Argument types shared by the subcommands: lists, finite numbers, the grid of plants
//! (normalized or physical), the beta limits of alpha_max searches, shards and output paths.

use anyhow::Context;
use std::ops::Range;

use clap::ValueEnum;
use stabound::amax::{AmaxOptions, DEFAULT_THETA_TOL};
use stabound::elements::list::{self, Accepts, Form, PARAMS, Param, Value};
use stabound::elements::{Loop, PhysicalElements};
use stabound::params::{Delay, Device, Plant};
use stabound::request::{self, DampingLimits, DeviceInputs, Given, Input, Takes};
use stabound::robust::{self, DeviceSet, Quantity};

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
            // a range 0:1:11 means 0.3, not 0.30000000000000004
            .map(|i| stabound::export::text::as_typed(start + step * i as f64))
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

/// The prefix of a finite set of devices: `one-of:1,2,3` (or `one-of:START:STOP:COUNT`) is
/// one set whose members take each value, beside `LO..HI` for every value between; a bare
/// LIST stays one row per value where a flag takes rows.
pub const ONE_OF: &str = "one-of:";

/// Reads `one-of:LIST` (a finite set of devices); `None` when `t` is none.
fn one_of(t: &str) -> Option<Result<Vec<f64>, String>> {
    let rest = t.trim().strip_prefix(ONE_OF)?;
    Some(parse_list(rest).map_err(|e| format!("'{t}' is no set of values ({e})")))
}

/// A device parameter's LIST (several devices, one row each), one interval `LO..HI` or one
/// finite set `one-of:LIST` (one set of devices, read by the element list's interval form
/// and [`ONE_OF`]).
#[derive(Debug, Clone, PartialEq)]
pub enum Spread {
    /// Values, one row each.
    List(Vec<f64>),
    /// One set of devices: every value from the low end to the high end.
    Interval(f64, f64),
    /// One set of devices: each of these values.
    OneOf(Vec<f64>),
}

impl Spread {
    /// The values of the rows: the list, or the set's smallest value (its reference).
    fn values(&self) -> Vec<f64> {
        match self {
            Spread::List(v) => v.clone(),
            _ => vec![self.low()],
        }
    }

    /// The first row's value, or the set's smallest (its reference member's).
    pub fn low(&self) -> f64 {
        match self {
            Spread::List(v) => v.first().copied().unwrap_or(f64::NAN),
            &Spread::Interval(lo, _) => lo,
            Spread::OneOf(v) => v.iter().copied().fold(f64::INFINITY, f64::min),
        }
    }

    /// The set of devices this gives, when it gives one (an interval or a finite set).
    pub fn set(&self) -> Option<robust::Spread> {
        match self {
            Spread::List(_) => None,
            &Spread::Interval(lo, hi) => Some(robust::Spread::Interval(lo, hi)),
            Spread::OneOf(v) => Some(robust::Spread::Values(v.clone())),
        }
    }
}

impl From<List> for Spread {
    fn from(l: List) -> Self {
        Spread::List(l.0)
    }
}

/// Reads `one-of:LIST`, `LO..HI` of `name` (the element list's interval form), else a LIST.
fn spread_of(name: &str, t: &str) -> Result<Spread, String> {
    if let Some(values) = one_of(t) {
        return values.map(Spread::OneOf);
    }
    match list::read_interval(t, name) {
        None => parse_list(t).map(Spread::List),
        Some(Ok(Form::Interval(lo, hi))) => Ok(Spread::Interval(lo, hi)),
        Some(Ok(Form::One(Value::Number(x)))) => Ok(Spread::List(vec![x])),
        Some(Ok(_)) => Err(format!("'{t}' is not a number ({name})")),
        Some(Err(e)) => Err(e.to_string()),
    }
}

/// clap value parser of the damping: a LIST, or `LO..HI` or `one-of:LIST` (one set of
/// devices).
pub fn damping_spread(t: &str) -> Result<Spread, String> {
    spread_of("damping", t)
}

/// clap value parser of the delays: a LIST, or `LO..HI` or `one-of:LIST` (one set of
/// devices).
pub fn delay_spread(t: &str) -> Result<Spread, String> {
    spread_of("delay", t)
}

/// clap value parser of one device value: one number, or `LO..HI` or `one-of:LIST` (one
/// set of devices).
pub fn one_or_set(t: &str) -> Result<Spread, String> {
    match (one_of(t), list::read_interval(t, "value")) {
        (None, None) => finite(t).map(|m| Spread::List(vec![m])),
        _ => spread_of("value", t),
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

/// clap value parser of a [`Span`]: a finite number, or `LO..HI` (the element list's
/// interval form).
pub fn span(t: &str) -> Result<Span, String> {
    match list::read_interval(t, "value") {
        None => finite(t).map(|v| Span { lo: v, hi: v }),
        Some(Ok(Form::Interval(lo, hi))) => Ok(Span { lo, hi }),
        Some(Ok(Form::One(Value::Number(v)))) => Ok(Span { lo: v, hi: v }),
        Some(Ok(_)) => Err(format!("'{t}' is not a number")),
        Some(Err(e)) => Err(e.to_string()),
    }
}

/// clap value parser of one finite number.
pub fn finite(t: &str) -> Result<f64, String> {
    let set = if t.contains("..") {
        Some("an interval (LO..HI)")
    } else {
        t.trim()
            .starts_with(ONE_OF)
            .then_some("a finite set (one-of:LIST)")
    };
    if let Some(set) = set {
        return Err(format!(
            "'{t}' is {set}, which this option does not take: give one number (sets of devices are answered by check, amax, table, boundary and scene)"
        ));
    }
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
    /// Device mass m in kg (LO..HI or one-of:A,B: a set of devices, normalized by the
    /// smallest).
    #[arg(long, value_parser = one_or_set, allow_hyphen_values = true)]
    pub mass: Option<Spread>,
    /// Sampling period T in s.
    #[arg(long, value_parser = finite, allow_hyphen_values = true)]
    pub period: Option<f64>,
    /// Physical damping b in N s/m (LIST, one row each; or LO..HI or one-of:LIST: one set of
    /// devices).
    #[arg(long, value_parser = damping_spread, allow_hyphen_values = true)]
    pub damping: Option<Spread>,
    /// Delays in s (LIST, one row each; or LO..HI or one-of:LIST: one set of devices).
    #[arg(long, value_parser = delay_spread, allow_hyphen_values = true, conflicts_with = "delay_samples")]
    pub delay: Option<Spread>,
    /// Delays in sampling periods (LIST, one row each; or LO..HI or one-of:LIST: one set of
    /// devices, e.g. 1..3 or one-of:1,2,3).
    #[arg(long = "delay-samples", value_parser = delay_spread, allow_hyphen_values = true)]
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
    /// The device parameters given as sets, `LO..HI` or `one-of:LIST` (the rows hold the
    /// smallest value).
    pub sets: Vec<(Quantity, robust::Spread)>,
}

impl GridArgs {
    /// Resolves the request to normalized `delta` and `d` lists, each value validated as a
    /// plant parameter.
    pub fn resolve(self) -> anyhow::Result<Grid> {
        let delay = self.delay.as_ref().or(self.delay_samples.as_ref());
        let sets: Vec<(Quantity, robust::Spread)> = [
            (Quantity::Mass, self.mass.as_ref()),
            (Quantity::Damping, self.damping.as_ref()),
            (Quantity::Delay, delay),
        ]
        .into_iter()
        .filter_map(|(q, s)| s?.set().map(|s| (q, s)))
        .collect();
        // the library decides the form and refuses mixed or missing inputs
        let given = DeviceInputs {
            delta: self.delta.map(Spread::from),
            d: self.d.map(Spread::from),
            mass: self.mass,
            period: self.period.map(|t| Spread::List(vec![t])),
            damping: self.damping,
            delay: self.delay,
            delay_samples: self.delay_samples,
            ..Default::default()
        }
        .resolve(Takes::Plants)
        .map_err(as_flags)?;
        let grid = match given {
            Given::Physical {
                mass,
                period,
                damping,
                delay,
                in_samples,
                ..
            } => {
                let (m, t, bs) = (mass.values()[0], period.values()[0], damping.values());
                let delays: Vec<Delay> = delay
                    .values()
                    .into_iter()
                    .map(|v| request::delay(v, in_samples))
                    .collect();
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
                    sets,
                }
            }
            Given::Normalized { delta, d, .. } => Grid {
                deltas: delta.values(),
                ds: d.values(),
                device: None,
                physical: (Vec::new(), Vec::new()),
                sets,
            },
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
    /// Only walls with nonnegative virtual damping (B >= 0): the same as --beta-min 0.
    #[arg(long = "nonnegative-wall-damping", conflicts_with_all = ["beta_min", "wall_damping_min"])]
    nonnegative_wall_damping: bool,
    /// Refinement tolerance of the critical root's angle theta, in radians, in [1e-15, 1e-2]
    /// (the cost hardly depends on it); for a loop with elements too.
    #[arg(long = "theta-tol", default_value_t = DEFAULT_THETA_TOL, value_parser = finite, allow_hyphen_values = true)]
    theta_tol: f64,
}

impl SearchArgs {
    /// The validated options; `device` is `(mass, period)` when the device was given in
    /// physical units, which the wall-damping limits need (`beta = B T / m`).
    pub fn options(&self, device: Option<(f64, f64)>) -> anyhow::Result<AmaxOptions> {
        let opts = AmaxOptions::new(self.theta_tol).context("--theta-tol")?;
        let limits = DampingLimits {
            beta_min: self.beta_min,
            beta_max: self.beta_max,
            wall_damping_min: self.wall_damping_min,
            wall_damping_max: self.wall_damping_max,
        };
        let (lo, hi) = limits.resolve(device).map_err(as_flags)?;
        // --nonnegative-wall-damping: a lower end of 0 where none is given
        let lo = match lo {
            None if self.nonnegative_wall_damping => Some(0.0),
            lo => lo,
        };
        Ok(opts.with_beta_limits(lo, hi)?)
    }

    /// Whether the lower and the upper damping limit were given in N s/m
    /// (`--wall-damping-min`, `--wall-damping-max`).
    pub fn physical_limits(&self) -> (bool, bool) {
        (
            self.wall_damping_min.is_some(),
            self.wall_damping_max.is_some(),
        )
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

    /// `LO..HI` is one set of devices; a LIST stays rows; equal ends are one value; an
    /// inverted or non-numeric interval is refused.
    #[test]
    fn intervals_and_lists() {
        assert_eq!(delay_spread("1..3").unwrap(), Spread::Interval(1.0, 3.0));
        assert_eq!(delay_spread("1,2").unwrap(), Spread::List(vec![1.0, 2.0]));
        assert_eq!(damping_spread("2..2").unwrap(), Spread::List(vec![2.0]));
        assert_eq!(span("0.1").unwrap(), Span { lo: 0.1, hi: 0.1 });
        assert_eq!(span("0.09..0.11").unwrap().interval(), Some((0.09, 0.11)));
        for bad in ["3..1", "1..x", "..2", "1..inf"] {
            assert!(delay_spread(bad).is_err() && span(bad).is_err(), "{bad}");
        }
    }

    /// `one-of:LIST` is one finite set (a comma list or a range, in the order given; its
    /// smallest value the rows' and the set's reference); walls and single numbers refuse it.
    #[test]
    fn finite_sets() {
        let s = delay_spread("one-of:3,1").unwrap();
        assert_eq!(s, Spread::OneOf(vec![3.0, 1.0]));
        assert_eq!((s.low(), s.values()), (1.0, vec![1.0]));
        assert_eq!(s.set(), Some(robust::Spread::Values(vec![3.0, 1.0])));
        assert_eq!(
            one_or_set("one-of:0:1:3").unwrap(),
            Spread::OneOf(vec![0.0, 0.5, 1.0])
        );
        assert_eq!(one_or_set("0.5").unwrap().set(), None);
        for bad in ["one-of:", "one-of:1,,2", "one-of:2:1:3", "one-of:1..2"] {
            assert!(one_or_set(bad).is_err(), "{bad}");
        }
        assert!(span("one-of:1,2").is_err());
        assert!(finite("one-of:1,2").unwrap_err().contains("finite set"));
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

/// The loop elements a device may have, in physical units: one flag per linear parameter of
/// the library's element list (`stabound::elements::list`), whose name, help and value check
/// come from the list.
#[derive(Debug, Clone, Default)]
pub struct ElementArgs {
    named: PhysicalElements,
    /// The parameters given as sets, `LO..HI` or `one-of:LIST` (`named` holds the smallest
    /// value).
    sets: Vec<(Quantity, robust::Spread)>,
    /// `--always-gripped`: the free device is no member of a set with a hand.
    always_gripped: bool,
}

/// The quantizers and dry friction a device may have, in physical units: one flag per
/// nonlinear parameter of the library's element list; each modelled only when named, and
/// then the command adds the buzz verdict.
#[derive(Debug, Clone, Default)]
pub struct NonlinearArgs {
    named: PhysicalElements,
}

/// One element flag's value or interval, read by the list, or its finite set
/// `one-of:LIST` (each value checked by the list).
#[derive(Debug, Clone)]
enum ElementValue {
    Form(Form),
    OneOf(Vec<f64>),
}

impl ElementValue {
    /// Reads `t` as parameter `p`'s value, interval or finite set.
    fn read(p: &Param, t: &str) -> Result<Self, String> {
        let Some(values) = one_of(t) else {
            return p.read_form(t).map(Self::Form).map_err(|e| e.to_string());
        };
        if !matches!(p.accepts, Accepts::NonNegative | Accepts::Positive) {
            return Err(format!("'{t}': the {} takes {}", p.name, p.expects()));
        }
        let values = values?;
        for &v in &values {
            p.accept(Value::Number(v)).map_err(|e| e.to_string())?;
        }
        Ok(Self::OneOf(values))
    }
}

/// The flag that keeps the free device out of a set with a hand.
const ALWAYS_GRIPPED: &str = "always-gripped";

const ELEMENT_HEADING: &str = "Loop elements (physical units)";
const NONLINEAR_HEADING: &str = "Quantizers and friction (physical units)";

/// The value names of the element flags (`HAND_MASS`), in the list's order.
static VALUE_NAMES: std::sync::LazyLock<Vec<String>> =
    std::sync::LazyLock::new(|| PARAMS.iter().map(|p| p.keyword.to_uppercase()).collect());

/// The flag of one element parameter.
fn element_arg(i: usize, p: &'static Param) -> clap::Arg {
    let check = move |s: &str| ElementValue::read(p, s);
    let heading = if p.element.nonlinear() {
        NONLINEAR_HEADING
    } else {
        ELEMENT_HEADING
    };
    let mut arg = clap::Arg::new(p.keyword)
        .long(p.flag)
        .help(p.help)
        .help_heading(heading)
        .value_name(VALUE_NAMES[i].as_str())
        .allow_hyphen_values(true);
    arg = match p.accepts {
        Accepts::Choice(names) => arg.value_parser({
            use clap::builder::TypedValueParser;
            clap::builder::PossibleValuesParser::new(names).try_map(move |s: String| check(&s))
        }),
        _ => arg.value_parser(check),
    };
    for k in p.requires.map_or(&[][..], |r| r.0) {
        arg = arg.requires(*k);
    }
    for k in p.conflicts.map_or(&[][..], |c| c.0) {
        arg = arg.conflicts_with(*k);
    }
    arg
}

/// The flags of the parameters whose element is (`nonlinear`) or is not nonlinear.
fn element_args(cmd: clap::Command, nonlinear: bool) -> clap::Command {
    cmd.args(
        PARAMS
            .iter()
            .enumerate()
            .filter(|(_, p)| p.element.nonlinear() == nonlinear)
            .map(|(i, p)| element_arg(i, p)),
    )
}

impl clap::FromArgMatches for ElementArgs {
    fn from_arg_matches(m: &clap::ArgMatches) -> Result<Self, clap::Error> {
        let mut named = PhysicalElements::default();
        let mut sets = Vec::new();
        for p in PARAMS.iter().filter(|p| !p.element.nonlinear()) {
            let set = match m.get_one::<ElementValue>(p.keyword) {
                Some(ElementValue::Form(Form::One(v))) => {
                    p.set(&mut named, *v);
                    continue;
                }
                Some(&ElementValue::Form(Form::Interval(lo, hi))) => {
                    robust::Spread::Interval(lo, hi)
                }
                Some(ElementValue::OneOf(v)) => robust::Spread::Values(v.clone()),
                Some(ElementValue::Form(_)) | None => continue,
            };
            p.set(&mut named, Value::Number(set.low()));
            let q = Quantity::element(p.keyword)
                .map_err(|e| clap::Error::raw(clap::error::ErrorKind::ValueValidation, e))?;
            sets.push((q, set));
        }
        Ok(Self {
            named,
            sets,
            always_gripped: m.get_flag(ALWAYS_GRIPPED),
        })
    }

    fn update_from_arg_matches(&mut self, m: &clap::ArgMatches) -> Result<(), clap::Error> {
        *self = Self::from_arg_matches(m)?;
        Ok(())
    }
}

impl clap::Args for ElementArgs {
    fn augment_args(cmd: clap::Command) -> clap::Command {
        // each number also reads as a set of devices, which the help says once per flag
        let sets = PARAMS.iter().filter(|p| {
            !p.element.nonlinear() && matches!(p.accepts, Accepts::NonNegative | Accepts::Positive)
        });
        let cmd = sets.fold(element_args(cmd, false), |cmd, p| {
            cmd.mut_arg(p.keyword, |a| {
                a.help(format!(
                    "{} Or LO..HI, or one-of:A,B,C: a set of devices (check, amax, table, boundary).",
                    p.help
                ))
            })
        });
        cmd.arg(
            clap::Arg::new(ALWAYS_GRIPPED)
                .long(ALWAYS_GRIPPED)
                .action(clap::ArgAction::SetTrue)
                .help("The hand never lets go of the handle: amax and table leave the free device (no hand) out of the set of devices. Without it, a named hand makes the set the device with the hand and without it.")
                .help_heading(ELEMENT_HEADING),
        )
    }

    fn augment_args_for_update(cmd: clap::Command) -> clap::Command {
        Self::augment_args(cmd)
    }
}

impl clap::FromArgMatches for NonlinearArgs {
    fn from_arg_matches(m: &clap::ArgMatches) -> Result<Self, clap::Error> {
        let mut named = PhysicalElements::default();
        for p in PARAMS.iter().filter(|p| p.element.nonlinear()) {
            match m.get_one::<ElementValue>(p.keyword) {
                Some(ElementValue::Form(Form::One(v))) => p.set(&mut named, *v),
                Some(_) => {
                    return Err(clap::Error::raw(
                        clap::error::ErrorKind::ValueValidation,
                        format!(
                            "--{} takes one number: the buzz simulation answers for one device\n",
                            p.flag
                        ),
                    ));
                }
                _ => {}
            }
        }
        Ok(Self { named })
    }

    fn update_from_arg_matches(&mut self, m: &clap::ArgMatches) -> Result<(), clap::Error> {
        *self = Self::from_arg_matches(m)?;
        Ok(())
    }
}

impl clap::Args for NonlinearArgs {
    fn augment_args(cmd: clap::Command) -> clap::Command {
        element_args(cmd, true)
    }

    fn augment_args_for_update(cmd: clap::Command) -> clap::Command {
        Self::augment_args(cmd)
    }
}

impl NonlinearArgs {
    /// The quantizers and friction named on the command line.
    pub fn named(&self) -> stabound::buzz::Nonlinear {
        stabound::buzz::Nonlinear::from(&self.named)
    }
}

impl ElementArgs {
    /// The loop of `device` with the elements named (none: the paper's loop); a value the
    /// library refuses is reported with the flag that gave it.
    pub fn loop_on(&self, device: &Device) -> anyhow::Result<Loop> {
        Loop::physical(device, &self.named).map_err(flagged)
    }

    /// The elements named on the command line (an interval's low end for a parameter given
    /// as one).
    pub fn named(&self) -> PhysicalElements {
        self.named
    }

    /// Refuses sets of devices where `command` answers for one device only.
    pub fn one_device(&self, command: &str) -> Result<(), UsageError> {
        if let Some((q, _)) = self.sets.first() {
            return Err(UsageError(format!(
                "{command} answers for one device: give the {} as one number (sets, LO..HI or one-of:LIST, are for amax, table and check)",
                q.name()
            )));
        }
        Ok(())
    }

    /// The set of devices `device` (its damping and delay those of one row) with the elements
    /// named, the device's own sets `extra` and the element flags' sets, and the
    /// hand let go unless --always-gripped (`let_go`: whether the command lets it go);
    /// `None` when that set is the one device, unless a hand the command could let go is
    /// held (the set then says it is always gripped).
    pub fn device_set(
        &self,
        device: &Device,
        extra: &[(Quantity, robust::Spread)],
        let_go: bool,
    ) -> anyhow::Result<Option<DeviceSet>> {
        let sets: Vec<_> = extra.iter().chain(&self.sets).cloned().collect();
        request::device_set(device, &self.named, &sets, self.always_gripped, let_go)
            .map_err(flagged)
    }
}

/// A library error, with the element flag that gave the value it names (physical or
/// normalized form) in front.
pub fn flagged(e: stabound::Error) -> anyhow::Error {
    match list::named_in(&e) {
        Some(p) => anyhow::Error::new(e).context(format!("--{}", p.flag)),
        None => e.into(),
    }
}

/// An input of the library's request layer as its flag (`--wall-damping-min`).
pub fn flag(i: Input) -> String {
    format!("--{}", i.keyword().replace('_', "-"))
}

/// A library error as the command line says it: a refused request with its inputs spelled
/// as flags, bad input (exit 2).
pub fn as_flags(e: stabound::Error) -> anyhow::Error {
    match e {
        stabound::Error::Request(r) => UsageError(r.message(&flag)).into(),
        e => e.into(),
    }
}

/// The library's refusal of `what` (loop elements, quantizers) given with a normalized
/// device, in flag names.
pub fn needs_physical(what: &'static str) -> anyhow::Error {
    as_flags(
        request::RequestError::NeedsPhysical {
            what,
            takes: Takes::Plants,
        }
        .into(),
    )
}

/// The velocity filter's flags alone (for commands that model only a filter), each from the
/// library's element list as [`ElementArgs`]' are.
#[derive(Debug, Clone, Default)]
pub struct FilterArgs {
    named: PhysicalElements,
}

/// The element list's velocity-filter parameters with their places in the list.
fn filter_params() -> impl Iterator<Item = (usize, &'static Param)> {
    PARAMS
        .iter()
        .enumerate()
        .filter(|(_, p)| p.element == list::Element::VelocityFilter)
}

impl clap::FromArgMatches for FilterArgs {
    fn from_arg_matches(m: &clap::ArgMatches) -> Result<Self, clap::Error> {
        let mut named = PhysicalElements::default();
        for (_, p) in filter_params() {
            match m.get_one::<ElementValue>(p.keyword) {
                Some(ElementValue::Form(Form::One(v))) => p.set(&mut named, *v),
                Some(_) => {
                    return Err(clap::Error::raw(
                        clap::error::ErrorKind::ValueValidation,
                        format!(
                            "--{}: give one value here, not a set (LO..HI or one-of:LIST)\n",
                            p.flag
                        ),
                    ));
                }
                _ => {}
            }
        }
        Ok(Self { named })
    }

    fn update_from_arg_matches(&mut self, m: &clap::ArgMatches) -> Result<(), clap::Error> {
        *self = Self::from_arg_matches(m)?;
        Ok(())
    }
}

impl clap::Args for FilterArgs {
    fn augment_args(cmd: clap::Command) -> clap::Command {
        cmd.args(filter_params().map(|(i, p)| element_arg(i, p)))
    }

    fn augment_args_for_update(cmd: clap::Command) -> clap::Command {
        Self::augment_args(cmd)
    }
}

impl FilterArgs {
    /// The filter parameters named on the command line.
    pub fn named(&self) -> PhysicalElements {
        self.named
    }
}
