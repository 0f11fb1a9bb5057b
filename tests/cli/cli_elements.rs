//! `stabound check` with loop elements named in physical units.

use crate::common::assert_bad_input;

fn json(args: &[&str]) -> serde_json::Value {
    let device = [
        "check",
        "--mass",
        "0.1",
        "--period",
        "0.001",
        "--damping",
        "10",
        "--stiffness",
        "2000",
        "--wall-damping",
        "5",
        "--delay-samples",
        "1",
        "--format",
        "json",
        "--radius",
    ];
    crate::common::json(&[&device[..], args].concat())
}

/// No element named: no `elements` entry. A hand of nothing changes nothing but the route
/// (the general discretization agrees with the closed forms to rounding, so the spectral
/// radius agrees to 1e-12).
#[test]
fn a_hand_of_nothing_changes_nothing() {
    let bare = json(&[]);
    assert!(bare.get("elements").is_none());
    let zero = json(&[
        "--hand-mass",
        "0",
        "--hand-damping",
        "0",
        "--hand-stiffness",
        "0",
    ]);
    assert_eq!(zero["verdict"], bare["verdict"]);
    assert_eq!(zero["degree"], bare["degree"]);
    let (r0, r1) = (
        bare["spectral_radius"].as_f64().unwrap(),
        zero["spectral_radius"].as_f64().unwrap(),
    );
    assert!((r0 - r1).abs() < 1e-12, "{r0} {r1}");
}

/// Physical units normalize as the model document's table: m_h = 0.05 kg on m = 0.1 kg is
/// mu_h = 0.5; b_h = 2 N s/m is delta_h = 0.02; a 10 Hz cutoff at 1 kHz is the pole
/// exp(-2 pi 0.01); tau_a = 2 ms is tau = 2. Each element adds its states to the degree.
#[test]
fn elements_in_physical_units() {
    let v = json(&[
        "--hand-mass",
        "0.05",
        "--hand-damping",
        "2",
        "--velocity-filter-cutoff",
        "10",
        "--actuator-time-constant",
        "0.002",
    ]);
    let e = &v["elements"];
    let close = |x: &serde_json::Value, want: f64| (x.as_f64().unwrap() - want).abs() < 1e-15;
    assert!(close(&e["hand"]["mu_h"], 0.5), "{e}");
    assert!(close(&e["hand"]["delta_h"], 0.02), "{e}");
    assert!(close(&e["actuator"]["tau"], 2.0), "{e}");
    let pole = (-2.0 * std::f64::consts::PI * 0.01).exp();
    assert!(close(&e["velocity_filter"]["low_pass_pole"], pole), "{e}");
    // degree: paper's 4, plus one for the lag (the low-pass's state and its z cancel)
    assert_eq!(v["degree"], 5);
    let t = json(&[
        "--handle-mass",
        "0.03",
        "--transmission-stiffness",
        "1e4",
        "--encoder",
        "handle",
    ]);
    assert_eq!(t["degree"], 6);
    assert_eq!(t["elements"]["transmission"]["encoder"], "handle");
}

/// A very stiff transmission is the rigid device: kappa_c = 1e9 N/m T^2 / m = 1e4, so the
/// loop's slow roots move by about 1 / kappa_c.
#[test]
fn stiff_transmission_is_the_rigid_device() {
    let bare = json(&[]);
    let stiff = json(&[
        "--handle-mass",
        "0.03",
        "--transmission-stiffness",
        "1e9",
        "--transmission-damping",
        "50",
    ]);
    let (r0, r1) = (
        bare["spectral_radius"].as_f64().unwrap(),
        stiff["spectral_radius"].as_f64().unwrap(),
    );
    assert!((r0 - r1).abs() < 1e-3, "{r0} {r1}");
}

#[test]
fn refuses_bad_elements() {
    let dev = [
        "check",
        "--mass",
        "0.1",
        "--period",
        "0.001",
        "--damping",
        "10",
        "--stiffness",
        "2000",
        "--wall-damping",
        "5",
        "--delay-samples",
        "1",
    ];
    fn with<'a>(dev: &[&'a str], extra: &[&'a str]) -> Vec<&'a str> {
        [dev, extra].concat()
    }
    let e = assert_bad_input(&with(&dev, &["--velocity-filter-cutoff", "600"]), true);
    assert!(e.contains("Nyquist"), "{e}");
    let e = assert_bad_input(
        &with(
            &dev,
            &["--handle-mass", "0.2", "--transmission-stiffness", "1e4"],
        ),
        true,
    );
    assert!(e.contains("below the device's mass"), "{e}");
    let e = assert_bad_input(&with(&dev, &["--hand-mass", "-1"]), true);
    assert!(e.contains("hand mass"), "{e}");
    let e = assert_bad_input(&with(&dev, &["--velocity-filter-samples", "0"]), true);
    assert!(e.contains("samples"), "{e}");
    let e = assert_bad_input(
        &[
            "check",
            "--alpha",
            "1",
            "--beta",
            "1",
            "--delta",
            "0",
            "--d",
            "0",
            "--hand-mass",
            "1",
        ],
        true,
    );
    assert!(e.contains("physical units"), "{e}");
}

