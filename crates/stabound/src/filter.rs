//! Velocity filters on the wall's damping term (model document, section 8).
//!
//! The wall law is `u_k = -(alpha y_k + beta w_k)` with `w = F(z) (1 - z^{-1}) y`: the
//! damping acts on a filtered backward difference of the sensed position. `F = 1` is the
//! paper's plain backward difference. Every filter here has `F(1) = 1`, so a constant
//! velocity is estimated without bias, and `F = Fn / Fd` with `Fd` monic.
//!
//! ```
//! use stabound::filter::VelocityFilter;
//!
//! // A first-order low-pass at 20 Hz on a 1 kHz loop.
//! let f = VelocityFilter::low_pass_cutoff(20.0, 1e-3)?;
//! assert!((f.response(0.0).re - 1.0).abs() < 1e-15); // F(1) = 1
//! assert_eq!(f.order(), 1);
//! # Ok::<(), stabound::Error>(())
//! ```

use std::f64::consts::PI;

use crate::error::{Error, Result};
use crate::params::finite;

/// A complex number on or near the unit circle (the filter's frequency response).
type Complex = nalgebra::Complex<f64>;

/// The longest moving average accepted, in samples.
///
/// Each sample of the window adds one degree to the characteristic polynomial; 64 samples
/// at 1 kHz already lag by 32 ms, beyond any filter a stable haptic wall tolerates.
pub const MAX_MOVING_AVERAGE: usize = 64;

/// The names reports give the low-pass velocity filter element of each order (`[order -
/// 1]`): the orders [`VelocityFilter::low_pass_order`] designs.
pub(crate) const LOW_PASS_NAMES: [&str; 2] = [
    "low-pass velocity filter",
    "second-order low-pass velocity filter",
];

/// A velocity filter `F(z)` with `F(1) = 1`. Built only through its constructors, so its
/// values are always valid.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VelocityFilter {
    kind: FilterKind,
}

/// What a [`VelocityFilter`] is, with its normalized parameter.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub enum FilterKind {
    /// No filter: `F = 1`, the paper's backward difference.
    None,
    /// First-order low-pass `w_k = a w_{k-1} + (1 - a)(y_k - y_{k-1})`, i.e.
    /// `F = (1 - a) z / (z - a)`, with pole `a = exp(-2 pi f_c T)` in `[0, 1)`.
    LowPass {
        /// The pole `a`.
        pole: f64,
    },
    /// Moving average of the backward difference over `samples` periods:
    /// `w_k = (y_k - y_{k-N}) / N`, i.e. `F = (1 + z^-1 + ... + z^-(N-1)) / N`.
    MovingAverage {
        /// The window length `N >= 1`.
        samples: usize,
    },
    /// Second-order Butterworth low-pass designed by the bilinear transform prewarped at the
    /// cutoff: with `K = tan(pi f_c T)`,
    /// `F = K^2 (z + 1)^2 / ((1 + sqrt2 K + K^2) z^2 + 2 (K^2 - 1) z + (1 - sqrt2 K + K^2))`,
    /// the coefficients `scipy.signal.butter(2, 2 f_c T)` returns, unit gain at DC.
    Butterworth {
        /// The cutoff as a fraction of the sampling rate, `f_c T` in `(0, 1/2)`.
        cutoff: f64,
    },
}

impl Default for VelocityFilter {
    fn default() -> Self {
        Self::none()
    }
}

impl VelocityFilter {
    /// No filter (`F = 1`).
    pub fn none() -> Self {
        Self {
            kind: FilterKind::None,
        }
    }

    /// A first-order low-pass with pole `a` (normalized form), `0 <= a < 1`. `a = 0` is
    /// no filter at all.
    pub fn low_pass(pole: f64) -> Result<Self> {
        finite("velocity filter pole", pole)?;
        if !(0.0..1.0).contains(&pole) {
            return Err(Error::InvalidParameter {
                name: "velocity filter pole",
                value: pole,
                expected: "the low-pass pole a = exp(-2 pi f_c T) must be in [0, 1)".into(),
            });
        }
        Ok(Self {
            kind: FilterKind::LowPass { pole },
        })
    }

