//! Output safety end to end: what happens to symbolic links, devices, FIFOs, read-only and
//! same-file outputs, a closed stdout, kills and file size limits, umask; inputs that once
//! hung or wrote `inf`; forged names in text reports. Every case checks the exit code and
//! that no `.stabound-*.part` file is left.

use std::os::unix::fs::{FileTypeExt, PermissionsExt};
use std::os::unix::process::ExitStatusExt;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

fn bin() -> PathBuf {
    assert_cmd::cargo::cargo_bin("stabound")
}

/// A quick run that writes data (`-o`) and a picture (`--svg`).
const QUICK: [&str; 5] = ["amax", "--delta", "0.5,1", "--d", "1"];

fn run(args: &[&str], extra: &[&Path]) -> Output {
    Command::new(bin())
        .args(args)
        .args(extra)
        .stdin(Stdio::null())
        .output()
        .unwrap()
}

/// Runs `stabound ARGS` through `sh -c "PREFIX; exec stabound ARGS SUFFIX"`.
fn via_sh(prefix: &str, args: &[&str], suffix: &str) -> Output {
    Command::new("sh")
        .arg("-c")
        .arg(sh_script(prefix, args, suffix))
        .output()
        .unwrap()
}

/// The script of [`via_sh`].
fn sh_script(prefix: &str, args: &[&str], suffix: &str) -> String {
    let quoted: Vec<String> = args.iter().map(|a| format!("'{a}'")).collect();
    format!(
        "{prefix}; exec '{}' {} {suffix}",
        bin().display(),
        quoted.join(" ")
    )
}

/// How long a run in [`no_memory_for_threads_is_exit_1`] may take before it counts as hung:
/// a successful one takes a few milliseconds, so a minute is never reached on a loaded
/// machine unless the run waits forever.
const HANG: std::time::Duration = std::time::Duration::from_secs(60);

/// [`via_sh`], killing the run (SIGKILL) when it has not ended within `limit`.
fn via_sh_within(prefix: &str, args: &[&str], limit: std::time::Duration) -> Output {
    let mut sh = Command::new("sh");
    sh.arg("-c")
        .arg(sh_script(prefix, args, ""))
        .stdin(Stdio::null());
    assert_cmd::Command::from_std(sh)
        .timeout(limit)
        .output()
        .unwrap()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Names of `.stabound-*` files anywhere in `dir` (one level of subdirectories).
fn parts(dir: &Path) -> Vec<String> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        let name = p.file_name().unwrap().to_string_lossy().into_owned();
        if name.starts_with(".stabound-") {
            out.push(p.display().to_string());
        }
        if p.is_dir() && !p.is_symlink() {
            out.extend(parts(&p));
        }
    }
    out
}

fn is_root() -> bool {
    // the effective uid is what counts for mknod; `id -u` prints it
    Command::new("id")
        .arg("-u")
        .output()
        .is_ok_and(|o| o.stdout == b"0\n")
}

fn mkfifo(p: &Path) {
    assert!(Command::new("mkfifo").arg(p).status().unwrap().success());
}

