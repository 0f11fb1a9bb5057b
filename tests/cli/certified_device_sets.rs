//! `check --certify` and `amax --certify` over a finite set of devices whose members differ
//! in mass, damping or delay: every member stated in the normalization of the set's reference
//! (smallest) mass, a member of another mass with its mass and the reference mass, which the
//! standalone checker (`tools/verify_certificate.py`) scales exactly. Each member's verdict is
//! judged independently by the eigenvalues of its own closed-loop state matrix
//! ([`crate::robust_sets::stable`], its own normalization); a certificate with a member's
//! device, the wall or the claim changed is rejected.

use std::path::Path;

use crate::amax_certify::certified;
use crate::certified_sets::enclosure;
use crate::certified_table::{from_hex, rejected_after, verify};
use crate::common::{assert_bad_input, csv};
use crate::robust_sets::stable;
use stabound::elements::PhysicalElements;
use stabound::params::{Delay, Device};

/// Masses 0.09 or 0.11 kg, dampings 0.2 or 0.5 N s/m and delays of 1 or 2 samples at 1 ms:
/// eight members, in the certificate's order (mass outermost, then damping, then delay).
const SET: [&str; 8] = [
    "--mass",
    "one-of:0.09,0.11",
    "--period",
    "0.001",
    "--damping",
    "one-of:0.2,0.5",
    "--delay-samples",
    "one-of:1,2",
];

/// Masses 0.09 or 0.11 kg, 0.5 N s/m, one sample of delay at 1 ms.
const TWO_MASSES: [&str; 8] = [
    "--mass",
    "one-of:0.09,0.11",
    "--period",
    "0.001",
    "--damping",
    "0.5",
    "--delay-samples",
    "1",
];

/// Runs the checker on the certificate at `path`: it must accept it and say `says`.
fn accepted(path: &Path, says: &str) {
    let (code, out, err) = verify(path);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains(says), "{out}");
}

/// The members of [`SET`] in the certificate's order.
fn members() -> Vec<Device> {
    let mut out = Vec::new();
    for m in [0.09, 0.11] {
        for b in [0.2, 0.5] {
            for d in [1.0, 2.0] {
                out.push(Device::new(m, 0.001, b, Delay::Samples(d)).unwrap());
            }
        }
    }
    out
}

/// Runs `check` on [`SET`] at the wall `(k, 1 N s/m)` with `--certify path`: the
/// certificate as JSON.
fn check_set(k: f64, path: &Path) -> serde_json::Value {
    let ks = k.to_string();
    let mut args = vec!["check"];
    args.extend(SET);
    args.extend(["--stiffness", &ks, "--wall-damping", "1"]);
    certified(&args, path);
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// Three walls on the eight members: at 300 N/m every member is stable by eigenvalues, at
/// 600 and 1,000 N/m some are not. Each member's certified verdict is its verdict by
/// eigenvalues, the set's claim is the first unstable member (or stable), the set names the
/// masses, dampings and delays, a member of the heavier mass carries its mass and the
/// reference mass, and the checker accepts each certificate.
#[test]
fn members_of_other_masses_dampings_and_delays_are_certified() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("set.json");
    let devices = members();
    let mut unstable_seen = 0;
    for k in [300.0, 600.0, 1000.0] {
        let cert = check_set(k, &path);
        let set = &cert["set"];
        let listed = |key: &str| -> Vec<f64> {
            set[key]
                .as_array()
                .unwrap()
                .iter()
                .map(|x| from_hex(x.as_str().unwrap()))
                .collect()
        };
        assert_eq!(listed("mass"), [0.09, 0.11], "{set}");
        assert_eq!(listed("d"), [1.0, 2.0], "{set}");
        // the dampings in the reference normalization, b T / m_ref
        let deltas = listed("delta");
        for (got, b) in deltas.iter().zip([0.2, 0.5]) {
            assert!((got - b * 0.001 / 0.09).abs() <= 1e-15, "{got} {b}");
        }
        let ms = cert["members"].as_array().unwrap();
        assert_eq!(ms.len(), 8);
        let mut first_unstable = None;
        for (i, (m, dev)) in ms.iter().zip(&devices).enumerate() {
            let inputs = &m["inputs"];
            assert_eq!(from_hex(inputs["mass"].as_str().unwrap()), dev.mass());
            assert_eq!(from_hex(inputs["reference_mass"].as_str().unwrap()), 0.09);
            let eig = stable(dev, &PhysicalElements::default(), k, 1.0);
            let verdict = m["claim"]["verdict"].as_str().unwrap();
            assert_eq!(verdict == "stable", eig, "{k} N/m, member {i}: {verdict}");
            if !eig {
                assert_eq!(verdict, "unstable", "{k} N/m, member {i}");
                first_unstable.get_or_insert(i);
                unstable_seen += 1;
            }
        }
        let says = match first_unstable {
            None => {
                assert_eq!(cert["claim"]["verdict"], "stable");
                "stable for each of the set's 8 devices".to_string()
            }
            Some(i) => {
                assert_eq!(cert["claim"]["verdict"], "unstable");
                assert_eq!(cert["claim"]["member"], i);
                format!("unstable for the set of 8 devices: member {i}")
            }
        };
        accepted(&path, &says);
    }
    assert!(unstable_seen > 0, "some member unstable at some wall");
}

