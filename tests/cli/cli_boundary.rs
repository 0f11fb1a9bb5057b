//! End-to-end tests of `stabound boundary`.

use crate::common::{assert_bad_input, csv as rows, stabound, stdout};

/// CSV header, one closed polyline per (delta, d) in request order, starting at (0, -delta)
/// (paper eq. 19), with alpha_max = 12 - 8 sqrt 2 for delta = 0, d = 0 (docs/MODEL.md section 6).
#[test]
fn csv_closed_polylines_in_order() {
    let out = stdout(&[
        "boundary", "--delta", "0,0.5", "--d", "0,1", "--tol", "1e-7",
    ]);
    let (header, rows) = rows(&out);
    assert_eq!(header, "delta,d,alpha,beta,piece");
    let mut groups: Vec<(String, String)> = Vec::new();
    for r in &rows {
        let key = (r[0].clone(), r[1].clone());
        if groups.last() != Some(&key) {
            groups.push(key);
        }
    }
    let expect: Vec<(String, String)> = [("0", "0"), ("0", "1"), ("0.5", "0"), ("0.5", "1")]
        .iter()
        .map(|(a, b)| (a.to_string(), b.to_string()))
        .collect();
    assert_eq!(groups, expect);
    for (delta, d) in &expect {
        let pts: Vec<(f64, f64)> = rows
            .iter()
            .filter(|r| &r[0] == delta && &r[1] == d)
            .map(|r| (r[2].parse().unwrap(), r[3].parse().unwrap()))
            .collect();
        assert_eq!(pts.first(), pts.last());
        let dl: f64 = delta.parse().unwrap();
        assert!(pts[0].0.abs() < 1e-12 && (pts[0].1 + dl).abs() < 1e-9);
        if delta == "0" && d == "0" {
            let amax = pts.iter().map(|p| p.0).fold(0.0, f64::max);
            assert!((amax - (12.0 - 8.0 * 2f64.sqrt())).abs() < 1e-6, "{amax}");
        }
    }
}

#[test]
fn json_svg_and_file_output() {
    let dir = tempfile::tempdir().unwrap();
    let svg = dir.path().join("b.svg");
    let json = dir.path().join("b.json");
    stabound()
        .args([
            "boundary", "--delta", "0.5", "--d", "1", "--format", "json", "-o",
        ])
        .arg(&json)
        .arg("--svg")
        .arg(&svg)
        .assert()
        .success()
        .stdout("");
    let v: serde_json::Value = serde_json::from_slice(&std::fs::read(&json).unwrap()).unwrap();
    let arr = v.as_array().unwrap();
    assert!(arr.len() > 100);
    assert_eq!(arr[0]["delta"], 0.5);
    assert_eq!(arr[0]["piece"], "curve");
    let s = std::fs::read_to_string(&svg).unwrap();
    assert!(
        s.starts_with("<svg") && s.contains("δ = 0.5") && s.contains("α (normalized stiffness)")
    );
}

/// Many curves: one panel per delay factor, each listing its own deltas in distinct colours
/// (a single panel of 12 curves would reuse the palette's ten colours); a few curves: one
/// panel with `d` in every label.
#[test]
fn many_curves_draw_one_panel_per_delay() {
    let dir = tempfile::tempdir().unwrap();
    let draw = |deltas: &str, ds: &str| {
        let svg = dir.path().join("b.svg");
        stabound()
            .args([
                "boundary", "--delta", deltas, "--d", ds, "--tol", "1e-6", "-o",
            ])
            .arg(dir.path().join("b.csv"))
            .arg("--svg")
            .arg(&svg)
            .assert()
            .success();
        std::fs::read_to_string(&svg).unwrap()
    };
    let s = draw("0,0.5,1,2", "0,0.5,1");
    for d in ["0", "0.5", "1"] {
        assert!(
            s.contains(&format!(">Stability boundaries, d = {d}<")),
            "panel d = {d}"
        );
    }
    assert_eq!(s.matches("<g transform=\"translate(").count(), 3);
    // each panel's legend names deltas only, each once per panel
    assert_eq!(s.matches(">δ = 0.5<").count(), 3);
    assert!(!s.contains("d = 0, δ"));
    // within a panel no colour repeats among the legend's line samples
    for panel in s.split("<g transform=\"translate(").skip(1) {
        let legend = panel.split("class=\"legend\"").nth(1).unwrap();
        let mut colours: Vec<&str> = legend
            .split("<path d=\"M")
            .skip(1)
            .filter(|p| p.split('"').next().is_some_and(|d| d.contains('H')))
            .filter_map(|p| p.split("stroke=\"").nth(1)?.split('"').next())
            .collect();
        let n = colours.len();
        colours.sort();
        colours.dedup();
        assert_eq!((colours.len(), n), (4, 4), "a colour repeats in a panel");
    }
    let s = draw("0,0.5", "0,1");
    assert_eq!(s.matches("<g transform=\"translate(").count(), 0);
    assert!(s.contains(">d = 1, δ = 0.5<") && s.contains(">Stability boundaries<"));
}

