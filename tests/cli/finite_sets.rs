//! Finite sets of devices on the command line (`one-of:LIST`) and in scene files
//! (`{ one_of = [...] }`): the set's answers against the single devices' own rows, and walls
//! judged by the eigenvalues of each member's closed-loop state matrix (nalgebra's Schur
//! form, [`crate::robust_sets::stable`]), not by the engines' Schur-Cohn tests.

use crate::common::{assert_bad_input, csv, json, stdout};
use crate::robust_sets::{c_array, stable};
use stabound::elements::PhysicalElements;
use stabound::params::{Delay, Device};

/// The paper's example device (normalized units) with the delay given by `delay`.
const JITTER: [&str; 6] = ["--mass", "1", "--period", "1", "--damping", "0.5"];

/// `amax ARGS` as one CSV row, each cell by its column name.
fn amax_row(args: &[&str]) -> impl Fn(&str) -> String + use<> {
    let mut all = vec!["amax"];
    all.extend_from_slice(args);
    let (head, rows) = csv(&stdout(&all));
    assert_eq!(rows.len(), 1, "{all:?}: {rows:?}");
    let names: Vec<String> = head.split(',').map(str::to_string).collect();
    let row = rows.into_iter().next().unwrap();
    move |name: &str| {
        let i = names.iter().position(|c| c == name).unwrap();
        row[i].clone()
    }
}

fn num(s: String) -> f64 {
    s.parse().unwrap()
}

fn device(mass: f64, delay: f64) -> Device {
    Device::new(mass, 1.0, 0.5, Delay::Samples(delay)).unwrap()
}

/// A delay of 1, 2 or 3 samples: the robust optimum is the least of the three single-delay
/// optima (the rows of the bare LIST), bound by the member that gives it; every member was
/// examined and the output says the check is complete. The wall is stable at each of the
/// three delays by eigenvalues, and a wall 0.1 % stiffer is not at the binding one.
#[test]
fn delay_list_is_the_least_single_delay_optimum() {
    let (head, rows) = csv(&stdout(
        &[&["amax"][..], &JITTER, &["--delay-samples", "1,2,3"]].concat(),
    ));
    let col = |name: &str| head.split(',').position(|c| c == name).unwrap();
    assert_eq!(rows.len(), 3, "one row per delay: {rows:?}");
    let (least, at) = rows
        .iter()
        .map(|r| (num(r[col("alpha_max")].clone()), num(r[col("d")].clone())))
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .unwrap();
    let set = amax_row(&[&JITTER[..], &["--delay-samples", "one-of:1,2,3"]].concat());
    let alpha = num(set("alpha_max"));
    // the same search on the binding member: equal to the rounding of its refinement
    assert!((alpha - least).abs() <= 1e-9 * least, "{alpha} vs {least}");
    assert_eq!(num(set("alpha_verified")), alpha, "a finite set is exact");
    assert_eq!(set("binding"), format!("delay = {at} samples"));
    assert_eq!(set("members_examined"), "3");
    assert_eq!(set("set"), "delay 1 or 2 or 3 samples");
    assert!(
        set("verification").starts_with("checked for every member"),
        "{}",
        set("verification")
    );
    let (k, b) = (num(set("K_verified")), num(set("B")));
    let none = PhysicalElements::default();
    for d in [1.0, 2.0, 3.0] {
        assert!(
            stable(&device(1.0, d), &none, k * (1.0 - 1e-9), b),
            "d = {d}"
        );
    }
    assert!(!stable(&device(1.0, at), &none, k * 1.001, b));
}

/// A list beside an interval (mass 0.9..1.1 kg, delay 1 or 2 samples): one row for the
/// whole set, naming both; the verified wall is stable for 21 masses at each listed delay,
/// and the optimum is no stiffer than either delay's own interval optimum.
#[test]
fn list_and_interval_together() {
    let mass = ["--mass", "0.9..1.1", "--period", "1", "--damping", "0.5"];
    let set = amax_row(&[&mass[..], &["--delay-samples", "one-of:1,2"]].concat());
    assert_eq!(set("set"), "mass 0.9..1.1 kg; delay 1 or 2 samples");
    let (k, b) = (num(set("K_verified")), num(set("B")));
    let none = PhysicalElements::default();
    for i in 0..=20 {
        let m = 0.9 + 0.2 * f64::from(i) / 20.0;
        for d in [1.0, 2.0] {
            let dev = Device::new(m, 1.0, 0.5, Delay::Samples(d)).unwrap();
            assert!(stable(&dev, &none, k, b), "m = {m}, d = {d}");
        }
    }
    for d in ["1", "2"] {
        let one = amax_row(&[&mass[..], &["--delay-samples", d]].concat());
        assert!(
            num(set("K_max")) <= num(one("K_max")) * (1.0 + 1e-9),
            "d = {d}"
        );
    }
}

