//! The second-order Butterworth velocity filter against scipy: the coefficients
//! `scipy.signal.butter(2, 2 f_c T)` returns, written once into `data/filters/butterworth2.csv`
//! by `python3 data/filters/butterworth2.py` (its bless command).

use stabound::filter::{FilterKind, VelocityFilter};

/// The golden file's rows: `(f_c T, b, a)` with `b` and `a` highest power of `z` first.
pub(crate) fn scipy_rows() -> Vec<(f64, [f64; 3], [f64; 3])> {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../data/filters/butterworth2.csv"
    );
    let text = std::fs::read_to_string(path).unwrap();
    text.lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with("fcT"))
        .map(|l| {
            let v: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
            (v[0], [v[1], v[2], v[3]], [v[4], v[5], v[6]])
        })
        .collect()
}

/// scipy's coefficients for cutoff `fct` (which must be a row of the golden file).
pub(crate) fn scipy_butter(fct: f64) -> ([f64; 3], [f64; 3]) {
    scipy_rows()
        .into_iter()
        // exact: the cutoffs are written and read back as the same decimal literals
        .find(|r| r.0 == fct)
        .map(|r| (r.1, r.2))
        .unwrap_or_else(|| panic!("no golden row for f_c T = {fct}"))
}

/// The library's `Fn` and `Fd` (lowest power first) are scipy's `b` and `a` (highest
/// first) to a few roundings: scipy goes through poles, zeros and gain (`bilinear_zpk`,
/// `zpk2tf`), the library through the closed form in `K = tan(pi f_c T)`, each rounding a
/// handful of times on numbers of size at most 2. Measured: at most `4.5e-16` apart, so
/// `8 eps` (`1.8e-15`) absolute. Over the cutoffs from `0.001` to `0.499` of the sampling
/// rate, both ends of the range.
#[test]
fn coefficients_are_scipys() {
    let rows = scipy_rows();
    assert!(rows.len() >= 10);
    let mut worst = 0.0f64;
    for (fct, b, a) in rows {
        let f = VelocityFilter::butterworth(fct).unwrap();
        assert_eq!(f.kind(), FilterKind::Butterworth { cutoff: fct });
        assert_eq!(f.order(), 2);
        let (num, den) = (f.numerator(), f.denominator());
        for i in 0..3 {
            worst = worst.max((num[2 - i] - b[i]).abs());
            worst = worst.max((den[2 - i] - a[i]).abs());
        }
        assert!(worst <= 8.0 * f64::EPSILON, "f_c T = {fct}: {worst:e}");
    }
}

/// In physical units the cutoff is `f_c T`: 40 Hz at 1 kHz is scipy's row 0.04.
#[test]
fn physical_cutoff() {
    let f = VelocityFilter::low_pass_order(2, 40.0, 1e-3).unwrap();
    let (b, a) = scipy_butter(0.04);
    let (num, den) = (f.numerator(), f.denominator());
    for i in 0..3 {
        assert!((num[2 - i] - b[i]).abs() <= 8.0 * f64::EPSILON);
        assert!((den[2 - i] - a[i]).abs() <= 8.0 * f64::EPSILON);
    }
    // the first order is the first-order low-pass, unchanged
    assert_eq!(
        VelocityFilter::low_pass_order(1, 40.0, 1e-3).unwrap(),
        VelocityFilter::low_pass_cutoff(40.0, 1e-3).unwrap()
    );
}
