//! End-to-end tests of `stabound scene`: the example scene's golden output, JSON output, and
//! malformed scenes (exit 2, one clear line naming the place).
//!
//! Regenerate the golden file after an intended change with
//! `cargo run --release -- scene data/scenes/NAME.toml -o data/scenes/NAME.txt` (NAME
//! `phantom` and `phantom_filtered`)
//! and check the diff by eye.

use predicates::prelude::*;
use std::path::PathBuf;

use crate::common::stabound;

fn data(p: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(p)
}

/// The golden files were checked by eye against the paper: in `phantom.txt` the three
/// "paper walls" (Section VIII: 75 % of alpha_max at the damping of alpha_max) show stiffness
/// margins of 0.75 to the paper's three printed digits, and the unstable walls are reported
/// unstable; in `phantom_filtered.txt` the paper's wall is unstable behind either velocity
/// filter and 75 % of the filtered K_max is stable with a margin of 0.75.
#[test]
fn golden_text() {
    for name in ["phantom", "phantom_filtered"] {
        let out = stabound()
            .args(["scene"])
            .arg(data(&format!("data/scenes/{name}.toml")))
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let want = std::fs::read_to_string(data(&format!("data/scenes/{name}.txt"))).unwrap();
        let got = String::from_utf8(out.stdout).unwrap();
        assert_eq!(got, want, "output differs from data/scenes/{name}.txt");
    }
}

/// The filtered example: each device's K_max is the one `amax` finds for the same filtered
/// loop, and each wall's verdict is the one `check` gives it.
#[test]
fn filtered_example_agrees_with_amax_and_check() {
    let out = stabound()
        .args(["scene", "--format", "json"])
        .arg(data("data/scenes/phantom_filtered.toml"))
        .output()
        .unwrap();
    assert!(out.status.success());
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let devices = v["devices"].as_array().unwrap();
    assert_eq!(devices.len(), 2);
    for (dev, cutoff) in devices.iter().zip(["31.8", "3.18"]) {
        let device = [
            "--mass",
            "0.1",
            "--period",
            "0.001",
            "--damping",
            "0",
            "--delay-samples",
            "1",
            "--velocity-filter-cutoff",
            cutoff,
        ];
        let rows = crate::common::json(&[&["amax"][..], &device, &["--format", "json"]].concat());
        let k_max = rows[0]["K_max_N_per_m"].as_f64().unwrap();
        let got = dev["max_stiffness"]["K_max_N_per_m"].as_f64().unwrap();
        assert!((got - k_max).abs() <= 1e-6 * k_max, "{got} vs {k_max}");
        for w in dev["walls"].as_array().unwrap() {
            let (k, b) = (
                w["stiffness_N_per_m"].as_f64().unwrap(),
                w["wall_damping_Ns_per_m"].as_f64().unwrap(),
            );
            let c = crate::common::json(
                &[
                    &["check", "--format", "json"][..],
                    &device,
                    &[
                        "--stiffness",
                        &k.to_string(),
                        "--wall-damping",
                        &b.to_string(),
                    ],
                ]
                .concat(),
            );
            assert_eq!(c["verdict"], w["verdict"], "{w}");
        }
    }
}

/// The paper's Section VIII walls sit at 75 % of alpha_max (docs/MODEL.md section 6), so their
/// margin K / K_lim at the damping of alpha_max is 0.75 to the 3 digits the paper gives.
#[test]
fn json_paper_margins() {
    let out = stabound()
        .args(["scene", "--format", "json"])
        .arg(data("data/scenes/phantom.toml"))
        .output()
        .unwrap();
    assert!(out.status.success());
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let devices = v["devices"].as_array().unwrap();
    assert_eq!(devices.len(), 3);
    for (dev, delta) in devices.iter().zip([0.0, 0.1, 1.0]) {
        assert!((dev["delta"].as_f64().unwrap() - delta).abs() < 1e-12);
        assert_eq!(dev["d"].as_f64().unwrap(), 1.0);
        let paper = &dev["walls"][0];
        assert_eq!(paper["verdict"], "stable");
        let m = paper["stiffness_margin"].as_f64().unwrap();
        // alpha is printed to 3 digits in the paper: 0.108/0.1445 = 0.7474, so +-0.004.
        assert!((m - 0.75).abs() < 4e-3, "{m}");
        let kinds: Vec<&str> = dev["walls"]
            .as_array()
            .unwrap()
            .iter()
            .map(|w| w["verdict"].as_str().unwrap())
            .collect();
        assert_eq!(kinds, ["stable", "stable", "unstable"]);
    }
}

