//! Certified enclosures of `alpha_max` on loops with elements, against the state-space
//! verdict (the eigenvalues of the closed loop's state matrix, built from the sampled device
//! and the wall law, not from the polynomial the certificate encloses): walls just below the
//! lower end are stable at the certified damping, and at the upper end (and a little above
//! it) no damping of a fine grid of the searched range is stable, nor at stiffnesses up to
//! twice the cap where the certificate proves it for every stiffer wall.

use stabound::certificate::{AmaxCertificate, certify_alpha_max};
use stabound::elements::{Actuator, Encoder, Hand, Loop, Transmission};
use stabound::filter::VelocityFilter;
use stabound::params::{Plant, Wall};
use stabound::stability::{Checker, Method, Options};
use stabound::{AmaxOptions, alpha_max};

/// Leaves each strip may be halved into (as the command line's `amax --certify`).
const LEAVES: usize = 4096;

/// Loops with each kind of element and the dampings searched: a hand and a low-pass filter
/// at fast sampling (1 ms), a transmission with an actuator lag, a moving average, and a
/// second-order filter (the filters from beta = 0.1: at beta = 0 they filter nothing).
fn loops() -> Vec<(&'static str, Loop, (f64, f64))> {
    let fast = Loop::new(Plant::new(0.0005, 1.5).unwrap())
        .with_hand(Hand::new(0.3, 0.002, 3e-4).unwrap())
        .and_then(|l| l.with_filter(VelocityFilter::low_pass_cutoff(30.0, 1e-3).unwrap()))
        .unwrap();
    let base = Loop::new(Plant::new(0.5, 1.0).unwrap());
    let tr = Transmission::new(0.2, 0.5, 0.05, 0.0, Encoder::Motor).unwrap();
    vec![
        ("hand+low-pass 1 ms", fast, (0.0, 0.01)),
        (
            "transmission+actuator",
            base.with_transmission(tr)
                .and_then(|l| l.with_actuator(Actuator::new(0.3).unwrap()))
                .unwrap(),
            (0.0, 2.0),
        ),
        (
            "moving average",
            base.with_filter(VelocityFilter::moving_average(4).unwrap())
                .unwrap(),
            (0.1, 2.0),
        ),
        (
            "second-order filter",
            base.with_filter(VelocityFilter::butterworth(0.1).unwrap())
                .unwrap(),
            (0.1, 2.0),
        ),
    ]
}

/// The verdicts of `lp` by the eigenvalues of its closed-loop state matrix.
fn state_space(lp: Loop) -> Checker {
    Checker::new(
        lp,
        Options {
            method: Method::StateSpace,
            ..Options::default()
        },
    )
    .unwrap()
}

/// The state-space spectral radius of `wall` on `lp`.
fn radius(checker: &Checker, alpha: f64, beta: f64) -> f64 {
    checker
        .analyze(&Wall::new(alpha, beta).unwrap())
        .unwrap()
        .spectral_radius
}

/// Each loop's enclosure holds its `alpha_max`; the walls `1e-7` and `1e-5` below the lower
/// end, at the certified damping, are stable by the eigenvalues, and at the upper end and 1 %
/// above it every damping of a 2001-point grid of the range is unstable.
#[test]
fn element_enclosures_agree_with_the_state_space_verdict() {
    for (name, lp, betas) in loops() {
        let opts = AmaxOptions::default()
            .with_beta_limits(Some(betas.0), Some(betas.1))
            .unwrap();
        let amax = alpha_max(lp, &opts).unwrap();
        let cert =
            certify_alpha_max(lp, &amax, betas, LEAVES).unwrap_or_else(|e| panic!("{name}: {e}"));
        let (lo, hi) = cert.bounds();
        println!("{name}: alpha_max {} in [{lo}, {hi}]", amax.alpha_max);
        assert!(lo <= amax.alpha_max && amax.alpha_max < hi, "{name}");
        assert_eq!(cert.dampings(), betas, "{name}");
        let checker = state_space(lp);
        let b = cert.beta_below();
        assert!(betas.0 <= b && b <= betas.1, "{name}");
        for s in [1e-7, 1e-5] {
            let r = radius(&checker, lo * (1.0 - s), b);
            assert!(r < 1.0, "{name}: {s} below alpha_lo: radius {r}");
        }
        for a in [hi, hi * 1.01] {
            for k in 0..=2000 {
                let beta = betas.0 + (betas.1 - betas.0) * f64::from(k) / 2000.0;
                let r = radius(&checker, a, beta);
                assert!(r > 1.0, "{name}: alpha {a} beta {beta}: radius {r}");
            }
        }
        let json = cert.to_json();
        assert!(json.contains("\"loop\": \"elements\""), "{name}");
    }
}

