//! Rows written as they are computed: a file given with `-o` holds the same bytes as stdout,
//! whatever the number of worker threads, for runs of many curves and many row chunks.

use crate::common::{csv, stabound};

/// Runs `stabound ARGS -o FILE` with `threads` workers and returns the file's bytes.
fn to_file(args: &[&str], threads: &str) -> Vec<u8> {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("out");
    let out = stabound()
        .env("RAYON_NUM_THREADS", threads)
        .args(args)
        .arg("-o")
        .arg(&path)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(out.stdout.is_empty(), "{args:?}: data on stdout with -o");
    // the file alone is left in the directory: no temporary file behind it
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
    std::fs::read(&path).unwrap()
}

fn to_stdout(args: &[&str], threads: &str) -> Vec<u8> {
    crate::common::stdout_with(args, Some(threads))
}

/// 24 curves (more than the few computed ahead per thread) in CSV and JSON, and a
/// delta-beta run: files and stdout agree byte for byte on 1, 2 and 3 threads, and the JSON
/// array holds the CSV's rows.
#[test]
fn boundary_files_equal_stdout_on_any_thread_count() {
    let base = [
        "boundary",
        "--delta",
        "0:1:6",
        "--d",
        "0,0.5,1,4",
        "--tol",
        "1e-5",
    ];
    let csv_one = to_file(&base, "1");
    for threads in ["2", "3"] {
        assert!(
            csv_one == to_file(&base, threads),
            "CSV file, {threads} threads"
        );
    }
    assert!(
        csv_one == to_stdout(&base, "2"),
        "CSV file and stdout differ"
    );
    let (header, rows) = csv(&csv_one);
    assert_eq!(header, "delta,d,alpha,beta,piece");
    // 24 closed polylines, each ending on its first point
    let starts = rows.windows(2).filter(|w| w[0][0..2] != w[1][0..2]).count();
    assert_eq!(starts + 1, 24);

    let json_args = [&base[..], &["--format", "json"]].concat();
    let json_one = to_file(&json_args, "1");
    assert!(json_one == to_file(&json_args, "2"), "JSON file, 2 threads");
    assert!(
        json_one == to_stdout(&json_args, "3"),
        "JSON file and stdout differ"
    );
    let v: serde_json::Value = serde_json::from_slice(&json_one).unwrap();
    let arr = v.as_array().unwrap();
    assert_eq!(arr.len(), rows.len());
    assert_eq!(arr[0]["piece"], rows[0][4].as_str());

    let plane = [
        "boundary",
        "--plane",
        "delta-beta",
        "--alpha",
        "0,0.05,0.1",
        "--d",
        "0,1",
        "--tol",
        "1e-5",
    ];
    let one = to_file(&plane, "1");
    assert!(one == to_file(&plane, "2"), "delta-beta file, 2 threads");
    assert!(
        one == to_stdout(&plane, "2"),
        "delta-beta file and stdout differ"
    );
}

/// 3 x 300 alpha_max rows, several chunks each: the same bytes on 1, 2 and 3 threads, to a
/// file and to stdout, in CSV and JSON.
#[test]
fn amax_files_equal_stdout_on_any_thread_count() {
    for format in ["csv", "json"] {
        let args = [
            "amax", "--delta", "0:3:300", "--d", "0,1,2", "--margin", "0.5", "--format", format,
        ];
        let one = to_file(&args, "1");
        assert!(one == to_file(&args, "2"), "{format}: 2 threads");
        assert!(one == to_file(&args, "3"), "{format}: 3 threads");
        assert!(
            one == to_stdout(&args, "2"),
            "{format}: file and stdout differ"
        );
        let lines = one.iter().filter(|&&b| b == b'\n').count();
        // CSV: header + 900 rows; JSON: [ + 900 rows + ]
        assert_eq!(lines, if format == "csv" { 901 } else { 902 });
    }
}

/// A run stopped after good curves leaves no file at all, though rows were already written
/// into its temporary file.
#[test]
fn a_failing_run_leaves_no_file() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("b.csv");
    // the first curve takes milliseconds; the second (alpha at the smallest subnormal, where
    // the stable band is thinner than any tolerance resolves) runs for minutes, so the time
    // limit stops the run after the first curve's rows were written
    let out = stabound()
        .env("RAYON_NUM_THREADS", "2")
        .args([
            "boundary",
            "--plane",
            "delta-beta",
            "--delta",
            "0,1",
            "--alpha",
            "1,4.9e-324",
            "--d",
            "0.5",
            "--tol",
            "1e-3",
            "--time-limit",
            "1",
            "-o",
        ])
        .arg(&path)
        .output()
        .unwrap();
    assert_eq!(
        out.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
}
