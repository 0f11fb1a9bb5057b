//! The element list seen from the command line: every parameter a flag of the commands that
//! model elements and a key of a scene, with the same value giving the same loop, and bad
//! values refused (exit 2) naming the flag.

use stabound::elements::list::PARAMS;

use crate::common::{assert_bad_input, json, stabound, stdout};

/// Every parameter of the list is a flag of `check`, `table`, `amax` and `step`.
#[test]
fn every_parameter_is_a_flag() {
    for cmd in ["check", "table", "amax", "step"] {
        let help = String::from_utf8(stdout(&[cmd, "--help"])).unwrap();
        for p in PARAMS {
            assert!(
                help.contains(&format!("--{} <", p.flag)),
                "{cmd}: --{}",
                p.flag
            );
            assert!(
                help.contains(p.help.split(':').next().unwrap()),
                "{cmd}: {}",
                p.help
            );
        }
    }
}

const DEVICE: [&str; 14] = [
    "--mass",
    "0.1",
    "--period",
    "0.001",
    "--damping",
    "20",
    "--delay-samples",
    "1",
    "--stiffness",
    "3000",
    "--wall-damping",
    "10",
    "--format",
    "json",
];

/// The same loop named by flags and by scene keys: each case's flags and keys, the check's
/// spectral radius and the scene wall's agree bit for bit (the same library computation).
#[test]
fn flags_and_scene_keys_give_the_same_loop() {
    let cases: [(&[&str], &str); 4] = [
        (
            &[
                "--handle-mass",
                "0.03",
                "--transmission-stiffness",
                "4e4",
                "--motor-damping",
                "15",
            ],
            "handle_mass_kg = 0.03\ntransmission_stiffness_N_per_m = 4e4\nmotor_damping_Ns_per_m = 15",
        ),
        (
            &[
                "--handle-mass",
                "0.03",
                "--transmission-stiffness",
                "4e4",
                "--handle-damping",
                "5",
                "--encoder",
                "handle",
            ],
            "handle_mass_kg = 0.03\ntransmission_stiffness_N_per_m = 4e4\nhandle_damping_Ns_per_m = 5\nencoder = \"handle\"",
        ),
        (
            &[
                "--velocity-filter-cutoff",
                "40",
                "--velocity-filter-order",
                "2",
            ],
            "velocity_filter_cutoff_Hz = 40\nvelocity_filter_order = 2",
        ),
        (
            &["--hand-mass", "0.05", "--velocity-filter-samples", "3"],
            "hand_mass_kg = 0.05\nvelocity_filter_samples = 3",
        ),
    ];
    let dir = tempfile::tempdir().unwrap();
    for (flags, keys) in cases {
        let check = json(&[&["check", "--radius"][..], &DEVICE, flags].concat());
        let path = dir.path().join("s.toml");
        std::fs::write(
            &path,
            format!(
                "[[device]]\nmass_kg = 0.1\nperiod_s = 0.001\ndamping_Ns_per_m = 20\ndelay_samples = 1\n{keys}\n[[device.wall]]\nstiffness_N_per_m = 3000\ndamping_Ns_per_m = 10\n"
            ),
        )
        .unwrap();
        let out = stabound()
            .args(["scene", "--format", "json"])
            .arg(&path)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{keys}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let scene: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        let wall = &scene["devices"][0]["walls"][0];
        assert_eq!(
            wall["spectral_radius"], check["spectral_radius"],
            "{flags:?} / {keys}"
        );
        assert_eq!(wall["verdict"], check["verdict"], "{flags:?}");
    }
}

/// `--motor-damping 15` on `b = 20 N s/m` leaves `5 N s/m` on the handle:
/// `delta_2 = 5 * 1e-3 / 0.1 = 0.05`, in the report's elements.
#[test]
fn dampers_are_reported() {
    let v = json(
        &[
            &["check"][..],
            &DEVICE,
            &[
                "--handle-mass",
                "0.03",
                "--transmission-stiffness",
                "4e4",
                "--motor-damping",
                "15",
            ],
        ]
        .concat(),
    );
    let d2 = v["elements"]["transmission"]["delta_2"].as_f64().unwrap();
    // b - b_1 and the scaling each round once
    assert!((d2 - 0.05).abs() < 1e-15, "{v}");
}

/// Bad element values exit 2 with one line naming the flag.
#[test]
fn bad_values_name_the_flag() {
    let trans = ["--handle-mass", "0.03", "--transmission-stiffness", "4e4"];
    let cases: [(&[&str], &str); 6] = [
        (&["--motor-damping", "-1"], "--motor-damping"),
        (&["--motor-damping", "25"], "--motor-damping"),
        (&["--handle-damping", "25"], "--handle-damping"),
        (
            &[
                "--velocity-filter-cutoff",
                "40",
                "--velocity-filter-order",
                "3",
            ],
            "--velocity-filter-order",
        ),
        (
            &[
                "--velocity-filter-cutoff",
                "500",
                "--velocity-filter-order",
                "2",
            ],
            "--velocity-filter-cutoff",
        ),
        (&["--hand-stiffness", "-2"], "--hand-stiffness"),
    ];
    for (flags, flag) in cases {
        let e = assert_bad_input(&[&["check"][..], &DEVICE, &trans, flags].concat(), true);
        assert!(e.contains(flag), "{flags:?}: {e}");
    }
    // both shares must add up to the device's damping
    let e = assert_bad_input(
        &[
            &["check"][..],
            &DEVICE,
            &trans,
            &["--motor-damping", "10", "--handle-damping", "5"],
        ]
        .concat(),
        true,
    );
    assert!(e.contains("add up"), "{e}");
}

/// The page on adding an element names files that exist: each path it gives in backticks
/// (a name with a `/` and an extension) is a file of the tree, or of the library's sources
/// (the short names of its table).
#[test]
fn adding_an_element_names_existing_files() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let page = std::fs::read_to_string(root.join("docs/elements.md")).unwrap();
    let paths: Vec<&str> = page
        .split('`')
        .skip(1)
        .step_by(2)
        .filter(|t| {
            t.contains('/') && !t.contains(' ') && t.rsplit('/').next().unwrap().contains('.')
        })
        .collect();
    assert!(paths.len() >= 10, "{paths:?}");
    for p in paths {
        let library = root.join("crates/stabound/src").join(p);
        assert!(
            root.join(p).is_file() || library.is_file(),
            "docs/elements.md names {p}, which is not a file"
        );
    }
}
