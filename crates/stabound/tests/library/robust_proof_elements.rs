//! The box recursion over loops with elements (a first- or second-order velocity filter's
//! cutoff, an actuator lag's time constant, a delay interval behind a filter, a
//! transmission's parameters, a share of the damping and the mass under a transmission),
//! checked against the closed-loop state matrices of the
//! members (eigenvalues by nalgebra's Schur form) at dense members of each interval.

use super::robust_sets::stable_by_eigenvalues;
use stabound::AmaxOptions;
use stabound::elements::PhysicalElements;
use stabound::params::{Delay, Device, Wall};
use stabound::robust::{
    DeviceSet, PROOF_BUDGET, Quantity, RobustAmax, Verification, prove_wall, robust_alpha_max,
};

/// A 0.1 kg device at 1 kHz with 1 N s/m of damping and one sample of delay.
fn device() -> Device {
    Device::new(0.1, 1e-3, 1.0, Delay::Samples(1.0)).unwrap()
}

/// The set of `device` with `named` and `param` over `[lo, hi]`.
fn set(device: &Device, named: &PhysicalElements, param: Quantity, lo: f64, hi: f64) -> DeviceSet {
    DeviceSet::new(device, named)
        .unwrap()
        .with_interval(param, lo, hi)
        .unwrap()
}

/// The robust optimum of `set` is proved over the box, the verified wall is stable by
/// eigenvalues at `count + 1` members spaced evenly across the interval (`member(t)`, `t`
/// in `[0, 1]`), and a wall 0.1 % above the optimum is not proved and is unstable at a
/// binding member by eigenvalues. Returns the optimum.
fn proved_and_tight(
    set: &DeviceSet,
    count: u32,
    member: impl Fn(f64) -> (Device, PhysicalElements),
) -> RobustAmax {
    let r = robust_alpha_max(set, &AmaxOptions::default()).unwrap();
    assert!(
        matches!(r.verification, Verification::Proved { .. }),
        "{r:?}"
    );
    assert!(r.verification.describe().starts_with("proved over the box"));
    tight(set, &r, r.alpha_verified, count, member);
    r
}

/// The set of [`device`] with `named` and the element parameter `keyword` over `[lo, hi]`
/// (`put` sets it): [`proved_and_tight`] at `count + 1` values across the interval.
fn element_interval_is_proved(
    named: PhysicalElements,
    keyword: &str,
    (lo, hi): (f64, f64),
    count: u32,
    put: impl Fn(&mut PhysicalElements, f64),
) {
    let param = Quantity::element(keyword).unwrap();
    let s = set(&device(), &named, param, lo, hi);
    proved_and_tight(&s, count, |t| {
        let mut e = named;
        put(&mut e, lo + (hi - lo) * t);
        (device(), e)
    });
}

/// The wall `(alpha, r.beta_at_max)` is stable by eigenvalues at `count + 1` members, and
/// the wall 0.1 % above the optimum `r` is not proved and unstable at a binding member.
fn tight(
    set: &DeviceSet,
    r: &RobustAmax,
    alpha: f64,
    count: u32,
    member: impl Fn(f64) -> (Device, PhysicalElements),
) {
    let reference = set.reference();
    let dev = reference.device();
    let (k, b) = (dev.stiffness(alpha), dev.wall_damping(r.beta_at_max));
    for i in 0..=count {
        let (d, e) = member(f64::from(i) / f64::from(count));
        assert!(stable_by_eigenvalues(&d, &e, k, b), "{d:?} {e:?}");
    }
    let above = Wall::new(1.001 * r.alpha_max, r.beta_at_max).unwrap();
    let p = prove_wall(set, &above, PROOF_BUDGET).unwrap().unwrap();
    assert!(!p.proved && p.leaves.iter().any(|c| !c.stable));
    let k_above = dev.stiffness(above.alpha());
    assert!(
        r.binding
            .iter()
            .any(|m| !stable_by_eigenvalues(m.device(), m.elements(), k_above, b)),
        "{:?}",
        r.binding
    );
}

/// `--velocity-filter-cutoff 30..60`: proved, stable at 121 cutoffs.
#[test]
fn filter_cutoff_interval_is_proved() {
    let mut named = PhysicalElements::default();
    named.velocity_filter_cutoff = Some(30.0);
    element_interval_is_proved(
        named,
        "velocity_filter_cutoff",
        (30.0, 60.0),
        120,
        |e, x| e.velocity_filter_cutoff = Some(x),
    );
}