/// The certificate of the wall at 600 N/m, changed (its CRC made to match again): the
/// heavier mass changed in the set and in its members alike (their proofs no longer hold),
/// the reference mass of every member, the wall of every member, and the claim's verdict are
/// each rejected by the proof; one member's mass or wall alone by the set's structure.
#[test]
fn a_changed_device_wall_or_claim_is_rejected() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("set.json");
    check_set(600.0, &path);
    let original = std::fs::read_to_string(&path).unwrap();
    let rewrite = |edit: &str| {
        format!("\ncert = json.loads(text)\n{edit}\nbody = json.dumps(cert, indent=2) + \"\\n\"")
    };
    // 0.11 kg becomes 0.125 kg: a changed digit of the device, consistently everywhere
    let heavier = r#"
old, new = cert['set']['mass'][1], '0x1p-3'
cert['set']['mass'][1] = new
for m in cert['members']:
    if m['inputs']['mass'] == old:
        m['inputs']['mass'] = new"#;
    let every = |key: &str, value: &str| {
        format!("\nfor m in cert['members']:\n    m['inputs']['{key}'] = '{value}'")
    };
    let cases = [
        (heavier.to_string(), "a claimed ball does not hold"),
        (
            every("reference_mass", "0x1.47ae147ae147bp-4"),
            "a claimed ball does not hold",
        ),
        (every("alpha", "0x1p-1"), "a claimed ball does not hold"),
        (
            "cert['claim']['verdict'] = 'stable'; del cert['claim']['member']".into(),
            "the members prove unstable",
        ),
        (
            "cert['members'][5]['inputs']['mass'] = '0x1.999999999999ap-4'".into(),
            "member 5: a claimed ball does not hold",
        ),
        (
            "cert['members'][5]['inputs']['alpha'] = '0x1p-1'".into(),
            "member 5: a claimed ball does not hold",
        ),
    ];
    for (edit, why) in cases {
        let err = rejected_after(&path, &rewrite(&edit));
        assert!(err.contains(why), "{edit}: {err}");
        std::fs::write(&path, &original).unwrap();
    }
    // a heavier reference mass than a member's is refused (the scale is at most 1)
    let err = rejected_after(
        &path,
        &rewrite(&every("reference_mass", "0x1.999999999999ap-3")),
    );
    assert!(err.contains("a mass at least the reference mass"), "{err}");
}

/// The robust alpha_max over two masses and a 0.3 kg hand that can let go (four members),
/// dampings 0 to 40 N s/m: the enclosure holds the row's K_max; by eigenvalues every member
/// is stable at its lower end (with the optimum's damping), and at its upper end every
/// damping of a grid of 41 has a member unstable. The checker accepts the certificate.
#[test]
fn amax_over_masses_and_a_hand_that_lets_go_is_certified() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("amax.json");
    let mut args = vec!["amax"];
    args.extend(TWO_MASSES);
    args.extend([
        "--hand-mass",
        "0.3",
        "--hand-damping",
        "2",
        "--hand-stiffness",
        "300",
    ]);
    args.extend(["--wall-damping-min", "0", "--wall-damping-max", "40"]);
    let (out, _) = certified(&args, &path);
    let (head, rows) = csv(&out);
    let col = |name: &str| -> f64 {
        let i = head.split(',').position(|c| c == name).unwrap();
        rows[0][i].parse().unwrap()
    };
    let (k_lo, k_hi, _, b) = enclosure(&col);
    let mut hand = PhysicalElements::default();
    hand.hand_mass = Some(0.3);
    hand.hand_damping = Some(2.0);
    hand.hand_stiffness = Some(300.0);
    let mut members = Vec::new();
    for m in [0.09, 0.11] {
        let dev = Device::new(m, 0.001, 0.5, Delay::Samples(1.0)).unwrap();
        members.push((dev, hand));
        members.push((dev, PhysicalElements::default()));
    }
    for (dev, el) in &members {
        assert!(stable(dev, el, k_lo, b), "{dev:?} {el:?} at K_lo");
    }
    for i in 0..=40 {
        let bw = f64::from(i);
        assert!(
            members.iter().any(|(dev, el)| !stable(dev, el, k_hi, bw)),
            "B = {bw} at K_hi"
        );
    }
    accepted(&path, "robust alpha_max of the set's 4 devices");
}

/// A certified table over devices of several masses is refused as bad input before any
/// file is written (its walls are one mass's), and so is an interval of masses.
#[test]
fn tables_over_masses_and_mass_intervals_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("c.json");
    let p = path.to_str().unwrap();
    let mut table = vec!["table"];
    table.extend(TWO_MASSES);
    table[6] = "0:1:3";
    table.extend(["--conservative", "--certify", p]);
    // a note on the set comes before the one line of the error
    let err = assert_bad_input(&table, false);
    assert!(err.contains("certify a table for each mass"), "{err}");
    let mut interval = vec!["check"];
    interval.extend(TWO_MASSES);
    interval[2] = "0.09..0.11";
    interval.extend(["--stiffness", "300", "--wall-damping", "1", "--certify", p]);
    assert_bad_input(&interval, true);
    assert!(!path.exists());
}