/// A copy of /dev/null made with mknod (root only): `-o` onto it writes into the device and
/// leaves the node a character device, where it used to be replaced by a regular file.
#[test]
fn device_node_output_stays_a_device() {
    if !is_root() {
        eprintln!("skipped: mknod needs root");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let null = dir.path().join("null");
    assert!(
        Command::new("mknod")
            .arg(&null)
            .args(["c", "1", "3"])
            .status()
            .unwrap()
            .success()
    );
    let o = run(&QUICK, &[Path::new("-o"), &null]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let m = std::fs::symlink_metadata(&null).unwrap();
    assert!(m.file_type().is_char_device(), "the node was replaced");
    assert!(parts(dir.path()).is_empty());
}

/// `-o` onto a symbolic link writes the file it points to and keeps the link.
#[test]
fn symlink_output_writes_through() {
    let dir = tempfile::tempdir().unwrap();
    let pointee = dir.path().join("real.csv");
    let link = dir.path().join("link.csv");
    std::fs::write(&pointee, "old\n").unwrap();
    std::os::unix::fs::symlink("real.csv", &link).unwrap();
    let o = run(&QUICK, &[Path::new("-o"), &link]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(std::fs::symlink_metadata(&link).unwrap().is_symlink());
    let text = std::fs::read_to_string(&pointee).unwrap();
    assert!(
        text.starts_with("delta,d,alpha_max,beta_at_max\n"),
        "{text}"
    );
    // a dangling link gets the file it points to created
    let dangling = dir.path().join("dangling.csv");
    std::os::unix::fs::symlink("new.csv", &dangling).unwrap();
    let o = run(&QUICK, &[Path::new("-o"), &dangling]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(dir.path().join("new.csv").is_file());
    assert!(parts(dir.path()).is_empty());
}

/// A read-only file is refused before any work (exit 2) and left as it was, even for root.
#[test]
fn read_only_output_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let ro = dir.path().join("ro.csv");
    std::fs::write(&ro, "keep\n").unwrap();
    std::fs::set_permissions(&ro, std::fs::Permissions::from_mode(0o444)).unwrap();
    let o = run(&QUICK, &[Path::new("-o"), &ro]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("read-only"), "{}", stderr(&o));
    assert_eq!(std::fs::read(&ro).unwrap(), b"keep\n");
}

/// With stdout closed the data cannot go anywhere: exit 1 with a message, where it used to
/// exit 0 with nothing written. With `-o` a closed stdout does not matter.
#[test]
fn closed_stdout_is_an_error() {
    let o = via_sh("true", &QUICK, ">&-");
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).contains("stdout is closed"), "{}", stderr(&o));
    let dir = tempfile::tempdir().unwrap();
    let f = dir.path().join("x.csv");
    let mut args = QUICK.to_vec();
    let fs = f.to_str().unwrap();
    args.extend(["-o", fs]);
    let o = via_sh("true", &args, ">&-");
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(std::fs::read_to_string(&f).unwrap().starts_with("delta,"));
}

/// Two outputs into one file, through different spellings, and an output onto the input
/// scene, are refused before any work.
#[test]
fn same_file_outputs_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::os::unix::fs::symlink("x.svg", d.join("l.svg")).unwrap();
    let spellings = [
        (d.join("x.svg"), d.join("x.svg")),
        (d.join("x.svg"), d.join(".").join("x.svg")),
        (d.join("x.svg"), d.join("l.svg")),
    ];
    for (a, b) in spellings {
        let o = run(&QUICK, &[Path::new("--svg"), &a, Path::new("-o"), &b]);
        assert_eq!(o.status.code(), Some(2), "{a:?} {b:?}: {}", stderr(&o));
        assert!(stderr(&o).contains("same file"), "{}", stderr(&o));
        assert!(!d.join("x.svg").exists());
    }
    let scene = d.join("s.toml");
    let original =
        std::fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join("data/scenes/phantom.toml"))
            .unwrap();
    std::fs::write(&scene, &original).unwrap();
    let o = run(
        &["scene"],
        &[&scene, Path::new("-o"), &d.join(".").join("s.toml")],
    );
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert_eq!(std::fs::read(&scene).unwrap(), original);
    assert!(parts(d).is_empty());
}

/// New files honour the umask, as a shell redirect does; replaced files keep their mode.
#[test]
fn new_files_honour_the_umask() {
    let dir = tempfile::tempdir().unwrap();
    let mode = |p: &Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o777;
    for (umask, want) in [("077", 0o600), ("022", 0o644), ("002", 0o664)] {
        let f = dir.path().join(format!("u{umask}.csv"));
        let mut args = QUICK.to_vec();
        let fs = f.to_str().unwrap();
        args.extend(["-o", fs]);
        let o = via_sh(&format!("umask {umask}"), &args, "");
        assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
        assert_eq!(mode(&f), want, "umask {umask}");
        std::fs::set_permissions(&f, std::fs::Permissions::from_mode(0o640)).unwrap();
        let o = via_sh("umask 000", &args, "");
        assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
        assert_eq!(mode(&f), 0o640, "replaced file, umask {umask}");
    }
}