/// `--velocity-filter-cutoff 30..60 --velocity-filter-order 2` (the second-order
/// Butterworth): proved, stable at 121 cutoffs.
#[test]
fn second_order_cutoff_interval_is_proved() {
    let mut named = PhysicalElements::default();
    named.velocity_filter_cutoff = Some(30.0);
    named.velocity_filter_order = Some(2);
    element_interval_is_proved(
        named,
        "velocity_filter_cutoff",
        (30.0, 60.0),
        120,
        |e, x| e.velocity_filter_cutoff = Some(x),
    );
}

/// `--actuator-time-constant 0.2e-3..1e-3` behind a 50 Hz filter: proved (in centred form;
/// the plain extension needed about 22,000 cells), stable at 121 time constants.
#[test]
fn actuator_lag_interval_is_proved() {
    let mut named = PhysicalElements::default();
    named.actuator_time_constant = Some(2e-4);
    named.velocity_filter_cutoff = Some(50.0);
    element_interval_is_proved(
        named,
        "actuator_time_constant",
        (2e-4, 1e-3),
        120,
        |e, x| e.actuator_time_constant = Some(x),
    );
}

/// `--delay-samples 1..3` behind a 50 Hz filter: proved, stable at 201 delays (fractional
/// ones included), and the leaves' delays tile `[1, 3]`.
#[test]
fn delay_interval_with_a_filter_is_proved() {
    let mut named = PhysicalElements::default();
    named.velocity_filter_cutoff = Some(50.0);
    let s = set(&device(), &named, Quantity::Delay, 1.0, 3.0);
    let r = proved_and_tight(&s, 200, |t| (delayed(1.0 + 2.0 * t), named));
    let p = prove_wall(
        &s,
        &Wall::new(r.alpha_verified, r.beta_at_max).unwrap(),
        PROOF_BUDGET,
    )
    .unwrap()
    .unwrap();
    let mut spans: Vec<(f64, f64)> = p.leaves.iter().map(|c| c.delay).collect();
    spans.sort_by(|a, b| a.0.total_cmp(&b.0));
    assert_eq!((spans[0].0, spans[spans.len() - 1].1), (1.0, 3.0));
    // halvings of fractions and their sums with a whole number below 4 are exact
    for w in spans.windows(2) {
        assert_eq!(w[0].1, w[1].0, "{spans:?}");
    }
}

/// The device with `d` samples of delay.
fn delayed(d: f64) -> Device {
    Device::new(0.1, 1e-3, 1.0, Delay::Samples(d)).unwrap()
}

/// `--delay-samples 1..3` with a hand of 0.2 kg and 300 N/m that can let go (the device let
/// go is the paper's loop, enclosed by the same matrix exponential): proved, stable at 101
/// delays held and at 101 delays let go.
#[test]
fn delay_interval_with_a_hand_that_lets_go_is_proved() {
    let mut named = PhysicalElements::default();
    named.hand_mass = Some(0.2);
    named.hand_stiffness = Some(300.0);
    let s = set(&device(), &named, Quantity::Delay, 1.0, 3.0);
    let r = proved_and_tight(&s, 100, |t| (delayed(1.0 + 2.0 * t), named));
    let dev = device();
    let (k, b) = (
        dev.stiffness(r.alpha_verified),
        dev.wall_damping(r.beta_at_max),
    );
    for i in 0..=100 {
        let d = delayed(1.0 + 2.0 * f64::from(i) / 100.0);
        assert!(
            stable_by_eigenvalues(&d, &PhysicalElements::default(), k, b),
            "{d:?}"
        );
    }
}

/// A compliant transmission (30 g handle, 2 N s/m coupling) whose coupling stiffness is
/// anywhere in `4e4..5e4` N/m: proved, stable at 121 stiffnesses.
#[test]
fn transmission_stiffness_interval_is_proved() {
    let mut named = PhysicalElements::default();
    named.handle_mass = Some(0.03);
    named.transmission_stiffness = Some(4e4);
    named.transmission_damping = Some(2.0);
    element_interval_is_proved(named, "transmission_stiffness", (4e4, 5e4), 120, |e, x| {
        e.transmission_stiffness = Some(x)
    });
}

