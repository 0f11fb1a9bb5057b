//! A sweep of `amax_report` over element families, delays, physical dampings and beta
//! limits (1,625 rows), each answer checked by the closed loop's state matrix: the best
//! eigenvalue radius a relative `1e-6` below `alpha_max` (at its damping where the stable
//! stiffnesses there reach it, else at the middles of the stable dampings at that
//! stiffness, else on a grid of dampings about `beta_at_max`, else on a fine grid of 4,001
//! dampings within `4e-6` of the answer's larger coordinate, where the stable walls below a
//! tip tilted off its damping lie). One line a row, then the counts: direct answers,
//! fallbacks, refusals, and answers with no wall below them that the eigenvalues call
//! strictly stable. The best wall with `beta >= 0` beside a negative-damping answer is
//! checked the same way (within its own limits), a missing one counted with whether the
//! report says why, and the answers whose wall `1e-6` below the checker calls marginal
//! (each says so in the report) are counted.
//!
//! The eigenvalues are those of the state matrix balanced first (Parlett-Reinsch, a
//! diagonal similarity): behind a filter pole `1e-7` from `z = 1` the optimum's damping
//! reaches `-5e11`, and unbalanced eigenvalues there err by `1e-4`, far more than the
//! `2e-8` by which the walls below the tip are stable. Checked against 50-digit
//! eigenvalues (`tools/amax_oracle.py`, independent of this crate): where the radius is
//! within `1e-8` of 1 (a slow filter, nine samples of delay), the balanced eigenvalues
//! agree with those to about `1e-12`, so their verdicts here are the oracle's.
//!
//! Run with `cargo run --release -p stabound --example amax_sweep [FAMILY-SUBSTRING]`.

use stabound::amax::{AmaxOptions, amax_report};
use stabound::elements::{Hand, Loop};
use stabound::filter::VelocityFilter;
use stabound::params::{Plant, Wall};
use stabound::search::stable_betas;
use stabound::stability::{Checker, Options};

type Build = Box<dyn Fn(Plant) -> Loop>;

fn families() -> Vec<(String, Build)> {
    let mut out: Vec<(String, Build)> = vec![("bare".into(), Box::new(Loop::new))];
    for pole in [0.999, 1.0 - 1e-5, 1.0 - 1e-7] {
        let f = VelocityFilter::low_pass(pole).unwrap();
        out.push((
            format!("low-pass {pole}"),
            Box::new(move |p| Loop::new(p).with_filter(f).unwrap()),
        ));
    }
    for (mu, delta, kappa) in [(0.5, 0.2, 0.0), (2.4121, 0.624, 0.131521)] {
        let h = Hand::new(mu, delta, kappa).unwrap();
        out.push((
            format!("hand {mu}"),
            Box::new(move |p| Loop::new(p).with_hand(h).unwrap()),
        ));
        for pole in [0.999, 0.9999] {
            let f = VelocityFilter::low_pass(pole).unwrap();
            out.push((
                format!("hand {mu} + low-pass {pole}"),
                Box::new(move |p| Loop::new(p).with_hand(h).unwrap().with_filter(f).unwrap()),
            ));
        }
    }
    for fc in [0.002, 0.005, 0.03] {
        let f = VelocityFilter::butterworth(fc).unwrap();
        out.push((
            format!("butterworth {fc}"),
            Box::new(move |p| Loop::new(p).with_filter(f).unwrap()),
        ));
    }
    out
}

fn radius(c: &Checker, alpha: f64, beta: f64) -> f64 {
    let mut m = c.state_matrix(&Wall::new(alpha, beta).unwrap());
    nalgebra::linalg::balancing::balance_parlett_reinsch(&mut m);
    m.complex_eigenvalues()
        .iter()
        .map(|z| z.norm())
        .fold(0.0, f64::max)
}

/// The best eigenvalue radius found a relative `1e-6` below `(a, b)`.
fn best_below(c: &Checker, a: f64, b: f64, lo: f64, hi: f64) -> f64 {
    let below = a * (1.0 - 1e-6);
    let mut best = radius(c, below, b);
    if let Ok(set) = stable_betas(c, below) {
        for i in set {
            let m = 0.5 * (i.lo.max(lo) + i.hi.min(hi));
            if m.is_finite() && (lo..=hi).contains(&m) {
                best = best.min(radius(c, below, m));
            }
        }
    }
    if best >= 1.0 {
        let half = 1e-3 * b.abs() + 1e-9;
        for j in 0..=400 {
            let beta = b - half + 2.0 * half * f64::from(j) / 400.0;
            if (lo..=hi).contains(&beta) {
                best = best.min(radius(c, below, beta));
            }
        }
    }
    if best >= 1.0 {
        // the stable walls below a tilted tip: a sliver some 5e-4 of this window wide and
        // an eighth of it off the answer's damping behind a filter pole 1e-7 from z = 1
        // (by the 50-digit oracle), so a spacing of 2.5e-4 of the window holds a sample
        let half = 4e-6 * a.abs().max(b.abs());
        for j in 0..=4000 {
            let beta = b - half + 2.0 * half * f64::from(j) / 4000.0;
            if (lo..=hi).contains(&beta) {
                best = best.min(radius(c, below, beta));
            }
        }
    }
    best
}

