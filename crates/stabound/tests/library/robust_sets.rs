//! Walls for a set of devices, checked against an independent closed-loop state matrix
//! (built here from the model document's section 2, eigenvalues by nalgebra's Schur form) and
//! an independent max-min search by bisection.

use nalgebra::DMatrix;
use stabound::AmaxOptions;
use stabound::elements::PhysicalElements;
use stabound::params::{Delay, Device, Wall};
use stabound::robust::{
    DeviceSet, Quantity, RobustCheck, Spread, Verification, prove_wall, robust_alpha_max,
    robust_check,
};
use stabound::stability::{Checker, Options};

/// The paper's closed loop (normalized, `delta`, any real delay `d`) as a state matrix over
/// `(x_k, v_k, x_{k-1}, f_{k-1}, ..., f_{k-n-1})`, from the exact ZOH discretization.
pub(super) fn paper_state_matrix(delta: f64, d: f64, alpha: f64, beta: f64) -> DMatrix<f64> {
    let n = d.floor() as usize;
    let eps = d - d.floor();
    let c = |t: f64| (-delta * t).exp();
    let phi1 = |t: f64| -(-delta * t).exp_m1() / delta;
    let phi2 = |t: f64| (t - phi1(t)) / delta;
    let (g0x, g0v) = (phi2(1.0 - eps), phi1(1.0 - eps));
    let (g1x, g1v) = (
        phi2(eps) + phi1(1.0 - eps) * phi1(eps),
        c(1.0 - eps) * phi1(eps),
    );
    let dim = 3 + n + 1;
    // the row giving f_{k-j} from the state
    let force = |j: usize| -> Vec<f64> {
        let mut r = vec![0.0; dim];
        if j == 0 {
            r[0] = -(alpha + beta);
            r[2] = beta;
        } else {
            r[3 + j - 1] = 1.0;
        }
        r
    };
    let (f0, f1) = (force(n), force(n + 1));
    let mut a = DMatrix::zeros(dim, dim);
    for col in 0..dim {
        a[(0, col)] = g0x * f0[col] + g1x * f1[col];
        a[(1, col)] = g0v * f0[col] + g1v * f1[col];
    }
    a[(0, 0)] += 1.0;
    a[(0, 1)] += phi1(1.0);
    a[(1, 1)] += c(1.0);
    a[(2, 0)] = 1.0;
    let now = force(0);
    for col in 0..dim {
        a[(3, col)] = now[col];
    }
    for i in 1..=n {
        a[(3 + i, 3 + i - 1)] = 1.0;
    }
    a
}

pub(super) fn radius(m: DMatrix<f64>) -> f64 {
    let schur = nalgebra::linalg::Schur::try_new(m, 1e-14, 10_000).expect("Schur converges");
    schur
        .complex_eigenvalues()
        .iter()
        .map(|z| z.norm())
        .fold(0.0, f64::max)
}

/// The largest stable alpha at beta by bisection on the independent spectral radius, the
/// stable set at fixed beta being `(0, hi)` for the paper's loop.
pub(super) fn sup_alpha(delta: f64, d: f64, beta: f64) -> f64 {
    let stable = |a: f64| radius(paper_state_matrix(delta, d, a, beta)) < 1.0;
    let (mut lo, mut hi) = (1e-6, 4.0);
    if !stable(lo) {
        return 0.0;
    }
    for _ in 0..50 {
        let m = 0.5 * (lo + hi);
        if stable(m) {
            lo = m;
        } else {
            hi = m;
        }
    }
    lo
}

