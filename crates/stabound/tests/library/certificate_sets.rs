//! Certified verdicts over a finite set of devices (a hand that can let go), against the
//! eigenvalues of each member's closed-loop state matrix (nalgebra's Schur form, not the
//! Schur-Cohn recursion the certificates replay): a wall certified stable for the set is
//! stable for the hand on and off, a wall certified unstable is unstable for the member the
//! certificate names, and the robust `alpha_max`'s enclosure holds a wall stable for both at
//! its lower end and none stable for the binding member at its upper end (or, where members'
//! limits cross, none stable for the member of each piece of the damping range).

use stabound::certificate::{SetAmaxCertificate, SetClaim, certify_set, certify_set_alpha_max};
use stabound::elements::{Loop, PhysicalElements};
use stabound::params::{Delay, Device, Wall};
use stabound::robust::{DeviceSet, Quantity, RobustAmax, robust_alpha_max};
use stabound::stability::{Checker, Options};
use stabound::{AmaxOptions, alpha_max};

/// The 0.1 kg device at 1 ms with one sample of delay behind a 50 Hz velocity filter, held
/// by a 0.3 kg hand of 2 N s/m and 300 N/m that can let go: the hand on and the hand off.
fn hand_set() -> (Device, DeviceSet, [PhysicalElements; 2]) {
    let device = Device::new(0.1, 0.001, 0.0, Delay::Samples(1.0)).unwrap();
    let mut free = PhysicalElements::default();
    free.velocity_filter_cutoff = Some(50.0);
    let mut held = free;
    held.hand_mass = Some(0.3);
    held.hand_damping = Some(2.0);
    held.hand_stiffness = Some(300.0);
    let set = DeviceSet::new(&device, &held).unwrap();
    (device, set, [held, free])
}

/// Whether every eigenvalue of the loop's closed-loop state matrix under `wall` is inside
/// the unit circle.
fn stable(device: &Device, named: &PhysicalElements, wall: &Wall) -> bool {
    let lp = Loop::physical(device, named).unwrap();
    let m = Checker::new(lp, Options::default())
        .unwrap()
        .state_matrix(wall);
    let schur = m.try_schur(1e-14, 10_000).expect("Schur form converges");
    schur.complex_eigenvalues().iter().all(|z| z.norm() < 1.0)
}

/// The member named `name` ("hand on" or "hand off").
fn member<'a>(name: &str, members: &'a [PhysicalElements; 2]) -> &'a PhysicalElements {
    match name {
        "hand on" => &members[0],
        "hand off" => &members[1],
        other => panic!("no member {other}"),
    }
}

/// Stiffnesses from 500 to 16,000 N/m at 5 N s/m: each certified verdict for the set is the
/// eigenvalues' verdict for both members (stable for both, or unstable for the member
/// named), and both verdicts occur.
#[test]
fn set_verdicts_match_each_members_eigenvalues() {
    let (device, set, members) = hand_set();
    let mut seen = (false, false);
    for k in [500.0, 2000.0, 4000.0, 8000.0, 16000.0] {
        let wall = device.wall(k, 5.0).unwrap();
        let cert = certify_set(&set, &wall, 1e-9).unwrap();
        assert_eq!(cert.members(), 2);
        let both = members.iter().all(|m| stable(&device, m, &wall));
        match cert.claim() {
            SetClaim::Stable => {
                assert!(both, "K = {k}: certified stable for the set");
                seen.0 = true;
            }
            SetClaim::Unstable { member: i } => {
                let name = cert.member(i).unwrap();
                assert!(
                    !stable(&device, member(name, &members), &wall),
                    "K = {k}: {name} certified unstable"
                );
                seen.1 = true;
            }
            other => panic!("K = {k}: {other:?}"),
        }
        assert!(cert.to_json().contains("\"kind\": \"set\""));
    }
    assert_eq!(seen, (true, true), "both verdicts occur");
}