#[test]
fn json_input_gives_the_same_report() {
    let dir = tempfile::tempdir().unwrap();
    let json = dir.path().join("s.json");
    std::fs::write(
        &json,
        r#"{"device": [{"name": "PHANToM-like, b = 0", "mass_kg": 0.1, "period_s": 0.001,
            "damping_Ns_per_m": 0, "delay_samples": 1,
            "wall": [{"name": "w", "stiffness_N_per_m": 10800, "damping_Ns_per_m": 42.5}]}]}"#,
    )
    .unwrap();
    let toml = dir.path().join("s.toml");
    std::fs::write(
        &toml,
        "[[device]]\nname = \"PHANToM-like, b = 0\"\nmass_kg = 0.1\nperiod_s = 0.001\n\
         damping_Ns_per_m = 0\ndelay_s = 0.001\n[[device.wall]]\nname = \"w\"\n\
         stiffness_N_per_m = 10800\ndamping_Ns_per_m = 42.5\n",
    )
    .unwrap();
    let a = stabound().arg("scene").arg(&json).output().unwrap();
    let b = stabound().arg("scene").arg(&toml).output().unwrap();
    assert!(a.status.success() && b.status.success());
    assert_eq!(a.stdout, b.stdout);
}

#[test]
fn output_file() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("r.json");
    stabound()
        .args(["scene", "--format", "json", "-o"])
        .arg(&p)
        .arg(data("data/scenes/phantom.toml"))
        .assert()
        .success()
        .stdout("");
    let v: serde_json::Value = serde_json::from_slice(&std::fs::read(&p).unwrap()).unwrap();
    assert_eq!(v["devices"].as_array().unwrap().len(), 3);
}

const DEVICE: &str =
    "[[device]]\nmass_kg = 0.1\nperiod_s = 0.001\ndamping_Ns_per_m = 0\ndelay_samples = 1\n";

/// Each malformed scene: exit 2, nothing on stdout, one line on stderr naming the file, the
/// line, and what to write instead.
#[test]
fn malformed_scenes_exit_2() {
    let wall = "[[device.wall]]\nstiffness_N_per_m = 5000\ndamping_Ns_per_m = 20\n";
    let cases: Vec<(&str, String, &[&str])> = vec![
        (
            "missing field",
            format!("{DEVICE}[[device.wall]]\nstiffness_N_per_m = 5000\n"),
            &["line 6", "missing field `damping_Ns_per_m`"],
        ),
        (
            "negative mass",
            DEVICE.replace("mass_kg = 0.1", "mass_kg = -0.1"),
            &["line 2", "mass_kg = -0.1", "greater than 0"],
        ),
        (
            "unknown key",
            format!("{DEVICE}colour = \"red\"\n{wall}"),
            &["line 6", "unknown field `colour`", "expected one of"],
        ),
        (
            "missing unit",
            DEVICE.replace("mass_kg", "mass"),
            &["line 2", "`mass` has no unit", "mass_kg"],
        ),
        (
            "wrong unit",
            format!(
                "{DEVICE}{}",
                wall.replace("stiffness_N_per_m", "stiffness_kN_per_m")
            ),
            &["line 7", "stiffness_kN_per_m", "stiffness_N_per_m"],
        ),
        (
            "unit in a string",
            DEVICE.replace("0.1", "\"0.1 kg\""),
            &["line 2", "plain number"],
        ),
        (
            "no delay",
            DEVICE.replace("delay_samples = 1\n", ""),
            &["device 1", "line 1", "delay_s"],
        ),
        (
            "two delays",
            format!("{DEVICE}{DEVICE}delay_s = 0.001\n"),
            &["device 2", "line 6", "exactly one"],
        ),
        (
            "key in the wrong case",
            DEVICE.replace(
                "delay_samples = 1\n",
                "delay_samples = 1\nvelocity_filter_cutoff_hz = 30\n",
            ),
            &["line 6", "did you mean `velocity_filter_cutoff_Hz`"],
        ),
        ("no device", String::new(), &["missing field `device`"]),
        ("not TOML", "[[device]\n".into(), &["line 1"]),
    ];
    let dir = tempfile::tempdir().unwrap();
    for (what, text, needles) in cases {
        let p = dir.path().join("bad.toml");
        std::fs::write(&p, &text).unwrap();
        let out = stabound().arg("scene").arg(&p).output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{what}: {err}");
        assert!(out.stdout.is_empty(), "{what}");
        assert_eq!(err.trim_end().lines().count(), 1, "{what}: {err}");
        assert!(err.contains("bad.toml"), "{what}: {err}");
        for n in needles {
            assert!(err.contains(n), "{what}: `{n}` not in {err}");
        }
    }
}

