//! The boundary of loops with elements: the general D-decomposition against the bisection
//! engine on the loop's point test (Hausdorff distance), against the paper's closed-form
//! engine for the bare loop, and its vertices against the eigenvalues of the closed loop's
//! state matrix (built from the sampled device and the wall law, not from the polynomial).

use stabound::boundary::{
    BisectOptions, Boundary, ExactOptions, Piece, bisect, bisect_alpha_beta, directed_distance,
    exact,
};
use stabound::elements::{Actuator, Encoder, Hand, Loop, Transmission};
use stabound::filter::VelocityFilter;
use stabound::params::{Plant, Wall};
use stabound::stability::Checker;
use stabound::stability::{Options, eigenvalues_capped, spectral_radius};

fn plant(delta: f64, d: f64) -> Loop {
    Loop::new(Plant::new(delta, d).unwrap())
}

/// One loop per element (the hand with a stiffness that makes negative stiffness stable,
/// both encoder sides, a lag, both filters) and one with all of them, named for messages.
pub(crate) fn element_loops() -> Vec<(&'static str, Loop)> {
    let motor = Transmission::new(0.3, 40.0, 0.5, 0.02, Encoder::Motor).unwrap();
    let handle = Transmission::new(0.4, 25.0, 0.3, 0.0, Encoder::Handle).unwrap();
    vec![
        (
            "stiff hand",
            plant(0.2, 1.0)
                .with_hand(Hand::new(0.5, 0.1, 0.01).unwrap())
                .unwrap(),
        ),
        (
            "transmission, motor encoder",
            plant(0.1, 1.0).with_transmission(motor).unwrap(),
        ),
        (
            "transmission, handle encoder",
            plant(0.2, 0.25).with_transmission(handle).unwrap(),
        ),
        (
            "actuator lag",
            plant(0.3, 1.0)
                .with_actuator(Actuator::new(0.7).unwrap())
                .unwrap(),
        ),
        (
            "low-pass filter",
            plant(0.1, 1.0)
                .with_filter(VelocityFilter::low_pass(0.8).unwrap())
                .unwrap(),
        ),
        (
            "moving average",
            plant(0.2, 0.0)
                .with_filter(VelocityFilter::moving_average(3).unwrap())
                .unwrap(),
        ),
        (
            "all elements",
            plant(0.2, 2.5)
                .with_hand(Hand::new(0.5, 0.05, 0.01).unwrap())
                .unwrap()
                .with_transmission(Transmission::new(0.3, 30.0, 0.4, 0.05, Encoder::Motor).unwrap())
                .unwrap()
                .with_actuator(Actuator::new(0.5).unwrap())
                .unwrap()
                .with_filter(VelocityFilter::moving_average(3).unwrap())
                .unwrap(),
        ),
    ]
}

/// The exact and the bisection engines' boundaries of `lp` at `tol`.
fn both_engines(lp: Loop, tol: f64) -> (Boundary, Boundary) {
    let e = exact(lp, &ExactOptions { tol }).unwrap();
    let b = bisect_alpha_beta(
        lp,
        &BisectOptions {
            tol,
            ..BisectOptions::default()
        },
    )
    .unwrap();
    (e, b)
}

fn hausdorff(a: &Boundary, b: &Boundary, cap: f64) -> f64 {
    let (pa, pb) = (a.xy(), b.xy());
    directed_distance(&pa, &pb, cap).max(directed_distance(&pb, &pa, cap))
}

/// Exact and bisection boundaries of every element loop within 10 tol of each other both
/// ways, the criterion the paper's loop meets at this tolerance (boundary_exact.rs): the
/// bisection engine knows only the point test, so agreement checks every piece the exact
/// engine kept or dropped.
#[test]
fn general_exact_matches_bisection_for_each_element() {
    let tol = 1e-6;
    for (name, lp) in element_loops() {
        let (e, b) = both_engines(lp, tol);
        let h = hausdorff(&e, &b, 1e-2);
        assert!(
            h <= 10.0 * tol,
            "{name}: Hausdorff {h:e} ({} vs {} points)",
            e.points.len(),
            b.points.len()
        );
    }
}

