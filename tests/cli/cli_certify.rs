//! `check --certify`: the certificate is written beside the report, the standalone checker
//! (`tools/verify_certificate.py`, Python's standard library only) accepts it, and what
//! cannot be certified writes nothing.

use std::path::Path;
use std::process::Command;

use crate::common::{assert_bad_input, stabound};

/// Runs the checker on `path`: its exit code and stdout.
pub(crate) fn verify(path: &Path) -> (i32, String) {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tools/verify_certificate.py");
    let out = Command::new("python3")
        .arg(script)
        .arg(path)
        .output()
        .expect("python3 runs the checker");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
    )
}

/// Stable, unstable and marginal walls, with integer and fractional delay: the checker
/// confirms each claim, and the report on stdout is the one without the flag.
#[test]
fn certificates_verify() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("cert.json");
    for (wall, verdict) in [
        (["0.1", "0.3", "0.5", "1"], "verified: stable"),
        (["3", "0.3", "0.5", "2.5"], "verified: unstable"),
        (["0", "0.3", "0.5", "1"], "verified: marginal"),
        (["1e300", "0", "0", "0"], "verified: unstable"),
    ] {
        let args = [
            "check", "--alpha", wall[0], "--beta", wall[1], "--delta", wall[2], "--d", wall[3],
        ];
        let plain = stabound().args(args).output().unwrap();
        let with = stabound()
            .args(args)
            .arg("--certify")
            .arg(&path)
            .output()
            .unwrap();
        assert!(with.status.success(), "{wall:?}");
        assert_eq!(plain.stdout, with.stdout, "{wall:?}");
        let (code, out) = verify(&path);
        assert_eq!(code, 0, "{wall:?}");
        assert!(out.starts_with(verdict), "{wall:?}: {out}");
        // one changed character is rejected
        let text = std::fs::read_to_string(&path).unwrap();
        let i = text.find("\"mid\": \"0x1.").unwrap() + 12;
        let ch = if &text[i..=i] == "1" { "2" } else { "1" };
        std::fs::write(&path, format!("{}{ch}{}", &text[..i], &text[i + 1..])).unwrap();
        assert_eq!(verify(&path).0, 1, "{wall:?}");
    }
}

/// A loop with elements (hand, low-pass velocity filter) is certified too: the checker
/// confirms the claim, which is the verdict of the report; a second-order filter that makes
/// the wall unstable is certified unstable.
#[test]
fn element_certificates_verify() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("cert.json");
    let device = [
        "check",
        "--mass",
        "1",
        "--period",
        "0.001",
        "--damping",
        "0.5",
        "--delay-samples",
        "1.5",
        "--wall-damping",
        "5",
        "--hand-mass",
        "0.3",
        "--velocity-filter-cutoff",
        "30",
    ];
    for (stiffness, order, verdict) in [
        ("1000", "1", "verified: stable"),
        ("30000", "2", "verified: unstable"),
    ] {
        let mut args: Vec<&str> = device.to_vec();
        args.extend(["--stiffness", stiffness, "--velocity-filter-order", order]);
        let out = stabound()
            .args(&args)
            .arg("--certify")
            .arg(&path)
            .output()
            .unwrap();
        assert!(out.status.success(), "{args:?}");
        let report = String::from_utf8_lossy(&out.stdout);
        let (code, checked) = verify(&path);
        assert_eq!(code, 0, "{args:?}");
        assert!(checked.starts_with(verdict), "{args:?}: {checked}");
        assert!(
            report.starts_with(&verdict["verified: ".len()..]),
            "{report}"
        );
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(
            text.contains("\"elements\": [\"hand\", \"filter\"]"),
            "{text}"
        );
    }
}

/// A batch is refused as bad input, before any file is written.
#[test]
fn certify_refusals() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("c.json");
    let p = path.to_str().unwrap();
    assert_bad_input(&["check", "--batch", "-", "--certify", p], false);
    assert!(!path.exists());
}

/// A stable wall at a delay beyond what `f64` intervals decide (d = 60) is refused with exit
/// status 1, a message that names the cap and its cause, and no file.
#[test]
fn long_delay_refusal_names_the_cap() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("c.json");
    let out = stabound()
        .args([
            "check",
            "--alpha",
            "0.001",
            "--beta",
            "0.02",
            "--delta",
            "0.5",
            "--d",
            "60",
            "--certify",
        ])
        .arg(&path)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("delays above about 35 samples"), "{err}");
    assert!(err.contains("degree 6 of 63"), "{err}");
    assert!(!path.exists());
}

/// A box of walls: well inside the stable region it is certified stable for every wall and
/// the checker agrees; across the boundary it is not proved (exit status 4 with
/// `--exit-status`); without `--certify` it is refused as bad input.
#[test]
fn box_certificates() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("box.json");
    let run = |alpha: &str, beta: &str, extra: &[&str]| {
        stabound()
            .args([
                "check", "--alpha", alpha, "--beta", beta, "--delta", "0.5", "--d", "1",
            ])
            .args(extra)
            .arg("--certify")
            .arg(&path)
            .output()
            .unwrap()
    };
    let out = run("0.1..0.12", "0.25..0.3", &[]);
    assert!(out.status.success());
    let report = String::from_utf8_lossy(&out.stdout);
    assert!(
        report.contains("verdict: stable for every wall of the box"),
        "{report}"
    );
    let (code, checked) = verify(&path);
    assert_eq!(code, 0);
    assert!(checked.starts_with("verified: stable for every wall of the box"));
    let out = run(
        "0.1..1.5",
        "0.25..0.3",
        &["--certify-leaves", "100", "--exit-status"],
    );
    assert_eq!(out.status.code(), Some(4));
    let report = String::from_utf8_lossy(&out.stdout);
    assert!(report.contains("not proved for the whole box"), "{report}");
    assert!(report.contains("at most 100 boxes"), "{report}");
    assert!(verify(&path).1.starts_with("verified: not proved"));
    std::fs::remove_file(&path).unwrap();
    assert_bad_input(
        &[
            "check", "--alpha", "0.1..0.2", "--beta", "0.3", "--delta", "0.5", "--d", "1",
        ],
        false,
    );
    assert!(!path.exists());
}