    /// A first-order low-pass with cutoff `cutoff_hz` on a loop sampled every `period_s`
    /// seconds: `a = exp(-2 pi f_c T)`. The cutoff must be positive and at most the Nyquist
    /// frequency `1 / (2 T)`.
    pub fn low_pass_cutoff(cutoff_hz: f64, period_s: f64) -> Result<Self> {
        finite("velocity filter cutoff", cutoff_hz)?;
        finite("period", period_s)?;
        if period_s <= 0.0 {
            return Err(Error::InvalidParameter {
                name: "period",
                value: period_s,
                expected: "must be greater than 0".into(),
            });
        }
        let nyquist = 0.5 / period_s;
        if cutoff_hz <= 0.0 || cutoff_hz > nyquist {
            return Err(Error::InvalidParameter {
                name: "velocity filter cutoff",
                value: cutoff_hz,
                expected: format!(
                    "the cutoff must be above 0 Hz and at most the Nyquist frequency {nyquist} Hz of this sampling period"
                ),
            });
        }
        Self::low_pass((-2.0 * PI * cutoff_hz * period_s).exp())
    }

    /// A second-order Butterworth low-pass (the bilinear transform prewarped at the cutoff,
    /// as `scipy.signal.butter(2, 2 f_c T)`) with cutoff `f_c T = cutoff` in `(0, 1/2)`
    /// (normalized form: the cutoff over the sampling rate).
    ///
    /// ```
    /// use stabound::filter::VelocityFilter;
    ///
    /// let f = VelocityFilter::butterworth(0.03)?;
    /// assert_eq!(f.order(), 2);
    /// // F(1) = 1 to the rounding of the coefficients' sums
    /// assert!((f.response(0.0).re - 1.0).abs() < 1e-14);
    /// // -3 dB at the cutoff
    /// let at = f.response(2.0 * std::f64::consts::PI * 0.03).norm();
    /// assert!((at - std::f64::consts::FRAC_1_SQRT_2).abs() < 1e-12);
    /// # Ok::<(), stabound::Error>(())
    /// ```
    pub fn butterworth(cutoff: f64) -> Result<Self> {
        finite("velocity filter cutoff", cutoff)?;
        if !(cutoff > 0.0 && cutoff < 0.5) {
            return Err(Error::InvalidParameter {
                name: "velocity filter cutoff",
                value: cutoff,
                expected: "the second-order filter's cutoff f_c T must be above 0 and below the Nyquist frequency 1/2 of the sampling rate".into(),
            });
        }
        Ok(Self {
            kind: FilterKind::Butterworth { cutoff },
        })
    }

    /// A low-pass of order `order` (1: [`VelocityFilter::low_pass_cutoff`], 2:
    /// [`VelocityFilter::butterworth`]) with cutoff `cutoff_hz` on a loop sampled every
    /// `period_s` seconds. The second order needs the cutoff below the Nyquist frequency.
    pub fn low_pass_order(order: usize, cutoff_hz: f64, period_s: f64) -> Result<Self> {
        match order {
            1 => Self::low_pass_cutoff(cutoff_hz, period_s),
            2 => {
                // the first order's checks name the cutoff and the period in hertz
                Self::low_pass_cutoff(cutoff_hz, period_s)?;
                let nyquist = 0.5 / period_s;
                if cutoff_hz >= nyquist {
                    return Err(Error::InvalidParameter {
                        name: "velocity filter cutoff",
                        value: cutoff_hz,
                        expected: format!(
                            "the second-order filter's cutoff must be below the Nyquist frequency {nyquist} Hz of this sampling period"
                        ),
                    });
                }
                Self::butterworth(cutoff_hz * period_s)
            }
            _ => Err(Error::InvalidParameter {
                name: "velocity filter order",
                value: order as f64,
                expected: "the low-pass velocity filter has order 1 or 2".into(),
            }),
        }
    }

    /// A moving average over `samples` periods, `1 <= samples <= MAX_MOVING_AVERAGE`.
    /// One sample is no filter at all.
    pub fn moving_average(samples: usize) -> Result<Self> {
        if samples == 0 || samples > MAX_MOVING_AVERAGE {
            return Err(Error::InvalidParameter {
                name: "velocity filter samples",
                value: samples as f64,
                expected: format!(
                    "the moving average needs a whole number of samples from 1 to {MAX_MOVING_AVERAGE}"
                ),
            });
        }
        Ok(Self {
            kind: FilterKind::MovingAverage { samples },
        })
    }