/// With no element the general engine (through the discretization by the matrix
/// exponential and La Budde's polynomial) gives the paper engine's boundary (closed forms)
/// within 10 tol, including at delta = 0 where the device's matrix is singular.
#[test]
fn general_exact_is_the_paper_engine_without_elements() {
    let tol = 1e-8;
    for (delta, d) in [
        (0.0, 0.0),
        (0.0, 1.0),
        (0.1, 0.5),
        (0.5, 1.0),
        (1.0, 2.5),
        (2.0, 6.0),
    ] {
        let p = Plant::new(delta, d).unwrap();
        let paper = exact(p, &ExactOptions { tol }).unwrap();
        // a hand of zeros is the same device on the general polynomial
        let general = Loop::new(p)
            .with_hand(Hand::new(0.0, 0.0, 0.0).unwrap())
            .unwrap();
        let general = exact(general, &ExactOptions { tol }).unwrap();
        let h = hausdorff(&paper, &general, 1e-3);
        assert!(h <= 10.0 * tol, "delta {delta} d {d}: Hausdorff {h:e}");
        // the same pieces: alpha = 0 and z = -1 lines, no line off alpha = 0
        assert!(general.points.iter().any(|q| q.piece == Piece::AlphaZero));
        assert!(general.points.iter().all(|q| q.piece != Piece::PlusOne));
        // the paper's lowest point (0, -delta) is where it starts (eq. 19)
        let p0 = general.points[0];
        assert!(
            p0.x.abs() <= 1e-12 && (p0.y + delta).abs() <= 1e-7,
            "{p0:?}"
        );
    }
}

/// Every vertex of the general boundary has spectral radius 1 by the eigenvalues of the
/// closed loop's state matrix. At tol 1e-9 a vertex is within about 1e-9 of the boundary,
/// where the radius moves by at most its slope (below 100 over these loops) times that;
/// the eigenvalues of a nonnormal matrix add about sqrt(eps) near a double root, so 1e-5.
#[test]
fn general_boundary_vertices_have_a_root_on_the_circle() {
    for (name, lp) in element_loops() {
        let b = exact(lp, &ExactOptions { tol: 1e-9 }).unwrap();
        let c = Checker::new(lp, Options::default()).unwrap();
        let step = (b.points.len() / 40).max(1);
        for p in b.points.iter().step_by(step) {
            let w = Wall::new(p.x, p.y).unwrap();
            let rho = spectral_radius(&eigenvalues_capped(c.state_matrix(&w)).unwrap());
            assert!((rho - 1.0).abs() < 1e-5, "{name}: {p:?} radius {rho}");
        }
        // and the region is stable inside: its centroid-ish point (mean of the vertices)
        // is a stable wall for the checker with its default margin
        let n = b.points.len() as f64;
        let (ma, mb) = b
            .points
            .iter()
            .fold((0.0, 0.0), |s, p| (s.0 + p.x / n, s.1 + p.y / n));
        assert!(c.is_stable(&Wall::new(ma, mb).unwrap()).unwrap(), "{name}");
    }
}

/// A hand stiffness moves the z = 1 edge to alpha = -kappa_h (the sampled plant's DC gain
/// equals the continuous one, 1 / kappa_h): the general boundary's leftmost edge is that
/// line, labelled as the z = 1 line off alpha = 0.
#[test]
fn stiff_hand_boundary_reaches_negative_stiffness() {
    for kh in [0.003, 0.01, 0.05] {
        let lp = plant(0.2, 1.0)
            .with_hand(Hand::new(0.5, 0.1, kh).unwrap())
            .unwrap();
        let b = exact(lp, &ExactOptions { tol: 1e-9 }).unwrap();
        let left = b.points.iter().map(|p| p.x).fold(f64::INFINITY, f64::min);
        assert!((left + kh).abs() < 1e-10, "kappa_h {kh}: leftmost {left}");
        let on_line: Vec<_> = b
            .points
            .iter()
            .filter(|p| p.piece == Piece::PlusOne)
            .collect();
        assert!(!on_line.is_empty());
        assert!(on_line.iter().all(|p| (p.x + kh).abs() < 1e-10));
        assert!(b.area() > 0.0);
    }
}

