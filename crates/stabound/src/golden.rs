//! Golden-section search for the maximum of a unimodal function on a bracket (J. Kiefer,
//! "Sequential minimax search for a maximum", Proc. AMS 4, 1953), the one routine the
//! passive region's searches and the robust searches share. A minimum is the maximum of the
//! negation: negating the values reverses every comparison exactly, so the points visited
//! are the same as those of a minimizing loop written out.

use crate::error::Result;

/// The state a golden-section search stops in.
pub(crate) struct Golden {
    /// The two interior points and their values.
    pub points: [(f64, f64); 2],
    /// The bracket `(l, h)` that holds them.
    pub bracket: (f64, f64),
}

/// Golden-section search for a maximum of `f` in the bracket `(l, h)`, shrinking it while
/// `shrink(l, h, steps)` holds. Where the two interior values tie (or are NaN) the lower
/// end moves up.
pub(crate) fn golden_max(
    mut f: impl FnMut(f64) -> Result<f64>,
    bracket: (f64, f64),
    shrink: impl Fn(f64, f64, usize) -> bool,
) -> Result<Golden> {
    golden_max_above(|x, _| f(x), bracket, shrink)
}

/// [`golden_max`] with `f(x, rival)` told the value `rival` its value will be compared
/// with (`-inf` for the first point): the search visits the same points and keeps the same
/// bracket when `f` returns, for a point whose value is below `rival`, any value below
/// `rival` instead (at least the true value), since the point then loses the comparison
/// either way and leaves the interior at the next step (or, at the last step, stands
/// beside a point whose true value is above it).
pub(crate) fn golden_max_above(
    mut f: impl FnMut(f64, f64) -> Result<f64>,
    (mut l, mut h): (f64, f64),
    shrink: impl Fn(f64, f64, usize) -> bool,
) -> Result<Golden> {
    let g = 0.5 * (5f64.sqrt() - 1.0);
    let mut c = h - g * (h - l);
    let mut d = l + g * (h - l);
    let mut fc = f(c, f64::NEG_INFINITY)?;
    let mut fd = f(d, fc)?;
    let mut steps = 0;
    while shrink(l, h, steps) {
        if fc > fd {
            h = d;
            d = c;
            fd = fc;
            c = h - g * (h - l);
            fc = f(c, fd)?;
        } else {
            l = c;
            c = d;
            fc = fd;
            d = l + g * (h - l);
            fd = f(d, fc)?;
        }
        steps += 1;
    }
    Ok(Golden {
        points: [(c, fc), (d, fd)],
        bracket: (l, h),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_a_peak_and_keeps_it_bracketed() {
        // the peak of -|x - 0.3| (a kink, so the values resolve it to rounding: a smooth
        // maximum is flat below the square root of the rounding error)
        let g = golden_max(
            |x| Ok(-(x - 0.3f64).abs()),
            (-2.0, 5.0),
            |l, h, _| h - l > 1e-9,
        )
        .unwrap();
        let (l, h) = g.bracket;
        assert!(l <= 0.3 && 0.3 <= h && h - l <= 1e-9, "{l} {h}");
        for (x, fx) in g.points {
            assert!((l..=h).contains(&x) && (x - 0.3).abs() < 1e-9 && fx <= 0.0);
        }
    }

    /// Values below the rival replaced by any value between the true one and the rival
    /// leave the search as it was: the same points evaluated in the same order, the same
    /// bracket and interior points, for a smooth peak and a kink; some values were replaced.
    #[test]
    fn values_shown_below_their_rival_change_nothing() {
        let peaks: [fn(f64) -> f64; 2] = [|x| 1.0 - (x - 0.3).powi(2), |x| -(x - 0.3f64).abs()];
        for f in peaks {
            let mut exact: Vec<u64> = Vec::new();
            let a = golden_max(
                |x| {
                    exact.push(x.to_bits());
                    Ok(f(x))
                },
                (-2.0, 5.0),
                |l, h, _| h - l > 1e-9,
            )
            .unwrap();
            let (mut shown, mut replaced) = (Vec::new(), 0);
            let b = golden_max_above(
                |x, rival| {
                    shown.push(x.to_bits());
                    let v = f(x);
                    Ok(if v < rival {
                        replaced += 1;
                        // halfway to the rival: below it (where the rounding of the half
                        // reaches the rival, the true value), at least the true value
                        let m = 0.5 * (v + rival);
                        if m < rival { m } else { v }
                    } else {
                        v
                    })
                },
                (-2.0, 5.0),
                |l, h, _| h - l > 1e-9,
            )
            .unwrap();
            assert_eq!(shown, exact);
            assert!(replaced > 10, "{replaced} values replaced");
            assert_eq!(a.bracket, b.bracket);
            let xs = |g: &Golden| g.points.map(|p| p.0.to_bits());
            assert_eq!(xs(&a), xs(&b));
            // the best interior value is the true one
            let best = |g: &Golden| {
                g.points
                    .iter()
                    .map(|p| p.1)
                    .fold(f64::NEG_INFINITY, f64::max)
            };
            assert_eq!(best(&a).to_bits(), best(&b).to_bits());
        }
    }
}
