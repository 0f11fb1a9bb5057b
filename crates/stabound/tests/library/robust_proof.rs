//! The box recursion over delay intervals and a hand's parameters, checked against the
//! independent closed-loop state matrices of [`super::robust_sets`] at dense members
//! (fractional delays included, the hand let go too).

use super::robust_sets::{paper_state_matrix, radius, stable_by_eigenvalues, sup_alpha};
use stabound::AmaxOptions;
use stabound::elements::PhysicalElements;
use stabound::params::{Delay, Device, Wall};
use stabound::robust::{
    DeviceSet, PROOF_BUDGET, Quantity, RobustCheck, Verification, prove_wall, robust_alpha_max,
    robust_check,
};

/// The paper's device (`m = T = 1`, `delta = 0.5`) with its delay over `[lo, hi]` samples.
fn jitter(lo: f64, hi: f64) -> DeviceSet {
    let device = Device::new(1.0, 1.0, 0.5, Delay::Samples(lo)).unwrap();
    DeviceSet::new(&device, &PhysicalElements::default())
        .unwrap()
        .with_interval(Quantity::Delay, lo, hi)
        .unwrap()
}

/// The largest spectral radius of the paper's loop under `(alpha, beta)` over `count + 1`
/// evenly spaced delays of `[lo, hi]`.
fn worst_radius(lo: f64, hi: f64, count: u32, alpha: f64, beta: f64) -> f64 {
    (0..=count)
        .map(|i| {
            let d = lo + (hi - lo) * f64::from(i) / f64::from(count);
            radius(paper_state_matrix(0.5, d, alpha, beta))
        })
        .fold(0.0, f64::max)
}

/// `amax --mass 1 --period 1 --damping 0.5 --delay-samples 1..3`: the verified wall is
/// proved over the delay interval, its leaves cover `[1, 3]` without gaps, and it is stable
/// at 1601 delays by eigenvalues.
#[test]
fn delay_interval_optimum_is_proved() {
    let set = jitter(1.0, 3.0);
    let r = robust_alpha_max(&set, &AmaxOptions::default()).unwrap();
    assert!(
        matches!(r.verification, Verification::Proved { .. }),
        "{r:?}"
    );
    assert!(r.verification.describe().starts_with("proved over the box"));
    let wall = Wall::new(r.alpha_verified, r.beta_at_max).unwrap();
    let p = prove_wall(&set, &wall, PROOF_BUDGET).unwrap().unwrap();
    assert!(p.proved && p.leaves.iter().all(|c| c.stable), "{p:?}");
    let mut spans: Vec<(f64, f64)> = p.leaves.iter().map(|c| c.delay).collect();
    spans.sort_by(|a, b| a.0.total_cmp(&b.0));
    assert_eq!(spans[0].0, 1.0);
    assert_eq!(spans[spans.len() - 1].1, 3.0);
    // the halvings of fractions below 1 and their sums with a whole number below 4 are
    // exact, so neighbouring leaves meet exactly
    for w in spans.windows(2) {
        assert_eq!(w[0].1, w[1].0, "{spans:?}");
    }
    let rho = worst_radius(1.0, 3.0, 1600, r.alpha_verified, r.beta_at_max);
    assert!(rho < 1.0, "{rho}");
}

/// A wall 0.1 % above the robust optimum is not proved, and some delay of the interval is
/// unstable under it by eigenvalues (the binding member, 3 samples, is).
#[test]
fn wall_above_the_delay_optimum_is_not_proved() {
    let set = jitter(1.0, 3.0);
    let r = robust_alpha_max(&set, &AmaxOptions::default()).unwrap();
    let (alpha, beta) = (1.001 * r.alpha_max, r.beta_at_max);
    let p = prove_wall(&set, &Wall::new(alpha, beta).unwrap(), PROOF_BUDGET)
        .unwrap()
        .unwrap();
    assert!(!p.proved);
    assert!(p.leaves.iter().any(|c| !c.stable));
    assert!(worst_radius(1.0, 3.0, 400, alpha, beta) >= 1.0);
}