/// Each element's limit in which it disappears gives the bare loop's boundary: a stiff
/// transmission (error first order in 1 / kappa_c), a vanishing actuator lag, a filter
/// cutoff at the pole a = 1e-9 and a hand of zero mass, damping and stiffness.
#[test]
fn element_limits_give_the_bare_boundary() {
    let tol = 1e-8;
    let p = Plant::new(0.2, 1.0).unwrap();
    let bare = exact(p, &ExactOptions { tol }).unwrap();
    let cases: Vec<(&str, Loop, f64)> = vec![
        (
            "zero hand",
            Loop::new(p)
                .with_hand(Hand::new(0.0, 0.0, 0.0).unwrap())
                .unwrap(),
            10.0 * tol,
        ),
        (
            "stiff transmission",
            Loop::new(p)
                .with_transmission(Transmission::new(0.3, 1e5, 1.0, 0.05, Encoder::Motor).unwrap())
                .unwrap(),
            // 0.5 / kappa_c relative (elements.rs), of a boundary of size about 1
            5e-6,
        ),
        (
            "short lag",
            Loop::new(p)
                .with_actuator(Actuator::new(1e-6).unwrap())
                .unwrap(),
            // the lag delays the force by about tau
            1e-5,
        ),
        (
            "low-pass pole 1e-9",
            Loop::new(p)
                .with_filter(VelocityFilter::low_pass(1e-9).unwrap())
                .unwrap(),
            // F differs from 1 by about the pole
            1e-7,
        ),
    ];
    for (name, lp, within) in cases {
        let b = exact(lp, &ExactOptions { tol }).unwrap();
        let h = hausdorff(&bare, &b, 1e-2);
        assert!(h <= within, "{name}: Hausdorff {h:e}");
    }
}

/// The `(delta, beta)` plane of a loop with elements, its loop rebuilt at every `delta`:
/// each vertex `(delta_v, beta_v)` of the contour at fixed `alpha` puts `(alpha, beta_v)` on
/// the general exact `(alpha, beta)` boundary of the loop at `delta_v`. The vertex is within
/// tol = 1e-7 of the contour in the plane; the alpha-beta boundary moves with delta by a
/// slope of order 1 here, so 1e-5 leaves a factor of a hundred.
#[test]
fn delta_beta_plane_of_a_loop_agrees_with_the_exact_boundaries() {
    use stabound::boundary::{Axis, Plane};
    use stabound::params::Normalized;
    let alpha = 0.05;
    let lp = plant(0.1, 1.0)
        .with_actuator(Actuator::new(0.5).unwrap())
        .unwrap()
        .with_filter(VelocityFilter::low_pass(0.5).unwrap())
        .unwrap();
    let plane = Plane {
        x: Axis::Delta,
        y: Axis::Beta,
        at: Normalized::new(alpha, 0.0, 0.0, 1.0).unwrap(),
    };
    let opts = BisectOptions {
        tol: 1e-7,
        grid: 32,
        x_range: Some((0.0, 1.0)),
        y_range: None,
    };
    let c = bisect(lp, &plane, &opts).unwrap();
    let outer = &c.loops[0];
    let step = (outer.len() / 12).max(1);
    let mut checked = 0;
    for v in outer.iter().step_by(step).filter(|v| !v.clipped()) {
        let at = lp.with_plant(Plant::new(v.x, 1.0).unwrap()).unwrap();
        let b = exact(at, &ExactOptions { tol: 1e-9 }).unwrap();
        let d = directed_distance(&[(alpha, v.y)], &b.xy(), 1.0);
        assert!(d < 1e-5, "vertex {v:?}: {d:e} from the exact boundary");
        checked += 1;
    }
    assert!(checked >= 6, "{checked} vertices checked");
}

