//! Recommended walls: the margin wall `amax` and `step` give is stable by the closed loop's
//! state-matrix eigenvalues (`check --method state-space`, independent of the search), the
//! notes say where the optimum needs negative damping or the stable set at its damping is not
//! one range, and `--nonnegative-wall-damping` / the scene key require `B >= 0`.

use crate::common::{csv_numbers, stabound, stdout};

/// The device behind an 8-sample moving average whose optimum is the tip of a thin wedge:
/// 75 % of `K_max` at its damping is unstable.
const WEDGE: [&str; 10] = [
    "--mass",
    "0.1",
    "--period",
    "0.001",
    "--damping",
    "50",
    "--delay-samples",
    "0.999",
    "--velocity-filter-samples",
    "8",
];

/// The verdict and spectral radius of `check --method state-space` at a physical wall.
fn state_space(device: &[&str], k: f64, b: f64) -> (String, f64) {
    let (k, b) = (k.to_string(), b.to_string());
    let args = [
        &["check"][..],
        device,
        &[
            "--stiffness",
            &k,
            "--wall-damping",
            &b,
            "--method",
            "state-space",
            "--radius",
        ],
    ]
    .concat();
    let out = String::from_utf8(stdout(&args)).unwrap();
    let verdict = out.split_whitespace().next().unwrap().to_string();
    let radius = out
        .lines()
        .find_map(|l| l.strip_prefix("spectral radius "))
        .and_then(|l| l.split(',').next())
        .unwrap()
        .parse()
        .unwrap();
    (verdict, radius)
}

/// The 75 % margin wall `(k_margin, b_margin)` of `device`, and every stiffness from it up
/// to its top at its damping, is stable by the state matrix.
fn margin_range_is_stable(device: &[&str], k_margin: f64, b_margin: f64) {
    let top = k_margin / 0.75;
    for s in [0.0, 0.25, 0.5, 0.75, 0.999] {
        let k = k_margin + s * (top - k_margin);
        let (verdict, radius) = state_space(device, k, b_margin);
        assert!(
            verdict == "stable" && radius < 1.0,
            "K = {k}: {verdict} {radius}"
        );
    }
}

#[test]
fn margin_wall_behind_a_wedge_is_stable_and_said() {
    let args = [&["amax"][..], &WEDGE, &["--margin", "0.75"]].concat();
    let out = stabound().args(&args).output().unwrap();
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(
        text.starts_with(
            "delta,d,alpha_max,beta_at_max,alpha_margin,beta_margin,damping_Ns_per_m,K_max_N_per_m,B_at_max_Ns_per_m,K_margin_N_per_m,B_margin_Ns_per_m\n"
        ),
        "{text}"
    );
    let row = &csv_numbers(text.as_bytes())[0];
    let (k_max, b_max, k_margin, b_margin) = (row[7], row[8], row[9], row[10]);
    // the paper's rule at the optimum's damping gives an unstable wall
    assert_eq!(state_space(&WEDGE, 0.75 * k_max, b_max).0, "unstable");
    // the recommended wall, and every stiffness from it up to its top, is stable
    margin_range_is_stable(&WEDGE, k_margin, b_margin);
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(err.contains("needs negative virtual damping"), "{err}");
    assert!(err.contains("are not one range from 0"), "{err}");
    assert!(err.contains("the margin wall is 0.75 of K = "), "{err}");
}

/// The device behind a 0.16 mHz low-pass filter sampled at 1 kHz (a pole 1e-6 from
/// `z = 1`): its stable region is a sliver along a tilted line, a million times longer in
/// damping than in stiffness.
const SLIVER: [&str; 10] = [
    "--mass",
    "0.1",
    "--period",
    "0.001",
    "--damping",
    "10",
    "--delay-samples",
    "1",
    "--velocity-filter-cutoff",
    "0.00016",
];

#[test]
fn margin_wall_on_a_sliver_is_stable() {
    let args = [&["amax"][..], &SLIVER, &["--margin", "0.75"]].concat();
    let out = stabound().args(&args).output().unwrap();
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(out.status.success(), "{err}");
    let row = &csv_numbers(&out.stdout)[0];
    let (k_max, k_margin, b_margin) = (row[7], row[9], row[10]);
    // only the sliver's wide end, far below its tip, holds a range of 25 % of a stiffness
    let top = k_margin / 0.75;
    assert!(top > 0.0 && top < 1e-3 * k_max, "{top} {k_max}");
    margin_range_is_stable(&SLIVER, k_margin, b_margin);
    assert!(err.contains("the margin wall is 0.75 of K = "), "{err}");
}

