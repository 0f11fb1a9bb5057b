//! Golden files: every figure's CSV is regenerated and compared with `data/figures/`, and
//! every drawing with its copy in `docs/figures/` (the pictures README and the model
//! document show).
//!
//! The golden files were produced by this code and checked by eye against the paper's
//! figures (the SVGs in `docs/figures/`) and against published values (docs/MODEL.md section 6).
//! The test always compares; to rewrite the files after an intended change, run
//! `cargo run --release -p stabound --example bless-figures` and review the difference.

use std::path::PathBuf;

use stabound::figures::{FIGURES, figure};

fn golden_path(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../data/figures")
        .join(format!("{name}.csv"))
}

fn parse(text: &str) -> (String, Vec<(String, Vec<f64>)>) {
    let mut lines = text.lines();
    let header = lines.next().unwrap_or_default().to_string();
    let rows = lines
        .map(|l| {
            // Labels never contain quotes in these figures; a quoted label holds commas.
            let (label, rest) = if let Some(stripped) = l.strip_prefix('"') {
                let end = stripped.find('"').unwrap();
                (stripped[..end].to_string(), &stripped[end + 2..])
            } else {
                let comma = l.find(',').unwrap();
                (l[..comma].to_string(), &l[comma + 1..])
            };
            // an empty field is a pen-up between pieces (NaN)
            let values = rest
                .split(',')
                .map(|v| {
                    if v.is_empty() {
                        f64::NAN
                    } else {
                        v.parse().unwrap()
                    }
                })
                .collect();
            (label, values)
        })
        .collect();
    (header, rows)
}

/// Compare within `1e-8` of each column's largest magnitude: the computation is deterministic
/// (results do not depend on threads), so differences can only come from the platform's `exp`
/// and `expm1` (a few ulps) amplified by root finding near boundaries; 1e-8 leaves room for
/// that and is far below anything visible in a figure.
fn compare(name: &str, fresh: &str, golden: &str) {
    let (h1, r1) = parse(fresh);
    let (h2, r2) = parse(golden);
    assert_eq!(h1, h2, "{name}: header");
    assert_eq!(r1.len(), r2.len(), "{name}: row count");
    let cols = r2.first().map_or(0, |r| r.1.len());
    let scale: Vec<f64> = (0..cols)
        .map(|c| {
            r2.iter()
                .fold(0.0f64, |m, r| m.max(r.1[c].abs()))
                .max(1e-300)
        })
        .collect();
    for (i, (a, b)) in r1.iter().zip(&r2).enumerate() {
        assert_eq!(a.0, b.0, "{name}: label of row {i}");
        assert_eq!(a.1.len(), b.1.len(), "{name}: row {i} width");
        for (c, (x, y)) in a.1.iter().zip(&b.1).enumerate() {
            let ok = (x.is_nan() && y.is_nan()) || (x - y).abs() <= 1e-8 * scale[c];
            assert!(ok, "{name}: row {i} column {c}: {x} vs golden {y}");
        }
    }
}

#[test]
fn every_figure_matches_its_golden_csv() {
    for n in FIGURES {
        let fd = figure(n).unwrap_or_else(|e| panic!("figure {n}: {e}"));
        let fresh = fd.to_csv();
        let path = golden_path(&fd.name);
        let golden = std::fs::read_to_string(&path).unwrap_or_else(|e| {
            panic!(
                "{}: {e}; `cargo run --release -p stabound --example bless-figures` writes it",
                path.display()
            )
        });
        compare(&fd.name, &fresh, &golden);
    }
}

/// The comparison itself can fail: a perturbed value is caught.
#[test]
fn comparison_catches_a_change() {
    let golden = "series,x\na,1\na,2\n";
    let moved = "series,x\na,1\na,2.001\n";
    let r = std::panic::catch_unwind(|| compare("t", moved, golden));
    assert!(r.is_err());
    compare("t", golden, golden);
}

/// The text of an SVG split into runs of numbers and runs of everything else.
fn tokens(svg: &str) -> Vec<(bool, &str)> {
    let mut out = Vec::new();
    let mut start = 0;
    let mut in_num = false;
    for (i, c) in svg.char_indices() {
        let num = c.is_ascii_digit() || c == '.' || (c == '-' && !in_num);
        if i > 0 && num != in_num {
            out.push((in_num, &svg[start..i]));
            start = i;
        }
        in_num = num;
    }
    out.push((in_num, &svg[start..]));
    out
}

/// Compare two drawings: the same text, and every number within 0.011 of the stored one.
/// Coordinates are printed to 1/100 pixel, so a data change of a few ulps (see `compare`)
/// can move a printed coordinate by one unit of its last digit, 0.01 px; anything larger
/// is a visible change and needs the drawing re-blessed.
fn compare_svg(name: &str, fresh: &str, stored: &str) {
    let (a, b) = (tokens(fresh), tokens(stored));
    assert_eq!(a.len(), b.len(), "{name}: the drawings differ in structure");
    for ((na, ta), (nb, tb)) in a.iter().zip(&b) {
        match (na, nb, ta.parse::<f64>(), tb.parse::<f64>()) {
            (true, true, Ok(x), Ok(y)) => {
                assert!((x - y).abs() <= 0.011, "{name}: {ta} vs stored {tb}")
            }
            _ => assert_eq!(ta, tb, "{name}: the drawings' text differs"),
        }
    }
}

#[test]
fn every_drawing_matches_its_copy_in_docs() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../docs/figures");
    for n in FIGURES {
        let fd = figure(n).unwrap_or_else(|e| panic!("figure {n}: {e}"));
        let path = dir.join(format!("{}.svg", fd.name));
        let stored = std::fs::read_to_string(&path).unwrap_or_else(|e| {
            panic!(
                "{}: {e}; `cargo run --release -p stabound --example bless-figures` writes it",
                path.display()
            )
        });
        compare_svg(&fd.name, &fd.to_svg().unwrap(), &stored);
    }
}

/// The drawing comparison catches a moved vertex and a changed label.
#[test]
fn drawing_comparison_catches_a_change() {
    let stored = "<text x=\"1.5\">α = 0.5</text><path d=\"M1 2L3.25 -4\"/>";
    compare_svg(
        "t",
        "<text x=\"1.51\">α = 0.5</text><path d=\"M1 2L3.25 -4\"/>",
        stored,
    );
    for changed in [
        "<text x=\"1.5\">α = 0.5</text><path d=\"M1 2L3.3 -4\"/>",
        "<text x=\"1.5\">α = 0.6</text><path d=\"M1 2L3.25 -4\"/>",
        "<text x=\"1.5\">β = 0.5</text><path d=\"M1 2L3.25 -4\"/>",
        "<text x=\"1.5\">α = 0.5</text><path d=\"M1 2L3.25 -4L5 5\"/>",
    ] {
        let r = std::panic::catch_unwind(|| compare_svg("t", changed, stored));
        assert!(r.is_err(), "{changed}");
    }
}
