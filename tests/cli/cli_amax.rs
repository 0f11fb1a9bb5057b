//! End-to-end tests of `stabound amax` against the paper's published values.

use crate::common::{assert_bad_input, csv, csv_numbers, stabound, stdout};

fn json(args: &[&str]) -> Vec<serde_json::Value> {
    let args = [&["amax"][..], args, &["--format", "json"]].concat();
    serde_json::from_value(crate::common::json(&args)).unwrap()
}

/// Paper Section VIII (docs/MODEL.md section 6): m = 0.1 kg, T = 1 ms, d = 1, b = 0, 10, 100 N s/m,
/// 75 % margin: alpha = 0.108, 0.149, 0.656 and beta = 0.425, 0.416, 0.388 to the digits.
#[test]
fn section_viii_physical() {
    let rows = json(&[
        "--mass",
        "0.1",
        "--period",
        "0.001",
        "--damping",
        "0,10,100",
        "--delay-samples",
        "1",
        "--margin",
        "0.75",
    ]);
    let want = [
        (0.108, 0.425, 0.0),
        (0.149, 0.416, 10.0),
        (0.656, 0.388, 100.0),
    ];
    assert_eq!(rows.len(), 3);
    for (r, (a, b, damping)) in rows.iter().zip(want) {
        let f = |k: &str| r[k].as_f64().unwrap();
        assert!((f("alpha_margin") - a).abs() < 5e-4, "{r}");
        assert!((f("beta_at_max") - b).abs() < 5e-4, "{r}");
        assert!((f("damping_Ns_per_m") - damping).abs() < 1e-9, "{r}");
        // K = alpha m / T^2
        assert!(
            (f("K_max_N_per_m") - f("alpha_max") * 0.1 / 1e-6).abs() < 1e-6 * f("K_max_N_per_m"),
            "{r}"
        );
    }
}

#[test]
fn anchors_and_csv_columns() {
    let out = stdout(&["amax", "--delta", "0", "--d", "0,1"]);
    assert_eq!(csv(&out).0, "delta,d,alpha_max,beta_at_max");
    let v = csv_numbers(&out);
    assert!((v[0][2] - (12.0 - 8.0 * 2f64.sqrt())).abs() < 1e-10);
    assert!((v[1][2] - 0.1445).abs() < 5e-5);
}

#[test]
fn bad_input_exits_2() {
    for args in [
        vec!["amax", "--delta", "-1", "--d", "0"],
        vec!["amax", "--delta", "0"],
        vec!["amax", "--delta", "0", "--d", "0", "--margin", "1.5"],
        vec![
            "amax",
            "--delta",
            "0",
            "--d",
            "0",
            "--beta-min",
            "1",
            "--beta-max",
            "0",
        ],
        vec!["amax", "--delta", "1", "--d", "0", "--beta-min", "1000"],
    ] {
        assert_bad_input(&args, true);
    }
}

#[test]
fn svg_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let svg = dir.path().join("f10.svg");
    let out = stabound()
        .args(["amax", "--delta", "0:10:11", "--d", "0,1", "--svg"])
        .arg(&svg)
        .output()
        .unwrap();
    assert!(out.status.success());
    let s = std::fs::read_to_string(&svg).unwrap();
    assert!(s.contains("<svg") && s.contains("d = 1"));
}

/// `--wall-damping-min` is `--beta-min` in N s/m (`beta = B T / m`): with B >= 60 N s/m the
/// paper's device (whose unconstrained maximum is at B = 42.5 N s/m) reaches its largest
/// stiffness on the limit, where `check` finds the wall marginal: stable just below K_max,
/// unstable just above.
#[test]
fn wall_damping_limits_are_physical() {
    let device = [
        "--mass",
        "0.1",
        "--period",
        "0.001",
        "--damping",
        "0",
        "--delay-samples",
        "1",
    ];
    let rows = json(&[&device[..], &["--wall-damping-min", "60"]].concat());
    let normalized = json(&[&device[..], &["--beta-min", "0.6"]].concat());
    assert_eq!(rows, normalized);
    let (k, b) = (
        rows[0]["K_max_N_per_m"].as_f64().unwrap(),
        rows[0]["B_at_max_Ns_per_m"].as_f64().unwrap(),
    );
    assert!((b - 60.0).abs() < 1e-6, "B = {b}");
    let check = |s: f64| {
        let mut cmd = vec!["check"];
        let st = s.to_string();
        let bs = b.to_string();
        cmd.extend_from_slice(&device[..6]);
        cmd.extend(["--delay-samples", "1", "--exit-status", "--stiffness", &st]);
        cmd.extend(["--wall-damping", &bs]);
        stabound()
            .args(&cmd)
            .output()
            .unwrap()
            .status
            .code()
            .unwrap()
    };
    assert_eq!(check(k * (1.0 - 1e-6)), 0, "just below K_max = {k}");
    assert_eq!(check(k * (1.0 + 1e-6)), 3, "just above K_max = {k}");
    // the physical limit needs the physical device
    let err = assert_bad_input(
        &[
            "amax",
            "--delta",
            "0",
            "--d",
            "1",
            "--wall-damping-min",
            "60",
        ],
        true,
    );
    assert!(
        err.contains("--mass") && err.contains("--beta-min"),
        "{err}"
    );
}

