//! Helpers shared by the CLI tests: running the binary, parsing its CSV and JSON output,
//! and the bad-input contract (exit 2, one line on stderr, no panic, nothing on stdout).

use assert_cmd::Command;

/// The `stabound` binary under test.
pub fn stabound() -> Command {
    Command::cargo_bin("stabound").unwrap()
}

/// Runs `stabound ARGS` with `RAYON_NUM_THREADS=threads` (or the default when `None`),
/// asserts success and returns stdout.
pub fn stdout_with(args: &[&str], threads: Option<&str>) -> Vec<u8> {
    let mut cmd = stabound();
    if let Some(t) = threads {
        cmd.env("RAYON_NUM_THREADS", t);
    }
    let out = cmd.args(args).output().unwrap();
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out.stdout
}

/// Runs `stabound ARGS`, asserts success and returns stdout.
pub fn stdout(args: &[&str]) -> Vec<u8> {
    stdout_with(args, None)
}

/// Runs `stabound ARGS`, asserts success and parses stdout as JSON.
pub fn json(args: &[&str]) -> serde_json::Value {
    serde_json::from_slice(&stdout(args)).unwrap()
}

/// The header line and the rows (split at commas) of CSV output.
pub fn csv(out: &[u8]) -> (String, Vec<Vec<String>>) {
    let text = String::from_utf8(out.to_vec()).unwrap();
    // `#` lines are comments (the robust region says how it was found)
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    let header = lines.next().unwrap_or_default().to_string();
    let rows = lines
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect();
    (header, rows)
}

/// The rows of CSV output as numbers (every cell must be one).
pub fn csv_numbers(out: &[u8]) -> Vec<Vec<f64>> {
    csv(out)
        .1
        .iter()
        .map(|r| r.iter().map(|x| x.parse().unwrap()).collect())
        .collect()
}

/// Asserts that `stabound ARGS` is rejected as bad input: exit code 2, nothing on stdout,
/// exactly one line on stderr (clap's usage errors, which add a usage block, excepted when
/// `one_line` is false), and no panic. Returns stderr.
pub fn assert_bad_input(args: &[&str], one_line: bool) -> String {
    let out = stabound().args(args).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
    assert!(!err.contains("panicked"), "{args:?}: {err}");
    assert!(out.stdout.is_empty(), "{args:?}");
    if one_line {
        assert_eq!(err.trim_end().lines().count(), 1, "{args:?}: {err}");
    }
    err
}
