//! `table --conservative --certify FILE`: the table says CERTIFIED, the standalone checker
//! (`tools/verify_certificate.py`) accepts the certificate and finds in it the very nodes the
//! table holds, a node raised in the certificate (its CRC made to match again) is rejected,
//! and what the certificate does not cover is refused before any work. A table of a loop with
//! a velocity filter is certified and checked too, and a changed filter pole, node or box in
//! its certificate is rejected. A table over a hand that can let go is certified for both
//! devices, its walls checked by eigenvalues, and a member dropped, duplicated or swapped is
//! rejected. A cell that cannot be proved fails with the flags that may help.

use std::path::Path;
use std::process::Command;

use crate::certified_sets::DEVICE;
use crate::common::{assert_bad_input, csv_numbers, stabound};
use crate::robust_sets::hand_header_holds;
use stabound::certificate::CELL_BOXES_CAP;
use stabound::params::{Plant, Wall};
use stabound::stability::{Checker, Options};

/// Runs the checker on `path`: its exit code, stdout and stderr.
pub(crate) fn verify(path: &Path) -> (i32, String, String) {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tools/verify_certificate.py");
    let out = Command::new("python3")
        .arg(script)
        .arg(path)
        .output()
        .expect("python3 runs the checker");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// Rewrites the certificate at `path` by the Python statements `edit` (which turn `text`, the
/// certificate, into `body`), seals it with a matching CRC-32, and runs the checker on it:
/// the proof, not the CRC, must reject it. Returns the checker's stderr.
pub(crate) fn rejected_after(path: &Path, edit: &str) -> String {
    let seal = r#"
body = body[: body.index('  "crc32"')]
open(p, "w").write(body + '  "crc32": "%08x"\n}\n' % zlib.crc32(body.encode()))"#;
    let script =
        format!("import json, sys, zlib\np = sys.argv[1]\ntext = open(p).read(){edit}{seal}\n");
    let st = Command::new("python3")
        .args(["-c", &script])
        .arg(path)
        .status()
        .unwrap();
    assert!(st.success());
    let (code, _, err) = verify(path);
    assert_eq!(code, 1, "{err}");
    err
}

/// A C99 hex float (`0x1.8p-1`, `0x0p+0`) as an `f64`, written here so that the test does not
/// trust the library's writer.
pub(crate) fn from_hex(s: &str) -> f64 {
    let (sign, rest) = match s.strip_prefix('-') {
        Some(r) => (-1.0, r),
        None => (1.0, s),
    };
    let rest = rest.strip_prefix("0x").unwrap();
    let (mant, exp) = rest.split_once('p').unwrap();
    let (int, frac) = mant.split_once('.').unwrap_or((mant, ""));
    // at most 53 bits: the integer of all the digits is exact, and so is the scaling
    let digits = u64::from_str_radix(&format!("{int}{frac}"), 16).unwrap() as f64;
    let exp: i32 = exp.parse().unwrap();
    let v = digits * 2f64.powi(-4 * frac.len() as i32);
    sign * v * 2f64.powi(exp)
}

const GRID: [&str; 4] = ["--delta", "0.5,0.75,1", "--d", "1,2"];

#[test]
fn certified_table_verifies_and_holds_the_tables_nodes() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("table-cert.json");
    let run = |format: &str| {
        let out = stabound()
            .arg("table")
            .args(GRID)
            .args(["--conservative", "--format", format, "--certify"])
            .arg(&path)
            .output()
            .unwrap();
        assert!(out.status.success(), "{out:?}");
        String::from_utf8(out.stdout).unwrap()
    };
    let header = run("c");
    assert!(header.contains("CERTIFIED: for every delta of every interval"));
    let plain = stabound()
        .arg("table")
        .args(GRID)
        .args(["--conservative", "--format", "c"])
        .output()
        .unwrap();
    assert!(!String::from_utf8_lossy(&plain.stdout).contains("CERTIFIED"));
    // the CSV (parsed by Rust's correctly rounded parser) rows: d outer, delta inner
    let rows = csv_numbers(run("csv").as_bytes());
    let (code, out, err) = verify(&path);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.starts_with("verified: stable for every wall of the table's lookup: 4 cells"),
        "{out}"
    );
    let cert: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    for (col, key) in [(2, "alpha"), (3, "beta")] {
        let nodes: Vec<f64> = cert["table"][key]
            .as_array()
            .unwrap()
            .iter()
            .flat_map(|row| row.as_array().unwrap().iter())
            .map(|v| from_hex(v.as_str().unwrap()))
            .collect();
        let table: Vec<f64> = rows.iter().map(|r| r[col]).collect();
        // the same doubles: exactly equal
        assert_eq!(nodes, table, "{key}");
    }
    // a node raised (doubled: its exponent up by one), the CRC computed again: the proof
    // itself must reject it (a box's enclosures no longer hold its walls, or, for a box
    // decided around its centre, the arcs no longer hold off its wider walls)
    let tamper = r#"
