//! Every number `Scene::check` reports, against independent computations: verdicts and
//! spectral radii against companion-matrix eigenvalues, `K_lim` and the damping interval ends
//! against eigenvalue point tests just inside and just outside, results against a
//! single-threaded run.

use stabound::params::{Plant, Wall};
use stabound::scene::{Scene, SceneFormat, SceneReport};
use stabound::stability::{Checker, Method, Options, Verdict, spectral_radius};

/// Walls around the edge of stability for several devices, delays fractional included.
fn scene_text() -> String {
    let mut s = String::new();
    let devices = [
        // (mass kg, period s, b N s/m, delay key)
        (0.1, 1e-3, 0.0, "delay_samples = 1"),
        (0.1, 1e-3, 10.0, "delay_s = 0.001"),
        (0.1, 1e-3, 100.0, "delay_samples = 1"),
        (0.5, 5e-4, 2.0, "delay_samples = 0"),
        (0.2, 1e-3, 30.0, "delay_s = 0.0025"),
        (1.0, 1e-3, 5.0, "delay_samples = 3"),
    ];
    for (m, t, b, delay) in devices {
        s.push_str(&format!(
            "[[device]]\nmass_kg = {m}\nperiod_s = {t}\ndamping_Ns_per_m = {b}\n{delay}\n"
        ));
        // alpha from 0.01 to 1.2, beta from -0.2 to 1.0, in physical units for this device
        for i in 0..6 {
            for j in 0..5 {
                let alpha = 0.01 + 0.24 * i as f64;
                let beta = -0.2 + 0.3 * j as f64;
                let k = alpha * m / (t * t);
                let bw = beta * m / t;
                s.push_str(&format!(
                    "[[device.wall]]\nstiffness_N_per_m = {k}\ndamping_Ns_per_m = {bw}\n"
                ));
            }
        }
    }
    s
}

fn report() -> (Scene, SceneReport) {
    let scene = Scene::parse(&scene_text(), SceneFormat::Toml, "test").unwrap();
    let r = scene.check(&Options::default()).unwrap();
    (scene, r)
}

fn eigen(plant: &Plant) -> Checker {
    Checker::new(
        plant,
        Options {
            method: Method::Eigen,
            ..Options::default()
        },
    )
    .unwrap()
}

/// Spectral radius by companion eigenvalues.
fn rho(e: &Checker, alpha: f64, beta: f64) -> f64 {
    let roots = e
        .roots(&Wall::new(alpha, beta).unwrap(), Method::Eigen)
        .unwrap();
    spectral_radius(&roots)
}

