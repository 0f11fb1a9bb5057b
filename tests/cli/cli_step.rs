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

/// With no element named the output is the one the paper's loop always gave: the time and
/// position columns equal, to the bit, those of Fig. 11's golden data
/// (`data/figures/fig11.csv`: 1 N for 80 ms, 5 points per period, 75 % of alpha_max).
#[test]
fn bare_loop_matches_golden_fig11() {
    let out = stabound()
        .arg("step")
        .args(DEVICE)
        .args(["--damping", "0,10,100", "--margin", "0.75"])
        .args(["--duration", "0.08", "--points-per-period", "5"])
        .output()
        .unwrap();
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    // (time, position) of each row, as the values the text spells
    let pair = |t: &str, x: &str| -> (u64, u64) {
        let v = |c: &str| c.parse::<f64>().unwrap().to_bits();
        (v(t), v(x))
    };
    let mine: Vec<(u64, u64)> = text
        .lines()
        .skip(1)
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            pair(f[3], f[4])
        })
        .collect();
    let golden_path = concat!(env!("CARGO_MANIFEST_DIR"), "/data/figures/fig11.csv");
    let golden_text = std::fs::read_to_string(golden_path).unwrap();
    // the label is quoted and holds commas: the last two fields are time and position
    let golden: Vec<(u64, u64)> = golden_text
        .lines()
        .skip(1)
        .map(|l| {
            let f: Vec<&str> = l.rsplitn(3, ',').collect();
            pair(f[1], f[0])
        })
        .collect();
    assert_eq!(mine.len(), golden.len());
    let first_difference = mine.iter().zip(&golden).position(|(a, b)| a != b);
    assert_eq!(first_difference, None, "rows differ from the golden data");
}

fn step_with(extra: &[&str]) -> std::process::Output {
    stabound()
        .arg("step")
        .args(DEVICE)
        .args([
            "--damping",
            "10",
            "--stiffness",
            "5000",
            "--wall-damping",
            "20",
        ])
        .args(["--duration", "0.5", "--points-per-period", "2"])
        .args(extra)
        .output()
        .unwrap()
}

/// Each element kind changes the response; the summary names what was modelled, and its
/// final value is the static deflection the hand's spring to ground shares with the wall:
/// 1 N / (5000 + 1000) N/m.
#[test]
fn elements_change_the_response() {
    let bare = step_with(&[]);
    assert!(bare.status.success());
    let kinds: &[&[&str]] = &[
        &["--hand-mass", "0.05", "--hand-damping", "1"],
        // without coupling damping this wall is unstable on the motor side (`check` agrees)
        &[
            "--handle-mass",
            "0.03",
            "--transmission-stiffness",
            "5e4",
            "--transmission-damping",
            "5",
        ],
        &[
            "--handle-mass",
            "0.03",
            "--transmission-stiffness",
            "5e4",
            "--encoder",
            "handle",
        ],
        &["--actuator-time-constant", "0.0003"],
        &["--velocity-filter-cutoff", "100"],
        &["--velocity-filter-samples", "3"],
    ];
    for args in kinds {
        let out = step_with(args);
        assert!(
            out.status.success(),
            "{args:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(
            out.stdout != bare.stdout,
            "{args:?}: same output as the bare loop"
        );
        let text = String::from_utf8(out.stdout).unwrap();
        assert_eq!(text.lines().count(), 1 + 500 * 2 + 1, "{args:?}");
        // 0.5 s of a stable wall: the last position is the deflection 1 N / 5000 N/m
        let last: f64 = text
            .lines()
            .last()
            .unwrap()
            .rsplit(',')
            .next()
            .unwrap()
            .parse()
            .unwrap();
        assert!((last * 5000.0 - 1.0).abs() < 1e-6, "{args:?}: {last}");
    }
    let out = step_with(&[
        "--hand-mass",
        "0.05",
        "--hand-stiffness",
        "1000",
        "--velocity-filter-cutoff",
        "100",
        "--format",
        "summary",
    ]);
    assert!(out.status.success());
    let line = String::from_utf8(out.stdout).unwrap();
    assert!(
        line.trim_end()
            .ends_with("; elements: hand, low-pass velocity filter"),
        "{line}"
    );
    let final_value: f64 = line
        .split("final ")
        .nth(1)
        .unwrap()
        .split(' ')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    // printed to 7 significant digits
    assert!((final_value * 6000.0 - 1.0).abs() < 1e-6, "{line}");
    let bare_summary = step_with(&["--format", "summary"]);
    assert!(
        !String::from_utf8(bare_summary.stdout)
            .unwrap()
            .contains("elements")
    );
}

