//! Shape properties of alpha_max(delta): monotone for d >= 1 on [0, 10] (paper Section VII),
//! and continuous across the switch between boundary pieces (d = 0 near delta = 2.3, where
//! the maximum moves from a smooth point of the curve to the z = -1 line).

use stabound::amax::{AmaxKind, AmaxOptions, alpha_max_detail};
use stabound::params::Plant;

fn detail(delta: f64, d: f64) -> stabound::amax::AmaxDetail {
    alpha_max_detail(&Plant::new(delta, d).unwrap(), &AmaxOptions::default()).unwrap()
}

#[test]
fn monotone_in_delta_for_d_at_least_one() {
    for d in [1.0, 1.5, 2.0, 4.0] {
        let mut prev = 0.0;
        for i in 0..=100 {
            let a = detail(i as f64 * 0.1, d).amax.alpha_max;
            assert!(a > prev, "d {d} delta {}: {a} <= {prev}", i as f64 * 0.1);
            prev = a;
        }
    }
}

/// On a fine delta grid across the switch (d = 0, delta in [3.2, 4.2]: the maximum leaves the
/// smooth part of the curve for its corner with the z = -1 line near delta = 3.65), no step
/// of alpha_max or beta_at_max is more than 3 times both its neighbours. A kink (beta's slope
/// changes there) passes; a jump is one isolated step orders of magnitude above its
/// neighbours and fails.
#[test]
fn continuous_across_the_switch() {
    let n = 400;
    let pts: Vec<_> = (0..=n)
        .map(|i| detail(3.2 + i as f64 / n as f64, 0.0))
        .collect();
    // the switch really happens inside the window, so the test covers it
    assert_eq!(pts[0].kind, AmaxKind::Smooth);
    assert_eq!(pts[n].kind, AmaxKind::MinusOneCorner, "{:?}", pts[n]);
    type Pick = fn(&stabound::amax::AmaxDetail) -> f64;
    let picks: [Pick; 2] = [|p| p.amax.alpha_max, |p| p.amax.beta_at_max];
    for pick in picks {
        let steps: Vec<f64> = pts
            .windows(2)
            .map(|w| (pick(&w[1]) - pick(&w[0])).abs())
            .collect();
        for i in 1..steps.len() - 1 {
            assert!(
                steps[i] <= 3.0 * steps[i - 1].max(steps[i + 1]),
                "jump at delta {}: {} vs {} {}",
                3.2 + i as f64 / n as f64,
                steps[i],
                steps[i - 1],
                steps[i + 1]
            );
        }
    }
}