/// `check` over a list: stable for every member when the wall is stable at each delay by
/// eigenvalues; otherwise the member it fails on is named (the 3-sample one here, where
/// the wall is stable at 1 and 2 samples).
#[test]
fn check_answers_for_every_listed_member() {
    let none = PhysicalElements::default();
    let run = |k: &str, b: &str| {
        json(
            &[
                &["check"][..],
                &JITTER,
                &["--delay-samples", "one-of:1,2,3", "--stiffness", k],
                &["--wall-damping", b, "--format", "json"],
            ]
            .concat(),
        )
    };
    let ok = run("0.2", "0.26");
    for d in [1.0, 2.0, 3.0] {
        assert!(stable(&device(1.0, d), &none, 0.2, 0.26), "d = {d}");
    }
    assert_eq!(ok["for_every_member"], true, "{ok}");
    assert!(
        ok["verification"]
            .as_str()
            .unwrap()
            .starts_with("checked for every member")
    );
    let bad = run("0.25", "0.3");
    assert!(stable(&device(1.0, 1.0), &none, 0.25, 0.3));
    assert!(stable(&device(1.0, 2.0), &none, 0.25, 0.3));
    assert!(!stable(&device(1.0, 3.0), &none, 0.25, 0.3));
    assert_eq!(bad["for_every_member"], false, "{bad}");
    assert_eq!(bad["failing_member"], "delay = 3 samples");
}

/// A list of hand masses: the members are each listed mass held and the device let go
/// (three, the let-go device once), each stable at the verified wall by eigenvalues;
/// `--always-gripped` leaves the free device out.
#[test]
fn hand_mass_list_with_the_hand_let_go() {
    let flags = [
        "--mass",
        "0.1",
        "--period",
        "0.001",
        "--damping",
        "0",
        "--delay-samples",
        "1",
        "--hand-mass",
        "one-of:0.5,0.2",
        "--hand-damping",
        "2",
        "--hand-stiffness",
        "300",
        "--velocity-filter-cutoff",
        "50",
    ];
    let set = amax_row(&flags);
    assert_eq!(set("members_examined"), "3");
    assert!(set("set").starts_with("hand mass 0.2 or 0.5 kg; hand on the handle or let go"));
    let (k, b) = (num(set("K_verified")), num(set("B")));
    let dev = Device::new(0.1, 1e-3, 0.0, Delay::Samples(1.0)).unwrap();
    let mut named = PhysicalElements::default();
    named.velocity_filter_cutoff = Some(50.0);
    assert!(stable(&dev, &named, k * (1.0 - 1e-9), b), "let go");
    named.hand_damping = Some(2.0);
    named.hand_stiffness = Some(300.0);
    for m in [0.2, 0.5] {
        named.hand_mass = Some(m);
        assert!(stable(&dev, &named, k * (1.0 - 1e-9), b), "hand {m}");
    }
    let gripped = amax_row(&[&flags[..], &["--always-gripped"]].concat());
    assert_eq!(gripped("members_examined"), "2");
}

/// Commands that answer for one device refuse a list in one line, as they refuse an
/// interval; malformed lists are refused by name.
#[test]
fn lists_are_refused_where_not_meant_and_when_malformed() {
    for args in [
        &[
            "step",
            "--mass",
            "1",
            "--period",
            "1",
            "--damping",
            "0.5",
            "--delay-samples",
            "one-of:1,2",
            "--stiffness",
            "0.1",
            "--wall-damping",
            "0.1",
        ][..],
        &[
            "passivity",
            "--mass",
            "one-of:0.1,0.2",
            "--period",
            "0.001",
            "--delta",
            "1",
            "--d",
            "1",
        ][..],
    ] {
        let err = assert_bad_input(args, true);
        assert!(
            err.contains("is a finite set (one-of:LIST)") && err.contains("amax, table, boundary"),
            "{args:?}: {err}"
        );
    }
    for bad in ["one-of:", "one-of:1,x", "one-of:3:1:2"] {
        let args = [&["amax"][..], &JITTER, &["--delay-samples", bad]].concat();
        let err = assert_bad_input(&args, false);
        assert!(err.contains("no set of values"), "{bad}: {err}");
    }
    // a hand mass below zero is refused where it is written
    let err = assert_bad_input(
        &[
            &["amax"][..],
            &JITTER,
            &["--delay-samples", "1", "--hand-mass", "one-of:-1,2"],
        ]
        .concat(),
        false,
    );
    assert!(err.contains("--hand-mass"), "{err}");
}

