//! End-to-end tests of `stabound check`.

use predicates::prelude::*;

use crate::common::{assert_bad_input, stabound};

fn json(args: &[&str]) -> serde_json::Value {
    crate::common::json(&[&["check"][..], args, &["--format", "json", "--radius"]].concat())
}

/// The JSON report (with the radius) of one normalized wall.
fn one_wall(alpha: f64, beta: f64, delta: f64, d: f64) -> serde_json::Value {
    let [a, b, x, d] = [alpha, beta, delta, d].map(|v| v.to_string());
    json(&["--alpha", &a, "--beta", &b, "--delta", &x, "--d", &d])
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
    // the wall as typed, not converted back from alpha and beta
    assert_eq!(v["physical"]["stiffness_N_per_m"].as_f64(), Some(2000.0));
    assert_eq!(v["physical"]["wall_damping_Ns_per_m"].as_f64(), Some(40.0));
    let out = stabound()
        .args([
            "check",
            "--mass",
            "0.1",
            "--period",
            "0.001",
            "--damping",
            "0",
        ])
        .args([
            "--delay-samples",
            "1",
            "--stiffness",
            "2000",
            "--wall-damping",
            "20",
        ])
        .output()
        .unwrap();
    let text = String::from_utf8(out.stdout).unwrap();
    assert_eq!(
        text.lines().nth(1),
        Some("wall K = 2000 N/m, B = 20 N s/m; device m = 0.1 kg, T = 0.001 s, b = 0 N s/m"),
        "{text}"
    );
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

/// `--batch --radius` gives, row for row, what one `check` per wall gives, in input order,
/// for normalized and physical walls (runs of walls on one plant among them, which share a
/// checker); `--exit-status` reports the worst verdict.
#[test]
fn batch_matches_single_checks_and_exit_status() {
    let walls = [
        (0.1, 0.3, 0.5, 1.0),
        (5.0, 0.3, 0.5, 1.0),
        (0.15, 0.3, 0.5, 1.0),
        (0.05, 0.2, 0.0, 2.5),
        (0.06, 0.2, 0.0, 2.5),
        (0.0, 0.0, 0.5, 1.0),
        (0.3, 0.1, 0.5, 1.0),
    ];
    let mut csv = String::from("d,alpha,beta,delta\n");
    for (a, b, x, d) in walls {
        csv.push_str(&format!("{d},{a},{b},{x}\n"));
    }
    let out = stabound()
        .args(["check", "--batch", "-", "--exit-status", "--radius"])
        .write_stdin(csv)
        .output()
        .unwrap();
    // one unstable wall: exit 3, data still written
    assert_eq!(out.status.code(), Some(3));
    let text = String::from_utf8(out.stdout).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some("alpha,beta,delta,d,verdict,spectral_radius,method")
    );
    for (&(a, b, x, d), line) in walls.iter().zip(lines) {
        let one = one_wall(a, b, x, d);
        let cells: Vec<&str> = line.split(',').collect();
        assert_eq!(cells[4], one["verdict"].as_str().unwrap(), "{line}");
        let radius: f64 = cells[5].parse().unwrap();
        assert_eq!(radius, one["spectral_radius"].as_f64().unwrap(), "{line}");
        assert_eq!(cells[0].parse::<f64>().unwrap(), a);
    }
    // physical walls on one device (paper Section VIII, 75 % of K_max: stable)
    let out = stabound()
        .args(["check", "--batch", "-", "--exit-status", "--mass", "0.1"])
        .args([
            "--period",
            "0.001",
            "--damping",
            "0",
            "--delay-samples",
            "1",
        ])
        .write_stdin("stiffness_N_per_m,wall_damping_Ns_per_m\n10800,42.5\n")
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0));
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.lines().nth(1).unwrap().contains(",stable,"), "{text}");
    // loop elements apply to every row of a physical batch as to a single check
    let device = ["--mass", "0.1", "--period", "0.001", "--damping", "0"];
    let filter = ["--delay-samples", "1", "--velocity-filter-cutoff", "3.18"];
    let out = stabound()
        .args(["check", "--batch", "-", "--radius"])
        .args(device)
        .args(filter)
        .write_stdin("stiffness_N_per_m,wall_damping_Ns_per_m\n10800,42.5\n")
        .output()
        .unwrap();
    let text = String::from_utf8(out.stdout).unwrap();
    let row: Vec<&str> = text.lines().nth(1).unwrap().split(',').collect();
    let one = crate::common::json(
        &[
            &["check"][..],
            &device,
            &filter,
            &[
                "--stiffness",
                "10800",
                "--wall-damping",
                "42.5",
                "--format",
                "json",
                "--radius",
            ],
        ]
        .concat(),
    );
    assert_eq!(row[6], one["verdict"].as_str().unwrap());
    assert_eq!(
        row[6], "unstable",
        "the 50 ms filter makes this wall unstable"
    );
    assert_eq!(
        row[7].parse::<f64>().unwrap(),
        one["spectral_radius"].as_f64().unwrap()
    );
    // marginal alone (alpha = 0 has the root z = 1): exit 4
    let code = stabound()
        .args(["check", "--alpha", "0", "--beta", "0.1", "--delta", "0.5"])
        .args(["--d", "1", "--exit-status"])
        .output()
        .unwrap()
        .status
        .code();
    assert_eq!(code, Some(4));
}