/// `amax --mass 1 --period 1 --damping 0.5 --delay-samples 1..3`: the verified wall is stable
/// at 401 delays of [1, 3] (fractional ones included) and within 1 % of an independent
/// max-min over 41 delays and a golden-section search in beta.
#[test]
fn delay_interval_wall_holds_and_is_near_the_best() {
    let device = Device::new(1.0, 1.0, 0.5, Delay::Samples(1.0)).unwrap();
    let set = DeviceSet::new(&device, &PhysicalElements::default())
        .unwrap()
        .with_interval(Quantity::Delay, 1.0, 3.0)
        .unwrap();
    let r = robust_alpha_max(&set, &AmaxOptions::default()).unwrap();
    assert!(
        matches!(r.verification, Verification::Proved { .. }),
        "{r:?}"
    );
    for i in 0..=400 {
        let d = 1.0 + 2.0 * f64::from(i) / 400.0;
        let rho = radius(paper_state_matrix(0.5, d, r.alpha_verified, r.beta_at_max));
        assert!(rho < 1.0, "d = {d}: radius {rho} at {r:?}");
    }
    // independent max-min: min over 41 delays of the bisected limit, maximized over beta
    let worst = |beta: f64| {
        (0..=40)
            .map(|i| sup_alpha(0.5, 1.0 + 2.0 * f64::from(i) / 40.0, beta))
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
        "robust {r:?}, independent {best} at beta {}",
        0.5 * (lo + hi)
    );
    // the binding member is the longest delay
    assert!(
        r.binding
            .iter()
            .any(|m| m.device().delay() == Delay::Samples(3.0)),
        "{:?}",
        r.binding
    );
}

/// Every eigenvalue of the closed loop of each member inside the unit circle, from the
/// loop's state matrix (no Schur-Cohn, no stable set).
pub(super) fn stable_by_eigenvalues(
    device: &Device,
    named: &PhysicalElements,
    k: f64,
    b: f64,
) -> bool {
    let lp = stabound::elements::Loop::physical(device, named).unwrap();
    let checker = Checker::new(lp, Options::default()).unwrap();
    let wall = device.wall(k, b).unwrap();
    radius(checker.state_matrix(&wall)) < 1.0
}

/// A hand on the handle: the robust wall holds with the hand and without it, and is no
/// stiffer than the free device's own limit; with the hand always gripped the free device
/// is not a member and the wall may be stiffer than the free device allows.
#[test]
fn hand_can_let_go() {
    let device = Device::new(0.1, 1e-3, 0.0, Delay::Samples(1.0)).unwrap();
    let mut hand = PhysicalElements::default();
    hand.hand_mass = Some(0.3);
    hand.hand_damping = Some(2.0);
    hand.hand_stiffness = Some(300.0);
    hand.velocity_filter_cutoff = Some(50.0);
    let set = DeviceSet::new(&device, &hand).unwrap();
    assert!(set.hand_may_let_go());
    let r = robust_alpha_max(&set, &AmaxOptions::default()).unwrap();
    assert!(matches!(r.verification, Verification::Exact { members: 2 }));
    let mut free = hand;
    free.hand_mass = None;
    free.hand_damping = None;
    free.hand_stiffness = None;
    let k = device.stiffness(r.alpha_verified * (1.0 - 1e-6));
    let b = device.wall_damping(r.beta_at_max);
    assert!(stable_by_eigenvalues(&device, &hand, k, b));
    assert!(stable_by_eigenvalues(&device, &free, k, b));
    let gripped =
        robust_alpha_max(&set.clone().always_gripped(true), &AmaxOptions::default()).unwrap();
    assert!(gripped.alpha_max > r.alpha_max, "{gripped:?} vs {r:?}");
    let k = device.stiffness(gripped.alpha_max * (1.0 - 1e-6));
    let b = device.wall_damping(gripped.beta_at_max);
    assert!(stable_by_eigenvalues(&device, &hand, k, b));
    assert!(!stable_by_eigenvalues(&device, &free, k, b));
}

/// The worst case of a hand-mass interval need not sit at a corner: whatever the search
/// reports, every one of 41 hand masses (and the free device) is stable at the verified
/// wall, by eigenvalues.
#[test]
fn hand_mass_interval_holds_everywhere() {
    let device = Device::new(0.1, 1e-3, 1.0, Delay::Samples(1.0)).unwrap();
    let mut hand = PhysicalElements::default();
    hand.hand_mass = Some(0.2);
    hand.hand_stiffness = Some(300.0);
    let set = DeviceSet::new(&device, &hand)
        .unwrap()
        .with_interval(Quantity::element("hand_mass").unwrap(), 0.2, 0.5)
        .unwrap();
    let r = robust_alpha_max(&set, &AmaxOptions::default()).unwrap();
    assert!(r.verification.holds(), "{r:?}");
    let k = device.stiffness(r.alpha_verified);
    let b = device.wall_damping(r.beta_at_max);
    for i in 0..=40 {
        let mut e = hand;
        e.hand_mass = Some(0.2 + 0.3 * f64::from(i) / 40.0);
        assert!(stable_by_eigenvalues(&device, &e, k, b), "{e:?}");
    }
    assert!(stable_by_eigenvalues(
        &device,
        &PhysicalElements::default(),
        k,
        b
    ));
}

