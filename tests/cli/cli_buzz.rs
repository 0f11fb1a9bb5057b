//! `stabound check` with an encoder, a force resolution or friction named: the buzz block.

use stabound::buzz::{BuzzOptions, Nonlinear, buzz, describing_function};
use stabound::elements::Loop;
use stabound::params::{Delay, Device};

use crate::common::{assert_bad_input, stdout};

/// m = 0.1 kg, T = 1 ms, b = 10 N s/m (delta = 0.1), one sample of delay, B = 30 N s/m
/// (beta = 0.3), K = 17000 N/m (alpha = 0.17: linearly stable, ray margin s* about 1.14).
const DEVICE: [&str; 13] = [
    "check",
    "--mass",
    "0.1",
    "--period",
    "0.001",
    "--damping",
    "10",
    "--stiffness",
    "17000",
    "--wall-damping",
    "30",
    "--delay-samples",
    "1",
];

fn json(args: &[&str]) -> serde_json::Value {
    crate::common::json(&[&DEVICE[..], args, &["--format", "json"]].concat())
}

/// The block reports what the library's protocol and describing function give for the same
/// device, wall and quantizers; without a quantizer or friction there is no block.
#[test]
fn json_block_matches_the_library() {
    assert!(json(&[]).get("buzz").is_none());
    let device = Device::new(0.1, 1e-3, 10.0, Delay::Samples(1.0)).unwrap();
    for (flags, named) in [
        (
            vec!["--encoder-resolution", "1e-5"],
            (Some(1e-5), None, None, None),
        ),
        (
            vec![
                "--encoder-resolution",
                "1e-5",
                "--coulomb-friction",
                "0.02",
                "--static-friction",
                "0.03",
            ],
            (Some(1e-5), None, Some(0.02), Some(0.03)),
        ),
        (
            vec!["--force-resolution", "0.01", "--coulomb-friction", "0.005"],
            (None, Some(0.01), Some(0.005), None),
        ),
    ] {
        let got = json(&flags);
        let b = &got["buzz"];
        let mut n = Nonlinear::default();
        (
            n.encoder_resolution,
            n.force_resolution,
            n.coulomb_friction,
            n.static_friction,
        ) = named;
        let q = n.normalize(&device, 17000.0).unwrap();
        let wall = device.wall(17000.0, 30.0).unwrap();
        let lp = Loop::new(device.plant().unwrap());
        let want = buzz(lp, &wall, &q, &BuzzOptions::default()).unwrap();
        let df = describing_function(lp, &wall).unwrap();
        assert_eq!(b["sustained"], want.sustained(), "{flags:?}");
        assert_eq!(
            b["peak_counts"].as_f64().unwrap(),
            want.peak_counts(),
            "{flags:?}"
        );
        assert_eq!(
            b["period_samples"].as_u64().map(|p| p as usize),
            want.period_samples(),
            "{flags:?}"
        );
        assert_eq!(b["runs"].as_array().unwrap().len(), 4);
        assert_eq!(
            b["describing_function"]["ray_margin"].as_f64(),
            df.ray_margin
        );
        assert_eq!(
            b["describing_function"]["predicts_buzz"],
            df.predicts_buzz()
        );
    }
    // the encoder alone on this wall (s* about 1.14): the exact simulation buzzes
    assert_eq!(
        json(&["--encoder-resolution", "1e-5"])["buzz"]["sustained"],
        true
    );
}

/// The text report shows the verdict, each start and the estimate.
#[test]
fn text_report_shows_buzz() {
    let out = stdout(&[&DEVICE[..], &["--encoder-resolution", "1e-5"]].concat());
    let text = String::from_utf8(out).unwrap();
    assert!(text.contains("buzz: sustained"), "{text}");
    assert!(text.contains("from rest at 3 counts"), "{text}");
    assert!(
        text.contains("describing function: ray margin s* = "),
        "{text}"
    );
}

/// Bad values and combinations exit 2 with one line.
#[test]
fn refuses_bad_quantizers() {
    for flags in [
        vec!["--encoder-resolution", "-1e-5"],
        vec!["--encoder-resolution", "0"],
        vec!["--coulomb-friction", "0.1", "--static-friction", "0.05"],
        vec!["--coulomb-friction", "-0.1"],
    ] {
        assert_bad_input(&[&DEVICE[..], &flags].concat(), true);
    }
    assert_bad_input(
        &[
            "check",
            "--alpha",
            "0.1",
            "--beta",
            "0.3",
            "--delta",
            "0.1",
            "--d",
            "1",
            "--encoder-resolution",
            "1e-5",
        ],
        true,
    );
}

