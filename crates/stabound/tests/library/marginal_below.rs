//! The wall a relative `1e-6` below `alpha_max` of the paper's loop, where the checker calls
//! it marginal: what `amax_report` and `marginal_below` say, against the closed loop's state
//! matrix eigenvalues (nalgebra's real Schur form) and the checker's own analysis.

use stabound::amax::{AmaxOptions, amax_report, marginal_below};
use stabound::elements::Loop;
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