cert = json.loads(text)
old = cert["table"]["alpha"][0][1]
mant, exp = old.split("p")
new = mant + "p" + format(int(exp) + 1, "+d")
body = text.replace('"' + old + '"', '"' + new + '"', 1)"#;
    let err = rejected_after(&path, tamper);
    assert!(
        err.contains("does not hold the recomputed coefficient")
            || err.contains("a root may cross the unit circle within the leaf"),
        "{err}"
    );
}

#[test]
fn certify_refusals() {
    // without --conservative, with --shard, with a set of devices: bad usage, nothing written
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("c.json");
    let p = path.to_str().unwrap();
    for extra in [
        &["--certify", p][..],
        &["--conservative", "--certify", p, "--shard", "1/2"][..],
    ] {
        assert_bad_input(&[&["table"][..], &GRID[..], extra].concat(), false);
    }
    assert_bad_input(
        &[
            "table",
            "--mass",
            "0.1",
            "--period",
            "0.001",
            "--damping",
            "50,60",
            "--delay-samples",
            "1",
            "--hand-mass",
            "0.05..0.1",
            "--conservative",
            "--certify",
            p,
        ],
        false,
    );
    // interpolated delays: refused by the library, nothing written
    assert_bad_input(
        &[
            "table",
            "--delta",
            "0.5,1",
            "--d",
            "1,1.5",
            "--conservative",
            "--certify",
            p,
        ],
        false,
    );
    assert!(!path.exists());
}

/// A box taken out of a cell (the CRC made to match again) leaves a gap the checker finds;
/// a small budget of boxes still certifies, by lowering further.
#[test]
fn a_missing_box_is_a_gap() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("tiny.json");
    let out = stabound()
        .args(["table", "--delta", "0.9,1", "--d", "1", "--conservative"])
        .args(["--certify-boxes", "16", "--certify"])
        .arg(&path)
        .output()
        .unwrap();
    assert!(out.status.success(), "{out:?}");
    let (code, text, err) = verify(&path);
    assert_eq!(code, 0, "{err}");
    assert!(text.contains("1 cells"), "{text}");
    let drop_box = r#"
start = text.index('      {"box"', text.index('      {"box"') + 1)
end = text.index('      {"box"', start + 1)
body = text[: start] + text[end:]"#;
    let err = rejected_after(&path, drop_box);
    assert!(err.contains("do not tile"), "{err}");
}

/// Wide cells behind a 50 Hz first-order low-pass (b = 0 to 25 N s/m, delta 0 to 0.25, and
/// b = 50 to 100 N s/m, delta 0.5 to 1, 0.1 kg at 1 ms, one sample): each table the command
/// says is CERTIFIED, the checker accepts. Over such a range of `delta` the checker's own
/// interval exponential wraps differently from the prover's: the first table's claimed
/// family balls, made on unwidened enclosures, did not hold the checker's, and the second's
/// Rouche arcs failed on the checker's enclosure of the whole range.
#[test]
fn wide_filtered_cells_said_certified_are_accepted_by_the_checker() {
    for damping in ["0,25", "50,100"] {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("wide.json");
        let out = stabound()
            .args([
                "table",
                "--mass",
                "0.1",
                "--period",
                "0.001",
                "--damping",
                damping,
            ])
            .args(["--delay-samples", "1", "--velocity-filter-cutoff", "50"])
            .args(["--conservative", "--format", "csv", "--certify"])
            .arg(&path)
            .output()
            .unwrap();
        assert!(out.status.success(), "{out:?}");
        let said = String::from_utf8_lossy(&out.stderr);
        assert!(said.contains("certified: 1 cells proved stable"), "{said}");
        let (code, text, err) = verify(&path);
        assert_eq!(code, 0, "damping {damping}: {err}");
        assert!(text.contains("1 cells"), "{text}");
    }
}

