//! The report of one wall's stability test, as text for a reader and as JSON for a program:
//! the verdict, the spectral radius and every root (when they were computed), the normalized
//! parameters, the loop elements modelled and (when the wall was given in physical units)
//! the device.

use serde_json::json;

use crate::buzz::{BuzzReport, DescribingFunction, Start};
use crate::elements::{Loop, list};
use crate::params::{Device, Normalized};
use crate::stability::{Analysis, Decision, MarginalReason, Verdict};

/// The spectral radius to report with a verdict, consistent with it: the analysis's own,
/// except for a verdict proven marginal ([`MarginalReason::WithinMargin`]: a root within
/// `band` of the unit circle and none beyond it), where the radius is known to lie in
/// `[1 - band, 1 + band]` and a computed one outside that interval is brought to its nearest
/// end. An undecided marginal verdict ([`MarginalReason::Undecided`]) keeps the computed
/// radius, which the text report then explains: near a multiple root on the circle (at
/// `alpha = beta = delta = 0` the root `z = 1` is double) eigenvalues split it by about the
/// square root of the rounding, `1e-8`, far wider than the default band.
///
/// ```
/// use stabound::export::report::shown_radius;
/// use stabound::params::{Plant, Wall};
/// use stabound::stability::{Checker, Options, Verdict};
///
/// let c = Checker::new(&Plant::new(0.5, 1.0)?, Options::default())?;
/// let an = c.analyze(&Wall::new(0.1, 0.3)?)?;
/// assert_eq!(an.verdict, Verdict::Stable);
/// assert_eq!(shown_radius(&an, 1e-9), an.spectral_radius);
/// # Ok::<(), stabound::Error>(())
/// ```
pub fn shown_radius(a: &Analysis, band: f64) -> f64 {
    shown_decided_radius(a.verdict, a.reason, a.spectral_radius, band)
}

/// [`shown_radius`] for a verdict, its reason and the computed radius, as
/// [`Checker::decide_with_radius`](crate::stability::Checker::decide_with_radius) returns
/// them.
///
/// ```
/// use stabound::export::report::shown_decided_radius;
/// use stabound::stability::{MarginalReason, Verdict};
///
/// // a proven marginal verdict brings the radius into its band
/// let within = Some(MarginalReason::WithinMargin);
/// assert_eq!(shown_decided_radius(Verdict::Marginal, within, 1.5, 1e-9), 1.0 + 1e-9);
/// assert_eq!(shown_decided_radius(Verdict::Unstable, None, 1.5, 1e-9), 1.5);
/// ```
pub fn shown_decided_radius(
    verdict: Verdict,
    reason: Option<MarginalReason>,
    radius: f64,
    band: f64,
) -> f64 {
    if verdict == Verdict::Marginal && reason == Some(MarginalReason::WithinMargin) {
        radius.clamp(1.0 - band, 1.0 + band)
    } else {
        radius
    }
}

/// The note of a text report on a marginal verdict whose computed radius lies outside the
/// band (empty otherwise).
fn radius_note(a: &Analysis, band: f64) -> String {
    if a.verdict != Verdict::Marginal || (a.spectral_radius - 1.0).abs() <= band {
        return String::new();
    }
    match a.reason {
        Some(MarginalReason::WithinMargin) => format!(
            "(the verdict proves the radius within the band; the computed roots reach |z| = {}, split by the rounding of a multiple root on the circle)\n",
            short(a.spectral_radius)
        ),
        _ => "(undecided: rounding leaves a root on either side of the band's circles, so the radius above is known only to the roots' accuracy, about 1e-8 near a multiple root on the circle; the verdict is marginal rather than a guess)\n".into(),
    }
}

/// What [`check_text`] and [`check_json`] report on.
#[derive(Debug, Clone, Copy)]
pub struct CheckReport<'a> {
    /// The verdict, the method that reached it and why a marginal verdict is marginal.
    pub decision: Decision,
    /// The degree of the characteristic polynomial.
    pub degree: usize,
    /// The spectral radius and the roots ([`Checker::analyze`](crate::stability::Checker::analyze)),
    /// reported only when given: they cost the roots, most of the time at long delays, where
    /// the verdict needs none.
    pub analysis: Option<&'a Analysis>,
    /// The four normalized parameters of the wall and plant.
    pub params: &'a Normalized,
    /// The marginal band the verdict used.
    pub band: f64,
    /// The loop the wall was tested on; its elements are listed when it is not the paper's.
    pub lp: &'a Loop,
    /// The device, when the wall was given in physical units.
    pub device: Option<&'a Device>,
    /// The buzz verdict and its describing-function estimate, when an encoder or force
    /// resolution or a friction is modelled.
    pub buzz: Option<(&'a BuzzReport, &'a DescribingFunction)>,
    /// The wall's stiffness `K` (N/m) and damping `B` (N s/m) as given, when given in
    /// physical units: echoed as typed rather than converted back from `alpha` and `beta`.
    pub wall: Option<(f64, f64)>,
}

