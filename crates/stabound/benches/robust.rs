//! The cost of a robust `alpha_max` over a set of devices against what it examines: one
//! member's `alpha_max` and one member's exact stable set (the unit of the search and of the
//! sampling argument), then the robust optimum of a delay interval, of a delay list (a
//! finite set), of a hand that can let go, and of a hand-mass interval. The number of members
//! each examines is printed, so the time per member can be read off. Then the proof alone
//! ([`prove_wall`]) of each set's verified wall over a box of mass and damping, over a
//! delay interval, over a velocity filter's cutoff, over an actuator lag's time constant,
//! over both at once and over a delay interval behind a
//! filter, with the cells it examines printed. Run with
//! `cargo bench -p stabound --bench robust`.

use criterion::{Criterion, criterion_group, criterion_main};
use stabound::elements::PhysicalElements;
use stabound::params::{Delay, Device, Wall};
use stabound::robust::{DeviceSet, PROOF_BUDGET, Quantity, prove_wall, robust_alpha_max};
use stabound::search::stable_alphas;
use stabound::stability::{Checker, Options};
use stabound::{AmaxOptions, alpha_max};
use std::hint::black_box;

fn sets() -> Vec<(&'static str, DeviceSet)> {
    let paper = Device::new(1.0, 1.0, 0.5, Delay::Samples(1.0)).unwrap();
    let none = PhysicalElements::default();
    let device = Device::new(0.1, 1e-3, 1.0, Delay::Samples(1.0)).unwrap();
    let mut hand = PhysicalElements::default();
    hand.hand_mass = Some(0.2);
    hand.hand_stiffness = Some(300.0);
    vec![
        (
            "delay 1..3",
            DeviceSet::new(&paper, &none)
                .unwrap()
                .with_interval(Quantity::Delay, 1.0, 3.0)
                .unwrap(),
        ),
        (
            "delay one of 1, 2, 3",
            DeviceSet::new(&paper, &none)
                .unwrap()
                .with_values(Quantity::Delay, &[1.0, 2.0, 3.0])
                .unwrap(),
        ),
        ("hand on or off", DeviceSet::new(&device, &hand).unwrap()),
        (
            "hand mass 0.2..0.5, on or off",
            DeviceSet::new(&device, &hand)
                .unwrap()
                .with_interval(Quantity::element("hand_mass").unwrap(), 0.2, 0.5)
                .unwrap(),
        ),
    ]
}

fn bench(c: &mut Criterion) {
    let opts = AmaxOptions::default();
    let paper = Device::new(1.0, 1.0, 0.5, Delay::Samples(3.0)).unwrap();
    let plant = paper.plant().unwrap();
    let checker = Checker::new(plant, Options::default()).unwrap();
    let mut g = c.benchmark_group("robust");
    g.bench_function("one member: alpha_max (paper, d = 3)", |b| {
        b.iter(|| alpha_max(black_box(plant), &opts).unwrap())
    });
    g.bench_function("one member: stable set at one beta (paper, d = 3)", |b| {
        b.iter(|| stable_alphas(black_box(&checker), 0.3).unwrap())
    });
    for (name, set) in sets() {
        let r = robust_alpha_max(&set, &opts).unwrap();
        eprintln!(
            "{name}: {} members examined, {}",
            r.examined,
            r.verification.describe()
        );
        g.bench_function(format!("robust alpha_max: {name}"), |b| {
            b.iter(|| robust_alpha_max(black_box(&set), &opts).unwrap())
        });
    }
    for (name, set) in proof_sets() {
        let r = robust_alpha_max(&set, &opts).unwrap();
        let wall = Wall::new(r.alpha_verified, r.beta_at_max).unwrap();
        let p = prove_wall(&set, &wall, PROOF_BUDGET).unwrap().unwrap();
        eprintln!(
            "prove {name}: proved {}, {} cells examined",
            p.proved, p.evaluated
        );
        g.bench_function(format!("prove_wall at the verified optimum: {name}"), |b| {
            b.iter(|| prove_wall(black_box(&set), &wall, PROOF_BUDGET).unwrap())
        });
    }
    g.finish();
}

/// The sets whose verified optimum the proof alone is timed on: a box of mass and damping
/// (0.1 kg class device at 1 kHz), the paper's device with its delay over 1..3 samples, and
/// a 0.1 kg device with a first-order velocity filter whose cutoff spreads over 30..60 Hz,
/// with an actuator lag whose time constant spreads over 0.3..0.6 ms, with both spread at
/// once, or with a 50 Hz filter and the delay over 1..3 samples.
fn proof_sets() -> Vec<(&'static str, DeviceSet)> {
    let none = PhysicalElements::default();
    let filtered = |fc: f64| {
        let mut e = PhysicalElements::default();
        e.velocity_filter_cutoff = Some(fc);
        e
    };
    let mut filtered_and_lagged = filtered(30.0);
    filtered_and_lagged.actuator_time_constant = Some(3e-4);
    let held = Device::new(0.1, 1e-3, 1.0, Delay::Samples(1.0)).unwrap();
    let device = Device::new(0.09, 1e-3, 0.5, Delay::Samples(1.0)).unwrap();
    let paper = Device::new(1.0, 1.0, 0.5, Delay::Samples(1.0)).unwrap();
    // the set with `keyword` over `[lo, hi]` more
    let spread = |s: DeviceSet, keyword: &str, lo: f64, hi: f64| {
        s.with_interval(Quantity::element(keyword).unwrap(), lo, hi)
            .unwrap()
    };
    let cutoffs = |s: DeviceSet| spread(s, "velocity_filter_cutoff", 30.0, 60.0);
    let lags = |s: DeviceSet| spread(s, "actuator_time_constant", 3e-4, 6e-4);
    let mut lagged = PhysicalElements::default();
    lagged.actuator_time_constant = Some(3e-4);
    vec![
        (
            "mass 0.09..0.11 x damping 0.5..1",
            DeviceSet::new(&device, &none)
                .unwrap()
                .with_interval(Quantity::Mass, 0.09, 0.11)
                .unwrap()
                .with_interval(Quantity::Damping, 0.5, 1.0)
                .unwrap(),
        ),
        (
            "delay 1..3",
            DeviceSet::new(&paper, &none)
                .unwrap()
                .with_interval(Quantity::Delay, 1.0, 3.0)
                .unwrap(),
        ),
        (
            "filter cutoff 30..60 Hz",
            cutoffs(DeviceSet::new(&held, &filtered(30.0)).unwrap()),
        ),
        (
            "actuator lag 0.3..0.6 ms",
            lags(DeviceSet::new(&held, &lagged).unwrap()),
        ),
        (
            "filter cutoff 30..60 Hz x actuator lag 0.3..0.6 ms",
            lags(cutoffs(
                DeviceSet::new(&held, &filtered_and_lagged).unwrap(),
            )),
        ),
        (
            "delay 1..3 behind a 50 Hz filter",
            DeviceSet::new(&held, &filtered(50.0))
                .unwrap()
                .with_interval(Quantity::Delay, 1.0, 3.0)
                .unwrap(),
        ),
    ]
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10);
    targets = bench
}
criterion_main!(benches);
