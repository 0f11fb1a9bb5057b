//! Step responses of the sampled loop: exact simulation, between the samples too.
//!
//! The operator pushes with a constant force `F_H` from `t = 0` on; the wall force
//! `F_k = -(K x_k + B (x_k - x_{k-1}) / T)` is computed at each sample and reaches the device
//! after `d T` through a zero-order hold (`docs/MODEL.md` section 2). Because `F_H` is constant, on
//! every piece of a period where one held wall force acts the total force `F_wall + F_H` is
//! constant too, and the damped mass moves by the exact formulas
//!
//! ```text
//! v(tau) = c(tau) v0 + phi1(tau) f
//! x(tau) = x0 + phi1(tau) v0 + phi2(tau) f
//! ```
//!
//! (normalized time `tau = t / T`, normalized force `f = F T^2 / m`, velocity `v = T dx/dt`,
//! position in metres). With `d = n + eps` the wall force `F_{k-n-1}` acts for the first `eps`
//! of period `k` and `F_{k-n}` for the rest. So the position at any time is exact up to
//! rounding, with no integration step: this is the response of the paper's Fig. 11
//! (Hulin, Preusche, Hirzinger, IROS 2006, Section VIII), evaluated also between samples.
//!
//! The simulation runs the loop directly with a force history; it does not use
//! [`crate::model::Discretization::state_matrix`], which the tests use as the independent
//! reference at the sampling instants.
//!
//! A loop with elements (hand, compliant transmission, actuator lag, velocity filter; the
//! model document, docs/MODEL.md, section 8) is simulated by [`step_response`] exactly
//! too: each piece of a period is one augmented matrix-exponential step of the device with
//! the held wall force and the operator's force as its two constant inputs.

mod elements;

pub(crate) use elements::Estimate;

use std::collections::VecDeque;

use crate::elements::Loop;
use crate::error::{Error, Result};
use crate::model::{decay, phi1, phi2};
use crate::params::{Device, finite, positive};

/// The most points one response may hold (about 80 MB of output as CSV); longer requests are
/// refused with a message instead of exhausting memory.
pub const MAX_POINTS: usize = 5_000_000;

/// What to simulate besides the device and the wall.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct StepOptions {
    /// Operator force `F_H` in N, applied as a step at `t = 0`.
    pub force: f64,
    /// Simulated time in s from 0, rounded up to whole sampling periods.
    pub duration: f64,
    /// Points per sampling period (1 gives the sampling instants only).
    pub points_per_period: usize,
}

impl Default for StepOptions {
    /// 1 N for 50 ms with 10 points per period: the time scale of the paper's Fig. 11.
    fn default() -> Self {
        Self {
            force: 1.0,
            duration: 0.05,
            points_per_period: 10,
        }
    }
}

/// A simulated step response in physical units.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct StepResponse {
    /// Times in s, increasing, starting at 0.
    pub time: Vec<f64>,
    /// Position in m at each time (penetration into the wall): with a compliant
    /// transmission, the side the encoder reads.
    pub position: Vec<f64>,
    /// Positions at the sampling instants `t = k T`, `k = 0, 1, ...`.
    pub samples: Vec<f64>,
    /// Sampling period `T` in s.
    pub period: f64,
    /// The static deflection `F_H / K` the response tends to when the loop is stable (with a
    /// hand's stiffness, see [`step_response`]), `None` when no stiffness holds the
    /// device (`K = 0`: no static equilibrium).
    pub final_value: Option<f64>,
}

impl StepResponse {
    /// The response's first point, at rest at `t = 0`, with room for `periods` periods of
    /// `per` points each; no final value yet.
    fn at_rest(periods: usize, per: usize, period: f64) -> Self {
        let mut time = Vec::with_capacity(periods * per + 1);
        let mut position = Vec::with_capacity(periods * per + 1);
        let mut samples = Vec::with_capacity(periods + 1);
        time.push(0.0);
        position.push(0.0);
        samples.push(0.0);
        Self {
            time,
            position,
            samples,
            period,
            final_value: None,
        }
    }

