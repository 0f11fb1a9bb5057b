//! Each main job of the command line against its physical floor, in one process.
//!
//! The floor of a job is what no method can avoid: per output row, one evaluation of the
//! model and one CSV row written by the crate's own writer. For the boundary jobs and
//! `amax` the evaluation is one point of the D-decomposition curve
//! ([`CharPoly::wall_on_circle_at`], the model document (docs/MODEL.md, section 4):
//! `e^{i theta}` by one complex rotation from the previous angle, then `alpha` and `beta` in
//! closed form); for the point tests it is forming the wall's characteristic polynomial
//! ([`CharPoly::new`] and [`CharPoly::coefficients_into`], section 3). The floors run on one
//! thread; ours runs as the command line does (rayon over curves, rows or walls).
//!
//! Groups (`ours` and `floor` in each):
//! - `main`: `stabound boundary --delta 0.5 --d 1` (tol 1e-9), one curve;
//! - `family`: `stabound boundary --delta 0,0.25,0.5,0.75,1 --d 0,1,2,4`, 20 curves, each
//!   floor curve with as many rows as ours;
//! - `amax`: `stabound amax --delta 0:10:1001 --d 1`, 1001 rows;
//! - `check`: `stabound check --batch` on 100,000 walls at d = 1 (the walls of
//!   `benches/compare.py`, a Weyl sequence, so both build the same ones), without parsing the
//!   input file.
//!
//! Output goes to `std::io::sink()` chunk by chunk, as the command line streams it.
//! Run with `cargo bench -p stabound --bench floor`; `benches/compare.py` runs it with the
//! whole-process timings and the Python peers.

use std::f64::consts::PI;
use std::hint::black_box;
use std::io::Write;

use criterion::{Criterion, criterion_group, criterion_main};
use rayon::prelude::*;
use stabound::amax::{AmaxOptions, AmaxPoint, alpha_max_each};
use stabound::boundary::{Boundary, Piece, SweepOptions, Vertex, sweep_each};
use stabound::export::csv::{CsvWriter, push_boundary_header, push_boundary_rows};
use stabound::poly::{CharPoly, Complex};
use stabound::stability::{Checker, Options};
use stabound::{Plant, Wall};

/// Rows per write, as the command line's boundary writer does.
const CHUNK_ROWS: usize = 4096;

/// Walls of the point-test job (`benches/compare.py` writes the same ones).
const WALLS: usize = 100_000;

/// The curves of the paper's Fig. 5, in the command line's order (delta outer, d inner).
fn family() -> Vec<(f64, f64)> {
    let deltas = [0.0, 0.25, 0.5, 0.75, 1.0];
    let ds = [0.0, 1.0, 2.0, 4.0];
    deltas
        .iter()
        .flat_map(|&x| ds.iter().map(move |&d| (x, d)))
        .collect()
}

/// Ours: the curves computed by `sweep_each` and written in chunks, as `stabound boundary`;
/// the rows of each curve in `counts`.
fn ours_boundaries(curves: &[(f64, f64)], buf: &mut Vec<u8>, counts: &mut Vec<usize>) {
    let mut header = true;
    counts.clear();
    sweep_each(
        curves.len(),
        |k| Plant::new(curves[k].0, curves[k].1),
        &SweepOptions::default(),
        None,
        |b: Boundary| -> Result<(), stabound::Error> {
            for chunk in b.points.chunks(CHUNK_ROWS) {
                buf.clear();
                if std::mem::take(&mut header) {
                    push_boundary_header(buf);
                }
                push_boundary_rows(buf, &b, chunk);
                std::io::sink().write_all(buf).unwrap_or(());
            }
            counts.push(b.points.len());
            Ok(())
        },
    )
    .unwrap_or(());
}

