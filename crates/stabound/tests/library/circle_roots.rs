//! Loops whose structure puts roots on the unit circle at `z = 1` (a free integrator, a free
//! mass: a double root) or `z = -1` (a two-sample average): Schur-Cohn alone calls them
//! marginal, as the roots' exact values say, not unstable; stable and unstable walls keep
//! their verdicts by the closed loop's eigenvalues.

use stabound::elements::{Hand, Loop};
use stabound::filter::VelocityFilter;
use stabound::params::{Plant, Wall};
use stabound::stability::{Checker, Method, Options, Verdict};

fn schur_cohn(lp: Loop, alpha: f64, beta: f64) -> Verdict {
    let opts = Options {
        method: Method::SchurCohn,
        ..Options::default()
    };
    Checker::new(lp, opts)
        .unwrap()
        .verdict(&Wall::new(alpha, beta).unwrap())
        .unwrap()
}

/// The spectral radius of the closed loop's state matrix, from its eigenvalues.
fn radius(lp: Loop, alpha: f64, beta: f64) -> f64 {
    Checker::new(lp, Options::default())
        .unwrap()
        .state_matrix(&Wall::new(alpha, beta).unwrap())
        .complex_eigenvalues()
        .iter()
        .map(|z| z.norm())
        .fold(0.0, f64::max)
}

#[test]
fn roots_on_the_circle_are_marginal() {
    let free = Plant::new(0.0, 1.0).unwrap();
    let held = Loop::new(free)
        .with_hand(Hand::new(0.5, 0.0, 0.0).unwrap())
        .unwrap();
    // a free mass with a hand's mass: z = 1 twice (exactly: no force acts on it)
    assert_eq!(schur_cohn(held, 0.0, 0.0), Verdict::Marginal);
    // a damped device at no stiffness: z = 1 once
    let damped = Loop::new(Plant::new(0.3, 1.0).unwrap())
        .with_hand(Hand::new(0.5, 0.1, 0.0).unwrap())
        .unwrap();
    assert_eq!(schur_cohn(damped, 0.0, 0.2), Verdict::Marginal);
    // a two-sample average: z = -1 among the roots at no stiffness and damping too
    let averaged = Loop::new(free)
        .with_filter(VelocityFilter::moving_average(2).unwrap())
        .unwrap();
    assert_eq!(schur_cohn(averaged, 0.0, 0.0), Verdict::Marginal);
    // away from the circle the verdicts are the eigenvalues'
    for lp in [held, damped, averaged] {
        for (alpha, beta) in [(0.05, 0.3), (0.02, 0.1), (3.0, 0.0), (0.05, -2.0)] {
            let r = radius(lp, alpha, beta);
            let want = if r < 1.0 - 1e-6 {
                Verdict::Stable
            } else if r > 1.0 + 1e-6 {
                Verdict::Unstable
            } else {
                continue;
            };
            assert_eq!(
                schur_cohn(lp, alpha, beta),
                want,
                "{lp:?} ({alpha}, {beta}): {r}"
            );
        }
    }
}