    /// The settling time: the first time after which the position stays within
    /// `tolerance * |final|` of the final value (the static deflection) until the end of the simulation.
    ///
    /// `None` when there is no final value or the response has not settled by the end
    /// (an unstable wall, or too short a duration: the last point is outside the band).
    pub fn settling_time(&self, tolerance: f64) -> Option<f64> {
        let target = self.final_value?;
        let band = tolerance * target.abs();
        // NaN (a diverged response) counts as outside.
        let outside = |x: f64| x.is_nan() || (x - target).abs() > band;
        let last_out = self.position.iter().rposition(|&x| outside(x));
        match last_out {
            None => Some(0.0),
            Some(i) if i + 1 < self.time.len() => Some(self.time[i + 1]),
            Some(_) => None,
        }
    }

    /// The largest position reached (overshoot peak) in m.
    pub fn peak(&self) -> f64 {
        self.position
            .iter()
            .copied()
            .fold(f64::NEG_INFINITY, f64::max)
    }
}

/// Simulates the response of the loop `lp` (built in physical units, [`Loop::physical`]),
/// touching a wall of stiffness `stiffness` (N/m) and damping `wall_damping` (N s/m), to a
/// step of operator force.
///
/// Method: for the paper's loop, the exact piecewise solution of the damped mass under the
/// held, delayed wall force plus the constant operator force (module docs; `docs/MODEL.md`
/// section 2); for a loop with elements, one augmented matrix-exponential step per piece of a
/// period (`docs/MODEL.md` section 8; Van Loan, "Computing integrals involving the matrix
/// exponential", IEEE Trans. Automatic Control 23(3), 1978). The operator's force acts on the
/// mass the hand holds (the handle side of a transmission), never through the actuator; the
/// positions are the sensed position. The state starts at rest (no force in flight, the
/// filter's memory at zero). An unstable wall gives a growing response, not an error.
///
/// ```
/// use stabound::elements::{Loop, PhysicalElements};
/// use stabound::params::{Delay, Device};
/// use stabound::sim::{StepOptions, step_response};
///
/// let device = Device::new(0.1, 1e-3, 1.0, Delay::Samples(1.0))?;
/// // a hand of 50 g with 2 N s/m of damping and 100 N/m to ground
/// let mut hand = PhysicalElements::default();
/// (hand.hand_mass, hand.hand_damping, hand.hand_stiffness) = (Some(0.05), Some(2.0), Some(100.0));
/// let lp = Loop::physical(&device, &hand)?;
/// let options = StepOptions { duration: 0.5, ..StepOptions::default() };
/// let r = step_response(&lp, 2000.0, 10.0, &options)?;
/// let want = 1.0 / (2000.0 + 100.0);
/// assert!((r.final_value.unwrap() - want).abs() < 1e-12 * want);
/// assert!((r.samples.last().unwrap() - want).abs() < 1e-6 * want);
/// // the free device settles at F_H / K
/// let free = Loop::physical(&device, &PhysicalElements::default())?;
/// let r = step_response(&free, 2000.0, 10.0, &options)?;
/// assert!((r.final_value.unwrap() - 1.0 / 2000.0).abs() < 1e-15);
/// # Ok::<(), stabound::Error>(())
/// ```
///
/// # Errors
///
/// A loop built in normalized units (it has no device); invalid wall values, `duration` not
/// positive, `points_per_period` zero, or more than [`MAX_POINTS`] points requested;
/// [`Error::Numerical`] if a matrix exponential is not finite (the element limits are there
/// to exclude it).
pub fn step_response(
    lp: &Loop,
    stiffness: f64,
    wall_damping: f64,
    options: &StepOptions,
) -> Result<StepResponse> {
    let device = lp.device().ok_or_else(|| {
        Error::InvalidRequest(
            "a step response needs the loop's physical device (mass, period, damping, delay): build the loop with Loop::physical".into(),
        )
    })?;
    if lp.is_paper() {
        paper_step_response(device, stiffness, wall_damping, options)
    } else {
        elements::general_step_response(device, lp, stiffness, wall_damping, options)
    }
}