/// --margin with elements takes the loop's alpha_max: the wall is 0.75 of what `amax`
/// reports for the same device and elements, with its damping.
#[test]
fn margin_with_elements_uses_the_loop_alpha_max() {
    // the held device alone: step answers for it, and amax does with --always-gripped
    let elements = [
        "--hand-mass",
        "0.05",
        "--velocity-filter-cutoff",
        "100",
        "--always-gripped",
    ];
    let amax = stabound()
        .arg("amax")
        .args(DEVICE)
        .args(["--damping", "10"])
        .args(elements)
        .output()
        .unwrap();
    assert!(amax.status.success());
    let text = String::from_utf8(amax.stdout).unwrap();
    let row: Vec<f64> = text
        .lines()
        .nth(1)
        .unwrap()
        .split(',')
        .map(|c| c.parse().unwrap())
        .collect();
    let (alpha_max, beta) = (row[2], row[3]);
    let out = stabound()
        .arg("step")
        .args(DEVICE)
        .args(["--damping", "10", "--margin", "0.75", "--format", "summary"])
        .args(elements)
        .output()
        .unwrap();
    assert!(out.status.success());
    let line = String::from_utf8(out.stdout).unwrap();
    let grab = |key: &str| -> f64 {
        let i = line.find(key).unwrap() + key.len();
        line[i..].split(')').next().unwrap().parse().unwrap()
    };
    // printed with 6 decimals: half a unit in the last place
    assert!(
        (grab("(alpha = ") - 0.75 * alpha_max).abs() <= 5e-7,
        "{line}"
    );
    assert!((grab("(beta = ") - beta).abs() <= 5e-7, "{line}");
    // the bare loop's margin wall is another one: the elements moved alpha_max
    assert!((0.75 * alpha_max - 0.148987).abs() > 1e-3, "{alpha_max}");
}

/// A bad element value exits 2 with one line naming its flag.
#[test]
fn bad_element_value_names_the_flag() {
    let cases: &[(&[&str], &str)] = &[
        (&["--hand-mass", "-1"], "--hand-mass"),
        (&["--hand-stiffness", "-5"], "--hand-stiffness"),
        (
            &["--velocity-filter-cutoff", "900"],
            "--velocity-filter-cutoff",
        ),
        (
            &["--velocity-filter-samples", "0"],
            "--velocity-filter-samples",
        ),
        (
            &["--actuator-time-constant", "-1"],
            "--actuator-time-constant",
        ),
        (
            &["--handle-mass", "0.2", "--transmission-stiffness", "1e4"],
            "--handle-mass",
        ),
        (
            &["--handle-mass", "0.02", "--transmission-stiffness", "-1"],
            "--transmission-stiffness",
        ),
    ];
    for (args, flag) in cases {
        let out = step_with(args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert!(out.stdout.is_empty(), "{args:?}");
        let err = String::from_utf8(out.stderr).unwrap();
        assert_eq!(err.trim_end().lines().count(), 1, "{err}");
        assert!(err.contains(flag), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{err}");
    }
}

/// A paper's loop whose wall a relative 1e-6 below alpha_max is marginal (m = 1 kg, T = 1 s,
/// b = 100 N s/m, no delay: delta = 100, where that wall keeps a root about 2e-10 inside the
/// unit circle) says so with --margin, as `amax` does; the margin wall itself is stable and
/// its response is drawn. The paper's Section VIII loops say nothing of the kind.
#[test]
fn margin_says_when_the_stiffest_wall_is_marginal() {
    let run = |device: &[&str], damping: &str| {
        stabound()
            .arg("step")
            .args(device)
            .args([
                "--damping",
                damping,
                "--margin",
                "0.75",
                "--format",
                "summary",
            ])
            .output()
            .unwrap()
    };
    let out = run(
        &["--mass", "1", "--period", "1", "--delay-samples", "0"],
        "100",
    );
    assert!(out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("note: b = 100 N s/m: the stiffest wall to render")
            && err.contains("within the marginal band"),
        "{err}"
    );
    assert!(String::from_utf8_lossy(&out.stdout).contains(", stable;"));
    let out = run(&DEVICE, "0,10,100");
    assert!(!String::from_utf8_lossy(&out.stderr).contains("marginal band"));
}
