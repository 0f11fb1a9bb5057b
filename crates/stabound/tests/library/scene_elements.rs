//! Scene devices that name loop elements: only what is named is modelled, the report says
//! which, its numbers match the loop built here from normalized values computed by hand
//! (checked by point tests of the eigenvalues of the closed loop's state matrix), and
//! invalid values are refused with the device named.

use stabound::elements::{Encoder, Hand, Loop, PhysicalElements, Transmission};
use stabound::filter::VelocityFilter;
use stabound::params::{Plant, Wall};
use stabound::scene::{Scene, SceneFormat};
use stabound::stability::Checker;
use stabound::stability::{Options, eigenvalues_capped, spectral_radius};

const HEAD: &str =
    "[[device]]\nmass_kg = 0.1\nperiod_s = 0.001\ndamping_Ns_per_m = 20.0\ndelay_samples = 1\n";
const WALL: &str = "[[device.wall]]\nstiffness_N_per_m = 3000.0\ndamping_Ns_per_m = 15.0\n";

fn scene(extra: &str) -> stabound::Result<Scene> {
    Scene::parse(
        &format!("{HEAD}{extra}\n{WALL}"),
        SceneFormat::Toml,
        "test.toml",
    )
}

/// The radius of the state matrix's eigenvalues (built from the sampled device and the wall
/// law, not from the polynomial) at `wall`.
fn radius(lp: &Loop, wall: &Wall) -> f64 {
    let c = Checker::new(lp, Options::default()).unwrap();
    spectral_radius(&eigenvalues_capped(c.state_matrix(wall)).unwrap())
}

/// A hand and a 30 Hz filter named: the report lists exactly those, and K_lim(B) sits on
/// the edge of the loop built here with mu = m_h / m, delta_h = b_h T / m, kappa_h =
/// k_h T^2 / m and a = exp(-2 pi f_c T): the state matrix's radius is below 1 just inside
/// (1e-6 relative) and above just outside.
#[test]
fn named_elements_are_modelled_and_reported() {
    let s = scene(
        "hand_mass_kg = 0.05\nhand_damping_Ns_per_m = 2.0\nhand_stiffness_N_per_m = 100.0\nvelocity_filter_cutoff_Hz = 30.0",
    )
    .unwrap();
    let r = s.check(&Options::default()).unwrap();
    let dev = &r.devices[0];
    assert_eq!(dev.elements, ["hand", "low-pass velocity filter"]);
    assert!(
        r.to_text()
            .contains("elements modelled: hand, low-pass velocity filter")
    );
    let (m, t) = (0.1, 0.001);
    let lp = Loop::new(Plant::new(20.0 * t / m, 1.0).unwrap())
        .with_hand(Hand::new(0.05 / m, 2.0 * t / m, 100.0 * t * t / m).unwrap())
        .unwrap()
        .with_filter(
            VelocityFilter::low_pass((-2.0 * std::f64::consts::PI * 30.0 * t).exp()).unwrap(),
        )
        .unwrap();
    let w = &dev.walls[0];
    let a = w.alpha_limit.unwrap();
    assert!(radius(&lp, &Wall::new(a * (1.0 - 1e-6), w.beta).unwrap()) < 1.0);
    assert!(radius(&lp, &Wall::new(a * (1.0 + 1e-6), w.beta).unwrap()) > 1.0);
    let rho = radius(&lp, &Wall::new(w.alpha, w.beta).unwrap());
    assert!(
        (w.spectral_radius - rho).abs() < 1e-9,
        "{} vs {rho}",
        w.spectral_radius
    );
    for i in &w.damping_intervals {
        for (b, inside) in [(i.lo_normalized, 1.0), (i.hi_normalized, -1.0)] {
            let db = 1e-6 * b.abs().max(1e-3);
            assert!(radius(&lp, &Wall::new(w.alpha, b + inside * db).unwrap()) < 1.0);
            assert!(radius(&lp, &Wall::new(w.alpha, b - inside * db).unwrap()) > 1.0);
        }
    }
    // K_max: the wall at (alpha_max, beta*) is on the edge too
    let mx = dev.max_stiffness.unwrap();
    assert!(radius(&lp, &Wall::new(mx.alpha * (1.0 + 1e-6), mx.beta).unwrap()) > 1.0);
    assert!(radius(&lp, &Wall::new(mx.alpha * (1.0 - 1e-6), mx.beta).unwrap()) < 1.0);
}

