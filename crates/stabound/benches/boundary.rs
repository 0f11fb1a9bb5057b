//! Boundary engine benches: `stabound boundary --delta 0.5 --d 1` end to end as a
//! library call plus CSV formatting (the same writer the command uses), and the 20-curve family of the paper's Fig. 5.
//! Run with `cargo bench --bench boundary`.

use criterion::{Criterion, criterion_group, criterion_main};
use stabound::boundary::{ExactOptions, SweepOptions, exact, sweep};
use stabound::export::csv::boundaries_csv;
use stabound::params::Plant;
use std::hint::black_box;

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("boundary");
    g.sample_size(20);
    let plant = Plant::new(0.5, 1.0).unwrap();
    g.bench_function("exact_delta0.5_d1", |b| {
        b.iter(|| exact(black_box(&plant), &ExactOptions::default()).unwrap())
    });
    g.bench_function("exact_delta0.5_d1_with_csv", |b| {
        b.iter(|| {
            let bd = exact(black_box(&plant), &ExactOptions::default()).unwrap();
            boundaries_csv(std::slice::from_ref(&bd))
        })
    });
    let deltas = [0.0, 0.25, 0.5, 0.75, 1.0];
    let ds = [0.0, 1.0, 2.0, 4.0];
    let one = exact(plant, &ExactOptions::default()).unwrap();
    g.bench_function("csv_only_delta0.5_d1", |b| {
        b.iter(|| boundaries_csv(black_box(std::slice::from_ref(&one))))
    });
    g.bench_function("fig5_family_20_curves", |b| {
        b.iter(|| sweep(black_box(&deltas), &ds, &SweepOptions::default(), None).unwrap())
    });
    g.bench_function("fig5_family_20_curves_with_csv", |b| {
        b.iter(|| {
            let bs = sweep(black_box(&deltas), &ds, &SweepOptions::default(), None).unwrap();
            boundaries_csv(&bs)
        })
    });
    g.bench_function("exact_delta0.5_d1_tol1e-6", |b| {
        b.iter(|| exact(black_box(&plant), &ExactOptions { tol: 1e-6 }).unwrap())
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