/// One wall's report lists the spectral radius and the roots only with `--radius`: without
/// it the same verdict, method and degree, and no roots computed (a wall at d = 500, whose
/// 503 roots took most of the run, and the double root of the free mass, undecided).
#[test]
fn one_wall_reports_roots_only_when_asked() {
    for wall in [
        [
            "--alpha", "0.1", "--beta", "0.3", "--delta", "0.5", "--d", "1",
        ],
        [
            "--alpha", "1e-6", "--beta", "0.01", "--delta", "0.5", "--d", "500",
        ],
        ["--alpha", "0", "--beta", "0", "--delta", "0", "--d", "1"],
        [
            "--alpha", "5", "--beta", "0.3", "--delta", "0.5", "--d", "2.5",
        ],
    ] {
        let full = json(&wall);
        let short = crate::common::json(&[&["check"][..], &wall, &["--format", "json"]].concat());
        let keys = |v: &serde_json::Value| -> Vec<String> {
            v.as_object().unwrap().keys().cloned().collect()
        };
        let mut want = keys(&full);
        want.retain(|k| k != "spectral_radius" && k != "roots");
        assert_eq!(keys(&short), want, "{wall:?}");
        for k in &want {
            assert_eq!(short[k], full[k], "{wall:?} {k}");
        }
        assert_eq!(
            full["roots"].as_array().unwrap().len() as u64,
            full["degree"].as_u64().unwrap()
        );
        let text =
            String::from_utf8(crate::common::stdout(&[&["check"][..], &wall].concat())).unwrap();
        let second = text.lines().nth(1).unwrap();
        let degree = full["degree"].to_string();
        assert_eq!(
            second,
            format!(
                "verdict by {}, marginal band +-1e-9, degree {degree}",
                full["method"].as_str().unwrap()
            ),
            "{text}"
        );
        assert!(!text.contains("roots") && !text.contains("|z|"), "{text}");
        assert_eq!(
            text.contains("(undecided:"),
            full["verdict"] == "marginal" && wall[1] == "0",
            "{text}"
        );
    }
}

/// A batch of many walls gives the same bytes on one thread as on four, each row the
/// wall's own (its verdict as one `check` of it finds, its numbers as given), blank and
/// CRLF lines as in a short batch, and a bad line far down is named by its own number.
#[test]
fn long_batch_is_the_same_on_any_number_of_threads() {
    let frac = |x: f64| x - x.floor();
    let walls: Vec<(f64, f64, f64)> = (0..10_000)
        .map(|i| {
            let i = f64::from(i);
            (
                frac(0.5 + i * 0.754_877_666_246_692_7),
                -0.2 + 1.2 * frac(0.5 + i * 0.569_840_290_998_053_2),
                2.0 * frac(0.5 + i * 0.618_033_988_749_894_9),
            )
        })
        .collect();
    let mut csv = String::from("alpha,beta,delta,d\r\n\n");
    for (i, (a, b, x)) in walls.iter().enumerate() {
        csv.push_str(&format!(
            " {a}, {b} ,{x},1{}",
            if i % 2 == 0 { "\n" } else { "\r\n" }
        ));
        if i == 5000 {
            csv.push_str("  \n");
        }
    }
    let run = |threads: &str, input: &str| {
        stabound()
            .args(["check", "--batch", "-"])
            .env("RAYON_NUM_THREADS", threads)
            .write_stdin(input.to_string())
            .output()
            .unwrap()
    };
    let one = run("1", &csv);
    assert!(
        one.status.success(),
        "{}",
        String::from_utf8_lossy(&one.stderr)
    );
    assert_eq!(run("4", &csv).stdout, one.stdout);
    let (head, rows) = crate::common::csv(&one.stdout);
    assert_eq!(head, "alpha,beta,delta,d,verdict,method");
    assert_eq!(rows.len(), walls.len());
    for k in [0, 2047, 2048, 5000, 5001, 9999] {
        let (a, b, x) = walls[k];
        let row = &rows[k];
        let given: Vec<f64> = row[..4].iter().map(|c| c.parse().unwrap()).collect();
        assert_eq!(given, [a, b, x, 1.0], "{k}");
        let v = one_wall(a, b, x, 1.0);
        assert_eq!(row[4], v["verdict"].as_str().unwrap(), "{k}");
        assert_eq!(row[5], v["method"].as_str().unwrap(), "{k}");
    }
    // the header, a blank line, wall k on line k + 3, and past the blank line after wall
    // 5000 on line k + 4
    let mut bad: Vec<&str> = csv.split_inclusive('\n').collect();
    bad[8000 + 3] = "0.1,0.2,-1,1\n";
    for threads in ["1", "4"] {
        let out = run(threads, &bad.concat());
        assert_eq!(out.status.code(), Some(2));
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains("stdin: line 8004"), "{err}");
        assert!(out.stdout.is_empty());
    }
}