/// A wall stable at 1 sample of delay but not at 3 fails for the set, at a long delay; a
/// soft one holds.
#[test]
fn check_names_the_failing_member() {
    let device = Device::new(1.0, 1.0, 0.5, Delay::Samples(1.0)).unwrap();
    let set = DeviceSet::new(&device, &PhysicalElements::default())
        .unwrap()
        .with_interval(Quantity::Delay, 1.0, 3.0)
        .unwrap();
    let stiff = Wall::new(0.3, 0.4).unwrap();
    assert!(radius(paper_state_matrix(0.5, 1.0, 0.3, 0.4)) < 1.0);
    match robust_check(&set, &stiff).unwrap() {
        RobustCheck::Fails(m, _) => {
            let Delay::Samples(d) = m.device().delay() else {
                panic!("samples")
            };
            assert!(radius(paper_state_matrix(0.5, d, 0.3, 0.4)) >= 1.0, "{d}");
        }
        other => panic!("{other:?}"),
    }
    assert!(matches!(
        robust_check(&set, &Wall::new(0.02, 0.3).unwrap()).unwrap(),
        RobustCheck::Stable(Verification::Proved { .. })
    ));
}

/// A scene device with a hand is checked with the hand on the handle and with it let go
/// (the firmware wall: stable held, unstable free, by eigenvalues); with
/// `always_gripped = true` only the held device is checked, and the report says so.
#[test]
fn scene_checks_the_hand_let_go() {
    use stabound::scene::{Scene, SceneFormat};
    let text = |extra: &str| {
        format!(
            "[[device]]\nname = \"proto\"\nmass_kg = 0.1\nperiod_s = 0.001\ndamping_Ns_per_m = 0\ndelay_samples = 1\nhand_mass_kg = 0.3\nhand_damping_Ns_per_m = 2\nhand_stiffness_N_per_m = 300\nvelocity_filter_cutoff_Hz = 50\n{extra}\n[[device.wall]]\nstiffness_N_per_m = 17924\ndamping_Ns_per_m = 96\n"
        )
    };
    let device = Device::new(0.1, 1e-3, 0.0, Delay::Samples(1.0)).unwrap();
    let mut held = PhysicalElements::default();
    held.velocity_filter_cutoff = Some(50.0);
    let free = held;
    held.hand_mass = Some(0.3);
    held.hand_damping = Some(2.0);
    held.hand_stiffness = Some(300.0);
    let held_stable = stable_by_eigenvalues(&device, &held, 17924.0, 96.0);
    let free_stable = stable_by_eigenvalues(&device, &free, 17924.0, 96.0);
    assert!(held_stable && !free_stable);
    let scene = Scene::parse(&text(""), SceneFormat::Toml, "t.toml").unwrap();
    let r = scene.check(&Options::default()).unwrap();
    assert_eq!(r.devices.len(), 2);
    assert_eq!(r.devices[1].name, "proto (hand let go)");
    assert!(r.devices[0].elements.contains(&"hand") && !r.devices[1].elements.contains(&"hand"));
    let verdicts: Vec<bool> = r
        .devices
        .iter()
        .map(|d| d.walls[0].verdict.is_stable())
        .collect();
    assert_eq!(verdicts, [held_stable, free_stable]);
    assert!(r.to_text().contains("hand: let go"));
    let gripped = Scene::parse(&text("always_gripped = true"), SceneFormat::Toml, "t.toml")
        .unwrap()
        .check(&Options::default())
        .unwrap();
    assert_eq!(gripped.devices.len(), 1);
    assert!(gripped.to_text().contains("hand: always on the handle"));
    // no hand: nothing to let go
    let bare = text("").replace(
        "hand_mass_kg = 0.3\nhand_damping_Ns_per_m = 2\nhand_stiffness_N_per_m = 300\n",
        "",
    );
    let r = Scene::parse(&bare, SceneFormat::Toml, "t.toml")
        .unwrap()
        .check(&Options::default())
        .unwrap();
    assert_eq!(r.devices.len(), 1);
    assert!(r.devices[0].hand.is_none());
}

