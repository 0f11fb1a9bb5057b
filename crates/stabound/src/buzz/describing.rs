//! The describing-function prediction of encoder limit cycles on the loop's own boundary
//! (the model document, docs/MODEL.md, sections 10.1 and 10.2).
//!
//! A mid-tread quantizer driven by `a sin` passes its first harmonic with the gain `N_q(a)`
//! ([`quantizer_gain`]). Put before the wall law it scales both wall gains, so harmonic
//! balance asks where the ray `(s alpha, s beta)`, `s > 0`, crosses the stability boundary:
//! on the ray `q(z) = Q0(z) + s (alpha QA(z) + beta QB(z))`, affine in `s`, and its crossings
//! are found exactly as the one-dimensional searches find theirs (the roots on the unit
//! circle of `S = P D* - P* D`, see [`crate::search`]). A crossing at gain `s` and frequency
//! `theta` predicts a limit cycle of amplitude `a` wherever `N_q(a) = s`; Loeb's criterion
//! decides whether it is sustained (a small growth of `a` must move the gain back into the
//! stable side) or a threshold.
//!
//! This is an approximation (it ignores the harmonics and the phase at which the samples
//! meet the quantizer): a fast first estimate beside the exact simulation ([`super::buzz`]),
//! never the verdict. It covers the encoder; force steps and friction are left to the
//! simulation.

use std::f64::consts::PI;

use crate::elements::Loop;
use crate::error::Result;
use crate::params::Wall;
use crate::stability::{Checker, Options};

/// The largest quantizer gain, `4 / pi`, reached at `a = 1 / sqrt 2`.
const MAX_GAIN: f64 = 4.0 / PI;

/// Amplitudes are searched up to this many counts: beyond it `N_q` is within about
/// `a^{-3/2} < 1e-3` of 1, which only a wall within `1e-3` of the boundary would meet.
const MAX_AMPLITUDE: f64 = 100.0;

/// Grid points per step of the quantizer when bracketing `N_q(a) = s` (quadratic spacing from
/// each step's start, where `N_q` has a square-root edge).
const GRID: usize = 64;

/// The describing function of the mid-tread quantizer `round(x)` for the input `a sin`
/// (`a` in counts): `0` for `a < 1/2`, and for `k - 1/2 <= a < k + 1/2`,
/// `N_q(a) = (4 / (pi a)) sum_{i=1..k} sqrt(1 - ((2i - 1) / (2a))^2)`.
///
/// ```
/// use stabound::buzz::quantizer_gain;
///
/// assert_eq!(quantizer_gain(0.4), 0.0);
/// let top = quantizer_gain(1.0 / 2f64.sqrt());
/// assert!((top - 4.0 / std::f64::consts::PI).abs() < 1e-12);
/// assert!((quantizer_gain(1000.0) - 1.0).abs() < 1e-3);
/// ```
pub fn quantizer_gain(a: f64) -> f64 {
    if !a.is_finite() || a < 0.5 {
        return 0.0;
    }
    let k = (a + 0.5).floor() as usize;
    let sum: f64 = (1..=k)
        .map(|i| {
            let r = (2 * i - 1) as f64 / (2.0 * a);
            (1.0 - r * r).max(0.0).sqrt()
        })
        .sum();
    4.0 / (PI * a) * sum
}

/// Where the ray through the wall crosses the stability boundary.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub struct Crossing {
    /// The gain `s` on the ray: the wall `(s alpha, s beta)` has a root on the unit circle.
    pub gain: f64,
    /// The root's frequency `theta` (radians per sample; `pi` is a period-2 oscillation).
    pub theta: f64,
    /// Whether the ray leaves the stable region here (stable just below `s`, not above).
    pub leaves: bool,
}

/// A limit cycle the describing function predicts.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub struct LimitCycle {
    /// Amplitude in counts, a solution of `N_q(a) = s`.
    pub amplitude_counts: f64,
    /// Its frequency `theta` (radians per sample).
    pub theta: f64,
    /// Sustained (Loeb's criterion holds) or a threshold (motions below it decay, above it
    /// grow, or the reverse).
    pub sustained: bool,
}

/// The describing-function prediction for one wall.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub struct DescribingFunction {
    /// The ray margin `s*`: the smallest gain at which the ray leaves the stable region
    /// (`None` if it never does).
    pub ray_margin: Option<f64>,
    /// The frequency of the crossing at `s*`.
    pub theta: Option<f64>,
    /// Every stability change on the ray with a gain in `(0, 4/pi]`.
    pub crossings: Vec<Crossing>,
    /// The limit cycles those crossings predict, amplitudes up to 100 counts.
    pub cycles: Vec<LimitCycle>,
}

impl DescribingFunction {
    /// Whether a sustained limit cycle is predicted.
    pub fn predicts_buzz(&self) -> bool {
        self.cycles.iter().any(|c| c.sustained)
    }

    /// The largest sustained amplitude predicted, in counts.
    pub fn amplitude_counts(&self) -> Option<f64> {
        self.cycles
            .iter()
            .filter(|c| c.sustained)
            .map(|c| c.amplitude_counts)
            .reduce(f64::max)
    }
}

