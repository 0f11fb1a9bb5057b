//! The request layer and the element list's report readings, against the conversions done
//! by hand: each reading converts back to the physical value given, a wall damping limit is
//! `B T / m`, and refusals name their inputs in the front end's spelling.

use stabound::elements::list::{Element, PARAMS, Value};
use stabound::elements::{Loop, PhysicalElements};
use stabound::params::{Delay, Device};
use stabound::request::{
    DampingLimits, DeviceInputs, Given, Input, PlaneFault, RequestError, Takes, device_set, margin,
};
use stabound::robust::{Quantity, Spread};

const MASS: f64 = 0.2;
const PERIOD: f64 = 1e-3;

fn device() -> Device {
    Device::new(MASS, PERIOD, 20.0, Delay::Samples(1.0)).unwrap()
}

/// Every element with every parameter named (a first-order filter, then a moving average
/// and a second-order filter in turn, and the transmission's damping split by its motor
/// side instead of its handle side), each value distinct.
fn loops() -> Vec<(PhysicalElements, Loop)> {
    let mut full = PhysicalElements::default();
    full.hand_mass = Some(0.05);
    full.hand_damping = Some(1.5);
    full.hand_stiffness = Some(40.0);
    full.handle_mass = Some(0.03);
    full.transmission_stiffness = Some(4e4);
    full.transmission_damping = Some(3.0);
    full.handle_damping = Some(5.0);
    full.encoder = Some(stabound::elements::Encoder::Handle);
    full.actuator_time_constant = Some(2e-4);
    full.velocity_filter_cutoff = Some(30.0);
    let mut averaged = full;
    averaged.velocity_filter_cutoff = None;
    averaged.velocity_filter_samples = Some(4);
    let mut second = full;
    second.velocity_filter_order = Some(2);
    let mut motor = full;
    motor.handle_damping = None;
    motor.motor_damping = Some(15.0);
    [full, averaged, second, motor]
        .into_iter()
        .map(|e| (e, Loop::physical(&device(), &e).unwrap()))
        .collect()
}

/// Each number a report shows converts back (through the device's mass and period) to the
/// physical value named, to the rounding of the two conversions; counts and choices are
/// shown as named. Only the motor side's share (the rest of `b`, not named here) and the
/// filter's order (named by the cutoff's form) show nothing.
#[test]
fn readings_convert_back_to_the_values_named() {
    for (named, lp) in loops() {
        for p in PARAMS {
            let given = p.get(&named);
            let shown = p.reading(&lp);
            match (given, shown) {
                (Some(Value::Number(x)), Some(r)) => {
                    let back = r.physical(MASS, PERIOD).unwrap();
                    // two roundings, and for the pole a log and an exp: well within 1e-12
                    assert!(
                        (back - x).abs() <= 1e-12 * x.abs(),
                        "{}: {back} vs {x}",
                        p.key
                    );
                }
                (Some(v), Some(r)) => {
                    assert_eq!(r.value, v, "{}", p.key);
                    assert_eq!(r.physical(MASS, PERIOD), None, "{}", p.key);
                }
                (Some(_), None) => assert!(
                    ["velocity_filter_order", "motor_damping"].contains(&p.keyword),
                    "{} is named and not reported",
                    p.key
                ),
                (None, Some(r)) if p.keyword == "handle_damping" => {
                    // the handle side takes what the motor side leaves of b = 20 N s/m
                    let b1 = named.motor_damping.unwrap();
                    let back = r.physical(MASS, PERIOD).unwrap();
                    assert!((back - (20.0 - b1)).abs() <= 1e-12 * 20.0, "{back}");
                }
                (None, Some(r)) => {
                    // the encoder's default is shown with its transmission
                    assert_eq!((p.keyword, r.value), ("encoder", Value::Choice("motor")));
                }
                (None, None) => {}
            }
        }
    }
}

/// The quantizers and friction, each named.
fn nonlinear() -> PhysicalElements {
    let mut e = PhysicalElements::default();
    e.encoder_resolution = Some(1e-5);
    e.force_resolution = Some(2e-3);
    e.coulomb_friction = Some(0.02);
    e.static_friction = Some(0.03);
    e
}