fn main() {
    let only = std::env::args().nth(1).unwrap_or_default();
    let limits: [(Option<f64>, Option<f64>); 5] = [
        (None, None),
        (Some(0.0), None),
        (None, Some(0.0)),
        (Some(-0.05), Some(-0.04)),
        (Some(-0.5), Some(0.5)),
    ];
    let (mut rows, mut direct, mut fallback, mut refused, mut not_stable) = (0, 0, 0, 0, 0);
    // the best wall with beta >= 0 beside a negative-damping answer: shown, held, or said
    // to be missing
    let (mut nonneg, mut nonneg_not_stable, mut nonneg_missing, mut nonneg_silent) = (0, 0, 0, 0);
    // answers whose wall 1e-6 below at their damping the checker calls marginal
    let mut marginal = 0;
    for (name, build) in families() {
        if !name.contains(&only) {
            continue;
        }
        for d in [0.0, 0.5, 1.0, 2.7, 9.0] {
            for delta in [0.0, 0.001, 0.1, 1.0, 10.0] {
                let lp = build(Plant::new(delta, d).unwrap());
                let c = Checker::new(lp, Options::default()).unwrap();
                for (lo, hi) in limits {
                    rows += 1;
                    let opts = AmaxOptions::default().with_beta_limits(lo, hi).unwrap();
                    let row = format!("{name} | delta {delta} | d {d} | beta {lo:?}..{hi:?}");
                    match amax_report(&lp, &opts) {
                        Err(e) => {
                            refused += 1;
                            println!("{row} | refused: {e}");
                        }
                        Ok(r) => {
                            let (a, b) = (r.amax.alpha_max, r.amax.beta_at_max);
                            let rho = best_below(
                                &c,
                                a,
                                b,
                                lo.unwrap_or(f64::NEG_INFINITY),
                                hi.unwrap_or(f64::INFINITY),
                            );
                            let how = if r.fallback.is_some() {
                                fallback += 1;
                                "fallback"
                            } else {
                                direct += 1;
                                "direct"
                            };
                            let flag = if rho < 1.0 {
                                ""
                            } else {
                                not_stable += 1;
                                " NOT-STABLE-BELOW"
                            };
                            println!("{row} | {how} {a:e} at {b:e} | radius below {rho:.12}{flag}");
                            if let Some(n) = r.nonnegative {
                                nonneg += 1;
                                let rho = best_below(
                                    &c,
                                    n.alpha_max,
                                    n.beta_at_max,
                                    lo.map_or(0.0, |l| l.max(0.0)),
                                    hi.unwrap_or(f64::INFINITY),
                                );
                                let flag = if rho < 1.0 {
                                    ""
                                } else {
                                    nonneg_not_stable += 1;
                                    " NOT-STABLE-BELOW"
                                };
                                println!(
                                    "{row} | beta >= 0: {:e} at {:e} | radius below {rho:.12}{flag}",
                                    n.alpha_max, n.beta_at_max
                                );
                            } else if b < 0.0 && hi.is_none_or(|h| h >= 0.0) {
                                nonneg_missing += 1;
                                match &r.no_nonnegative {
                                    Some(why) => println!("{row} | beta >= 0: none: {why}"),
                                    None => {
                                        nonneg_silent += 1;
                                        println!("{row} | beta >= 0: none shown, nothing said");
                                    }
                                }
                            }
                            if let Some(rho) = r.marginal_below {
                                marginal += 1;
                                println!("{row} | marginal below: radius {rho:.15}");
                            }
                        }
                    }
                }
            }
        }
    }
    println!(
        "{rows} rows: {direct} direct, {fallback} fallback, {refused} refused, {not_stable} answers with no strictly stable wall found 1e-6 below"
    );
    println!(
        "beta >= 0 beside a negative-damping answer (limits admitting beta >= 0): {nonneg} shown, {nonneg_not_stable} of them with no strictly stable wall found 1e-6 below, {nonneg_missing} not shown, {nonneg_silent} of those with no reason given"
    );
    println!(
        "{marginal} answers whose wall 1e-6 below is marginal by the checker (said in the report)"
    );
}
