//! Checking a scene of 1000 walls (a realistic large scene). Walls are
//! spread over the stable and unstable parts of the paper's Section VIII device (m = 0.1 kg,
//! T = 1 ms, one sample of delay, b = 0, 10, 100 N s/m). Parsing is measured separately.
//! Run with `cargo bench --bench scene`.

use criterion::{Criterion, criterion_group, criterion_main};
use stabound::scene::{Scene, SceneFormat};
use stabound::stability::Options;
use std::hint::black_box;

fn scene_text(walls: usize) -> String {
    let mut s = String::new();
    let per_device = walls / 3;
    for b in [0.0, 10.0, 100.0] {
        s.push_str(&format!(
            "[[device]]\nmass_kg = 0.1\nperiod_s = 0.001\ndamping_Ns_per_m = {b}\ndelay_samples = 1\n"
        ));
        for i in 0..per_device + usize::from(b == 0.0) * (walls - 3 * per_device) {
            // K from 1 to 100 kN/m, B from -20 to 120 N s/m, on a deterministic scatter.
            let k = 1000.0 + (i as f64 * 0.618_034).fract() * 99_000.0;
            let bw = -20.0 + (i as f64 * 0.414_214).fract() * 140.0;
            s.push_str(&format!(
                "[[device.wall]]\nstiffness_N_per_m = {k}\ndamping_Ns_per_m = {bw}\n"
            ));
        }
    }
    s
}

fn bench(c: &mut Criterion) {
    let text = scene_text(1000);
    let scene = Scene::parse(&text, SceneFormat::Toml, "bench").unwrap();
    assert_eq!(scene.wall_count(), 1000);
    let options = Options::default();
    let mut g = c.benchmark_group("scene");
    g.bench_function("check_1000_walls", |b| {
        b.iter(|| scene.check(black_box(&options)).unwrap())
    });
    g.bench_function("parse_1000_walls", |b| {
        b.iter(|| Scene::parse(black_box(&text), SceneFormat::Toml, "bench").unwrap())
    });
    g.finish();

    // The parts of one wall's check, for the paper's wall on the undamped device.
    let plant = stabound::params::Plant::new(0.0, 1.0).unwrap();
    let checker = stabound::stability::Checker::new(plant, options).unwrap();
    let wall = stabound::params::Wall::new(0.108, 0.425).unwrap();
    let mut g = c.benchmark_group("scene_wall_parts");
    g.bench_function("verdict", |b| b.iter(|| checker.verdict(black_box(&wall))));
    g.bench_function("spectral_radius", |b| {
        b.iter(|| checker.spectral_radius_schur_cohn(black_box(&wall)))
    });
    g.bench_function("stable_alphas", |b| {
        b.iter(|| stabound::search::stable_alphas(&checker, black_box(wall.beta())))
    });
    g.bench_function("stable_betas", |b| {
        b.iter(|| stabound::search::stable_betas(&checker, black_box(wall.alpha())))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
