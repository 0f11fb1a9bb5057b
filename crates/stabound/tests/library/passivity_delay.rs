//! The passive region with whole-sample delay and velocity filters, checked against closed
//! forms (Colgate's eq. 21, Diolaiti et al.'s delay bound, the criterion as a polynomial in
//! cos theta for short delays) and against an independent time-domain energy computation.

use stabound::elements::Loop;
use stabound::filter::{FilterKind, VelocityFilter};
use stabound::params::{Plant, Wall};
use stabound::passivity::{ColumnComparison, compare_delta_beta, compare_on_lines};
use stabound::passivity::{Criterion, Edge, compare};
use stabound::stability::{Checker, Method, Options, spectral_radius};

const TOL: f64 = 1e-9;

/// The maximum over theta in [0, pi] of alpha A + beta B for F = 1 and n <= 2, written as a
/// polynomial in c = cos theta (A = sum of Chebyshev polynomials, B = -2 T_{n+1}(c)) and
/// maximized over c in [-1, 1] at the ends and the roots of its derivative (degree <= 2).
fn max_poly(n: usize, alpha: f64, beta: f64) -> f64 {
    // coefficients of p(c), lowest power first
    let p: Vec<f64> = match n {
        // A = 1, B = -2c
        0 => vec![alpha, -2.0 * beta],
        // A = 1 + 2c, B = -2 (2c^2 - 1)
        1 => vec![alpha + 2.0 * beta, 2.0 * alpha, -4.0 * beta],
        // A = 1 + 2c + 2 (2c^2 - 1) = 4c^2 + 2c - 1, B = -2 (4c^3 - 3c)
        2 => vec![-alpha, 2.0 * alpha + 6.0 * beta, 4.0 * alpha, -8.0 * beta],
        _ => unreachable!(),
    };
    let eval = |c: f64| p.iter().rev().fold(0.0, |acc, &k| acc * c + k);
    let mut cands = vec![-1.0, 1.0];
    // derivative roots
    let d: Vec<f64> = p
        .iter()
        .enumerate()
        .skip(1)
        .map(|(i, &k)| i as f64 * k)
        .collect();
    match d.len() {
        2 if d[1] != 0.0 => cands.push(-d[0] / d[1]),
        3 => {
            let (a, b, c) = (d[2], d[1], d[0]);
            if a.abs() > 0.0 {
                let disc = b * b - 4.0 * a * c;
                if disc >= 0.0 {
                    cands.push((-b + disc.sqrt()) / (2.0 * a));
                    cands.push((-b - disc.sqrt()) / (2.0 * a));
                }
            } else if b.abs() > 0.0 {
                cands.push(-c / b);
            }
        }
        _ => {}
    }
    cands
        .into_iter()
        .filter(|c| (-1.0..=1.0).contains(c))
        .map(eval)
        .fold(f64::NEG_INFINITY, f64::max)
}

fn filters() -> Vec<VelocityFilter> {
    vec![
        VelocityFilter::none(),
        VelocityFilter::low_pass(0.5).unwrap(),
        VelocityFilter::low_pass(0.9).unwrap(),
        VelocityFilter::moving_average(2).unwrap(),
        VelocityFilter::moving_average(4).unwrap(),
        VelocityFilter::butterworth(0.1).unwrap(),
    ]
}

#[test]
fn no_delay_is_colgates_triangle() {
    let c = Criterion::new(0.0, VelocityFilter::none()).unwrap();
    for delta in [0.1, 0.5, 1.0, 3.0] {
        let r = c.region_alpha_beta(delta, TOL).unwrap();
        for p in &r.points {
            // on the edge delta = alpha/2 + |beta| or on the axis alpha = 0 between the ends
            let on_edge = (p.x / 2.0 + p.y.abs() - delta).abs() <= 1e-9 * delta.max(1.0);
            // exact zero: the library clamps the axis vertices to alpha = 0
            let on_axis = p.x == 0.0 && p.y.abs() <= delta * (1.0 + 1e-12);
            assert!(on_edge || on_axis, "delta {delta}: {p:?}");
        }
        // the corner (2 delta, 0) is found and flagged, and the area is 2 delta^2
        let corner = r
            .points
            .iter()
            .find(|p| (p.x - 2.0 * delta).abs() < 1e-8 && p.y.abs() < 1e-8)
            .expect("corner");
        assert_eq!(corner.piece.edge, Edge::Corner, "delta {delta}");
        assert!((r.area() - 2.0 * delta * delta).abs() < 1e-8 * delta.max(1.0));
        // the (delta, beta) plane: |beta| = delta - alpha / 2
        for alpha in [0.0, 1.0, 2.0] {
            let e = c.region_delta_beta(alpha, 4.0, TOL).unwrap();
            assert!(e.points.len() >= 3);
            for p in &e.points {
                assert!((alpha / 2.0 + p.y.abs() - p.x).abs() < 1e-8, "{p:?}");
            }
            let apex = e.points.iter().map(|p| p.x).fold(f64::INFINITY, f64::min);
            assert!((apex - alpha / 2.0).abs() < 1e-8);
            let top = e.points[0];
            assert!((top.x - 4.0).abs() < 1e-8 && (top.y - (4.0 - alpha / 2.0)).abs() < 1e-8);
        }
        // largest passive stiffness 2 delta at beta = 0 (eq. 21)
        let (a, b) = c.max_stiffness(delta, TOL).unwrap().unwrap();
        assert!((a - 2.0 * delta).abs() < 1e-8 && b.abs() < 1e-6, "{a} {b}");
    }
    assert!(c.region_alpha_beta(0.0, TOL).unwrap().points.is_empty());
    assert!(c.max_stiffness(0.0, TOL).unwrap().is_none());
}