/// Every parameter of the element list is exercised here: each is named in one of the
/// loops above (so the readings test reads it back) or among the quantizers and friction; a
/// parameter added to the list without a case here fails.
#[test]
fn every_parameter_is_exercised() {
    let mut named: Vec<PhysicalElements> = loops().into_iter().map(|(e, _)| e).collect();
    named.push(nonlinear());
    for p in PARAMS {
        assert!(
            named.iter().any(|e| p.get(e).is_some()),
            "{} is named by no case: add it to loops() or nonlinear()",
            p.key
        );
    }
}

/// The serde form (a scene's keys) is the element list's: each value named appears under
/// its parameter's key and nothing else does, and it reads back to the same elements.
#[test]
fn serde_keys_are_the_list_keys() {
    let mut named: Vec<PhysicalElements> = loops().into_iter().map(|(e, _)| e).collect();
    named.push(nonlinear());
    for e in named {
        let json = serde_json::to_value(e).unwrap();
        let keys: Vec<&str> = json
            .as_object()
            .unwrap()
            .keys()
            .map(|k| k.as_str())
            .collect();
        let mut want: Vec<&str> = PARAMS
            .iter()
            .filter(|p| p.get(&e).is_some())
            .map(|p| p.key)
            .collect();
        want.sort_unstable();
        let mut got = keys.clone();
        got.sort_unstable();
        assert_eq!(got, want);
        let back: PhysicalElements = serde_json::from_value(json).unwrap();
        assert_eq!(back, e);
    }
}

/// The labels a report uses are those of the model document's normalized forms, one per
/// element object (no two parameters of one element share a label).
#[test]
fn labels_are_distinct_within_each_element() {
    for (_, lp) in loops() {
        for el in Element::ALL {
            let labels: Vec<&str> = el.readings(&lp).iter().map(|(_, r)| r.label).collect();
            let mut unique = labels.clone();
            unique.sort_unstable();
            unique.dedup();
            assert_eq!(unique.len(), labels.len(), "{labels:?}");
        }
    }
    let (_, lp) = &loops()[0];
    let hand: Vec<(&str, Value)> = Element::Hand
        .readings(lp)
        .iter()
        .map(|(_, r)| (r.label, r.value))
        .collect();
    // m_h / m, b_h T / m, k_h T^2 / m by hand
    let expect = [
        ("mu_h", 0.05 / MASS),
        ("delta_h", 1.5 * PERIOD / MASS),
        ("kappa_h", 40.0 * PERIOD * PERIOD / MASS),
    ];
    for ((label, v), (l, x)) in hand.iter().zip(expect) {
        let Value::Number(v) = v else { panic!() };
        assert_eq!(*label, l);
        assert!((v - x).abs() <= 1e-15 * x, "{label}: {v} vs {x}");
    }
}

/// The names a scene report lists, one per element named, in the list's order.
#[test]
fn element_names() {
    let names: Vec<Vec<&str>> = loops().iter().map(|(e, _)| e.names()).collect();
    let common = [
        "hand",
        "transmission (encoder on the handle)",
        "actuator lag",
    ];
    for (got, filter) in names.iter().zip([
        "low-pass velocity filter",
        "moving-average velocity filter",
        "second-order low-pass velocity filter",
    ]) {
        assert_eq!(got[..3], common);
        assert_eq!(got[3..], [filter]);
    }
    assert!(PhysicalElements::default().names().is_empty());
}

/// A wall-damping limit is `B T / m` of the device; named twice or without the device it is
/// refused, naming its inputs as the front end spells them.
#[test]
fn damping_limits() {
    let limits = DampingLimits {
        wall_damping_min: Some(60.0),
        beta_max: Some(2.0),
        ..Default::default()
    };
    assert_eq!(
        limits.resolve(Some((MASS, PERIOD))).unwrap(),
        (Some(60.0 * PERIOD / MASS), Some(2.0))
    );
    let flag = |i: Input| format!("--{}", i.keyword().replace('_', "-"));
    let request = |e: stabound::Error| match e {
        stabound::Error::Request(r) => r,
        e => panic!("{e}"),
    };
    let r = request(limits.resolve(None).unwrap_err());
    assert_eq!(
        r,
        RequestError::NeedsDevice {
            input: Input::WallDampingMin,
            normalized: Input::BetaMin
        }
    );
    let m = r.message(&flag);
    assert!(
        m.contains("--wall-damping-min") && m.contains("--mass") && m.contains("--beta-min"),
        "{m}"
    );
    let both = DampingLimits {
        beta_max: Some(1.0),
        wall_damping_max: Some(1.0),
        ..Default::default()
    };
    let r = request(both.resolve(Some((MASS, PERIOD))).unwrap_err());
    assert!(
        r.message(&|i| format!("{}=", i.keyword()))
            .contains("beta_max= or wall_damping_max=")
    );
    // the limits' order is the search options' check
    let inverted = DampingLimits {
        beta_min: Some(1.0),
        wall_damping_max: Some(0.0),
        ..Default::default()
    };
    assert!(matches!(
        inverted.options(stabound::amax::DEFAULT_THETA_TOL, Some((MASS, PERIOD))),
        Err(stabound::Error::InvalidRequest(_))
    ));
}

