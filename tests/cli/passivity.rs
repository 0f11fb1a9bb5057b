//! End-to-end tests of `stabound passivity`.

use crate::common::{assert_bad_input, csv as rows, json, stabound, stdout, stdout_with};

/// d = 0 without a filter: every passive vertex is on Colgate's edge `delta = alpha/2 +
/// |beta|` (eq. 21) or on the axis, the polygon closes, and the stable boundary follows.
#[test]
fn no_delay_region_is_eq_21() {
    let out = stdout(&["passivity", "--delta", "0.5", "--d", "0", "--tol", "1e-8"]);
    let (header, rows) = rows(&out);
    assert_eq!(header, "region,delta,d,alpha,beta,theta,edge");
    let passive: Vec<(f64, f64)> = rows
        .iter()
        .filter(|r| r[0] == "passive")
        .map(|r| (r[3].parse().unwrap(), r[4].parse().unwrap()))
        .collect();
    assert!(passive.len() >= 4);
    assert_eq!(passive.first(), passive.last());
    // exact zero: the library clamps the axis vertices to alpha = 0
    for &(a, b) in &passive {
        assert!(
            a == 0.0 || (a / 2.0 + b.abs() - 0.5).abs() < 1e-9,
            "{a} {b}"
        );
    }
    assert!(rows.iter().any(|r| r[0] == "stable"));
    assert!(rows.iter().any(|r| r[6] == "corner"));
}

/// d = 1: the largest passive stiffness is `(2 sqrt 2 - 2) delta` at `beta = (1 - 1/sqrt 2)
/// delta`. Derivation: with `c = cos theta`, `alpha A + beta B = -4 beta c^2 + 2 alpha c +
/// alpha + 2 beta`; for `beta > 0` its maximum over `c` is at `c = alpha / (4 beta)`, giving
/// `alpha^2 / (4 beta) + alpha + 2 beta = 2 delta`; maximizing `alpha` over `beta` gives
/// `beta^2 - 2 beta delta + delta^2 / 2 = 0` (with `c < 1` and the `theta = 0` line slack).
#[test]
fn summary_for_one_sample_of_delay() {
    let v = json(&[
        "passivity",
        "--delta",
        "2",
        "--d",
        "1",
        "--summary",
        "--format",
        "json",
        "--beta",
        "0",
    ]);
    let r = &v[0];
    let a = r["alpha_max_passive"].as_f64().unwrap();
    let b = r["beta_at_max"].as_f64().unwrap();
    let s = 2f64.sqrt();
    assert!((a - 2.0 * (2.0 * s - 2.0)).abs() < 1e-6, "{a}");
    assert!((b - 2.0 * (1.0 - 1.0 / s)).abs() < 1e-3, "{b}");
    // Diolaiti et al.: at beta = 0, alpha < 2 delta / (1 + 2 n)
    let a0 = r["alpha_max_at_beta"].as_f64().unwrap();
    assert!((a0 - 4.0 / 3.0).abs() < 1e-6, "{a0}");
    assert_eq!(r["inside"], "yes");
    let share = r["passive_share_of_stable"].as_f64().unwrap();
    assert!(share > 0.0 && share < 1.0);
    assert!(r["witness_alpha"].is_null());
}