/// The delta-beta plane at alpha = 0 (paper Fig. 6): at delta = 0, d = 1 the stable beta
/// range is (0, 2 sqrt 2 - 2), the same as the alpha = 0 edge of the alpha-beta boundary.
#[test]
fn delta_beta_plane() {
    let out = stdout(&[
        "boundary",
        "--plane",
        "delta-beta",
        "--alpha",
        "0",
        "--d",
        "1",
        "--delta",
        "0,1",
        "--tol",
        "1e-7",
    ]);
    let (header, rows) = rows(&out);
    assert_eq!(header, "alpha,d,delta,beta,loop,piece");
    let at0: Vec<f64> = rows
        .iter()
        .filter(|r| r[2].parse::<f64>().unwrap() == 0.0)
        .map(|r| r[3].parse().unwrap())
        .collect();
    let hi = at0.iter().copied().fold(f64::MIN, f64::max);
    let lo = at0.iter().copied().fold(f64::MAX, f64::min);
    assert!((hi - (2.0 * 2f64.sqrt() - 2.0)).abs() < 1e-6, "{hi}");
    assert!(lo.abs() < 1e-6, "{lo}");
}

#[test]
fn bad_input_exits_2() {
    for args in [
        &["boundary", "--delta", "0.5"][..],
        &["boundary", "--delta", "-1", "--d", "1"],
        &["boundary", "--delta", "0.5", "--d", "1", "--tol", "0"],
        &["boundary", "--delta", "0.5", "--d", "x"],
        &["boundary", "--plane", "delta-beta", "--d", "1"],
        &[
            "boundary",
            "--plane",
            "delta-beta",
            "--alpha",
            "0",
            "--d",
            "1",
            "--method",
            "exact",
        ],
        &["boundary", "--delta", "0.5", "--d", "1", "--alpha", "0.1"],
    ] {
        assert_bad_input(args, false);
    }
}

/// A device in physical units gives the same curve as its normalized plant (delta = b T / m,
/// d = delay / T, computed here), with the physical values of every vertex beside it.
#[test]
fn physical_units_give_the_normalized_curve_and_its_physical_values() {
    let (m, t, b) = (0.25, 1e-3, 2.0);
    let phys = crate::common::stdout(&[
        "boundary",
        "--mass",
        "0.25",
        "--period",
        "1e-3",
        "--damping",
        "2",
        "--delay",
        "0.002",
        "--tol",
        "1e-4",
    ]);
    let norm =
        crate::common::stdout(&["boundary", "--delta", "0.008", "--d", "2", "--tol", "1e-4"]);
    let (head, rows) = crate::common::csv(&phys);
    assert_eq!(
        head,
        "delta,d,alpha,beta,piece,damping_Ns_per_m,stiffness_N_per_m,wall_damping_Ns_per_m"
    );
    let (_, norm_rows) = crate::common::csv(&norm);
    assert_eq!(rows.len(), norm_rows.len());
    for (p, n) in rows.iter().zip(&norm_rows) {
        assert_eq!(&p[..5], &n[..], "normalized columns");
        let num = |i: usize| p[i].parse::<f64>().unwrap();
        let (alpha, beta) = (num(2), num(3));
        assert!((num(5) - b).abs() <= 1e-12 * b);
        assert!((num(6) - alpha * m / (t * t)).abs() <= 1e-9 * (1.0 + num(6).abs()));
        assert!((num(7) - beta * m / t).abs() <= 1e-9 * (1.0 + num(7).abs()));
    }
    let e = assert_bad_input(
        &[
            "boundary",
            "--plane",
            "delta-beta",
            "--alpha",
            "1",
            "--d",
            "1",
            "--mass",
            "0.25",
        ],
        true,
    );
    // the delta-beta plane's axes are normalized; a device there only carries elements
    assert!(e.contains("loop elements"), "{e}");
    let e = assert_bad_input(
        &[
            "boundary",
            "--plane",
            "delta-beta",
            "--alpha",
            "1",
            "--d",
            "1",
            "--damping",
            "5",
        ],
        true,
    );
    assert!(e.contains("alpha-beta plane"), "{e}");
}

