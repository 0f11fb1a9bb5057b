//! `alpha_max` against an independent brute force that never looks at the D-decomposition
//! curve: for each beta on a grid, the largest stable alpha by a scan in alpha and bisection
//! with Schur-Cohn point tests; then golden-section search in beta around the best grid
//! value. Grid: delta in [0, 100] spread out, d in {0, 0.125, 0.25, 0.5, 1, 2, 4, 8}.

use stabound::amax::{AmaxOptions, alpha_max};
use stabound::params::{Plant, Wall};
use stabound::stability::{Checker, Options};

/// Largest stable alpha at fixed beta: scan `hi` down to `1e-5 hi` on `n` geometrically
/// spaced points (alpha_max spans 0.007 at d = 8 to 400 at delta = 100) for the first stable
/// one, then bisect to the unstable point above it. Returns 0 when no point is stable.
fn sup_alpha(ch: &Checker, beta: f64, hi: f64, n: usize) -> f64 {
    let stable = |a: f64| ch.is_stable(&Wall::new(a, beta).unwrap()).unwrap();
    let r = 1e-5f64.powf(1.0 / n as f64);
    let mut up = hi;
    let mut a = hi * r;
    for _ in 0..n {
        if stable(a) {
            let mut lo = a;
            // 80 halvings: below f64 resolution of the bracket.
            for _ in 0..80 {
                let mid = 0.5 * (lo + up);
                if stable(mid) {
                    lo = mid;
                } else {
                    up = mid;
                }
            }
            return lo;
        }
        up = a;
        a *= r;
    }
    0.0
}

fn brute(delta: f64, d: f64) -> (f64, f64) {
    // Checker margin 1e-13: decisions right at the boundary, where the bisection lands.
    let ch = Checker::new(
        Plant::new(delta, d).unwrap(),
        Options {
            margin: 1e-13,
            ..Options::default()
        },
    )
    .unwrap();
    // For d = 0 the slope alpha_max/delta stays below 5; 6 (1 + delta) bounds every case.
    let hi = 6.0 * (1.0 + delta);
    let (blo, bhi) = (-delta - 0.5, 1.5 * delta + 2.0);
    let nb = 120;
    let step = (bhi - blo) / nb as f64;
    let (mut best_b, mut best_a) = (0.0, -1.0);
    for i in 0..=nb {
        let b = blo + step * i as f64;
        let a = sup_alpha(&ch, b, hi, 300);
        if a > best_a {
            best_a = a;
            best_b = b;
        }
    }
    // golden section on [best_b - step, best_b + step] (A(beta) is unimodal near its max)
    let g = 0.5 * (5f64.sqrt() - 1.0);
    let (mut x0, mut x3) = (best_b - step, best_b + step);
    let f = |b: f64| sup_alpha(&ch, b, hi, 300);
    let mut x1 = x3 - g * (x3 - x0);
    let mut x2 = x0 + g * (x3 - x0);
    let (mut f1, mut f2) = (f(x1), f(x2));
    for _ in 0..60 {
        if f1 > f2 {
            x3 = x2;
            x2 = x1;
            f2 = f1;
            x1 = x3 - g * (x3 - x0);
            f1 = f(x1);
        } else {
            x0 = x1;
            x1 = x2;
            f1 = f2;
            x2 = x0 + g * (x3 - x0);
            f2 = f(x2);
        }
    }
    if f1 > f2 { (f1, x1) } else { (f2, x2) }
}

#[test]
fn matches_brute_force_on_grid() {
    let ds = [0.0, 0.125, 0.25, 0.5, 1.0, 2.0, 4.0, 8.0];
    let deltas = [0.0, 0.05, 0.4, 1.7, 2.3, 5.0, 13.0, 40.0, 100.0];
    for (i, &d) in ds.iter().enumerate() {
        // every d gets 4 of the deltas, rotating, so the grid is spread but cheap
        for k in 0..4 {
            let delta = deltas[(i * 2 + k * 2) % deltas.len()];
            let ours = alpha_max(Plant::new(delta, d).unwrap(), &AmaxOptions::default()).unwrap();
            let (a, b) = brute(delta, d);
            // The brute force is exact up to its bisection (1e-15) and the golden section
            // (a kinked maximum is found to ~1e-12 relative in beta), so 1e-8 relative in
            // alpha leaves room only for a wrong maximum.
            assert!(
                (ours.alpha_max - a).abs() <= 1e-8 * a,
                "delta {delta} d {d}: ours {ours:?}, brute ({a}, {b})"
            );
            // beta at a smooth maximum is ill-conditioned for the brute force (flat in beta),
            // so only a loose check.
            assert!(
                (ours.beta_at_max - b).abs() <= 1e-3 * (1.0 + b.abs()),
                "delta {delta} d {d}: ours {ours:?}, brute ({a}, {b})"
            );
        }
    }
}
