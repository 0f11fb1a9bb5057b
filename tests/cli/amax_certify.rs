//! `amax --certify` on devices in physical units, with loop elements, over grids: one row per
//! device and one certificate holding every row's proof, which the standalone checker
//! (`tools/verify_certificate.py`) replays row by row; the rows are `amax`'s own.

use std::path::Path;

use crate::cli_certify::verify;
use crate::common::{assert_bad_input, csv, stabound, stdout};

/// A 1 kg device sampled at 1 ms with 1.5 samples of delay, two dampings (two rows), a
/// 0.3 kg hand that stays on the handle and a 30 Hz low-pass velocity filter; walls with
/// 0 to 10 N s/m of damping.
const DEVICE: [&str; 21] = [
    "amax",
    "--mass",
    "1",
    "--period",
    "0.001",
    "--damping",
    "0.5,1",
    "--delay-samples",
    "1.5",
    "--wall-damping-min",
    "0",
    "--wall-damping-max",
    "10",
    "--hand-mass",
    "0.3",
    "--hand-damping",
    "2",
    "--hand-stiffness",
    "300",
    "--always-gripped",
    "--velocity-filter-cutoff=30",
];

/// The rows of CSV output by column name, as numbers.
fn named_rows(out: &[u8]) -> Vec<Vec<(String, f64)>> {
    let (header, rows) = csv(out);
    rows.iter()
        .map(|r| {
            header
                .split(',')
                .zip(r)
                .map(|(k, v)| (k.to_string(), v.parse().unwrap()))
                .collect()
        })
        .collect()
}

fn cell(row: &[(String, f64)], name: &str) -> f64 {
    row.iter().find(|(k, _)| k == name).unwrap().1
}

/// The enclosures `row k: alpha_max in [lo, hi]` the checker printed, in order.
fn checked_enclosures(out: &str) -> Vec<(f64, f64)> {
    out.lines()
        .filter_map(|l| l.split_once("alpha_max in [")?.1.split_once("]"))
        .map(|(pair, _)| {
            let (lo, hi) = pair.split_once(", ").unwrap();
            (lo.parse().unwrap(), hi.parse().unwrap())
        })
        .collect()
}

/// Runs `args` with `--certify` into `path`, asserting success: the rows on stdout, and the
/// messages on stderr.
pub(crate) fn certified(args: &[&str], path: &Path) -> (Vec<u8>, String) {
    let out = stabound()
        .args(args)
        .arg("--certify")
        .arg(path)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(out.status.success(), "{args:?}: {err}");
    (out.stdout, err)
}

/// Two devices with a hand and a filter: every column `amax` writes without `--certify` is
/// the same, each enclosure holds its row's alpha_max (normalized and in N/m), and the
/// checker proves each row's enclosure, the same numbers as the rows.
#[test]
fn devices_with_elements_are_certified_row_by_row() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("amax.json");
    let plain = named_rows(&stdout(&DEVICE));
    let rows = named_rows(&certified(&DEVICE, &path).0);
    assert_eq!(rows.len(), 2);
    for (row, plain) in rows.iter().zip(&plain) {
        for (k, v) in plain {
            // exact: the same search on the same inputs
            assert_eq!(cell(row, k).to_bits(), v.to_bits(), "{k}");
        }
        let (lo, hi) = (
            cell(row, "alpha_lo_certified"),
            cell(row, "alpha_hi_certified"),
        );
        assert!(lo <= cell(row, "alpha_max") && cell(row, "alpha_max") < hi);
        let (klo, khi) = (
            cell(row, "K_lo_certified_N_per_m"),
            cell(row, "K_hi_certified_N_per_m"),
        );
        assert!(klo <= cell(row, "K_max_N_per_m") && cell(row, "K_max_N_per_m") < khi);
    }
    let (code, out) = verify(&path);
    assert_eq!(code, 0, "{out}");
    assert!(out.starts_with("verified: 2 rows"), "{out}");
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.contains("\"elements\": [\"hand\", \"filter\"]"));
    let enclosures = checked_enclosures(&out);
    let want: Vec<(f64, f64)> = rows
        .iter()
        .map(|r| (cell(r, "alpha_lo_certified"), cell(r, "alpha_hi_certified")))
        .collect();
    assert_eq!(enclosures, want);
    // the same rows as JSON
    let mut json_args = DEVICE.to_vec();
    json_args.extend(["--format", "json"]);
    let v: serde_json::Value = serde_json::from_slice(&certified(&json_args, &path).0).unwrap();
    for (obj, row) in v.as_array().unwrap().iter().zip(&rows) {
        for (k, x) in row {
            assert_eq!(obj[k.as_str()].as_f64(), Some(*x), "{k}");
        }
    }
}

/// A grid of the paper's loop in normalized units (two deltas, dampings 0 to 0.1): one
/// certificate for both rows, each row's enclosure proved.
#[test]
fn normalized_grid_is_certified() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("amax.json");
    let args = [
        "amax",
        "--delta",
        "0.5,1",
        "--d",
        "1",
        "--beta-min",
        "0",
        "--beta-max",
        "0.1",
    ];
    let rows = named_rows(&certified(&args, &path).0);
    let (code, out) = verify(&path);
    assert_eq!(code, 0, "{out}");
    assert!(out.starts_with("verified: 2 rows"), "{out}");
    let want: Vec<(f64, f64)> = rows
        .iter()
        .map(|r| (cell(r, "alpha_lo_certified"), cell(r, "alpha_hi_certified")))
        .collect();
    assert_eq!(checked_enclosures(&out), want);
}

/// What the certificate does not cover is refused as bad input, before any file is
/// written: an interval of hand masses (a set of devices that is not finite), elements
/// without a device in physical units, a missing damping limit, and a quantizer.
#[test]
fn amax_certify_refusals() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("c.json");
    let p = path.to_str().unwrap();
    let interval: Vec<&str> = DEVICE
        .iter()
        .map(|&a| if a == "0.3" { "0.2..0.4" } else { a })
        .collect();
    let mut no_max: Vec<&str> = DEVICE.to_vec();
    no_max.drain(11..13);
    let mut quantizer: Vec<&str> = DEVICE.to_vec();
    quantizer.extend(["--encoder-resolution", "1e-5"]);
    let normalized = [
        "amax",
        "--delta",
        "0.5",
        "--d",
        "1",
        "--beta-min",
        "0",
        "--beta-max",
        "1",
        "--velocity-filter-cutoff",
        "30",
    ];
    for args in [&interval[..], &no_max, &quantizer, &normalized] {
        let mut args = args.to_vec();
        args.extend(["--certify", p]);
        assert_bad_input(&args, true);
        assert!(!path.exists(), "{args:?}");
    }
}
