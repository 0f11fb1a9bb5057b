//! Inputs that once hung, panicked or exhausted memory: every one now returns, with a typed
//! error where the request cannot be met.

use stabound::Error;
use stabound::amax::{AmaxOptions, slope_g};
use stabound::plot::{Figure, LineStyle};

fn figure(points: Vec<(f64, f64)>) -> Figure {
    let mut f = Figure::new("t", "x", "y");
    f.push("a", points, LineStyle::Solid, 0);
    f
}

/// Given axis ranges that cannot be drawn (NaN, infinite, inverted, empty, or so wide that
/// their width overflows) are typed errors, not a panic or an endless tick computation.
#[test]
fn figure_rejects_undrawable_ranges() {
    let bad = [
        (f64::NAN, 1.0),
        (0.0, f64::NAN),
        (f64::NEG_INFINITY, 1.0),
        (-1e308, 1e308),
        (-f64::MAX, f64::MAX),
        (1.0, 1.0),
        (2.0, 1.0),
    ];
    for r in bad {
        for axis in 0..2 {
            let mut f = figure(vec![(0.0, 0.0), (1.0, 1.0)]);
            if axis == 0 {
                f.x_range = Some(r);
            } else {
                f.y_range = Some(r);
            }
            match f.to_svg() {
                Err(Error::InvalidRequest(m)) => assert!(m.contains("range"), "{m}"),
                other => panic!("{r:?} on axis {axis}: {other:?}"),
            }
        }
    }
}

/// Data reaching +-f64::MAX (an unstable response) is drawn on a fitted range cut to the
/// drawable size instead of hanging; wide but drawable given ranges still draw.
#[test]
fn figure_draws_data_near_the_f64_limit() {
    let f = figure(vec![(0.0, -f64::MAX), (1.0, 0.0), (2.0, f64::MAX)]);
    let svg = f.to_svg().unwrap();
    assert!(svg.starts_with("<svg"));
    for r in [(-1e300, 1e300), (1e-300, 2e-300), (0.0, 1e-200)] {
        let mut f = figure(vec![(0.0, 0.0), (1.0, 1.0)]);
        f.y_range = Some(r);
        assert!(f.to_svg().is_ok(), "{r:?}");
    }
}

/// A number of fit points that cannot be allocated is refused before any allocation.
#[test]
fn slope_fit_refuses_huge_point_counts() {
    for n in [usize::MAX, usize::MAX / 2, stabound::amax::MAX_ROWS + 1] {
        match slope_g(1.0, 10.0, 100.0, n, &AmaxOptions::default()) {
            Err(Error::InvalidRequest(m)) => assert!(m.contains("points"), "{m}"),
            other => panic!("{n}: {other:?}"),
        }
    }
}

/// One curve far too large for its tolerance (delta = 1e9 at tol 1e-9 once refined for 104 s
/// to 3.2 GiB): the exact engine stops at its vertex budget with a typed error.
#[test]
fn exact_boundary_stops_at_the_vertex_budget() {
    use stabound::boundary::{ExactOptions, exact};
    let plant = stabound::params::Plant::new(1e9, 1.0).unwrap();
    match exact(plant, &ExactOptions { tol: 1e-9 }) {
        Err(Error::InvalidRequest(m)) => assert!(m.contains("vertices"), "{m}"),
        other => panic!("{:?}", other.map(|b| b.points.len())),
    }
}

/// At d = 300 the stable region is tiny (alpha_max = 6.07e-6, far below one cell of the
/// default grid): the bisection engine seeds its box with the alpha_max search's point and
/// finds the region, its rightmost vertex within the tolerance of alpha_max.
#[test]
fn bisection_finds_a_region_below_the_grid_resolution() {
    use stabound::boundary::{BisectOptions, bisect_alpha_beta};
    let plant = stabound::params::Plant::new(0.0, 300.0).unwrap();
    let b = bisect_alpha_beta(plant, &BisectOptions::default()).unwrap();
    let (a, _) = b.rightmost();
    let want = stabound::amax::alpha_max(plant, &AmaxOptions::default())
        .unwrap()
        .alpha_max;
    // both are located to the default tolerance 1e-9 (absolute, normalized units)
    assert!((a - want).abs() < 1e-8, "{a} vs {want}");
    assert!(want > 1e-6 && want < 1e-5, "{want}");
}
