//! End-to-end tests of `stabound step`.

use assert_cmd::Command;

fn stabound() -> Command {
    Command::cargo_bin("stabound").unwrap()
}

const DEVICE: [&str; 6] = ["--mass", "0.1", "--period", "0.001", "--delay-samples", "1"];

/// The CSV: header, one row per point, the time grid of --points-per-period, and the response
/// of a stable wall ends at F_H / K (static deflection, independent of the simulation).
#[test]
fn csv_rows_and_final_value() {
    let out = stabound()
        .arg("step")
        .args(DEVICE)
        .args([
            "--damping",
            "0,100",
            "--stiffness",
            "8000",
            "--wall-damping",
            "40",
        ])
        .args([
            "--force",
            "2",
            "--duration",
            "0.4",
            "--points-per-period",
            "4",
        ])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next().unwrap(),
        "damping_Ns_per_m,stiffness_N_per_m,wall_damping_Ns_per_m,time_s,position_m"
    );
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|c| c.parse().unwrap()).collect())
        .collect();
    // 400 periods x 4 points + the start, per damping.
    assert_eq!(rows.len(), 2 * 1601);
    for b in [0.0, 100.0] {
        let mine: Vec<&Vec<f64>> = rows.iter().filter(|r| r[0] == b).collect();
        assert_eq!(mine.len(), 1601);
        assert!((mine[4][3] - 0.001).abs() < 1e-15);
        let last = mine.last().unwrap();
        // 0.4 s is over 50 decay times of these walls: within 1e-6 of 2 N / 8000 N/m.
        assert!(
            (last[4] / (2.0 / 8000.0) - 1.0).abs() < 1e-6,
            "{b}: {}",
            last[4]
        );
    }
}

/// Summary and SVG; an unstable wall warns on stderr but still simulates.
#[test]
fn summary_svg_and_warning() {
    let dir = tempfile::tempdir().unwrap();
    let svg = dir.path().join("s.svg");
    let out = stabound()
        .arg("step")
        .args(DEVICE)
        .args([
            "--damping",
            "0,100",
            "--stiffness",
            "20000",
            "--wall-damping",
            "40",
        ])
        .args(["--format", "summary", "--svg", svg.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    assert_eq!(text.lines().count(), 2);
    // alpha = 0.2 > alpha_max(0, 1) = 0.1445 (paper eq. 25): unstable; with b = 100 N s/m
    // (delta = 1) the same wall is stable.
    assert!(text.lines().next().unwrap().contains("unstable"));
    assert!(text.lines().nth(1).unwrap().contains(", stable;"));
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(err.contains("warning") && err.contains("unstable"), "{err}");
    let s = std::fs::read_to_string(&svg).unwrap();
    assert!(s.starts_with("<svg") && s.contains("b = 100 N s/m"));
}

#[test]
fn bad_input_exits_2() {
    let cases: &[&[&str]] = &[
        &["--damping", "0", "--stiffness", "1", "--mass", "0"],
        &["--damping", "-1", "--stiffness", "1"],
        &["--damping", "0"],
        &["--damping", "0", "--stiffness", "1", "--margin", "0.75"],
        &["--damping", "0", "--stiffness", "1", "--duration", "1e9"],
        &[
            "--damping",
            "0",
            "--stiffness",
            "1",
            "--points-per-period",
            "0",
        ],
        &["--damping", "a", "--stiffness", "1"],
    ];
    for args in cases {
        let out = stabound()
            .arg("step")
            .args(DEVICE)
            .args(*args)
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!err.contains("panicked"), "{err}");
        assert!(out.stdout.is_empty());
    }
}

/// --margin 0.75 reproduces the paper's Section VIII walls (docs/MODEL.md section 6): alpha =
/// 0.108, 0.149, 0.656 and beta = 0.425, 0.416, 0.388 for b = 0, 10, 100 N s/m.
#[test]
fn margin_gives_section8_walls() {
    let out = stabound()
        .arg("step")
        .args(DEVICE)
        .args([
            "--damping",
            "0,10,100",
            "--margin",
            "0.75",
            "--format",
            "summary",
        ])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).unwrap();
    let grab = |line: &str, key: &str| -> f64 {
        let i = line.find(key).unwrap() + key.len();
        line[i..].split(')').next().unwrap().parse().unwrap()
    };
    let published = [(0.108, 0.425), (0.149, 0.416), (0.656, 0.388)];
    for (line, (alpha, beta)) in text.lines().zip(published) {
        // Published to three decimals: half a unit in the last place.
        assert!((grab(line, "(alpha = ") - alpha).abs() <= 5e-4, "{line}");
        assert!((grab(line, "(beta = ") - beta).abs() <= 5e-4, "{line}");
        assert!(line.contains(", stable;"), "{line}");
    }
}
