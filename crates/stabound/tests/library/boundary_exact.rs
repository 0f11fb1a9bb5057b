//! Tests of the boundary engines: exact against bisection, eigenvalue
//! checks of the exact points, the paper's shapes and published values (docs/MODEL.md section 6).

use stabound::boundary::{
    BisectOptions, Boundary, ExactOptions, Piece, bisect_alpha_beta, directed_distance, exact,
};
use stabound::params::{Plant, Wall};
use stabound::stability::{Checker, Method, Options, Verdict, spectral_radius};

type Pts = Vec<(f64, f64)>;

const DS: [f64; 6] = [0.0, 0.25, 0.5, 1.0, 2.0, 4.0];
const DELTAS: [f64; 6] = [0.0, 0.25, 0.5, 0.75, 1.0, 3.0];

fn ex(delta: f64, d: f64, tol: f64) -> Boundary {
    exact(Plant::new(delta, d).unwrap(), &ExactOptions { tol }).unwrap()
}

/// The vertices of the exact and of the bisection boundary of `(delta, d)` at `tol`.
fn both_engines(delta: f64, d: f64, tol: f64) -> (Pts, Pts) {
    let b = bisect_alpha_beta(
        Plant::new(delta, d).unwrap(),
        &BisectOptions {
            tol,
            ..BisectOptions::default()
        },
    )
    .unwrap();
    (ex(delta, d, tol).xy(), b.xy())
}

/// Exact (D-decomposition) and bisection (grid + point tests only) boundaries agree within
/// 10 tol in the Hausdorff distance, both ways, over the test family.
#[test]
fn exact_matches_bisection() {
    // 1e-8 keeps the test quick; the engines and the criterion do not depend on the value.
    let tol = 1e-8;
    for &d in &DS {
        for &delta in &DELTAS {
            let (pe, pb) = both_engines(delta, d, tol);
            let h = 1e-3;
            // The lowest corner (0, -delta) is a double root at z = 1, where point tests cannot
            // resolve the thin wedge of the region below about 1e-5 (the stability gap there
            // is far below rounding); the exact engine has it in closed form. Both engines must
            // agree to 1e-5 overall, and to 10 tol for vertices away from that corner.
            let keep = |p: &&(f64, f64)| p.0.hypot(p.1 + delta) > 1e-4;
            let (qe, qb): (Pts, Pts) = (
                pe.iter().filter(keep).copied().collect(),
                pb.iter().filter(keep).copied().collect(),
            );
            let all = directed_distance(&pe, &pb, h).max(directed_distance(&pb, &pe, h));
            assert!(all <= 1e-5, "delta {delta} d {d}: Hausdorff {all:e}");
            let dist = directed_distance(&qe, &pb, h).max(directed_distance(&qb, &pe, h));
            assert!(
                dist <= 10.0 * tol,
                "delta {delta} d {d}: Hausdorff {dist:e} ({} vs {} points)",
                pe.len(),
                pb.len()
            );
        }
    }
}

/// The Hausdorff criterion taken literally, with no vertex left out: at tol 1e-6
/// (the numpy comparison's tolerance) the two engines agree within 10 tol everywhere,
/// the corner (0, -delta) included.
#[test]
fn exact_matches_bisection_everywhere_at_1e_6() {
    let tol = 1e-6;
    for &d in &DS {
        for &delta in &DELTAS {
            let (pe, pb) = both_engines(delta, d, tol);
            let h = 1e-3;
            let all = directed_distance(&pe, &pb, h).max(directed_distance(&pb, &pe, h));
            assert!(
                all <= 10.0 * tol,
                "delta {delta} d {d}: Hausdorff {all:e} ({} vs {} points)",
                pe.len(),
                pb.len()
            );
        }
    }
}

/// Every exact point with alpha > 0 has spectral radius 1 to 1e-9 by companion eigenvalues
/// (not the Schur-Cohn test the engine uses), and the polyline closes.
#[test]
fn exact_points_have_a_root_on_the_circle() {
    for &d in &DS {
        for &delta in &DELTAS {
            let plant = Plant::new(delta, d).unwrap();
            let b = ex(delta, d, 1e-9);
            let c = Checker::new(plant, Options::default()).unwrap();
            let first = b.points[0];
            let last = b.points[b.points.len() - 1];
            assert!(first.x == last.x && first.y == last.y);
            // every 7th point and every corner (piece change): eigenvalues cost microseconds
            let n = b.points.len();
            for (i, p) in b.points.iter().enumerate() {
                let corner = i > 0 && b.points[i - 1].piece != p.piece;
                if p.x <= 0.0 || !(i % 7 == 0 || corner || i + 1 == n) {
                    continue;
                }
                let roots = c
                    .roots(&Wall::new(p.x, p.y).unwrap(), Method::Eigen)
                    .unwrap();
                let r = spectral_radius(&roots);
                assert!(
                    (r - 1.0).abs() <= 1e-9,
                    "delta {delta} d {d} point {i} {p:?}: radius {r}"
                );
            }
        }
    }
}