/// `amax` with loop elements: every row's K_max is the edge of the stable walls that
/// `check` with the same element flags finds (stable 1e-5 below at B, unstable 1e-5 above at
/// B and at B +- 2 %); without elements the rows are the bare loop's.
#[test]
fn amax_with_elements_is_the_edge_check_finds() {
    let device = [
        "--mass",
        "0.1",
        "--period",
        "1e-3",
        "--damping",
        "0,2",
        "--delay-samples",
        "1",
    ];
    for flags in [
        &["--velocity-filter-cutoff", "30"][..],
        // the held device alone (without --always-gripped the free device joins the set)
        &[
            "--hand-mass",
            "0.05",
            "--hand-stiffness",
            "200",
            "--always-gripped",
        ],
        &["--actuator-time-constant", "2e-4"],
    ] {
        let out = crate::common::stdout(&[&["amax"][..], &device, flags].concat());
        let (head, rows) = crate::common::csv(&out);
        assert_eq!(
            head,
            "delta,d,alpha_max,beta_at_max,damping_Ns_per_m,K_max_N_per_m,B_at_max_Ns_per_m"
        );
        assert_eq!(rows.len(), 2);
        for r in &rows {
            let (b, k, bw): (f64, f64, f64) = (
                r[4].parse().unwrap(),
                r[5].parse().unwrap(),
                r[6].parse().unwrap(),
            );
            let verdict = |k: f64, bw: f64| {
                let v = crate::common::json(
                    &[
                        &[
                            "check",
                            "--mass",
                            "0.1",
                            "--period",
                            "1e-3",
                            "--delay-samples",
                            "1",
                        ][..],
                        &["--damping", &b.to_string()],
                        &[
                            "--stiffness",
                            &k.to_string(),
                            "--wall-damping",
                            &bw.to_string(),
                        ],
                        flags,
                        &["--format", "json"],
                    ]
                    .concat(),
                );
                v["verdict"].as_str().unwrap().to_string()
            };
            assert_eq!(verdict(k * (1.0 - 1e-5), bw), "stable", "{flags:?} {r:?}");
            for f in [0.98, 1.0, 1.02] {
                assert_eq!(
                    verdict(k * (1.0 + 1e-5), bw * f),
                    "unstable",
                    "{flags:?} {r:?}"
                );
            }
        }
    }
    let e = assert_bad_input(
        &["amax", "--delta", "0", "--d", "1", "--hand-mass", "0.1"],
        true,
    );
    assert!(e.contains("physical units"), "{e}");
}

/// A velocity filter whose pole is 1e-5 from `z = 1` (cutoff 1.59 mHz at 1 kHz) on a device
/// with no physical damping: no wall with `B <= 0` is stable (at `B = 0` the filter splits off
/// and the undamped paper loop is unstable at every stiffness; a 50-digit computation,
/// `tools/amax_oracle.py`, finds no stable damping `<= 0` down to 1e-12 of the stiffness the
/// polynomial's tests proposed). `amax` refuses with exit code 2, one line that says no such
/// wall was found and what to do, not a stiffness of 2e-8 whose walls are stable only
/// within rounding.
#[test]
fn amax_refuses_walls_stable_only_within_rounding() {
    let e = assert_bad_input(
        &[
            "amax",
            "--mass",
            "0.1",
            "--period",
            "1e-3",
            "--damping",
            "0",
            "--delay-samples",
            "0",
            "--velocity-filter-cutoff",
            "1.5915574e-3",
            "--beta-max",
            "0",
        ],
        true,
    );
    assert!(
        e.contains("no stable wall of this loop was found")
            && e.contains("state-matrix eigenvalues")
            && e.contains("widen the beta limits"),
        "{e}"
    );
}