#[test]
fn malformed_json_names_the_line() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("bad.json");
    std::fs::write(
        &p,
        "{\"device\": [{\"mass_kg\": 0.1, \"period_s\": 0.001,\n\"damping_Ns_per_m\": -3, \"delay_samples\": 1}]}",
    )
    .unwrap();
    stabound()
        .arg("scene")
        .arg(&p)
        .assert()
        .code(2)
        .stderr(predicate::str::contains("line 2").and(predicate::str::contains("0 or more")));
}

#[test]
fn missing_file_exits_2() {
    stabound()
        .args(["scene", "/nonexistent/scene.toml"])
        .assert()
        .code(2)
        .stderr(predicate::str::contains("cannot read scene"));
}

#[test]
fn help_says_what_is_computed() {
    stabound()
        .args(["scene", "--help"])
        .assert()
        .success()
        .stdout(predicate::str::contains(
            "never a full stability boundary or a grid",
        ));
}

/// `--exit-status` as `check --exit-status` has it: 3 when any wall is unstable, 4 when any
/// is marginal (and none unstable), 0 when all are stable; the report is written either way.
#[test]
fn exit_status_by_the_worst_verdict() {
    stabound()
        .args(["scene", "--exit-status"])
        .arg(data("data/scenes/phantom.toml"))
        .assert()
        .code(3)
        .stdout(predicates::str::contains("unstable"));
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("s.toml");
    for (k, code) in [("500", 0), ("0", 4)] {
        std::fs::write(
            &p,
            format!("{DEVICE}[[device.wall]]\nstiffness_N_per_m = {k}\ndamping_Ns_per_m = 5\n"),
        )
        .unwrap();
        stabound()
            .args(["scene", "--exit-status"])
            .arg(&p)
            .assert()
            .code(code);
        // without the flag a finished check exits 0
        stabound().arg("scene").arg(&p).assert().code(0);
    }
}

/// A device whose scale takes `K_max` past the range of f64 says so instead of `inf`.
#[test]
fn k_max_beyond_f64_is_said_in_words() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("big.toml");
    std::fs::write(
        &p,
        "[[device]]\nmass_kg = 1e300\nperiod_s = 1e-12\ndamping_Ns_per_m = 0\ndelay_samples = 1\n[[device.wall]]\nstiffness_N_per_m = 1e3\ndamping_Ns_per_m = 0\n",
    )
    .unwrap();
    let out = stabound().arg("scene").arg(&p).output().unwrap();
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let k_max = text.lines().find(|l| l.contains("K_max =")).unwrap();
    assert!(k_max.contains("beyond the range of f64"), "{k_max}");
    assert!(!text.contains("inf"), "{text}");
}

