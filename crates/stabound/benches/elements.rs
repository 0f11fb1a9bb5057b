//! The cost of each loop element in `check` (one verdict), `amax` and `boundary` (exact),
//! against the bare loop at the same plant (delta = 0.1, d = 1). `amax` also times, for each
//! element, the bare loop at the same polynomial degree (a longer delay) and the former
//! route, the rightmost vertex of the traced exact boundary at `1e-9`; `limit` the largest
//! stable stiffness at one damping; `recommend` the checked 75 % margin wall. Run with `cargo bench -p stabound --bench elements`.

use criterion::{Criterion, criterion_group, criterion_main};
use stabound::amax::{TableOptions, amax_table, recommend};
use stabound::boundary::{ExactOptions, exact};
use stabound::elements::{Actuator, Encoder, Hand, Loop, PhysicalElements, Transmission};
use stabound::filter::VelocityFilter;
use stabound::params::{Delay, Device, Plant, Wall};
use stabound::search::alpha_limit;
use stabound::stability::{Checker, Options};
use stabound::{AmaxOptions, alpha_max};
use std::hint::black_box;

fn loops(plant: Plant) -> Vec<(&'static str, Loop)> {
    let bare = Loop::new(plant);
    vec![
        (
            "hand",
            bare.with_hand(Hand::new(0.5, 0.1, 0.01).unwrap()).unwrap(),
        ),
        (
            "transmission",
            bare.with_transmission(
                Transmission::new(0.3, 40.0, 0.5, 0.02, Encoder::Motor).unwrap(),
            )
            .unwrap(),
        ),
        (
            "actuator",
            bare.with_actuator(Actuator::new(0.7).unwrap()).unwrap(),
        ),
        (
            "low-pass",
            bare.with_filter(VelocityFilter::low_pass(0.8).unwrap())
                .unwrap(),
        ),
        (
            "moving-average",
            bare.with_filter(VelocityFilter::moving_average(4).unwrap())
                .unwrap(),
        ),
    ]
}

fn bench(c: &mut Criterion) {
    let plant = Plant::new(0.1, 1.0).unwrap();
    let wall = Wall::new(0.05, 0.1).unwrap();
    let tol = ExactOptions { tol: 1e-9 };
    let amax = AmaxOptions::default();

    let mut g = c.benchmark_group("check");
    let bare = Checker::new(plant, Options::default()).unwrap();
    g.bench_function("bare", |b| {
        b.iter(|| bare.verdict(black_box(&wall)).unwrap())
    });
    for (name, lp) in loops(plant) {
        let lc = Checker::new(lp, Options::default()).unwrap();
        g.bench_function(name, |b| b.iter(|| lc.verdict(black_box(&wall)).unwrap()));
    }
    g.finish();

    let mut g = c.benchmark_group("amax");
    g.sample_size(20);
    g.bench_function("bare", |b| {
        b.iter(|| alpha_max(black_box(&plant), &amax).unwrap())
    });
    g.bench_function("bare, general route", |b| {
        b.iter(|| alpha_max(black_box(&Loop::new(plant)), &amax).unwrap())
    });
    for (name, lp) in loops(plant) {
        g.bench_function(name, |b| {
            b.iter(|| alpha_max(black_box(&lp), &amax).unwrap())
        });
        // the bare loop of the same degree: an integer delay d has degree d + 3
        let same = Plant::new(0.1, (lp.degree() - 3) as f64).unwrap();
        g.bench_function(format!("{name}: bare at degree {}", lp.degree()), |b| {
            b.iter(|| alpha_max(black_box(&same), &amax).unwrap())
        });
        g.bench_function(format!("{name}: traced boundary"), |b| {
            b.iter(|| {
                exact(black_box(&lp), &tol)
                    .unwrap()
                    .points
                    .iter()
                    .map(|p| p.x)
                    .fold(f64::NEG_INFINITY, f64::max)
            })
        });
    }
    g.finish();

    let mut g = c.benchmark_group("limit");
    g.sample_size(20);
    let beta = 0.1;
    g.bench_function("bare", |b| {
        b.iter(|| alpha_limit(&bare, black_box(beta)).unwrap())
    });
    for (name, lp) in loops(plant) {
        g.bench_function(name, |b| {
            let c = Checker::new(lp, Options::default()).unwrap();
            b.iter(|| alpha_limit(black_box(&c), beta).unwrap())
        });
    }
    g.finish();

    // the recommended 75 % wall (alpha_max, the stable set at its damping, the checker's
    // verdict; behind the wedge a scan of dampings for a lower top)
    let mut g = c.benchmark_group("recommend");
    g.sample_size(20);
    g.bench_function("bare", |b| {
        b.iter(|| recommend(black_box(&Loop::new(plant)), &amax, 0.75).unwrap())
    });
    for (name, lp) in loops(plant) {
        g.bench_function(name, |b| {
            b.iter(|| recommend(black_box(&lp), &amax, 0.75).unwrap())
        });
    }
    let device = Device::new(0.1, 1e-3, 50.0, Delay::Samples(0.999)).unwrap();
    let mut average = PhysicalElements::default();
    average.velocity_filter_samples = Some(8);
    let wedge = Loop::physical(&device, &average).unwrap();
    g.bench_function("8-sample average behind a wedge", |b| {
        b.iter(|| recommend(black_box(&wedge), &amax, 0.75).unwrap())
    });
    // a 0.16 mHz low-pass at 1 kHz (pole 1e-6 from z = 1): a sliver region whose margin
    // range fits only near its wide end
    let device = Device::new(0.1, 1e-3, 10.0, Delay::Samples(1.0)).unwrap();
    let mut slow = PhysicalElements::default();
    slow.velocity_filter_cutoff = Some(0.00016);
    let sliver = Loop::physical(&device, &slow).unwrap();
    g.bench_function("sliver behind a 0.16 mHz low-pass", |b| {
        b.iter(|| recommend(black_box(&sliver), &amax, 0.75).unwrap())
    });
    g.finish();

    // the conservative table of a device with m = 0.1 kg, T = 1 ms, b = 0 to 200 N s/m
    // (delta = 0 to 2 in 101 rows) at delays of 1 and 2 samples, bare and behind a 30 Hz
    // first-order low-pass velocity filter
    let mut g = c.benchmark_group("table");
    g.sample_size(10);
    let deltas: Vec<f64> = (0..=100).map(|i| 0.02 * f64::from(i)).collect();
    let ds = [1.0, 2.0];
    let conservative = TableOptions::new(amax).with_conservative(true);
    g.bench_function("101x2 conservative, bare", |b| {
        b.iter(|| amax_table(black_box(&deltas), &ds, &conservative).unwrap())
    });
    let filter = VelocityFilter::low_pass_cutoff(30.0, 1e-3).unwrap();
    let filtered = conservative
        .clone()
        .with_elements(Loop::new(plant).with_filter(filter).unwrap());
    g.bench_function("101x2 conservative, 30 Hz low-pass", |b| {
        b.iter(|| amax_table(black_box(&deltas), &ds, &filtered).unwrap())
    });
    g.finish();

    let mut g = c.benchmark_group("boundary");
    g.sample_size(20);
    g.bench_function("bare", |b| {
        b.iter(|| exact(black_box(&plant), &tol).unwrap())
    });
    g.bench_function("bare, general route", |b| {
        b.iter(|| exact(black_box(&Loop::new(plant)), &tol).unwrap())
    });
    for (name, lp) in loops(plant) {
        g.bench_function(name, |b| b.iter(|| exact(black_box(&lp), &tol).unwrap()));
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
