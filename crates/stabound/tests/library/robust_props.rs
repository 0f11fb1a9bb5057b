//! Property tests over the public API: no panic for any input; every
//! failure is a typed error. Case counts are bounded so the file runs in seconds.

use proptest::prelude::*;
use stabound::amax::{AmaxOptions, alpha_max};
use stabound::boundary::{ExactOptions, exact};
use stabound::params::{MAX_DELAY, Plant, Wall};
use stabound::search::{alpha_limit, stable_alphas, stable_betas};
use stabound::stability::{Checker, Method, Options};

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
        let _ = c.verdict(&wall);
    }

    /// Eigenvalue and argument-principle verdicts and analyses (roots, spectral radius), up to
    /// |alpha|, |beta| of 1e300 (this test found a hang there: balancing overflowed its norms; fixed by scaling
    /// the matrix by a power of two first).
    #[test]
    fn eigen_analysis_never_panics(p in plant(), alpha in -1e300..1e300f64, beta in -1e300..1e300f64) {
        let wall = Wall::new(alpha, beta).unwrap();
        for method in [Method::SchurCohn, Method::Eigen, Method::ArgumentPrinciple] {
            let c = Checker::new(p, Options { method, ..Options::default() }).unwrap();
            let _ = c.verdict(&wall);
            if let Ok(an) = c.analyze(&wall) {
                prop_assert!(an.spectral_radius >= 0.0 || an.spectral_radius.is_nan());
            }
        }
    }

    /// The one-dimensional searches on any finite line.
    #[test]
    fn searches_never_panic(p in plant(), v in wall_value()) {
        let c = Checker::new(p, Options::default()).unwrap();
        if let Ok(set) = stable_alphas(&c, v) {
            // intervals sorted and disjoint, stiffness positive
            for w in set.windows(2) {
                prop_assert!(w[0].hi <= w[1].lo);
            }
            prop_assert!(set.iter().all(|i| i.lo >= 0.0 && i.lo <= i.hi));
        }
        let _ = stable_betas(&c, v);
        let _ = alpha_limit(&c, v);
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, ..ProptestConfig::default() })]

    /// alpha_max with and without beta limits, at a coarse tolerance.
    #[test]
    fn alpha_max_never_panics(p in plant(), lo in prop::option::of(-2.0..2.0f64),
                              width in prop::option::of(0.0..2.0f64)) {
        let opts = AmaxOptions::new(1e-6).unwrap().with_beta_limits(lo, lo.zip(width).map(|(l, w)| l + w)).unwrap();
        if let Ok(a) = alpha_max(p, &opts) {
            prop_assert!(a.alpha_max.is_finite() && a.alpha_max >= 0.0);
        }
    }

    /// The exact boundary at a coarse tolerance: a closed polyline when it succeeds.
    #[test]
    fn exact_boundary_never_panics(p in plant()) {
        if let Ok(b) = exact(p, &ExactOptions { tol: 1e-3 }) {
            let (first, last) = (b.points.first().unwrap(), b.points.last().unwrap());
            prop_assert!((first.x - last.x).abs() <= 0.0 && (first.y - last.y).abs() <= 0.0);
        }
    }
}