/// The robust region of a finite set (two masses of one device): every member is
/// intersected, walls 1 % inside the region's edge of largest stiffness are stable for both
/// masses and walls 1 % outside fail for one, by the independent state matrix; its
/// rightmost point is the robust `alpha_max`.
#[test]
fn robust_region_is_the_intersection() {
    let device = Device::new(0.8, 1.0, 0.5, Delay::Samples(1.0)).unwrap();
    let set = DeviceSet::new(&device, &PhysicalElements::default())
        .unwrap()
        .with_values(Quantity::Mass, &[0.8, 1.25])
        .unwrap();
    let r = stabound::robust::robust_region(&set, 1e-8).unwrap();
    assert!(r.exact && r.members.len() == 2 && r.pieces == 1, "{r:?}");
    let pts = r.boundary.xy();
    assert_eq!(pts.first(), pts.last());
    assert!(r.boundary.area() > 0.0, "counterclockwise");
    // member of mass m sees the reference wall (alpha, beta) as (0.8 / m) (alpha, beta)
    let stable_at = |m: f64, a: f64, b: f64| {
        let s = 0.8 / m;
        radius(paper_state_matrix(0.5 / m, 1.0, a * s, b * s)) < 1.0
    };
    let mut tried = 0;
    for &(a, b) in pts.iter().step_by((pts.len() / 60).max(1)) {
        if a < 1e-3 {
            continue;
        }
        tried += 1;
        assert!(
            stable_at(0.8, 0.99 * a, b) && stable_at(1.25, 0.99 * a, b),
            "inside ({a}, {b})"
        );
        assert!(
            !stable_at(0.8, 1.01 * a, b) || !stable_at(1.25, 1.01 * a, b),
            "outside ({a}, {b})"
        );
    }
    assert!(tried > 10, "{tried}");
    let best = robust_alpha_max(&set, &AmaxOptions::default()).unwrap();
    let (right, _) = r.boundary.rightmost();
    assert!(
        (right - best.alpha_max).abs() < 1e-4 * best.alpha_max,
        "{right} vs {}",
        best.alpha_max
    );
    // the intersection lies within each member's own region
    for mb in &r.member_boundaries {
        assert!(r.boundary.area() <= mb.area() * (1.0 + 1e-6));
    }
}

/// The region's edges at each damping of its polygon: `(beta, lo, hi)`, the upper and
/// lower vertices paired by their damping (the polygon runs up one edge and back down the
/// other, so both ends of a strip share its damping exactly).
fn region_strips(pts: &[(f64, f64)]) -> Vec<(f64, f64, f64)> {
    let mut by_beta: std::collections::BTreeMap<u64, (f64, f64, f64)> = Default::default();
    for &(a, b) in pts {
        let e = by_beta.entry(b.to_bits()).or_insert((b, a, a));
        e.1 = e.1.min(a);
        e.2 = e.2.max(a);
    }
    by_beta.into_values().collect()
}

/// Whether `(a, b)` lies inside the closed polygon `pts` (even-odd rule).
fn inside_polygon(pts: &[(f64, f64)], (a, b): (f64, f64)) -> bool {
    let mut inside = false;
    for w in pts.windows(2) {
        let ((x0, y0), (x1, y1)) = (w[0], w[1]);
        if (y0 > b) != (y1 > b) && a < x0 + (b - y0) * (x1 - x0) / (y1 - y0) {
            inside = !inside;
        }
    }
    inside
}

/// A delay interval whose binding member is interior: the device's damping `delta = 2`,
/// the delay anywhere in 1..3 samples. At large wall dampings a delay near 2.9 samples
/// leaves no stable stiffness where the ends and middle (1, 2, 3) still share some, so the
/// intersection over those three (the finite set, the region before the search) holds
/// walls unstable at a delay of a 101-point grid, by the independent state matrix. The
/// region searched over the interval leaves them out, and every one of its strips, its
/// edges moved `tol` inward (its middle where it is narrower than `2 tol`), is stable at
/// all 101 delays.
#[test]
fn robust_region_finds_an_interior_binding_delay() {
    interior_binding_delay(1e-6);
}

