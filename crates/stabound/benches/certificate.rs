//! One certified verdict (enclosures, interval Schur-Cohn, JSON) at short and long delays,
//! and a marginal wall (three recursions); d = 30 is near the longest delay `f64` intervals
//! certify. Run with `cargo bench --bench certificate`.

use criterion::{Criterion, criterion_group, criterion_main};
use stabound::certificate::certify;
use stabound::params::{Plant, Wall};
use std::hint::black_box;

fn bench(c: &mut Criterion) {
    for (alpha, beta, delta, d) in [
        (0.1, 0.3, 0.5, 1.0),
        (0.1, 0.3, 0.5, 2.5),
        (0.01, 0.3, 0.5, 10.0),
        (0.0, 0.3, 0.5, 10.0),
        (0.003, 0.2, 0.5, 30.0),
    ] {
        let plant = Plant::new(delta, d).unwrap();
        let wall = Wall::new(alpha, beta).unwrap();
        c.bench_function(&format!("certify alpha={alpha} d={d}"), |b| {
            b.iter(|| {
                certify(black_box(&plant), &wall, 1e-9)
                    .unwrap()
                    .to_json()
                    .len()
            })
        });
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
