//! The largest stable stiffness of a [`Loop`]: over all virtual dampings (`alpha_max`) and
//! at a given one.
//!
//! Method: the general D-decomposition boundary ([`crate::boundary::exact`] of the loop, the model
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

use super::Loop;
use crate::amax::{Amax, AmaxOptions};
use crate::boundary::{Boundary, DEFAULT_TOL, ExactOptions, exact};
use crate::error::{Error, Result};
use crate::params::Wall;
use crate::search::Interval;
use crate::stability::Checker;
use crate::stability::Options;

/// `alpha_max` of `lp` and the `beta` where it is reached, within the beta limits of `opts`,
/// to [`DEFAULT_TOL`] (see the module documentation; `opts`'s theta tolerance is the paper
/// engine's and is not used here): the general route of [`crate::alpha_max`].
///
/// # Errors
///
/// As [`exact`]; [`Error::InvalidRequest`] when the beta limits leave no stable wall.
pub(crate) fn loop_alpha_max(lp: &Loop, opts: &AmaxOptions) -> Result<Amax> {
    LoopEdges::new(lp, Options::default())?.alpha_max(opts)
}

/// A loop's boundary and point test, built once for any number of one-dimensional
/// questions (the scene's walls ask several each).
pub(crate) struct LoopEdges {
    checker: Checker,
    boundary: Boundary,
}

impl LoopEdges {
    /// `options` are the point test's; the edges themselves are found at radius exactly 1.
    pub(crate) fn new(lp: &Loop, options: Options) -> Result<Self> {
        Ok(Self {
            checker: Checker::new(lp, options)?,
            boundary: exact(lp, &ExactOptions { tol: DEFAULT_TOL })?,
        })
    }

    pub(crate) fn alpha_max(&self, opts: &AmaxOptions) -> Result<Amax> {
        let (lo, hi) = (
            opts.beta_min().unwrap_or(f64::NEG_INFINITY),
            opts.beta_max().unwrap_or(f64::INFINITY),
        );
        let mut best: Option<(f64, f64)> = None;
        let mut offer = |alpha: f64, beta: f64| {
            if best.is_none_or(|(a, _)| alpha > a) {
                best = Some((alpha, beta));
            }
        };
        for p in self
            .boundary
            .points
            .iter()
            .filter(|p| p.y >= lo && p.y <= hi)
        {
            offer(p.x, p.y);
        }
        for beta in [opts.beta_min(), opts.beta_max()].into_iter().flatten() {
            if let Some(i) = self.stable_alphas(beta).last() {
                offer(i.hi, beta);
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

    /// The stable `alpha` at `beta`, sorted open intervals: the closed polyline's crossings
    /// with the line, paired in order (the polyline is a simple closed curve around the
    /// stable region, so they alternate in and out), each end polished by bisection on the
    /// point test.
    pub(crate) fn stable_alphas(&self, fixed: f64) -> Vec<Interval> {
        let at = |s: f64| Wall {
            alpha: s,
            beta: fixed,
        };
        let split = |p: &crate::boundary::Vertex| (p.y, p.x);
        let mut cuts: Vec<f64> = self
            .boundary
            .points
            .windows(2)
            .filter_map(|w| {
                let ((f0, s0), (f1, s1)) = (split(&w[0]), split(&w[1]));
                // half-open so a vertex exactly on the line counts once
                if (f0 <= fixed) == (f1 <= fixed) {
                    return None;
                }
                Some(s0 + (fixed - f0) / (f1 - f0) * (s1 - s0))
            })
            .collect();
        cuts.sort_by(f64::total_cmp);
        let stable = |s: f64| self.checker.unit_circle_stable(&at(s));
        cuts.chunks_exact(2)
            .map(|c| Interval {
                lo: polish(c[0], self.boundary.tol, &stable, false),
                hi: polish(c[1], self.boundary.tol, &stable, true),
            })
            .collect()
    }
}

/// A crossing `edge` found on the polyline (within `tol` of the boundary, relative to its
/// size), refined by bisection on `stable` until the bracket is below `1e-15` of the value;
/// `stable_below` says on which side the stable region lies. A bracket of 4 tol each way
/// holds the edge unless the region is thinner than that there, when the polyline's value
/// is the answer to tol.
fn polish(edge: f64, tol: f64, stable: &impl Fn(f64) -> bool, stable_below: bool) -> f64 {
    let reach = 4.0 * tol * edge.abs().max(1.0);
    let (mut s, mut u) = if stable_below {
        (edge - reach, edge + reach)
    } else {
        (edge + reach, edge - reach)
    };
    if !stable(s) || stable(u) {
        return edge;
    }
    while (u - s).abs() > 1e-15 * edge.abs().max(1e-300) {
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
    // the unstable end: the interval is open and its ends are on the boundary
    u
}
