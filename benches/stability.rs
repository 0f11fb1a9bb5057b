//! Stability tests at degrees 3 to 20: Schur-Cohn against companion and state-space
//! eigenvalues. Run with `cargo bench --bench stability`.

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use stabound::params::{Plant, Wall};
use stabound::stability::{Checker, Method, Options};
use std::hint::black_box;

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("stability");
    let wall = Wall::new(0.05, 0.2).unwrap();
    for degree in [3usize, 4, 5, 8, 12, 20] {
        // degree n + 3 for integer d = n
        let plant = Plant::new(0.5, (degree - 3) as f64).unwrap();
        for method in [Method::SchurCohn, Method::Eigen, Method::StateSpace] {
            let checker = Checker::new(
                &plant,
                Options {
                    method,
                    ..Options::default()
                },
            )
            .unwrap();
            g.bench_with_input(BenchmarkId::new(method.name(), degree), &wall, |b, w| {
                b.iter(|| checker.verdict(black_box(w)).unwrap())
            });
        }
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