/// The same below the first pass's tolerance, where the region is drawn twice and the final
/// pass searches only where a member cut in the first: the same checks hold, and the final
/// pass searched some of its dampings, not all.
#[test]
fn robust_region_two_passes_find_the_interior_binding_delay() {
    let s = interior_binding_delay(1e-8);
    assert_eq!(s.first_pass, Some(stabound::robust::FIRST_PASS_TOL));
    assert!(
        s.final_searched > 0 && s.final_searched < s.final_dampings,
        "{s:?}"
    );
}

/// The checks of [`robust_region_finds_an_interior_binding_delay`] at `tol`; the search's
/// account.
fn interior_binding_delay(tol: f64) -> stabound::robust::RegionSearch {
    let device = Device::new(1.0, 1.0, 2.0, Delay::Samples(1.0)).unwrap();
    let base = DeviceSet::new(&device, &PhysicalElements::default()).unwrap();
    let three = base
        .clone()
        .with_values(Quantity::Delay, &[1.0, 2.0, 3.0])
        .unwrap();
    let old = stabound::robust::robust_region(&three, tol).unwrap();
    let set = base.with_interval(Quantity::Delay, 1.0, 3.0).unwrap();
    let new = stabound::robust::robust_region(&set, tol).unwrap();
    let search = new.search.as_ref().expect("intervals are searched");
    assert!(search.found > 0 && search.unresolved == 0, "{search:?}");
    let (deepest, by) = search.deepest.expect("a member cut the strip");
    let Delay::Samples(d) = deepest.device().delay() else {
        panic!("{deepest:?}")
    };
    assert!(d > 2.0 && d < 3.0, "{d}");
    assert!(by > 0.0, "{by}");
    let delays: Vec<f64> = (0..=100)
        .map(|i| 1.0 + 2.0 * f64::from(i) / 100.0)
        .collect();
    let unstable_at = |a: f64, b: f64| {
        delays
            .iter()
            .copied()
            .find(|&d| radius(paper_state_matrix(2.0, d, a, b)) >= 1.0)
    };
    // walls tol inside the old region's upper edge that a delay of the grid makes unstable
    let old_pts = old.boundary.xy();
    let bad: Vec<(f64, f64, f64)> = region_strips(&old_pts)
        .into_iter()
        .filter(|&(_, lo, hi)| hi - lo > 2.0 * tol)
        .filter_map(|(b, _, hi)| unstable_at(hi - tol, b).map(|d| (hi - tol, b, d)))
        .collect();
    assert!(bad.len() > 3, "{bad:?}");
    assert!(
        bad.iter().any(|&(_, _, d)| d > 2.0 && d < 3.0),
        "an interior delay binds: {bad:?}"
    );
    let new_pts = new.boundary.xy();
    for &(a, b, d) in &bad {
        assert!(
            !inside_polygon(&new_pts, (a, b)),
            "({a}, {b}) unstable at d = {d} is inside the searched region"
        );
    }
    let strips = region_strips(&new_pts);
    assert!(strips.len() > 100, "{}", strips.len());
    for (b, lo, hi) in strips {
        let walls = if hi - lo > 2.0 * tol {
            vec![hi - tol, lo + tol]
        } else {
            vec![0.5 * (lo + hi)]
        };
        for a in walls {
            assert_eq!(unstable_at(a, b), None, "({a}, {b}) of [{lo}, {hi}]");
        }
    }
    search.clone()
}

/// A device whose mass lies in 0.09..0.11 kg (and, with `damping`, whose damping lies in
/// 0.5..1 N s/m; else 0.5 N s/m), `T = 1 ms`, one sample of delay.
fn mass_box(damping: bool) -> DeviceSet {
    let device = Device::new(0.09, 1e-3, 0.5, Delay::Samples(1.0)).unwrap();
    let set = DeviceSet::new(&device, &PhysicalElements::default())
        .unwrap()
        .with_interval(Quantity::Mass, 0.09, 0.11)
        .unwrap();
    if damping {
        set.with_interval(Quantity::Damping, 0.5, 1.0).unwrap()
    } else {
        set
    }
}

