//! End-to-end tests of `stabound figure`.

use assert_cmd::Command;

fn stabound() -> Command {
    Command::cargo_bin("stabound").unwrap()
}

/// `figure 11` writes the SVG and the CSV, whole, into --output-dir (created if missing).
#[test]
fn writes_svg_and_csv() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("new/sub");
    let o = stabound()
        .args(["figure", "11", "--output-dir", out.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(
        o.stdout.is_empty(),
        "data goes to files, messages to stderr"
    );
    let svg = std::fs::read_to_string(out.join("fig11.svg")).unwrap();
    assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
    assert!(svg.contains("b = 100 N s/m"));
    let csv = std::fs::read_to_string(out.join("fig11.csv")).unwrap();
    assert!(csv.starts_with("series,time_s,position_m\n"));
    // 3 responses x (80 periods x 5 points + the start).
    assert_eq!(csv.lines().count(), 1 + 3 * 401);
}

#[test]
fn bad_figure_exits_2() {
    for which in ["4", "12", "x", "-1", ""] {
        let o = stabound().args(["figure", which]).output().unwrap();
        assert_eq!(o.status.code(), Some(2), "{which}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!err.contains("panicked"), "{err}");
    }
}