/// A heavier damping (`delta = 2`, `m = T = 1`) with the delay over `0.5..3.7` samples: four
/// pieces, both ends fractional, the first below one sample. The verified optimum is proved,
/// its leaves tile `[0.5, 3.7]`, and it is stable at 1,601 delays by the eigenvalues of the
/// closed-loop state matrix; a wall 0.1 % above the optimum is not proved, and the binding
/// delay is unstable under it by eigenvalues.
#[test]
fn fractional_ends_across_pieces_are_proved_below_the_optimum_only() {
    let device = Device::new(1.0, 1.0, 2.0, Delay::Samples(0.5)).unwrap();
    let set = DeviceSet::new(&device, &PhysicalElements::default())
        .unwrap()
        .with_interval(Quantity::Delay, 0.5, 3.7)
        .unwrap();
    let r = robust_alpha_max(&set, &AmaxOptions::default()).unwrap();
    assert!(
        matches!(r.verification, Verification::Proved { .. }),
        "{r:?}"
    );
    let wall = Wall::new(r.alpha_verified, r.beta_at_max).unwrap();
    let p = prove_wall(&set, &wall, PROOF_BUDGET).unwrap().unwrap();
    assert!(p.proved && p.leaves.iter().all(|c| c.stable), "{p:?}");
    let width: f64 = p.leaves.iter().map(|c| c.delay.1 - c.delay.0).sum();
    // the leaves' ends are sums of a whole number below 4 and halvings of a fraction:
    // each rounds by at most 2^-51, so their widths add to 3.2 within a few hundred of those
    assert!((width - 3.2).abs() < 1e-12, "{width}");
    let delta = 2.0;
    let rho = (0..=1600)
        .map(|i| {
            let d = 0.5 + 3.2 * f64::from(i) / 1600.0;
            radius(paper_state_matrix(
                delta,
                d,
                r.alpha_verified,
                r.beta_at_max,
            ))
        })
        .fold(0.0, f64::max);
    assert!(rho < 1.0, "{rho}");
    let above = Wall::new(1.001 * r.alpha_max, r.beta_at_max).unwrap();
    let p = prove_wall(&set, &above, PROOF_BUDGET).unwrap().unwrap();
    assert!(!p.proved && p.leaves.iter().any(|c| !c.stable));
    let d = match r.binding[..] {
        [member] => member.device().plant().unwrap().d(),
        _ => panic!("one binding delay: {r:?}"),
    };
    assert!(radius(paper_state_matrix(delta, d, above.alpha(), above.beta())) >= 1.0);
}

/// Fractional ends: the robust optimum of delay `1.3..2.6` samples (normalized, `m = T = 1`,
/// `delta = 0.3`) is proved and within 1 % of an independent max-min (bisection at 27
/// delays, golden section in beta); with the damping spread over `0.3..0.8` too, a wall 10 %
/// inside the optimum is proved within the budget and stable on a 21 x 131 grid of members
/// by eigenvalues.
#[test]
fn fractional_delay_and_damping_box_is_proved() {
    let device = Device::new(1.0, 1.0, 0.3, Delay::Samples(1.3)).unwrap();
    let set = DeviceSet::new(&device, &PhysicalElements::default())
        .unwrap()
        .with_interval(Quantity::Delay, 1.3, 2.6)
        .unwrap();
    let r = robust_alpha_max(&set, &AmaxOptions::default()).unwrap();
    assert!(
        matches!(r.verification, Verification::Proved { .. }),
        "{r:?}"
    );
    let grid = |i: u32, n: u32, lo: f64, hi: f64| lo + (hi - lo) * f64::from(i) / f64::from(n);
    let worst = |beta: f64| {
        (0..=26)
            .map(|j| sup_alpha(0.3, grid(j, 26, 1.3, 2.6), beta))
            .fold(f64::INFINITY, f64::min)
    };
    let (mut lo, mut hi) = (0.0, 1.5);
    let g = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..30 {
        let (c, e) = (hi - g * (hi - lo), lo + g * (hi - lo));
        if worst(c) > worst(e) {
            hi = e;
        } else {
            lo = c;
        }
    }
    let best = worst(0.5 * (lo + hi));
    assert!(
        r.alpha_verified >= 0.99 * best && r.alpha_max <= best * 1.001,
        "robust {r:?}, independent {best}"
    );
    let both = set.with_interval(Quantity::Damping, 0.3, 0.8).unwrap();
    let both_opt = robust_alpha_max(&both, &AmaxOptions::default()).unwrap();
    let (alpha, beta) = (0.9 * both_opt.alpha_max, both_opt.beta_at_max);
    let p = prove_wall(&both, &Wall::new(alpha, beta).unwrap(), PROOF_BUDGET)
        .unwrap()
        .unwrap();
    assert!(p.proved, "{} cells", p.evaluated);
    for i in 0..=20 {
        for j in 0..=130 {
            let (delta, d) = (grid(i, 20, 0.3, 0.8), grid(j, 130, 1.3, 2.6));
            let rho = radius(paper_state_matrix(delta, d, alpha, beta));
            assert!(rho < 1.0, "delta {delta}, d {d}: {rho}");
        }
    }
}

