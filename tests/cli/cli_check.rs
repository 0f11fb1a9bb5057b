//! End-to-end tests of `stabound check`.

use predicates::prelude::*;

use crate::common::{assert_bad_input, stabound};

fn json(args: &[&str]) -> serde_json::Value {
    crate::common::json(&[&["check"][..], args, &["--format", "json"]].concat())
}

/// Paper anchor (docs/MODEL.md section 6): alpha_max = 12 - 8 sqrt 2 at beta = 2 sqrt 2 - 2 for
/// delta = 0, d = 0.
#[test]
fn anchor_through_the_cli() {
    let s2 = 2f64.sqrt();
    let beta = format!("{}", 2.0 * s2 - 2.0);
    for (alpha, stable) in [
        (12.0 - 8.0 * s2 - 1e-6, true),
        (12.0 - 8.0 * s2 + 1e-6, false),
    ] {
        for method in [
            "schur-cohn",
            "eigen",
            "state-space",
            "argument-principle",
            "auto",
        ] {
            let v = json(&[
                "--alpha",
                &alpha.to_string(),
                "--beta",
                &beta,
                "--delta",
                "0",
                "--d",
                "0",
                "--method",
                method,
            ]);
            assert_eq!(v["stable"], stable, "{method} {alpha}");
            assert_eq!(v["degree"], 3);
            assert_eq!(v["roots"].as_array().unwrap().len(), 3);
            let r = v["spectral_radius"].as_f64().unwrap();
            assert_eq!(r < 1.0, stable, "{method} {r}");
        }
    }
}

/// Physical units convert as docs/MODEL.md section 1: b = 10 N s/m, m = 0.1 kg, T = 1 ms is
/// delta = 0.1; K = 2000 N/m is alpha = 0.02.
#[test]
fn physical_units() {
    let v = json(&[
        "--mass",
        "0.1",
        "--period",
        "0.001",
        "--damping",
        "10",
        "--stiffness",
        "2000",
        "--wall-damping",
        "40",
        "--delay",
        "0.0015",
    ]);
    assert!((v["delta"].as_f64().unwrap() - 0.1).abs() < 1e-12);
    assert!((v["alpha"].as_f64().unwrap() - 0.02).abs() < 1e-12);
    assert!((v["beta"].as_f64().unwrap() - 0.4).abs() < 1e-12);
    assert!((v["d"].as_f64().unwrap() - 1.5).abs() < 1e-12);
    assert_eq!(v["degree"], 5);
}

#[test]
fn bad_input_exits_2_with_one_line() {
    let cases: &[&[&str]] = &[
        &["--alpha", "nan", "--beta", "0", "--delta", "0", "--d", "0"],
        &["--alpha", "1", "--beta", "0", "--delta", "-1", "--d", "0"],
        &["--alpha", "1", "--beta", "0", "--delta", "0", "--d", "1e6"],
        &["--alpha", "1", "--beta", "0", "--delta", "0"],
        &[
            "--mass",
            "0",
            "--period",
            "0.001",
            "--damping",
            "0",
            "--stiffness",
            "1",
            "--wall-damping",
            "0",
            "--delay",
            "0",
        ],
        &[
            "--alpha", "1", "--beta", "0", "--delta", "0", "--d", "0", "--mass", "1",
        ],
        &[
            "--alpha", "1", "--beta", "0", "--delta", "0", "--d", "0", "--method", "magic",
        ],
    ];
    for args in cases {
        assert_bad_input(&[&["check"][..], args].concat(), false);
    }
    stabound()
        .args([
            "check", "--alpha", "1", "--beta", "0", "--delta", "-1", "--d", "0",
        ])
        .assert()
        .code(2)
        .stderr(predicate::str::contains("delta").and(predicate::str::contains("range")));
}

#[test]
fn output_file_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("r.json");
    stabound()
        .args([
            "check", "--alpha", "0.1", "--beta", "0.3", "--delta", "0.5", "--d", "1", "--format",
            "json", "-o",
        ])
        .arg(&p)
        .assert()
        .success()
        .stdout("");
    let v: serde_json::Value = serde_json::from_slice(&std::fs::read(&p).unwrap()).unwrap();
    assert_eq!(v["stable"], true);
}
