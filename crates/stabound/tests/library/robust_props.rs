//! Property tests over the public API: no panic for any input; every
//! failure is a typed error. Case counts are bounded so the file runs in seconds.

use proptest::prelude::*;
use stabound::Error;
use stabound::amax::{AmaxOptions, alpha_max};
use stabound::boundary::{ExactOptions, exact};
use stabound::params::{MAX_DELAY, Plant, Wall};
use stabound::search::{MAX_FIXED, alpha_limit, stable_alphas, stable_betas};
use stabound::stability::{Checker, Method, Options, Verdict};

/// Any finite f64, from subnormals to the largest magnitudes.
fn finite() -> impl Strategy<Value = f64> {
    prop::num::f64::NORMAL | prop::num::f64::SUBNORMAL | prop::num::f64::ZERO
}

/// Any f64 at all, NaN and infinities included.
fn anything() -> impl Strategy<Value = f64> {
    prop::num::f64::ANY
}

/// A valid plant: delta from 0 to 1e4 (log-spread), d from 0 to 20 with fractions.
fn plant() -> impl Strategy<Value = Plant> {
    (
        prop_oneof![Just(0.0), 1e-300..1e-6f64, 0.0..10.0f64, 10.0..1e4f64],
        prop_oneof![Just(0.0), 0.0..3.0f64, 0.0..20.0f64],
    )
        .prop_map(|(delta, d)| Plant::new(delta, d).unwrap())
}