/// The scene form `{ one_of = [1, 2, 3] }` gives the command line's answers: the robust
/// optimum of `amax` with `one-of:1,2,3` and each wall's verdict of `check`, bit for bit;
/// the text report is the golden file beside the scene.
#[test]
fn scene_list_answers_equal_the_command_lines() {
    let scene = "data/scenes/delays.toml";
    let text = String::from_utf8(stdout(&["scene", scene, "--format", "json"])).unwrap();
    let report: serde_json::Value = serde_json::from_str(&text).unwrap();
    let set = &report["devices"][0]["set"];
    let o = &set["optimum"];
    let amax = amax_row(&[&JITTER[..], &["--delay-samples", "one-of:1,2,3"]].concat());
    // the numbers as written, read by Rust's correctly rounded parser (serde_json's own
    // reading of a float may differ in the last bit)
    let written = |key: &str| -> f64 {
        let at = text.find(&format!("\"{key}\": ")).unwrap() + key.len() + 4;
        let end = text[at..].find([',', '\n']).unwrap();
        text[at..at + end].parse().unwrap()
    };
    for (key, col) in [
        ("alpha_max", "alpha_max"),
        ("beta_at_max", "beta_at_max"),
        ("alpha_verified", "alpha_verified"),
        ("K_max_N_per_m", "K_max"),
        ("B_at_max_Ns_per_m", "B"),
        ("K_verified_N_per_m", "K_verified"),
    ] {
        assert_eq!(written(key), num(amax(col)), "{key}");
    }
    assert_eq!(o["verification"].as_str().unwrap(), amax("verification"));
    assert_eq!(o["binding"][0].as_str().unwrap(), amax("binding"));
    for wall in set["walls"].as_array().unwrap() {
        let (k, b) = (
            wall["stiffness_N_per_m"].to_string(),
            wall["wall_damping_Ns_per_m"].to_string(),
        );
        let check = json(
            &[
                &["check"][..],
                &JITTER,
                &["--delay-samples", "one-of:1,2,3", "--stiffness", &k],
                &["--wall-damping", &b, "--format", "json"],
            ]
            .concat(),
        );
        assert_eq!(wall["verdict"], check["verdict"], "{wall}");
        assert_eq!(
            wall["for_every_member"], check["for_every_member"],
            "{wall}"
        );
    }
    let text = String::from_utf8(stdout(&["scene", scene])).unwrap();
    let golden = std::fs::read_to_string("data/scenes/delays.txt").unwrap();
    assert_eq!(text, golden);
}

/// `boundary` over a list draws the robust region exactly (no note that the members are a
/// sample), and it lies within every member's own region: at each row's damping the
/// region's stiffness is a stable wall of both delays just inside it.
#[test]
fn boundary_of_a_list_is_exact() {
    let args = [
        &["boundary"][..],
        &JITTER,
        &["--delay-samples", "one-of:1,3", "--tol", "1e-4"],
    ]
    .concat();
    let out = crate::common::stabound().args(&args).output().unwrap();
    assert!(out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!err.contains("sampled"), "{err}");
    let (head, rows) = csv(&out.stdout);
    let col = |name: &str| head.split(',').position(|c| c == name).unwrap();
    assert!(rows.len() > 10, "{rows:?}");
    let none = PhysicalElements::default();
    let mut inside = 0;
    for r in &rows {
        let (alpha, beta) = (num(r[col("alpha")].clone()), num(r[col("beta")].clone()));
        // the upper edge of the region (positive damping): a wall 1 % softer is inside
        if beta > 0.05 && alpha > 0.01 {
            for d in [1.0, 3.0] {
                assert!(
                    stable(&device(1.0, d), &none, 0.99 * alpha, beta),
                    "{r:?} d = {d}"
                );
            }
            inside += 1;
        }
    }
    assert!(inside > 3, "{rows:?}");
}

/// A conservative table over a list of hand masses: the header names the set and the hand's
/// assumption, and every node and every wall the documented interpolation yields between
/// nodes (16 steps per interval) is stable for each listed hand and for the hand let go.
#[test]
fn table_over_a_hand_mass_list_holds_for_every_member() {
    let header = String::from_utf8(stdout(&[
        "table",
        "--mass",
        "0.1",
        "--period",
        "0.001",
        "--damping",
        "0:100:11",
        "--delay-samples",
        "1",
        "--velocity-filter-cutoff",
        "50",
        "--hand-mass",
        "one-of:0.2,0.5",
        "--hand-damping",
        "2",
        "--hand-stiffness",
        "300",
        "--conservative",
        "--format",
        "c",
    ]))
    .unwrap();
    assert!(header.contains("hand mass 0.2 or 0.5 kg;"), "{header}");
    assert!(header.contains("the free device is a member"), "{header}");
    let (xs, ks, bs) = (
        c_array(&header, "stabound_damping"),
        c_array(&header, "stabound_k_max"),
        c_array(&header, "stabound_b_at_max"),
    );
    assert_eq!(xs.len(), 11);
    let mut free = PhysicalElements::default();
    free.velocity_filter_cutoff = Some(50.0);
    let mut members = vec![free];
    for m in [0.2, 0.5] {
        let mut held = free;
        held.hand_mass = Some(m);
        held.hand_damping = Some(2.0);
        held.hand_stiffness = Some(300.0);
        members.push(held);
    }
    let lerp = |v: &[f64], j: usize, s: f64| v[j] + s * (v[j + 1] - v[j]);
    for j in 0..xs.len() - 1 {
        for step in 0..=16 {
            let s = f64::from(step) / 16.0;
            let (b, k, bw) = (lerp(&xs, j, s), lerp(&ks, j, s), lerp(&bs, j, s));
            let device = Device::new(0.1, 0.001, b, Delay::Samples(1.0)).unwrap();
            for e in &members {
                assert!(
                    stable(&device, e, k, bw),
                    "{:?}: b = {b}, K = {k}, B = {bw}",
                    e.hand_mass
                );
            }
        }
    }
}