/// Loops whose exact boundary once did not close (long moving averages at large damping,
/// where the curve runs off to infinity between the average's zeros on the circle and the
/// boundary is made of short pieces between its self-intersections; a damped hand at a long
/// delay) answer, and agree with the bisection engine (which knows only the point test):
/// every bisection vertex is within 10 tol of the region's size of the exact polyline, and
/// every exact vertex farther than that from the bisection polyline (the tips of thin
/// wedges, which the bisection's grid and chord searches cut; at delta 10 with a
/// 16-sample average a wedge 0.02 wide, stable 0.01 inside its edge) has a root on the
/// circle by the eigenvalues of the closed loop's state matrix (1e-5: see
/// `general_boundary_vertices_have_a_root_on_the_circle`). Where the exact engine still
/// cannot close a boundary the answer is the bisection engine's, and says so.
#[test]
fn hard_loops_answer_and_agree_with_bisection() {
    let tol = 1e-6;
    let ma = |delta: f64, d: f64, n: usize| {
        plant(delta, d)
            .with_filter(VelocityFilter::moving_average(n).unwrap())
            .unwrap()
    };
    let loops = [
        ("moving average 16, delta 10", ma(10.0, 0.0, 16)),
        ("moving average 48, delta 10, d 1", ma(10.0, 1.0, 48)),
        ("moving average 64, delta 30", ma(30.0, 0.0, 64)),
        (
            "damped hand, d 9",
            plant(30.353117147339287, 9.0)
                .with_hand(Hand::new(2.4121, 0.624, 0.131521).unwrap())
                .unwrap(),
        ),
    ];
    for (name, lp) in loops {
        let (e, b) = both_engines(lp, tol);
        let size = e
            .points
            .iter()
            .fold(1.0f64, |m, p| m.max(p.x.abs()).max(p.y.abs()));
        let near = 10.0 * tol * size;
        let (pe, pb) = (e.xy(), b.xy());
        let h = directed_distance(&pb, &pe, 1.0);
        assert!(
            h <= near,
            "{name}: bisection vertex {h:e} off at size {size}"
        );
        let c = Checker::new(lp, Options::default()).unwrap();
        // 2,000 exact vertices, each against every bisection segment
        let off: Vec<_> = e
            .points
            .iter()
            .step_by((e.points.len() / 2000).max(1))
            .filter(|p| {
                pb.windows(2)
                    .all(|s| crate::boundary_tolerance::seg_dist(p.xy(), s[0], s[1]) > near)
            })
            .collect();
        for p in off.iter().step_by((off.len() / 100).max(1)) {
            let w = Wall::new(p.x, p.y).unwrap();
            let rho = spectral_radius(&eigenvalues_capped(c.state_matrix(&w)).unwrap());
            assert!((rho - 1.0).abs() < 1e-5, "{name}: {p:?} radius {rho}");
        }
        // a boundary drawn by the fallback is the bisection engine's, and says why
        let bisected = e.points.iter().all(|p| p.piece == Piece::Bisection);
        assert_eq!(e.fallback.is_some(), bisected, "{name}");
        if let Some(why) = &e.fallback {
            assert!(why.contains("did not close"), "{name}: {why}");
        }
    }
}

