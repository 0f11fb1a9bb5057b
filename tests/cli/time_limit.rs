//! `--time-limit SECONDS`: a slow request ends at the limit with exit status 1 and a message
//! naming the flag, leaves no output file, and a request that finishes in time is unchanged.

use std::time::{Duration, Instant};

use crate::common::{assert_bad_input, stabound, stdout};

/// A request that takes minutes: the delta-beta plane at a subnormal stiffness, a fine
/// tolerance and a fractional delay.
const SLOW: [&str; 9] = [
    "boundary",
    "--plane",
    "delta-beta",
    "--alpha",
    "4.9e-324",
    "--d",
    "0.5",
    "--tol",
    "1e-3",
];

#[test]
fn a_slow_request_stops_at_the_limit() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("b.csv");
    let start = Instant::now();
    let out = stabound()
        .args(SLOW)
        .args(["--time-limit", "0.5", "-o"])
        .arg(&file)
        .output()
        .unwrap();
    let took = start.elapsed();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("--time-limit 0.5 s"), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    // the limit, plus the start-up and exit of a process on a loaded machine
    assert!(took < Duration::from_secs(20), "{took:?}");
    assert!(!file.exists());
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
}

#[test]
fn a_request_in_time_is_unchanged() {
    let args = [
        "check", "--alpha", "0.1", "--beta", "0.3", "--delta", "0.5", "--d", "1",
    ];
    let limited = stdout(&[&args[..], &["--time-limit", "60"]].concat());
    assert_eq!(limited, stdout(&args));
    // before the subcommand too
    let first = stdout(&[&["--time-limit", "60"][..], &args].concat());
    assert_eq!(first, limited);
}

#[test]
fn a_time_limit_is_seconds_above_zero() {
    for bad in ["0", "-1", "nan", "inf", "1e300", "soon"] {
        let err = assert_bad_input(
            &[
                "check",
                "--alpha",
                "0",
                "--beta",
                "0",
                "--delta",
                "0",
                "--d",
                "1",
                "--time-limit",
                bad,
            ],
            true,
        );
        assert!(
            err.contains("time-limit") || err.contains(bad),
            "{bad}: {err}"
        );
    }
}