/// A point slightly inside the curve (1e-6 along the inward normal of the polyline,
/// counterclockwise so inward is to the left) is stable, one slightly outside is not; away
/// from corners, where the normal is well defined.
#[test]
fn inside_is_stable_outside_is_not() {
    for &d in &DS {
        for &delta in &DELTAS {
            let plant = Plant::new(delta, d).unwrap();
            let b = ex(delta, d, 1e-9);
            let c = Checker::new(plant, Options::default()).unwrap();
            let corners: Vec<(f64, f64)> = (1..b.points.len())
                .filter(|&i| b.points[i - 1].piece != b.points[i].piece)
                .map(|i| (b.points[i].x, b.points[i].y))
                .chain(std::iter::once((b.points[0].x, b.points[0].y)))
                .collect();
            for i in (0..b.points.len() - 1).step_by(97) {
                let (p, q) = (b.points[i], b.points[i + 1]);
                let m = (0.5 * (p.x + q.x), 0.5 * (p.y + q.y));
                if corners.iter().any(|k| (k.0 - m.0).hypot(k.1 - m.1) < 1e-3) {
                    continue;
                }
                let (dx, dy) = (q.x - p.x, q.y - p.y);
                let l = dx.hypot(dy);
                let (nx, ny) = (-dy / l, dx / l);
                let e = 1e-6;
                let inside = Wall::new(m.0 + e * nx, m.1 + e * ny).unwrap();
                let outside = Wall::new(m.0 - e * nx, m.1 - e * ny).unwrap();
                assert_eq!(
                    c.verdict(&inside).unwrap(),
                    Verdict::Stable,
                    "{delta} {d} {i}"
                );
                assert_eq!(
                    c.verdict(&outside).unwrap(),
                    Verdict::Unstable,
                    "{delta} {d} {i}"
                );
            }
        }
    }
}

/// Paper eq. (19): every curve starts at (0, -delta), the lowest point on alpha = 0.
#[test]
fn lower_start_is_minus_delta() {
    for &d in &[0.0, 0.25, 0.5, 1.0, 2.0, 4.0, 7.5] {
        for &delta in &[0.0, 0.1, 0.5, 1.0, 3.0, 10.0] {
            let b = ex(delta, d, 1e-9);
            let p = b.points[0];
            assert!(p.x.abs() <= 1e-12, "{delta} {d}: {p:?}");
            assert!(
                (p.y + delta).abs() <= 1e-9 * (1.0 + delta),
                "{delta} {d}: {p:?}"
            );
        }
    }
}

/// docs/MODEL.md section 4 / paper Fig. 7: for d = 0 and delta > 2.3 the upper edge is the z = -1
/// line of slope -1/2; below 2.3 it is not part of the boundary.
#[test]
fn upper_edge_for_large_delta_is_the_minus_one_line() {
    for &delta in &[2.4, 3.0, 5.0, 20.0] {
        let b = ex(delta, 0.0, 1e-9);
        let seg: Vec<_> = b
            .points
            .windows(2)
            .filter(|w| w[0].piece == Piece::MinusOne)
            .collect();
        assert!(!seg.is_empty(), "delta {delta}: no z = -1 edge");
        for w in seg {
            let slope = (w[1].y - w[0].y) / (w[1].x - w[0].x);
            assert!((slope + 0.5).abs() < 1e-9, "delta {delta}: slope {slope}");
        }
    }
    for &delta in &[0.5, 1.0, 2.0, 2.2] {
        let b = ex(delta, 0.0, 1e-9);
        assert!(
            b.points.iter().all(|p| p.piece != Piece::MinusOne),
            "delta {delta}"
        );
    }
}

/// Published values (docs/MODEL.md section 6): alpha_max for delta = 0, d = 0 is 12 - 8 sqrt 2 at
/// beta = 2 sqrt 2 - 2; for d = 1 it is 0.1445; section VIII's 75 % values and betas.
#[test]
fn rightmost_points_match_published_values() {
    let s2 = 2f64.sqrt();
    let (a, b) = ex(0.0, 0.0, 1e-9).rightmost();
    assert!((a - (12.0 - 8.0 * s2)).abs() < 1e-8, "{a}");
    assert!((b - (2.0 * s2 - 2.0)).abs() < 1e-3, "{b}");
    let (a, _) = ex(0.0, 1.0, 1e-9).rightmost();
    assert!((a - 0.1445).abs() < 5e-5, "{a}");
    for (delta, a75, beta) in [
        (0.0, 0.108, 0.425),
        (0.1, 0.149, 0.416),
        (1.0, 0.656, 0.388),
    ] {
        let (a, b) = ex(delta, 1.0, 1e-9).rightmost();
        assert!((0.75 * a - a75).abs() < 5e-4, "{delta}: {a}");
        assert!((b - beta).abs() < 5e-4, "{delta}: {b}");
    }
}

/// Continuity in d (docs/MODEL.md section 2): alpha_max moves little for a tiny change of d across
/// an integer, where the polynomial's degree changes.
#[test]
fn continuous_across_integer_delay() {
    for &delta in &[0.0, 0.5] {
        let (a1, _) = ex(delta, 1.0, 1e-9).rightmost();
        let (a2, _) = ex(delta, 1.0 + 1e-7, 1e-9).rightmost();
        let (a0, _) = ex(delta, 1.0 - 1e-7, 1e-9).rightmost();
        assert!(
            (a1 - a2).abs() < 1e-5 && (a1 - a0).abs() < 1e-5,
            "{a0} {a1} {a2}"
        );
    }
}

#[test]
fn bad_tolerance_is_rejected() {
    let p = Plant::new(0.5, 1.0).unwrap();
    for tol in [0.0, -1.0, f64::NAN, 1.0] {
        assert!(matches!(
            exact(p, &ExactOptions { tol }),
            Err(stabound::Error::InvalidParameter { .. })
        ));
    }
}