/// Delay `1.3..2.6` samples with the damping over `0.3..0.8` (normalized): the robust optimum
/// itself, a tenth of a percent inside, is proved within the budget, and its wall is stable
/// on a 21 x 131 grid of members by eigenvalues; a wall 0.1 % above the optimum is not
/// proved, and the binding member is unstable under it by eigenvalues.
#[test]
fn delay_and_damping_optimum_is_proved() {
    let device = Device::new(1.0, 1.0, 0.3, Delay::Samples(1.3)).unwrap();
    let set = DeviceSet::new(&device, &PhysicalElements::default())
        .unwrap()
        .with_interval(Quantity::Delay, 1.3, 2.6)
        .unwrap()
        .with_interval(Quantity::Damping, 0.3, 0.8)
        .unwrap();
    let r = robust_alpha_max(&set, &AmaxOptions::default()).unwrap();
    assert!(
        matches!(r.verification, Verification::Proved { .. }),
        "{r:?}"
    );
    let (alpha, beta) = (r.alpha_verified, r.beta_at_max);
    let grid = |i: u32, n: u32, lo: f64, hi: f64| lo + (hi - lo) * f64::from(i) / f64::from(n);
    for i in 0..=20 {
        for j in 0..=130 {
            let (delta, d) = (grid(i, 20, 0.3, 0.8), grid(j, 130, 1.3, 2.6));
            let rho = radius(paper_state_matrix(delta, d, alpha, beta));
            assert!(rho < 1.0, "delta {delta}, d {d}: {rho}");
        }
    }
    let above = Wall::new(1.001 * r.alpha_max, beta).unwrap();
    let p = prove_wall(&set, &above, PROOF_BUDGET).unwrap().unwrap();
    assert!(!p.proved);
    let member = r.binding[0].device().plant().unwrap();
    let m = paper_state_matrix(member.delta(), member.d(), above.alpha(), above.beta());
    assert!(radius(m) >= 1.0, "{r:?}");
}

/// A delay in seconds proves the same wall as the same delays in samples, and `check` says
/// proved; a wall unstable only at fractional delays is not proved (the recursion looks
/// between whole delays, not only at them).
#[test]
fn seconds_and_interior_members() {
    let device = Device::new(1.0, 1e-3, 500.0, Delay::Seconds(1e-3)).unwrap();
    let secs = DeviceSet::new(&device, &PhysicalElements::default())
        .unwrap()
        .with_interval(Quantity::Delay, 1e-3, 3e-3)
        .unwrap();
    // delta = b T / m = 0.5, as the paper's device: a wall 5 % inside its optimum
    let r = robust_alpha_max(&jitter(1.0, 3.0), &AmaxOptions::default()).unwrap();
    let wall = Wall::new(0.95 * r.alpha_max, r.beta_at_max).unwrap();
    assert!(
        prove_wall(&secs, &wall, PROOF_BUDGET)
            .unwrap()
            .unwrap()
            .proved
    );
    assert!(matches!(
        robust_check(&secs, &wall).unwrap(),
        RobustCheck::Stable(Verification::Proved { .. })
    ));
    // the optimum of [1, 2.5] (a tenth of a percent inside) is proved there, and not over
    // [1, 2.55]: the whole delays 1 and 2 are stable under it, only fractional ones fail
    let r = robust_alpha_max(&jitter(1.0, 2.5), &AmaxOptions::default()).unwrap();
    let wall = Wall::new(0.999 * r.alpha_max, r.beta_at_max).unwrap();
    let (a, b) = (wall.alpha(), wall.beta());
    assert!(
        prove_wall(&jitter(1.0, 2.5), &wall, PROOF_BUDGET)
            .unwrap()
            .unwrap()
            .proved
    );
    assert!(
        !prove_wall(&jitter(1.0, 2.55), &wall, PROOF_BUDGET)
            .unwrap()
            .unwrap()
            .proved
    );
    assert!(radius(paper_state_matrix(0.5, 1.0, a, b)) < 1.0);
    assert!(radius(paper_state_matrix(0.5, 2.0, a, b)) < 1.0);
    assert!(radius(paper_state_matrix(0.5, 2.55, a, b)) >= 1.0);
}

/// A 0.1 kg device at 1 kHz held by a hand of 300 N/m whose mass is `hand_mass` and damping
/// `hand_damping`, through a 50 Hz velocity filter when `filtered`.
fn held(hand_mass: f64, hand_damping: f64, filtered: bool) -> (Device, PhysicalElements) {
    let device = Device::new(0.1, 1e-3, 1.0, Delay::Samples(1.0)).unwrap();
    let mut hand = PhysicalElements::default();
    hand.hand_mass = Some(hand_mass);
    hand.hand_damping = Some(hand_damping);
    hand.hand_stiffness = Some(300.0);
    if filtered {
        hand.velocity_filter_cutoff = Some(50.0);
    }
    (device, hand)
}