/// The spectral radius of the member `(m, b)` of [`mass_box`] under the wall
/// `(alpha, beta)` in the set's reference normalization (`m_ref = 0.09`), by the independent
/// state matrix.
fn box_member_radius(m: f64, b: f64, alpha: f64, beta: f64) -> f64 {
    let s = 0.09 / m;
    radius(paper_state_matrix(b * 1e-3 / m, 1.0, alpha * s, beta * s))
}

/// `amax --mass 0.09..0.11 --period 0.001 --damping 0.5 --delay-samples 1`: the robust
/// optimum's verified wall is proved over the box and stable for 401 masses by eigenvalues;
/// `check` of a wall 5 % below the optimum says proved too.
#[test]
fn mass_interval_optimum_is_proved() {
    let set = mass_box(false);
    let r = robust_alpha_max(&set, &AmaxOptions::default()).unwrap();
    assert!(
        matches!(r.verification, Verification::Proved { .. }),
        "{r:?}"
    );
    assert!(r.verification.describe().contains("proved over the box"));
    for i in 0..=400 {
        let m = 0.09 + 0.02 * f64::from(i) / 400.0;
        let rho = box_member_radius(m, 0.5, r.alpha_verified, r.beta_at_max);
        assert!(rho < 1.0, "m = {m}: radius {rho} at {r:?}");
    }
    let wall = Wall::new(0.95 * r.alpha_max, r.beta_at_max).unwrap();
    let check = robust_check(&set, &wall).unwrap();
    assert!(
        matches!(check, RobustCheck::Stable(Verification::Proved { .. })),
        "{check:?}"
    );
}

/// Over mass and damping, a wall 5 % below the robust optimum is proved, stable for 41 x 41
/// members by eigenvalues, and the recursion's leaves cover the box (their areas add up to
/// it and every grid member lies in one).
#[test]
fn mass_and_damping_box_is_proved() {
    let set = mass_box(true);
    let r = robust_alpha_max(&set, &AmaxOptions::default()).unwrap();
    assert!(
        matches!(r.verification, Verification::Proved { .. }),
        "{r:?}"
    );
    let (alpha, beta) = (0.95 * r.alpha_max, r.beta_at_max);
    let wall = Wall::new(alpha, beta).unwrap();
    let p = prove_wall(&set, &wall, 4096).unwrap().expect("qualifies");
    assert!(p.proved, "{p:?}");
    let grid = |i: usize, lo: f64, hi: f64| lo + (hi - lo) * i as f64 / 40.0;
    let mut area = 0.0;
    for c in &p.leaves {
        assert!(c.stable && 0.09 <= c.mass.0 && c.mass.1 <= 0.11);
        assert!(0.5 <= c.damping.0 && c.damping.1 <= 1.0);
        area += (c.mass.1 - c.mass.0) * (c.damping.1 - c.damping.0);
    }
    // the halvings are exact; the sum of a few hundred products rounds far below 1e-12
    assert!((area - 0.02 * 0.5).abs() <= 1e-12, "{area}");
    for i in 0..=40 {
        for j in 0..=40 {
            let (m, b) = (grid(i, 0.09, 0.11), grid(j, 0.5, 1.0));
            assert!(
                p.leaves.iter().any(|c| c.mass.0 <= m
                    && m <= c.mass.1
                    && c.damping.0 <= b
                    && b <= c.damping.1)
            );
            let rho = box_member_radius(m, b, alpha, beta);
            assert!(rho < 1.0, "m = {m}, b = {b}: radius {rho}");
        }
    }
}