/// One certificate for a grid of rows holds each row's certificate, in order, and the
/// count of rows.
#[test]
fn rows_certificate_holds_every_row() {
    let opts = AmaxOptions::default()
        .with_beta_limits(Some(0.0), Some(2.0))
        .unwrap();
    let rows: Vec<AmaxCertificate> = [0.5, 1.0, 2.0]
        .iter()
        .map(|&delta| {
            let plant = Plant::new(delta, 1.0).unwrap();
            let amax = alpha_max(plant, &opts).unwrap();
            certify_alpha_max(plant, &amax, (0.0, 2.0), LEAVES).unwrap()
        })
        .collect();
    // a grid of one row is that row's own certificate, not a grid of one
    assert_eq!(AmaxCertificate::rows_json(&rows[..1]), rows[0].to_json());
    let json = AmaxCertificate::rows_json(&rows);
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(v["certificate"], "stabound certificate 2");
    assert_eq!(v["kind"], "alpha_max grid");
    assert_eq!(v["claim"]["rows"], 3);
    let listed = v["rows"].as_array().unwrap();
    assert_eq!(listed.len(), 3);
    for (row, cert) in listed.iter().zip(&rows) {
        let own: serde_json::Value = serde_json::from_str(&cert.to_json()).unwrap();
        let mut own = own.as_object().unwrap().clone();
        own.remove("crc32");
        assert_eq!(row, &serde_json::Value::Object(own));
    }
}

/// The upper end bounds every stiffer wall: on the paper's loop and on a loop with a
/// transmission and an actuator lag, the certificate proves no wall from `alpha_hi` on to be
/// stable (a cap and the box up to it), and by the state-space eigenvalues every one of 201
/// dampings of the range is unstable at 13 stiffnesses from `alpha_hi` to twice the cap
/// (geometric steps).
#[test]
fn upper_end_holds_for_every_stiffer_wall() {
    let base = Loop::new(Plant::new(0.5, 1.0).unwrap());
    let tr = Transmission::new(0.2, 0.5, 0.05, 0.0, Encoder::Motor).unwrap();
    let element = base
        .with_transmission(tr)
        .and_then(|l| l.with_actuator(Actuator::new(0.3).unwrap()))
        .unwrap();
    for (name, lp, betas) in [
        ("paper", base, (0.0, 1.0)),
        ("transmission+actuator", element, (0.0, 2.0)),
    ] {
        let opts = AmaxOptions::default()
            .with_beta_limits(Some(betas.0), Some(betas.1))
            .unwrap();
        let amax = alpha_max(lp, &opts).unwrap();
        let cert = certify_alpha_max(lp, &amax, betas, 16384).unwrap();
        assert!(cert.every_stiffer_wall(), "{name}");
        let (_, hi) = cert.bounds();
        let cap = cert.cap().unwrap();
        assert!(hi < cap && cap < 100.0 * hi, "{name}: {hi} {cap}");
        let json = cert.to_json();
        assert!(json.contains("\"stiffer\": \"none stable\""), "{name}");
        let checker = state_space(lp);
        for i in 0..=12 {
            let alpha = hi * (2.0 * cap / hi).powf(f64::from(i) / 12.0);
            for k in 0..=200 {
                let beta = betas.0 + (betas.1 - betas.0) * f64::from(k) / 200.0;
                let r = radius(&checker, alpha, beta);
                assert!(r > 1.0, "{name}: alpha {alpha} beta {beta}: radius {r}");
            }
        }
    }
}
