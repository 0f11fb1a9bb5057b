//! End-to-end tests of `stabound check`.

use predicates::prelude::*;

use crate::common::{assert_bad_input, stabound};

fn json(args: &[&str]) -> serde_json::Value {
    crate::common::json(&[&["check"][..], args, &["--format", "json"]].concat())
}

/// Paper anchor (MATH.md section 6): alpha_max = 12 - 8 sqrt 2 at beta = 2 sqrt 2 - 2 for
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

/// Physical units convert as MATH.md section 1: b = 10 N s/m, m = 0.1 kg, T = 1 ms is
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

/// Walls whose verdict used to be decided by rounding: a stiffness at the top of the f64
/// range is unstable (far outside every stable region) with a finite radius; a near-double
/// root at z = 1 and the defective case alpha = beta = delta = 0 are marginal, not an error.
#[test]
fn verdicts_at_the_edges_of_f64() {
    let v = json(&[
        "--alpha",
        "1.7976931348623157e308",
        "--beta",
        "0",
        "--delta",
        "0.5",
        "--d",
        "1",
    ]);
    assert_eq!(v["verdict"], "unstable");
    assert!(v["spectral_radius"].as_f64().unwrap() > 1.0);
    for args in [
        ["1e-12", "-999999.999", "1e6", "2.5"],
        ["0", "0", "0", "2.5"],
    ] {
        let v = json(&[
            "--alpha", args[0], "--beta", args[1], "--delta", args[2], "--d", args[3],
        ]);
        assert_eq!(v["verdict"], "marginal", "{args:?}");
    }
}

/// A margin below the resolution of f64 near 1 is bad input, and the message names the
/// smallest accepted one.
#[test]
fn margin_below_rounding_is_bad_input() {
    let err = assert_bad_input(
        &[
            "check", "--alpha", "0", "--beta", "0.2", "--delta", "0.5", "--d", "1", "--margin",
            "1e-16",
        ],
        true,
    );
    assert!(err.contains("smallest accepted margin"), "{err}");
}