/// The quantizers and friction by scene keys (from the element list, as the flags): each
/// wall's buzz block is the one `check` reports for the same device, flags and wall; the
/// text report shows it; a device without them has none.
#[test]
fn scene_walls_show_buzz() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("buzz.toml");
    std::fs::write(
        &path,
        "[[device]]\nmass_kg = 0.1\nperiod_s = 0.001\ndamping_Ns_per_m = 10\ndelay_samples = 1\nencoder_resolution_m = 1e-5\ncoulomb_friction_N = 0.02\nstatic_friction_N = 0.03\nhand_mass_kg = 0.02\n[[device.wall]]\nstiffness_N_per_m = 17000\ndamping_Ns_per_m = 30\n\n[[device]]\nmass_kg = 0.1\nperiod_s = 0.001\ndamping_Ns_per_m = 10\ndelay_samples = 1\n[[device.wall]]\nstiffness_N_per_m = 17000\ndamping_Ns_per_m = 30\n",
    )
    .unwrap();
    let p = path.to_str().unwrap();
    let scene = crate::common::json(&["scene", "--format", "json", p]);
    let flags = [
        "--encoder-resolution",
        "1e-5",
        "--coulomb-friction",
        "0.02",
        "--static-friction",
        "0.03",
        "--hand-mass",
        "0.02",
    ];
    let check = json(&flags);
    let wall = &scene["devices"][0]["walls"][0]["buzz"];
    for key in [
        "sustained",
        "diverged",
        "peak_counts",
        "period_samples",
        "runs",
    ] {
        assert_eq!(wall[key], check["buzz"][key], "{key}");
    }
    // the first device names a hand, so the same device with the hand let go follows it, with
    // the same quantizers; the last device has none
    let devices = scene["devices"].as_array().unwrap();
    assert_eq!(devices.len(), 3);
    assert!(devices[1]["walls"][0]["buzz"]["sustained"].is_boolean());
    assert!(devices[2]["walls"][0].get("buzz").is_none());
    let text = String::from_utf8(stdout(&["scene", p])).unwrap();
    assert!(text.contains("    buzz: "), "{text}");
    assert!(
        text.contains("elements modelled: hand, encoder resolution, dry friction"),
        "{text}"
    );
}

/// `step` with an encoder: each summary line ends with the library's buzz verdict for that
/// wall, and `--svg` adds the limit-cycle panel when the wall buzzes.
#[test]
fn step_shows_buzz_and_draws_the_limit_cycle() {
    let dir = tempfile::tempdir().unwrap();
    let svg = dir.path().join("step.svg");
    let out = stdout(&[
        "step",
        "--mass",
        "0.1",
        "--period",
        "0.001",
        "--damping",
        "10",
        "--delay-samples",
        "1",
        "--stiffness",
        "17000",
        "--wall-damping",
        "30",
        "--format",
        "summary",
        "--encoder-resolution",
        "1e-5",
        "--svg",
        svg.to_str().unwrap(),
    ]);
    let text = String::from_utf8(out).unwrap();
    let device = Device::new(0.1, 1e-3, 10.0, Delay::Samples(1.0)).unwrap();
    let mut n = Nonlinear::default();
    n.encoder_resolution = Some(1e-5);
    let q = n.normalize(&device, 17000.0).unwrap();
    let wall = device.wall(17000.0, 30.0).unwrap();
    let lp = Loop::new(device.plant().unwrap());
    let want = buzz(lp, &wall, &q, &BuzzOptions::default()).unwrap();
    assert!(want.sustained());
    let line = format!(
        "; buzz: {}\n",
        stabound::export::report::buzz_verdict(&want)
    );
    assert!(text.ends_with(&line), "{text}");
    let drawing = std::fs::read_to_string(&svg).unwrap();
    assert!(drawing.contains("Limit cycles"), "no limit-cycle panel");
}

