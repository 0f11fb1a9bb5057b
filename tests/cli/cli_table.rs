//! End-to-end tests of `stabound table`: the C header compiles and matches the CSV; the Rust
//! export compiles; output is identical for 1 and 2 threads.

use crate::common::{assert_bad_input, csv_numbers, stdout_with};

fn run(args: &[&str], threads: &str) -> String {
    String::from_utf8(stdout_with(&[&["table"][..], args].concat(), Some(threads))).unwrap()
}

const GRID: [&str; 4] = ["--delta", "0:20:9", "--d", "0,0.5,1,2"];

/// Numbers of one `static const double NAME[...] = { ... };` block of the header.
fn c_array(h: &str, name: &str) -> Vec<f64> {
    let start = h.find(&format!("double {name}[")).unwrap();
    let body = &h[start..];
    let open = body.find("= {").unwrap() + 3;
    let close = body.find("};").unwrap();
    body[open..close]
        .split(|c: char| c == ',' || c == '{' || c == '}' || c.is_whitespace())
        .filter(|t| !t.is_empty())
        .map(|t| t.parse().unwrap())
        .collect()
}

#[test]
fn c_header_compiles_and_matches_csv() {
    let h = run(
        &[&GRID[..], &["--format", "c", "--conservative"]].concat(),
        "2",
    );
    let csv = run(
        &[&GRID[..], &["--format", "csv", "--conservative"]].concat(),
        "2",
    );
    let rows = csv_numbers(csv.as_bytes());
    let alpha = c_array(&h, "stabound_alpha_max");
    let beta = c_array(&h, "stabound_beta_at_max");
    assert_eq!(rows.len(), 36);
    for (i, r) in rows.iter().enumerate() {
        // same shortest round-trip literals on both sides: exactly equal
        assert_eq!(r[2].to_bits(), alpha[i].to_bits(), "row {i}");
        assert_eq!(r[3].to_bits(), beta[i].to_bits(), "row {i}");
    }
    assert!(h.contains("CONSERVATIVE"));
    let Ok(cc) = which_cc() else {
        eprintln!("SKIPPED compile check: no C compiler (cc) found on PATH");
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("amax_table.h"), &h).unwrap();
    std::fs::write(
        dir.path().join("main.c"),
        "#include \"amax_table.h\"\nint main(void) { return stabound_alpha_max[0][0] >= 0.0 && stabound_delta[0] >= 0.0 && stabound_d[0] >= 0.0 && stabound_beta_at_max[0][0] > -1e9 ? 0 : 1; }\n",
    )
    .unwrap();
    let out = std::process::Command::new(cc)
        .args(["-std=c99", "-Wall", "-Werror", "-o"])
        .arg(dir.path().join("main"))
        .arg(dir.path().join("main.c"))
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        std::process::Command::new(dir.path().join("main"))
            .status()
            .unwrap()
            .success()
    );
}

fn which_cc() -> Result<&'static str, ()> {
    for cc in ["cc", "gcc", "clang"] {
        if std::process::Command::new(cc)
            .arg("--version")
            .output()
            .is_ok()
        {
            return Ok(cc);
        }
    }
    Err(())
}

#[test]
fn rust_export_compiles() {
    let cases: [&[&str]; 4] = [
        &["--delta", "0:4:3", "--d", "0,1"],
        &[
            "--delta",
            "0:4:3",
            "--d",
            "1,2",
            "--conservative",
            "--precision",
            "float",
        ],
        &["--delta", "0.5", "--d", "0.5", "--conservative"],
        &[
            "--mass",
            "0.1",
            "--period",
            "0.001",
            "--damping",
            "0:10:3",
            "--delay-samples",
            "1",
            "--conservative",
            "--precision",
            "float",
        ],
    ];
    for args in cases {
        let src = run(&[args, &["--format", "rust"][..]].concat(), "1");
        compile_rust(&src);
    }
}