/// A scene device spread over intervals answers as `check` and `amax` do for the same set
/// given as `LO..HI` flags (verdict, failing member, robust optimum, binding member, how
/// each was shown), in TOML and in JSON; the failing member fails and the verified wall
/// holds at every member tried, by closed-loop eigenvalues.
#[test]
fn scene_sets_answer_as_check_and_amax() {
    use crate::robust_sets::stable;
    use stabound::elements::PhysicalElements;
    use stabound::params::{Delay, Device};

    let walls = [("stiff", 0.3, 0.4), ("soft", 0.02, 0.3)];
    let mut toml = String::from(
        "[[device]]\nname = \"jitter\"\nmass_kg = 1\nperiod_s = 1\ndamping_Ns_per_m = 0.5\ndelay_samples = [1, 3]\n",
    );
    for (name, k, b) in walls {
        toml.push_str(&format!(
            "[[device.wall]]\nname = \"{name}\"\nstiffness_N_per_m = {k}\ndamping_Ns_per_m = {b}\n"
        ));
    }
    let json_scene = serde_json::json!({"device": [{
        "name": "jitter", "mass_kg": 1, "period_s": 1, "damping_Ns_per_m": 0.5,
        "delay_samples": [1, 3],
        "wall": walls.iter().map(|(n, k, b)| serde_json::json!({
            "name": n, "stiffness_N_per_m": k, "damping_Ns_per_m": b})).collect::<Vec<_>>(),
    }]});
    let dir = tempfile::tempdir().unwrap();
    let (tp, jp) = (dir.path().join("s.toml"), dir.path().join("s.json"));
    std::fs::write(&tp, toml).unwrap();
    std::fs::write(&jp, json_scene.to_string()).unwrap();
    let report = |p: &PathBuf| -> serde_json::Value {
        let out = stabound()
            .args(["scene", "--format", "json"])
            .arg(p)
            .output()
            .unwrap();
        assert!(out.status.success());
        serde_json::from_slice(&out.stdout).unwrap()
    };
    let v = report(&tp);
    assert_eq!(v, report(&jp));
    let set = &v["devices"][0]["set"];
    assert_eq!(set["spread"][0], "delay 1..3 samples", "{set}");
    let device = [
        "--mass",
        "1",
        "--period",
        "1",
        "--damping",
        "0.5",
        "--delay-samples",
        "1..3",
        "--format",
        "json",
    ];
    let amax = crate::common::json(&[&["amax"][..], &device[..]].concat());
    let row = &amax[0];
    let o = &set["optimum"];
    for (scene_key, cli_key) in [
        ("alpha_max", "alpha_max"),
        ("beta_at_max", "beta_at_max"),
        ("alpha_verified", "alpha_verified"),
        ("K_verified_N_per_m", "K_verified"),
        ("B_at_max_Ns_per_m", "B"),
        ("verification", "verification"),
    ] {
        assert_eq!(o[scene_key], row[cli_key], "{scene_key}: {o} vs {row}");
    }
    assert_eq!(o["binding"][0], row["binding"], "{o} vs {row}");
    for (i, (_, k, b)) in walls.iter().enumerate() {
        let (k, b) = (k.to_string(), b.to_string());
        let check = crate::common::json(
            &[
                &["check"][..],
                &device[..],
                &["--stiffness", &k, "--wall-damping", &b],
            ]
            .concat(),
        );
        let w = &set["walls"][i];
        for key in [
            "verdict",
            "for_every_member",
            "verification",
            "failing_member",
        ] {
            assert_eq!(w[key], check[key], "{key}: {w} vs {check}");
        }
    }
    // independent: the stiff wall fails at the member named, the soft one and the verified
    // optimum hold at every delay tried (fractional ones included)
    let at = |d: f64| Device::new(1.0, 1.0, 0.5, Delay::Samples(d)).unwrap();
    let none = PhysicalElements::default();
    let failing = set["walls"][0]["failing_member"].as_str().unwrap();
    let d: f64 = failing
        .strip_prefix("delay = ")
        .and_then(|m| m.strip_suffix(" samples"))
        .unwrap()
        .parse()
        .unwrap();
    assert!(!stable(&at(d), &none, 0.3, 0.4));
    let (kv, bv) = (
        o["K_verified_N_per_m"].as_f64().unwrap(),
        o["B_at_max_Ns_per_m"].as_f64().unwrap(),
    );
    for i in 0..=100 {
        let d = 1.0 + 2.0 * f64::from(i) / 100.0;
        assert!(stable(&at(d), &none, 0.02, 0.3), "soft wall at d = {d}");
        assert!(stable(&at(d), &none, kv, bv), "verified wall at d = {d}");
    }
    // the set's verdicts reach the exit status
    stabound()
        .args(["scene", "--exit-status"])
        .arg(&tp)
        .assert()
        .code(3)
        .stdout(predicate::str::contains(
            "failing member: delay = 3 samples",
        ));
}