/// A file size limit (`ulimit -f`) ends the run with an error message (exit 1) and no file,
/// where SIGXFSZ used to kill it and leave a `.part` file.
#[test]
fn file_size_limit_is_an_error_and_leaves_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let f = dir.path().join("b.csv");
    let fs = f.to_str().unwrap();
    // about 4 MB of CSV against a 64 KiB limit (ulimit -f counts 1024-byte blocks in dash
    // and bash alike)
    let args = ["boundary", "--delta", "0.5,1", "--d", "1,2", "-o", fs];
    let o = via_sh("ulimit -f 64", &args, "");
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).contains("File too large"), "{}", stderr(&o));
    assert!(!f.exists());
    assert!(parts(dir.path()).is_empty(), "{:?}", parts(dir.path()));
}

/// SIGKILL at 20 moments spread over a run writing megabytes, most of them late, when the
/// output is being written: never a `.part` file, and the old output either untouched or
/// wholly replaced.
#[test]
fn sigkill_leaves_no_partial_file() {
    let dir = tempfile::tempdir().unwrap();
    let f = dir.path().join("b.csv");
    let args = [
        "boundary", "--delta", "0:1:8", "--d", "0,1", "--tol", "1e-8",
    ];
    let start = std::time::Instant::now();
    let whole = {
        let o = run(&args, &[Path::new("-o"), &f]);
        assert!(o.status.success(), "{}", stderr(&o));
        std::fs::read(&f).unwrap()
    };
    let full = start.elapsed();
    for k in 0..20 {
        let frac = 0.3 + 0.04 * k as f64;
        std::fs::write(&f, b"old\n").unwrap();
        let mut child = Command::new(bin())
            .args(args)
            .arg("-o")
            .arg(&f)
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        std::thread::sleep(full.mul_f64(frac));
        let _ = child.kill();
        let _ = child.wait();
        let now = std::fs::read(&f).unwrap();
        assert!(
            now == b"old\n" || now == whole,
            "{} bytes after SIGKILL at {frac:.2} of the run",
            now.len()
        );
        // The one leftover a SIGKILL can cause: killed between linking the finished file
        // under `.stabound-PID-N.part` and renaming it over the old one (microseconds; a
        // loaded machine can deschedule the process right there). It is then a complete
        // copy of the new output, never a partial one; anything else fails.
        for p in parts(dir.path()) {
            let name = Path::new(&p)
                .file_name()
                .unwrap()
                .to_string_lossy()
                .into_owned();
            let linked = name
                .strip_prefix(".stabound-")
                .and_then(|r| r.strip_suffix(".part"))
                .is_some_and(|r| r.split('-').all(|n| n.parse::<u64>().is_ok()));
            assert!(
                linked && std::fs::read(&p).unwrap() == whole,
                "after SIGKILL at {frac:.2} of the run: {p} is left"
            );
            std::fs::remove_file(&p).unwrap();
        }
    }
}

/// Output paths are checked before any work, in every subcommand (exit 2, quickly).
#[test]
fn output_paths_checked_before_work() {
    let dir = tempfile::tempdir().unwrap();
    let afile = dir.path().join("afile");
    std::fs::write(&afile, "x").unwrap();
    let cases: Vec<Vec<String>> = vec![
        "step --mass 1 --period 0.001 --delay-samples 1 --damping 0 --stiffness 100 -o /nonexistent/x.csv",
        "step --mass 1 --period 0.001 --delay-samples 1 --damping 0 --stiffness 100 --svg /nonexistent/x.svg",
        "check --alpha 0.1 --beta 0.3 --delta 0.5 --d 1 -o /nonexistent/x",
        "table --delta 0,1 --d 1 -o /nonexistent/x",
        "boundary --delta 0.5 --d 1 --svg /nonexistent/x.svg",
        "amax --delta 0.5 --d 1 -o /",
    ]
    .into_iter()
    .map(|s| s.split(' ').map(String::from).collect())
    .chain([vec![
        "figure".to_string(),
        "5".into(),
        "--output-dir".into(),
        afile.display().to_string(),
    ]])
    .collect();
    for args in cases {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let o = run(&args, &[]);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        assert_eq!(stderr(&o).lines().count(), 1, "{args:?}: {}", stderr(&o));
    }
}