fn compile_rust(src: &str) {
    let dir = tempfile::tempdir().unwrap();
    let f = dir.path().join("table.rs");
    std::fs::write(&f, src).unwrap();
    let out = std::process::Command::new(std::env::var("RUSTC").unwrap_or_else(|_| "rustc".into()))
        .args([
            "--crate-type",
            "lib",
            "--edition",
            "2021",
            "-D",
            "warnings",
            "--out-dir",
        ])
        .arg(dir.path())
        .arg(&f)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn identical_for_any_thread_count() {
    let a = run(
        &[&GRID[..], &["--format", "json", "--conservative"]].concat(),
        "1",
    );
    let b = run(
        &[&GRID[..], &["--format", "json", "--conservative"]].concat(),
        "2",
    );
    assert_eq!(a, b);
}

#[test]
fn unsorted_axis_is_bad_input() {
    assert_bad_input(&["table", "--delta", "1,0", "--d", "0"], true);
}

/// Rows of whole delays are built alone: a shard computing only its own rows gives the
/// same conservative values, bit for bit, as the whole table.
#[test]
fn whole_delay_shards_join_to_the_whole_table() {
    let args = ["--delta", "0:2:5", "--d", "1,2,3", "--conservative"];
    let whole = run(&args, "2");
    let mut joined = String::new();
    for k in 1..=3 {
        let shard = format!("{k}/3");
        let part = run(&[&args[..], &["--shard", &shard]].concat(), "2");
        let body = if k == 1 {
            part.as_str()
        } else {
            part.split_once('\n').map_or("", |(_, rest)| rest)
        };
        joined.push_str(body);
    }
    assert_eq!(joined, whole);
}

#[test]
fn float_csv_is_bad_input() {
    let msg = assert_bad_input(
        &[
            "table",
            "--delta",
            "0,1",
            "--d",
            "1",
            "--precision",
            "float",
        ],
        true,
    );
    assert!(msg.contains("--format"), "{msg}");
}

/// The device and grid of the loop-element tables below.
const DEVICE: [&str; 8] = [
    "--mass",
    "0.1",
    "--period",
    "0.001",
    "--damping",
    "0:4:5",
    "--delay-samples",
    "1,2",
];

/// With loop elements every node is that loop's `alpha_max`, computed here through the
/// library on each node's own device in physical units (damping and delay as given), and
/// the elements change the nodes: a 30 Hz velocity filter lowers every one (its lag), a
/// hand changes every one. Without elements the rows are the bare loop's.
#[test]
fn loop_elements_give_each_nodes_loop_alpha_max() {
    use stabound::elements::{Loop, PhysicalElements};
    use stabound::{AmaxOptions, Delay, Device, alpha_max};

    let bare = csv_numbers(run(&DEVICE, "2").as_bytes());
    let mut filter = PhysicalElements::default();
    filter.velocity_filter_cutoff = Some(30.0);
    let mut hand = PhysicalElements::default();
    hand.hand_mass = Some(0.05);
    hand.hand_damping = Some(1.0);
    hand.hand_stiffness = Some(200.0);
    let cases: [(&[&str], PhysicalElements); 2] = [
        (&["--velocity-filter-cutoff", "30"], filter),
        (
            &[
                "--hand-mass",
                "0.05",
                "--hand-damping",
                "1",
                "--hand-stiffness",
                "200",
                // the held device alone (the free device would join the set)
                "--always-gripped",
            ],
            hand,
        ),
    ];
    for (flags, named) in cases {
        let rows = csv_numbers(run(&[&DEVICE[..], flags].concat(), "2").as_bytes());
        assert_eq!(rows.len(), 10);
        for (r, b) in rows.iter().zip(&bare) {
            // columns: d, delta, alpha_max, beta_at_max, damping_Ns_per_m, K_max_N_per_m, B_at_max_Ns_per_m
            let (d, damping, alpha) = (r[0], r[4], r[2]);
            let device = Device::new(0.1, 0.001, damping, Delay::Samples(d)).unwrap();
            let lp = Loop::new(device.plant().unwrap())
                .with_physical(&device, &named)
                .unwrap();
            let want = alpha_max(lp, &AmaxOptions::default()).unwrap();
            // the same loop (its elements depend on mass and period alone), so the same
            // value to the last bits of the plant's normalization
            assert!(
                (alpha - want.alpha_max).abs() <= 1e-12 * want.alpha_max,
                "{flags:?} {r:?}: {}",
                want.alpha_max
            );
            assert!((r[3] - want.beta_at_max).abs() <= 1e-9, "{flags:?} {r:?}");
            // elements change the loop by far more than the boundary's 1e-9
            assert!(
                (alpha - b[2]).abs() > 1e-3 * b[2],
                "{flags:?}: {alpha} vs bare {}",
                b[2]
            );
            if flags[0] == "--velocity-filter-cutoff" {
                assert!(alpha < b[2], "{r:?} {b:?}");
            }
        }
    }
}

/// A conservative table with elements never exceeds the loop's exact node values, keeps
/// the same rows when sharded, and says in its header (and its JSON and Rust forms) which
/// elements it modelled.
#[test]
fn conservative_loop_table_header_names_the_elements() {
    let flags = [
        "--velocity-filter-cutoff",
        "30",
        "--actuator-time-constant",
        "2e-4",
        "--conservative",
    ];
    let exact = csv_numbers(run(&[&DEVICE[..], &flags[..4]].concat(), "2").as_bytes());
    let low = csv_numbers(run(&[&DEVICE[..], &flags].concat(), "2").as_bytes());
    for (l, e) in low.iter().zip(&exact) {
        assert!(l[2] <= e[2] && l[2] > 0.9 * e[2], "{l:?} {e:?}");
    }
    let parts: String = (1..=2)
        .map(|k| {
            let s = format!("{k}/2");
            let out = run(&[&DEVICE[..], &flags, &["--shard", &s]].concat(), "1");
            let body: String = out.lines().skip(1).map(|l| format!("{l}\n")).collect();
            body
        })
        .collect();
    let whole = run(&[&DEVICE[..], &flags].concat(), "1");
    assert_eq!(
        whole.lines().skip(1).collect::<Vec<_>>(),
        parts.lines().collect::<Vec<_>>()
    );
    let h = run(&[&DEVICE[..], &flags, &["--format", "c"]].concat(), "2");
    assert!(h.contains("Loop elements modelled"), "{h}");
    assert!(
        h.contains(" *   actuator lag:\n *     tau = tau_a / T = 0.2 (0.0002 s).\n"),
        "{h}"
    );
    assert!(
        h.contains("velocity filter on the wall's damping term:\n *     a = exp(-2 pi f_c T) = ")
            && h.contains(" (30 Hz)."),
        "{h}"
    );
    // the C header's K values are the CSV's conservative ones, rounded down
    let k = c_array(&h, "stabound_k_max");
    for (kc, r) in k.iter().zip(&low) {
        assert!(*kc <= r[5] && *kc >= r[5] * (1.0 - 1e-15), "{kc} {r:?}");
    }
    let bare = run(
        &[&DEVICE[..], &["--conservative", "--format", "c"]].concat(),
        "2",
    );
    assert!(!bare.contains("Loop elements"));
    // the JSON object and the Rust module carry the same lines
    let j: serde_json::Value = serde_json::from_str(&run(
        &[&DEVICE[..], &flags, &["--format", "json"]].concat(),
        "2",
    ))
    .unwrap();
    let lines: Vec<&str> = j["elements"]
        .as_array()
        .unwrap()
        .iter()
        .map(|l| l.as_str().unwrap())
        .collect();
    for l in &lines {
        assert!(h.contains(&format!(" * {l}\n")), "{l}");
    }
    assert!(
        lines.iter().any(|l| l.contains("actuator lag")),
        "{lines:?}"
    );
    let r = run(&[&DEVICE[..], &flags, &["--format", "rust"]].concat(), "2");
    assert!(r.contains(&format!("//! {}\n", lines[0])), "{r}");
}

/// Bad element values exit 2 naming the flag; elements need the device in physical units.
#[test]
fn bad_element_values_name_the_flag() {
    let with = |extra: &[&'static str]| [&["table"][..], &DEVICE, extra].concat();
    for (flags, name) in [
        (&["--hand-mass", "-1"][..], "--hand-mass"),
        (&["--hand-stiffness", "-5"], "--hand-stiffness"),
        (
            &["--velocity-filter-cutoff", "600"],
            "--velocity-filter-cutoff",
        ),
        (
            &["--velocity-filter-samples", "0"],
            "--velocity-filter-samples",
        ),
        (
            &["--actuator-time-constant", "0"],
            "--actuator-time-constant",
        ),
        (
            &["--handle-mass", "0.2", "--transmission-stiffness", "1e4"],
            "--handle-mass",
        ),
        (
            &["--handle-mass", "0.05", "--transmission-stiffness", "-3"],
            "--transmission-stiffness",
        ),
    ] {
        let e = assert_bad_input(&with(flags), true);
        assert!(e.contains(name), "{flags:?}: {e}");
    }
    let e = assert_bad_input(
        &["table", "--delta", "0,1", "--d", "1", "--hand-mass", "0.1"],
        true,
    );
    assert!(e.contains("physical units"), "{e}");
}