/// A 0.1 kg device at 1 ms with one sample of delay and a 30 Hz first-order low-pass on the
/// velocity (b = 80 to 82 N s/m, delta = 0.8 to 0.82; 16 boxes a cell keep the checker to
/// seconds): certified, checked, and the checker rejects the certificate with the filter's
/// pole changed, with a node's digit changed, and with a box taken out (each with its CRC
/// made to match again).
#[test]
fn filtered_table_is_certified_and_tampering_rejected() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("filtered.json");
    let out = stabound()
        .args([
            "table",
            "--mass",
            "0.1",
            "--period",
            "0.001",
            "--damping",
            "80,81,82",
        ])
        .args(["--delay-samples", "1", "--velocity-filter-cutoff", "30"])
        .args([
            "--conservative",
            "--format",
            "c",
            "--certify-boxes",
            "16",
            "--certify",
        ])
        .arg(&path)
        .output()
        .unwrap();
    assert!(out.status.success(), "{out:?}");
    assert!(String::from_utf8_lossy(&out.stdout).contains("CERTIFIED"));
    let (code, text, err) = verify(&path);
    assert_eq!(code, 0, "{err}");
    assert!(text.contains("2 cells"), "{text}");
    let original = std::fs::read_to_string(&path).unwrap();
    assert!(original.contains("\"elements\": [\"filter\"]"));
    let restore = || std::fs::write(&path, &original).unwrap();
    // the pole (0.83) changed in its first hex digit after the point
    let pole = r#"
cert = json.loads(text)
old = cert["table"]["filter"]["pole"]
i = old.index(".") + 1
new = old[:i] + format((int(old[i], 16) + 4) % 16, "x") + old[i + 1:]
body = text.replace('"pole": "' + old + '"', '"pole": "' + new + '"')"#;
    let err = rejected_after(&path, pole);
    assert!(err.contains("does not hold the recomputed"), "{err}");
    restore();
    // a node's first hex digit after the point changed
    let node = r#"
cert = json.loads(text)
old = cert["table"]["alpha"][0][1]
i = old.index(".") + 1
new = old[:i] + format((int(old[i], 16) + 4) % 16, "x") + old[i + 1:]
body = text.replace('"' + old + '"', '"' + new + '"', 1)"#;
    let err = rejected_after(&path, node);
    assert!(!err.contains("CRC"), "{err}");
    restore();
    let drop_box = r#"
start = text.index('      {"box"')
end = text.index('      {"box"', start + 1)
body = text[: start] + text[end:]"#;
    let err = rejected_after(&path, drop_box);
    assert!(err.contains("do not tile"), "{err}");
}

/// The hand-held device of a 30 Hz velocity filter whose hand (0.3 kg, 2 N s/m, 300 N/m)
/// can let go (0.1 kg, 1 ms, one sample; b = 80 to 82 N s/m, 16 boxes a cell): the table
/// is certified for both devices, the checker accepts it for the set's 2 devices, and every
/// node of the C header and the walls at 1/8 steps between them are stable for both devices
/// by the eigenvalues of their closed-loop state matrices.
#[test]
fn table_over_a_hand_that_lets_go_is_certified_for_both_devices() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("hand.json");
    let out = stabound()
        .args(HAND)
        .args(["c", "--certify"])
        .arg(&path)
        .output()
        .unwrap();
    assert!(out.status.success(), "{out:?}");
    let header = String::from_utf8(out.stdout).unwrap();
    assert!(header.contains("CERTIFIED") && header.contains("the free device is a member"));
    let (code, text, err) = verify(&path);
    assert_eq!(code, 0, "{err}");
    assert!(
        text.contains("stable for each of the set's 2 devices"),
        "{text}"
    );
    hand_header_holds(&header, 30.0, 8);
}

/// The table of the hand that can let go, certified with 16 boxes a cell.
const HAND: [&str; 21] = [
    "table",
    "--mass",
    "0.1",
    "--period",
    "0.001",
    "--damping",
    "80,81,82",
    "--delay-samples",
    "1",
    "--velocity-filter-cutoff",
    "30",
    "--hand-mass",
    "0.3",
    "--hand-damping",
    "2",
    "--hand-stiffness",
    "300",
    "--conservative",
    "--certify-boxes",
    "16",
    "--format",
];