/// With a velocity filter the stable region is the filtered loop's exact boundary:
/// containment, shares, and a stable wall that is not passive, confirmed here by the
/// library's state-space eigenvalues of the filtered loop and by the criterion's certified
/// margin.
#[test]
fn filtered_loop_is_compared_with_its_stable_region() {
    let out = stabound()
        .args([
            "passivity",
            "--delta",
            "1",
            "--d",
            "1",
            "--velocity-filter-cutoff",
            "50",
            "--period",
            "0.001",
            "--mass",
            "0.5",
            "--summary",
        ])
        .output()
        .unwrap();
    assert!(out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("inside the stable region: yes"), "{err}");
    let (header, rows) = rows(&out.stdout);
    assert!(header.contains("K_max_N_per_m"));
    let cols: Vec<&str> = header.split(',').collect();
    let get = |name: &str| rows[0][cols.iter().position(|c| *c == name).unwrap()].clone();
    let num = |name: &str| -> f64 { get(name).parse().unwrap() };
    assert_eq!(get("inside"), "yes");
    assert_eq!(get("stable_method"), "exact");
    assert!(get("filter").starts_with("low-pass"));
    let a = num("alpha_max_passive");
    let k = num("K_max_N_per_m");
    // K = alpha m / T^2
    assert!((k - a * 0.5 / 1e-6).abs() <= 1e-9 * k);
    // the low-pass lag lowers the passive stiffness below the unfiltered 2 sqrt 2 - 2
    assert!(a > 0.0 && a < 2.0 * 2f64.sqrt() - 2.0, "{a}");
    let share = num("passive_share_of_stable");
    assert!(share > 0.0 && share < 1.0);
    assert!(get("witness_alpha").is_empty());
    let wall = stabound::Wall::new(
        num("stable_not_passive_alpha"),
        num("stable_not_passive_beta"),
    )
    .unwrap();
    let filter = stabound::VelocityFilter::low_pass_cutoff(50.0, 1e-3).unwrap();
    let lp = stabound::elements::Loop::new(stabound::Plant::new(1.0, 1.0).unwrap())
        .with_filter(filter)
        .unwrap();
    let checker =
        stabound::stability::Checker::new(lp, stabound::stability::Options::default()).unwrap();
    let roots = checker
        .roots(&wall, stabound::stability::Method::StateSpace)
        .unwrap();
    assert!(stabound::stability::spectral_radius(&roots) < 1.0);
    let crit = stabound::passivity::Criterion::new(1.0, filter).unwrap();
    assert!(crit.margin(1.0, &wall).unwrap().1 < 0.0);
}

/// The (delta, beta) plane at one stiffness: the summary row and the region rows, with and
/// without a filter; alpha = 0 has no stable region to compare with.
#[test]
fn delta_beta_comparison() {
    for extra in [&[][..], &["--velocity-filter-samples", "3"][..]] {
        let mut args = vec![
            "passivity",
            "--plane",
            "delta-beta",
            "--alpha",
            "0.5",
            "--d",
            "1",
            "--delta",
            "3",
            "--summary",
            "--format",
            "json",
        ];
        args.extend(extra);
        let v = json(&args);
        let r = &v[0];
        assert_eq!(r["inside"], "yes");
        assert_eq!(r["stable_method"], "columns");
        let share = r["passive_share_of_stable"].as_f64().unwrap();
        assert!(share > 0.0 && share < 1.0, "{share}");
        assert!(r["witness_delta"].is_null());
        assert!(r["stable_not_passive_delta"].as_f64().unwrap() <= 3.0);
    }
    let out = stdout(&[
        "passivity",
        "--plane",
        "delta-beta",
        "--alpha",
        "0.5",
        "--d",
        "1",
        "--filter-pole",
        "0.5",
    ]);
    let (header, rows) = rows(&out);
    assert_eq!(header, "region,alpha,d,delta,beta,theta,edge");
    assert!(rows.iter().any(|r| r[0] == "stable" && r[6] == "columns"));
    assert_bad_input(
        &[
            "passivity",
            "--plane",
            "delta-beta",
            "--alpha",
            "0",
            "--summary",
        ],
        true,
    );
}

