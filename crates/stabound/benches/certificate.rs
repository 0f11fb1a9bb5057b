//! One certified verdict (enclosures, interval Schur-Cohn, JSON) at short and long delays,
//! and a marginal wall (three recursions); d = 30 is near the longest delay `f64` intervals
//! certify; and loops with elements (the enclosed matrix exponential): a hand and a low-pass
//! filter, and every element with a second-order filter; and boxes of walls certified stable
//! (every leaf of the bisection, and the JSON); a certified 101 x 2 lookup table, and an
//! 11-node table of a loop with a low-pass velocity filter; and one row of `amax --certify`
//! on a loop with elements. Run with `cargo bench --bench certificate`.

use criterion::{Criterion, criterion_group, criterion_main};
use stabound::alpha_max;
use stabound::amax::{AmaxOptions, AmaxTable, TableOptions, amax_table};
use stabound::certificate::{
    BoxClaim, DEFAULT_CELL_BOXES, WallBox, certify, certify_alpha_max, certify_box, certify_table,
};
use stabound::elements::{Actuator, Encoder, Hand, Loop, Transmission};
use stabound::filter::VelocityFilter;
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
    let plant = Plant::new(0.0005, 1.5).unwrap();
    let hand = Loop::new(plant)
        .with_hand(Hand::new(0.3, 0.002, 3e-4).unwrap())
        .and_then(|l| l.with_filter(VelocityFilter::low_pass(0.83).unwrap()))
        .unwrap();
    let all = hand
        .with_transmission(Transmission::new(0.2, 1.0, 0.05, 0.0, Encoder::Motor).unwrap())
        .and_then(|l| l.with_actuator(Actuator::new(0.2).unwrap()))
        .and_then(|l| l.with_filter(VelocityFilter::butterworth(0.1).unwrap()))
        .unwrap();
    let wall = Wall::new(0.001, 0.005).unwrap();
    for (name, lp) in [("hand+low-pass", hand), ("all elements", all)] {
        c.bench_function(&format!("certify {name} d=1.5"), |b| {
            b.iter(|| certify(black_box(lp), &wall, 1e-9).unwrap().to_json().len())
        });
    }
}

fn boxes(c: &mut Criterion) {
    let plant = Plant::new(0.5, 1.0).unwrap();
    for (lo, hi) in [((0.1, 0.25), (0.12, 0.3)), ((0.1, 0.2), (0.2, 0.4))] {
        let walls = WallBox::new(
            Wall::new(lo.0, lo.1).unwrap(),
            Wall::new(hi.0, hi.1).unwrap(),
        )
        .unwrap();
        let cert = certify_box(plant, &walls, 4096).unwrap();
        assert_eq!(cert.claim(), BoxClaim::Stable);
        let leaves = cert.counts().0;
        c.bench_function(
            &format!("certify box alpha {lo:?}..{hi:?} d=1 ({leaves} leaves)"),
            |b| {
                b.iter(|| {
                    certify_box(black_box(&plant), &walls, 4096)
                        .unwrap()
                        .to_json()
                        .len()
                })
            },
        );
    }
}

/// Boxes of walls on a loop with elements at 1 ms (a hand and a 30 Hz low-pass, 1.5
/// samples of delay), decided around their leaves' centres: K in [900, 900.01] N/m with B
/// in [2, 2.01] N s/m (one leaf), and K in [1000, 1500] with B in [2, 3] (a few leaves).
fn element_boxes(c: &mut Criterion) {
    let lp = Loop::new(Plant::new(0.0005, 1.5).unwrap())
        .with_hand(Hand::new(0.3, 0.002, 3e-4).unwrap())
        .and_then(|l| l.with_filter(VelocityFilter::low_pass_cutoff(30.0, 1e-3).unwrap()))
        .unwrap();
    for (k, b) in [
        ((900.0, 900.01), (2.0, 2.01)),
        ((1000.0, 1500.0), (2.0, 3.0)),
    ] {
        let wall = |k: f64, b: f64| Wall::new(k * 1e-6, b * 1e-3).unwrap();
        let walls = WallBox::new(wall(k.0, b.0), wall(k.1, b.1)).unwrap();
        let cert = certify_box(lp, &walls, 4096).unwrap();
        assert_eq!(cert.claim(), BoxClaim::Stable);
        let leaves = cert.counts().0;
        c.bench_function(
            &format!("certify box hand+low-pass 1 ms K {k:?} B {b:?} ({leaves} leaves)"),
            |bench| {
                bench.iter(|| {
                    certify_box(black_box(lp), &walls, 4096)
                        .unwrap()
                        .to_json()
                        .len()
                })
            },
        );
    }
}