/// The certificate of the hand that can let go, changed (its CRC made to match again):
/// a member dropped or duplicated, a digit of the set's hand changed (the members are then
/// not the set's), and the two members' proofs swapped (each proof then given the other
/// device's model) are all rejected.
#[test]
fn a_set_certificate_with_a_member_dropped_duplicated_or_swapped_is_rejected() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("hand.json");
    let out = stabound()
        .args(&HAND[..HAND.len() - 1])
        .arg("--certify")
        .arg(&path)
        .output()
        .unwrap();
    assert!(out.status.success(), "{out:?}");
    let original = std::fs::read_to_string(&path).unwrap();
    let restore = || std::fs::write(&path, &original).unwrap();
    let rewrite = |edit: &str| {
        format!("\ncert = json.loads(text)\n{edit}\nbody = json.dumps(cert, indent=2) + \"\\n\"")
    };
    for edit in [
        "del cert['members'][1]",
        "cert['members'].append(cert['members'][0])",
        "cert['members'][1] = cert['members'][0]",
        "h = cert['set']['hand'][0]; h['mu_h'] = h['mu_h'].replace('0x1.8p+1', '0x1.9p+1')",
    ] {
        let err = rejected_after(&path, &rewrite(edit));
        assert!(err.contains("members are not the set's 2"), "{edit}: {err}");
        restore();
    }
    let swap = "m = cert['members']; m[0]['cells'], m[1]['cells'] = m[1]['cells'], m[0]['cells']";
    let err = rejected_after(&path, &rewrite(swap));
    assert!(err.contains("member 0:"), "{err}");
}

/// The example device behind a 30 Hz low-pass with cells 50 N s/m wide (b = 0 to 200 N s/m,
/// delta 0 to 2): no lowering down to 1/8 proves any cell within the default 256 boxes, so
/// each cell's budget grows before its nodes are lowered, and the table is certified. The
/// certificate is the one `--certify-boxes 4096` writes (each cell proved as it is with at
/// most 4096 boxes), its nodes lie at or below the conservative table's, and stderr says
/// how far the budget grew. The checker replays these 5,644 boxes in minutes, so it is run
/// here on a narrow cell whose budget of 2 boxes grows to 8.
#[test]
fn wide_cells_grow_their_budget_before_lowering() {
    const WIDE: [&str; 12] = [
        "table",
        "--mass",
        "0.1",
        "--period",
        "0.001",
        "--damping",
        "0:200:5",
        "--delay-samples",
        "1",
        "--velocity-filter-cutoff",
        "30",
        "--conservative",
    ];
    let dir = tempfile::tempdir().unwrap();
    let (grown, given) = (dir.path().join("grown.json"), dir.path().join("given.json"));
    let out = stabound()
        .args(WIDE)
        .arg("--certify")
        .arg(&grown)
        .output()
        .unwrap();
    assert!(out.status.success(), "{out:?}");
    let said = String::from_utf8_lossy(&out.stderr);
    assert!(said.contains("certified: 4 cells proved stable"), "{said}");
    assert!(
        said.contains("4 cells that no lowering proved within 256 boxes a cell had their budget grown, up to 4096 boxes a cell"),
        "{said}"
    );
    let certified = csv_numbers(&out.stdout);
    let plain = stabound().args(WIDE).output().unwrap();
    assert!(plain.status.success());
    for (c, p) in certified.iter().zip(csv_numbers(&plain.stdout)) {
        assert!(c[2] <= p[2], "{c:?} {p:?}");
    }
    let explicit = stabound()
        .args(WIDE)
        .args(["--certify-boxes", "4096", "--certify"])
        .arg(&given)
        .output()
        .unwrap();
    assert!(explicit.status.success(), "{explicit:?}");
    assert!(!String::from_utf8_lossy(&explicit.stderr).contains("grown"));
    assert_eq!(
        std::fs::read(&grown).unwrap(),
        std::fs::read(&given).unwrap()
    );
    // a narrow cell, its budget grown from 2 boxes: the checker accepts it
    let small = dir.path().join("small.json");
    let out = stabound()
        .args([&WIDE[..6], &["80,82"][..], &WIDE[7..]].concat())
        .args(["--certify-boxes", "2", "--certify"])
        .arg(&small)
        .output()
        .unwrap();
    assert!(out.status.success(), "{out:?}");
    let said = String::from_utf8_lossy(&out.stderr);
    assert!(
        said.contains("within 2 boxes a cell had their budget grown"),
        "{said}"
    );
    let (code, text, err) = verify(&small);
    assert_eq!(code, 0, "{err}");
    assert!(text.contains("1 cells"), "{text}");
}