#[test]
fn step_margin_behind_a_wedge_is_stable() {
    let args = [
        &["step"][..],
        &WEDGE,
        &[
            "--margin",
            "0.75",
            "--format",
            "summary",
            "--duration",
            "0.01",
        ],
    ]
    .concat();
    let out = stabound().args(&args).output().unwrap();
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("), stable;"), "{text}");
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(!err.contains("warning"), "{err}");
    assert!(err.contains("the stiffest whose every stiffness"), "{err}");
}

/// The paper's loop at `d = 0` reaches its optimum with negative damping above
/// `delta = 3.65`: the note gives the `beta >= 0` optimum, which is what
/// `--nonnegative-wall-damping` (and `--beta-min 0`) computes; the data are unchanged.
#[test]
fn negative_damping_is_said_and_can_be_refused() {
    let out = stabound()
        .args(["amax", "--delta", "1,10", "--d", "0"])
        .output()
        .unwrap();
    assert!(out.status.success());
    let rows = csv_numbers(&out.stdout);
    assert!(rows[0][3] > 0.0 && rows[1][3] < 0.0);
    let err = String::from_utf8(out.stderr).unwrap();
    assert_eq!(err.lines().count(), 1, "{err}");
    let nonneg = stdout(&[
        "amax",
        "--delta",
        "10",
        "--d",
        "0",
        "--nonnegative-wall-damping",
    ]);
    assert_eq!(
        nonneg,
        stdout(&["amax", "--delta", "10", "--d", "0", "--beta-min", "0"])
    );
    let n = &csv_numbers(&nonneg)[0];
    assert!(n[3] >= 0.0 && n[2] < rows[1][2]);
    assert!(
        err.starts_with("note: delta = 10, d = 0: the stiffest wall")
            && err.contains(&format!("alpha = {}, beta = {}", n[2], n[3])),
        "{err}"
    );
    // the bare loop with beta >= 0 at its optimum says nothing
    let quiet = stabound()
        .args(["amax", "--delta", "0,1", "--d", "1", "--margin", "0.75"])
        .output()
        .unwrap();
    assert!(quiet.stderr.is_empty());
}

#[test]
fn scene_says_negative_damping_and_requires_nonnegative() {
    let dir = tempfile::tempdir().unwrap();
    let device = "mass_kg = 0.1\nperiod_s = 0.001\ndamping_Ns_per_m = 100.0\ndelay_samples = 1\n\
                  velocity_filter_cutoff_Hz = 3.18\n";
    let wall = "[[device.wall]]\nstiffness_N_per_m = 1000.0\ndamping_Ns_per_m = 10\n";
    let text = format!(
        "[[device]]\n{device}{wall}\n[[device]]\n{device}nonnegative_wall_damping = true\n{wall}"
    );
    let path = dir.path().join("s.toml");
    std::fs::write(&path, text).unwrap();
    let report = String::from_utf8(stdout(&["scene", path.to_str().unwrap()])).unwrap();
    let lines: Vec<&str> = report.lines().collect();
    let free = lines
        .iter()
        .position(|l| {
            l.starts_with("  K_max needs negative virtual damping; with B >= 0 the largest is ")
        })
        .unwrap_or_else(|| panic!("{report}"));
    // the second device's K_max is the first's B >= 0 optimum
    let nonneg = lines[free]
        .split("the largest is ")
        .nth(1)
        .and_then(|s| s.split(" at B").next())
        .unwrap();
    let required = lines
        .iter()
        .position(|l| l.starts_with("  nonnegative wall damping required"))
        .unwrap_or_else(|| panic!("{report}"));
    assert!(required > free, "{report}");
    assert!(
        lines[required - 1].starts_with(&format!("  K_max = {nonneg} at B* = 0 N s/m")),
        "{report}"
    );
    // a misspelt key is refused
    let bad = dir.path().join("bad.toml");
    std::fs::write(
        &bad,
        format!("[[device]]\n{device}nonnegative_wall_damping = 1\n{wall}"),
    )
    .unwrap();
    let out = stabound()
        .args(["scene", bad.to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
}