/// A margin is a fraction in `(0, 1]`.
#[test]
fn margins() {
    for ok in [1e-300, 0.5, 1.0] {
        assert_eq!(margin(ok).unwrap(), ok);
    }
    for bad in [0.0, -0.5, 1.0 + f64::EPSILON, f64::NAN, f64::INFINITY] {
        let e = margin(bad).unwrap_err();
        assert!(e.to_string().contains("fraction in (0, 1]"), "{e}");
    }
}

fn refused(e: stabound::Error) -> RequestError {
    match e {
        stabound::Error::Request(r) => r,
        e => panic!("{e}"),
    }
}

/// The device as given: each form resolves with its values untouched and converts as the
/// paper's definitions do by hand (`delta = b T / m`, `d = delay / T`, `alpha = K T^2 / m`,
/// `beta = B T / m`); a request that mixes the forms, lacks an input or names the delay
/// twice is refused naming exactly those inputs, in each front end's spelling.
#[test]
fn device_inputs_resolve_once() {
    let physical = DeviceInputs {
        mass: Some(MASS),
        period: Some(PERIOD),
        damping: Some(20.0),
        delay: Some(2e-3),
        ..Default::default()
    };
    let g = physical.resolve(Takes::Plants).unwrap();
    assert_eq!(
        g,
        Given::Physical {
            mass: MASS,
            period: PERIOD,
            damping: 20.0,
            delay: 2e-3,
            in_samples: false,
            wall: None
        }
    );
    let p = g.plant().unwrap();
    assert!((p.delta() - 20.0 * PERIOD / MASS).abs() <= 1e-15 && (p.d() - 2.0).abs() <= 1e-12);
    assert_eq!(g.device().unwrap().unwrap().mass(), MASS);
    // a plant request takes no wall
    assert!(g.normalized().is_err());
    let walls = DeviceInputs {
        stiffness: Some(1e4),
        wall_damping: Some(30.0),
        ..physical
    };
    let n = walls.resolve(Takes::Walls).unwrap().normalized().unwrap();
    assert!((n.alpha() - 1e4 * PERIOD * PERIOD / MASS).abs() <= 1e-15);
    assert!((n.beta() - 30.0 * PERIOD / MASS).abs() <= 1e-15);
    let normalized = DeviceInputs {
        alpha: Some(0.1),
        beta: Some(0.3),
        delta: Some(0.5),
        d: Some(1.0),
        ..Default::default()
    };
    let n = normalized.resolve(Takes::Walls).unwrap();
    assert!(!n.is_physical() && n.device().unwrap().is_none());
    assert_eq!(
        (n.normalized().unwrap().alpha(), n.plant().unwrap().d()),
        (0.1, 1.0)
    );
    // values of any type pass through untouched (a front end's lists, arrays)
    let lists = DeviceInputs {
        delta: Some(vec![0.0, 1.0]),
        d: Some(vec![2.0]),
        ..Default::default()
    };
    let Given::Normalized { delta, d, wall } = lists.resolve(Takes::Plants).unwrap() else {
        panic!("normalized")
    };
    assert_eq!((delta, d, wall), (vec![0.0, 1.0], vec![2.0], None));

    let flag = |i: Input| format!("--{}", i.keyword().replace('_', "-"));
    let keyword = |i: Input| format!("{}=", i.keyword());
    // mixed: the inputs of each form given, nothing else
    let mixed = DeviceInputs {
        delta: Some(0.5),
        ..physical
    };
    let r = refused(mixed.resolve(Takes::Plants).unwrap_err());
    assert_eq!(
        r,
        RequestError::Mixed {
            normalized: vec![Input::Delta],
            physical: vec![
                &[Input::Mass][..],
                &[Input::Period],
                &[Input::Damping],
                &[Input::Delay, Input::DelaySamples]
            ],
        }
    );
    assert_eq!(
        r.message(&flag),
        "--delta (normalized) and --mass, --period, --damping and --delay|--delay-samples (physical units) were both given: give one kind, not both"
    );
    // missing: the absent inputs of the form given, the delay's two spellings as one
    let lacking = DeviceInputs {
        period: None,
        delay: None,
        ..physical
    };
    let r = refused(lacking.resolve(Takes::Plants).unwrap_err());
    assert!(
        r.message(&flag).starts_with(
            "missing --period and --delay|--delay-samples: the device in physical units needs --mass, --period, --damping and --delay|--delay-samples"
        ),
        "{}",
        r.message(&flag)
    );
    assert!(
        r.message(&keyword)
            .starts_with("missing period= and delay=|delay_samples=:")
    );
    let r = refused(
        DeviceInputs::<f64>::default()
            .resolve(Takes::Walls)
            .unwrap_err(),
    );
    assert!(
        r.message(&flag)
            .starts_with("missing --alpha, --beta, --delta and --d: give --alpha, --beta, --delta and --d, or the wall in physical units")
    );
    let r = refused(physical.resolve(Takes::Walls).unwrap_err());
    assert!(
        r.message(&flag)
            .starts_with("missing --stiffness and --wall-damping:")
    );
    // a request that names loop elements is physical: it lacks the device, not delta and d
    let r = refused(
        DeviceInputs::<f64>::default()
            .resolve_physical(Takes::Plants)
            .unwrap_err(),
    );
    assert!(
        r.message(&keyword)
            .starts_with("missing mass=, period=, damping= and delay=|delay_samples=:")
    );
    let twice = DeviceInputs {
        delay_samples: Some(1.0),
        ..physical
    };
    let r = refused(twice.resolve(Takes::Plants).unwrap_err());
    assert!(
        r.message(&keyword)
            .starts_with("give delay= or delay_samples=, not both")
    );
    // loop elements and intervals need the physical form
    let n = normalized.resolve(Takes::Walls).unwrap();
    assert!(n.physical_for("loop elements", false, Takes::Walls).is_ok());
    let r = refused(
        n.physical_for("loop elements", true, Takes::Walls)
            .unwrap_err(),
    );
    assert!(
        r.message(&flag)
            .starts_with("loop elements are given in physical units: give the wall with --mass")
    );
}

