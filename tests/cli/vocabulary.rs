//! One vocabulary for physical quantities: every command's CSV columns and JSON keys name a
//! quantity in physical units by what it is, then its unit, as README's table lists them;
//! physical values computed back from normalized ones come out as they were typed; and
//! messages print numbers short.

use crate::common::{assert_bad_input, csv, json, stdout};

/// The paper's device (Section VIII) with dampings from a range.
const DEVICE: [&str; 8] = [
    "--mass",
    "0.1",
    "--period",
    "0.001",
    "--damping",
    "0:100:21",
    "--delay-samples",
    "1",
];

/// Names a physical quantity had before the vocabulary was one, or could be confused with
/// (`margin` is a fraction of `alpha_max` on the command line, not the marginal band).
const OLD: [&str; 12] = [
    "damping",
    "K_max",
    "B",
    "K_margin",
    "K_N_per_m",
    "B_Ns_per_m",
    "margin",
    "mass",
    "period",
    "stiffness",
    "wall_damping",
    "delay",
];

/// The unit suffixes of the vocabulary.
const UNITS: [&str; 5] = ["_kg", "_s", "_m", "_N_per_m", "_Ns_per_m"];

fn with_device(cmd: &[&str], extra: &[&str]) -> Vec<String> {
    [cmd, &DEVICE[..], extra]
        .concat()
        .into_iter()
        .map(String::from)
        .collect()
}

/// Every key of a JSON value, at any depth.
fn keys(v: &serde_json::Value, out: &mut Vec<String>) {
    match v {
        serde_json::Value::Object(m) => {
            for (k, x) in m {
                out.push(k.clone());
                keys(x, out);
            }
        }
        serde_json::Value::Array(a) => a.iter().for_each(|x| keys(x, out)),
        _ => {}
    }
}

/// The names each command writes, CSV header and JSON keys, for a device in physical units.
fn names() -> Vec<(String, Vec<String>)> {
    let mut got = Vec::new();
    let csv_runs: Vec<Vec<String>> = vec![
        with_device(&["amax"], &["--margin", "0.75"]),
        with_device(&["table"], &[]),
        with_device(&["boundary"], &["--tol", "1e-2"]),
        with_device(
            &["step"],
            &[
                "--margin",
                "0.75",
                "--duration",
                "0.002",
                "--points-per-period",
                "1",
            ],
        ),
        [
            "passivity",
            "--delta",
            "0.5",
            "--d",
            "1",
            "--mass",
            "0.1",
            "--period",
            "0.001",
        ]
        .map(String::from)
        .to_vec(),
    ];
    for args in csv_runs {
        let a: Vec<&str> = args.iter().map(String::as_str).collect();
        let (head, _) = csv(&stdout(&a));
        got.push((a.join(" "), head.split(',').map(String::from).collect()));
    }
    let json_runs: Vec<Vec<String>> = vec![
        with_device(&["table"], &["--format", "json"]),
        [
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
            "40",
            "--delay-samples",
            "1",
            "--format",
            "json",
        ]
        .map(String::from)
        .to_vec(),
        [
            "scene",
            concat!(env!("CARGO_MANIFEST_DIR"), "/data/scenes/phantom.toml"),
            "--format",
            "json",
        ]
        .map(String::from)
        .to_vec(),
    ];
    for args in json_runs {
        let a: Vec<&str> = args.iter().map(String::as_str).collect();
        let mut k = Vec::new();
        keys(&json(&a), &mut k);
        got.push((a.join(" "), k));
    }
    got
}

/// No command writes an old or ambiguous name, and every name with a unit is one README's
/// vocabulary table lists.
#[test]
fn physical_names_follow_readme() {
    let readme =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/README.md")).unwrap();
    let start = readme.find("**Names of columns and JSON keys.**").unwrap();
    let table = &readme[start..start + readme[start..].find("\n\n`").unwrap()];
    for (cmd, names) in names() {
        for n in &names {
            assert!(!OLD.contains(&n.as_str()), "{cmd}: {n}");
            if UNITS.iter().any(|u| n.ends_with(u)) {
                assert!(
                    table.contains(&format!("`{n}`")),
                    "{cmd}: {n} is not in README"
                );
            }
        }
    }
}

/// `check` JSON calls its band `marginal_band` and echoes the device and wall by the
/// vocabulary's names.
#[test]
fn check_json_names_the_band_and_the_device() {
    let v = json(&[
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
        "40",
        "--delay-samples",
        "1",
        "--marginal-band",
        "1e-6",
        "--format",
        "json",
    ]);
    assert_eq!(v["marginal_band"].as_f64(), Some(1e-6));
    let p = &v["physical"];
    assert_eq!(p["mass_kg"].as_f64(), Some(0.1));
    assert_eq!(p["period_s"].as_f64(), Some(0.001));
    assert_eq!(p["damping_Ns_per_m"].as_f64(), Some(10.0));
    assert_eq!(p["stiffness_N_per_m"].as_f64(), Some(2000.0));
    assert_eq!(p["wall_damping_Ns_per_m"].as_f64(), Some(40.0));
}

/// A damping range gives the dampings as typed in every physical column (55, not
/// `54.99999999999999`, after `b T / m` and back): `amax`, `table` and `boundary`.
#[test]
fn damping_ranges_come_back_as_typed() {
    let want: Vec<String> = (0..21).map(|i| (5 * i).to_string()).collect();
    for (cmd, extra) in [
        ("amax", &[][..]),
        ("table", &[][..]),
        ("boundary", &["--tol", "1e-2"][..]),
    ] {
        let a = with_device(&[cmd], extra);
        let a: Vec<&str> = a.iter().map(String::as_str).collect();
        let (head, rows) = csv(&stdout(&a));
        let col = head
            .split(',')
            .position(|c| c == "damping_Ns_per_m")
            .unwrap();
        let mut seen: Vec<String> = Vec::new();
        for r in rows {
            if seen.last() != Some(&r[col]) && !seen.contains(&r[col]) {
                seen.push(r[col].clone());
            }
        }
        seen.sort_by(|a, b| a.parse::<f64>().unwrap().total_cmp(&b.parse().unwrap()));
        assert_eq!(seen, want, "{cmd}");
    }
}

/// Messages print numbers in shortest round-trip form, in exponent form when tiny or huge:
/// the library's parameter errors, its other messages and the command line's own.
#[test]
fn messages_print_numbers_short() {
    for (args, want) in [
        (
            &[
                "check", "--alpha", "0", "--beta", "0", "--delta", "-1e-300", "--d", "1",
            ][..],
            "invalid delta = -1e-300:",
        ),
        (
            &[
                "check", "--alpha", "0", "--beta", "0", "--delta", "0", "--d", "1e300",
            ][..],
            "invalid d = 1e300:",
        ),
        (
            &[
                "step",
                "--mass",
                "0.1",
                "--period",
                "0.001",
                "--damping",
                "0",
                "--delay-samples",
                "1",
                "--stiffness",
                "1",
                "--wall-damping",
                "40",
                "--duration",
                "1e300",
            ][..],
            "a duration of 1e300 s",
        ),
        (
            &["amax", "--delta", "0", "--d", "1", "--margin", "1e300"][..],
            "--margin 1e300: must",
        ),
        (
            &["amax", "--delta", "0", "--d", "1", "--theta-tol", "5e-324"][..],
            "= 5e-324:",
        ),
    ] {
        let err = assert_bad_input(args, true);
        assert!(err.contains(want), "{args:?}: {err}");
        assert!(err.len() < 400, "{args:?}: {err}");
    }
}
