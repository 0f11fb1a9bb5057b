//! alpha_max for one plant and a 1000 x 7 table. Run with `cargo bench --bench amax`.

use criterion::{Criterion, criterion_group, criterion_main};
use stabound::amax::{AmaxOptions, TableOptions, alpha_max, amax_table};
use stabound::params::Plant;
use std::hint::black_box;

fn bench(c: &mut Criterion) {
    let opts = AmaxOptions::default();
    for (delta, d) in [(0.0, 0.0), (1.0, 1.0), (5.0, 0.0), (10.0, 4.0)] {
        let plant = Plant::new(delta, d).unwrap();
        c.bench_function(&format!("alpha_max delta={delta} d={d}"), |b| {
            b.iter(|| alpha_max(black_box(&plant), &opts).unwrap())
        });
    }
    let deltas: Vec<f64> = (0..1000).map(|i| i as f64 * 0.1).collect();
    let ds = [0.0, 0.125, 0.25, 0.5, 1.0, 2.0, 4.0];
    let mut g = c.benchmark_group("table");
    g.sample_size(10);
    g.bench_function("1000x7", |b| {
        b.iter(|| {
            amax_table(
                &deltas,
                &ds,
                &TableOptions::new(opts).with_conservative(false),
            )
            .unwrap()
        })
    });
    g.bench_function("1000x7 conservative", |b| {
        b.iter(|| {
            amax_table(
                &deltas,
                &ds,
                &TableOptions::new(opts).with_conservative(true),
            )
            .unwrap()
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
