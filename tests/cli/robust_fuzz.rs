//! Fuzz-style CLI test: hundreds of malformed argument sets across every
//! command, each built from a small valid request plus one or two faults, so a missed check
//! would show up as exit 0 (or a panic) instead of exit 2. The generator is deterministic
//! (every single fault, then pairs of faults picked by a fixed linear congruential
//! sequence), so a failure reproduces exactly.

use crate::common::stabound;

/// A command's valid small request and the faults that each make it invalid. A fault is a
/// list of arguments appended to (and, for a flag already given, overriding) the request.
struct Case {
    base: &'static [&'static str],
    faults: Vec<Vec<&'static str>>,
}

/// Bad values for any number: not a number, not finite, empty, several.
const NOT_NUMBERS: [&str; 9] = [
    "nan", "NaN", "inf", "-inf", "1e999", "", "abc", "0x10", "1,2",
];
/// Bad LIST values: the above and malformed, inverted, empty or oversized ranges.
const BAD_LISTS: [&str; 14] = [
    "nan",
    "inf",
    "-inf",
    "1e999",
    "",
    "abc",
    "1,,2",
    "1:0:3",
    "0:1:0",
    "0:1",
    "0:1:x",
    "0:1:1e9",
    "0:1:2:3",
    "-1e308:1e308:3",
];
/// Output paths that cannot be written: missing directory, a directory, a pseudo-filesystem.
const BAD_PATHS: [&str; 3] = ["/nonexistent-dir/out.csv", "/", "/proc/stabound-out.csv"];