/// `boundary` with loop elements: walls just inside the drawn curve (pulled 1 % toward its
/// centre) are stable and walls just outside (pushed 1 % away) unstable, by `check --batch`
/// with the same flags; a hand stiffness puts the left edge at alpha = -K_h T^2 / m.
#[test]
fn boundary_with_elements_is_the_edge_check_finds() {
    let device = [
        "--mass",
        "0.1",
        "--period",
        "1e-3",
        "--damping",
        "0",
        "--delay-samples",
        "1",
    ];
    let hand = ["--hand-mass", "0.05", "--hand-stiffness", "200"];
    let out =
        crate::common::stdout(&[&["boundary"][..], &device, &hand, &["--tol", "1e-7"]].concat());
    let (head, rows) = crate::common::csv(&out);
    assert_eq!(
        head,
        "delta,d,alpha,beta,piece,damping_Ns_per_m,stiffness_N_per_m,wall_damping_Ns_per_m"
    );
    let kb: Vec<(f64, f64)> = rows
        .iter()
        .map(|r| (r[6].parse().unwrap(), r[7].parse().unwrap()))
        .collect();
    let left = rows
        .iter()
        .map(|r| r[2].parse::<f64>().unwrap())
        .fold(f64::INFINITY, f64::min);
    assert!((left + 200.0 * 1e-6 / 0.1).abs() < 1e-9, "{left}");
    let (ck, cb) = (
        kb.iter().map(|p| p.0).sum::<f64>() / kb.len() as f64,
        kb.iter().map(|p| p.1).sum::<f64>() / kb.len() as f64,
    );
    for (scale, want) in [(0.99, "stable"), (1.01, "unstable")] {
        let mut csv = String::from("stiffness_N_per_m,wall_damping_Ns_per_m\n");
        for &(k, b) in kb.iter().step_by(20) {
            csv += &format!("{},{}\n", ck + scale * (k - ck), cb + scale * (b - cb));
        }
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("walls.csv");
        std::fs::write(&path, csv).unwrap();
        let out = crate::common::stdout(
            &[
                &["check", "--batch", path.to_str().unwrap()][..],
                &device,
                &hand,
            ]
            .concat(),
        );
        let (head, rows) = crate::common::csv(&out);
        let col = head.split(',').position(|c| c == "verdict").unwrap();
        assert!(rows.len() > 10);
        for r in &rows {
            assert_eq!(r[col], want, "{scale} {r:?}");
        }
    }
}

/// The delta-beta plane with a velocity filter (m = 0.1 kg, T = 1 ms, 30 Hz low-pass) at
/// alpha = 0.1 (K = 10 kN/m), d = 1: the filter moves the curve, and across each boundary
/// vertex `check` of the same filtered device (physical damping b = 100 delta, wall damping
/// B = 100 beta) finds one side stable and the other not.
#[test]
fn delta_beta_plane_with_elements_is_the_edge_check_finds() {
    let plane = [
        "boundary",
        "--plane",
        "delta-beta",
        "--alpha",
        "0.1",
        "--d",
        "1",
        "--delta",
        "0:1:2",
        "--tol",
        "1e-6",
    ];
    let filter = [
        "--mass",
        "0.1",
        "--period",
        "0.001",
        "--velocity-filter-cutoff",
        "30",
    ];
    let bare = crate::common::stdout(&plane);
    let out = crate::common::stdout(&[&plane[..], &filter].concat());
    assert_ne!(bare, out);
    let (head, rows) = crate::common::csv(&out);
    assert_eq!(head, "alpha,d,delta,beta,loop,piece");
    let pts: Vec<(f64, f64)> = rows
        .iter()
        .filter(|r| r[5] == "bisection")
        .map(|r| (r[2].parse().unwrap(), r[3].parse().unwrap()))
        .collect();
    let left = pts.iter().map(|p| p.0).fold(f64::INFINITY, f64::min);
    // away from the leftmost turn (a vertical tangent) and the range's ends
    let tested: Vec<(f64, f64)> = pts
        .iter()
        .copied()
        .filter(|p| p.0 > left + 0.1 && p.0 < 0.95)
        .step_by(pts.len() / 12)
        .collect();
    assert!(tested.len() >= 6, "{}", tested.len());
    let stable = |delta: f64, beta: f64| {
        let (b, wb) = ((100.0 * delta).to_string(), (100.0 * beta).to_string());
        let o = crate::common::stabound()
            .args([
                "check",
                "--damping",
                &b,
                "--delay-samples",
                "1",
                "--stiffness",
                "10000",
            ])
            .args(["--wall-damping", &wb, "--exit-status"])
            .args(filter)
            .output()
            .unwrap();
        match o.status.code() {
            Some(0) => true,
            Some(3) => false,
            c => panic!("{c:?} at delta {delta}, beta {beta}"),
        }
    };
    for (x, y) in tested {
        assert_ne!(
            stable(x, y + 1e-3),
            stable(x, y - 1e-3),
            "vertex ({x}, {y})"
        );
    }
    // the axes stay normalized: physical damping and delays are refused here
    assert_bad_input(&[&plane[..], &filter, &["--damping", "10"]].concat(), true);
    assert_bad_input(
        &[&plane[..], &["--mass", "0.1", "--period", "0.001"]].concat(),
        true,
    );
}