/// A set of devices: none for one device without a hand; an interval makes a set; a hand
/// makes the hand let go a member unless always gripped or the computation does not let go
/// (a point test); the members' loops are the device's at each end.
#[test]
fn device_sets_from_a_request() {
    let none = PhysicalElements::default();
    assert!(
        device_set(&device(), &none, &[], false, true)
            .unwrap()
            .is_none()
    );
    let set = device_set(
        &device(),
        &none,
        &[(Quantity::Delay, Spread::Interval(1.0, 3.0))],
        false,
        true,
    )
    .unwrap()
    .unwrap();
    assert!(!set.is_single() && set.has_intervals());
    assert_eq!(set.reference().device().delay_factor(), 1.0);
    let mut hand = none;
    hand.hand_mass = Some(0.3);
    let free = device_set(&device(), &hand, &[], false, true)
        .unwrap()
        .unwrap();
    assert!(free.hand_may_let_go() && !free.is_single());
    let held = device_set(&device(), &hand, &[], true, true)
        .unwrap()
        .unwrap();
    assert!(!held.hand_may_let_go() && held.is_single());
    // a point test checks the device as given: no set without an interval
    assert!(
        device_set(&device(), &hand, &[], false, false)
            .unwrap()
            .is_none()
    );
    // an inverted interval and an empty list are the library's refusals
    let inverted = [(Quantity::Mass, Spread::Interval(0.3, 0.2))];
    assert!(device_set(&device(), &none, &inverted, false, true).is_err());
    let empty = [(Quantity::Mass, Spread::Values(Vec::new()))];
    assert!(device_set(&device(), &none, &empty, false, true).is_err());
    // a list is a finite set: no intervals, its smallest value the reference
    let list = [(Quantity::Delay, Spread::Values(vec![3.0, 2.0]))];
    let set = device_set(&device(), &none, &list, false, true)
        .unwrap()
        .unwrap();
    assert!(set.is_spread() && !set.has_intervals());
    assert_eq!(set.reference().device().delay_factor(), 2.0);
}