/// A loop whose exact boundary does not close (a 64-sample average at delta = 30, where the
/// boundary is dozens of short curve pieces between the curve's excursions to infinity)
/// still answers: the bisection engine's boundary, exit 0, and a warning on stderr that says
/// so; a loop the exact engine closes prints no warning.
#[test]
fn unclosed_exact_boundary_falls_back_and_says_so() {
    let loop_args = |samples: &'static str, damping: &'static str| {
        [
            "boundary",
            "--mass",
            "1",
            "--period",
            "1",
            "--damping",
            damping,
            "--delay-samples",
            "0",
            "--velocity-filter-samples",
            samples,
            "--tol",
            "1e-6",
        ]
    };
    let out = stabound().args(loop_args("64", "30")).output().unwrap();
    assert_eq!(out.status.code(), Some(0));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.starts_with("warning: ") && err.contains("bisection engine drew it"),
        "{err}"
    );
    let (_, lines) = rows(&out.stdout);
    assert!(lines.len() > 100 && lines.iter().all(|r| r[4] == "bisection"));
    let out = stabound().args(loop_args("16", "10")).output().unwrap();
    assert_eq!(out.status.code(), Some(0));
    assert!(
        out.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let (_, lines) = rows(&out.stdout);
    assert!(lines.iter().any(|r| r[4] == "curve"));
}

/// A region too large for --tol's vertex budget (delta = 1000 at the default 1e-9) is traced
/// to the same fraction of its size and answers, with a warning naming the tolerance used;
/// its rows are those of asking for that tolerance (1e-6 of a region of size 1000).
#[test]
fn large_region_answers_at_a_relative_tolerance() {
    let out = stabound()
        .args(["boundary", "--delta", "1000", "--d", "1"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.starts_with("warning: ") && err.contains("traced to 1"),
        "{err}"
    );
    let asked = stdout(&["boundary", "--delta", "1000", "--d", "1", "--tol", "1e-6"]);
    let (_, got) = rows(&out.stdout);
    let (_, want) = rows(&asked);
    assert_eq!(got.len(), want.len());
}

/// Behind a second-order Butterworth filter at 2 Hz on a 1 kHz loop (0.002 of the rate, delta
/// 0.001) the stable region ends in a wedge whose two edges meet at about 0.005 rad. At the
/// default tolerance the exact engine closes it (exit 0, no warning, no bisection piece), one
/// closed polyline, and its stiffest vertex is the wedge's tip that `amax` finds by its own
/// search, to a relative `1e-6` (the two engines share no code path).
#[test]
fn slow_butterworth_wedge_closes_at_the_default_tolerance() {
    for delay in ["0", "0.001", "0.0027"] {
        let device = [
            "--mass",
            "1",
            "--period",
            "0.001",
            "--damping",
            "1",
            "--delay",
            delay,
            "--velocity-filter-cutoff",
            "2",
            "--velocity-filter-order",
            "2",
        ];
        let out = stabound()
            .args([&["boundary"][..], &device].concat())
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "delay {delay}: {err}");
        assert!(!err.contains("warning"), "delay {delay}: {err}");
        let (_, rows) = rows(&out.stdout);
        assert!(rows.iter().all(|r| r[4] != "bisection"), "delay {delay}");
        let pts: Vec<(f64, f64)> = rows
            .iter()
            .map(|r| (r[2].parse().unwrap(), r[3].parse().unwrap()))
            .collect();
        assert_eq!(pts.first(), pts.last(), "delay {delay}");
        let right = pts.iter().map(|p| p.0).fold(f64::NEG_INFINITY, f64::max);
        let amax = crate::common::json(&[&["amax", "--format", "json"][..], &device].concat());
        let amax = amax[0]["alpha_max"].as_f64().unwrap();
        assert!(
            (right - amax).abs() <= 1e-6 * amax,
            "delay {delay}: stiffest vertex {right}, alpha_max {amax}"
        );
    }
}

/// A loop whose stable region lies within rounding of the unit circle (no physical damping
/// and a first-order velocity filter whose pole is 1e-7 from `z = 1`, 2.7 samples of delay):
/// the exact engine's rounds of finer samples meet as many turns off the region as the
/// round before, so its pieces are not trusted and the bisection engine is asked instead;
/// its grid holds no clearly stable point either (walls there are stable by less than
/// `1e-8`, below what the eigenvalues resolve), so the command ends with exit 1 and one
/// message giving both engines' reasons, never a boundary drawn from rounding.
#[test]
fn region_within_rounding_of_the_circle_says_why_both_engines_fail() {
    // pole exp(-2 pi f_c T) = 1 - 1e-7 at T = 1 s
    let cutoff = (-(1.0f64 - 1e-7).ln() / (2.0 * std::f64::consts::PI)).to_string();
    let out = stabound()
        .args([
            "boundary",
            "--mass",
            "1",
            "--period",
            "1",
            "--damping",
            "0",
            "--delay-samples",
            "2.7",
            "--velocity-filter-cutoff",
            &cutoff,
        ])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("rounds of finer samples") && err.contains("no stable point found"),
        "{err}"
    );
}