    /// What this filter is.
    pub fn kind(&self) -> FilterKind {
        self.kind
    }

    /// Whether this is `F = 1` (no filter, a zero pole, or a one-sample average).
    pub fn is_identity(&self) -> bool {
        match self.kind {
            FilterKind::None => true,
            // exact: a zero pole makes F = z / z = 1 identically
            FilterKind::LowPass { pole } => pole == 0.0,
            FilterKind::MovingAverage { samples } => samples == 1,
            FilterKind::Butterworth { .. } => false,
        }
    }

    /// Whether its coefficients are the bilinear transform's prewarped at the cutoff, a
    /// function of `K = tan(pi f_c T)` alone ([`prewarped_design`]): a proof over an
    /// interval of cutoffs encloses `K` and then the design.
    pub(crate) fn is_prewarped(&self) -> bool {
        matches!(self.kind, FilterKind::Butterworth { .. })
    }

    /// Its name with its normalized parameter, as summaries write it.
    ///
    /// ```
    /// use stabound::filter::VelocityFilter;
    ///
    /// assert_eq!(VelocityFilter::low_pass(0.5)?.name(), "low-pass a = 0.5");
    /// assert_eq!(VelocityFilter::moving_average(3)?.name(), "moving average N = 3");
    /// assert_eq!(VelocityFilter::butterworth(0.04)?.name(), "second-order low-pass f_c T = 0.04");
    /// assert_eq!(VelocityFilter::moving_average(1)?.name(), "none"); // F = 1
    /// # Ok::<(), stabound::Error>(())
    /// ```
    pub fn name(&self) -> String {
        match self.kind {
            _ if self.is_identity() => "none".into(),
            FilterKind::LowPass { pole } => format!("low-pass a = {pole}"),
            FilterKind::MovingAverage { samples } => format!("moving average N = {samples}"),
            FilterKind::Butterworth { cutoff } => format!("second-order low-pass f_c T = {cutoff}"),
            FilterKind::None => "none".into(),
        }
    }