/// A request that takes the device's parts one by one: each physical part converts as by
/// hand (`delta = b T / m`, `alpha = K T^2 / m`, `beta = B T / m`, `d = delay / T`), the
/// normalized ones pass through, and the refusals name their inputs.
#[test]
fn parts_resolve_once() {
    let given = DeviceInputs {
        damping: Some(20.0),
        stiffness: Some(3000.0),
        wall_damping: Some(10.0),
        delay: Some(2e-3),
        mass: Some(MASS),
        period: Some(PERIOD),
        ..Default::default()
    };
    let p = given.resolve_parts().unwrap();
    // one product and one quotient each: within 2 roundings
    let close = |x: Option<f64>, want: f64| (x.unwrap() - want).abs() <= 4e-16 * want;
    assert!(close(p.delta, 20.0 * PERIOD / MASS), "{:?}", p.delta);
    assert!(
        close(p.alpha, 3000.0 * PERIOD * PERIOD / MASS),
        "{:?}",
        p.alpha
    );
    assert!(close(p.beta, 10.0 * PERIOD / MASS), "{:?}", p.beta);
    assert_eq!((p.d, p.device), (2.0, Some((MASS, PERIOD))));
    let normalized = DeviceInputs {
        delta: Some(0.5),
        beta: Some(0.1),
        d: Some(3.0),
        ..Default::default()
    };
    let p = normalized.resolve_parts().unwrap();
    assert_eq!(
        (p.delta, p.alpha, p.beta, p.d, p.device),
        (Some(0.5), None, Some(0.1), 3.0, None)
    );
    assert_eq!(
        DeviceInputs::<f64>::default().resolve_parts().unwrap().d,
        0.0
    );
    let refused = |g: DeviceInputs<f64>| match g.resolve_parts().unwrap_err() {
        stabound::Error::Request(r) => r,
        e => panic!("{e}"),
    };
    assert_eq!(
        refused(DeviceInputs {
            delta: Some(1.0),
            damping: Some(2.0),
            ..Default::default()
        }),
        RequestError::Either {
            first: Input::Delta,
            second: Input::Damping,
            what: "they are the same parameter"
        }
    );
    assert_eq!(
        refused(DeviceInputs {
            delay: Some(1e-3),
            ..Default::default()
        }),
        RequestError::NeedsPeriod {
            input: Input::Delay
        }
    );
    assert_eq!(
        refused(DeviceInputs {
            mass: Some(1.0),
            ..Default::default()
        }),
        RequestError::NeedsPeriod { input: Input::Mass }
    );
    let r = refused(DeviceInputs {
        stiffness: Some(1.0),
        delay: Some(1e-3),
        period: Some(1e-3),
        ..Default::default()
    });
    assert_eq!(
        r,
        RequestError::Unconverted {
            inputs: vec![Input::Delay, Input::Stiffness]
        }
    );
    let flag = |i: Input| format!("--{}", i.keyword().replace('_', "-"));
    assert_eq!(
        r.message(&flag),
        "--delay, --stiffness are in physical units and need the device: give --mass and --period, or the normalized --delta, --alpha, --beta"
    );
}