/// The text report: the verdict with the parameters, the method, the band and the degree,
/// the elements (normalized, when any is modelled) and, when the analysis is given, the
/// spectral radius and one line per root.
///
/// ```
/// use stabound::elements::Loop;
/// use stabound::export::report::{CheckReport, check_text};
/// use stabound::params::{Normalized, Plant, Wall};
/// use stabound::stability::{Checker, Options};
///
/// let lp = Loop::new(Plant::new(0.5, 1.0)?);
/// let checker = Checker::new(&lp, Options::default())?;
/// let wall = Wall::new(0.1, 0.3)?;
/// let params = Normalized::new(0.1, 0.3, 0.5, 1.0)?;
/// let mut report = CheckReport {
///     decision: checker.decide(&wall)?,
///     degree: checker.degree(),
///     analysis: None,
///     params: &params,
///     band: 1e-9,
///     lp: &lp,
///     device: None,
///     wall: None,
///     buzz: None,
/// };
/// let text = check_text(&report);
/// assert!(text.starts_with("stable (alpha = 0.1, beta = 0.3, delta = 0.5, d = 1)\nverdict by"));
/// assert!(!text.contains("roots"));
/// let analysis = checker.analyze(&wall)?;
/// report.analysis = Some(&analysis);
/// assert!(check_text(&report).contains("spectral radius 0.8416436328665768, verdict by"));
/// # Ok::<(), stabound::Error>(())
/// ```
pub fn check_text(r: &CheckReport) -> String {
    let (d, p) = (&r.decision, r.params);
    let mut s = format!(
        "{} (alpha = {}, beta = {}, delta = {}, d = {})\n",
        d.verdict.name(),
        short(p.alpha()),
        short(p.beta()),
        short(p.delta()),
        short(p.d()),
    );
    if let (Some(dev), Some((k, b))) = (r.device, r.wall) {
        s.push_str(&format!(
            "wall K = {} N/m, B = {} N s/m; device m = {} kg, T = {} s, b = {} N s/m\n",
            short(k),
            short(b),
            short(dev.mass()),
            short(dev.period()),
            short(dev.damping()),
        ));
    }
    if !r.lp.is_paper() {
        s.push_str(&format!("elements (normalized): {}\n", elements_json(r.lp)));
    }
    match r.analysis {
        Some(a) => {
            s.push_str(&format!(
                "spectral radius {}, verdict by {}, marginal band +-{:e}\n{}degree {}, roots:\n",
                short(shown_radius(a, r.band)),
                d.method.name(),
                r.band,
                radius_note(a, r.band),
                r.degree
            ));
            for z in &a.roots {
                s.push_str(&format!(
                    "  {:+.12} {:+.12}i  |z| = {:.12}\n",
                    z.re,
                    z.im,
                    z.norm()
                ));
            }
        }
        None => {
            s.push_str(&format!(
                "verdict by {}, marginal band +-{:e}, degree {}\n",
                d.method.name(),
                r.band,
                r.degree
            ));
            if d.reason == Some(MarginalReason::Undecided) {
                s.push_str("(undecided: rounding leaves a root on either side of the band's circles; the verdict is marginal rather than a guess)\n");
            }
        }
    }
    if let Some((b, df)) = r.buzz {
        s.push_str(&buzz_text(b, df));
    }
    s
}

/// The buzz verdict in a few words: `none (every start comes to rest)`, `sustained, peak 2
/// counts, period 7 samples`, or `diverged (...)`.
///
/// ```
/// use stabound::buzz::{BuzzOptions, Quantization, buzz};
/// use stabound::export::report::buzz_verdict;
/// use stabound::params::{Plant, Wall};
///
/// let q = Quantization::new(true, 0.0, 0.0, 0.0)?;
/// let b = buzz(&Plant::new(0.1, 1.0)?, &Wall::new(0.02, 0.3)?, &q, &BuzzOptions::default())?;
/// assert_eq!(buzz_verdict(&b), "none (every start comes to rest)");
/// # Ok::<(), stabound::Error>(())
/// ```
pub fn buzz_verdict(b: &BuzzReport) -> String {
    match (b.sustained(), b.period_samples()) {
        _ if b.diverged() => format!(
            "diverged (a start grew beyond {} counts)",
            short(crate::buzz::DIVERGED)
        ),
        (false, _) => "none (every start comes to rest)".to_string(),
        (true, Some(p)) => format!(
            "sustained, peak {} counts, period {p} samples",
            short(b.peak_counts())
        ),
        (true, None) => format!(
            "sustained, peak {} counts, not periodic in the window",
            short(b.peak_counts())
        ),
    }
}

/// The buzz lines of the text report: the verdict, one line per start, the estimate.
pub fn buzz_text(b: &BuzzReport, df: &DescribingFunction) -> String {
    let mut s = format!("buzz: {}\n", buzz_verdict(b));
    for run in &b.runs {
        let start = match run.start {
            Start::Rest(x) => format!("rest at {} counts", short(x)),
            Start::Impact(v) => format!("impact at {} counts/sample", short(v)),
        };
        let period = run
            .period_samples
            .map_or(String::new(), |p| format!(", period {p}"));
        s.push_str(&format!(
            "  from {start}: {}, peak {} counts{period}\n",
            run.outcome.name(),
            short(run.peak_counts)
        ));
    }
    s.push_str(&match (df.ray_margin, df.theta) {
        (Some(m), Some(t)) => format!(
            "  describing function: ray margin s* = {}, crossing at theta = {}, {}\n",
            short(m),
            short(t),
            match df.amplitude_counts() {
                Some(a) => format!("predicts a limit cycle of {a:.3} counts"),
                None => "predicts no limit cycle".to_string(),
            }
        ),
        _ => "  describing function: the ray through the wall never leaves the stable region\n"
            .to_string(),
    });
    s
}