/// A wall 0.1 % above the robust optimum is not proved, and some member of the box is
/// unstable under it by eigenvalues.
#[test]
fn wall_above_the_optimum_is_not_proved() {
    let set = mass_box(true);
    let r = robust_alpha_max(&set, &AmaxOptions::default()).unwrap();
    let (alpha, beta) = (1.001 * r.alpha_max, r.beta_at_max);
    let p = prove_wall(&set, &Wall::new(alpha, beta).unwrap(), 4096)
        .unwrap()
        .expect("qualifies");
    assert!(!p.proved);
    assert!(p.leaves.iter().any(|c| !c.stable));
    let worst = (0..=40)
        .flat_map(|i| (0..=40).map(move |j| (i, j)))
        .map(|(i, j)| {
            let m = 0.09 + 0.02 * f64::from(i) / 40.0;
            let b = 0.5 + 0.5 * f64::from(j) / 40.0;
            box_member_radius(m, b, alpha, beta)
        })
        .fold(0.0, f64::max);
    assert!(worst >= 1.0, "{worst}");
    assert!(matches!(
        robust_check(&set, &Wall::new(alpha, beta).unwrap()).unwrap(),
        RobustCheck::Fails(..)
    ));
}

/// A fractional delay (1.5 samples) over the mass box: the robust optimum is proved and its
/// verified wall is stable for 201 masses by eigenvalues.
#[test]
fn mass_interval_with_fractional_delay_is_proved() {
    let device = Device::new(0.09, 1e-3, 0.5, Delay::Samples(1.5)).unwrap();
    let set = DeviceSet::new(&device, &PhysicalElements::default())
        .unwrap()
        .with_interval(Quantity::Mass, 0.09, 0.11)
        .unwrap();
    let r = robust_alpha_max(&set, &AmaxOptions::default()).unwrap();
    assert!(
        matches!(r.verification, Verification::Proved { .. }),
        "{r:?}"
    );
    for i in 0..=200 {
        let m = 0.09 + 0.02 * f64::from(i) / 200.0;
        let s = 0.09 / m;
        let rho = radius(paper_state_matrix(
            0.5e-3 / m,
            1.5,
            r.alpha_verified * s,
            r.beta_at_max * s,
        ));
        assert!(rho < 1.0, "m = {m}: radius {rho} at {r:?}");
    }
}

/// A finite set's members are exactly the values given (sorted, a repeat once), crossed with
/// another list and with the hand let go; the robust optimum of a delay list examines each
/// member once, says it checked every member, and is within 0.1 % of an independent max-min
/// over the three delays (bisected limits on an independent state matrix, golden section in
/// beta), while every delay between the listed ones is no member.
#[test]
fn list_members_are_the_values_given() {
    let device = Device::new(1.0, 1.0, 0.5, Delay::Samples(1.0)).unwrap();
    let set = DeviceSet::new(&device, &PhysicalElements::default())
        .unwrap()
        .with_spread(Quantity::Delay, &Spread::Values(vec![3.0, 1.0, 2.0, 3.0]))
        .unwrap();
    let delays: Vec<Delay> = set
        .sampled_members()
        .iter()
        .map(|m| m.device().delay())
        .collect();
    let given: Vec<Delay> = [1.0, 2.0, 3.0].map(Delay::Samples).to_vec();
    assert_eq!(delays, given);
    assert_eq!(set.reference().device().delay(), Delay::Samples(1.0));
    let r = robust_alpha_max(&set, &AmaxOptions::default()).unwrap();
    assert_eq!(r.verification, Verification::Exact { members: 3 });
    assert!(
        r.verification
            .describe()
            .starts_with("checked for every member")
    );
    assert_eq!(
        r.alpha_verified, r.alpha_max,
        "exact: nothing to verify between members"
    );
    let worst = |beta: f64| {
        [1.0, 2.0, 3.0]
            .iter()
            .map(|&d| sup_alpha(0.5, d, beta))
            .fold(f64::INFINITY, f64::min)
    };
    let (mut lo, mut hi) = (0.0, 1.5);
    let g = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..40 {
        let (c, e) = (hi - g * (hi - lo), lo + g * (hi - lo));
        if worst(c) > worst(e) {
            hi = e;
        } else {
            lo = c;
        }
    }
    let best = worst(0.5 * (lo + hi));
    assert!(
        (r.alpha_max - best).abs() <= 1e-3 * best,
        "robust {r:?}, independent {best}"
    );
    for d in [1.0, 2.0, 3.0] {
        let rho = radius(paper_state_matrix(
            0.5,
            d,
            r.alpha_max * (1.0 - 1e-9),
            r.beta_at_max,
        ));
        assert!(rho < 1.0, "d = {d}");
    }

    // two lists and a hand that lets go: 2 masses x 2 hand masses held, and each mass let go
    let mut hand = PhysicalElements::default();
    hand.hand_mass = Some(0.3);
    hand.hand_stiffness = Some(300.0);
    let dev = Device::new(0.1, 1e-3, 1.0, Delay::Samples(1.0)).unwrap();
    let set = DeviceSet::new(&dev, &hand)
        .unwrap()
        .with_spread(Quantity::Mass, &Spread::Values(vec![0.12, 0.1]))
        .unwrap()
        .with_spread(
            Quantity::element("hand_mass").unwrap(),
            &Spread::Values(vec![0.5, 0.2]),
        )
        .unwrap();
    let mut seen: Vec<(f64, Option<f64>)> = set
        .sampled_members()
        .iter()
        .map(|m| (m.device().mass(), m.elements().hand_mass))
        .collect();
    seen.sort_by(|a, b| a.partial_cmp(b).unwrap());
    assert_eq!(
        seen,
        [
            (0.1, None),
            (0.1, Some(0.2)),
            (0.1, Some(0.5)),
            (0.12, None),
            (0.12, Some(0.2)),
            (0.12, Some(0.5)),
        ]
    );
    // an empty list is refused by name
    let err = DeviceSet::new(&dev, &hand)
        .unwrap()
        .with_spread(Quantity::Delay, &Spread::Values(Vec::new()))
        .unwrap_err();
    assert!(err.to_string().contains("delay list is empty"), "{err}");
}