    /// Its title in a table's header, which names its kind (its parameter's reading alone
    /// does not say it).
    ///
    /// ```
    /// use stabound::filter::VelocityFilter;
    ///
    /// assert_eq!(
    ///     VelocityFilter::butterworth(0.04)?.title(),
    ///     "second-order Butterworth low-pass velocity filter on the wall's damping term"
    /// );
    /// # Ok::<(), stabound::Error>(())
    /// ```
    pub fn title(&self) -> &'static str {
        match self.kind {
            FilterKind::LowPass { .. } => {
                "first-order low-pass velocity filter on the wall's damping term"
            }
            FilterKind::Butterworth { .. } => {
                "second-order Butterworth low-pass velocity filter on the wall's damping term"
            }
            FilterKind::MovingAverage { .. } => {
                "moving-average velocity filter on the wall's damping term"
            }
            FilterKind::None => "velocity filter on the wall's damping term",
        }
    }

    /// The cutoff `f_c T` of a filter designed from it beyond the first-order low-pass (read
    /// by its pole), with the label a report gives it, which names the design.
    pub(crate) fn design_cutoff(&self) -> Option<(&'static str, f64)> {
        match self.kind {
            FilterKind::Butterworth { cutoff } => Some(("butterworth_cutoff", cutoff)),
            _ => None,
        }
    }

    /// Degree of the denominator `Fd` (the filter's own state dimension).
    pub fn order(&self) -> usize {
        match self.kind {
            FilterKind::None => 0,
            FilterKind::LowPass { .. } => 1,
            FilterKind::MovingAverage { samples } => samples - 1,
            FilterKind::Butterworth { .. } => 2,
        }
    }

    /// The numerator `Fn`, coefficients lowest power first.
    pub fn numerator(&self) -> Vec<f64> {
        match self.kind {
            FilterKind::None => vec![1.0],
            FilterKind::LowPass { pole } => vec![0.0, 1.0 - pole],
            FilterKind::MovingAverage { samples } => vec![1.0 / samples as f64; samples],
            FilterKind::Butterworth { cutoff } => {
                let (b, _) = butterworth2(cutoff);
                vec![b[2], b[1], b[0]]
            }
        }
    }

    /// The monic denominator `Fd`, coefficients lowest power first.
    pub fn denominator(&self) -> Vec<f64> {
        match self.kind {
            FilterKind::None => vec![1.0],
            FilterKind::LowPass { pole } => vec![-pole, 1.0],
            FilterKind::MovingAverage { samples } => {
                let mut d = vec![0.0; samples];
                d[samples - 1] = 1.0;
                d
            }
            FilterKind::Butterworth { cutoff } => {
                let (_, a) = butterworth2(cutoff);
                vec![a[2], a[1], 1.0]
            }
        }
    }

    /// A bound on `sum_k |h_k| (m + k)^2` over the impulse response `h` of `F` (`m >= 1`):
    /// the passivity criterion of a delay of `m - 1` samples bounds the curvature of its
    /// filter term by twice this (`crate::passivity::Criterion`, whose term is
    /// `B = -2 sum_k h_k cos((m + k) theta)`). Each kind states its own derivation: the
    /// match lists every kind on purpose (a bound is a derivation, not a default).
    ///
    /// - none: `h = (1)`, the sum is `m^2`;
    /// - first-order low-pass: `h_k = (1 - a) a^k >= 0`, and
    ///   `sum (1 - a) a^k (m + k)^2 = m^2 + 2 m a / (1 - a) + a (1 + a) / (1 - a)^2`;
    /// - moving average: `h_k = 1 / N` for `k < N`, summed as it is;
    /// - second-order Butterworth: its impulse response changes sign; partial fractions over
    ///   its complex pole pair bound it (`damped_pair_bound`).
    pub(crate) fn shifted_moment_bound(&self, m: f64) -> f64 {
        match self.kind {
            FilterKind::LowPass { pole: a } => {
                m * m + 2.0 * m * a / (1.0 - a) + a * (1.0 + a) / ((1.0 - a) * (1.0 - a))
            }
            FilterKind::MovingAverage { samples } => {
                (0..samples).map(|k| (m + k as f64).powi(2)).sum::<f64>() / samples as f64
            }
            FilterKind::Butterworth { .. } => {
                damped_pair_bound(&self.numerator(), &self.denominator(), m)
            }
            FilterKind::None => m * m,
        }
    }

    /// A bound on the passivity criterion's `|B''|` over `[t, pi]` only, for a delay of
    /// `m - 1` samples, tighter than twice [`VelocityFilter::shifted_moment_bound`] away from
    /// `theta = 0` (where a low-pass filter's term peaks); `None` for a filter that has no
    /// such bound stated (the global one holds).
    pub(crate) fn curvature_bound_from(&self, m: f64, t: f64) -> Option<f64> {
        match self.kind {
            FilterKind::LowPass { pole } => Some(low_pass_b2_from(pole, m, t)),
            _ => None,
        }
    }

    /// The frequency response `F(e^{i theta})`.
    pub fn response(&self, theta: f64) -> Complex {
        let z = Complex::from_polar(1.0, theta);
        eval(&self.numerator(), z) / eval(&self.denominator(), z)
    }
}

/// The second-order Butterworth low-pass with cutoff `f_c T = cutoff`, as
/// `(b, a)` in `scipy.signal.butter`'s order (highest power of `z` first, `a[0] = 1`).
///
/// Method: the analog prototype `1 / (s^2 + sqrt2 s + 1)` scaled to the prewarped cutoff
/// and mapped by the bilinear transform `s = (z - 1) / (z + 1)` (its factor `2 / T`
/// cancels against the prewarping `w_a = (2 / T) tan(pi f_c T)`), leaving `K = tan(pi f_c T)`
/// (Oppenheim and Schafer, *Discrete-Time Signal Processing*, 3rd ed., 2010, section 7.2.2).
fn butterworth2(cutoff: f64) -> ([f64; 3], [f64; 3]) {
    let k = (std::f64::consts::PI * cutoff).tan();
    let (k2, r2k) = (k * k, std::f64::consts::SQRT_2 * k);
    let norm = 1.0 / (1.0 + r2k + k2);
    let b0 = k2 * norm;
    (
        [b0, 2.0 * b0, b0],
        [1.0, 2.0 * (k2 - 1.0) * norm, (1.0 - r2k + k2) * norm],
    )
}

