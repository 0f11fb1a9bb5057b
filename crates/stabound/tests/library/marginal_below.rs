//! The wall a relative `1e-6` below `alpha_max` of the paper's loop, where the checker calls
//! it marginal: what `amax_report` and `marginal_below` say, against the closed loop's state
//! matrix eigenvalues (nalgebra's real Schur form) and the checker's own analysis; and
//! `alpha_max_with_marginal`, which answers both at once, against `alpha_max` and
//! `marginal_below` asked apart.

use stabound::amax::{AmaxOptions, alpha_max_with_marginal, amax_report, marginal_below};
use stabound::elements::Loop;
use stabound::filter::VelocityFilter;
use stabound::params::{Plant, Wall};
use stabound::stability::{Checker, Options, Verdict};

/// The largest modulus of the closed loop's state-matrix eigenvalues at `wall`.
fn eigen_radius(c: &Checker, wall: &Wall) -> f64 {
    c.state_matrix(wall)
        .complex_eigenvalues()
        .iter()
        .map(|z| z.norm())
        .fold(0.0, f64::max)
}

/// At delta = 100 with no delay the paper's loop's optimum needs negative damping
/// (`beta` near `-delta`), and the wall a relative `1e-6` below it keeps a root about
/// `2e-10` inside the unit circle (state-matrix eigenvalues of a 3 x 3 matrix with entries
/// up to 400, good to about `1e-13` here): within the default band of `1e-9`. The report
/// and `marginal_below` give the same radius, within `1e-11` of the eigenvalues', and the
/// checker's analysis calls the wall marginal.
#[test]
fn paper_loop_wall_below_within_the_band_is_reported() {
    let lp = Loop::new(Plant::new(100.0, 0.0).unwrap());
    let r = amax_report(&lp, &AmaxOptions::default()).unwrap();
    let a = r.amax;
    let wall = Wall::new(a.alpha_max * (1.0 - 1e-6), a.beta_at_max).unwrap();
    let c = Checker::new(lp, Options::default()).unwrap();
    let rho = eigen_radius(&c, &wall);
    assert!(rho < 1.0 && rho > 1.0 - 1e-9, "{rho}");
    assert_eq!(c.analyze(&wall).unwrap().verdict, Verdict::Marginal);
    let reported = r
        .marginal_below
        .expect("the report says the wall below is marginal");
    assert!((reported - rho).abs() < 1e-11, "{reported} vs {rho}");
    assert_eq!(marginal_below(&lp, &a).unwrap(), Some(reported));
}

/// Over a grid of the paper's loop (delta 0 to 300, delays 0 to 30 samples, beta limits
/// none and `>= 0`), `marginal_below` names a radius exactly where the checker's full
/// analysis (its guarded recursion, root count and inclusion discs, without the interval
/// recursion that spares it) calls the wall below marginal, and that radius is the
/// analysis's; where it names none, the state-matrix eigenvalues put every root more than
/// `1e-9` inside the circle.
#[test]
fn paper_loop_marginal_note_agrees_with_the_checker() {
    let mut marginal = 0;
    for delta in [0.0, 1e-3, 0.1, 1.0, 10.0, 30.0, 100.0, 300.0] {
        for d in [0.0, 0.5, 1.0, 2.7, 10.0, 30.0] {
            let lp = Loop::new(Plant::new(delta, d).unwrap());
            let c = Checker::new(lp, Options::default()).unwrap();
            for lo in [None, Some(0.0)] {
                let opts = AmaxOptions::default().with_beta_limits(lo, None).unwrap();
                let a = stabound::alpha_max(lp, &opts).unwrap();
                let wall = Wall::new(a.alpha_max * (1.0 - 1e-6), a.beta_at_max).unwrap();
                let an = c.analyze(&wall).unwrap();
                let got = marginal_below(&lp, &a).unwrap();
                assert_eq!(alpha_max_with_marginal(lp, &opts).unwrap(), (a, got));
                if an.verdict == Verdict::Marginal {
                    marginal += 1;
                    assert_eq!(got, Some(an.spectral_radius), "{delta} {d} {lo:?}");
                } else {
                    assert_eq!(got, None, "{delta} {d} {lo:?}");
                    let rho = eigen_radius(&c, &wall);
                    assert!(rho < 1.0 - 1e-9, "{delta} {d} {lo:?}: {rho}");
                }
            }
        }
    }
    // the grid holds marginal walls too (delta = 100 at d = 0 is one, as above)
    assert!(marginal >= 2, "{marginal}");
}

/// Loops with elements: `alpha_max_with_marginal` takes the state matrix's radius that the
/// answer's hold computed, and asks the checker only near the circle; `marginal_below` asks
/// the checker every time. Both give the same radius, and `alpha_max` the same answer, on
/// low-pass filters with poles from `0.8` to `1e-5` from `z = 1` without physical damping
/// (whose walls below the optimum are marginal at the slowest pole) and a few dampings.
#[test]
fn loops_with_elements_answer_as_asked_apart() {
    let mut marginal = 0;
    for pole in [0.8, 0.999, 1.0 - 1e-5] {
        for (delta, d) in [(0.0, 0.0), (0.0, 1.0), (0.1, 1.0), (1.0, 2.0)] {
            let lp = Loop::new(Plant::new(delta, d).unwrap())
                .with_filter(VelocityFilter::low_pass(pole).unwrap())
                .unwrap();
            for lo in [None, Some(0.0)] {
                let opts = AmaxOptions::default().with_beta_limits(lo, None).unwrap();
                let Ok(a) = stabound::alpha_max(lp, &opts) else {
                    assert!(alpha_max_with_marginal(lp, &opts).is_err());
                    continue;
                };
                let apart = marginal_below(&lp, &a).unwrap();
                marginal += usize::from(apart.is_some());
                let both = alpha_max_with_marginal(lp, &opts).unwrap();
                assert_eq!(both, (a, apart), "{pole} {delta} {d} {lo:?}");
            }
        }
    }
    assert!(marginal >= 1, "{marginal}");
}
