//! Axis ticks: steps of 1, 2 or 5 times a power of ten, labels with exactly the decimals of
//! the step (`10`, not `10.0`; `0.25` steps do not occur), never `-0`, and a typographic
//! minus sign.

/// One tick: its value and its label.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Tick {
    pub value: f64,
    pub label: String,
}

/// Ticks for the range `(lo, hi)` (checked by the caller: finite, `lo < hi`, width finite and
/// above `1e-12` of the ends), about `target` of them (at least two fall inside the range).
pub(crate) fn ticks(lo: f64, hi: f64, target: usize) -> Vec<Tick> {
    let target = target.clamp(2, 12) as f64;
    let raw = (hi - lo) / target;
    let mut e = raw.log10().floor();
    let norm = raw / 10f64.powf(e);
    // the nearest of 1, 2, 5, 10 on a log scale: between 2/3 and 3/2 of `target` intervals
    let m = if norm < 1.5 {
        1.0
    } else if norm < 3.0 {
        2.0
    } else if norm < 7.0 {
        5.0
    } else {
        e += 1.0;
        1.0
    };
    let step = m * 10f64.powf(e);
    // a step that cannot be resolved at this magnitude (caller's width check makes this
    // unreachable) gives the two ends
    if !(step.is_finite() && step > 0.0) {
        return ends(lo, hi);
    }
    // 1e-9 of a step: the quotient lo / step carries rounding of a few ulps, far below it
    let k0 = (lo / step - 1e-9).ceil();
    let k1 = (hi / step + 1e-9).floor();
    if k0.is_nan() || k1.is_nan() || k1 - k0 >= 100.0 {
        return ends(lo, hi);
    }
    let (k0, k1) = (k0 as i64, k1 as i64);
    let values: Vec<f64> = (k0..=k1)
        .map(|k| {
            // the value as the integer k m times 10^e: for e < 0 a division by the exact
            // power of ten, so that 3 x 0.1 is the double nearest 0.3
            let km = k as f64 * m;
            if e < 0.0 {
                km / 10f64.powf(-e)
            } else {
                km * 10f64.powf(e)
            }
        })
        .collect();
    let top = values.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let label = labeller(step, e, top);
    values
        .into_iter()
        .map(|v| Tick {
            value: v,
            label: label(v),
        })
        .collect()
}

fn ends(lo: f64, hi: f64) -> Vec<Tick> {
    [lo, hi]
        .into_iter()
        .map(|v| Tick {
            value: v,
            label: tidy(format!("{v:e}"), v == 0.0),
        })
        .collect()
}

/// The label function for ticks of step `step = m 10^e` up to `top` in size: fixed decimals
/// (as many as the step has) for magnitudes in `[1e-4, 1e6)`, else `M e N` with the
/// mantissa's decimals those of the step at the largest tick's exponent.
fn labeller(step: f64, e: f64, top: f64) -> impl Fn(f64) -> String {
    let scientific = top >= 1e6 || e < -4.0;
    let decimals = if scientific {
        let big = top.max(step).log10().floor();
        (big - e).max(0.0) as usize
    } else {
        (-e).max(0.0) as usize
    };
    move |v: f64| {
        // a tick within a thousandth of a step of zero is zero (k = 0 gives exactly 0.0;
        // this also catches -0.0)
        let zero = v.abs() < 1e-3 * step;
        let text = if zero {
            "0".to_string()
        } else if scientific {
            format!("{v:.decimals$e}")
        } else {
            format!("{v:.decimals$}")
        };
        tidy(text, zero)
    }
}

/// A typographic minus sign for negative labels, and `0` for any zero.
fn tidy(text: String, zero: bool) -> String {
    if zero {
        return "0".into();
    }
    match text.strip_prefix('-') {
        Some(rest) => format!("\u{2212}{rest}"),
        None => text,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn labels(lo: f64, hi: f64, n: usize) -> Vec<String> {
        ticks(lo, hi, n).into_iter().map(|t| t.label).collect()
    }

    /// Labels worked out by hand: steps of 2 over [0, 10] print no decimals; 0.2 over
    /// [-1, 1] one, with `0` (not `-0.0`) and the minus sign U+2212.
    #[test]
    fn labels_have_the_decimals_of_the_step() {
        assert_eq!(labels(0.0, 10.0, 5), ["0", "2", "4", "6", "8", "10"]);
        assert_eq!(
            labels(-1.0, 1.0, 5),
            ["\u{2212}1.0", "\u{2212}0.5", "0", "0.5", "1.0"]
        );
        assert_eq!(labels(-0.3, 0.3, 6), {
            let v: Vec<String> = [
                "\u{2212}0.3",
                "\u{2212}0.2",
                "\u{2212}0.1",
                "0",
                "0.1",
                "0.2",
                "0.3",
            ]
            .map(String::from)
            .to_vec();
            v
        });
        assert_eq!(labels(0.0, 3e7, 3), ["0", "1e7", "2e7", "3e7"]);
        assert_eq!(
            labels(1e-300, 2e-300, 2),
            ["1.0e-300", "1.5e-300", "2.0e-300"]
        );
    }

    /// Never more than 20 ticks (3/2 of the largest target of 12, plus the ends), and at
    /// least two inside the range, for ranges of every
    /// size (including the widest drawable one).
    #[test]
    fn tick_counts_stay_bounded() {
        for (lo, hi) in [(0.0, 1e-9), (-1e300, 1e300), (5.0, 5.0001), (-3.7, 12.2)] {
            for n in [2, 5, 8, 12, 40] {
                let t = ticks(lo, hi, n);
                assert!(t.len() >= 2 && t.len() <= 20, "{lo} {hi} {n}: {}", t.len());
                assert!(t.iter().all(|t| t.value >= lo - 1e-9 * (hi - lo)));
            }
        }
    }
}