/// A scene that is a FIFO or a device is refused at once (it used to block forever or read
/// gigabytes).
#[test]
fn scene_input_must_be_a_regular_file() {
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("s.toml");
    mkfifo(&fifo);
    for p in [fifo.as_path(), Path::new("/dev/zero")] {
        let o = run(&["scene"], &[p]);
        assert_eq!(o.status.code(), Some(2), "{p:?}: {}", stderr(&o));
        assert!(stderr(&o).contains("not a regular file"), "{}", stderr(&o));
    }
}

/// Physical units whose conversion overflows are refused; no `inf` reaches the data.
#[test]
fn overflowing_physical_units_are_refused() {
    let grid = [
        "--mass",
        "1e300",
        "--period",
        "1e-12",
        "--damping",
        "0,1",
        "--delay-samples",
        "1",
    ];
    for (cmd, format) in [
        ("table", "c"),
        ("table", "csv"),
        ("amax", "csv"),
        ("amax", "json"),
    ] {
        let mut args = vec![cmd, "--format", format];
        args.extend(grid);
        let o = run(&args, &[]);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        assert!(o.stdout.is_empty(), "{args:?}");
        assert!(stderr(&o).contains("not a finite number"), "{}", stderr(&o));
    }
}

/// A wall name carrying a newline, quotes and a terminal escape stays on its own line,
/// escaped: it cannot add a line that reads as another wall's verdict.
#[test]
fn forged_wall_name_is_escaped() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("forge.toml");
    std::fs::write(
        &scene,
        "[[device]]\nname = \"d\"\nmass_kg = 0.1\nperiod_s = 0.001\ndamping_Ns_per_m = 0\n\
         delay_samples = 1\n[[device.wall]]\n\
         name = \"w\\\": unstable\\n\\n  wall \\\"x\\\": stable\\u001b[1A\\r\"\n\
         stiffness_N_per_m = 1e6\ndamping_Ns_per_m = 0\n",
    )
    .unwrap();
    let o = run(&["scene"], &[&scene]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let text = String::from_utf8(o.stdout).unwrap();
    assert!(!text.contains('\x1b') && !text.contains('\r'), "{text:?}");
    let walls: Vec<&str> = text
        .lines()
        .filter(|l| l.trim_start().starts_with("wall "))
        .collect();
    // K = 1e6 N/m with m = 0.1 kg, T = 1 ms is alpha = 10, far beyond alpha_max (< 1 at d = 1)
    assert_eq!(walls.len(), 1, "{text}");
    assert!(walls[0].ends_with(": unstable"), "{}", walls[0]);
    assert!(walls[0].contains("\\n"), "{}", walls[0]);
}

/// Too little memory for the worker threads is a clean error (exit 1), not a panic and
/// not a hang.
///
/// Where that window lies depends on the size of the binary and of the C library: some
/// 14,000 to 22,000 KiB with the PNG/PDF renderers and their font (measured). Below it the
/// loader, the C library or the Rust runtime itself gives up (glibc can abort while registering
/// a thread's destructors, the runtime while allocating the main thread's signal stack, before
/// any of our code runs); above it the run succeeds. So a range of limits
/// is tried: at none may the binary panic or hang, and at one at least the thread error must
/// be the clean exit 1. A worker thread the runtime could not give its signal stack used to
/// panic and, with `RUST_BACKTRACE` set, hang the run on the runtime's own output lock.
#[test]
fn no_memory_for_threads_is_exit_1() {
    let mut clean_error = false;
    for kib in (11_000..=26_000).step_by(500) {
        let o = via_sh_within(&format!("ulimit -v {kib}"), &QUICK, HANG);
        // a run stopped by the timeout was killed by a signal, with no exit code
        assert!(
            o.status.code().is_some() || o.status.signal() != Some(9),
            "ulimit -v {kib}: no answer in {HANG:?}: {}",
            stderr(&o)
        );
        let err = stderr(&o);
        // the Rust runtime's own start-up (the signal stack of the main thread) can fail
        // before main, as the loader can: no code of ours has run
        let runtime_start = err.contains("fatal runtime error: initialization")
            || (err.contains("thread 'main'")
                && err.contains("failed to allocate an alternative stack"));
        if runtime_start {
            continue;
        }
        assert!(!err.contains("panicked"), "ulimit -v {kib}: {err}");
        assert_ne!(o.status.code(), Some(101), "ulimit -v {kib}: {err}");
        clean_error |= o.status.code() == Some(1);
    }
    assert!(
        clean_error,
        "no limit from 11,000 to 20,000 KiB gave the clean exit 1"
    );
}