/// Friction with a transmission and an actuator lag: `check` reports what the library's
/// protocol gives on the loop with those elements.
#[test]
fn friction_with_elements_matches_the_library() {
    let flags = [
        "--encoder-resolution",
        "1e-5",
        "--coulomb-friction",
        "0.02",
        "--handle-mass",
        "0.03",
        "--transmission-stiffness",
        "4e5",
        "--actuator-time-constant",
        "2e-4",
    ];
    let got = json(&flags);
    let device = Device::new(0.1, 1e-3, 10.0, Delay::Samples(1.0)).unwrap();
    let mut named = stabound::elements::PhysicalElements::default();
    named.handle_mass = Some(0.03);
    named.transmission_stiffness = Some(4e5);
    named.actuator_time_constant = Some(2e-4);
    named.encoder_resolution = Some(1e-5);
    named.coulomb_friction = Some(0.02);
    let lp = Loop::physical(&device, &named).unwrap();
    let q = stabound::buzz::Nonlinear::from(&named)
        .normalize(&device, 17000.0)
        .unwrap();
    let want = buzz(
        lp,
        &device.wall(17000.0, 30.0).unwrap(),
        &q,
        &BuzzOptions::default(),
    )
    .unwrap();
    assert_eq!(got["buzz"]["sustained"], want.sustained());
    assert_eq!(
        got["buzz"]["peak_counts"].as_f64().unwrap(),
        want.peak_counts()
    );
    let runs = got["buzz"]["runs"].as_array().unwrap();
    for (r, w) in runs.iter().zip(&want.runs) {
        assert_eq!(r["outcome"], w.outcome.name());
    }
}

/// `amax` with an encoder: each row's buzz-free stiffness is the library's search on that
/// device's loop, below the linear K_max, and the protocol finds that wall quiet.
#[test]
fn amax_gives_the_buzz_free_stiffness() {
    let out = stdout(&[
        "amax",
        "--mass",
        "0.1",
        "--period",
        "0.001",
        "--damping",
        "10",
        "--delay-samples",
        "1",
        "--encoder-resolution",
        "1e-5",
        "--format",
        "json",
    ]);
    let rows: serde_json::Value = serde_json::from_slice(&out).unwrap();
    let row = &rows[0];
    let device = Device::new(0.1, 1e-3, 10.0, Delay::Samples(1.0)).unwrap();
    let lp = Loop::physical(&device, &stabound::elements::PhysicalElements::default()).unwrap();
    let mut n = Nonlinear::default();
    n.encoder_resolution = Some(1e-5);
    let want = stabound::buzz::buzz_free_alpha_max(
        lp,
        &n,
        &stabound::buzz::BuzzFreeOptions::default(),
        &|| (),
    )
    .unwrap();
    let best = want.best.unwrap();
    let alpha = row["alpha_buzz_free"].as_f64().unwrap();
    assert_eq!(alpha, best.alpha.unwrap());
    assert_eq!(row["beta_buzz_free"].as_f64().unwrap(), best.beta);
    assert_eq!(row["alpha_max"].as_f64().unwrap(), want.alpha_max);
    assert!(alpha < want.alpha_max);
    let q = n.normalize(&device, device.stiffness(alpha)).unwrap();
    let wall = stabound::params::Wall::new(alpha, best.beta).unwrap();
    assert!(
        !buzz(lp, &wall, &q, &BuzzOptions::default())
            .unwrap()
            .sustained()
    );
    // the same rows from `table`
    let table = stdout(&[
        "table",
        "--mass",
        "0.1",
        "--period",
        "0.001",
        "--damping",
        "10",
        "--delay-samples",
        "1",
        "--encoder-resolution",
        "1e-5",
        "--format",
        "json",
    ]);
    assert_eq!(table, out);
}

/// The buzz-free stiffness is for one device: an interval of the device or of an element is
/// refused before any work, naming the parameter, and so is an interval of a quantizer.
#[test]
fn buzz_free_stiffness_refuses_sets_of_devices() {
    let device = ["--mass", "0.1", "--period", "0.001", "--damping", "10"];
    for (extra, named) in [
        (&["--delay-samples", "1..2"][..], "delay"),
        (
            &["--delay-samples", "1", "--hand-mass", "0.1..0.2"][..],
            "hand mass",
        ),
    ] {
        for command in ["amax", "table"] {
            let args = [
                &[command][..],
                &device,
                extra,
                &["--encoder-resolution", "1e-5"],
            ]
            .concat();
            let err = assert_bad_input(&args, true);
            assert!(
                err.contains("answers for one device") && err.contains(named),
                "{err}"
            );
        }
    }
    let args = [
        &["amax"][..],
        &device,
        &["--delay-samples", "1", "--encoder-resolution", "1e-5..2e-5"],
    ]
    .concat();
    assert!(assert_bad_input(&args, true).contains("takes one number"));
}
