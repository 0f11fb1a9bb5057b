//! Certificates at walls within `1e-12` of the stability boundary: the claims along a line
//! of walls across it never contradict each other (no wall certified stable beyond one
//! certified unstable), and the share left undecided is measured and printed (run with
//! `--nocapture`; recorded in docs/performance.md).

use stabound::certificate::{Claim, certify};
use stabound::params::{Plant, Wall};
use stabound::stability::{DEFAULT_MARGIN, MIN_MARGIN};

fn claim(plant: &Plant, alpha: f64, beta: f64, margin: f64) -> Option<Claim> {
    certify(plant, &Wall::new(alpha, beta).ok()?, margin)
        .ok()
        .map(|c| c.claim())
}

fn stable(c: Option<Claim>) -> bool {
    c == Some(Claim::Stable)
}

fn unstable(c: Option<Claim>) -> bool {
    matches!(
        c,
        Some(Claim::Unstable { .. } | Claim::UnstableByCoefficient { .. })
    )
}

/// The stiffness where the certified claims at `beta` turn from stable to unstable, by
/// bisection on the certificates themselves (the narrowest band), or `None` when the line
/// starts unstable.
fn crossing(plant: &Plant, beta: f64) -> Option<f64> {
    let (mut lo, mut hi) = (1e-3, 1e-3);
    if !stable(claim(plant, lo, beta, MIN_MARGIN)) {
        return None;
    }
    while !unstable(claim(plant, hi, beta, MIN_MARGIN)) {
        hi *= 2.0;
        assert!(hi < 1e6, "no unstable wall at beta = {beta}");
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        match claim(plant, mid, beta, MIN_MARGIN) {
            c if stable(c) => lo = mid,
            c if unstable(c) => hi = mid,
            _ => break,
        }
    }
    Some(0.5 * (lo + hi))
}

/// Walls at `k 1e-13` from the crossing (`|k| <= 10`) on lines across the boundary of four
/// plants: along each line, with the default band and the narrowest, no certified-stable wall
/// lies beyond a certified-unstable one; the shares of claims are printed.
#[test]
fn walls_near_the_boundary() {
    let mut counts = [[0usize; 4]; 2]; // [band][stable, unstable, marginal, undecided]
    for (delta, d) in [(0.5, 1.0), (0.2, 2.5), (1.0, 0.5), (0.1, 4.0)] {
        let plant = Plant::new(delta, d).unwrap();
        for beta in [0.05, 0.1, 0.2, 0.3, 0.45] {
            let Some(at) = crossing(&plant, beta) else {
                continue;
            };
            for (band, margin) in [DEFAULT_MARGIN, MIN_MARGIN].into_iter().enumerate() {
                let claims: Vec<Option<Claim>> = (-10..=10)
                    .map(|k| claim(&plant, at + f64::from(k) * 1e-13, beta, margin))
                    .collect();
                let first_unstable = claims.iter().position(|&c| unstable(c));
                let last_stable = claims.iter().rposition(|&c| stable(c));
                if let (Some(u), Some(s)) = (first_unstable, last_stable) {
                    assert!(s < u, "delta {delta} d {d} beta {beta}: {claims:?}");
                }
                for c in claims {
                    let i = match c {
                        Some(Claim::Stable) => 0,
                        Some(Claim::Marginal { .. }) => 2,
                        None => 3,
                        _ => 1,
                    };
                    counts[band][i] += 1;
                }
            }
        }
    }
    for (band, margin) in [DEFAULT_MARGIN, MIN_MARGIN].into_iter().enumerate() {
        let [s, u, m, n] = counts[band];
        let all = (s + u + m + n) as f64;
        println!(
            "band {margin:e}: {s} stable, {u} unstable, {m} marginal, {n} undecided of {all} walls within 1e-12 of the boundary ({:.1} % undecided)",
            100.0 * n as f64 / all
        );
    }
    assert!(counts[0].iter().sum::<usize>() >= 300, "{counts:?}");
}
