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