/// Diolaiti, Niemeyer, Barbagli and Salisbury (IEEE T-RO 22(2), 2006): with no virtual
/// damping, `K < 2 b / (T + 2 t_d)`, i.e. `alpha < 2 delta / (1 + 2 n)`.
#[test]
fn diolaiti_bound_at_zero_damping() {
    for n in [0usize, 1, 2, 3, 5, 10] {
        let c = Criterion::new(n as f64, VelocityFilter::none()).unwrap();
        for delta in [0.05, 0.3, 1.0, 7.0] {
            let a = c.max_stiffness_at(delta, 0.0, TOL).unwrap().unwrap();
            let want = 2.0 * delta / (1.0 + 2.0 * n as f64);
            assert!(
                (a - want).abs() <= 2.0 * TOL,
                "n {n} delta {delta}: {a} vs {want}"
            );
            // in physical units: m = 2 kg, T = 1 ms, b = delta m / T
            let (m, t) = (2.0, 1e-3);
            let k = a * m / (t * t);
            let kb = 2.0 * (delta * m / t) / (t + 2.0 * n as f64 * t);
            assert!((k - kb).abs() <= 1e-6 * kb);
        }
    }
}

/// For n = 0, 1, 2 without a filter every vertex of the passive polygon is on the edge
/// of the closed-form criterion, and the polygon's largest stiffness matches too.
#[test]
fn short_delays_match_the_polynomial_form() {
    for n in 0..=2usize {
        let c = Criterion::new(n as f64, VelocityFilter::none()).unwrap();
        for delta in [0.1, 0.5, 2.0] {
            let r = c.region_alpha_beta(delta, TOL).unwrap();
            assert!(r.points.len() > 10);
            for p in r.points.iter().filter(|p| p.x > 0.0) {
                let m = 0.5 * max_poly(n, p.x, p.y);
                assert!(
                    (m - delta).abs() < 1e-10 * delta.max(1.0),
                    "n {n}: {p:?} {m}"
                );
            }
            // the polygon is within tol of the edge between vertices: chord midpoints are
            // passive and less than 2 tol inside
            for w in r.points.windows(2).filter(|w| w[0].x > 0.0 && w[1].x > 0.0) {
                let (a, b) = (0.5 * (w[0].x + w[1].x), 0.5 * (w[0].y + w[1].y));
                let m = 0.5 * max_poly(n, a, b);
                assert!(m <= delta + 1e-12, "{a} {b}");
                // moving out by 2 tol along the chord's normal leaves the region
                let (dx, dy) = (w[1].x - w[0].x, w[1].y - w[0].y);
                let l = dx.hypot(dy);
                if l > 1e-6 {
                    let (ox, oy) = (dy / l, -dx / l);
                    let out = 0.5 * max_poly(n, a + 2.0 * TOL * ox, b + 2.0 * TOL * oy);
                    assert!(out > delta - 1e-12, "n {n} delta {delta}: {a} {b}");
                }
            }
            let (amax, bmax) = c.max_stiffness(delta, TOL).unwrap().unwrap();
            let top = r.points.iter().map(|p| p.x).fold(0.0, f64::max);
            assert!(amax >= top - 2e-8 && amax <= top + 2e-8, "{amax} {top}");
            assert!((0.5 * max_poly(n, amax, bmax) - delta).abs() < 1e-8);
        }
    }
}