/// The table of the paper's loop over `delta` 0.5 and 1 and that of the 0.1 kg device at
/// 1 ms over the dampings `dampings` (N s/m, the table's axis), both `samples` samples late.
fn delayed_tables(samples: &'static str, dampings: &'static str) -> [Vec<&'static str>; 2] {
    [
        vec!["table", "--delta", "0.5,1", "--d", samples],
        [
            &["table"][..],
            &DEVICE[..5],
            &[dampings, "--delay-samples", samples],
        ]
        .concat(),
    ]
}

/// Tables at a delay of 10 samples (teleoperation), normalized over `delta` 0.5 to 1 and
/// for the 0.1 kg device at 1 ms over dampings 50 to 100 N s/m: certified, the checker
/// accepts the certificate, the nodes are the conservative table's lowered by less than
/// 1/16, and every node and the walls at 1/16 steps between them (as the CSV gives them)
/// are stable by the eigenvalues of the closed loop's state matrix.
#[test]
fn long_delay_tables_are_certified() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("long.json");
    let [normalized, physical] = delayed_tables("10", "50,75,100");
    for (args, cells) in [(&normalized, 1), (&physical, 2)] {
        let run = |extra: &[&str]| {
            let out = stabound()
                .args(args)
                .args(["--conservative", "--format", "csv"])
                .args(extra)
                .output()
                .unwrap();
            assert!(out.status.success(), "{out:?}");
            csv_numbers(&out.stdout)
        };
        let plain = run(&[]);
        let rows = run(&["--certify", path.to_str().unwrap()]);
        let (code, out, err) = verify(&path);
        assert_eq!(code, 0, "{err}");
        assert!(out.contains(&format!("{cells} cells")), "{out}");
        // columns d, delta, alpha_max, beta_at_max
        for (r, p) in rows.iter().zip(&plain) {
            assert!(
                r[2] <= p[2] && r[2] > p[2] * (1.0 - 1.0 / 16.0),
                "{r:?} {p:?}"
            );
        }
        for w in rows.windows(2) {
            for step in 0..=16 {
                let s = f64::from(step) / 16.0;
                let at = |k: usize| w[0][k] + s * (w[1][k] - w[0][k]);
                let plant = Plant::new(at(1), 10.0).unwrap();
                let m = Checker::new(plant, Options::default())
                    .unwrap()
                    .state_matrix(&Wall::new(at(2), at(3)).unwrap());
                let schur = m.try_schur(1e-14, 10_000).expect("Schur form converges");
                let radius = schur
                    .complex_eigenvalues()
                    .iter()
                    .map(|z| z.norm())
                    .fold(0.0, f64::max);
                // the certified walls lie about 3e-3 inside; eigenvalues are good to 1e-12
                assert!(radius < 1.0, "{:?} radius {radius}", (at(1), at(2), at(3)));
            }
        }
    }
}

/// A cell that no lowering proves within the largest budget (the paper's loop 40 samples
/// late over delta 0.5 to 1, or the 0.1 kg device at 1 ms over dampings 50 to 100 N s/m:
/// `q` of degree 43, beyond what the recursion in double-precision intervals decides even
/// for one wall): the command fails (exit 1, a numerical failure, not bad input) naming the cell, writes
/// no certificate and no table, and says what may help in the flags and units it was given:
/// the largest budget of boxes and the axis with a node halfway in each interval.
#[test]
fn a_cell_not_proved_fails_with_the_flags_that_help() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("never.json");
    let [normalized, physical] = delayed_tables("40", "50,100");
    for (args, cell, axis) in [
        (&normalized, "d = 40, delta in [0.5, 1]", "--delta 0.5:1:3"),
        (&physical, "d = 40, delta in [0.5, ", "--damping 50:100:3"),
    ] {
        let out = stabound()
            .args(args)
            .args(["--conservative", "--certify"])
            .arg(&path)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{err}");
        assert!(out.stdout.is_empty() && !path.exists(), "{err}");
        assert!(!err.contains("panicked"), "{err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{err}");
        assert!(err.contains(&format!("proves the cell {cell}")), "{err}");
        let hint = format!(
            "try --certify-boxes 65536 (the budget grew to {CELL_BOXES_CAP} boxes a cell), or a finer axis, {axis}"
        );
        assert!(err.trim_end().ends_with(&hint), "{err}");
    }
}
