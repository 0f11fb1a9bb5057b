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
