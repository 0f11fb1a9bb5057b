//! Certified boxes of walls on loops with elements at fast sampling (1 ms, a hand and a
//! low-pass velocity filter): narrow boxes are decided around their centre, boxes across
//! the boundary are not claimed, and every decided leaf agrees with the state-space
//! verdict (the eigenvalues of the closed loop's state matrix, not the polynomial the
//! certificate encloses) at seeded random walls inside it.

use serde_json::Value;
use stabound::certificate::{BoxClaim, WallBox, certify_box};
use stabound::elements::{Hand, Loop};
use stabound::filter::VelocityFilter;
use stabound::params::{Plant, Wall};
use stabound::stability::{Checker, Method, Options};

/// 1 kg, b = 0.5 N s/m, T = 1 ms, 1.5 samples of delay; a 0.3 kg hand with 2 N s/m and
/// 300 N/m; a first-order low-pass at 30 Hz (`alpha = K T^2 / m`, `beta = B T / m`).
fn fast_loop() -> Loop {
    let plant = Plant::new(0.0005, 1.5).unwrap();
    Loop::new(plant)
        .with_hand(Hand::new(0.3, 0.002, 3e-4).unwrap())
        .and_then(|l| l.with_filter(VelocityFilter::low_pass_cutoff(30.0, 1e-3).unwrap()))
        .unwrap()
}

fn walls(k: (f64, f64), b: (f64, f64)) -> WallBox {
    let wall = |k: f64, b: f64| Wall::new(k * 1e-6, b * 1e-3).unwrap();
    WallBox::new(wall(k.0, b.0), wall(k.1, b.1)).unwrap()
}

fn hex(v: &Value) -> f64 {
    let s = v.as_str().unwrap();
    let (neg, s) = s.strip_prefix('-').map_or((false, s), |r| (true, r));
    let (mant, exp) = s.strip_prefix("0x").unwrap().split_once('p').unwrap();
    let (int, frac) = mant.split_once('.').unwrap_or((mant, ""));
    let bits = u64::from_str_radix(&format!("{int}{frac:0<13}"), 16).unwrap();
    let x = bits as f64 * 2f64.powi(exp.parse::<i32>().unwrap() - 52);
    if neg { -x } else { x }
}

/// Seeded uniform numbers in [0, 1) (xorshift64*).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Every decided leaf of `json` against the eigenvalues at its corners, its centre and
/// `random` seeded walls inside it, where the spectral radius is farther than 1e-9 from 1
/// (closer, `f64` eigenvalues do not decide). Returns (leaves decided around their centre,
/// walls compared).
fn leaves_agree(lp: Loop, json: &str, random: usize) -> (usize, usize) {
    let cert: Value = serde_json::from_str(json).unwrap();
    let checker = Checker::new(
        lp,
        Options {
            method: Method::StateSpace,
            ..Options::default()
        },
    )
    .unwrap();
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let (mut around, mut compared) = (0, 0);
    for leaf in cert["leaves"].as_array().unwrap() {
        let claim = leaf["claim"].as_str().unwrap();
        if claim == "undecided" {
            continue;
        }
        around += usize::from(leaf.get("arcs").is_some());
        let side = |k: &str| (hex(&leaf["box"][k][0]), hex(&leaf["box"][k][1]));
        let ((a0, a1), (b0, b1)) = (side("alpha"), side("beta"));
        let mut points = vec![(a0, b0), (a0, b1), (a1, b0), (a1, b1)];
        points.extend(
            (0..random).map(|_| (a0 + (a1 - a0) * rng.next(), b0 + (b1 - b0) * rng.next())),
        );
        for (a, b) in points {
            let an = checker.analyze(&Wall::new(a, b).unwrap()).unwrap();
            if (an.spectral_radius - 1.0).abs() < 1e-9 {
                continue;
            }
            compared += 1;
            let outside = an.roots.iter().filter(|z| z.norm() > 1.0).count();
            match claim {
                "stable" => assert_eq!(outside, 0, "{a} {b}: {}", an.spectral_radius),
                _ => assert_eq!(outside as u64, leaf["outside"].as_u64().unwrap(), "{a} {b}"),
            }
        }
    }
    (around, compared)
}

/// A box of relative width 1e-5 in K and 5e-3 in B near K = 900 N/m, B = 2 N s/m: one
/// leaf, decided around its centre (the interval recursion over the box stays undecided
/// in 1024 leaves), and its claim holds at random walls inside.
#[test]
fn narrow_box_at_fast_sampling_is_decided() {
    let b = walls((900.0, 900.01), (2.0, 2.01));
    let cert = certify_box(fast_loop(), &b, 1024).unwrap();
    assert_eq!(cert.claim(), BoxClaim::Stable);
    assert_eq!(cert.counts(), (1, 0, 0));
    let (around, compared) = leaves_agree(fast_loop(), &cert.to_json(), 200);
    assert_eq!((around, compared), (1, 204));
}

/// Boxes across the boundary (near K = 2150 N/m at B = 2 N s/m) are never claimed either
/// way, and their decided leaves, on both sides, agree with the eigenvalues; boxes wholly
/// on one side are decided for the whole box.
#[test]
fn boxes_across_the_boundary_are_not_claimed() {
    for (k, b) in [
        ((2000.0, 4000.0), (2.0, 2.5)),
        ((100.0, 9000.0), (0.0, 10.0)),
    ] {
        let cert = certify_box(fast_loop(), &walls(k, b), 256).unwrap();
        assert_eq!(cert.claim(), BoxClaim::NotProved, "{k:?} {b:?}");
        let (stable, unstable, _) = cert.counts();
        assert!(stable > 0 && unstable > 0, "{:?}", cert.counts());
        let (around, compared) = leaves_agree(fast_loop(), &cert.to_json(), 3);
        assert!(
            around > 0 && compared > 4 * (stable + unstable),
            "{around} {compared}"
        );
    }
    for (k, want) in [
        ((1000.0, 1500.0), BoxClaim::Stable),
        ((4000.0, 4500.0), BoxClaim::Unstable),
    ] {
        let cert = certify_box(fast_loop(), &walls(k, (2.0, 3.0)), 256).unwrap();
        assert_eq!(cert.claim(), want, "{k:?}");
        let (around, _) = leaves_agree(fast_loop(), &cert.to_json(), 20);
        assert!(around > 0);
    }
}