/// The device's mass in `0.09..0.11` kg under a transmission (its parameters normalized by
/// the mass move with it): proved, stable at 121 masses.
#[test]
fn mass_interval_under_a_transmission_is_proved() {
    let mut named = PhysicalElements::default();
    named.handle_mass = Some(0.03);
    named.transmission_stiffness = Some(3e4);
    named.transmission_damping = Some(2.0);
    let dev = |m: f64| Device::new(m, 1e-3, 1.0, Delay::Samples(1.0)).unwrap();
    let s = set(&dev(0.09), &named, Quantity::Mass, 0.09, 0.11);
    proved_and_tight(&s, 120, |t| (dev(0.09 + 0.02 * t), named));
}

/// A transmission (30 g handle, 50,000 N/m) as `--transmission-damping 1..3`, as
/// `--handle-mass 0.02..0.04` and as `--motor-damping 0.1..0.5` (the motor side's share of
/// the device's 1 N s/m, the handle side taking the rest): each proved, stable at 101
/// members.
#[test]
fn transmission_damping_handle_mass_and_share_intervals_are_proved() {
    let mut named = PhysicalElements::default();
    named.handle_mass = Some(0.03);
    named.transmission_stiffness = Some(5e4);
    named.transmission_damping = Some(2.0);
    let cases: [(&str, f64, f64); 3] = [
        ("transmission_damping", 1.0, 3.0),
        ("handle_mass", 0.02, 0.04),
        ("motor_damping", 0.1, 0.5),
    ];
    for (keyword, lo, hi) in cases {
        let mut low = named;
        let put = |e: &mut PhysicalElements, x: f64| match keyword {
            "transmission_damping" => e.transmission_damping = Some(x),
            "handle_mass" => e.handle_mass = Some(x),
            _ => e.motor_damping = Some(x),
        };
        put(&mut low, lo);
        element_interval_is_proved(low, keyword, (lo, hi), 100, put);
    }
}

/// Two element parameters spread in one box, `--velocity-filter-cutoff 30..60
/// --actuator-time-constant 0.0003..0.0006`: proved over the box (each cell in the
/// mean-value form in both), the verified wall stable by eigenvalues at the 11 x 11 grid of
/// cutoffs and time constants, and the wall 0.1 % above the optimum not proved and unstable
/// at a binding member.
#[test]
fn cutoff_and_lag_box_is_proved() {
    let mut named = PhysicalElements::default();
    named.velocity_filter_cutoff = Some(30.0);
    named.actuator_time_constant = Some(3e-4);
    let s = DeviceSet::new(&device(), &named)
        .unwrap()
        .with_interval(
            Quantity::element("velocity_filter_cutoff").unwrap(),
            30.0,
            60.0,
        )
        .unwrap()
        .with_interval(
            Quantity::element("actuator_time_constant").unwrap(),
            3e-4,
            6e-4,
        )
        .unwrap();
    // member `t = i / 120` is the grid point `(i mod 11, i div 11)`
    proved_and_tight(&s, 120, |t| {
        let i = (t * 120.0).round() as u32;
        let mut e = named;
        e.velocity_filter_cutoff = Some(30.0 + 3.0 * f64::from(i % 11));
        e.actuator_time_constant = Some(3e-4 + 3e-5 * f64::from(i / 11));
        (device(), e)
    });
}

/// The second-order Butterworth's cutoff and the lag's time constant in one box,
/// `--velocity-filter-cutoff 40..60 --velocity-filter-order 2 --actuator-time-constant
/// 0.0003..0.0004`: proved over the box (each cell in the second-order form in both), the
/// verified wall stable by eigenvalues at the 11 x 11 grid, and the wall 0.1 % above the
/// optimum not proved and unstable at a binding member.
#[test]
fn second_order_cutoff_and_lag_box_is_proved() {
    let mut named = PhysicalElements::default();
    named.velocity_filter_cutoff = Some(40.0);
    named.velocity_filter_order = Some(2);
    named.actuator_time_constant = Some(3e-4);
    let s = DeviceSet::new(&device(), &named)
        .unwrap()
        .with_interval(
            Quantity::element("velocity_filter_cutoff").unwrap(),
            40.0,
            60.0,
        )
        .unwrap()
        .with_interval(
            Quantity::element("actuator_time_constant").unwrap(),
            3e-4,
            4e-4,
        )
        .unwrap();
    // member `t = i / 120` is the grid point `(i mod 11, i div 11)`
    proved_and_tight(&s, 120, |t| {
        let i = (t * 120.0).round() as u32;
        let mut e = named;
        e.velocity_filter_cutoff = Some(40.0 + 2.0 * f64::from(i % 11));
        e.actuator_time_constant = Some(3e-4 + 1e-5 * f64::from(i / 11));
        (device(), e)
    });
}