/// `--svg` draws alpha_max against delta: one delta is refused before any work (nothing on
/// stdout), saying what to give.
#[test]
fn svg_with_one_delta_is_refused_first() {
    let dir = tempfile::tempdir().unwrap();
    let svg = dir.path().join("a.svg");
    let e = crate::common::assert_bad_input(
        &[
            "amax",
            "--delta",
            "0.5",
            "--d",
            "1",
            "--svg",
            svg.to_str().unwrap(),
        ],
        true,
    );
    assert!(e.contains("range of deltas"), "{e}");
    assert!(!svg.exists());
}

/// A loop whose direct search confirms no rightmost point (a Butterworth filter at 0.002 of
/// the sampling rate, no physical damping, no delay) answers from the traced boundary, and
/// the output says which method answered; the answer is the library's.
#[test]
fn traced_boundary_answer_says_so() {
    let args = [
        "amax",
        "--mass",
        "1",
        "--period",
        "1",
        "--damping",
        "0",
        "--delay-samples",
        "0",
        "--velocity-filter-cutoff",
        "0.002",
        "--velocity-filter-order",
        "2",
    ];
    let out = stabound().args(args).output().unwrap();
    assert!(out.status.success());
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(
        err.contains("the direct search on the loop's curve confirmed no rightmost point; alpha_max is the rightmost point of the exact boundary"),
        "{err}"
    );
    let lp = stabound::elements::Loop::new(stabound::params::Plant::new(0.0, 0.0).unwrap())
        .with_filter(stabound::filter::VelocityFilter::butterworth(0.002).unwrap())
        .unwrap();
    let want = stabound::alpha_max(lp, &stabound::AmaxOptions::default()).unwrap();
    let row = &csv_numbers(&out.stdout)[0];
    // the CSV prints the shortest round-trip form: the same bits
    assert!(
        row[2].to_bits() == want.alpha_max.to_bits(),
        "{row:?} vs {want:?}"
    );
}

/// The paper's loop at delta = 100 with no delay: the wall a relative 1e-6 below its
/// optimum keeps a root about 2e-10 inside the unit circle (the library's tests hold that
/// radius to the state matrix's eigenvalues), so its row says on stderr, as a row of a loop
/// with elements does, that `check` calls that wall marginal: and `check` does, on the wall
/// the note names, while the 75 % wall the note points to is stable. An ordinary row
/// (delta 1, d 1) says nothing of the kind.
#[test]
fn paper_loop_row_says_when_its_wall_below_is_marginal() {
    let out = stabound()
        .args(["amax", "--delta", "100", "--d", "0"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0));
    let err = String::from_utf8_lossy(&out.stderr);
    let note = err
        .lines()
        .find(|l| l.starts_with("note: delta = 100, d = 0: the stiffest wall to render (alpha = "))
        .unwrap_or_else(|| panic!("{err}"));
    assert!(
        note.contains("within the marginal band") && note.contains("--margin"),
        "{note}"
    );
    let wall = note.split("(alpha = ").nth(1).unwrap();
    let alpha = wall.split(',').next().unwrap();
    let beta = wall
        .split("beta = ")
        .nth(1)
        .unwrap()
        .split(',')
        .next()
        .unwrap();
    let verdict = |alpha: &str| {
        crate::common::json(&[
            "check", "--alpha", alpha, "--beta", beta, "--delta", "100", "--d", "0", "--format",
            "json",
        ])["verdict"]
            .as_str()
            .unwrap()
            .to_string()
    };
    assert_eq!(verdict(alpha), "marginal");
    let softer = (0.75 * alpha.parse::<f64>().unwrap()).to_string();
    assert_eq!(verdict(&softer), "stable");
    let out = stabound()
        .args(["amax", "--delta", "1", "--d", "1"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0));
    assert!(
        out.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}
