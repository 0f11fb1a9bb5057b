//! A stiff transmission at the command line: the wall of `docs/MODEL.md` section 8.1 whose
//! radius is `1 - 2.7e-9` (40 digits, `data/stiff/walls.csv`) is stable, not unstable; a
//! coupling of `1e8` (normalized) is accepted and a stiffer one refused with what to do.

use crate::common::{assert_bad_input, json};

/// The device of `data/stiff/walls.csv` in units where the flags are normalized values.
const DEVICE: [&str; 14] = [
    "--mass",
    "1",
    "--period",
    "1",
    "--damping",
    "0.001",
    "--delay-samples",
    "1",
    "--handle-mass",
    "0.3",
    "--encoder",
    "handle",
    "--format",
    "json",
];

fn check(kc: &str, alpha: &str, beta: &str) -> serde_json::Value {
    let mut args = vec!["check", "--radius"];
    args.extend(DEVICE);
    args.extend([
        "--transmission-stiffness",
        kc,
        "--stiffness",
        alpha,
        "--wall-damping",
        beta,
    ]);
    json(&args)
}

#[test]
fn stiff_coupling_near_alpha_zero_is_not_called_unstable() {
    // reference radius 0.9999999972946 (a double-precision exponential gave 1.0000000000153)
    let v = check("521140.08", "2.395027e-11", "7.852916e-03");
    assert_eq!(v["verdict"], "stable", "{v}");
    let radius = v["spectral_radius"].as_f64().unwrap();
    assert!((radius - 0.999_999_997_294_6).abs() < 1e-11, "{radius}");
}

#[test]
fn coupling_up_to_1e8_accepted_stiffer_refused() {
    let v = check("1e8", "0.01", "0.05");
    assert!(v["spectral_radius"].as_f64().unwrap() < 1.0, "{v}");
    let mut args = vec!["check"];
    args.extend(DEVICE);
    args.extend([
        "--transmission-stiffness",
        "1.5e8",
        "--stiffness",
        "0.01",
        "--wall-damping",
        "0.05",
    ]);
    let err = assert_bad_input(&args, true);
    assert!(err.contains("leave the transmission out"), "{err}");
}