/// The net energy per period the operator puts into device and wall, for a velocity held
/// constant over each period at `v_k = cos(k theta)` (the worst case of Colgate and
/// Schenkel), by direct time stepping of the sampled, delayed, filtered wall: position
/// `y_{k+1} = y_k + v_k`, force `f_k = -(alpha y_k + beta w_k)` with `w` the filter's
/// recursion on `y_k - y_{k-1}`, held over period `k + n`; energy in period `k` is
/// `delta v_k^2 - f_{k-n} v_k`. A squared Hann window over the second half of the run removes the
/// start-up transient and the oscillation at `2 theta`.
fn energy_per_period(delta: f64, n: usize, filter: VelocityFilter, wall: Wall, theta: f64) -> f64 {
    let periods = 200_000usize;
    let start = 20_000usize;
    // y_0 = -1/2 makes y_k = sin((k - 1/2) theta) / (2 sin(theta / 2)): zero mean
    let mut y = -0.5;
    let mut y_hist: Vec<f64> = Vec::with_capacity(periods + 1);
    let mut forces: Vec<f64> = Vec::with_capacity(periods + 1);
    let mut w_prev = 0.0;
    let (mut w_prev2, mut dy1, mut dy2) = (0.0, 0.0, 0.0);
    // scipy's coefficients (the golden file) for a second-order filter
    let butter = match filter.kind() {
        FilterKind::Butterworth { cutoff } => Some(super::butterworth::scipy_butter(cutoff)),
        _ => None,
    };
    let (mut acc, mut wsum) = (0.0, 0.0);
    for k in 0..periods {
        y_hist.push(y);
        let dy = if k == 0 { 0.0 } else { y - y_hist[k - 1] };
        let w = match filter.kind() {
            FilterKind::LowPass { pole } => pole * w_prev + (1.0 - pole) * dy,
            FilterKind::MovingAverage { samples } => {
                if k >= samples {
                    (y - y_hist[k - samples]) / samples as f64
                } else {
                    (y - y_hist[0]) / samples as f64
                }
            }
            FilterKind::Butterworth { .. } => {
                let (b, a) = butter.unwrap();
                b[0] * dy + b[1] * dy1 + b[2] * dy2 - a[1] * w_prev - a[2] * w_prev2
            }
            _ => dy,
        };
        (dy2, dy1) = (dy1, dy);
        w_prev2 = w_prev;
        w_prev = w;
        forces.push(-(wall.alpha() * y + wall.beta() * w));
        let v = (k as f64 * theta).cos();
        let f = if k >= n { forces[k - n] } else { 0.0 };
        if k >= start {
            let s = (std::f64::consts::PI * (k - start) as f64 / (periods - start) as f64).sin();
            // sin^4 (Hann squared): side lobes fall as k^-5, so the oscillation at 2 theta
            // leaks below 1e-9 of its amplitude even at theta = 0.003 (about 100 periods of
            // the sinusoid in the window)
            let win = s * s * s * s;
            acc += win * (delta * v * v - f * v);
            wsum += win;
        }
        y += v;
    }
    acc / wsum
}

/// Checks one wall's verdict against the time-domain energy at its worst frequency (and,
/// when passive, at six more); returns how many frequencies were checked.
fn check_energy(c: &Criterion, delta: f64, wall: Wall, passive: bool) -> usize {
    let (n, filter) = (c.delay(), c.filter());
    let (_, _, worst) = c.margin(delta, &wall).unwrap();
    let mut thetas = vec![worst];
    if worst < 0.02 {
        // the supremum sits at the limit theta -> 0: take small thetas where the condition
        // is still violated
        thetas = vec![0.02, 0.01, 0.005, 0.003];
    }
    if passive {
        thetas.extend((1..=6).map(|k| 0.45 * k as f64 + 0.05));
    }
    let mut violated = false;
    let mut checked = 0;
    for &t in &thetas {
        let margin = delta - c.value(&wall, t);
        let e = energy_per_period(delta, n, filter, wall, t);
        let scale = if (t - std::f64::consts::PI).abs() < 1e-12 {
            1.0
        } else {
            0.5
        };
        assert!(
            (e - scale * margin).abs() <= 0.02 * margin.abs() + 1e-7,
            "{filter:?} n {n} delta {delta} theta {t}: {e} vs {margin}"
        );
        if passive {
            assert!(e > 0.0, "{filter:?} n {n} {wall:?} {t}: {e}");
        } else if margin < 0.0 {
            assert!(e < 0.0, "{filter:?} n {n} {wall:?} {t}: {e}");
            violated = true;
        }
        checked += 1;
    }
    if !passive {
        assert!(violated, "{filter:?} n {n} delta {delta}: {wall:?}");
    }
    checked
}

/// Every verdict on both sides of the edge, at 1e-3 relative from it, against the
/// time-domain energy: outside, the energy at the worst frequency is negative (the wall
/// gives energy back); inside, it is positive there and at a set of other frequencies.
/// The energy is also `margin(theta) / 2` (`margin` at `theta = pi`), within 2 %.
#[test]
fn verdicts_agree_with_time_domain_energy() {
    let mut checked = 0;
    for filter in filters() {
        for n in [0usize, 1, 2, 4] {
            for delta in [0.1, 0.6, 2.0] {
                let c = Criterion::new(n as f64, filter).unwrap();
                let r = c.region_alpha_beta(delta, 1e-7).unwrap();
                let pts: Vec<_> = r.points.iter().filter(|p| p.x > 0.0).collect();
                let pick = [pts.len() / 5, pts.len() / 2, 4 * pts.len() / 5];
                for &i in &pick {
                    let p = pts[i];
                    for (side, s) in [(1.0 + 1e-3, "outside"), (1.0 - 1e-3, "inside")] {
                        let wall = Wall::new(p.x * side, p.y * side).unwrap();
                        let passive = c.is_passive(delta, &wall).unwrap();
                        assert_eq!(passive, side < 1.0, "{s}: {filter:?} n {n} {wall:?}");
                        checked += check_energy(&c, delta, wall, passive);
                    }
                }
            }
        }
    }
    assert!(checked > 500);
}

