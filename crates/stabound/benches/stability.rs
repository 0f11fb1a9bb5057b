//! Stability tests at degrees 3 to 20 and at d = 100 (degree 103): Schur-Cohn, the guarded
//! default (auto), companion and state-space eigenvalues. The wall is stable
//! (alpha = 0.5 alpha_max at its beta), where auto's guard is hardest to satisfy.
//! Run with `cargo bench --bench stability`.

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use stabound::amax::{AmaxOptions, alpha_max};
use stabound::params::{Plant, Wall};
use stabound::stability::{Checker, Method, Options};
use std::hint::black_box;

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("stability");
    for degree in [3usize, 4, 5, 8, 12, 20, 103] {
        // degree n + 3 for integer d = n
        let plant = Plant::new(0.5, (degree - 3) as f64).unwrap();
        let a = alpha_max(&plant, &AmaxOptions::default()).unwrap();
        let wall = Wall::new(0.5 * a.alpha_max, a.beta_at_max).unwrap();
        for method in [
            Method::SchurCohn,
            Method::Auto,
            Method::Eigen,
            Method::StateSpace,
            Method::ArgumentPrinciple,
        ] {
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