/// The robust `alpha_max` of `set` over the dampings `betas` and its certificate (16,384
/// leaves a proof), with the search's options.
fn certified(set: &DeviceSet, betas: (f64, f64)) -> (AmaxOptions, RobustAmax, SetAmaxCertificate) {
    let opts = AmaxOptions::default()
        .with_beta_limits(Some(betas.0), Some(betas.1))
        .unwrap();
    let r = robust_alpha_max(set, &opts).unwrap();
    let cert = certify_set_alpha_max(set, (r.alpha_max, r.beta_at_max), betas, 16_384).unwrap();
    (opts, r, cert)
}

/// The robust `alpha_max` of the hand that can let go, dampings 0 to 1: its enclosure holds
/// the search's optimum; the wall at the lower end is stable for both members by
/// eigenvalues, and at the upper end no damping of a grid of 201 over the range is stable
/// for the binding member.
#[test]
fn robust_enclosure_holds_against_eigenvalues() {
    let (device, set, members) = hand_set();
    let betas = (0.0, 1.0);
    let (_, r, cert) = certified(&set, betas);
    let (lo, hi) = cert.bounds();
    assert!(
        lo <= r.alpha_max && r.alpha_max < hi,
        "{lo} {} {hi}",
        r.alpha_max
    );
    assert_eq!(cert.members(), 2);
    let below = Wall::new(lo, r.beta_at_max).unwrap();
    for m in &members {
        assert!(stable(&device, m, &below), "{m:?} at alpha_lo");
    }
    let binding = member(cert.binding(), &members);
    for i in 0..=200 {
        let beta = betas.0 + (betas.1 - betas.0) * f64::from(i) / 200.0;
        let wall = Wall::new(hi, beta).unwrap();
        assert!(
            !stable(&device, binding, &wall),
            "beta = {beta} at alpha_hi"
        );
    }
}

/// The 0.1 kg device at 1 ms with one sample of delay behind a compliant transmission (a
/// 0.02 kg handle, 1 N s/m of coupling damping) whose coupling stiffness is 2,000 or 5,000
/// N/m: the stiffer coupling binds at low damping, the softer one at high damping, so the
/// robust optimum lies where their limits cross. The members, 2,000 N/m first.
fn crossing_set() -> (Device, DeviceSet, [PhysicalElements; 2]) {
    let device = Device::new(0.1, 0.001, 0.0, Delay::Samples(1.0)).unwrap();
    let mut e = PhysicalElements::default();
    e.handle_mass = Some(0.02);
    e.transmission_damping = Some(1.0);
    e.transmission_stiffness = Some(2000.0);
    let set = DeviceSet::new(&device, &e)
        .unwrap()
        .with_values(
            Quantity::element("transmission_stiffness").unwrap(),
            &[2000.0, 5000.0],
        )
        .unwrap();
    let mut stiff = e;
    stiff.transmission_stiffness = Some(5000.0);
    (device, set, [e, stiff])
}