/// The (delta, beta) edge and the (alpha, beta) region describe one set: a vertex
/// `(delta, beta)` of the edge at stiffness alpha puts `(alpha, beta)` on the edge of the
/// `(alpha, beta)` region for that delta (the least passive delta equals delta); and the
/// `(delta, beta)` verdicts at 1e-3 relative on both sides agree with the time-domain energy.
#[test]
fn planes_agree() {
    for filter in filters() {
        for n in [0usize, 1, 3] {
            let c = Criterion::new(n as f64, filter).unwrap();
            for alpha in [0.0, 0.5, 2.0] {
                let e = c.region_delta_beta(alpha, 20.0, 1e-8).unwrap();
                assert!(!e.points.is_empty());
                // both sides of the (delta, beta) edge against the time-domain energy
                // (at alpha = 0 the apex is delta = 0, where no wall is passive: skipped)
                let edge: Vec<_> = e.points.iter().filter(|p| p.x > 1e-3).collect();
                for p in [edge[edge.len() / 3], edge[2 * edge.len() / 3]] {
                    let wall = Wall::new(alpha, p.y).unwrap();
                    for side in [1.0 + 1e-3, 1.0 - 1e-3] {
                        let passive = c.is_passive(p.x * side, &wall).unwrap();
                        assert_eq!(passive, side > 1.0, "{filter:?} n {n} {p:?}");
                        check_energy(&c, p.x * side, wall, passive);
                    }
                }
                for p in e.points.iter().step_by(7) {
                    let wall = Wall::new(alpha, p.y).unwrap();
                    let inside = Wall::new(alpha, p.y).unwrap();
                    assert!(c.is_passive(p.x * (1.0 + 1e-6) + 1e-9, &inside).unwrap());
                    assert!(!c.is_passive(p.x * (1.0 - 1e-6), &wall).unwrap());
                }
            }
        }
    }
}

/// The passive region lies inside the stable one for every tested delay, not only for
/// d = 0 (paper Section VI); confirmed independently of the polygon clipping by
/// state-space eigenvalues at the passive polygon's vertices pulled 1e-3 towards the
/// origin's side. The passive share of the stable region grows with the delay.
#[test]
fn comparison_with_the_stable_region() {
    let mut last_fraction = 0.0;
    for d in [0.0, 1.0, 2.0, 4.0] {
        for delta in [0.25, 1.0, 3.0] {
            let cmp = compare(delta, d, VelocityFilter::none(), 1e-7).unwrap();
            assert!(
                cmp.inside,
                "delta {delta} d {d}: {:?}",
                cmp.passive_unstable
            );
            assert!(cmp.passive_unstable.is_none());
            assert!(cmp.stable_fraction_of_passive > 1.0 - 1e-5);
            assert!(cmp.passive_fraction_of_stable > 0.0 && cmp.passive_fraction_of_stable < 1.0);
            // exact: d comes from the literal list above
            if d == 0.0 {
                assert!((cmp.passive_area - 2.0 * delta * delta).abs() < 1e-5);
            }
            let s = cmp
                .stable_not_passive
                .expect("a stable wall that is not passive");
            let checker = Checker::new(Plant::new(delta, d).unwrap(), Options::default()).unwrap();
            let wall = Wall::new(s.alpha, s.beta).unwrap();
            let r = spectral_radius(&checker.roots(&wall, Method::StateSpace).unwrap());
            assert!(r < 1.0, "{s:?}");
            if d <= 2.0 {
                assert!(0.5 * max_poly(d as usize, s.alpha, s.beta) > delta);
            }
            for p in cmp.region.points.iter().filter(|p| p.x > 0.0).step_by(23) {
                let wall = Wall::new(p.x * (1.0 - 1e-3), p.y * (1.0 - 1e-3)).unwrap();
                let r = spectral_radius(&checker.roots(&wall, Method::StateSpace).unwrap());
                assert!(r < 1.0, "d {d} delta {delta}: {p:?} radius {r}");
            }
            if delta == 1.0 {
                assert!(cmp.passive_fraction_of_stable > last_fraction, "d {d}");
                last_fraction = cmp.passive_fraction_of_stable;
            }
        }
    }
}