/// A scene's `{ one_of = [...] }` is the finite set of its values (the optimum of the same
/// set built by the library, its walls judged for each listed member by the independent
/// state matrix), a two-element array stays an interval, and malformed sets are refused
/// with what to write.
#[test]
fn scene_one_of_is_a_finite_set() {
    use stabound::scene::{Scene, SceneFormat};
    let text = |delay: &str| {
        format!(
            "[[device]]\nmass_kg = 1\nperiod_s = 1\ndamping_Ns_per_m = 0.5\ndelay_samples = {delay}\n[[device.wall]]\nstiffness_N_per_m = 0.25\ndamping_Ns_per_m = 0.3\n"
        )
    };
    let parse = |delay: &str| Scene::parse(&text(delay), SceneFormat::Toml, "t.toml");
    let r = parse("{ one_of = [3, 1, 2] }")
        .unwrap()
        .check(&Options::default())
        .unwrap();
    let set = r.devices[0].set.as_ref().expect("a set of devices");
    assert_eq!(set.spread, ["delay 1 or 2 or 3 samples"]);
    let device = Device::new(1.0, 1.0, 0.5, Delay::Samples(1.0)).unwrap();
    let lib = DeviceSet::new(&device, &PhysicalElements::default())
        .unwrap()
        .with_values(Quantity::Delay, &[1.0, 2.0, 3.0])
        .unwrap();
    let expected = robust_alpha_max(&lib, &AmaxOptions::default()).unwrap();
    assert_eq!(set.optimum.alpha_max, expected.alpha_max);
    let unstable_somewhere = [1.0, 2.0, 3.0]
        .iter()
        .any(|&d| radius(paper_state_matrix(0.5, d, 0.25, 0.3)) >= 1.0);
    assert_eq!(set.walls[0].for_every_member, !unstable_somewhere);
    // [1, 3] is every delay between
    let r = parse("[1, 3]").unwrap().check(&Options::default()).unwrap();
    assert_eq!(
        r.devices[0].set.as_ref().unwrap().spread,
        ["delay 1..3 samples"]
    );
    for (bad, says) in [
        ("{ one_of = [] }", "set is empty"),
        ("{ values = [1, 2] }", "one_of = [A, B, ...]"),
        ("{ one_of = [1, -2] }", "not accepted"),
        ("{ one_of = [1, 2], more = 1 }", "one_of = [A, B, ...]"),
    ] {
        let err = parse(bad).unwrap_err().to_string();
        assert!(err.contains(says), "{bad}: {err}");
    }
    let period = text("1").replace("period_s = 1", "period_s = { one_of = [1, 2] }");
    let err = Scene::parse(&period, SceneFormat::Toml, "t.toml").unwrap_err();
    assert!(
        err.to_string().contains("one number for a whole set"),
        "{err}"
    );
}