#[test]
fn files_svg_and_companion_figures() {
    let dir = tempfile::tempdir().unwrap();
    let (svg, data) = (dir.path().join("p.svg"), dir.path().join("p.json"));
    stabound()
        .args([
            "passivity",
            "--plane",
            "delta-beta",
            "--alpha",
            "1",
            "--d",
            "2",
            "--velocity-filter-samples",
            "3",
            "--format",
            "json",
            "-o",
        ])
        .arg(&data)
        .arg("--svg")
        .arg(&svg)
        .assert()
        .success()
        .stdout("");
    let v: serde_json::Value = serde_json::from_slice(&std::fs::read(&data).unwrap()).unwrap();
    let arr = v.as_array().unwrap();
    // the passive edge, then the filtered loop's stable region from its columns
    assert!(arr.iter().filter(|r| r["region"] == "passive").count() > 10);
    assert!(
        arr.iter()
            .filter(|r| r["region"] == "stable")
            .all(|r| r["edge"] == "columns")
    );
    assert!(std::fs::read_to_string(&svg).unwrap().starts_with("<svg"));
    let figs = dir.path().join("figs");
    stabound()
        .args(["passivity", "--figures-dir"])
        .arg(&figs)
        .assert()
        .success();
    for name in [
        "fig08-d1", "fig08-d2", "fig08-d4", "fig09-d1", "fig09-d2", "fig09-d4",
    ] {
        let csv = std::fs::read_to_string(figs.join(format!("{name}.csv"))).unwrap();
        assert!(
            csv.contains("passivity") && csv.contains("boundary"),
            "{name}"
        );
        assert!(figs.join(format!("{name}.svg")).exists());
    }
    assert_clean_legends(&figs);
}

#[test]
fn same_output_on_one_and_two_threads() {
    let args = ["passivity", "--delta", "1", "--d", "2", "--tol", "1e-6"];
    assert_eq!(stdout_with(&args, Some("1")), stdout_with(&args, Some("2")));
}

#[test]
fn bad_input() {
    let e = assert_bad_input(&["passivity", "--delta", "1", "--d", "0.5"], true);
    assert!(e.contains("whole"), "{e}");
    let e = assert_bad_input(
        &[
            "passivity",
            "--delta",
            "1",
            "--velocity-filter-cutoff",
            "30",
        ],
        true,
    );
    assert!(e.contains("--period"), "{e}");
    assert_bad_input(
        &[
            "passivity",
            "--delta",
            "1",
            "--filter-pole",
            "0.5",
            "--velocity-filter-samples",
            "3",
        ],
        false,
    );
    assert_bad_input(&["passivity", "--plane", "delta-beta", "--d", "1"], true);
    assert_bad_input(&["passivity", "--d", "1"], true);
    assert_bad_input(&["passivity", "--delta", "-1"], true);
    assert_bad_input(&["passivity", "--delta", "1", "--filter-pole", "1"], true);
    assert_bad_input(&["passivity", "--delta", "1", "--tol", "0"], true);
}

/// Physical units: m = 0.1 kg, T = 1 ms, b = 200 N s/m is delta = 2, a delay of 1 ms is one
/// sample, and B = 0 N s/m is beta = 0. The largest passive stiffness is then
/// `2 (2 sqrt 2 - 2)` (normalized, as above) and `K = alpha m / T^2` in N/m; at B = 0 it is
/// Diolaiti et al.'s `2 delta / (1 + 2 n) = 4/3`.
#[test]
fn physical_units_are_converted() {
    let v = json(&[
        "passivity",
        "--mass",
        "0.1",
        "--period",
        "0.001",
        "--damping",
        "200",
        "--delay",
        "0.001",
        "--wall-damping",
        "0",
        "--summary",
        "--format",
        "json",
    ]);
    let r = &v[0];
    let a = r["alpha_max_passive"].as_f64().unwrap();
    let s = 2f64.sqrt();
    assert!((r["delta"].as_f64().unwrap() - 2.0).abs() < 1e-12, "{r}");
    assert!((r["d"].as_f64().unwrap() - 1.0).abs() < 1e-12, "{r}");
    assert!((a - 2.0 * (2.0 * s - 2.0)).abs() < 1e-6, "{a}");
    assert!(
        (r["alpha_max_at_beta"].as_f64().unwrap() - 4.0 / 3.0).abs() < 1e-6,
        "{r}"
    );
    // the delta-beta plane at K = 20 kN/m (alpha = 0.2), drawn up to b = 400 N s/m
    let out = stdout(&[
        "passivity",
        "--plane",
        "delta-beta",
        "--mass",
        "0.1",
        "--period",
        "0.001",
        "--stiffness",
        "20000",
        "--damping",
        "400",
        "--delay-samples",
        "1",
    ]);
    let (header, rows) = rows(&out);
    assert!(header.starts_with("region,alpha,d,delta,beta"), "{header}");
    assert!(
        rows.iter()
            .all(|r| (r[1].parse::<f64>().unwrap() - 0.2).abs() < 1e-12)
    );
    let widest = rows
        .iter()
        .filter(|r| r[0] == "passive")
        .map(|r| r[3].parse::<f64>().unwrap())
        .fold(f64::NEG_INFINITY, f64::max);
    // the edge is traced to the default tolerance 1e-7
    assert!((widest - 4.0).abs() <= 1e-7, "{widest}");
    for args in [
        &["passivity", "--damping", "200", "--d", "1"][..],
        &[
            "passivity",
            "--delta",
            "2",
            "--damping",
            "200",
            "--mass",
            "0.1",
            "--period",
            "0.001",
        ],
        &["passivity", "--delta", "2", "--delay", "0.001"],
    ] {
        // clap reports the conflict with its usage lines; the others are one line
        let err = assert_bad_input(args, false);
        assert!(err.contains("--"), "{err}");
    }
}