#[test]
fn batch_bad_input_is_exit_2_naming_the_line() {
    for (input, want) in [
        ("alpha,beta\n1,2\n", "line 1"),
        ("alpha,beta,delta,d\n0.1,x,0,0\n", "line 2"),
        ("alpha,beta,delta,d\n0.1,0.2,0\n", "line 2"),
        ("alpha,beta,delta,d\n0.1,0.2,-1,0\n", "line 2"),
        ("", "empty"),
    ] {
        let out = stabound()
            .args(["check", "--batch", "-"])
            .write_stdin(input)
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(2), "{input:?}");
        let err = String::from_utf8(out.stderr).unwrap();
        assert!(err.contains(want), "{input:?}: {err}");
        assert!(out.stdout.is_empty());
    }
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
            "check",
            "--alpha",
            "0",
            "--beta",
            "0.2",
            "--delta",
            "0.5",
            "--d",
            "1",
            "--marginal-band",
            "1e-16",
        ],
        true,
    );
    assert!(err.contains("smallest accepted margin"), "{err}");
}

/// A request that mixes normalized and physical values names the flags of each kind that
/// were given; a request that lacks values names exactly the missing ones.
#[test]
fn messages_name_what_is_mixed_or_missing() {
    let e = assert_bad_input(&["check", "--alpha", "1", "--mass", "0.25"], true);
    assert!(
        e.contains("--alpha (normalized) and --mass (physical units)"),
        "{e}"
    );
    let e = assert_bad_input(
        &[
            "check",
            "--mass",
            "0.25",
            "--period",
            "1e-3",
            "--damping",
            "1",
            "--delay",
            "0",
        ],
        true,
    );
    assert!(e.contains("missing --stiffness and --wall-damping:"), "{e}");
    let e = assert_bad_input(&["check", "--alpha", "1", "--beta", "1"], true);
    assert!(e.contains("missing --delta and --d:"), "{e}");
    let e = assert_bad_input(&["amax", "--mass", "0.25", "--damping", "1"], true);
    assert!(
        e.contains("missing --period and --delay|--delay-samples:"),
        "{e}"
    );
    let e = assert_bad_input(&["table", "--d", "1", "--delay", "1e-3"], true);
    assert!(
        e.contains("--d (normalized) and --delay|--delay-samples (physical units)"),
        "{e}"
    );
}

