//! One buzz verdict: the exact simulation of the protocol (four starts, 20,000 samples each)
//! on the paper's loop with an encoder, with and without Coulomb friction, and the
//! describing-function estimate. Run with `cargo bench --bench buzz`.

use criterion::{Criterion, criterion_group, criterion_main};
use std::hint::black_box;

use stabound::buzz::{BuzzOptions, Quantization, buzz, describing_function};
use stabound::params::{Plant, Wall};

fn bench(c: &mut Criterion) {
    let plant = Plant::new(0.1, 1.0).unwrap();
    // linearly stable, ray margin s* about 1.14: buzzes by one or two counts
    let wall = Wall::new(0.17, 0.3).unwrap();
    let options = BuzzOptions::default();
    let encoder = Quantization::new(true, 0.0, 0.0, 0.0).unwrap();
    let friction = Quantization::new(true, 0.0, 0.002, 0.003).unwrap();
    c.bench_function("buzz verdict, encoder, d = 1", |b| {
        b.iter(|| buzz(black_box(&plant), &wall, &encoder, &options).unwrap())
    });
    c.bench_function("buzz verdict, encoder and friction, d = 1", |b| {
        b.iter(|| buzz(black_box(&plant), &wall, &friction, &options).unwrap())
    });
    c.bench_function("describing function, d = 1", |b| {
        b.iter(|| describing_function(black_box(&plant), &wall).unwrap())
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
