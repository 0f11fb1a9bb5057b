//! The exact boundary's polyline stays within its tolerance of the true curve at every
//! vertex, the corner `(0, -delta)` included: the curve is taken as the same engine's
//! polyline at the smallest tolerance, `1e-12`, and each of its vertices must lie within
//! `tol` of the coarser polyline.

use stabound::boundary::{Boundary, ExactOptions, exact};
use stabound::params::Plant;

/// Distance from `p` to the segment `a b`.
pub(crate) fn seg_dist(p: (f64, f64), a: (f64, f64), b: (f64, f64)) -> f64 {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let len2 = dx * dx + dy * dy;
    let t = if len2 > 0.0 {
        (((p.0 - a.0) * dx + (p.1 - a.1) * dy) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p.0 - a.0 - t * dx).hypot(p.1 - a.1 - t * dy)
}

/// The largest distance from a vertex of `fine` to the polyline `coarse`, and where. Both
/// run counterclockwise from the same start, so each vertex of `fine` is compared with the
/// segments of `coarse` around the last nearest one (a window of 64 ahead, 4 behind), and a
/// window too small would only make the distance larger (the check fails safe).
fn deviation(fine: &Boundary, coarse: &Boundary) -> (f64, (f64, f64)) {
    let c: Vec<(f64, f64)> = coarse.xy();
    let mut j = 0usize;
    let mut worst = (0.0f64, (f64::NAN, f64::NAN));
    for p in fine.xy() {
        let lo = j.saturating_sub(4);
        let hi = (j + 64).min(c.len() - 1);
        let (mut best, mut at) = (f64::INFINITY, j);
        for k in lo..hi {
            let d = seg_dist(p, c[k], c[k + 1]);
            if d < best {
                best = d;
                at = k;
            }
        }
        j = at;
        if best > worst.0 {
            worst = (best, p);
        }
    }
    worst
}

/// At tol 1e-9 and 1e-6 on (delta, d) = (0, 0), (0, 1), (0, 4), (1, 4), (0.5, 1): every
/// vertex of the 1e-12 polyline is within `tol` of the coarser one. The allowance beyond
/// `tol` is the reference's own tolerance and 1e-12 for rounding of coordinates of order 1.
#[test]
fn polyline_within_tol_at_every_vertex_and_the_corner() {
    for (delta, d) in [(0.0, 0.0), (0.0, 1.0), (0.0, 4.0), (1.0, 4.0), (0.5, 1.0)] {
        let plant = Plant::new(delta, d).unwrap();
        // 1e-12, or the next tolerance that fits the engine's vertex budget (at d = 0 the
        // loop is large enough to need more than a million vertices at 1e-12)
        let (fine, fine_tol) = [1e-12, 2e-12, 5e-12]
            .into_iter()
            .find_map(|t| exact(plant, &ExactOptions { tol: t }).ok().map(|b| (b, t)))
            .unwrap();
        for tol in [1e-9, 1e-6] {
            let coarse = exact(plant, &ExactOptions { tol }).unwrap();
            let (dev, at) = deviation(&fine, &coarse);
            assert!(
                dev <= tol + fine_tol + 1e-12,
                "(delta, d) = ({delta}, {d}), tol {tol:e}: the polyline is {dev:e} from the curve at {at:?}"
            );
            // and not far below it: the refinement does not waste vertices
            assert!(dev > 0.5 * tol, "({delta}, {d}), tol {tol:e}: only {dev:e}");
        }
    }
}
