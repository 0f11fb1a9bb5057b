//! Figure outputs take their format from the file's extension: `.svg`, `.png`, `.pdf` for
//! every subcommand that draws; any other extension is a usage error (exit 2) that names the
//! accepted ones and writes nothing.

use assert_cmd::Command;

fn stabound() -> Command {
    Command::cargo_bin("stabound").unwrap()
}

const PNG: &[u8] = b"\x89PNG\r\n\x1a\n";

/// Each drawing subcommand, with the figure option last (its file name appended).
const DRAWERS: [&[&str]; 4] = [
    &[
        "amax",
        "--delta",
        "0:1:5",
        "--d",
        "0,1",
        "-o",
        "/dev/null",
        "--svg",
    ],
    &[
        "boundary",
        "--delta",
        "0.5",
        "--d",
        "1",
        "--tol",
        "1e-4",
        "-o",
        "/dev/null",
        "--svg",
    ],
    &[
        "step",
        "--mass",
        "0.1",
        "--period",
        "0.001",
        "--delay-samples",
        "1",
        "--damping",
        "10",
        "--stiffness",
        "5000",
        "--duration",
        "0.01",
        "-o",
        "/dev/null",
        "--svg",
    ],
    &[
        "passivity",
        "--delta",
        "1",
        "--d",
        "1",
        "--tol",
        "1e-5",
        "-o",
        "/dev/null",
        "--svg",
    ],
];

#[test]
fn every_drawing_follows_its_extension() {
    let dir = tempfile::tempdir().unwrap();
    for (k, args) in DRAWERS.iter().enumerate() {
        for (ext, magic) in [("svg", &b"<svg"[..]), ("PNG", PNG), ("pdf", b"%PDF-")] {
            let path = dir.path().join(format!("f{k}.{ext}"));
            let o = stabound().args(*args).arg(&path).output().unwrap();
            assert!(
                o.status.success(),
                "{args:?} {ext}: {}",
                String::from_utf8_lossy(&o.stderr)
            );
            let bytes = std::fs::read(&path).unwrap();
            assert!(bytes.starts_with(magic), "{args:?} {ext}");
        }
        let path = dir.path().join(format!("f{k}.jpg"));
        let o = stabound().args(*args).arg(&path).output().unwrap();
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(
            err.contains("--svg") && err.contains(".svg, .png or .pdf"),
            "{err}"
        );
        assert!(!path.exists(), "nothing written for a refused extension");
    }
}

/// `figure` and `passivity --figures-dir` write one file per `--extension`; an unknown one
/// is exit 2 before any file is written.
#[test]
fn figure_directories_take_extensions() {
    let dir = tempfile::tempdir().unwrap();
    let o = stabound()
        .args(["figure", "11", "--extension", "svg,pdf,png", "-o"])
        .arg(dir.path())
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(
        std::fs::read(dir.path().join("fig11.png"))
            .unwrap()
            .starts_with(PNG)
    );
    assert!(
        std::fs::read(dir.path().join("fig11.pdf"))
            .unwrap()
            .starts_with(b"%PDF-")
    );
    assert!(
        std::fs::read(dir.path().join("fig11.svg"))
            .unwrap()
            .starts_with(b"<svg")
    );
    let other = tempfile::tempdir().unwrap();
    for args in [
        &["figure", "11", "--extension", "jpg", "-o"][..],
        &["passivity", "--extension", "svg,gif", "--figures-dir"][..],
    ] {
        let o = stabound().args(args).arg(other.path()).output().unwrap();
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        assert!(String::from_utf8_lossy(&o.stderr).contains(".svg, .png or .pdf"));
        assert_eq!(std::fs::read_dir(other.path()).unwrap().count(), 0);
    }
}

/// The size options reach the drawing: a PNG of --width 400 --height 300 is 400 x 300
/// (read from the IHDR chunk), and a font too large for the canvas is exit 2.
#[test]
fn size_options_set_the_canvas() {
    let dir = tempfile::tempdir().unwrap();
    let o = stabound()
        .args([
            "figure",
            "6",
            "--extension",
            "png",
            "--width",
            "400",
            "--height",
            "300",
            "-o",
        ])
        .arg(dir.path())
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let png = std::fs::read(dir.path().join("fig06.png")).unwrap();
    let be = |i: usize| u32::from_be_bytes(png[i..i + 4].try_into().unwrap());
    assert_eq!((be(16), be(20)), (400, 300));
    let o = stabound()
        .args(["figure", "6", "--font-size", "100", "-o"])
        .arg(dir.path())
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
}

/// The drawing commands take the size options of `figure` for their `--svg` file: the PNG
/// has the asked size; without options the drawing is the one at the figure's own style
/// (the default 480 x 360 at 16 px); the options need `--svg`, and a size out of range is
/// exit 2 before any output.
#[test]
fn drawing_commands_take_size_options() {
    let dir = tempfile::tempdir().unwrap();
    for (k, args) in DRAWERS.iter().enumerate() {
        let png = dir.path().join(format!("s{k}.png"));
        let o = stabound()
            .args(*args)
            .arg(&png)
            .args(["--width", "400", "--height", "300", "--font-size", "12"])
            .output()
            .unwrap();
        assert!(
            o.status.success(),
            "{args:?}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        let bytes = std::fs::read(&png).unwrap();
        let be = |i: usize| u32::from_be_bytes(bytes[i..i + 4].try_into().unwrap());
        assert_eq!((be(16), be(20)), (400, 300), "{args:?}");
        let (plain, explicit) = (dir.path().join("p.svg"), dir.path().join("e.svg"));
        let run = |path: &std::path::Path, extra: &[&str]| {
            let o = stabound()
                .args(*args)
                .arg(path)
                .args(extra)
                .output()
                .unwrap();
            assert!(o.status.success(), "{args:?}");
            std::fs::read(path).unwrap()
        };
        assert_eq!(
            run(&plain, &[]),
            run(
                &explicit,
                &["--width", "480", "--height", "360", "--font-size", "16"]
            ),
            "{args:?}"
        );
        let without_svg: Vec<&str> = args[..args.len() - 1].to_vec();
        let o = stabound()
            .args(&without_svg)
            .args(["--width", "400"])
            .output()
            .unwrap();
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        let bad = dir.path().join(format!("bad{k}.svg"));
        let o = stabound()
            .args(*args)
            .arg(&bad)
            .args(["--width", "5"])
            .output()
            .unwrap();
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        assert!(String::from_utf8_lossy(&o.stderr).contains("width"));
        assert!(!bad.exists());
    }
}
