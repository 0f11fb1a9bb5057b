//! The largest stable stiffness of a [`Loop`]: over all virtual dampings (`alpha_max`) and
//! at a given one.
//!
//! Method: the general D-decomposition boundary ([`crate::boundary::exact_loop`], the model
//! document, docs/MODEL.md, section 8) computed to `tol`, whose vertices lie on the curve of
//! complex roots on the circle or on the lines of the roots `z = +-1`:
//!
//! - `alpha_max` is the rightmost vertex (within the beta limits, their edges at those
//!   limits included, found as below). Between two vertices the curve is within `tol` of the chord, so the
//!   true maximum exceeds the rightmost vertex by at most `tol`, and every vertex is on the
//!   boundary to rounding: the result is within `tol` below the true `alpha_max`.
//! - At a fixed `beta`, the rightmost crossing of the line with the polyline (within `tol`
//!   of the true edge), polished by bisection on the loop's point test (Schur-Cohn at radius
//!   1 on the loop's polynomial) until the bracket is below `1e-15` of the value's size.
//!
//! For the paper's loop, [`crate::alpha_max`] (closed forms, Brent's method on the curve) is
//! the faster route and agrees with these within `tol`.

use super::{Loop, LoopChecker};
use crate::amax::{Amax, AmaxOptions};
use crate::boundary::{Boundary, DEFAULT_TOL, ExactOptions, exact_loop};
use crate::error::{Error, Result};
use crate::params::{Wall, finite};
use crate::stability::Options;

/// `alpha_max` of `lp` and the `beta` where it is reached, within the beta limits of `opts`,
/// to [`DEFAULT_TOL`] (see the module documentation; `opts`'s theta tolerance is the paper
/// engine's and is not used here).
///
/// ```
/// use stabound::elements::{Loop, loop_alpha_max};
/// use stabound::filter::VelocityFilter;
/// use stabound::params::Plant;
/// use stabound::AmaxOptions;
///
/// let plant = Plant::new(0.2, 1.0)?;
/// let bare = loop_alpha_max(&Loop::new(plant), &AmaxOptions::default())?;
/// let filtered = Loop::new(plant).with_filter(VelocityFilter::low_pass(0.9)?)?;
/// // a velocity filter's lag lowers the largest stable stiffness
/// assert!(loop_alpha_max(&filtered, &AmaxOptions::default())?.alpha_max < bare.alpha_max);
/// # Ok::<(), stabound::Error>(())
/// ```
///
/// # Errors
///
/// As [`exact_loop`]; [`Error::InvalidRequest`] when the beta limits leave no stable wall.
pub fn loop_alpha_max(lp: &Loop, opts: &AmaxOptions) -> Result<Amax> {
    let b = boundary(lp)?;
    let (lo, hi) = (
        opts.beta_min().unwrap_or(f64::NEG_INFINITY),
        opts.beta_max().unwrap_or(f64::INFINITY),
    );
    let inside = |beta: f64| beta >= lo && beta <= hi;
    let mut best: Option<(f64, f64)> = None;
    let mut offer = |alpha: f64, beta: f64| {
        if best.is_none_or(|(a, _)| alpha > a) {
            best = Some((alpha, beta));
        }
    };
    for p in b.points.iter().filter(|p| inside(p.beta)) {
        offer(p.alpha, p.beta);
    }
    let limits: Vec<f64> = [opts.beta_min(), opts.beta_max()]
        .into_iter()
        .flatten()
        .collect();
    if !limits.is_empty() {
        let checker = LoopChecker::new(lp, Options::default())?;
        for beta in limits {
            if let Some(alpha) = polished_edge(&checker, &b, beta) {
                offer(alpha, beta);
            }
        }
    }
    let (alpha_max, beta_at_max) = best.ok_or_else(|| {
        Error::InvalidRequest(format!(
            "no stable wall of this loop has a virtual damping between {lo} and {hi}; widen the beta limits"
        ))
    })?;
    Ok(Amax {
        alpha_max,
        beta_at_max,
    })
}

/// The largest stable stiffness of `lp` at virtual damping `beta`, or `None` if no stiffness
/// is stable there (see the module documentation).
///
/// ```
/// use stabound::elements::{Hand, Loop, loop_alpha_limit};
/// use stabound::params::Plant;
///
/// let lp = Loop::new(Plant::new(0.2, 1.0)?).with_hand(Hand::new(0.5, 0.1, 0.0)?)?;
/// let a = loop_alpha_limit(&lp, 0.1)?.expect("stable walls at beta = 0.1");
/// assert!(a > 0.0 && a < 1.0);
/// assert_eq!(loop_alpha_limit(&lp, -5.0)?, None);
/// # Ok::<(), stabound::Error>(())
/// ```
///
/// # Errors
///
/// A non-finite `beta`; as [`exact_loop`].
pub fn loop_alpha_limit(lp: &Loop, beta: f64) -> Result<Option<f64>> {
    finite("beta", beta)?;
    let b = boundary(lp)?;
    let checker = LoopChecker::new(lp, Options::default())?;
    Ok(polished_edge(&checker, &b, beta))
}

/// The rightmost crossing of the polyline `b` with the line at `beta`, polished by bisection
/// on the point test; `None` if the line misses the region.
fn polished_edge(checker: &LoopChecker, b: &Boundary, beta: f64) -> Option<f64> {
    let edge = crossings(b, beta).into_iter().reduce(f64::max)?;
    let stable = |alpha: f64| checker.unit_circle_stable(&Wall { alpha, beta });
    // The polyline is within tol of the edge: a bracket of 4 tol (of the boundary's size)
    // each way holds it unless the region is thinner than that there, when the polyline's
    // value is the answer to tol.
    let reach = 4.0 * b.tol * edge.abs().max(1.0);
    let (mut s, mut u) = (edge - reach, edge + reach);
    if !stable(s) || stable(u) {
        return Some(edge);
    }
    while u - s > 1e-15 * edge.abs().max(1e-300) {
        let m = 0.5 * (s + u);
        if m == s || m == u {
            break;
        }
        if stable(m) {
            s = m;
        } else {
            u = m;
        }
    }
    Some(s)
}

fn boundary(lp: &Loop) -> Result<Boundary> {
    exact_loop(lp, &ExactOptions { tol: DEFAULT_TOL })
}

/// The `alpha` where the closed polyline crosses the horizontal line at `beta`.
fn crossings(b: &Boundary, beta: f64) -> Vec<f64> {
    b.points
        .windows(2)
        .filter_map(|w| {
            let (p, q) = (w[0], w[1]);
            // half-open in beta so a vertex exactly on the line counts once
            if (p.beta <= beta) == (q.beta <= beta) {
                return None;
            }
            let t = (beta - p.beta) / (q.beta - p.beta);
            Some(p.alpha + t * (q.alpha - p.alpha))
        })
        .collect()
}