/// Without physical damping no wall is passive, and at the smallest subnormal damping the
/// passive triangle's area underflows to 0: no share of the stable region is passive.
#[test]
fn empty_passive_region_has_no_share() {
    for (delta, d) in [("0", "1"), ("5e-324", "0")] {
        let v = json(&[
            "passivity",
            "--delta",
            delta,
            "--d",
            d,
            "--summary",
            "--format",
            "json",
        ]);
        let r = &v[0];
        assert_eq!(r["passive_area"].as_f64(), Some(0.0), "{r}");
        assert!(r["stable_area"].as_f64().unwrap() > 0.0, "{r}");
        assert_eq!(r["passive_share_of_stable"].as_f64(), Some(0.0), "{r}");
    }
}

/// A low-pass pole near 1 (a peak of B one millionth of a radian wide at theta = 0): the
/// maximum over frequency converges and the largest passive stiffness tends to Diolaiti's
/// bound without damping, `2 delta / (1 + 2n)` (the filtered velocity is near zero).
#[test]
fn slow_filter_converges() {
    let v = json(&[
        "passivity",
        "--delta",
        "1",
        "--d",
        "1",
        "--filter-pole",
        "0.999999",
        "--summary",
        "--format",
        "json",
    ]);
    let a = v[0]["alpha_max_passive"].as_f64().unwrap();
    assert!((a - 2.0 / 3.0).abs() < 1e-5, "{a}");
    // the stable region reaches beta ~ 1e8; the passive region is still resolved
    assert_eq!(v[0]["stable_method"], "exact");
    let (passive, stable) = (
        v[0]["passive_area"].as_f64().unwrap(),
        v[0]["stable_area"].as_f64().unwrap(),
    );
    assert!(passive > 0.0 && passive < stable, "{passive} {stable}");
    let share = v[0]["passive_share_of_stable"].as_f64().unwrap();
    assert!((share - passive / stable).abs() <= 1e-9 * share, "{share}");
}

/// A second-order Butterworth velocity filter: the exact comparison answers, and its passive
/// share agrees with the library's column comparison (an independent route to the stable
/// region, exact on lines) within that route's error bound.
#[test]
fn butterworth_filter_is_compared_exactly() {
    let v = json(&[
        "passivity",
        "--delta",
        "1",
        "--d",
        "1",
        "--velocity-filter-order",
        "2",
        "--velocity-filter-cutoff",
        "100",
        "--period",
        "0.001",
        "--summary",
        "--format",
        "json",
    ]);
    let r = &v[0];
    assert_eq!(r["stable_method"], "exact");
    assert_eq!(r["inside"], "yes");
    assert!(r["filter"].as_str().unwrap().starts_with("second-order"));
    let share = r["passive_share_of_stable"].as_f64().unwrap();
    let filter = stabound::VelocityFilter::butterworth(0.1).unwrap();
    let c = stabound::passivity::compare_on_lines(1.0, 1.0, filter, 128, 1e-7).unwrap();
    assert!(
        (share - c.passive_fraction_of_stable).abs() <= c.fraction_bound,
        "{share} {c:?}"
    );
}

