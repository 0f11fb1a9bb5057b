//! Certificates at walls within `1e-12` of the stability boundary: the claims along a line
//! of walls across it never contradict each other (no wall certified stable beyond one
//! certified unstable), and the share left undecided is measured and printed (run with
//! `--nocapture`; recorded in docs/performance.md). The same for boxes of walls on loops
//! with elements, which are decided around their centre (Rouché on the unit circle).

use stabound::certificate::{BoxClaim, Claim, WallBox, certify, certify_box};
use stabound::elements::{Encoder, Hand, Loop, Transmission};
use stabound::filter::VelocityFilter;
use stabound::params::{Plant, Wall};
use stabound::stability::{Checker, DEFAULT_MARGIN, MIN_MARGIN, Options};

fn claim(lp: impl Into<Loop>, alpha: f64, beta: f64, margin: f64) -> Option<Claim> {
    certify(lp, &Wall::new(alpha, beta).ok()?, margin)
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
fn crossing(plant: impl Into<Loop> + Copy, beta: f64) -> Option<f64> {
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
            let Some(at) = crossing(plant, beta) else {
                continue;
            };
            for (band, margin) in [DEFAULT_MARGIN, MIN_MARGIN].into_iter().enumerate() {
                let claims: Vec<Option<Claim>> = (-10..=10)
                    .map(|k| claim(plant, at + f64::from(k) * 1e-13, beta, margin))
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

/// The stiffness where the double-precision spectral radius at `beta` crosses 1 (starting
/// stable at `alpha = 1e-4`), by bisection to the last bit: the certificates of a loop with
/// elements stop deciding within about `1e-9` of the boundary, too far to place it.
fn radius_crossing(lp: Loop, beta: f64) -> f64 {
    let checker = Checker::new(lp, Options::default()).unwrap();
    let rho = |a: f64| {
        checker
            .analyze(&Wall::new(a, beta).unwrap())
            .unwrap()
            .spectral_radius
    };
    let (mut lo, mut hi) = (1e-4, 1e-4);
    assert!(rho(lo) < 1.0, "beta {beta}");
    while rho(hi) < 1.0 {
        hi *= 2.0;
    }
    while lo < 0.5 * lo + 0.5 * hi && 0.5 * lo + 0.5 * hi < hi {
        let mid = 0.5 * lo + 0.5 * hi;
        if rho(mid) < 1.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo
}

/// Boxes of walls `w` wide in `alpha` and `beta`, centred at `k w` from the crossing
/// (`|k| <= 10`), for `w` from `1e-13` (every box within `1e-12` of the boundary) to
/// `1e-7`, on lines across the boundary of loops with elements (a hand and a low-pass filter
/// at 1 ms; a hand, a transmission and a moving average): along each line no box proved
/// stable lies beyond one proved unstable, and the shares are printed. The coefficients of a
/// loop with elements are enclosed to a relative width near `1e-12` (the matrix exponential),
/// which no method on these enclosures can see below.
#[test]
fn element_boxes_near_the_boundary() {
    let fast = Loop::new(Plant::new(0.0005, 1.5).unwrap())
        .with_hand(Hand::new(0.3, 0.002, 3e-4).unwrap())
        .and_then(|l| l.with_filter(VelocityFilter::low_pass_cutoff(30.0, 1e-3).unwrap()))
        .unwrap();
    let slow = Loop::new(Plant::new(0.5, 1.0).unwrap())
        .with_hand(Hand::new(0.3, 0.002, 3e-4).unwrap())
        .and_then(|l| {
            l.with_transmission(Transmission::new(0.2, 0.02, 0.005, 0.0, Encoder::Motor).unwrap())
        })
        .and_then(|l| l.with_filter(VelocityFilter::moving_average(4).unwrap()))
        .unwrap();
    let lines: Vec<(Loop, f64, f64)> = [(fast, [0.001, 0.002, 0.005]), (slow, [0.05, 0.2, 0.4])]
        .into_iter()
        .flat_map(|(lp, betas)| betas.map(|b| (lp, b, radius_crossing(lp, b))))
        .collect();
    let mut decided_at_widest = 0;
    for w in [1e-13, 1e-11, 1e-9, 1e-7] {
        let mut counts = [0usize; 3]; // stable, unstable, not proved
        let mut points = 0; // centres whose own certificate is stable or unstable
        for &(lp, beta, at) in &lines {
            points += (-10..=10)
                .filter(|&k| {
                    let c = claim(lp, at + f64::from(k) * w, beta, MIN_MARGIN);
                    stable(c) || unstable(c)
                })
                .count();
            let claims: Vec<BoxClaim> = (-10..=10)
                .map(|k| {
                    let c = at + f64::from(k) * w;
                    let lo = Wall::new(c - 0.5 * w, beta - 0.5 * w).unwrap();
                    let hi = Wall::new(c + 0.5 * w, beta + 0.5 * w).unwrap();
                    let walls = WallBox::new(lo, hi).unwrap();
                    certify_box(lp, &walls, 8).unwrap().claim()
                })
                .collect();
            let first_unstable = claims.iter().position(|&c| c == BoxClaim::Unstable);
            let last_stable = claims.iter().rposition(|&c| c == BoxClaim::Stable);
            if let (Some(u), Some(s)) = (first_unstable, last_stable) {
                assert!(s < u, "beta {beta} width {w:e}: {claims:?}");
            }
            for c in claims {
                counts[match c {
                    BoxClaim::Stable => 0,
                    BoxClaim::Unstable => 1,
                    _ => 2,
                }] += 1;
            }
        }
        let [s, u, n] = counts;
        println!(
            "boxes with elements, width {w:e}: {s} stable, {u} unstable, {n} not proved of {} boxes within {:e} of the boundary ({:.1} % not proved); {points} of their centres certified alone",
            s + u + n,
            10.5 * w,
            100.0 * n as f64 / (s + u + n) as f64
        );
        decided_at_widest = s.min(u);
    }
    assert!(decided_at_widest > 0);
}