#[test]
fn every_number_agrees_with_eigenvalues() {
    let (scene, r) = report();
    let mut with_limit = 0;
    let mut with_interval = 0;
    for (dev, dr) in scene.devices.iter().zip(&r.devices) {
        let plant = dev.device.plant().unwrap();
        let e = eigen(&plant);
        for w in &dr.walls {
            let wall = Wall::new(w.alpha, w.beta).unwrap();
            let roots = e.roots(&wall, Method::Eigen).unwrap();
            let radius = spectral_radius(&roots);
            // Schur-Cohn bisection stops at 1e-13 relative; eigenvalues of these low degrees
            // are accurate to about 1e-13 as well: 1e-9 is wide of both.
            assert!((w.spectral_radius - radius).abs() < 1e-9, "{w:?} {radius}");
            assert_eq!(w.verdict, e.verdict(&wall).unwrap(), "{w:?}");
            // K_lim: spectral radius below 1 just below, above 1 just above. The radius
            // itself, not the verdict: at small K_lim a relative step of 1e-6 moves the
            // crossing root by less than the 1e-9 marginal band, but by far more than the
            // ~1e-14 error of eigenvalues at these degrees.
            if let Some(a) = w.alpha_limit {
                with_limit += 1;
                assert!(rho(&e, a * (1.0 - 1e-6), w.beta) < 1.0, "{w:?}");
                assert!(rho(&e, a * (1.0 + 1e-6), w.beta) > 1.0, "{w:?}");
                assert!((w.stiffness_margin.unwrap() - w.alpha / a).abs() < 1e-15);
                let k = dev.device.stiffness(a);
                assert!((w.stiffness_limit.unwrap() - k).abs() <= 1e-12 * k);
            } else {
                // No stable stiffness at this B: the wall itself cannot be stable.
                assert_ne!(w.verdict, Verdict::Stable, "{w:?}");
            }
            // A single stable stretch of stiffness: margin below 1 exactly when stable.
            if w.stable_stiffness_pieces == 1 && w.verdict != Verdict::Marginal {
                assert_eq!(
                    w.stiffness_margin.unwrap() < 1.0,
                    w.verdict == Verdict::Stable,
                    "{w:?}"
                );
            }
            // Damping intervals: ends are boundaries, the wall is stable iff inside one.
            let inside = w
                .damping_intervals
                .iter()
                .any(|i| i.lo_normalized < w.beta && w.beta < i.hi_normalized);
            if w.verdict != Verdict::Marginal {
                assert_eq!(inside, w.verdict == Verdict::Stable, "{w:?}");
            }
            for i in &w.damping_intervals {
                with_interval += 1;
                let (lo, hi) = (i.lo_normalized, i.hi_normalized);
                let h = 1e-6 * (hi - lo);
                for (b, want) in [
                    (lo - h, false),
                    (lo + h, true),
                    (hi - h, true),
                    (hi + h, false),
                ] {
                    assert_eq!(rho(&e, w.alpha, b) < 1.0, want, "beta {b} {w:?}");
                }
                assert!((i.lo - dev.device.wall_damping(lo)).abs() <= 1e-12 * i.lo.abs());
            }
        }
    }
    // The sample must exercise both searches in earnest.
    assert!(
        with_limit > 60 && with_interval > 30,
        "{with_limit} {with_interval}"
    );
}

/// Same report with one thread as with the default pool (rayon collects in order).
#[test]
fn independent_of_threads() {
    let (scene, r) = report();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let one = pool.install(|| scene.check(&Options::default())).unwrap();
    assert_eq!(r, one);
}

/// A delay in seconds that is a whole number of samples up to division rounding is taken
/// as whole: 0.003 s / 0.001 s = 2.9999999999999996.
#[test]
fn whole_sample_delay_in_seconds() {
    let t = "[[device]]\nmass_kg = 0.1\nperiod_s = 0.001\ndamping_Ns_per_m = 0\ndelay_s = 0.003\n";
    let s = Scene::parse(t, SceneFormat::Toml, "t").unwrap();
    let p = s.devices[0].device.plant().unwrap();
    assert!(p.is_integer_delay());
    assert_eq!(p.degree(), 6);
}

#[test]
fn library_errors_are_invalid_request() {
    let err = Scene::parse("[[device]]\nmass_kg = 0\n", SceneFormat::Toml, "x.toml").unwrap_err();
    assert!(matches!(err, stabound::Error::InvalidRequest(_)), "{err:?}");
    assert!(err.to_string().starts_with("x.toml: line 2"), "{err}");
    let bad = Options {
        margin: f64::NAN,
        ..Options::default()
    };
    let s = Scene::parse(&scene_text(), SceneFormat::Toml, "t").unwrap();
    assert!(s.check(&bad).is_err());
}