/// The (delta, beta) plane: its axis range is the smallest to the largest `delta` given
/// (`[0, 1]` by default), the curves' values pass untouched, and the device is the loop
/// elements' `(mass, period)` alone. Each refusal names exactly the inputs concerned, in
/// each front end's spelling, and a value out of range is refused before any curve.
#[test]
fn delta_beta_plane_refusals() {
    let (alpha, d, delta) = ([0.5, 0.0], [1.0, 2.0], [2.0, 0.0, 0.5]);
    let (one, two) = ([1.0], [0.1, 0.2]);
    let (m, t) = ([MASS], [PERIOD]);
    let base = DeviceInputs {
        alpha: Some(&alpha[..]),
        d: Some(&d[..]),
        delta: Some(&delta[..]),
        ..Default::default()
    };
    let plane = base.delta_beta_plane(false).unwrap();
    assert_eq!((plane.alphas, plane.ds), (&alpha[..], &d[..]));
    // the smallest and largest values given, whatever their order
    assert_eq!((plane.range, plane.device), ((0.0, 2.0), None));
    let bare = DeviceInputs {
        delta: None,
        ..base
    };
    assert_eq!(bare.delta_beta_plane(false).unwrap().range, (0.0, 1.0));
    let device = DeviceInputs {
        mass: Some(&m[..]),
        period: Some(&t[..]),
        ..base
    };
    assert_eq!(
        device.delta_beta_plane(true).unwrap().device,
        Some((MASS, PERIOD))
    );

    let fault = |given: DeviceInputs<&[f64]>, elements: bool| -> (PlaneFault, Vec<Input>) {
        match refused(given.delta_beta_plane(elements).unwrap_err()) {
            RequestError::DeltaBeta { why, inputs } => (why, inputs),
            r => panic!("{r}"),
        }
    };
    let damped = DeviceInputs {
        damping: Some(&one[..]),
        delay_samples: Some(&one[..]),
        ..device
    };
    assert_eq!(
        fault(damped, true),
        (
            PlaneFault::NotTaken,
            vec![Input::Damping, Input::DelaySamples]
        )
    );
    let e = refused(damped.delta_beta_plane(true).unwrap_err());
    let flag = |i: Input| format!("--{}", i.keyword().replace('_', "-"));
    let keyword = |i: Input| format!("{}=", i.keyword());
    assert!(
        e.message(&flag)
            .starts_with("--damping and --delay-samples are not taken in the delta-beta plane"),
        "{e}"
    );
    assert!(
        e.message(&keyword)
            .starts_with("damping= and delay_samples= are"),
        "{e}"
    );
    let e = refused(
        DeviceInputs {
            delay: Some(&one[..]),
            ..base
        }
        .delta_beta_plane(false)
        .unwrap_err(),
    );
    assert!(e.message(&flag).starts_with("--delay is not taken"), "{e}");

    let unnamed = DeviceInputs {
        alpha: None,
        d: None,
        ..base
    };
    assert_eq!(
        fault(unnamed, false),
        (PlaneFault::Missing, vec![Input::Alpha, Input::D])
    );
    assert_eq!(
        fault(DeviceInputs { d: None, ..base }, false),
        (PlaneFault::Missing, vec![Input::D])
    );
    for range in [&[1.0][..], &[1.0, 1.0], &[], &[0.0, f64::NAN]] {
        let given = DeviceInputs {
            delta: Some(range),
            ..base
        };
        assert_eq!(
            fault(given, false),
            (PlaneFault::Range, vec![Input::Delta]),
            "{range:?}"
        );
    }
    assert_eq!(
        fault(device, false),
        (
            PlaneFault::DeviceWithoutElements,
            vec![Input::Mass, Input::Period]
        )
    );
    let massive = DeviceInputs {
        mass: Some(&m[..]),
        ..base
    };
    assert_eq!(
        fault(massive, true),
        (PlaneFault::ElementsWithoutDevice, vec![Input::Period])
    );
    assert_eq!(
        fault(base, true),
        (
            PlaneFault::ElementsWithoutDevice,
            vec![Input::Mass, Input::Period]
        )
    );
    let e = refused(base.delta_beta_plane(true).unwrap_err());
    assert!(
        e.message(&keyword)
            .starts_with("missing mass= and period=: loop elements"),
        "{e}"
    );
    let several = DeviceInputs {
        period: Some(&two[..]),
        ..device
    };
    assert_eq!(
        fault(several, true),
        (PlaneFault::OneDevice, vec![Input::Period])
    );

    // values out of range: a negative stiffness, a NaN delay factor, a device's mass
    let negative = [-1.0];
    let e = refused(
        DeviceInputs {
            alpha: Some(&negative[..]),
            ..base
        }
        .delta_beta_plane(false)
        .unwrap_err(),
    );
    assert!(
        matches!(e, RequestError::Refused { input: Input::Alpha, value, .. } if value == -1.0),
        "{e}"
    );
    assert!(
        e.message(&keyword)
            .starts_with("invalid alpha= -1: stiffness must be >= 0"),
        "{e}"
    );
    let nan = [f64::NAN];
    assert!(
        DeviceInputs {
            d: Some(&nan[..]),
            ..base
        }
        .delta_beta_plane(false)
        .is_err()
    );
    let no_mass = [0.0];
    let weightless = DeviceInputs {
        mass: Some(&no_mass[..]),
        ..device
    };
    assert!(weightless.delta_beta_plane(true).is_err());
}