/// The paper's loop's step response on its closed forms (see [`step_response`]).
fn paper_step_response(
    device: &Device,
    stiffness: f64,
    wall_damping: f64,
    options: &StepOptions,
) -> Result<StepResponse> {
    let plant = device.plant()?;
    let wall = device.wall(stiffness, wall_damping)?;
    let periods = periods(device, options)?;
    let per = options.points_per_period;

    let delta = plant.delta();
    let n = plant.whole_samples();
    let eps = plant.fraction();
    let (alpha, beta) = (wall.alpha(), wall.beta());
    // Normalized operator force f_H = F_H T^2 / m (in metres, like the position).
    let f_h = options.force * device.period() * device.period() / device.mass();

    // The wall forces computed so far, newest first, zero before the start. After the push at
    // sample k, history[j] = f_{k-j}; n + 2 entries hold f_{k-n} and f_{k-n-1}.
    let mut history: VecDeque<f64> = std::iter::repeat_n(0.0, n + 2).collect();
    let (mut x, mut v, mut x_prev) = (0.0f64, 0.0f64, 0.0f64);

    let mut r = StepResponse::at_rest(periods, per, device.period());
    for k in 0..periods {
        // Wall force computed at sample k from x_k and x_{k-1} (normalized).
        let f_now = -(alpha * x + beta * (x - x_prev));
        history.push_front(f_now);
        history.pop_back();
        // history[j] is now f_{k-j}.
        let f_late = history[n] + f_h; // f_{k-n}, acts on [eps, 1)
        let f_early = history[n + 1] + f_h; // f_{k-n-1}, acts on [0, eps)
        // State at tau = eps.
        let (x_e, v_e) = (
            x + phi1(delta, eps) * v + phi2(delta, eps) * f_early,
            decay(delta, eps) * v + phi1(delta, eps) * f_early,
        );
        let t0 = k as f64;
        for i in 1..=per {
            let tau = i as f64 / per as f64;
            let xi = if tau <= eps {
                x + phi1(delta, tau) * v + phi2(delta, tau) * f_early
            } else {
                let s = tau - eps;
                x_e + phi1(delta, s) * v_e + phi2(delta, s) * f_late
            };
            r.time.push((t0 + tau) * device.period());
            r.position.push(xi);
        }
        let rest = 1.0 - eps;
        let x_next = x_e + phi1(delta, rest) * v_e + phi2(delta, rest) * f_late;
        let v_next = decay(delta, rest) * v_e + phi1(delta, rest) * f_late;
        x_prev = x;
        x = x_next;
        v = v_next;
        r.samples.push(x);
    }
    r.final_value = (stiffness.abs() > 0.0).then(|| options.force / stiffness);
    Ok(r)
}

