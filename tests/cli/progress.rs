//! Progress on stderr: a job that runs longer than a second draws a bar (`done/total`) when
//! stderr is a terminal, here a pseudo-terminal, and writes nothing of it when stderr is a
//! pipe.

use std::io::Read;
use std::process::{Command, Output, Stdio};

use nix::pty::{Winsize, openpty};

use crate::common::stabound;

/// `amax` over 100,000 rows at d = 100 (tens of seconds of work), cut by its time limit:
/// the bar appears after a second of work, the limit ends the run after three.
const LONG: [&str; 7] = [
    "amax",
    "--delta",
    "0:10:100000",
    "--d",
    "100",
    "--time-limit",
    "3",
];

/// What the bar shows: units done out of the 100,000 rows.
const BAR: &str = "/100000";

/// Runs `args` with stderr on a pseudo-terminal of 80 columns; returns the output with the
/// terminal's text as its stderr.
fn with_terminal_stderr(args: &[&str]) -> Output {
    let size = Winsize {
        ws_row: 24,
        ws_col: 80,
        ws_xpixel: 0,
        ws_ypixel: 0,
    };
    let pty = openpty(&size, None).expect("a pseudo-terminal");
    let child = Command::new(env!("CARGO_BIN_EXE_stabound"))
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::from(pty.slave))
        .spawn()
        .unwrap();
    // the terminal's text, read while the job runs (a full terminal would block it); Linux
    // ends the read with EIO once the last holder of the terminal's other side has exited
    let mut master = std::fs::File::from(pty.master);
    let reader = std::thread::spawn(move || {
        let mut text = Vec::new();
        let mut buf = [0u8; 4096];
        while let Ok(n) = master.read(&mut buf) {
            if n == 0 {
                break;
            }
            text.extend_from_slice(&buf[..n]);
        }
        text
    });
    let mut out = child.wait_with_output().unwrap();
    out.stderr = reader.join().unwrap();
    out
}

#[test]
fn a_long_job_draws_its_progress_on_a_terminal_only() {
    let shown = with_terminal_stderr(&LONG);
    let on_terminal = String::from_utf8_lossy(&shown.stderr);
    assert_eq!(shown.status.code(), Some(1), "{on_terminal}");
    assert!(
        on_terminal.contains(BAR),
        "no progress drawn: {on_terminal:?}"
    );
    assert!(on_terminal.contains("--time-limit 3 s"), "{on_terminal:?}");

    let piped = stabound().args(LONG).output().unwrap();
    let err = String::from_utf8_lossy(&piped.stderr);
    assert_eq!(piped.status.code(), Some(1), "{err}");
    assert!(!err.contains(BAR), "progress drawn into a pipe: {err:?}");
    // the time limit's message and nothing else
    assert_eq!(err.lines().count(), 1, "{err:?}");
    assert!(err.contains("--time-limit 3 s"), "{err:?}");
}
