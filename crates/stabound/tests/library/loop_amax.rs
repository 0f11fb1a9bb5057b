//! The largest stable stiffness of loops with elements against bisection on the loop's
//! verdicts (no D-decomposition involved), and against the paper engine's `alpha_max` for
//! the bare loop.

use crate::loop_boundary::element_loops;
use stabound::elements::{Hand, Loop};
use stabound::params::{Plant, Wall};
use stabound::search::alpha_limit;
use stabound::stability::Checker;
use stabound::stability::Options;
use stabound::{AmaxOptions, alpha_max};

/// The largest stable `alpha` at `beta` by bisection on the checker's verdicts, scanning
/// down from far right for the last unstable-to-stable change (a grid of 4000 steps across
/// `[lo, hi]`, then 60 halvings): independent of the boundary engines.
fn bisected_limit(c: &Checker, beta: f64, lo: f64, hi: f64) -> Option<f64> {
    let stable = |a: f64| c.is_stable(&Wall::new(a, beta).unwrap()).unwrap();
    let n = 4000;
    let at = |i: usize| lo + (hi - lo) * i as f64 / n as f64;
    let i = (0..n).rev().find(|&i| stable(at(i)))?;
    let (mut s, mut u) = (at(i), at(i + 1));
    for _ in 0..60 {
        let m = 0.5 * (s + u);
        if stable(m) {
            s = m;
        } else {
            u = m;
        }
    }
    Some(s)
}

/// With no element (a hand of zeros, so the general route) the general route gives the paper engine's `alpha_max` within the
/// boundary's tolerance 1e-9 (the rightmost vertex is at most tol inside), with and without
/// beta limits.
#[test]
fn bare_loop_alpha_max_is_the_paper_engines() {
    let limited = AmaxOptions::default()
        .with_beta_limits(Some(0.0), Some(0.05))
        .unwrap();
    for (delta, d) in [(0.0, 0.0), (0.1, 1.0), (0.5, 0.5), (1.0, 3.0), (0.3, 7.0)] {
        let p = Plant::new(delta, d).unwrap();
        for opts in [AmaxOptions::default(), limited] {
            let want = alpha_max(p, &opts).unwrap();
            // a hand of zeros is the same device on the general polynomial
            let general = Loop::new(p)
                .with_hand(Hand::new(0.0, 0.0, 0.0).unwrap())
                .unwrap();
            let got = alpha_max(general, &opts).unwrap();
            let err = want.alpha_max - got.alpha_max;
            assert!(
                (-1e-12..=1e-9).contains(&err),
                "delta {delta} d {d} {opts:?}: {got:?} vs {want:?}"
            );
        }
    }
}

/// For each element loop: the stiffness limit at several dampings matches bisection on the
/// checker's verdicts, and `alpha_max` bounds them all and is reached at its `beta`. The
/// verdicts carry the default marginal band of 1e-9 in radius, which moves the edge by that
/// over the radius's slope in alpha (above 1e-3 here): 1e-6 covers it.
#[test]
fn loop_alpha_max_and_limit_match_bisection() {
    for (name, lp) in element_loops() {
        let c = Checker::new(lp, Options::default()).unwrap();
        let m = alpha_max(lp, &AmaxOptions::default()).unwrap();
        let at_max = bisected_limit(&c, m.beta_at_max, -1.0, 4.0).unwrap();
        assert!(
            (at_max - m.alpha_max).abs() < 1e-6,
            "{name}: {m:?} vs bisection {at_max}"
        );
        for k in 0..=8 {
            let beta = m.beta_at_max * (0.25 * k as f64 - 0.5);
            let want = bisected_limit(&c, beta, -1.0, 4.0);
            let got = alpha_limit(&c, beta).unwrap();
            match (want, got) {
                (Some(w), Some(g)) => {
                    assert!((w - g).abs() < 1e-6, "{name} beta {beta}: {g} vs {w}");
                    assert!(
                        g <= m.alpha_max + 1e-9,
                        "{name} beta {beta}: {g} above {m:?}"
                    );
                }
                (None, None) => {}
                other => panic!("{name} beta {beta}: {other:?}"),
            }
        }
    }
}
