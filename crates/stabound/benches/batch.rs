//! `stabound check --batch` once its file is parsed: per wall a checker of its plant, the
//! verdict and, with `--radius`, the spectral radius the row prints
//! (`Checker::decide_with_radius`, the roots by companion or state-matrix eigenvalues),
//! against the default batch (`Checker::decide`, no roots). Each batch ends in its CSV text,
//! written to `std::io::sink()`.
//!
//! Groups (`radius` and `verdict-only`, the default output, in each), on one thread so that
//! the ratio does not depend on the cores free on a loaded machine:
//! - `batch-d1`: 20,000 walls at delta = 0.1, d = 1 (a degree-4 polynomial per wall);
//! - `batch-d500`: 8 walls at delta = 0.1, d = 500 (degree 503: the radius comes from the
//!   state matrix's eigenvalues, the verdict from Schur-Cohn).
//!
//! The walls are a Weyl sequence over alpha and beta (both verdicts occur). Run with
//! `cargo bench -p stabound --bench batch`.

use std::hint::black_box;
use std::io::Write;

use criterion::{Criterion, criterion_group, criterion_main};
use stabound::export::report::shown_decided_radius;
use stabound::export::{Cell, Table, csv::to_csv_bytes};
use stabound::params::Normalized;
use stabound::stability::{Checker, Options};

/// The normalized damping of every wall.
const DELTA: f64 = 0.1;

/// The `i`-th wall: alpha in `[0, alpha_top)`, beta in `[-0.2, 1.0)`, by the fractional parts
/// of multiples of two irrational steps (a Weyl sequence, the same walls on every run).
fn wall_of(i: usize, alpha_top: f64) -> (f64, f64) {
    let frac = |g: f64| {
        let x = 0.5 + i as f64 * g;
        x - x.floor()
    };
    (
        alpha_top * frac(0.754_877_666_246_692_7),
        -0.2 + 1.2 * frac(0.569_840_290_998_053_2),
    )
}

/// The batch of `walls` at delay `d`, as the command line runs it after parsing (a checker
/// per wall, the verdict, the radius unless `verdict_only`, a table and its CSV); returns
/// the number of bytes written.
fn batch(walls: &[(f64, f64)], d: f64, verdict_only: bool) -> usize {
    let options = Options::default();
    let mut cols = vec!["alpha", "beta", "delta", "d", "verdict"];
    if !verdict_only {
        cols.push("spectral_radius");
    }
    cols.push("method");
    let mut table = Table::new(&cols);
    table.reserve(walls.len());
    let mut cells = Vec::with_capacity(cols.len());
    for &(a, b) in walls {
        let Ok((plant, wall)) = Normalized::new(a, b, DELTA, d).and_then(|p| p.split()) else {
            continue;
        };
        let Ok(checker) = Checker::new(plant, options) else {
            continue;
        };
        let row = if verdict_only {
            checker.decide(&wall).map(|x| (x.verdict, x.method, None))
        } else {
            checker.decide_with_radius(&wall).map(|(x, radius)| {
                let shown = shown_decided_radius(x.verdict, x.reason, radius, options.margin);
                (x.verdict, x.method, Some(shown))
            })
        };
        let Ok((verdict, method, radius)) = row else {
            continue;
        };
        cells.clear();
        cells.extend([
            Cell::Num(a),
            Cell::Num(b),
            Cell::Num(DELTA),
            Cell::Num(d),
            Cell::Static(verdict.name()),
        ]);
        cells.extend(radius.map(Cell::Num));
        cells.push(Cell::Static(method.name()));
        table.push_cells(cells.drain(..));
    }
    let bytes = to_csv_bytes(&table);
    std::io::sink().write_all(&bytes).unwrap_or(());
    bytes.len()
}

fn bench(c: &mut Criterion) {
    for (name, d, count, alpha_top) in [
        ("batch-d1", 1.0, 20_000, 3.0),
        ("batch-d500", 500.0, 8, 0.01),
    ] {
        let walls: Vec<(f64, f64)> = (0..count).map(|i| wall_of(i, alpha_top)).collect();
        let mut g = c.benchmark_group(name);
        g.sample_size(10);
        for (label, verdict_only) in [("radius", false), ("verdict-only", true)] {
            g.bench_function(label, |b| {
                b.iter(|| black_box(batch(black_box(&walls), d, verdict_only)))
            });
        }
        g.finish();
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
