//! `stabound check --batch` as a user runs it: the release binary started on a CSV of
//! 20,000 walls (alpha in [0, 3), beta in [-1, 3), delta in [0, 2), d = 1, a Weyl sequence),
//! its parsing, the checks and the CSV written to a null sink, by default (the verdicts) and
//! with `--radius` (the spectral radius of every wall too, from its roots). One thread (`RAYON_NUM_THREADS=1`), so that the ratio does not depend on
//! the cores a loaded machine leaves free. The library's own bench of the same work after
//! parsing is `cargo bench -p stabound --bench batch`. Run with
//! `cargo bench --bench batch_command`.

use std::fmt::Write as _;
use std::path::Path;
use std::process::{Command, Stdio};

use criterion::{Criterion, criterion_group, criterion_main};

/// The walls' file: the `i`-th wall by the fractional parts of multiples of three irrational
/// steps (the same walls on every run).
fn walls(n: usize) -> String {
    let frac = |i: usize, g: f64| {
        let x = 0.5 + i as f64 * g;
        x - x.floor()
    };
    let mut s = String::from("alpha,beta,delta,d\n");
    for i in 0..n {
        let alpha = 3.0 * frac(i, 0.754_877_666_246_692_7);
        let beta = -1.0 + 4.0 * frac(i, 0.569_840_290_998_053_2);
        let delta = 2.0 * frac(i, 0.438_579_785_510_917_5);
        writeln!(s, "{alpha},{beta},{delta},1").unwrap();
    }
    s
}

/// One run of the command on `file`, its output discarded; panics if it fails.
fn run(file: &Path, extra: &[&str]) {
    let status = Command::new(env!("CARGO_BIN_EXE_stabound"))
        .args(["check", "--batch"])
        .arg(file)
        .args(extra)
        .env("RAYON_NUM_THREADS", "1")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .expect("the stabound binary runs");
    assert!(status.success(), "check --batch failed");
}

fn bench(c: &mut Criterion) {
    let dir = tempfile::tempdir().expect("a temporary directory");
    let file = dir.path().join("walls.csv");
    std::fs::write(&file, walls(20_000)).expect("the walls' file is written");
    let mut g = c.benchmark_group("check-batch-20000");
    g.sample_size(20);
    g.bench_function("default", |b| b.iter(|| run(&file, &[])));
    g.bench_function("radius", |b| b.iter(|| run(&file, &["--radius"])));
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
