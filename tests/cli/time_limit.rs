//! `--time-limit SECONDS`: a slow request ends at the limit with exit status 1 and a message
//! naming the flag, leaves no output file, and a request that finishes in time is unchanged;
//! an interrupt ends the run with status 130 and no output file; 0 is no limit.

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
fn a_time_limit_is_seconds_from_zero_to_a_year() {
    for bad in ["-1", "nan", "inf", "1e300", "soon"] {
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

/// Requests that ran for minutes: each engine stops at its own polls, well before the
/// watch that ends a process which does not stop (two seconds past the limit): the message
/// comes once, on one line, and no output file is left.
#[test]
fn every_slow_engine_stops_at_the_limit() {
    let walls = {
        let mut s = String::from("alpha,beta,delta,d\n");
        for i in 0..2000 {
            s.push_str(&format!("{},0.01,0.5,500\n", 1e-6 * f64::from(i % 7)));
        }
        s
    };
    let dir = tempfile::tempdir().unwrap();
    let batch = dir.path().join("walls.csv");
    std::fs::write(&batch, walls).unwrap();
    let batch = batch.to_str().unwrap().to_string();
    // every element at a long delay: alpha_max for the hand on and let go takes some
    // seconds; stopped, its searches confirm no candidate, and must say why
    let elements = "amax --mass 0.1 --period 0.001 --damping 0 --delay-samples 100 \
        --velocity-filter-cutoff 100 --velocity-filter-order 2 --hand-mass 0.2 \
        --hand-damping 1 --hand-stiffness 50 --handle-mass 0.03 \
        --transmission-stiffness 2e5 --actuator-time-constant 2e-4";
    let elements: Vec<&str> = elements.split_whitespace().collect();
    let slow: [&[&str]; 6] = [
        &["passivity", "--delta", "0.5", "--d", "1", "--tol", "1e-12"],
        &elements,
        &[
            "table",
            "--delta",
            "1:10:11",
            "--d",
            "499.99999999999994",
            "--conservative",
        ],
        &["check", "--batch", &batch, "--radius"],
        &[&SLOW[..], &["--method", "bisect"]].concat(),
        &SLOW,
    ];
    for args in slow {
        let file = dir.path().join("out");
        let start = Instant::now();
        let out = stabound()
            .args(args)
            .args(["--time-limit", "0.3", "-o"])
            .arg(&file)
            .output()
            .unwrap();
        let took = start.elapsed();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{args:?}: {err}");
        assert!(err.contains("--time-limit 0.3 s"), "{args:?}: {err}");
        assert_eq!(err.lines().count(), 1, "{args:?}: {err}");
        assert!(!file.exists(), "{args:?}");
        // on a loaded machine a process may wait a while for a core; the point is that it
        // does not run on to minutes
        assert!(took < Duration::from_secs(30), "{args:?}: {took:?}");
    }
}

#[test]
fn zero_is_no_limit() {
    let args = [
        "check", "--alpha", "0.1", "--beta", "0.3", "--delta", "0.5", "--d", "1",
    ];
    assert_eq!(
        stdout(&[&args[..], &["--time-limit", "0"]].concat()),
        stdout(&args)
    );
}

#[test]
fn the_default_limit_is_stated_in_the_help() {
    let help = String::from_utf8(stdout(&["--help"])).unwrap();
    assert!(help.contains("600 s"), "{help}");
    assert!(help.contains("0 is no limit"), "{help}");
}

/// Ctrl-C (SIGINT) during a slow request: the engines stop, the run exits with 130 as
/// shells report an interrupt, and the output file is not written.
#[cfg(unix)]
#[test]
fn an_interrupt_stops_the_run_without_an_output_file() {
    use nix::sys::signal::{Signal, kill};
    use nix::unistd::Pid;
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("b.csv");
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_stabound"))
        .args(SLOW)
        .args(["--time-limit", "0", "-o"])
        .arg(&file)
        .spawn()
        .unwrap();
    std::thread::sleep(Duration::from_millis(700));
    kill(Pid::from_raw(child.id() as i32), Signal::SIGINT).unwrap();
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(130));
    assert!(!file.exists());
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
}
