//! Plane geometry on `(x, y)` points, shared by the boundary engines and the passivity
//! comparison: distances, polygon areas, point in polygon and convex clipping.

/// Euclidean length of `(x, y)`. `sqrt(x^2 + y^2)` rather than `hypot`: the crate's
/// coordinates stay far below 1e150 (alpha and beta are at most a few times delta <= 1e9), so
/// the squares cannot overflow, and `hypot`'s scaling cost a tenth of a boundary's run time.
pub(crate) fn norm2(x: f64, y: f64) -> f64 {
    (x * x + y * y).sqrt()
}

/// Distance between the points `a` and `b`.
pub(crate) fn point_dist(a: (f64, f64), b: (f64, f64)) -> f64 {
    norm2(a.0 - b.0, a.1 - b.1)
}

/// Distance from `p` to the segment `[a, b]` (to `a` when the segment is a point).
pub(crate) fn seg_dist(p: (f64, f64), a: (f64, f64), b: (f64, f64)) -> f64 {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let len2 = dx * dx + dy * dy;
    let t = if len2 > 0.0 {
        (((p.0 - a.0) * dx + (p.1 - a.1) * dy) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    norm2(p.0 - a.0 - t * dx, p.1 - a.1 - t * dy)
}

/// Signed area of a closed polygon (the closing edge is implied): positive when the
/// vertices run counterclockwise (the shoelace formula).
pub(crate) fn polygon_area(p: &[(f64, f64)]) -> f64 {
    let n = p.len();
    (0..n)
        .map(|i| {
            let (a, b) = (p[i], p[(i + 1) % n]);
            a.0 * b.1 - b.0 * a.1
        })
        .sum::<f64>()
        * 0.5
}

/// Whether `q` lies inside the closed polygon `p` (the closing repeat dropped), by the
/// crossing number of a ray towards larger `x` (Shimrat, "Algorithm 112: position of point
/// relative to polygon", CACM 5(8), 1962).
pub(crate) fn inside_polygon(q: (f64, f64), p: &[(f64, f64)]) -> bool {
    let mut inside = false;
    for i in 0..p.len() {
        let (a, b) = (p[i], p[(i + 1) % p.len()]);
        if (a.1 > q.1) != (b.1 > q.1) {
            let x = a.0 + (q.1 - a.1) / (b.1 - a.1) * (b.0 - a.0);
            if q.0 < x {
                inside = !inside;
            }
        }
    }
    inside
}

/// The part of polygon `subject` inside the convex counterclockwise polygon `clip_poly`
/// (Sutherland-Hodgman).
pub(crate) fn clip(subject: &[(f64, f64)], clip_poly: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let mut out = subject.to_vec();
    let k = clip_poly.len();
    for i in 0..k {
        if out.is_empty() || crate::cancel::stopped() {
            break;
        }
        let (a, b) = (clip_poly[i], clip_poly[(i + 1) % k]);
        let side = |p: (f64, f64)| (b.0 - a.0) * (p.1 - a.1) - (b.1 - a.1) * (p.0 - a.0);
        let input = std::mem::take(&mut out);
        for j in 0..input.len() {
            let (p, q) = (input[j], input[(j + 1) % input.len()]);
            let (sp, sq) = (side(p), side(q));
            if sp >= 0.0 {
                out.push(p);
            }
            if (sp >= 0.0) != (sq >= 0.0) {
                let t = sp / (sp - sq);
                out.push((p.0 + t * (q.0 - p.0), p.1 + t * (q.1 - p.1)));
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distances_and_areas_of_known_figures() {
        assert_eq!(point_dist((0.0, 0.0), (3.0, 4.0)), 5.0);
        // beyond either end the nearest point is the end
        assert_eq!(seg_dist((-3.0, 4.0), (0.0, 0.0), (10.0, 0.0)), 5.0);
        assert_eq!(seg_dist((13.0, 4.0), (0.0, 0.0), (10.0, 0.0)), 5.0);
        assert_eq!(seg_dist((5.0, 2.0), (0.0, 0.0), (10.0, 0.0)), 2.0);
        assert_eq!(seg_dist((3.0, 4.0), (0.0, 0.0), (0.0, 0.0)), 5.0);
        let square = [(0.0, 0.0), (2.0, 0.0), (2.0, 2.0), (0.0, 2.0)];
        assert_eq!(polygon_area(&square), 4.0);
        let mut reversed = square;
        reversed.reverse();
        assert_eq!(polygon_area(&reversed), -4.0);
    }

    /// Two unit-offset 2 x 2 squares overlap in a unit square.
    #[test]
    fn clip_of_squares() {
        let s = [(0.0, 0.0), (2.0, 0.0), (2.0, 2.0), (0.0, 2.0)];
        let c = [(1.0, 1.0), (3.0, 1.0), (3.0, 3.0), (1.0, 3.0)];
        let a = polygon_area(&clip(&s, &c));
        assert!((a - 1.0).abs() < 1e-15);
    }

    /// The crossing number of a ray: inside, and outside on either side.
    #[test]
    fn point_in_polygon() {
        let square = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)];
        assert!(inside_polygon((0.5, 0.5), &square));
        assert!(!inside_polygon((1.5, 0.5), &square));
        assert!(!inside_polygon((0.5, -0.5), &square));
    }
}