/// Wall parameters around and far from the stable region.
fn wall_value() -> impl Strategy<Value = f64> {
    prop_oneof![-2.0..5.0f64, finite()]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    /// Constructors accept exactly the documented ranges and never panic.
    #[test]
    fn constructors_never_panic(a in anything(), b in anything()) {
        let p = Plant::new(a, b);
        let valid = (0.0..=stabound::params::MAX_DELTA).contains(&a) && (0.0..=MAX_DELAY).contains(&b);
        prop_assert_eq!(p.is_ok(), valid);
        prop_assert_eq!(Wall::new(a, b).is_ok(), a.is_finite() && b.is_finite());
    }

    /// Schur-Cohn verdicts for any finite wall: a result or a typed error, never a panic.
    #[test]
    fn schur_cohn_verdict_never_panics(p in plant(), alpha in wall_value(), beta in wall_value()) {
        let wall = Wall::new(alpha, beta).unwrap();
        let c = Checker::new(p, Options::default()).unwrap();
        let v = c.verdict(&wall).unwrap();
        // against the state-space eigenvalues where their radius is clearly off the circle
        // (1 % is far above their error on these degrees)
        let eig = Checker::new(p, Options { method: Method::StateSpace, ..Options::default() }).unwrap();
        if let Ok(an) = eig.analyze(&wall) {
            if an.spectral_radius < 0.99 {
                prop_assert_eq!(v, Verdict::Stable, "{:?} {:?}: radius {}", p, wall, an.spectral_radius);
            } else if an.spectral_radius > 1.01 {
                prop_assert_eq!(v, Verdict::Unstable, "{:?} {:?}: radius {}", p, wall, an.spectral_radius);
            }
        }
    }

    /// Eigenvalue and argument-principle verdicts and analyses (roots, spectral radius), up to
    /// |alpha|, |beta| of 1e300 (this test found a hang there: balancing overflowed its norms; fixed by scaling
    /// the matrix by a power of two first).
    #[test]
    fn eigen_analysis_never_panics(p in plant(), alpha in -1e300..1e300f64, beta in -1e300..1e300f64) {
        let wall = Wall::new(alpha, beta).unwrap();
        for method in [Method::SchurCohn, Method::Eigen, Method::ArgumentPrinciple] {
            let c = Checker::new(p, Options { method, ..Options::default() }).unwrap();
            match (c.verdict(&wall), c.analyze(&wall)) {
                (Ok(v), Ok(an)) => {
                    prop_assert_eq!(v, an.verdict);
                    prop_assert!(an.spectral_radius >= 0.0, "{:?} {:?}: {}", p, wall, an.spectral_radius);
                }
                // an iterative method may give up on walls this far out, as documented
                (v, an) => {
                    for e in [v.err(), an.err()].into_iter().flatten() {
                        prop_assert!(matches!(e, Error::NoConvergence { .. } | Error::Numerical(_)), "{e}");
                    }
                }
            }
        }
    }

    /// The one-dimensional searches on any finite line: a result within the documented
    /// range of the fixed value ([`MAX_FIXED`]), the documented refusal beyond it.
    #[test]
    fn searches_never_panic(p in plant(), v in wall_value()) {
        let c = Checker::new(p, Options::default()).unwrap();
        let (alphas, betas, limit) = (stable_alphas(&c, v), stable_betas(&c, v), alpha_limit(&c, v));
        if v.abs() > MAX_FIXED {
            for r in [alphas.map(|_| ()), betas.map(|_| ()), limit.map(|_| ())] {
                prop_assert!(matches!(r, Err(Error::InvalidParameter { .. })), "{r:?}");
            }
            return Ok(());
        }
        let (alphas, betas) = (alphas.unwrap(), betas.unwrap());
        for (set, stiffness) in [(&alphas, true), (&betas, false)] {
            // intervals sorted and disjoint; stable stiffnesses positive
            for w in set.windows(2) {
                prop_assert!(w[0].hi <= w[1].lo);
            }
            prop_assert!(set.iter().all(|i| i.lo <= i.hi && (!stiffness || i.lo >= 0.0)));
            // the middle of each interval wide enough to sample (1e-6 of its ends' size,
            // far above the crossings' rounding) is not unstable by the state-space
            // eigenvalues, a method independent of the crossing polynomial
            let eig = Checker::new(p, Options { method: Method::StateSpace, ..Options::default() }).unwrap();
            for i in set.iter().filter(|i| i.hi - i.lo > 1e-6 * i.lo.abs().max(i.hi.abs()).max(1.0)) {
                let mid = 0.5 * (i.lo + i.hi);
                let wall = if stiffness { Wall::new(mid, v) } else { Wall::new(v, mid) }.unwrap();
                prop_assert_ne!(eig.verdict(&wall).unwrap(), Verdict::Unstable, "{:?} {:?}", p, wall);
            }
        }
        prop_assert_eq!(limit.unwrap(), alphas.last().map(|i| i.hi));
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, ..ProptestConfig::default() })]

    /// alpha_max with and without beta limits, at a coarse tolerance.
    ///
    /// Without limits every valid plant has an `alpha_max`; with limits the answer is either
    /// within them and no larger than the unlimited one, or the documented refusal of limits
    /// that leave no stable wall, which cannot happen when they hold the unlimited maximum.
    #[test]
    fn alpha_max_never_panics(p in plant(), lo in prop::option::of(-2.0..2.0f64),
                              width in prop::option::of(0.0..2.0f64)) {
        let free = alpha_max(p, &AmaxOptions::new(1e-6).unwrap()).unwrap();
        prop_assert!(free.alpha_max.is_finite() && free.alpha_max > 0.0, "{:?}: {:?}", p, free);
        let hi = lo.zip(width).map(|(l, w)| l + w);
        let opts = AmaxOptions::new(1e-6).unwrap().with_beta_limits(lo, hi).unwrap();
        let within = |b: f64| lo.is_none_or(|l| b >= l) && hi.is_none_or(|h| b <= h);
        match alpha_max(p, &opts) {
            Ok(a) => {
                prop_assert!(a.alpha_max.is_finite() && a.alpha_max >= 0.0);
                prop_assert!(within(a.beta_at_max), "{:?} {:?}: {:?}", lo, hi, a);
                // both to the search's relative tolerance 1e-6
                prop_assert!(a.alpha_max <= free.alpha_max * (1.0 + 1e-5), "{:?} above {:?}", a, free);
            }
            Err(Error::InvalidRequest(m)) => {
                prop_assert!(!within(free.beta_at_max), "{:?}: refused although the maximum {:?} is within: {}", p, free, m);
            }
            Err(e) => prop_assert!(false, "{:?} {:?} {:?}: {}", p, lo, hi, e),
        }
    }

    /// The exact boundary at a coarse tolerance: always a closed polyline, whose rightmost
    /// vertex is `alpha_max` (an independent search) to the tolerance.
    #[test]
    fn exact_boundary_never_panics(p in plant()) {
        let b = exact(p, &ExactOptions { tol: 1e-3 }).unwrap();
        let (first, last) = (b.points.first().unwrap(), b.points.last().unwrap());
        prop_assert!((first.x - last.x).abs() <= 0.0 && (first.y - last.y).abs() <= 0.0);
        let (right, _) = b.rightmost();
        let a = alpha_max(p, &AmaxOptions::new(1e-9).unwrap()).unwrap().alpha_max;
        prop_assert!((right - a).abs() <= 2e-3 * a.max(1.0), "{:?}: rightmost {} vs alpha_max {}", p, right, a);
    }
}
