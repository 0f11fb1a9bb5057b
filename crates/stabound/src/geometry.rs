//! Plane geometry on `(x, y)` points, shared by the boundary engines and the passivity
//! comparison: distances, polygon areas and convex clipping.

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
}