/// The prewarped second-order design of [`butterworth2`] as a function of `K` in any
/// arithmetic with the four operations (interval arithmetic, or a value with its
/// derivative): `(Fn, Fd)` lowest power first, given `K`, one and an enclosure of
/// `sqrt 2`. The same steps as `butterworth2`, with `K` given rather than computed, and a
/// division by the norm where `butterworth2` multiplies by its reciprocal (in interval
/// arithmetic one rounding fewer).
pub(crate) fn prewarped_design<T>(k: T, one: T, sqrt2: T) -> ([T; 3], [T; 3])
where
    T: Copy
        + std::ops::Add<Output = T>
        + std::ops::Sub<Output = T>
        + std::ops::Mul<Output = T>
        + std::ops::Div<Output = T>,
{
    let r2k = sqrt2 * k;
    let k2 = k * k;
    let norm = one + r2k + k2;
    let b0 = k2 / norm;
    let two = one + one;
    (
        [b0, two * b0, b0],
        [(one - r2k + k2) / norm, two * (k2 - one) / norm, one],
    )
}

/// A bound on `|B''|` over `[t, pi]` for the low-pass filter with pole `a`, and delay `m - 1`
/// samples: `B = -2 Re g` with `g = (1 - a) u^m / (1 - a u)`, `u = e^{-i theta}`. Two
/// derivatives of `g` (with `D = |1 - a u|`) give
/// `|g''| <= (1 - a) (m^2 / D + (2m + 1) a / D^2 + 2 a^2 / D^3)`, and `D^2 = (1 - a)^2 +
/// 4 a sin^2(theta / 2)` grows on `[0, pi]`, so `D(t)` bounds it from below there. At
/// `t = 0` this is the global bound; away from it the bound falls as `D^{-3}`, which keeps
/// the branch and bound short for a pole near 1, whose peak at `theta = 0` is `1 - a` wide
/// and `(1 - a)^{-2}` sharp.
fn low_pass_b2_from(a: f64, m: f64, t: f64) -> f64 {
    let s = (0.5 * t).sin();
    let dd = ((1.0 - a) * (1.0 - a) + 4.0 * a * s * s).sqrt();
    2.0 * (1.0 - a) * (m * m / dd + (2.0 * m + 1.0) * a / (dd * dd) + 2.0 * a * a / (dd * dd * dd))
}

/// `sum_k |h_k| (m + k)^2` for the impulse response `h` of `F = Fn / Fd` with `Fd` monic of
/// degree two and complex poles `p, conj(p)` of radius `rho < 1` (a second-order low-pass),
/// an upper bound.
///
/// Method: partial fractions, `F = b0 + R / Fd` with `R` of degree one, so for `k >= 1`
/// `h_k = 2 Re(c p^(k-1))` with `c = R(p) / (p - conj(p))` and `|h_k| <= 2 |c| rho^(k-1)`.
/// The sum runs by the recursion until the terms' bound falls below `1e-17` of the sum and
/// shrinks by a ratio `q < 1` per step; the rest is bounded by the geometric series, and
/// `1e-12` relative is added for the rounding of a few thousand terms.
fn damped_pair_bound(num: &[f64], den: &[f64], m: f64) -> f64 {
    let (a0, a1) = (den[0], den[1]);
    let (n0, n1, n2) = (num[0], num[1], num[2]);
    // R = Fn - b0 Fd, with b0 = n2
    let (r0, r1) = (n0 - n2 * a0, n1 - n2 * a1);
    let disc = a1 * a1 - 4.0 * a0;
    let p = Complex::new(-a1 / 2.0, (-disc).max(0.0).sqrt() / 2.0);
    let rho = p.norm();
    let c = (Complex::new(r0, 0.0) + p * r1) / (p - p.conj());
    let amp = 2.0 * c.norm();
    // the recursion h_k = -a1 h_{k-1} - a0 h_{k-2} + (inputs), from the impulse
    let (mut h2, mut h1) = (0.0, 0.0);
    let mut sum = 0.0;
    for k in 0..100_000usize {
        let x = |j: usize| if k == j { 1.0 } else { 0.0 };
        let h = n2 * x(0) + n1 * x(1) + n0 * x(2) - a1 * h1 - a0 * h2;
        let mk = m + k as f64;
        sum += h.abs() * mk * mk;
        (h2, h1) = (h1, h);
        if k >= 2 {
            let bound = amp * rho.powi(k as i32) * (mk + 1.0) * (mk + 1.0);
            let q = rho * ((mk + 2.0) / (mk + 1.0)).powi(2);
            if q < 1.0 && bound < 1e-17 * sum {
                return (sum + bound / (1.0 - q)) * (1.0 + 1e-12);
            }
        }
    }
    // not reached for rho < 1 (a cutoff above 0): the bound falls below any fraction
    f64::INFINITY
}