/// The `buzz` object of the JSON report.
pub fn buzz_json(b: &BuzzReport, df: &DescribingFunction) -> serde_json::Value {
    let runs: Vec<serde_json::Value> = b
        .runs
        .iter()
        .map(|run| {
            let (kind, value) = match run.start {
                Start::Rest(x) => ("rest_counts", x),
                Start::Impact(v) => ("impact_counts_per_sample", v),
            };
            json!({
                "start": {kind: value},
                "outcome": run.outcome.name(),
                "peak_counts": run.peak_counts,
                "period_samples": run.period_samples,
            })
        })
        .collect();
    json!({
        "sustained": b.sustained(),
        "diverged": b.diverged(),
        "peak_counts": b.peak_counts(),
        "period_samples": b.period_samples(),
        "runs": runs,
        "describing_function": {
            "ray_margin": df.ray_margin,
            "theta": df.theta,
            "predicts_buzz": df.predicts_buzz(),
            "amplitude_counts": df.amplitude_counts(),
            "cycles": df.cycles.iter().map(|c| json!({
                "amplitude_counts": c.amplitude_counts,
                "theta": c.theta,
                "sustained": c.sustained,
            })).collect::<Vec<_>>(),
        },
    })
}

/// The JSON report (pretty-printed, one object, a final line break): `stable`, `verdict`,
/// `spectral_radius` and `roots` as `[re, im]` (when the analysis is given), `degree`,
/// `method`, `marginal_band`, the
/// normalized parameters, `elements` when any is modelled, `physical` with a device, and `buzz` (the verdict, each start's run and the describing function's estimate) when quantizers or friction are modelled.
pub fn check_json(r: &CheckReport) -> String {
    let (d, p) = (&r.decision, r.params);
    // a zero as 0.0 whatever its sign, as in every JSON table (`export::json`)
    let unsigned = |x: f64| x + 0.0;
    let mut obj = json!({
        "stable": d.verdict.is_stable(),
        "verdict": d.verdict.name(),
        "degree": r.degree,
        "method": d.method.name(),
        "marginal_band": r.band,
        "alpha": unsigned(p.alpha()),
        "beta": unsigned(p.beta()),
        "delta": unsigned(p.delta()),
        "d": unsigned(p.d()),
    });
    if let Some(a) = r.analysis {
        let roots: Vec<[f64; 2]> = a
            .roots
            .iter()
            .map(|z| [unsigned(z.re), unsigned(z.im)])
            .collect();
        obj["spectral_radius"] = json!(shown_radius(a, r.band));
        obj["roots"] = json!(roots);
    }
    if !r.lp.is_paper() {
        obj["elements"] = elements_json(r.lp);
    }
    if let Some(dev) = r.device {
        obj["physical"] = json!({
            "mass_kg": dev.mass(),
            "period_s": dev.period(),
            "damping_Ns_per_m": dev.damping(),
            "stiffness_N_per_m": r.wall.map_or_else(|| dev.stiffness(p.alpha()), |w| w.0),
            "wall_damping_Ns_per_m": r.wall.map_or_else(|| dev.wall_damping(p.beta()), |w| w.1),
            "delay_samples": p.d(),
        });
    }
    if let Some((b, df)) = r.buzz {
        obj["buzz"] = buzz_json(b, df);
    }
    // serializing a tree of numbers, strings and arrays cannot fail
    format!(
        "{}\n",
        serde_json::to_string_pretty(&obj).unwrap_or_default()
    )
}

/// The normalized values of the loop's elements, one object per element kind, each value
/// under its label in the element list ([`list::Element::readings`]).
fn elements_json(lp: &Loop) -> serde_json::Value {
    let mut obj = serde_json::Map::new();
    for el in list::Element::ALL {
        let readings: serde_json::Map<String, serde_json::Value> = el
            .readings(lp)
            .into_iter()
            .map(|(_, r)| {
                let v = match r.value {
                    list::Value::Number(x) => json!(x),
                    list::Value::Count(n) => json!(n),
                    list::Value::Choice(c) => json!(c),
                };
                (r.label.to_string(), v)
            })
            .collect();
        if !readings.is_empty() {
            obj.insert(el.key().to_string(), readings.into());
        }
    }
    obj.into()
}

/// A number as typed (`0.5`, the shortest form that reads back) in the everyday range, in
/// exponent form (`1e300`) outside it, so extreme inputs do not print hundreds of digits.
fn short(x: f64) -> String {
    let a = x.abs();
    if x.classify() == std::num::FpCategory::Zero || (1e-4..1e9).contains(&a) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}