/// A hand whose mass is anywhere in `0.2..0.5` kg and that can let go: the robust optimum
/// is proved, the free device is a cell of its own (no hand), and the verified wall is
/// stable for 201 hand masses and for the free device by eigenvalues; the same through a
/// 50 Hz velocity filter.
#[test]
fn hand_mass_interval_is_proved_with_the_hand_let_go() {
    for filtered in [false, true] {
        let (device, hand) = held(0.2, 2.0, filtered);
        let set = DeviceSet::new(&device, &hand)
            .unwrap()
            .with_interval(Quantity::element("hand_mass").unwrap(), 0.2, 0.5)
            .unwrap();
        let r = robust_alpha_max(&set, &AmaxOptions::default()).unwrap();
        assert!(
            matches!(r.verification, Verification::Proved { .. }),
            "{filtered}: {r:?}"
        );
        let wall = Wall::new(r.alpha_verified, r.beta_at_max).unwrap();
        let p = prove_wall(&set, &wall, PROOF_BUDGET).unwrap().unwrap();
        assert!(p.proved);
        // the free device is one leaf; the held leaves' hand masses tile [0.2, 0.5]
        let free_leaves = p.leaves.iter().filter(|c| c.hand == [(0.0, 0.0); 3]);
        assert_eq!(free_leaves.count(), 1);
        let width: f64 = p
            .leaves
            .iter()
            .filter(|c| c.hand != [(0.0, 0.0); 3])
            .map(|c| c.hand[0].1 - c.hand[0].0)
            .sum();
        // the halvings are exact; a sum of a few dozen widths rounds far below 1e-12
        assert!((width - 0.3).abs() <= 1e-12, "{width}");
        let (k, b) = (
            device.stiffness(r.alpha_verified),
            device.wall_damping(r.beta_at_max),
        );
        for i in 0..=200 {
            let mut e = hand;
            e.hand_mass = Some(0.2 + 0.3 * f64::from(i) / 200.0);
            assert!(stable_by_eigenvalues(&device, &e, k, b), "{e:?}");
        }
        let mut free = hand;
        (free.hand_mass, free.hand_damping, free.hand_stiffness) = (None, None, None);
        assert!(stable_by_eigenvalues(&device, &free, k, b));
    }
}

/// A hand always on the handle whose mass (0.2..0.5 kg) and stiffness (100..300 N/m) vary: a
/// wall 0.1 % inside the robust optimum is proved and stable on a 21 x 21 grid of hands by
/// eigenvalues; a wall 0.1 % above it is not proved, `check` names a failing member, and
/// some hand of the grid is unstable under it by eigenvalues.
#[test]
fn gripped_hand_box_is_proved_only_below_the_optimum() {
    let (device, hand) = held(0.2, 0.0, false);
    let set = DeviceSet::new(&device, &hand)
        .unwrap()
        .with_interval(Quantity::element("hand_mass").unwrap(), 0.2, 0.5)
        .unwrap()
        .with_interval(Quantity::element("hand_stiffness").unwrap(), 100.0, 300.0)
        .unwrap()
        .always_gripped(true);
    let r = robust_alpha_max(&set, &AmaxOptions::default()).unwrap();
    let members = |alpha: f64| {
        let (k, b) = (device.stiffness(alpha), device.wall_damping(r.beta_at_max));
        (0..=20)
            .flat_map(|i| (0..=20).map(move |j| (i, j)))
            .filter(|&(i, j)| {
                let mut e = hand;
                e.hand_mass = Some(0.2 + 0.3 * f64::from(i) / 20.0);
                e.hand_stiffness = Some(100.0 + 200.0 * f64::from(j) / 20.0);
                stable_by_eigenvalues(&device, &e, k, b)
            })
            .count()
    };
    let below = Wall::new(0.999 * r.alpha_max, r.beta_at_max).unwrap();
    assert!(
        prove_wall(&set, &below, PROOF_BUDGET)
            .unwrap()
            .unwrap()
            .proved
    );
    assert_eq!(members(below.alpha()), 441);
    let above = Wall::new(1.001 * r.alpha_max, r.beta_at_max).unwrap();
    assert!(
        !prove_wall(&set, &above, PROOF_BUDGET)
            .unwrap()
            .unwrap()
            .proved
    );
    assert!(matches!(
        robust_check(&set, &above).unwrap(),
        RobustCheck::Fails(..)
    ));
    assert!(members(above.alpha()) < 441);
}
