//! One buzz verdict: the exact simulation of the protocol (four starts, 20,000 samples each)
//! on the paper's loop with an encoder, with and without Coulomb friction, and the
//! describing-function estimate; with a hand and friction (the elements' route: matrix
//! exponentials and located events); and one buzz-free alpha_max (the search over the
//! damping grid, bisection with the protocol as the oracle). Run with
//! `cargo bench --bench buzz`.

use criterion::{Criterion, criterion_group, criterion_main};
use std::hint::black_box;

use stabound::buzz::{
    BuzzFreeOptions, BuzzOptions, Nonlinear, Quantization, buzz, buzz_free_alpha_max,
    describing_function,
};
use stabound::elements::{Hand, Loop, PhysicalElements};
use stabound::params::{Delay, Device, Plant, Wall};

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
    let hand = Loop::new(plant)
        .with_hand(Hand::new(0.5, 0.05, 0.01).unwrap())
        .unwrap();
    let soft = Wall::new(0.08, 0.2).unwrap();
    c.bench_function("buzz verdict, hand, encoder and friction, d = 1", |b| {
        b.iter(|| buzz(black_box(hand), &soft, &friction, &options).unwrap())
    });
    let device = Device::new(0.1, 1e-3, 10.0, Delay::Samples(1.0)).unwrap();
    let lp = Loop::physical(&device, &PhysicalElements::default()).unwrap();
    let mut n = Nonlinear::default();
    n.encoder_resolution = Some(1e-5);
    let free = BuzzFreeOptions::default();
    let mut g = c.benchmark_group("buzz-free");
    g.sample_size(10);
    g.bench_function("buzz-free alpha_max, encoder, b = 10 N s/m, d = 1", |b| {
        b.iter(|| buzz_free_alpha_max(black_box(lp), &n, &free, &|| ()).unwrap())
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