fn cases() -> Vec<Case> {
    let mut all = Vec::new();
    let mut f = Vec::new();
    for v in NOT_NUMBERS {
        for flag in ["--alpha", "--beta", "--delta", "--d", "--marginal-band"] {
            f.push(vec![flag, v]);
        }
    }
    for (flag, v) in [
        ("--delta", "-1"),
        ("--delta", "1e10"),
        ("--d", "-0.5"),
        ("--d", "501"),
        ("--marginal-band", "-1"),
        ("--marginal-band", "0.5"),
        ("--method", "magic"),
        ("--format", "xml"),
        ("--format", ""),
    ] {
        f.push(vec![flag, v]);
    }
    // physical units mixed with normalized ones, or invalid
    f.push(vec!["--mass", "1"]);
    for p in BAD_PATHS {
        f.push(vec!["-o", p]);
    }
    all.push(Case {
        base: &[
            "check", "--alpha", "0.1", "--beta", "0.3", "--delta", "0.5", "--d", "1",
        ],
        faults: f,
    });
    let physical_check: &[&str] = &[
        "check",
        "--mass",
        "0.1",
        "--period",
        "0.001",
        "--damping",
        "1",
        "--stiffness",
        "100",
        "--wall-damping",
        "1",
        "--delay-samples",
        "1",
    ];
    let mut f = Vec::new();
    for flag in ["--mass", "--period"] {
        for v in ["0", "-1", "nan", "inf"] {
            f.push(vec![flag, v]);
        }
    }
    for v in ["-1", "nan", "1e999"] {
        f.push(vec!["--damping", v]);
        f.push(vec!["--delay-samples", v]);
    }
    f.push(vec!["--delay-samples", "1e6"]);
    f.push(vec!["--delay", "0.001"]);
    all.push(Case {
        base: physical_check,
        faults: f,
    });

    // boundary: coarse tolerance so that a missed check would still finish quickly
    let mut f = Vec::new();
    for v in BAD_LISTS {
        f.push(vec!["--delta", v]);
        f.push(vec!["--d", v]);
    }
    for v in NOT_NUMBERS {
        f.push(vec!["--tol", v]);
    }
    for (flag, v) in [
        ("--delta", "-1"),
        ("--d", "-1"),
        ("--d", "1000"),
        ("--tol", "0"),
        ("--tol", "-1e-3"),
        ("--tol", "1"),
        ("--format", "xml"),
        ("--plane", "gamma-beta"),
        ("--method", "magic"),
        ("--alpha", "0.1"),
        ("--shard", "0/3"),
        ("--shard", "4/3"),
        ("--shard", "1/0"),
        ("--shard", "x"),
        ("--shard", "1/2/3"),
    ] {
        f.push(vec![flag, v]);
    }
    // more curves than a run computes (100,000)
    f.push(vec!["--delta", "0:1:100000", "--d", "0,1"]);
    f.push(vec!["--shard", "1/2", "--format", "json"]);
    f.push(vec!["--shard", "1/2", "--svg", "x.svg"]);
    f.push(vec!["--delta", "0:1:100000", "--d", "0:1:100000"]);
    for p in BAD_PATHS {
        f.push(vec!["-o", p]);
        f.push(vec!["--svg", p]);
    }
    all.push(Case {
        base: &["boundary", "--delta", "0.5", "--d", "1", "--tol", "1e-3"],
        faults: f,
    });
    let mut f = Vec::new();
    for v in ["-1", "nan", "", "1:0:2"] {
        f.push(vec!["--alpha", v]);
    }
    f.push(vec!["--delta", "1,1"]);
    f.push(vec!["--delta", "-1,1"]);
    f.push(vec!["--method", "exact"]);
    f.push(vec!["--alpha", "0:1:100000", "--d", "0,1"]);
    all.push(Case {
        base: &[
            "boundary",
            "--plane",
            "delta-beta",
            "--alpha",
            "0.1",
            "--d",
            "1",
            "--tol",
            "1e-3",
        ],
        faults: f,
    });

    // amax and table share their grid arguments
    for cmd in ["amax", "table"] {
        let mut f = Vec::new();
        for v in BAD_LISTS {
            f.push(vec!["--delta", v]);
            f.push(vec!["--d", v]);
        }
        for v in NOT_NUMBERS {
            f.push(vec!["--theta-tol", v]);
            f.push(vec!["--beta-min", v]);
            f.push(vec!["--beta-max", v]);
        }
        for (flag, v) in [
            ("--delta", "-1"),
            ("--d", "-1"),
            ("--theta-tol", "0"),
            ("--theta-tol", "1"),
            ("--format", "xml"),
            ("--shard", "0/1"),
            ("--shard", "3/2"),
            ("--mass", "0.1"),
            ("--delay", "0.001"),
        ] {
            f.push(vec![flag, v]);
        }
        f.push(vec!["--beta-min", "1", "--beta-max", "0"]);
        // more rows than a run computes (10^8 amax rows, 10^6 table nodes)
        f.push(vec!["--delta", "0:1:100000", "--d", "0:1:1001"]);
        f.push(vec!["--delta", "0:1:100000", "--d", "0:1:100000"]);
        for p in BAD_PATHS {
            f.push(vec!["-o", p]);
        }
        if cmd == "amax" {
            for v in ["0", "1.5", "-0.5", "nan"] {
                f.push(vec!["--margin", v]);
            }
            f.push(vec!["--shard", "1/2", "--format", "json"]);
            f.push(vec!["--svg", "/nonexistent-dir/x.svg"]);
        } else {
            f.push(vec!["--delta", "1,0"]);
            f.push(vec!["--d", "0,0"]);
            for fmt in ["json", "c", "rust"] {
                f.push(vec!["--shard", "1/2", "--format", fmt]);
            }
        }
        all.push(Case {
            base: if cmd == "amax" {
                &["amax", "--delta", "0.5", "--d", "1", "--theta-tol", "1e-6"]
            } else {
                &[
                    "table",
                    "--delta",
                    "0,0.5",
                    "--d",
                    "1",
                    "--theta-tol",
                    "1e-6",
                ]
            },
            faults: f,
        });
        let mut f = Vec::new();
        for flag in ["--mass", "--period"] {
            for v in ["0", "-1", "nan", ""] {
                f.push(vec![flag, v]);
            }
        }
        for v in ["-1", "nan", "1:0:2", ""] {
            f.push(vec!["--damping", v]);
            f.push(vec!["--delay-samples", v]);
        }
        f.push(vec!["--delay-samples", "600"]);
        f.push(vec!["--delay", "0.001"]);
        f.push(vec!["--delta", "0"]);
        all.push(Case {
            base: if cmd == "amax" {
                &[
                    "amax",
                    "--mass",
                    "0.1",
                    "--period",
                    "0.001",
                    "--damping",
                    "0,10",
                    "--delay-samples",
                    "1",
                    "--theta-tol",
                    "1e-6",
                ]
            } else {
                &[
                    "table",
                    "--mass",
                    "0.1",
                    "--period",
                    "0.001",
                    "--damping",
                    "0,10",
                    "--delay-samples",
                    "1",
                    "--theta-tol",
                    "1e-6",
                ]
            },
            faults: f,
        });
    }

    const SCENE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/data/scenes/phantom.toml");
    let mut f = Vec::new();
    for v in NOT_NUMBERS {
        f.push(vec!["--marginal-band", v]);
    }
    f.push(vec!["--marginal-band", "-0.1"]);
    f.push(vec!["--format", "xml"]);
    for p in BAD_PATHS {
        f.push(vec!["-o", p]);
    }
    all.push(Case {
        base: &["scene", SCENE],
        faults: f,
    });
    all.push(Case {
        base: &["scene"],
        faults: vec![
            vec!["/nonexistent-dir/scene.toml"],
            vec!["/"],
            vec![concat!(env!("CARGO_MANIFEST_DIR"), "/Cargo.toml")],
        ],
    });
    all
}