/// A certified conservative table of 101 x 2 nodes (delta 0.5..1.5 in steps of 0.01, d = 1
/// and 2): the table's construction outside the timing, the certificate (every cell's boxes,
/// the lowering, the JSON) inside.
fn table(c: &mut Criterion) {
    let deltas: Vec<f64> = (0..=100).map(|k| 0.5 + f64::from(k) / 100.0).collect();
    let opts = TableOptions::new(AmaxOptions::default()).with_conservative(true);
    let t = amax_table(&deltas, &[1.0, 2.0], &opts).unwrap();
    bench_table(c, "101 x 2 delta 0.5..1.5 d 1,2", &t);
}

/// A certified conservative table of a loop with a velocity filter: a 0.1 kg device at 1 ms,
/// one sample of delay, b = 0 to 100 N s/m in 11 nodes (delta 0 to 1), a 30 Hz first-order
/// low-pass; the table's construction outside the timing, the certificate inside.
fn filtered_table(c: &mut Criterion) {
    let deltas: Vec<f64> = (0..=10).map(|k| f64::from(k) / 10.0).collect();
    let lp = Loop::new(Plant::new(0.0, 1.0).unwrap())
        .with_filter(VelocityFilter::low_pass_cutoff(30.0, 1e-3).unwrap())
        .unwrap();
    let opts = TableOptions::new(AmaxOptions::default())
        .with_conservative(true)
        .with_elements(lp);
    let t = amax_table(&deltas, &[1.0], &opts).unwrap();
    bench_table(c, "11 x 1 low-pass 30 Hz delta 0..1 d 1", &t);
}

/// Times the certificate of `t` (every cell's boxes, the lowering, the JSON), 10 samples.
fn bench_table(c: &mut Criterion, name: &str, t: &AmaxTable) {
    let (cells, boxes) = certify_table(t, DEFAULT_CELL_BOXES).unwrap().counts();
    let mut group = c.benchmark_group("certified table");
    group.sample_size(10);
    group.bench_function(format!("{name} ({cells} cells, {boxes} boxes)"), |b| {
        b.iter(|| {
            certify_table(black_box(t), DEFAULT_CELL_BOXES)
                .unwrap()
                .to_json()
                .len()
        })
    });
    group.finish();
}

/// One row of `amax --certify` with elements, as the command line runs it: alpha_max of a
/// loop with a hand and a 30 Hz low-pass at 1 ms (1 kg, b = 0.5 N s/m, 1.5 samples of
/// delay; walls with 0 to 10 N s/m of damping), the stable wall below it, the unstable
/// strip above it (4096 leaves at most) and the JSON.
fn amax_elements(c: &mut Criterion) {
    let lp = Loop::new(Plant::new(0.0005, 1.5).unwrap())
        .with_hand(Hand::new(0.3, 0.002, 3e-4).unwrap())
        .and_then(|l| l.with_filter(VelocityFilter::low_pass_cutoff(30.0, 1e-3).unwrap()))
        .unwrap();
    let betas = (0.0, 0.01);
    let opts = AmaxOptions::default()
        .with_beta_limits(Some(betas.0), Some(betas.1))
        .unwrap();
    c.bench_function("certify amax hand+low-pass 1 ms B 0..10", |b| {
        b.iter(|| {
            let amax = alpha_max(black_box(lp), &opts).unwrap();
            certify_alpha_max(lp, &amax, betas, 4096)
                .unwrap()
                .to_json()
                .len()
        })
    });
}

criterion_group!(
    benches,
    bench,
    boxes,
    element_boxes,
    table,
    filtered_table,
    amax_elements
);
criterion_main!(benches);