/// The suggestion path with the published anchor for delta = 0, d = 0 (docs/MODEL.md section 6:
/// alpha_max = 12 - 8 sqrt 2 at beta* = 2 sqrt 2 - 2) as the limit source: B* and K_max in
/// physical units, the margin K / K_max, and the 1-D search's K_lim(B*) equal to the published
/// alpha_max (the search never sees the anchor).
#[test]
fn suggestion_from_published_anchor() {
    let s2 = 2f64.sqrt();
    let (amax, bstar) = (12.0 - 8.0 * s2, 2.0 * s2 - 2.0);
    let text = "[[device]]\nmass_kg = 0.2\nperiod_s = 0.002\ndamping_Ns_per_m = 0\n\
                delay_samples = 0\n[[device.wall]]\nstiffness_N_per_m = 20000\n\
                damping_Ns_per_m = 10\n";
    let scene = Scene::parse(text, SceneFormat::Toml, "t").unwrap();
    let r = scene
        .check_with(&Options::default(), |_, _| Ok(Some((amax, bstar))))
        .unwrap();
    let dev = &r.devices[0];
    let max = dev.max_stiffness.unwrap();
    // m / T^2 = 5e4 N/m, m / T = 100 N s/m
    assert!((max.stiffness - amax * 5e4).abs() < 1e-9);
    assert!((max.damping - bstar * 100.0).abs() < 1e-12);
    let w = &dev.walls[0];
    let g = w.suggested.unwrap();
    assert!((g.damping - bstar * 100.0).abs() < 1e-12);
    assert!((g.stiffness_margin - 0.4 / amax).abs() < 1e-15);
    let checker = Checker::new(Plant::new(0.0, 0.0).unwrap(), Options::default()).unwrap();
    let lim = stabound::search::alpha_limit(&checker, bstar)
        .unwrap()
        .unwrap();
    assert!((lim - amax).abs() < 1e-9, "{lim}");
}

/// The reported maximum stiffness and suggested damping agree with the 1-D searches:
/// `K_lim(B*)` equals `K_max` (alpha_max is the largest `K_lim`), no wall's `K_lim` exceeds
/// it, and `B*` lies in the damping interval of every stiffness below `K_max`.
#[test]
fn suggestion_agrees_with_alpha_max() {
    let (_, r) = report();
    for dev in &r.devices {
        let max = dev.max_stiffness.expect("check() computes alpha_max");
        let plant = Plant::new(dev.delta, dev.d).unwrap();
        let sc = Checker::new(plant, Options::default()).unwrap();
        let lim = stabound::search::alpha_limit(&sc, max.beta)
            .unwrap()
            .unwrap();
        // alpha_max is accurate to 1e-10 relative, the search to rounding: 1e-8 leaves room
        // for the flatness of K_lim(B) at its maximum.
        assert!(
            (lim - max.alpha).abs() <= 1e-8 * max.alpha,
            "{lim} vs {}",
            max.alpha
        );
        for w in &dev.walls {
            if let Some(a) = w.alpha_limit {
                assert!(a <= max.alpha * (1.0 + 1e-9), "{} > {}", a, max.alpha);
            }
            let s = w.suggested.unwrap();
            assert!((s.stiffness_margin - w.alpha / max.alpha).abs() < 1e-12);
            if w.alpha > 0.0 && w.alpha < 0.999 * max.alpha {
                assert!(
                    w.damping_intervals
                        .iter()
                        .any(|i| i.lo_normalized < s.beta && s.beta < i.hi_normalized),
                    "beta* {} outside {:?}",
                    s.beta,
                    w.damping_intervals
                );
            }
        }
    }
}

/// The passive line of each wall against the closed-form delay bound of Diolaiti et al.:
/// with no virtual damping a wall is passive iff `K < 2 b / (T + 2 t_d)`, here
/// `b = 100 N s/m`, `T = t_d = 1 ms`: `K < 66,666.7 N/m`. A fractional delay has no answer.
#[test]
fn passive_per_wall_matches_the_delay_bound() {
    let wall = |k: f64| {
        format!("[[device.wall]]\nname = \"w\"\nstiffness_N_per_m = {k}\ndamping_Ns_per_m = 0\n")
    };
    let device = "[[device]]\nmass_kg = 0.1\nperiod_s = 0.001\ndamping_Ns_per_m = 100\n";
    let t = format!(
        "{device}delay_samples = 1\n{}{}{device}delay_samples = 1.5\n{}",
        wall(66_000.0),
        wall(67_300.0),
        wall(1000.0)
    );
    let s = Scene::parse(&t, SceneFormat::Toml, "t").unwrap();
    let r = s.check(&Options::default()).unwrap();
    let passive: Vec<Option<bool>> = r
        .devices
        .iter()
        .flat_map(|d| d.walls.iter().map(|w| w.passive))
        .collect();
    assert_eq!(passive, [Some(true), Some(false), None]);
    assert!(
        r.to_text()
            .contains("passive: not defined for a fractional delay")
    );
}