/// The describing-function prediction (the model document, section 10.2) for `wall` on the
/// loop `lp` with an encoder: the exact crossings of the ray through the wall with the
/// stability boundary, and the amplitudes where the quantizer's gain meets them.
///
/// ```
/// use stabound::buzz::describing_function;
/// use stabound::params::{Plant, Wall};
/// use stabound::search::alpha_limit;
/// use stabound::stability::{Checker, Options};
///
/// let plant = Plant::new(0.1, 1.0)?;
/// // a wall at 80 % of the stiffness limit at its damping: s* = 1.25 < 4/pi
/// let beta = 0.3;
/// let limit = alpha_limit(&Checker::new(&plant, Options::default())?, beta)?.unwrap();
/// let df = describing_function(&plant, &Wall::new(0.8 * limit, 0.8 * beta)?)?;
/// let s = df.ray_margin.unwrap();
/// assert!(s > 1.0 && s < 4.0 / std::f64::consts::PI);
/// assert!(df.predicts_buzz());
/// # Ok::<(), stabound::Error>(())
/// ```
///
/// # Errors
///
/// As [`Checker::new`] and the polynomial root finder.
pub fn describing_function(lp: impl Into<Loop>, wall: &Wall) -> Result<DescribingFunction> {
    let checker = Checker::new(lp.into(), Options::default())?;
    let [q0, qa, qb] = checker.affine();
    let d: Vec<f64> = qa
        .iter()
        .zip(&qb)
        .map(|(a, b)| wall.alpha() * a + wall.beta() * b)
        .collect();
    let on_ray = |s: f64| checker.is_stable(&Wall::new(s * wall.alpha(), s * wall.beta())?);
    let mut crossings = Vec::new();
    let mut ray_margin = None;
    let mut theta = None;
    for (s, th) in crate::search::crossings(&q0, &d)? {
        if s <= 0.0 {
            continue;
        }
        // one part in 1e6 either side: far above the 1e-9 marginal band, far below the gap
        // between two crossings of a ray
        let (below, above) = (on_ray(s * (1.0 - 1e-6))?, on_ray(s * (1.0 + 1e-6))?);
        if below == above {
            continue;
        }
        if below && ray_margin.is_none() {
            ray_margin = Some(s);
            theta = Some(th);
        }
        if s <= MAX_GAIN {
            crossings.push(Crossing {
                gain: s,
                theta: th,
                leaves: below,
            });
        }
    }
    let cycles = crossings
        .iter()
        .flat_map(|c| {
            amplitudes(c.gain)
                .into_iter()
                .map(|(a, rising)| LimitCycle {
                    amplitude_counts: a,
                    theta: c.theta,
                    // Loeb: growing a must move the gain to the stable side of the crossing
                    sustained: rising != c.leaves,
                })
        })
        .collect();
    Ok(DescribingFunction {
        ray_margin,
        theta,
        crossings,
        cycles,
    })
}

/// The solutions `a` of `N_q(a) = s` up to [`MAX_AMPLITUDE`], each with whether `N_q` rises
/// there: bracketed on a grid within each step of the quantizer and refined by Brent's
/// method.
fn amplitudes(s: f64) -> Vec<(f64, bool)> {
    let mut out = Vec::new();
    let g = |a: f64| quantizer_gain(a) - s;
    let mut k = 0.5;
    while k < MAX_AMPLITUDE {
        // inside [k, k + 1) N_q is smooth; at k it has a square-root edge
        let point = |i: usize| {
            let t = i as f64 / GRID as f64;
            k + t * t * (1.0 - 1e-12)
        };
        let mut prev = (point(0), g(point(0)));
        for i in 1..=GRID {
            let a = point(i);
            let now = g(a);
            if prev.1 * now < 0.0 {
                // to 1e-12 counts: far below anything the simulation resolves
                let root = crate::roots::brent(&g, prev.0, a, 1e-12);
                out.push((root, prev.1 < 0.0));
            }
            prev = (a, now);
        }
        k += 1.0;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The gain's documented landmarks: its maximum `4/pi` at `1/sqrt 2`, the dip to about
    /// 0.80 just below `3/2`, and the value from a direct Fourier integral of the staircase.
    #[test]
    fn quantizer_gain_landmarks() {
        let dip = quantizer_gain(1.5 - 1e-9);
        assert!((dip - 0.80).abs() < 0.01, "{dip}");
        for &a in &[0.6, 0.9, 1.7, 2.2, 3.49, 7.3] {
            // first-harmonic coefficient (2/pi) int_0^pi round(a sin t) sin t dt / a by the
            // midpoint rule on 2e5 points: the staircase's jumps cost O(1/n) of accuracy
            let n = 200_000;
            let h = PI / n as f64;
            let integral: f64 = (0..n)
                .map(|i| {
                    let t = (i as f64 + 0.5) * h;
                    (a * t.sin()).round() * t.sin()
                })
                .sum::<f64>()
                * h;
            let want = 2.0 / PI * integral / a;
            assert!(
                (quantizer_gain(a) - want).abs() < 1e-4,
                "{a}: {} vs {want}",
                quantizer_gain(a)
            );
        }
    }
}