/// A region too large for the requested tolerance's vertex budget (delta = 1000 behind a
/// 0.1 Hz low-pass filter at T = 1 s: size about 2e3, more than a million vertices at 1e-9)
/// is traced to the same tolerance relative to its size, and says so in `tol`; its
/// rightmost point is alpha_max by the direct search (an independent route: scan, bracket
/// and Brent on the curve, no polyline) within that tolerance, and its vertices have a root
/// on the circle by the closed loop's eigenvalues.
#[test]
fn large_region_is_traced_to_a_relative_tolerance() {
    use stabound::amax::{AmaxOptions, alpha_max};
    let lp = plant(1000.0, 1.0)
        .with_filter(VelocityFilter::low_pass_cutoff(0.1, 1.0).unwrap())
        .unwrap();
    let b = exact(lp, &ExactOptions { tol: 1e-9 }).unwrap();
    let size = b
        .points
        .iter()
        .fold(1.0f64, |m, p| m.max(p.x.abs()).max(p.y.abs()));
    assert!(b.fallback.is_none());
    assert!(
        (b.tol / (1e-9 * size) - 1.0).abs() < 0.1,
        "tol {} at size {size}",
        b.tol
    );
    let want = alpha_max(lp, &AmaxOptions::default()).unwrap().alpha_max;
    let (got, _) = b.rightmost();
    assert!((got - want).abs() <= 2.0 * b.tol, "{got} vs {want}");
    let c = Checker::new(lp, Options::default()).unwrap();
    for p in b.points.iter().step_by(b.points.len() / 50) {
        let w = Wall::new(p.x, p.y).unwrap();
        let rho = spectral_radius(&eigenvalues_capped(c.state_matrix(&w)).unwrap());
        assert!((rho - 1.0).abs() < 1e-5, "{p:?} radius {rho}");
    }
}

/// Behind a second-order Butterworth filter at 0.002 of the sampling rate (delta 0.001) the
/// curve runs out to stiffnesses near `1e5` and back inside one chord of the coarse scan,
/// and along a straight run past the tip of the region's wedge, whose two edges meet at about
/// `0.005` rad. Traced to `1e-8` and to the default `1e-9` (where the wedge's two ends lie
/// farther apart than the chaining's join and are joined at the edges' intersection), the
/// boundary closes without the bisection engine, and every vertex is a boundary point by the
/// closed loop's state matrix: no eigenvalue farther than `1e-7` outside the circle (a vertex
/// within `tol` of the boundary moves a root off it by that times the root's sensitivity,
/// measured up to `3.5e-9` here; the walls drawn before had roots out to `1.0004` and
/// beyond, one at `3.5e6`). Its rightmost vertex is the direct search's `alpha_max` to a
/// relative `1e-6` (the wedge's tip, located by two engines that share no code path).
#[test]
fn slow_butterworth_boundary_vertices_are_on_the_boundary() {
    for (d, tol) in [0.0, 1.0, 2.7]
        .into_iter()
        .flat_map(|d| [(d, 1e-8), (d, 1e-9)])
    {
        let lp = plant(0.001, d)
            .with_filter(VelocityFilter::butterworth(0.002).unwrap())
            .unwrap();
        let b = exact(lp, &ExactOptions { tol }).unwrap();
        assert!(
            b.fallback.is_none(),
            "d = {d}, tol = {tol}: {:?}",
            b.fallback
        );
        let c = Checker::new(lp, Options::default()).unwrap();
        let mut worst: f64 = 0.0;
        for p in &b.points {
            let a = c.state_matrix(&Wall::new(p.x, p.y).unwrap());
            let r = a
                .complex_eigenvalues()
                .iter()
                .map(|z| z.norm())
                .fold(0.0, f64::max);
            worst = worst.max(r - 1.0);
            assert!(
                r <= 1.0 + 1e-7,
                "d = {d}, tol = {tol}: vertex ({}, {}) radius {r}",
                p.x,
                p.y
            );
        }
        let right = b
            .points
            .iter()
            .map(|p| p.x)
            .fold(f64::NEG_INFINITY, f64::max);
        let amax = stabound::alpha_max(lp, &stabound::amax::AmaxOptions::default())
            .unwrap()
            .alpha_max;
        assert!(
            (right - amax).abs() <= 1e-6 * amax,
            "d = {d}, tol = {tol}: rightmost vertex {right}, alpha_max {amax} (worst radius 1 + {worst:e})"
        );
    }
}
