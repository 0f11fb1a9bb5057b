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
        let a = alpha_max(plant, &AmaxOptions::default()).unwrap();
        let wall = Wall::new(0.5 * a.alpha_max, a.beta_at_max).unwrap();
        for method in [
            Method::SchurCohn,
            Method::Auto,
            Method::Eigen,
            Method::StateSpace,
            Method::ArgumentPrinciple,
        ] {
            let checker = Checker::new(
                plant,
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

/// The loop's elements: the default check (auto) of the bare loop through `Checker` and
/// through a `Loop` with no element (which must be the same fast path), and with each element named,
/// at delta = 0.5, d = 1 and a wall at half the bare loop's alpha_max.
fn bench_elements(c: &mut Criterion) {
    use stabound::elements::{Actuator, Encoder, Hand, Loop, Transmission};
    use stabound::filter::VelocityFilter;
    let mut g = c.benchmark_group("elements");
    let plant = Plant::new(0.5, 1.0).unwrap();
    let a = alpha_max(plant, &AmaxOptions::default()).unwrap();
    let wall = Wall::new(0.5 * a.alpha_max, a.beta_at_max).unwrap();
    let bare = Loop::new(plant);
    let loops = [
        ("bare", bare),
        (
            "hand",
            bare.with_hand(Hand::new(0.5, 0.05, 0.01).unwrap()).unwrap(),
        ),
        (
            "transmission",
            bare.with_transmission(
                Transmission::new(0.3, 100.0, 0.5, 0.1, Encoder::Motor).unwrap(),
            )
            .unwrap(),
        ),
        (
            "actuator",
            bare.with_actuator(Actuator::new(0.5).unwrap()).unwrap(),
        ),
        (
            "low-pass",
            bare.with_filter(VelocityFilter::low_pass(0.8).unwrap())
                .unwrap(),
        ),
        (
            "moving-average-4",
            bare.with_filter(VelocityFilter::moving_average(4).unwrap())
                .unwrap(),
        ),
    ];
    let checker = Checker::new(plant, Options::default()).unwrap();
    g.bench_with_input(BenchmarkId::new("checker", "bare"), &wall, |b, w| {
        b.iter(|| checker.verdict(black_box(w)).unwrap())
    });
    for (name, lp) in loops {
        let lc = Checker::new(lp, Options::default()).unwrap();
        g.bench_with_input(BenchmarkId::new("loop-checker", name), &wall, |b, w| {
            b.iter(|| lc.verdict(black_box(w)).unwrap())
        });
    }
    // building the checker: closed forms for the bare loop, matrix exponentials otherwise
    for (name, lp) in loops {
        g.bench_with_input(BenchmarkId::new("build", name), &lp, |b, lp| {
            b.iter(|| Checker::new(black_box(lp), Options::default()).unwrap())
        });
    }
    g.finish();
}

criterion_group!(benches, bench, bench_elements);
criterion_main!(benches);