/// Horner evaluation of `c` (lowest power first) at `z`.
fn eval(c: &[f64], z: Complex) -> Complex {
    c.iter()
        .rev()
        .fold(Complex::new(0.0, 0.0), |acc, &ck| acc * z + ck)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_dc_gain_and_recursions() {
        // F(1) = 1 for every filter, and the response matches the time-domain recursion's
        // steady state for a sampled sinusoid, computed independently here.
        let filters = [
            VelocityFilter::none(),
            VelocityFilter::low_pass(0.9).unwrap(),
            VelocityFilter::low_pass_cutoff(30.0, 1e-3).unwrap(),
            VelocityFilter::moving_average(1).unwrap(),
            VelocityFilter::moving_average(7).unwrap(),
            VelocityFilter::butterworth(0.03).unwrap(),
            VelocityFilter::low_pass_order(2, 200.0, 1e-3).unwrap(),
        ];
        for f in filters {
            let dc = f.response(0.0);
            assert!((dc.re - 1.0).abs() < 1e-14 && dc.im.abs() < 1e-14, "{f:?}");
            // Drive the filter with x_k = e^{i k theta} (its backward difference input is
            // (1 - e^{-i theta}) x_k) long enough for the transient to vanish.
            let theta = 0.7;
            let z = Complex::from_polar(1.0, theta);
            let (n, d) = (f.numerator(), f.denominator());
            let steps = 4000;
            let x: Vec<Complex> = (0..steps).map(|k| z.powf(k as f64)).collect();
            let diff: Vec<Complex> = (0..steps)
                .map(|k| if k == 0 { x[0] } else { x[k] - x[k - 1] })
                .collect();
            // Fd(q) w = Fn(q) diff, with q the forward shift; solve for the top term.
            let lead = d.len() - 1;
            let mut w = vec![Complex::new(0.0, 0.0); steps];
            for k in lead..steps {
                let mut acc = Complex::new(0.0, 0.0);
                for (j, nj) in n.iter().enumerate() {
                    acc += diff[k - lead + j] * *nj;
                }
                for (j, dj) in d.iter().enumerate().take(lead) {
                    acc -= w[k - lead + j] * *dj;
                }
                w[k] = acc;
            }
            let want = f.response(theta) * (Complex::new(1.0, 0.0) - z.inv()) * x[steps - 1];
            assert!((w[steps - 1] - want).norm() < 1e-9, "{f:?}");
        }
    }

    #[test]
    fn refuses_bad_values() {
        assert!(VelocityFilter::low_pass(1.0).is_err());
        assert!(VelocityFilter::low_pass(-0.1).is_err());
        assert!(VelocityFilter::low_pass(f64::NAN).is_err());
        assert!(VelocityFilter::moving_average(0).is_err());
        assert!(VelocityFilter::moving_average(MAX_MOVING_AVERAGE + 1).is_err());
        let err = VelocityFilter::low_pass_cutoff(600.0, 1e-3).unwrap_err();
        assert!(err.to_string().contains("Nyquist"), "{err}");
        assert!(VelocityFilter::low_pass_cutoff(0.0, 1e-3).is_err());
        assert!(VelocityFilter::low_pass_cutoff(500.0, 1e-3).is_ok());
        assert!(VelocityFilter::low_pass_order(2, 500.0, 1e-3).is_err());
        assert!(VelocityFilter::low_pass_order(3, 50.0, 1e-3).is_err());
        assert!(VelocityFilter::butterworth(0.0).is_err());
        assert!(VelocityFilter::butterworth(0.5).is_err());
    }
}