/// `--figures-dir` draws each companion with the size options, checks them before any work
/// (exit 2, as every other command), and a path that is not a directory is bad input.
#[test]
fn figures_dir_takes_the_size_options() {
    let dir = tempfile::tempdir().unwrap();
    let figs = dir.path().join("figs");
    let e = assert_bad_input(
        &[
            "passivity",
            "--figures-dir",
            figs.to_str().unwrap(),
            "--width",
            "20000",
        ],
        true,
    );
    assert!(e.contains("width"), "{e}");
    assert!(!figs.exists(), "nothing written before the check");
    let file = dir.path().join("a-file");
    std::fs::write(&file, "x").unwrap();
    let e = assert_bad_input(
        &["passivity", "--figures-dir", file.to_str().unwrap()],
        true,
    );
    assert!(e.contains("not a directory"), "{e}");
    stabound()
        .args(["passivity", "--figures-dir"])
        .arg(&figs)
        .args(["--width", "640", "--height", "400"])
        .assert()
        .success();
    let svg = std::fs::read_to_string(figs.join("fig08-d1.svg")).unwrap();
    assert!(svg.contains("width=\"640\""), "{}", &svg[..200]);
}

/// The encoder and Coulomb friction: the largest passive spring is `min(2 b / T, 2 f_c /
/// Delta_x)` in N/m (here 2 f_c / Delta_x = 2 * 0.5 / 1e-5 = 1e5 N/m against 2 b / T = 4e5
/// N/m); a delay is refused with the reason (exit 2).
#[test]
fn encoder_and_friction_bound_the_passive_spring() {
    let base = [
        "passivity",
        "--damping",
        "200",
        "--mass",
        "0.5",
        "--period",
        "0.001",
        "--encoder-resolution",
        "1e-5",
        "--coulomb-friction",
        "0.5",
        "--summary",
    ];
    let out = stabound().args(base).args(["--d", "0"]).output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let err = String::from_utf8_lossy(&out.stderr);
    let line = err
        .lines()
        .find(|l| l.starts_with("largest passive spring with the quantizers"))
        .unwrap_or_else(|| panic!("{err}"));
    let k: f64 = line
        .split("K = ")
        .nth(1)
        .and_then(|r| r.split(' ').next())
        .unwrap()
        .parse()
        .unwrap();
    assert!((k - 1e5).abs() <= 1e-6 * 1e5, "{line}");
    let e = assert_bad_input(&[&base[..], &["--d", "1"][..]].concat(), false);
    assert!(e.contains("undelayed"), "{e}");
}

/// The companions' legends (in `figs`) print the stiffness `alpha0 / (1 + 2d)` cleanly: four
/// decimals without trailing zeros (`0.3333`, `0.2`), never the binary expansion
/// (`0.3333333333333333`) or padding (`0.2000`).
fn assert_clean_legends(figs: &std::path::Path) {
    let legends = |name: &str| -> Vec<String> {
        let svg = std::fs::read_to_string(figs.join(name)).unwrap();
        svg.split("α = ")
            .skip(1)
            .map(|r| {
                r.chars()
                    .take_while(|c| c.is_ascii_digit() || *c == '.')
                    .collect()
            })
            .collect()
    };
    let d1 = legends("fig09-d1.svg");
    for v in ["0.3333", "0.6667", "1.3333"] {
        assert!(d1.iter().any(|l| l == v), "{d1:?}");
    }
    let d2 = legends("fig09-d2.svg");
    assert!(d2.iter().any(|l| l == "0.2"), "{d2:?}");
    for l in d1.iter().chain(&d2) {
        let decimals = l.split('.').nth(1).map_or(0, str::len);
        assert!((decimals <= 4 && !l.ends_with('0')) || l == "0", "{l}");
    }
}