/// Minimal linear congruential generator (Knuth's MMIX constants): deterministic picks.
struct Lcg(u64);

impl Lcg {
    fn below(&mut self, n: usize) -> usize {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 33) % n as u64) as usize
    }
}

/// The request `base` with the faults applied: a fault `[flag, value]` replaces the value of
/// `flag` when `base` has it (so that the value is what is tested, not clap's refusal of a
/// repeated flag), else is appended; a one-element fault is a positional argument.
fn apply<'a>(base: &[&'a str], faults: &[&Vec<&'a str>]) -> Vec<&'a str> {
    let mut args = base.to_vec();
    for fault in faults {
        if fault.len() == 1 {
            args.push(fault[0]);
            continue;
        }
        for pair in fault.chunks(2) {
            match args.iter().position(|a| *a == pair[0]) {
                Some(i) if i + 1 < args.len() => args[i + 1] = pair[1],
                _ => args.extend_from_slice(pair),
            }
        }
    }
    args
}

fn assert_rejected(args: &[&str]) {
    let out = stabound().args(args).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
    assert!(!err.contains("panicked"), "{args:?}: {err}");
    assert!(out.stdout.is_empty(), "{args:?}");
    assert!(err.starts_with("error"), "{args:?}: {err}");
}

#[test]
fn malformed_arguments_exit_2_without_panic() {
    let cases = cases();
    let mut tried = 0;
    for c in &cases {
        for fault in &c.faults {
            assert_rejected(&apply(c.base, &[fault]));
            tried += 1;
        }
    }
    // pairs of faults of the same command, in a fixed pseudo-random order
    let mut rng = Lcg(0x5eed);
    for _ in 0..60 {
        let c = &cases[rng.below(cases.len())];
        let a = &c.faults[rng.below(c.faults.len())];
        let b = &c.faults[rng.below(c.faults.len())];
        assert_rejected(&apply(c.base, &[a, b]));
        tried += 1;
    }
    assert!(tried >= 200, "only {tried} argument sets");
    eprintln!("{tried} malformed argument sets rejected");
}

/// The size caps name the limit and the way out.
#[test]
fn oversized_requests_say_the_cap_and_suggest_shards() {
    let err = crate::common::assert_bad_input(
        &["amax", "--delta", "0:1:100000", "--d", "0:1:1001"],
        true,
    );
    assert!(
        err.contains("100000000") && err.contains("--shard"),
        "{err}"
    );
    let err = crate::common::assert_bad_input(
        &["boundary", "--delta", "0:1:100000", "--d", "0,1,2"],
        true,
    );
    assert!(
        err.contains("100000") && err.contains("--shard K/N, N >= 3"),
        "{err}"
    );
}