/// Without physical damping no wall is passive (eq. 21 and its delayed form need
/// `delta > 0`), and at the smallest subnormal damping the passive triangle's area underflows
/// to 0: no share of the stable region is passive, by either engine, while the stable region
/// itself is there.
#[test]
fn no_passive_region_has_no_share() {
    for (delta, d) in [(0.0, 1.0), (0.0, 0.0), (5e-324, 0.0), (5e-324, 2.0)] {
        let cmp = compare(delta, d, VelocityFilter::none(), 1e-7).unwrap();
        assert!(cmp.stable_area > 0.0, "delta {delta} d {d}");
        // exact zeros: nothing passive, so nothing common
        assert_eq!(cmp.passive_area, 0.0, "delta {delta} d {d}");
        assert_eq!(cmp.common_area, 0.0, "delta {delta} d {d}");
        assert_eq!(cmp.passive_fraction_of_stable, 0.0, "delta {delta} d {d}");
        assert!(cmp.passive_unstable.is_none());
    }
    let f = VelocityFilter::moving_average(2).unwrap();
    let cmp = compare_on_lines(0.0, 1.0, f, 16, 1e-7).unwrap();
    assert!(cmp.stable_area > 0.0);
    assert_eq!(cmp.passive_fraction_of_stable, 0.0);
}

/// The loop of `(delta, d)` with `filter`, for independent stability checks.
fn loop_checker(delta: f64, d: f64, filter: VelocityFilter) -> Checker {
    let lp = Loop::new(Plant::new(delta, d).unwrap())
        .with_filter(filter)
        .unwrap();
    Checker::new(lp, Options::default()).unwrap()
}

/// Spectral radius by the closed loop's state-matrix eigenvalues: independent of the
/// crossing polynomial and the Schur-Cohn tests the column comparison uses.
fn radius(c: &Checker, wall: &Wall) -> f64 {
    spectral_radius(&c.roots(wall, Method::StateSpace).unwrap())
}

/// Without a filter the column comparison (exact stable sets on lines of constant beta)
/// and the exact comparison (D-decomposition polygon clipped by the passive polygon) are
/// two independent routes to the same areas: they agree within the column engine's error
/// bound, and within six times its halving estimate (the largest ratio seen, at
/// d = 0, delta = 0.25; plus 1e-6 for the polygons' own tolerance-level error).
#[test]
fn column_comparison_agrees_with_the_exact_boundary() {
    for d in [0.0, 1.0, 2.0] {
        for delta in [0.25, 1.0] {
            let e = compare(delta, d, VelocityFilter::none(), 1e-7).unwrap();
            let c = compare_on_lines(delta, d, VelocityFilter::none(), 128, 1e-7).unwrap();
            assert_eq!(c.inside, e.inside, "d {d} delta {delta}");
            let diff = (c.passive_fraction_of_stable - e.passive_fraction_of_stable).abs();
            // the bound holds; the estimate is within a factor 6 (module documentation)
            assert!(
                diff <= c.fraction_bound,
                "d {d} delta {delta}: {diff} {c:?}"
            );
            assert!(
                diff <= 6.0 * c.fraction_error + 1e-6,
                "d {d} delta {delta}: {diff}"
            );
            assert!(c.fraction_bound < 0.02, "{}", c.fraction_bound);
            assert!((c.stable_area - e.stable_area).abs() <= 1e-3 * e.stable_area);
        }
    }
}