/// The floor of one boundary curve: `rows` points of the D-decomposition curve at evenly
/// spaced angles in `(0, pi)`, each written as one CSV row, in chunks.
fn floor_curve(cp: &CharPoly, b: &mut Boundary, rows: usize, buf: &mut Vec<u8>) {
    let step = PI / rows as f64;
    let k = cp.circle_power() as f64;
    // the first angle half a step in; each next one by a rotation (a complex product)
    let (mut z, mut zk) = (
        Complex::from_polar(1.0, 0.5 * step),
        Complex::from_polar(1.0, 0.5 * step * k),
    );
    let (r, rk) = (
        Complex::from_polar(1.0, step),
        Complex::from_polar(1.0, step * k),
    );
    let mut left = rows;
    while left > 0 {
        let n = left.min(CHUNK_ROWS);
        b.points.clear();
        for _ in 0..n {
            // where M(e^{i theta}) vanishes (no such angle on these curves) an empty field
            let (alpha, beta) = cp
                .wall_on_circle_at(z, zk)
                .map_or((f64::NAN, f64::NAN), |w| (w.alpha(), w.beta()));
            b.points.push(Vertex {
                x: alpha,
                y: beta,
                piece: Piece::Curve,
            });
            z *= r;
            zk *= rk;
        }
        buf.clear();
        push_boundary_rows(buf, b, &b.points);
        std::io::sink().write_all(buf).unwrap_or(());
        left -= n;
    }
}

fn floor_boundaries(curves: &[(f64, f64)], rows: &[usize], buf: &mut Vec<u8>) {
    buf.clear();
    push_boundary_header(buf);
    std::io::sink().write_all(buf).unwrap_or(());
    let mut b = Boundary {
        delta: 0.0,
        d: 0.0,
        tol: 1e-9,
        points: Vec::with_capacity(CHUNK_ROWS),
        fallback: None,
    };
    for (&(x, d), &n) in curves.iter().zip(rows) {
        let Ok(cp) = Plant::new(x, d).and_then(CharPoly::new) else {
            continue;
        };
        b.delta = x;
        b.d = d;
        floor_curve(&cp, &mut b, n, buf);
    }
}

const AMAX_COLUMNS: [&str; 4] = ["delta", "d", "alpha_max", "beta_at_max"];

fn amax_deltas() -> Vec<f64> {
    // `--delta 0:10:1001`: 0, 0.01, ..., 10
    (0..1001).map(|i| 10.0 * i as f64 / 1000.0).collect()
}

fn ours_amax(deltas: &[f64]) {
    let mut w = CsvWriter::new(&AMAX_COLUMNS, 256);
    alpha_max_each(
        deltas.len(),
        |i| Plant::new(deltas[i], 1.0),
        &AmaxOptions::default(),
        |_, chunk: &[AmaxPoint]| -> Result<(), stabound::Error> {
            for r in chunk {
                for v in [r.delta, r.d, r.alpha_max, r.beta_at_max] {
                    w.num(v);
                }
            }
            w.write_to(&mut std::io::sink()).unwrap_or(());
            Ok(())
        },
    )
    .unwrap_or(());
}

/// The floor of `amax`: per row the plant's polynomial and one point of its curve (at a
/// fixed angle), written as one row.
fn floor_amax(deltas: &[f64]) {
    let mut w = CsvWriter::new(&AMAX_COLUMNS, 256);
    let z = Complex::from_polar(1.0, 0.5);
    for (i, &x) in deltas.iter().enumerate() {
        let Ok(cp) = Plant::new(x, 1.0).and_then(CharPoly::new) else {
            continue;
        };
        let zk = Complex::from_polar(1.0, 0.5 * cp.circle_power() as f64);
        let wall = cp.wall_on_circle_at(z, zk);
        let (a, b) = wall.map_or((0.0, 0.0), |w| (w.alpha(), w.beta()));
        for v in [x, 1.0, a, b] {
            w.num(v);
        }
        if (i + 1) % 256 == 0 {
            w.write_to(&mut std::io::sink()).unwrap_or(());
        }
    }
    w.write_to(&mut std::io::sink()).unwrap_or(());
}

/// Wall `i` of the point-test job: a Weyl sequence, `frac(0.5 + i g)` for three irrational
/// `g`, mapped to alpha in [0, 1), beta in [-0.2, 1), delta in [0, 2) (the ranges of
/// `python/bench.py`). `benches/compare.py` computes the same numbers.
fn wall_of(i: usize) -> (f64, f64, f64) {
    let frac = |g: f64| {
        let x = 0.5 + i as f64 * g;
        x - x.floor()
    };
    (
        frac(0.754_877_666_246_692_7),
        -0.2 + 1.2 * frac(0.569_840_290_998_053_2),
        2.0 * frac(0.618_033_988_749_894_9),
    )
}

