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
}