/// Checks a column comparison's verdicts independently: the stable-not-passive witness by
/// state-space eigenvalues (stable) and the time-domain energy (not passive); the passive
/// edge's vertices 1e-3 inside (relative) are passive by the energy and stable by
/// eigenvalues, 1e-3 outside not passive by the energy; and the stable outline's vertices,
/// 1e-3 inside the column ends, are stable by eigenvalues, 1e-3 outside unstable.
/// `plane_wall` maps a plane point to `(wall, delta)`; `to_origin` pulls towards the
/// region's interior.
fn check_columns(
    crit: &Criterion,
    c: &ColumnComparison,
    filter: VelocityFilter,
    d: f64,
    plane_wall: &dyn Fn((f64, f64)) -> (Wall, f64),
    inward: &dyn Fn((f64, f64), f64) -> (f64, f64),
) -> usize {
    let mut checked = 0;
    assert!(c.inside);
    assert!(c.passive_unstable.is_none());
    let s = c
        .stable_not_passive
        .expect("a stable wall that is not passive");
    let wall = Wall::new(s.alpha, s.beta).unwrap();
    assert!(
        radius(&loop_checker(s.delta, d, filter), &wall) < 1.0,
        "{s:?}"
    );
    checked += check_energy(crit, s.delta, wall, false);
    let pts: Vec<(f64, f64)> = c.region.xy();
    for &p in pts.iter().step_by((pts.len() / 6).max(1)) {
        let (w_in, dl_in) = plane_wall(inward(p, 1.0 - 1e-3));
        let (w_out, dl_out) = plane_wall(inward(p, 1.0 + 1e-3));
        if w_in.alpha() <= 0.0 || dl_in <= 1e-3 {
            continue; // the axis alpha = 0 and the apex delta = 0 bound no passive wall
        }
        assert!(crit.is_passive(dl_in, &w_in).unwrap(), "{p:?}");
        checked += check_energy(crit, dl_in, w_in, true);
        assert!(
            radius(&loop_checker(dl_in, d, filter), &w_in) < 1.0,
            "{p:?}"
        );
        if !crit.is_passive(dl_out, &w_out).unwrap() {
            checked += check_energy(crit, dl_out, w_out, false);
        }
    }
    // the outline runs along the upper column ends and back along the lower ones: vertex i
    // and vertex len - 2 - i are the two ends of one column; move along the column
    let outline = &c.stable_outline;
    let m = outline.len().saturating_sub(1);
    for i in (0..m / 2).step_by((m / 16).max(1)) {
        let (hi, lo) = (outline[i], outline[m - 1 - i]);
        for (end, other) in [(hi, lo), (lo, hi)] {
            let along = |s: f64| {
                let t = |a: f64, b: f64| b + (a - b) * s;
                // the free coordinate: alpha (first) when the columns are of constant beta
                if (end.1 - other.1).abs() > 0.0 {
                    (end.0, t(end.1, other.1))
                } else {
                    (t(end.0, other.0), end.1)
                }
            };
            let (w_in, dl) = plane_wall(along(1.0 - 1e-3));
            let (w_out, _) = plane_wall(along(1.0 + 1e-3));
            if w_in.alpha() <= 0.0 || w_out.alpha() <= 0.0 || dl < 1e-6 {
                continue; // the z = 1 line alpha = 0 (or the column delta = 0)
            }
            let lc = loop_checker(dl, d, filter);
            assert!(radius(&lc, &w_in) < 1.0, "{end:?} {w_in:?}");
            assert!(radius(&lc, &w_out) > 1.0, "{end:?} {w_out:?}");
            checked += 2;
        }
    }
    checked
}

/// Loops with a velocity filter, `(alpha, beta)` plane: every comparison finds the passive
/// region inside the stable one, a stable wall that is not passive, and a passive share
/// whose error estimate is small; each verdict is checked independently (see
/// [`check_columns`]).
#[test]
fn filtered_loops_alpha_beta_comparison() {
    let mut checked = 0;
    for filter in filters().into_iter().skip(1) {
        for d in [0.0, 1.0, 2.0] {
            for delta in [0.1, 1.0] {
                let crit = Criterion::new(d, filter).unwrap();
                let c = compare_on_lines(delta, d, filter, 64, 1e-7).unwrap();
                assert!(c.fraction_error < 5e-3, "{filter:?} {d} {delta}: {c:?}");
                assert!(c.passive_fraction_of_stable > 0.0 && c.passive_fraction_of_stable < 1.0);
                assert!(c.stable_fraction_of_passive > 1.0 - 1e-6);
                // pull towards (0, beta): the axis alpha = 0 is inside both regions' closure
                checked += check_columns(
                    &crit,
                    &c,
                    filter,
                    d,
                    &|(a, b)| (Wall::new(a, b).unwrap(), delta),
                    &|(a, b), s| (a * s, b * s),
                );
            }
        }
    }
    assert!(checked > 300, "{checked}");
}

/// The same in the `(delta, beta)` plane at fixed stiffness, with and without a filter,
/// pulling towards larger `delta` (more physical damping is inside both regions).
#[test]
fn delta_beta_comparison() {
    let mut checked = 0;
    for filter in filters() {
        for d in [0.0, 1.0, 2.0] {
            for alpha in [0.1, 0.5] {
                let crit = Criterion::new(d, filter).unwrap();
                let c = compare_delta_beta(alpha, d, filter, 3.0, 32, 1e-7).unwrap();
                assert!(c.passive_fraction_of_stable > 0.0 && c.passive_fraction_of_stable < 1.0);
                checked += check_columns(
                    &crit,
                    &c,
                    filter,
                    d,
                    &|(x, b)| (Wall::new(alpha, b).unwrap(), x),
                    &|(x, b), s| (x / s, b),
                );
            }
        }
    }
    assert!(checked > 300, "{checked}");
}

