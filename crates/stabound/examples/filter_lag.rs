//! The paper's Section VIII device (m = 0.1 kg, T = 1 ms, d = 1, no physical damping) with a
//! first-order velocity filter: how far the largest stable wall stiffness drops with a filter
//! of about 50 ms lag, and which cutoff renders the stiffest wall.
//!
//! `K_max` is the largest stable stiffness over wall dampings `B >= 0`: for each damping the
//! stable stiffness limit by bisection on the verdict, the best damping by a scan and a
//! golden-section refinement; the best cutoff by golden-section search on `log f_c`.
//!
//! Run with `cargo run --release -p stabound --example filter_lag`.

use stabound::elements::Loop;
use stabound::filter::VelocityFilter;
use stabound::params::{Plant, Wall};
use stabound::stability::{Checker, Options};

const MASS: f64 = 0.1;
const PERIOD: f64 = 1e-3;

/// Largest stable alpha at fixed beta (0 when none): the largest stable point of a
/// geometric scan of alpha (the stable set need not start at 0 for negative beta), then
/// bisection to the next, unstable, scan point.
fn alpha_limit(c: &Checker, beta: f64) -> f64 {
    let stable = |a: f64| c.is_stable(&Wall::new(a, beta).unwrap()).unwrap();
    let grid: Vec<f64> = (0..=120)
        .map(|i| 1e-5 * 10f64.powf(i as f64 / 15.0))
        .collect();
    let Some(k) = (0..grid.len()).rev().find(|&i| stable(grid[i])) else {
        return 0.0;
    };
    if k + 1 == grid.len() {
        return grid[k];
    }
    let (mut lo, mut hi) = (grid[k], grid[k + 1]);
    for _ in 0..50 {
        let mid = 0.5 * (lo + hi);
        if stable(mid) { lo = mid } else { hi = mid }
    }
    lo
}

/// Golden-section search for the maximum of `f` on `[a, b]`.
fn golden_max(f: impl Fn(f64) -> f64, mut a: f64, mut b: f64, tol: f64) -> (f64, f64) {
    let g = (5f64.sqrt() - 1.0) / 2.0;
    let mut x1 = b - g * (b - a);
    let mut x2 = a + g * (b - a);
    let (mut f1, mut f2) = (f(x1), f(x2));
    while b - a > tol {
        if f1 < f2 {
            a = x1;
            x1 = x2;
            f1 = f2;
            x2 = a + g * (b - a);
            f2 = f(x2);
        } else {
            b = x2;
            x2 = x1;
            f2 = f1;
            x1 = b - g * (b - a);
            f1 = f(x1);
        }
    }
    let x = 0.5 * (a + b);
    (x, f(x))
}

/// (alpha_max, beta at it) of a loop: a scan of beta brackets the best, golden section refines.
fn alpha_max(lp: &Loop) -> (f64, f64) {
    let c = Checker::new(lp, Options::default()).unwrap();
    let n = 80;
    // Walls with non-negative damping only: with a lagging filter, a negative beta acts at
    // high frequency as a stiffness of its own (the filtered difference tends to a multiple
    // of the position), and the largest alpha over all beta then sits at strongly negative
    // damping and says little about the wall a user feels.
    let b0 = 0.0;
    let betas: Vec<f64> = (0..=n)
        .map(|i| b0 + (1.5 - b0) * i as f64 / n as f64)
        .collect();
    let vals: Vec<f64> = betas.iter().map(|&b| alpha_limit(&c, b)).collect();
    let k = (0..=n)
        .max_by(|&i, &j| vals[i].total_cmp(&vals[j]))
        .unwrap();
    let lo = betas[k.saturating_sub(1)];
    let hi = betas[(k + 1).min(n)];
    let (beta, alpha) = golden_max(|b| alpha_limit(&c, b), lo, hi, 1e-7);
    (alpha, beta)
}

fn with_cutoff(plant: Plant, fc: f64) -> Loop {
    Loop::new(plant)
        .with_filter(VelocityFilter::low_pass_cutoff(fc, PERIOD).unwrap())
        .unwrap()
}

fn main() {
    let k = |alpha: f64| alpha * MASS / (PERIOD * PERIOD);
    for (delta, d) in [(0.0, 1.0), (0.1, 1.0), (1.0, 1.0), (0.1, 0.0), (3.0, 0.0)] {
        let plant = Plant::new(delta, d).unwrap();
        let (a0, b0) = alpha_max(&Loop::new(plant));
        println!(
            "delta = {delta}, d = {d}: no filter: alpha_max = {a0:.5} at beta = {b0:.4}, K_max = {:.0} N/m, 75 % = {:.0} N/m",
            k(a0),
            0.75 * k(a0)
        );
        // a first-order low-pass lags by 1 / (2 pi f_c) at low frequency: 50 ms is 3.18 Hz
        for lag in [0.005, 0.02, 0.05] {
            let fc = 1.0 / (2.0 * std::f64::consts::PI * lag);
            let (a, b) = alpha_max(&with_cutoff(plant, fc));
            println!(
                "  low-pass f_c = {fc:.2} Hz (lag {:.0} ms): alpha_max = {a:.5} at beta = {b:.4}, K_max = {:.0} N/m ({:.2} of the unfiltered), 75 % = {:.0} N/m",
                lag * 1e3,
                k(a),
                a / a0,
                0.75 * k(a)
            );
        }
        // the cutoff that renders the stiffest wall: golden section on log f_c over
        // [1 Hz, Nyquist]
        let (lf, a) = golden_max(
            |lf| alpha_max(&with_cutoff(plant, lf.exp())).0,
            1f64.ln(),
            500f64.ln(),
            1e-4,
        );
        println!(
            "  best cutoff {:.2} Hz: alpha_max = {a:.5}, K_max = {:.0} N/m ({:.3} of the unfiltered)",
            lf.exp(),
            k(a),
            a / a0
        );
    }
}
