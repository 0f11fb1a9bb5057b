//! README's command samples, run: every `stabound ...` line of a `sh` block must succeed,
//! and every `console` block must print what README shows.
//!
//! A `console` block holds `$ COMMAND` lines, each followed by the text the command prints
//! (stdout, then stderr); a line `...` stands for any number of lines.
//! Commands run through `sh -c` in a fresh directory that has the repository's `data/`, with
//! the freshly built `stabound` first on `PATH`, so files they write land there.

use std::path::{Path, PathBuf};
use std::process::Command;

fn readme() -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("README.md");
    std::fs::read_to_string(path).unwrap()
}

/// The fenced blocks of `text` as (info string, body lines); a fence may be indented (inside
/// a list item), and its body loses the same indentation.
fn blocks(text: &str) -> Vec<(String, Vec<String>)> {
    let mut out = Vec::new();
    let mut open: Option<(String, usize, Vec<String>)> = None;
    for line in text.lines() {
        let indent = line.len() - line.trim_start().len();
        let fence = line.trim_start().strip_prefix("```");
        match (&mut open, fence) {
            (None, Some(info)) => open = Some((info.trim().to_string(), indent, Vec::new())),
            (Some(_), Some(_)) => out.extend(open.take().map(|(info, _, body)| (info, body))),
            (Some((_, pad, body)), None) => {
                let cut = (*pad).min(indent);
                body.push(line[cut..].to_string());
            }
            (None, None) => {}
        }
    }
    out
}

/// A directory to run samples in, with `data/` from the repository.
fn sandbox() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("data");
    std::os::unix::fs::symlink(data, dir.path().join("data")).unwrap();
    dir
}

fn bin_dir() -> PathBuf {
    let bin = assert_cmd::cargo::cargo_bin("stabound");
    bin.parent().unwrap().to_path_buf()
}

fn run(cmd: &str, dir: &Path) -> std::process::Output {
    let path = format!(
        "{}:{}",
        bin_dir().display(),
        std::env::var("PATH").unwrap_or_default()
    );
    Command::new("sh")
        .arg("-c")
        .arg(cmd)
        .current_dir(dir)
        .env("PATH", path)
        .output()
        .unwrap()
}

/// Joins shell lines ending in `\` with the next.
fn commands(body: &[String]) -> Vec<String> {
    let mut out = Vec::new();
    let mut cur = String::new();
    for line in body {
        if let Some(head) = line.strip_suffix('\\') {
            cur.push_str(head);
            cur.push(' ');
        } else {
            cur.push_str(line);
            out.push(std::mem::take(&mut cur));
        }
    }
    out
}

/// Whether `got` matches `want`, where a `want` line `...` matches any run of lines.
fn matches(want: &[&str], got: &[&str]) -> bool {
    match want.split_first() {
        None => got.is_empty(),
        Some((&"...", rest)) => (0..=got.len()).any(|k| matches(rest, &got[k..])),
        Some((w, rest)) => got
            .split_first()
            .is_some_and(|(g, grest)| g == w && matches(rest, grest)),
    }
}

#[test]
fn sh_samples_succeed() {
    let dir = sandbox();
    let mut ran = 0;
    for (info, body) in blocks(&readme()) {
        if info != "sh" {
            continue;
        }
        for cmd in commands(&body) {
            if !cmd.trim_start().starts_with("stabound ") {
                continue;
            }
            let out = run(&cmd, dir.path());
            assert!(
                out.status.success(),
                "README sample failed: {cmd}\n{}",
                String::from_utf8_lossy(&out.stderr)
            );
            ran += 1;
        }
    }
    assert!(ran >= 10, "only {ran} README samples found");
}

#[test]
fn console_samples_print_what_readme_shows() {
    let dir = sandbox();
    let mut ran = 0;
    for (info, body) in blocks(&readme()) {
        if info != "console" {
            continue;
        }
        let mut i = 0;
        while i < body.len() {
            let Some(cmd) = body[i].strip_prefix("$ ") else {
                panic!("a console block must start with `$ COMMAND`: {:?}", body[i]);
            };
            let end = (i + 1..body.len())
                .find(|&j| body[j].starts_with("$ "))
                .unwrap_or(body.len());
            let want: Vec<&str> = body[i + 1..end].iter().map(String::as_str).collect();
            let out = run(cmd, dir.path());
            let text = String::from_utf8_lossy(&[out.stdout, out.stderr].concat()).into_owned();
            let got: Vec<&str> = text.lines().collect();
            assert!(
                matches(&want, &got),
                "README shows for `{cmd}`:\n{}\nbut it prints:\n{text}",
                want.join("\n")
            );
            ran += 1;
            i = end;
        }
    }
    assert!(ran >= 4, "only {ran} README console samples found");
}

#[test]
fn elision_matches_runs_of_lines() {
    assert!(matches(&["a", "...", "d"], &["a", "b", "c", "d"]));
    assert!(matches(&["a", "..."], &["a"]));
    assert!(!matches(&["a", "...", "d"], &["a", "b"]));
    assert!(!matches(&["a"], &["a", "b"]));
}

/// README's word for `--format json` on a table ("a JSON array, one object per row") is what
/// is written: each sample whose comment says so prints a JSON array with one object per
/// row of the same command's CSV, keyed by its header; no line says "one JSON object per
/// row" (one object per line, which is not what is written).
#[test]
fn json_samples_are_arrays_of_the_csv_rows() {
    let text = readme();
    assert!(!text.contains("one JSON object per row"));
    let dir = sandbox();
    let mut ran = 0;
    for (info, body) in blocks(&text) {
        if info != "sh" {
            continue;
        }
        for line in commands(&body) {
            let Some((cmd, comment)) = line.split_once(" # ") else {
                continue;
            };
            if !comment.contains("a JSON array, one object per row") {
                continue;
            }
            let cmd = cmd.trim();
            assert!(cmd.contains("--format json"), "{line}");
            let json = run(cmd, dir.path());
            assert!(json.status.success(), "{cmd}");
            let value: serde_json::Value = serde_json::from_slice(&json.stdout).unwrap();
            let rows = value
                .as_array()
                .unwrap_or_else(|| panic!("not an array: {cmd}"));
            let csv = run(&cmd.replace("--format json", ""), dir.path());
            assert!(csv.status.success(), "{cmd}");
            let csv = String::from_utf8(csv.stdout).unwrap();
            let mut lines = csv.lines();
            let mut header: Vec<&str> = lines.next().unwrap().split(',').collect();
            header.sort_unstable();
            assert_eq!(rows.len(), lines.count(), "{cmd}");
            for row in rows {
                let mut keys: Vec<&str> = row
                    .as_object()
                    .unwrap_or_else(|| panic!("a row is not an object: {cmd}"))
                    .keys()
                    .map(String::as_str)
                    .collect();
                keys.sort_unstable();
                assert_eq!(keys, header, "{cmd}");
            }
            ran += 1;
        }
    }
    assert!(ran >= 1, "no README sample says what --format json writes");
}