/// Where the two members' limits cross (dampings 0 to 1): each member's own `alpha_max` over
/// the range lies above the certified `alpha_hi` (so neither alone is unstable there at every
/// damping) and the proof comes in pieces of both members, meeting end to end over the range.
/// Against the eigenvalues: both members stable at the lower end; at `alpha_hi` and stiffer
/// (1, 1.01, 1.1 and 2 times it) the member of each piece unstable at 41 dampings across
/// it, so every damping of a grid over the range has a member unstable.
#[test]
fn crossing_limits_are_certified_in_pieces() {
    let (device, set, members) = crossing_set();
    let betas = (0.0, 1.0);
    let (opts, r, cert) = certified(&set, betas);
    let (lo, hi) = cert.bounds();
    assert!(lo <= r.alpha_max && r.alpha_max < hi);
    // the enclosure is the nearest step above: 1e-4 of alpha_max
    assert!(hi <= r.alpha_max * (1.0 + 1.001e-4), "{hi} {}", r.alpha_max);
    assert!(cert.every_stiffer_wall());
    for m in &members {
        let own = alpha_max(Loop::physical(&device, m).unwrap(), &opts).unwrap();
        assert!(own.alpha_max > hi, "{m:?}: {} alone", own.alpha_max);
        assert!(stable(&device, m, &Wall::new(lo, r.beta_at_max).unwrap()));
    }
    let pieces = cert.pieces();
    assert!(pieces.len() >= 2, "{pieces:?}");
    // exact: the pieces' ends are the range's ends and each other's
    assert_eq!((pieces[0].0, pieces[pieces.len() - 1].1), betas);
    assert!(pieces.windows(2).all(|w| w[0].1 == w[1].0), "{pieces:?}");
    let named: Vec<&str> = pieces.iter().map(|p| p.2).collect();
    assert!(named.iter().any(|n| n.contains("2000")), "{named:?}");
    assert!(named.iter().any(|n| n.contains("5000")), "{named:?}");
    for (b0, b1, name) in pieces {
        let m = if name.contains("5000") {
            &members[1]
        } else {
            &members[0]
        };
        for i in 0..=40 {
            let beta = b0 + (b1 - b0) * f64::from(i) / 40.0;
            for s in [1.0, 1.01, 1.1, 2.0] {
                let wall = Wall::new(hi * s, beta).unwrap();
                assert!(!stable(&device, m, &wall), "{name} at {s} alpha_hi, {beta}");
            }
        }
    }
}

/// A hand that can let go on a device of 0.09 or 0.11 kg (0.5 N s/m, one sample of delay at
/// 1 ms), stiffnesses from 200 to 3,000 N/m at 1 N s/m: the wall is given in the reference
/// (0.09 kg) normalization, and each member judged by the eigenvalues of its own loop under
/// the same physical wall. Each certified verdict for the set is theirs (stable for all four,
/// or unstable for the member named), both verdicts occur, and each member's certificate of
/// the heavier mass states its mass and the reference mass.
#[test]
fn set_verdicts_over_masses_match_each_members_eigenvalues() {
    let mut held = PhysicalElements::default();
    held.hand_mass = Some(0.3);
    held.hand_damping = Some(2.0);
    held.hand_stiffness = Some(300.0);
    let device = |m: f64| Device::new(m, 0.001, 0.5, Delay::Samples(1.0)).unwrap();
    let set = DeviceSet::new(&device(0.09), &held)
        .unwrap()
        .with_values(Quantity::Mass, &[0.09, 0.11])
        .unwrap();
    // a member's device and elements from its name ("mass = 0.11 kg; hand off")
    let own = |name: &str| {
        let mass = if name.contains("mass = 0.11 kg") {
            0.11
        } else {
            0.09
        };
        let el = if name.contains("hand on") {
            held
        } else {
            PhysicalElements::default()
        };
        (device(mass), el)
    };
    let mut seen = (false, false);
    for k in [200.0, 800.0, 1500.0, 3000.0] {
        let cert = certify_set(&set, &device(0.09).wall(k, 1.0).unwrap(), 1e-9).unwrap();
        assert_eq!(cert.members(), 4);
        let verdicts: Vec<bool> = (0..4)
            .map(|i| {
                let (d, el) = own(cert.member(i).unwrap());
                stable(&d, &el, &d.wall(k, 1.0).unwrap())
            })
            .collect();
        match cert.claim() {
            SetClaim::Stable => {
                assert!(verdicts.iter().all(|&v| v), "K = {k}: {verdicts:?}");
                seen.0 = true;
            }
            SetClaim::Unstable { member: i } => {
                assert!(!verdicts[i], "K = {k}: member {i} certified unstable");
                seen.1 = true;
            }
            other => panic!("K = {k}: {other:?}"),
        }
        let json = cert.to_json();
        assert!(json.contains("\"reference_mass\": \"0x1.70a3d70a3d70ap-4\""));
        assert!(json.contains("\"mass\": \"0x1.c28f5c28f5c29p-4\""));
    }
    assert_eq!(seen, (true, true), "both verdicts occur");
}