/// A marginal verdict prints a spectral radius inside its own band: at `alpha = beta = delta
/// = 0` the root `z = 1` is double (the free mass), and eigenvalues of the whole polynomial
/// split it by about `1e-8`, far wider than the band `1e-9`; divided out, both copies are
/// exactly 1 in the text and in JSON, and the other roots are those of `z^4` (all at 0).
#[test]
fn marginal_radius_lies_in_its_band() {
    let args = [
        "check", "--alpha", "0", "--beta", "0", "--delta", "0", "--d", "2.5", "--radius",
    ];
    let v = json(&args[1..args.len() - 1]);
    assert_eq!(v["verdict"], "marginal");
    assert_eq!(v["spectral_radius"].as_f64(), Some(1.0));
    let roots = v["roots"].as_array().unwrap();
    let ones = roots
        .iter()
        .filter(|r| r[0].as_f64() == Some(1.0) && r[1].as_f64() == Some(0.0))
        .count();
    assert_eq!(ones, 2, "{roots:?}");
    // the other four: z^4 = 0, within the fourth root of the rounding
    for r in roots {
        let (re, im) = (r[0].as_f64().unwrap(), r[1].as_f64().unwrap());
        assert!(re.hypot(im) < 1e-3 || (re == 1.0 && im == 0.0), "{r:?}");
    }
    let out = stabound().args(args).output().unwrap();
    let text = String::from_utf8(out.stdout).unwrap();
    let line = text.lines().nth(1).unwrap();
    assert!(line.starts_with("spectral radius 1, "), "{text}");
    // no note: the radius is where the verdict says
    assert!(text.lines().nth(2).unwrap().starts_with("degree"), "{text}");
    // a wall well inside: no note
    let out = stabound()
        .args([
            "check", "--alpha", "0.1", "--beta", "0.3", "--delta", "0.5", "--d", "1", "--radius",
        ])
        .output()
        .unwrap();
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.lines().nth(2).unwrap().starts_with("degree"), "{text}");
}

/// JSON never writes a negative zero (readers differ on it): not for a `-0` given, nor for
/// the zeros the boundary and the roots produce.
#[test]
fn json_has_no_negative_zero() {
    let check = stabound()
        .args([
            "check", "--alpha", "0.1", "--beta", "-0", "--delta", "0.5", "--d", "1",
        ])
        .args(["--format", "json", "--radius"])
        .output()
        .unwrap();
    let boundary = stabound()
        .args([
            "boundary", "--delta", "0", "--d", "0", "--tol", "1e-3", "--format", "json",
        ])
        .output()
        .unwrap();
    for out in [check, boundary] {
        assert!(out.status.success());
        let text = String::from_utf8(out.stdout).unwrap();
        assert!(
            !text.contains("-0.0,") && !text.contains("-0.0}") && !text.contains("-0.0\n"),
            "{text}"
        );
        assert!(text.contains("0.0"));
    }
}

/// The batch prints no spectral radius unless asked (`--radius`; it needs the roots, the
/// verdict does not), and its verdicts and methods are the radius run's; `--verdict-only`
/// is the default output, goes only with `--batch` and never with `--radius`.
#[test]
fn batch_default_has_the_verdicts_of_the_radius_run() {
    // walls on both sides of the edge, at short and long delays (degree up to 1,000 at 500)
    let mut csv = String::from("alpha,beta,delta,d\n");
    for (i, d) in ["0", "1", "2.5", "500"].iter().enumerate() {
        for k in 0..6 {
            let alpha = [0.0001, 0.05, 0.1, 0.15, 0.3, 2.0][k] / (1 + i) as f64;
            csv.push_str(&format!("{alpha},0.4,0.5,{d}\n"));
        }
    }
    let run = |extra: &[&str]| {
        let out = stabound()
            .args(["check", "--batch", "-"])
            .args(extra)
            .write_stdin(csv.clone())
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        out.stdout
    };
    let default = run(&[]);
    assert_eq!(run(&["--verdict-only"]), default);
    let (head, short) = crate::common::csv(&default);
    let (full_head, full) = crate::common::csv(&run(&["--radius"]));
    assert_eq!(head, "alpha,beta,delta,d,verdict,method");
    assert_eq!(
        full_head,
        "alpha,beta,delta,d,verdict,spectral_radius,method"
    );
    assert_eq!(full.len(), 24);
    let verdicts: std::collections::BTreeSet<&str> = full.iter().map(|r| r[4].as_str()).collect();
    assert!(
        verdicts.contains("stable") && verdicts.contains("unstable"),
        "{verdicts:?}"
    );
    for (f, s) in full.iter().zip(&short) {
        assert_eq!(f[..5], s[..5]);
        assert_eq!(f[6], s[5]);
        // the radius is on the verdict's side of the unit circle
        let radius: f64 = f[5].parse().unwrap();
        match f[4].as_str() {
            "stable" => assert!(radius < 1.0, "{f:?}"),
            "unstable" => assert!(radius > 1.0, "{f:?}"),
            _ => {}
        }
    }
    assert_bad_input(
        &["check", "--batch", "-", "--radius", "--verdict-only"],
        true,
    );
    assert_bad_input(
        &[
            "check",
            "--alpha",
            "0.1",
            "--beta",
            "0.3",
            "--delta",
            "0.5",
            "--d",
            "1",
            "--verdict-only",
        ],
        true,
    );
}