/// The columns of `stabound check --batch` (the spectral radius only with `--radius`).
const CHECK_COLUMNS: [&str; 6] = ["alpha", "beta", "delta", "d", "verdict", "method"];

/// Walls per chunk, as the command line's batch formats them.
const CHECK_CHUNK: usize = 2048;

/// Ours: what `stabound check --batch` does once the file is parsed (chunks of walls in
/// parallel, each wall's checker and verdict, each chunk's CSV rows; the chunks joined in
/// order).
fn ours_check(walls: &[(f64, f64, f64)]) -> usize {
    let parts: Vec<Vec<u8>> = walls
        .par_chunks(CHECK_CHUNK)
        .map(|chunk| {
            let mut w = CsvWriter::without_header(CHECK_COLUMNS.len(), chunk.len());
            for &(a, b, x) in chunk {
                let Ok(decision) = Plant::new(x, 1.0).and_then(|plant| {
                    Checker::new(plant, Options::default())?.decide(&Wall::new(a, b)?)
                }) else {
                    continue;
                };
                for v in [a, b, x, 1.0] {
                    w.num(v);
                }
                w.text(decision.verdict.name());
                w.text(decision.method.name());
            }
            w.finish()
        })
        .collect();
    let mut bytes = CsvWriter::new(&CHECK_COLUMNS, 0).finish();
    bytes.reserve(parts.iter().map(Vec::len).sum());
    for p in &parts {
        bytes.extend_from_slice(p);
    }
    std::io::sink().write_all(&bytes).unwrap_or(());
    bytes.len()
}

/// The floor of the point tests: per wall its polynomial formed and one row written (the
/// text cells are ours').
fn floor_check(walls: &[(f64, f64, f64)]) {
    let mut w = CsvWriter::new(&CHECK_COLUMNS, 4096);
    let mut q = [0.0; 8];
    for (i, &(a, b, x)) in walls.iter().enumerate() {
        let (Ok(cp), Ok(wall)) = (Plant::new(x, 1.0).and_then(CharPoly::new), Wall::new(a, b))
        else {
            continue;
        };
        black_box(cp.coefficients_into(&wall, &mut q)[0]);
        for v in [a, b, x, 1.0] {
            w.num(v);
        }
        w.text("stable");
        w.text("schur-cohn");
        if (i + 1) % 4096 == 0 {
            w.write_to(&mut std::io::sink()).unwrap_or(());
        }
    }
    w.write_to(&mut std::io::sink()).unwrap_or(());
}

/// One group of the job `name`: ours and its floor.
fn pair(
    c: &mut Criterion,
    name: &str,
    samples: usize,
    mut ours: impl FnMut(),
    mut floor: impl FnMut(),
) {
    let mut g = c.benchmark_group(name);
    g.sample_size(samples);
    g.bench_function("ours", |b| b.iter(&mut ours));
    g.bench_function("floor", |b| b.iter(&mut floor));
    g.finish();
}

fn bench(c: &mut Criterion) {
    let buf = std::cell::RefCell::new(Vec::with_capacity(64 * CHUNK_ROWS));
    let mut rows = Vec::new();
    for (name, curves, samples) in [("main", vec![(0.5, 1.0)], 20), ("family", family(), 10)] {
        // the floor writes as many rows per curve as ours
        let mut counts = Vec::new();
        ours_boundaries(&curves, &mut buf.borrow_mut(), &mut counts);
        rows.push(counts.iter().sum::<usize>());
        let mut scratch = Vec::new();
        pair(
            c,
            name,
            samples,
            || ours_boundaries(black_box(&curves), &mut buf.borrow_mut(), &mut scratch),
            || floor_boundaries(black_box(&curves), &counts, &mut buf.borrow_mut()),
        );
    }
    let deltas = amax_deltas();
    pair(
        c,
        "amax",
        10,
        || ours_amax(black_box(&deltas)),
        || floor_amax(black_box(&deltas)),
    );
    let walls: Vec<(f64, f64, f64)> = (0..WALLS).map(wall_of).collect();
    pair(
        c,
        "check",
        10,
        || {
            black_box(ours_check(black_box(&walls)));
        },
        || floor_check(black_box(&walls)),
    );
    eprintln!(
        "rows: main {}, family {}, amax {}, check {}",
        rows[0],
        rows[1],
        deltas.len(),
        walls.len()
    );
}

criterion_group!(benches, bench);
criterion_main!(benches);
