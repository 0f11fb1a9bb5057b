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