/// An independent estimate of the passive share for one filtered loop: a lattice of
/// 200 x 200 walls over the stable region's bounding box, stability by state-space
/// eigenvalues, passivity by the time-free criterion; the lattice's own error is about
/// the boundary cells' share, some 1 %.
#[test]
fn passive_share_against_a_lattice() {
    let (delta, d) = (1.0, 1.0);
    let filter = VelocityFilter::low_pass(0.5).unwrap();
    let c = compare_on_lines(delta, d, filter, 128, 1e-7).unwrap();
    let crit = Criterion::new(d, filter).unwrap();
    let lc = loop_checker(delta, d, filter);
    let (x0, x1, y0, y1) = c.stable_outline.iter().fold(
        (
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ),
        |(a, b, e, f), p| (a.min(p.0), b.max(p.0), e.min(p.1), f.max(p.1)),
    );
    let k = 200;
    let (mut stable, mut both) = (0usize, 0usize);
    for i in 0..k {
        for j in 0..k {
            let a = x0 + (x1 - x0) * (i as f64 + 0.5) / k as f64;
            let b = y0 + (y1 - y0) * (j as f64 + 0.5) / k as f64;
            let w = Wall::new(a, b).unwrap();
            if radius(&lc, &w) < 1.0 {
                stable += 1;
                if crit.is_passive(delta, &w).unwrap() {
                    both += 1;
                }
            }
        }
    }
    let cell = (x1 - x0) * (y1 - y0) / (k * k) as f64;
    let share = both as f64 / stable as f64;
    assert!(
        (share - c.passive_fraction_of_stable).abs() < 0.01,
        "{share} {c:?}"
    );
    assert!((stable as f64 * cell - c.stable_area).abs() < 0.02 * c.stable_area);
}

/// No passive wall is unstable in the filtered loops searched: low-pass poles 0.1 to 0.97,
/// moving averages over 5 to 32 samples, d = 0 to 10, delta from 1e-3 to 10 in the
/// `(alpha, beta)` plane and alpha from 0.01 to 2 in the `(delta, beta)` plane (252
/// comparisons while developing; this is a share of them). A numerical search, not a
/// proof: the witness path itself is tested on made-up columns in the library's unit tests.
#[test]
fn no_passive_unstable_wall_in_the_families_searched() {
    let mut filters = vec![VelocityFilter::low_pass(0.97).unwrap()];
    filters.push(VelocityFilter::moving_average(16).unwrap());
    for filter in filters {
        for d in [0.0, 3.0, 10.0] {
            for delta in [0.001, 0.3, 10.0] {
                let c = compare_on_lines(delta, d, filter, 32, 1e-6).unwrap();
                assert!(
                    c.inside && c.passive_unstable.is_none(),
                    "{filter:?} {d} {delta}"
                );
            }
            let c = compare_delta_beta(0.3, d, filter, 3.0, 16, 1e-6).unwrap();
            assert!(c.inside && c.passive_unstable.is_none(), "{filter:?} {d}");
        }
    }
}

/// A lattice of `k x k` walls over the bounding box of `stable` (a closed polygon): the
/// area where the loop is stable by its state-space eigenvalues, and the share of it where
/// the wall is also passive by the certified criterion. Independent of the D-decomposition,
/// the clipping and the columns.
fn lattice_share(
    crit: &Criterion,
    lc: &Checker,
    delta: f64,
    stable: &[(f64, f64)],
    k: usize,
) -> (f64, f64) {
    let (x0, x1, y0, y1) = stable.iter().fold(
        (
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ),
        |(a, b, e, f), p| (a.min(p.0), b.max(p.0), e.min(p.1), f.max(p.1)),
    );
    let (mut n_stable, mut both) = (0usize, 0usize);
    for i in 0..k {
        for j in 0..k {
            let a = x0 + (x1 - x0) * (i as f64 + 0.5) / k as f64;
            let b = y0 + (y1 - y0) * (j as f64 + 0.5) / k as f64;
            let w = Wall::new(a, b).unwrap();
            // the eigenvalues, or where their iteration does not converge (a repeated root
            // on the lattice) the Schur-Cohn verdict, another method than the boundary's
            let stable = match lc.roots(&w, Method::StateSpace) {
                Ok(r) => spectral_radius(&r) < 1.0,
                Err(_) => lc.verdict(&w).unwrap() == stabound::stability::Verdict::Stable,
            };
            if stable {
                n_stable += 1;
                if crit.is_passive(delta, &w).unwrap() {
                    both += 1;
                }
            }
        }
    }
    let cell = (x1 - x0) * (y1 - y0) / (k * k) as f64;
    (n_stable as f64 * cell, both as f64 / n_stable as f64)
}

