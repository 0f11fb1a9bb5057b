//! Certificates of loops with elements against the state-space verdict (the eigenvalues of
//! the closed loop's state matrix, built from the sampled device and the wall law, not from
//! the polynomial the certificate encloses).

use stabound::certificate::{Claim, certify};
use stabound::elements::{Actuator, Encoder, Hand, Loop, Transmission};
use stabound::filter::VelocityFilter;
use stabound::params::{Plant, Wall};
use stabound::stability::{Checker, Method, Options, Verdict};

/// Loops with each element and all of them, at whole and fractional delays.
fn loops() -> Vec<Loop> {
    let mut out = Vec::new();
    for (delta, d) in [(0.5, 1.0), (0.2, 2.5), (0.0, 0.25)] {
        let plant = Plant::new(delta, d).unwrap();
        let base = Loop::new(plant);
        let hand = Hand::new(0.3, 0.002, 3e-4).unwrap();
        let tr = |enc| Transmission::new(0.2, 0.02, 0.005, 0.0, enc).unwrap();
        out.extend([
            base.with_hand(hand).unwrap(),
            base.with_transmission(tr(Encoder::Motor)).unwrap(),
            base.with_transmission(tr(Encoder::Handle)).unwrap(),
            base.with_actuator(Actuator::new(0.5).unwrap()).unwrap(),
            base.with_filter(VelocityFilter::low_pass(0.83).unwrap())
                .unwrap(),
            base.with_filter(VelocityFilter::moving_average(4).unwrap())
                .unwrap(),
            base.with_filter(VelocityFilter::butterworth(0.05).unwrap())
                .unwrap(),
            base.with_hand(hand)
                .and_then(|l| l.with_transmission(tr(Encoder::Motor)))
                .and_then(|l| l.with_actuator(Actuator::new(0.2).unwrap()))
                .and_then(|l| l.with_filter(VelocityFilter::butterworth(0.1).unwrap()))
                .unwrap(),
        ]);
    }
    out
}

/// On a grid of walls from deep inside to far outside the stable region, every certificate
/// agrees with the state-space verdict where that verdict is clear (spectral radius farther
/// than 1e-6 from 1). Most such walls are certified; the rest are refused (`f64` intervals
/// lose the decision where the device has lightly damped roots near the circle, see
/// `docs/MODEL.md` section 11), never certified wrongly.
#[test]
fn element_certificates_agree_with_the_state_space_verdict() {
    let mut counts = [0usize; 3];
    for lp in loops() {
        let checker = Checker::new(
            lp,
            Options {
                method: Method::StateSpace,
                ..Options::default()
            },
        )
        .unwrap();
        for alpha in [-0.01, 0.0005, 0.005, 0.05, 0.5, 5.0] {
            for beta in [-0.3, 0.01, 0.2, 1.0] {
                let wall = Wall::new(alpha, beta).unwrap();
                let a = checker.analyze(&wall).unwrap();
                if (a.spectral_radius - 1.0).abs() < 1e-6 {
                    continue;
                }
                let Ok(cert) = certify(lp, &wall, 1e-9) else {
                    counts[2] += 1;
                    continue;
                };
                let outside = a.roots.iter().filter(|z| z.norm() > 1.0).count();
                match cert.claim() {
                    Claim::Stable => {
                        assert_eq!(a.verdict, Verdict::Stable, "{lp:?} {wall:?}");
                        counts[0] += 1;
                    }
                    Claim::Unstable { outside: k } => {
                        assert_eq!(k, outside, "{lp:?} {wall:?}");
                        counts[1] += 1;
                    }
                    other => panic!("{lp:?} {wall:?}: {other:?}"),
                }
            }
        }
    }
    // both verdicts occur often, refusals are rare
    assert!(counts[0] > 50 && counts[1] > 50, "{counts:?}");
    assert!(counts[2] * 10 < counts[0] + counts[1], "{counts:?}");
}