/// The whole periods `options` asks for on `device`, after checking the force, the
/// duration, the points per period and the [`MAX_POINTS`] cap.
fn periods(device: &Device, options: &StepOptions) -> Result<usize> {
    finite("force", options.force)?;
    positive("duration", options.duration)?;
    if options.points_per_period == 0 {
        return Err(Error::InvalidRequest(
            "points per period must be at least 1".into(),
        ));
    }
    let periods_f = (options.duration / device.period()).ceil();
    let per = options.points_per_period;
    // periods_f may be infinite for absurd ratios; the comparison rejects that too.
    if periods_f * per as f64 + 1.0 > MAX_POINTS as f64 {
        return Err(Error::InvalidRequest(format!(
            "a duration of {} s at a period of {} s with {per} points per period needs more than {MAX_POINTS} points; shorten the duration or lower the points per period",
            options.duration,
            device.period()
        )));
    }
    Ok(periods_f as usize)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::PaperDiscretization;
    use crate::params::{Delay, Wall};
    use approx::assert_relative_eq;
    use nalgebra::DVector;

    /// The step response of the paper's loop on `dev`.
    fn step_response(
        dev: &Device,
        stiffness: f64,
        wall_damping: f64,
        options: &StepOptions,
    ) -> Result<StepResponse> {
        let lp = Loop::physical(dev, &crate::elements::PhysicalElements::default())?;
        super::step_response(&lp, stiffness, wall_damping, options)
    }

    fn device(damping: f64, d: f64) -> Device {
        Device {
            mass: 0.1,
            period: 1e-3,
            damping,
            delay: Delay::Samples(d),
        }
    }

    /// At the sampling instants the simulation equals iterating the closed-loop state matrix
    /// (built independently in `model`) plus the operator force's input column
    /// `[phi2(1), phi1(1), 0, ...]` (a constant force over the whole period).
    #[test]
    fn samples_match_state_matrix_iteration() {
        for &(b, d) in &[
            (0.0, 0.0),
            (0.0, 1.0),
            (10.0, 1.0),
            (100.0, 0.0),
            (30.0, 0.25),
            (5.0, 1.5),
            (250.0, 3.0),
            (0.0, 2.75),
        ] {
            let dev = device(b, d);
            let (k, bw) = (5000.0, 30.0);
            let opts = StepOptions {
                force: 2.0,
                duration: 0.06,
                points_per_period: 3,
            };
            let r = step_response(&dev, k, bw, &opts).unwrap();
            let plant = dev.plant().unwrap();
            let wall: Wall = dev.wall(k, bw).unwrap();
            let disc = PaperDiscretization::new(&plant);
            let a = disc.state_matrix(&wall);
            let dim = disc.state_dim();
            let mut input = DVector::<f64>::zeros(dim);
            input[0] = phi2(plant.delta(), 1.0);
            input[1] = phi1(plant.delta(), 1.0);
            let f_h = opts.force * dev.period * dev.period / dev.mass;
            let mut s = DVector::<f64>::zeros(dim);
            let scale = r.samples.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            assert_eq!(r.samples.len(), 61);
            for (i, &x) in r.samples.iter().enumerate() {
                // Both are O(60) steps of well-conditioned affine updates: rounding stays
                // below 1e-12 of the response's size.
                assert!(
                    (x - s[0]).abs() <= 1e-12 * scale,
                    "b {b} d {d} sample {i}: {x} vs {}",
                    s[0]
                );
                s = &a * &s + &input * f_h;
            }
            // The dense output passes through every sample.
            for (i, &x) in r.samples.iter().enumerate() {
                assert_eq!(r.position[i * 3], x);
                assert_relative_eq!(r.time[i * 3], i as f64 * 1e-3, max_relative = 1e-12);
            }
        }
    }

    /// Between the samples: a fine classical Runge-Kutta integration of the continuous
    /// `m x'' = F_wall(t) + F_H - b x'` with the held, delayed wall force (the force at each
    /// sample from the integrated positions) must agree with the exact formulas.
    #[test]
    fn between_samples_match_runge_kutta() {
        for &(b, d) in &[(10.0, 1.5), (0.0, 0.5), (100.0, 1.0)] {
            let dev = device(b, d);
            let (k, bw) = (20000.0, 20.0);
            let per = 10;
            let opts = StepOptions {
                force: 1.0,
                duration: 0.02,
                points_per_period: per,
            };
            let r = step_response(&dev, k, bw, &opts).unwrap();
            let (m, t) = (dev.mass, dev.period);
            let n = d.floor() as usize;
            let eps = d - d.floor();
            let sub = 40; // RK steps per output interval
            let h = t / (per * sub) as f64;
            let (mut x, mut v) = (0.0f64, 0.0f64);
            let mut forces: Vec<f64> = Vec::new();
            let mut x_prev = 0.0;
            let mut worst = 0.0f64;
            for period in 0..20 {
                forces.push(-(k * x + bw * (x - x_prev) / t));
                x_prev = x;
                let held = |j: isize| {
                    if j < 0 { 0.0 } else { forces[j as usize] }
                };
                let late = held(period as isize - n as isize);
                let early = held(period as isize - n as isize - 1);
                for i in 0..per {
                    for s in 0..sub {
                        let tau = (i * sub + s) as f64 / (per * sub) as f64;
                        // eps is a multiple of 1/per here, so no step straddles the switch.
                        let f = if tau < eps { early } else { late } + opts.force;
                        let acc = |v: f64| (f - b * v) / m;
                        let (k1x, k1v) = (v, acc(v));
                        let (k2x, k2v) = (v + 0.5 * h * k1v, acc(v + 0.5 * h * k1v));
                        let (k3x, k3v) = (v + 0.5 * h * k2v, acc(v + 0.5 * h * k2v));
                        let (k4x, k4v) = (v + h * k3v, acc(v + h * k3v));
                        x += h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
                        v += h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
                    }
                    let exact = r.position[period * per + i + 1];
                    worst = worst.max((exact - x).abs());
                }
            }
            let scale = r.position.iter().fold(0.0f64, |a, x| a.max(x.abs()));
            // RK4 with h = T/400 on dynamics of time scale >= 0.7 ms: local error ~ (h w)^5,
            // global well under 1e-8 of the response's size.
            assert!(worst <= 1e-8 * scale, "b {b} d {d}: {worst} vs {scale}");
        }
    }

    /// No wall (K = B = 0): the free damped mass under a constant force has the closed form
    /// x(t) = (F/b) (t - (m/b)(1 - exp(-b t / m))), and F t^2 / (2 m) for b = 0.
    #[test]
    fn free_mass_closed_form() {
        for &b in &[0.0, 10.0, 100.0] {
            let dev = device(b, 1.0);
            let opts = StepOptions {
                force: 3.0,
                duration: 0.01,
                points_per_period: 7,
            };
            let r = step_response(&dev, 0.0, 0.0, &opts).unwrap();
            assert!(r.final_value.is_none());
            for (&t, &x) in r.time.iter().zip(&r.position) {
                let m = dev.mass;
                // `b` is a literal test input; exactly zero selects the undamped closed form
                let want = if b == 0.0 {
                    3.0 * t * t / (2.0 * m)
                } else {
                    3.0 / b * (t - m / b * (1.0 - (-b * t / m).exp()))
                };
                assert_relative_eq!(x, want, max_relative = 1e-10, epsilon = 1e-18);
            }
        }
    }

    /// The response of a stable wall ends at the static deflection F_H / K.
    #[test]
    fn final_value_is_force_over_stiffness() {
        for &(b, d, k, bw) in &[(0.0, 1.0, 10_000.0, 40.0), (50.0, 0.5, 30_000.0, 10.0)] {
            let dev = device(b, d);
            let opts = StepOptions {
                force: 1.5,
                duration: 0.5,
                points_per_period: 1,
            };
            let r = step_response(&dev, k, bw, &opts).unwrap();
            let want = 1.5 / k;
            assert_relative_eq!(r.final_value.unwrap(), want, max_relative = 1e-15);
            // After 0.5 s (hundreds of decay times of these well-damped walls) the transient
            // is below 1e-9 of the deflection.
            assert_relative_eq!(*r.samples.last().unwrap(), want, max_relative = 1e-9);
            assert!(r.settling_time(0.02).unwrap() < 0.1);
        }
    }

    /// Paper Section VIII / Fig. 11: d = 1, m = 0.1 kg, T = 1 ms, b = 0, 10, 100 N s/m with
    /// the published walls (alpha, beta) = (0.108, 0.425), (0.149, 0.416), (0.656, 0.388):
    /// the highly damped system settles fastest, although its wall is six times stiffer.
    #[test]
    fn paper_fig11_highly_damped_settles_fastest() {
        let cases = [
            (0.0, 0.108, 0.425),
            (10.0, 0.149, 0.416),
            (100.0, 0.656, 0.388),
        ];
        let mut settle = Vec::new();
        for &(b, alpha, beta) in &cases {
            let dev = device(b, 1.0);
            let r = step_response(
                &dev,
                dev.stiffness(alpha),
                dev.wall_damping(beta),
                &StepOptions {
                    duration: 0.2,
                    ..StepOptions::default()
                },
            )
            .unwrap();
            settle.push(r.settling_time(0.02).unwrap());
        }
        assert!(settle[2] < settle[0] && settle[2] < settle[1], "{settle:?}");
    }

    #[test]
    fn rejects_bad_requests() {
        let dev = device(0.0, 1.0);
        let o = StepOptions {
            points_per_period: 0,
            ..StepOptions::default()
        };
        assert!(matches!(
            step_response(&dev, 1.0, 0.0, &o),
            Err(Error::InvalidRequest(_))
        ));
        let o = StepOptions {
            duration: 1e6,
            ..StepOptions::default()
        };
        assert!(matches!(
            step_response(&dev, 1.0, 0.0, &o),
            Err(Error::InvalidRequest(_))
        ));
        let o = StepOptions {
            duration: -1.0,
            ..StepOptions::default()
        };
        assert!(step_response(&dev, 1.0, 0.0, &o).is_err());
        assert!(step_response(&dev, f64::NAN, 0.0, &StepOptions::default()).is_err());
    }
}
