//! End-to-end tests of `stabound completions` and `stabound man`.

use crate::common::stdout;

/// `stabound completions SHELL` and `stabound man` come from the parser's own definitions:
/// every subcommand and a sample of flags appear, bash accepts the script's syntax, and the
/// man page is roff that names every subcommand.
#[test]
fn completions_and_man_page_follow_the_arguments() {
    let subcommands = [
        "boundary",
        "amax",
        "table",
        "check",
        "scene",
        "step",
        "figure",
        "passivity",
        "completions",
        "man",
    ];
    for shell in ["bash", "zsh", "fish", "elvish", "powershell"] {
        let out = stdout(&["completions", shell]);
        let text = String::from_utf8(out).unwrap();
        for s in subcommands {
            assert!(text.contains(s), "{shell}: {s}");
        }
        for flag in [
            "marginal-band",
            "exit-status",
            "figures-dir",
            "delay-samples",
        ] {
            assert!(text.contains(flag), "{shell}: {flag}");
        }
    }
    let bash = stdout(&["completions", "bash"]);
    let dir = tempfile::tempdir().unwrap();
    let script = dir.path().join("stabound.bash");
    std::fs::write(&script, &bash).unwrap();
    let syntax = std::process::Command::new("bash")
        .arg("-n")
        .arg(&script)
        .output();
    if let Ok(o) = syntax {
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    let man = String::from_utf8(stdout(&["man"])).unwrap();
    assert!(
        man.starts_with(".ie") || man.contains(".TH stabound"),
        "{}",
        &man[..200]
    );
    assert!(man.contains(".TH stabound"));
    for s in subcommands {
        assert!(man.contains(s), "man: {s}");
    }
    // a bad shell is a usage error
    crate::common::assert_bad_input(&["completions", "tcsh"], false);
}
