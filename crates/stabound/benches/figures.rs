//! Time to compute each of the paper's figures (data and SVG), as `stabound figure N` does.
//! Run with `cargo bench --bench figures -- --warm-up-time 1 --measurement-time 3`.

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use stabound::figures::{FIGURES, figure};
use stabound::sim::{StepOptions, step_response};
use std::hint::black_box;

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("figures");
    g.sample_size(10);
    for n in FIGURES {
        if figure(n).is_err() {
            continue;
        }
        g.bench_with_input(BenchmarkId::new("figure", n), &n, |b, &n| {
            b.iter(|| {
                let fd = figure(black_box(n)).unwrap();
                (fd.to_csv().len(), fd.to_svg().unwrap().len())
            })
        });
    }
    g.finish();
    // One step response: 1000 periods of the Section VIII device, 10 points each.
    let dev = stabound::figures::section8_device(10.0).unwrap();
    let lp = stabound::Loop::physical(&dev, &Default::default()).unwrap();
    let opts = StepOptions {
        duration: 1.0,
        ..StepOptions::default()
    };
    c.bench_function("step_response_1000_periods_x10", |b| {
        b.iter(|| step_response(&lp, black_box(14_900.0), 41.6, &opts).unwrap())
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