/// The exact comparison of a filtered loop (its D-decomposition boundary clipped by the
/// passive polygon) for each filter the loop accepts: first-order low-pass, moving average
/// and second-order Butterworth. Checked against three independent routes: the column
/// comparison (exact stable sets on lines, its own error bound), the stable-not-passive
/// witness by state-space eigenvalues and the time-domain energy, and the passive edge's
/// vertices 1e-3 inside by the energy and by eigenvalues.
#[test]
fn exact_comparison_with_velocity_filters() {
    let (mut checked, mut twice) = (0, 0);
    for filter in filters().into_iter().skip(1) {
        for d in [0.0, 1.0, 2.0] {
            for delta in [0.1, 1.0] {
                let crit = Criterion::new(d, filter).unwrap();
                let lc = loop_checker(delta, d, filter);
                let e = match compare(delta, d, filter, 1e-7) {
                    Ok(e) => e,
                    Err(why) => {
                        // a stable region of two pieces, the passive region in the smaller:
                        // the columns see both (each column's stable set is exact), and the
                        // passive polygon's vertex mean is stable by eigenvalues
                        assert!(why.to_string().contains("more than one piece"), "{why}");
                        let c = compare_on_lines(delta, d, filter, 64, 1e-7).unwrap();
                        assert!(c.inside && c.passive_fraction_of_stable > 0.0);
                        let p = c.region.xy();
                        let k = p.len() as f64;
                        let (a, b) = p
                            .iter()
                            .fold((0.0, 0.0), |s, q| (s.0 + q.0 / k, s.1 + q.1 / k));
                        assert!(radius(&lc, &Wall::new(a, b).unwrap()) < 1.0);
                        twice += 1;
                        continue;
                    }
                };
                assert!(e.stable_fallback.is_none(), "{filter:?} {d} {delta}");
                assert!(e.inside && e.passive_unstable.is_none(), "{filter:?} {d}");
                assert!(e.stable_fraction_of_passive > 1.0 - 1e-6);
                let c = compare_on_lines(delta, d, filter, 64, 1e-7).unwrap();
                let diff = (c.passive_fraction_of_stable - e.passive_fraction_of_stable).abs();
                assert!(
                    diff <= c.fraction_bound,
                    "{filter:?} d {d} delta {delta}: {diff} {}",
                    c.fraction_bound
                );
                assert!(
                    (c.stable_area - e.stable_area).abs() <= 1e-2 * e.stable_area,
                    "{filter:?} d {d} delta {delta}: {} {}",
                    c.stable_area,
                    e.stable_area
                );
                let s = e
                    .stable_not_passive
                    .expect("a stable wall that is not passive");
                let wall = Wall::new(s.alpha, s.beta).unwrap();
                assert!(radius(&lc, &wall) < 1.0, "{s:?}");
                checked += check_energy(&crit, delta, wall, false);
                let pts: Vec<(f64, f64)> = e.region.xy();
                for &(a, b) in pts.iter().step_by((pts.len() / 5).max(1)) {
                    let w = Wall::new(a * (1.0 - 1e-3), b * (1.0 - 1e-3)).unwrap();
                    if w.alpha() <= 0.0 {
                        continue;
                    }
                    assert!(radius(&lc, &w) < 1.0, "{filter:?} {d} {delta}: {w:?}");
                    checked += check_energy(&crit, delta, w, true);
                }
            }
        }
    }
    assert!(checked > 200, "{checked}");
    // the second-order filter at d = 0, delta = 0.1 (its stable region has two pieces)
    assert_eq!(twice, 1);
}

/// The exact comparison's stable area and passive share against a 200 x 200 lattice of
/// point tests (stability by state-space eigenvalues, passivity by the criterion), for one
/// loop with each kind of filter; the lattice's own error is about the share of its cells
/// the two boundaries cross, some 1 %.
#[test]
fn exact_filtered_share_against_a_lattice() {
    for (filter, d) in [
        (VelocityFilter::low_pass(0.5).unwrap(), 1.0),
        (VelocityFilter::moving_average(3).unwrap(), 2.0),
        (VelocityFilter::butterworth(0.1).unwrap(), 1.0),
    ] {
        let delta = 1.0;
        let e = compare(delta, d, filter, 1e-7).unwrap();
        let crit = Criterion::new(d, filter).unwrap();
        let (area, share) = lattice_share(
            &crit,
            &loop_checker(delta, d, filter),
            delta,
            &e.stable,
            200,
        );
        assert!(
            (share - e.passive_fraction_of_stable).abs() < 0.01,
            "{filter:?}: {share} {}",
            e.passive_fraction_of_stable
        );
        assert!(
            (area - e.stable_area).abs() < 0.02 * e.stable_area,
            "{filter:?}: {area}"
        );
    }
}

/// A low-pass pole near 1 stretches the stable region to `beta ~ 1e8`: the exact comparison
/// still answers, with the passive area resolved (columns spaced over the stable region's
/// extent would miss the passive region entirely) and the largest passive stiffness near
/// Diolaiti's bound without damping, `2 delta / (1 + 2n)`.
#[test]
fn exact_comparison_with_a_slow_filter() {
    let filter = VelocityFilter::low_pass(0.999999).unwrap();
    let e = compare(1.0, 1.0, filter, 1e-7).unwrap();
    assert!(e.inside);
    assert!(e.passive_area > 0.0 && e.passive_area < e.stable_area);
    assert!((e.passive_area - e.region.area()).abs() <= 1e-9 * e.passive_area);
    let crit = Criterion::new(1.0, filter).unwrap();
    let (a, _) = crit.max_stiffness(1.0, 1e-7).unwrap().unwrap();
    assert!((a - 2.0 / 3.0).abs() < 1e-5, "{a}");
}