/// An unstable step response growing to 1e305 is drawn (it used to hang the SVG forever).
#[test]
fn unstable_step_response_draws() {
    let dir = tempfile::tempdir().unwrap();
    let svg = dir.path().join("st.svg");
    let csv = dir.path().join("st.csv");
    let args = "step --mass 0.1 --period 0.001 --delay-samples 1 --damping 0 --stiffness 1e5 --duration 2 --points-per-period 1";
    let args: Vec<&str> = args.split(' ').collect();
    let o = run(&args, &[Path::new("--svg"), &svg, Path::new("-o"), &csv]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(std::fs::read_to_string(&svg).unwrap().contains("<svg"));
}

/// The kinds of file an output can be pointed at in [`adversarial_outputs`].
#[derive(Debug, Clone, Copy, PartialEq)]
enum Kind {
    New,
    Existing,
    LinkToExisting,
    Dangling,
    ReadOnly,
    FifoNoReader,
    DevNullCopy,
    Directory,
    MissingDir,
    /// The same file as the other output (a second spelling of its path).
    SameAsOther,
}

const KINDS: [Kind; 10] = [
    Kind::New,
    Kind::Existing,
    Kind::LinkToExisting,
    Kind::Dangling,
    Kind::ReadOnly,
    Kind::FifoNoReader,
    Kind::DevNullCopy,
    Kind::Directory,
    Kind::MissingDir,
    Kind::SameAsOther,
];

/// Makes a path of `kind` named `name` in `dir`; `None` when the kind needs root and this
/// is not root.
fn make(dir: &Path, name: &str, kind: Kind) -> Option<PathBuf> {
    let p = dir.join(name);
    match kind {
        Kind::New | Kind::SameAsOther => {}
        Kind::Existing => std::fs::write(&p, "old\n").unwrap(),
        Kind::LinkToExisting => {
            std::fs::write(dir.join(format!("{name}.real")), "old\n").unwrap();
            std::os::unix::fs::symlink(format!("{name}.real"), &p).unwrap();
        }
        Kind::Dangling => std::os::unix::fs::symlink(format!("{name}.missing"), &p).unwrap(),
        Kind::ReadOnly => {
            std::fs::write(&p, "old\n").unwrap();
            std::fs::set_permissions(&p, std::fs::Permissions::from_mode(0o444)).unwrap();
        }
        Kind::FifoNoReader => mkfifo(&p),
        Kind::DevNullCopy => {
            if !is_root() {
                return None;
            }
            let ok = Command::new("mknod")
                .arg(&p)
                .args(["c", "1", "3"])
                .status()
                .unwrap()
                .success();
            assert!(ok);
        }
        Kind::Directory => std::fs::create_dir(&p).unwrap(),
        Kind::MissingDir => return Some(dir.join("missing").join(name)),
    }
    Some(p)
}

/// Seeded random pairs of output kinds for `-o` and `--svg` (and a closed stdout), with the
/// exit code each must give and the state of the files afterwards: refused kinds exit 2 and
/// leave their file as it was, symbolic links stay links, devices stay devices, and no
/// `.part` file is ever left. Bounded: 60 runs of a command of a few milliseconds.
#[test]
fn adversarial_outputs() {
    // SplitMix64, seeded: the same cases on every run
    let mut state: u64 = 0x05ee_d0f0_u64;
    let mut next = move || {
        state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        (z ^ (z >> 31)) as usize
    };
    let refused = |k: Kind| {
        matches!(
            k,
            Kind::ReadOnly | Kind::FifoNoReader | Kind::Directory | Kind::MissingDir
        )
    };
    let mut runs = 0;
    for case in 0..60 {
        let dir = tempfile::tempdir().unwrap();
        let ko = KINDS[next() % KINDS.len()];
        let mut ks = KINDS[next() % KINDS.len()];
        if ko == Kind::SameAsOther {
            ks = if ks == Kind::SameAsOther {
                Kind::New
            } else {
                ks
            };
        }
        let stdout_closed = next() % 4 == 0;
        let use_o = next() % 5 != 0;
        let (Some(po), Some(ps)) = (
            if ko == Kind::SameAsOther {
                Some(PathBuf::new())
            } else {
                make(dir.path(), "o.csv", ko)
            },
            if ks == Kind::SameAsOther {
                Some(PathBuf::new())
            } else {
                make(dir.path(), "p.svg", ks)
            },
        ) else {
            continue;
        };
        // a second spelling of the other output's path
        let po = if ko == Kind::SameAsOther {
            ps.parent().unwrap().join(".").join(ps.file_name().unwrap())
        } else {
            po
        };
        let ps = if ks == Kind::SameAsOther {
            po.parent().unwrap().join(".").join(po.file_name().unwrap())
        } else {
            ps
        };
        let (ko, use_o) = if ks == Kind::SameAsOther {
            (ko, true)
        } else {
            (ko, use_o || ko == Kind::SameAsOther)
        };
        let mut args: Vec<String> = QUICK.iter().map(|s| s.to_string()).collect();
        args.extend(["--svg".into(), ps.display().to_string()]);
        if use_o {
            args.extend(["-o".into(), po.display().to_string()]);
        }
        let argv: Vec<&str> = args.iter().map(String::as_str).collect();
        let o = via_sh(
            "true",
            &argv,
            if stdout_closed { ">&-" } else { ">/dev/null" },
        );
        // the other output's kind decides for a second spelling
        let eff = |k: Kind, other: Kind| if k == Kind::SameAsOther { other } else { k };
        let (eo, es) = (eff(ko, ks), eff(ks, ko));
        let same = use_o && (ko == Kind::SameAsOther || ks == Kind::SameAsOther);
        // refused kinds, and the same file twice (harmless only for a character device)
        let bad = (use_o && refused(eo)) || refused(es) || (same && eo != Kind::DevNullCopy);
        let want = if bad {
            2
        } else if !use_o && stdout_closed {
            1
        } else {
            0
        };
        assert_eq!(
            o.status.code(),
            Some(want),
            "case {case}: -o {ko:?} ({use_o}), --svg {ks:?}, stdout closed {stdout_closed}: {}",
            stderr(&o)
        );
        assert!(!stderr(&o).contains("panicked"), "{}", stderr(&o));
        assert!(
            parts(dir.path()).is_empty(),
            "case {case}: {:?}",
            parts(dir.path())
        );
        for (p, k, used) in [(&po, eo, use_o), (&ps, es, true)] {
            if !used {
                continue;
            }
            let m = std::fs::symlink_metadata(p).ok();
            match k {
                Kind::ReadOnly => assert_eq!(std::fs::read(p).unwrap(), b"old\n"),
                Kind::LinkToExisting | Kind::Dangling => {
                    assert!(m.unwrap().is_symlink(), "case {case}: link replaced")
                }
                Kind::DevNullCopy => {
                    assert!(m.unwrap().file_type().is_char_device(), "case {case}")
                }
                Kind::FifoNoReader => assert!(m.unwrap().file_type().is_fifo(), "case {case}"),
                Kind::Directory => assert!(m.unwrap().is_dir()),
                _ => {}
            }
            if want == 0
                && matches!(
                    k,
                    Kind::New | Kind::Existing | Kind::LinkToExisting | Kind::Dangling
                )
            {
                let text = std::fs::read(p).unwrap();
                assert!(
                    text != b"old\n" && !text.is_empty(),
                    "case {case}: {p:?} not written"
                );
            }
        }
        runs += 1;
    }
    assert!(runs >= 40, "only {runs} cases ran");
}