/// A hand whose mass spreads over an interval, the free device included: the scene's robust
/// optimum is `amax`'s for the same flags, and its verified wall is stable with the hand
/// (lightest, heaviest and between) and without it, by eigenvalues.
#[test]
fn scene_hand_interval_answers_as_amax() {
    use crate::robust_sets::stable;
    use stabound::elements::PhysicalElements;
    use stabound::params::{Delay, Device};

    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("h.toml");
    std::fs::write(
        &p,
        "[[device]]\nmass_kg = 0.1\nperiod_s = 0.001\ndamping_Ns_per_m = 0\ndelay_samples = 1\n\
         velocity_filter_cutoff_Hz = 50\nhand_mass_kg = [0.2, 0.5]\nhand_damping_Ns_per_m = 2\n\
         hand_stiffness_N_per_m = 300\n",
    )
    .unwrap();
    let out = stabound()
        .args(["scene", "--format", "json"])
        .arg(&p)
        .output()
        .unwrap();
    assert!(out.status.success());
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let o = &v["devices"][0]["set"]["optimum"];
    let amax = crate::common::json(&[
        "amax",
        "--mass",
        "0.1",
        "--period",
        "0.001",
        "--damping",
        "0",
        "--delay-samples",
        "1",
        "--velocity-filter-cutoff",
        "50",
        "--hand-mass",
        "0.2..0.5",
        "--hand-damping",
        "2",
        "--hand-stiffness",
        "300",
        "--format",
        "json",
    ]);
    let row = &amax[0];
    assert_eq!(o["alpha_max"], row["alpha_max"], "{o} vs {row}");
    assert_eq!(o["alpha_verified"], row["alpha_verified"], "{o} vs {row}");
    assert_eq!(o["binding"][0], row["binding"], "{o} vs {row}");
    let (k, b) = (
        o["K_verified_N_per_m"].as_f64().unwrap(),
        o["B_at_max_Ns_per_m"].as_f64().unwrap(),
    );
    let device = Device::new(0.1, 0.001, 0.0, Delay::Samples(1.0)).unwrap();
    let mut e = PhysicalElements::default();
    e.velocity_filter_cutoff = Some(50.0);
    assert!(stable(&device, &e, k, b), "hand let go");
    e.hand_damping = Some(2.0);
    e.hand_stiffness = Some(300.0);
    for i in 0..=10 {
        e.hand_mass = Some(0.2 + 0.03 * f64::from(i));
        assert!(stable(&device, &e, k, b), "{e:?}");
    }
}

/// Intervals a scene cannot take: inverted, not two numbers, an end out of range, a period
/// (one for the whole set), a member that is no valid loop. Exit 2 and one line naming the
/// place (the line written last: the key replaced is left out of the device above it).
#[test]
fn scene_interval_errors_exit_2() {
    let cases: [(&str, &[&str]); 6] = [
        ("mass_kg = [0.2, 0.1]", &["line 5", "inverted"]),
        ("mass_kg = [0.1, 0.2, 0.3]", &["line 5", "two numbers"]),
        ("hand_mass_kg = [0.2, -1]", &["line 6", "0 or more"]),
        ("delay_samples = [-1, 2]", &["line 5", "0 or more"]),
        ("period_s = [0.001, 0.002]", &["line 5", "one number"]),
        (
            "handle_mass_kg = [0.01, 0.2]\ntransmission_stiffness_N_per_m = 2e5",
            &[
                "device 1",
                "handle mass interval",
                "below the device's mass",
            ],
        ),
    ];
    let dir = tempfile::tempdir().unwrap();
    for (line, needles) in cases {
        let key = line.split(' ').next().unwrap();
        let base: String = DEVICE
            .lines()
            .filter(|l| !l.starts_with(key))
            .map(|l| format!("{l}\n"))
            .collect();
        let p = dir.path().join("bad.toml");
        std::fs::write(&p, format!("{base}{line}\n")).unwrap();
        let out = stabound().arg("scene").arg(&p).output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{line}: {err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{line}: {err}");
        for n in needles {
            assert!(err.contains(n), "{line}: `{n}` not in {err}");
        }
    }
}