/// Only what the scene names: a filter alone leaves the rigid one-mass device, and the
/// limit is the filtered loop's, below the bare device's. A transmission named is modelled
/// with its encoder side.
#[test]
fn only_what_is_named_is_modelled() {
    let bare = scene("").unwrap().check(&Options::default()).unwrap();
    assert!(bare.devices[0].elements.is_empty());
    assert!(!bare.to_text().contains("elements modelled"));
    let json = serde_json::to_string(&bare).unwrap();
    assert!(!json.contains("elements"), "{json}");
    let f = scene("velocity_filter_samples = 4").unwrap();
    let rf = f.check(&Options::default()).unwrap();
    assert_eq!(rf.devices[0].elements, ["moving-average velocity filter"]);
    let lp = Loop::new(Plant::new(0.2, 1.0).unwrap())
        .with_filter(VelocityFilter::moving_average(4).unwrap())
        .unwrap();
    let a = rf.devices[0].walls[0].alpha_limit.unwrap();
    let b = rf.devices[0].walls[0].beta;
    assert!(radius(&lp, &Wall::new(a * (1.0 - 1e-6), b).unwrap()) < 1.0);
    assert!(radius(&lp, &Wall::new(a * (1.0 + 1e-6), b).unwrap()) > 1.0);
    assert!(a < bare.devices[0].walls[0].alpha_limit.unwrap());
    let t =
        scene("handle_mass_kg = 0.03\ntransmission_stiffness_N_per_m = 4e4\nencoder = \"handle\"")
            .unwrap();
    let named = t.devices[0].elements;
    assert_eq!(named.handle_mass, Some(0.03));
    assert_eq!(named.encoder, Some(Encoder::Handle));
    assert_eq!(
        (named.hand_mass, named.actuator_time_constant),
        (None, None)
    );
    let rt = t.check(&Options::default()).unwrap();
    assert_eq!(
        rt.devices[0].elements,
        ["transmission (encoder on the handle)"]
    );
    let lp = Loop::new(Plant::new(0.2, 1.0).unwrap())
        .with_transmission(
            Transmission::new(0.3, 4e4 * 1e-6 / 0.1, 0.0, 0.0, Encoder::Handle).unwrap(),
        )
        .unwrap();
    let w = &rt.devices[0].walls[0];
    let a = w.alpha_limit.unwrap();
    assert!(radius(&lp, &Wall::new(a * (1.0 - 1e-6), w.beta).unwrap()) < 1.0);
    assert!(radius(&lp, &Wall::new(a * (1.0 + 1e-6), w.beta).unwrap()) > 1.0);
}

/// Values no loop accepts are refused at parse time, naming the device and saying why.
#[test]
fn invalid_elements_are_refused() {
    for (extra, says) in [
        ("hand_mass_kg = -0.1", "0 or more"),
        (
            "handle_mass_kg = 0.2\ntransmission_stiffness_N_per_m = 1e4",
            "below the device",
        ),
        ("handle_mass_kg = 0.02", "both the handle mass"),
        ("velocity_filter_cutoff_Hz = 600.0", "Nyquist"),
        ("velocity_filter_samples = 0", "at least 1"),
        (
            "velocity_filter_samples = 3\nvelocity_filter_cutoff_Hz = 30.0",
            "one velocity filter",
        ),
        ("encoder = \"middle\"", "unknown variant"),
        ("actuator_time_constant_s = 0.0", "greater than 0"),
    ] {
        let err = scene(extra).unwrap_err().to_string();
        assert!(err.contains(says), "{extra}: {err}");
        assert!(err.contains("test.toml"), "{extra}: {err}");
    }
}

/// The elements' serde form carries the unit in every key and refuses what no device could
/// accept (through `try_from`), and what it writes it reads back.
#[test]
fn physical_elements_serde_round_trip_and_refusals() {
    let e: PhysicalElements =
        serde_json::from_str(r#"{"hand_mass_kg": 0.2, "velocity_filter_cutoff_Hz": 30.0}"#)
            .unwrap();
    assert_eq!(e.hand_mass, Some(0.2));
    assert_eq!(e.velocity_filter_cutoff, Some(30.0));
    let back: PhysicalElements = serde_json::from_str(&serde_json::to_string(&e).unwrap()).unwrap();
    assert_eq!(back, e);
    for bad in [
        r#"{"hand_mass_kg": -1.0}"#,
        r#"{"velocity_filter_samples": 0}"#,
        r#"{"handle_mass_kg": 0.02}"#,
        r#"{"hand_mass": 0.2}"#,
    ] {
        assert!(
            serde_json::from_str::<PhysicalElements>(bad).is_err(),
            "{bad}"
        );
    }
}
