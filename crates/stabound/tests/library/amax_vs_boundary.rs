//! `alpha_max` (direct search on the D-decomposition curve) against the rightmost vertex of
//! the boundary engine's exact polyline, an independent route (the boundary is assembled and
//! refined without any maximization), on the grid delta in [0, 100],
//! d in {0, 0.125, 0.25, 0.5, 1, 2, 4, 8}.

use stabound::amax::{AmaxOptions, DEFAULT_SLOPE_RANGE, alpha_max, slope_g};
use stabound::boundary::{ExactOptions, exact};
use stabound::params::Plant;

/// Polyline tolerance of the boundary: the rightmost vertex lies within `TOL` of the true
/// rightmost point (chords deviate from the curve by at most `TOL`), so alpha_max must lie in
/// `[rightmost, rightmost + TOL]` up to rounding.
const TOL: f64 = 1e-7;

fn rightmost(delta: f64, d: f64) -> (f64, f64) {
    exact(Plant::new(delta, d).unwrap(), &ExactOptions { tol: TOL })
        .unwrap()
        .rightmost()
}

#[test]
fn alpha_max_is_the_boundary_rightmost_point() {
    for &d in &[0.0, 0.125, 0.25, 0.5, 1.0, 2.0, 4.0, 8.0] {
        for &delta in &[0.0, 0.3, 1.0, 3.0, 10.0, 35.0, 100.0] {
            let a = alpha_max(Plant::new(delta, d).unwrap(), &AmaxOptions::default()).unwrap();
            let (r_alpha, r_beta) = rightmost(delta, d);
            // rounding of both engines: 1e-12 relative of the values involved
            let slack = 1e-12 * a.alpha_max.abs().max(1.0);
            assert!(
                a.alpha_max >= r_alpha - slack && a.alpha_max <= r_alpha + 2.0 * TOL + slack,
                "delta {delta} d {d}: alpha_max {} vs rightmost vertex {r_alpha}",
                a.alpha_max
            );
            // beta at a smooth maximum is flat to second order: a vertex within TOL in alpha
            // can sit sqrt(TOL / curvature) away in beta; 1e-2 relative covers every case here,
            // while a maximum on the wrong piece (or a wrong corner) would be off by O(1).
            assert!(
                (a.beta_at_max - r_beta).abs() <= 1e-2 * (1.0 + r_beta.abs()),
                "delta {delta} d {d}: beta_at_max {} vs {r_beta}",
                a.beta_at_max
            );
        }
    }
}

/// The slope g(d) of eq. (22) against a difference quotient of the boundary engine's
/// rightmost points at the ends of the fitted range (alpha_max is linear there to the fit's
/// residual, so the two slopes agree to a few times that residual).
#[test]
fn slope_g_matches_boundary_difference_quotient() {
    let (lo, hi) = DEFAULT_SLOPE_RANGE;
    for &d in &[0.0, 1.0, 4.0] {
        let fit = slope_g(d, lo, hi, 19, &AmaxOptions::default()).unwrap();
        let g_fd = (rightmost(hi, d).0 - rightmost(lo, d).0) / (hi - lo);
        let rel = (fit.g - g_fd).abs() / g_fd;
        assert!(
            rel <= 1e-3 + 4.0 * fit.max_rel_residual,
            "d {d}: fitted g {} vs difference quotient {g_fd} (residual {})",
            fit.g,
            fit.max_rel_residual
        );
        eprintln!(
            "g({d}) = {} on delta in [{lo}, {hi}], max residual {:e}",
            fit.g, fit.max_rel_residual
        );
    }
}
