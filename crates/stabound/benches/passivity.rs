//! The passive region (sandwich algorithm) and the largest passive stiffness, with and
//! without a velocity filter. Run with `cargo bench -p stabound --bench passivity`.

use criterion::{Criterion as Bench, criterion_group, criterion_main};
use stabound::VelocityFilter;
use stabound::passivity::Criterion;
use std::hint::black_box;

fn bench(c: &mut Bench) {
    let cases = [
        ("d=0", 0.0, VelocityFilter::none()),
        ("d=1", 1.0, VelocityFilter::none()),
        ("d=4", 4.0, VelocityFilter::none()),
        (
            "d=1 low-pass 0.9",
            1.0,
            VelocityFilter::low_pass(0.9).unwrap(),
        ),
    ];
    let mut g = c.benchmark_group("passivity");
    g.sample_size(10);
    for (name, d, f) in cases {
        let crit = Criterion::new(d, f).unwrap();
        g.bench_function(format!("region tol=1e-7 {name}"), |b| {
            b.iter(|| crit.region_alpha_beta(black_box(1.0), 1e-7).unwrap())
        });
        g.bench_function(format!("max stiffness tol=1e-9 {name}"), |b| {
            b.iter(|| crit.max_stiffness(black_box(1.0), 1e-9).unwrap())
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
