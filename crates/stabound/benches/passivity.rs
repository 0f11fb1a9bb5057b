//! The passive region (sandwich algorithm), the largest passive stiffness, with and
//! without a velocity filter, and the comparison with a filtered loop's stable region. Run with `cargo bench -p stabound --bench passivity`.

use criterion::{Criterion as Bench, criterion_group, criterion_main};
use stabound::VelocityFilter;
use stabound::passivity::{Criterion, compare, compare_on_lines};
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
    // the comparison with the stable region of a filtered loop: the exact boundary clipped,
    // and the columns (128 per half) for the same loop
    for (name, f) in [
        ("low-pass 0.5", VelocityFilter::low_pass(0.5).unwrap()),
        ("butterworth 0.1", VelocityFilter::butterworth(0.1).unwrap()),
    ] {
        g.bench_function(format!("compare exact d=1 {name}"), |b| {
            b.iter(|| compare(black_box(1.0), 1.0, f, 1e-7).unwrap())
        });
        g.bench_function(format!("compare columns=128 d=1 {name}"), |b| {
            b.iter(|| compare_on_lines(black_box(1.0), 1.0, f, 128, 1e-7).unwrap())
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
