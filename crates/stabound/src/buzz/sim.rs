//! The exact simulation of the nonlinear sampled loop (the model document, docs/MODEL.md,
//! section 10.1).
//!
//! Normalized units: time in samples, positions in counts, forces as `F T^2 / (m Delta_x)`.
//! At each sample `k` the encoder reads `y_k = round(x_k)` (mid-tread; the exact position
//! without an encoder), the wall computes `u_k = -(alpha y_k + beta w_k)` (`w` the loop's
//! velocity estimate of the readings; the backward difference `y_k - y_{k-1}` on the
//! paper's loop) and the output holds `Delta_u round(u_k / Delta_u)`. With `d = n + eps`
//! the held force `u_{k-n-1}` acts for the first `eps` of period `k` and `u_{k-n}` for the
//! rest.
//!
//! Between two force changes the damped mass with Coulomb friction obeys
//! `v' = f - delta v - phi sign(v)`: while it slides in one direction this is linear with
//! the constant force `f - phi sign(v)`, so its motion is the closed form of section 2
//! (`v(tau) = c(tau) v0 + phi1(tau) f_eff`, `x(tau) = x0 + phi1(tau) v0 + phi2(tau) f_eff`).
//! The velocity reaches zero inside a piece only when `f_eff` opposes the motion, and then
//! at the one root of `c(tau) v0 + phi1(tau) f_eff = 0`,
//! `tau0 = log(1 - delta v0 / f_eff) / delta` (`-v0 / f_eff` at `delta = 0`): the event is
//! located in closed form, not by an integration step. At zero velocity the mass sticks while
//! the applied force is at most the static friction, and otherwise breaks away in the
//! force's direction (where the velocity cannot return to zero within the piece, since the
//! force beyond friction accelerates it monotonically).
//!
//! A velocity filter acts only on the wall's estimate: with it the device is still the
//! single damped mass above. Loops with a hand, a transmission or an actuator lag advance,
//! without friction, by their exact discretization ([`crate::model::Discretization`]):
//! the quantizers act only at the samples, so between them the device is the linear one;
//! with friction, by the event-located exact pieces of the friction module (the friction on
//! the mass the commanded force drives).

use std::collections::VecDeque;

use nalgebra::DVector;

use super::friction::FrictionDevice;
use super::{DIVERGED, Quantization, Start};
use crate::elements::{Continuous, GeneralDiscretization, Loop};
use crate::error::{Error, Result};
use crate::model::{decay, phi1, phi2};
use crate::params::Wall;
use crate::sim::Estimate;

/// The damped mass with Coulomb and static friction, normalized.
#[derive(Debug, Clone, Copy)]
struct Mass {
    delta: f64,
    coulomb: f64,
    stiction: f64,
}

/// Position (counts) and velocity (counts per sample); a velocity of exactly zero means the
/// mass is at rest (stuck or about to break away), as the event location sets it.
#[derive(Debug, Clone, Copy)]
struct State {
    x: f64,
    v: f64,
}

impl Mass {
    /// The motion over `tau` under the constant force `f` with no friction switching.
    fn free(&self, s: State, f: f64, tau: f64) -> State {
        State {
            x: s.x + phi1(self.delta, tau) * s.v + phi2(self.delta, tau) * f,
            v: decay(self.delta, tau) * s.v + phi1(self.delta, tau) * f,
        }
    }

    /// The time the velocity `v0` reaches zero under `f_eff` opposing it (closed form).
    fn stop_time(&self, v0: f64, f_eff: f64) -> f64 {
        // exact: delta = 0 is the undamped mass, whose closed form differs
        if self.delta == 0.0 {
            -v0 / f_eff
        } else {
            (-self.delta * v0 / f_eff).ln_1p() / self.delta
        }
    }

    /// The exact motion over `tau` under the applied force `f`, with stick and slip.
    fn advance(&self, s: State, f: f64, tau: f64) -> State {
        if self.stiction <= 0.0 {
            return self.free(s, f, tau);
        }
        let mut s = s;
        let mut left = tau;
        // At most two passes: slide to a stop, then stick or break away.
        loop {
            // exact: zero velocity is only ever set, never computed
            if s.v == 0.0 {
                if f.abs() <= self.stiction {
                    return s;
                }
                return self.free(s, f - self.coulomb * f.signum(), left);
            }
            let f_eff = f - self.coulomb * s.v.signum();
            if f_eff * s.v < 0.0 {
                let t0 = self.stop_time(s.v, f_eff);
                if t0 < left {
                    s = State {
                        x: self.free(s, f_eff, t0).x,
                        v: 0.0,
                    };
                    left -= t0;
                    continue;
                }
            }
            return self.free(s, f_eff, left);
        }
    }
}

/// The quantizers of `q`: reading and held force.
struct Quantizers {
    encoder: bool,
    step: f64,
}

impl Quantizers {
    fn read(&self, x: f64) -> f64 {
        if self.encoder { x.round() } else { x }
    }

    fn hold(&self, u: f64) -> f64 {
        if self.step > 0.0 {
            self.step * (u / self.step).round()
        } else {
            u
        }
    }
}

/// The readings `y_0, ..., y_samples` (counts) of the loop `lp` on `wall` with the quantizers
/// and friction `q`, from `start`: the exact simulation of the module doc. The run stops
/// early (fewer readings) when the motion passes [`DIVERGED`] counts.
///
/// ```
/// use stabound::buzz::{Quantization, Start, readings};
/// use stabound::params::{Plant, Wall};
///
/// // d = 1, delta = 0.1, an encoder and Coulomb friction of 0.05 (normalized).
/// let q = Quantization::new(true, 0.0, 0.05, 0.0)?;
/// let y = readings(&Plant::new(0.1, 1.0)?, &Wall::new(0.1, 0.2)?, &q, Start::Rest(3.0), 200)?;
/// assert_eq!(y.len(), 201);
/// assert_eq!(y[0], 3.0);
/// assert!(y.iter().all(|v| v.fract() == 0.0));
/// # Ok::<(), stabound::Error>(())
/// ```
///
/// # Errors
///
/// [`Error::InvalidRequest`] for a non-finite start or too many samples; as
/// [`crate::model::Discretization::new`]; [`Error::Numerical`] when the device's matrix exponential is
/// not finite.
pub fn readings(
    lp: impl Into<Loop>,
    wall: &Wall,
    q: &Quantization,
    start: Start,
    samples: usize,
) -> Result<Vec<f64>> {
    let lp = lp.into();
    let (x0, v0) = start.state();
    crate::params::finite("start position", x0)?;
    crate::params::finite("impact velocity", v0)?;
    if samples > super::MAX_SAMPLES {
        return Err(Error::InvalidRequest(format!(
            "a buzz run takes at most {} samples",
            super::MAX_SAMPLES
        )));
    }
    let quant = Quantizers {
        encoder: q.encoder,
        step: q.force_step,
    };
    let plant = lp.plant();
    let n = plant.whole_samples();
    let eps = plant.fraction();
    let (alpha, beta) = (wall.alpha(), wall.beta());
    let mut out = Vec::with_capacity(samples + 1);
    out.push(quant.read(x0));
    // The held forces, newest first, zero before the start: after the push at sample k,
    // history[j] = u_{k-j}.
    let mut history: VecDeque<f64> = std::iter::repeat_n(0.0, n + 2).collect();
    let mut estimate = Estimate::resting_at(lp.filter(), out[0]);
    let mut force = |y: f64| {
        let w = estimate.next(y);
        history.push_front(quant.hold(-(alpha * y + beta * w)));
        history.pop_back();
        (history[n + 1], history[n])
    };
    let diverged = |x: f64| !x.is_finite() || x.abs() > DIVERGED;
    // the device is the single damped mass (a velocity filter acts only on the estimate)
    let plain = lp.hand().is_none() && lp.transmission().is_none() && lp.actuator().is_none();
    if plain {
        let mass = Mass {
            delta: plant.delta(),
            coulomb: q.coulomb,
            stiction: q.stiction,
        };
        let mut s = State { x: x0, v: v0 };
        for k in 0..samples {
            let (early, late) = force(out[k]);
            if eps > 0.0 {
                s = mass.advance(s, early, eps);
            }
            s = mass.advance(s, late, 1.0 - eps);
            if diverged(s.x) {
                break;
            }
            out.push(quant.read(s.x));
        }
        return Ok(out);
    }
    let mut x = initial_state(&lp, x0, v0);
    if q.has_friction() {
        let dev = FrictionDevice::new(&lp, q.coulomb, q.stiction, &[eps, 1.0 - eps])?;
        let c = Continuous::new(&lp).c;
        for k in 0..samples {
            let (early, late) = force(out[k]);
            if eps > 0.0 {
                x = dev.advance(x, early, eps);
            }
            x = dev.advance(x, late, 1.0 - eps);
            let y = c.dot(&x);
            if diverged(y) {
                break;
            }
            out.push(quant.read(y));
        }
        return Ok(out);
    }
    let disc = GeneralDiscretization::new(&lp)?;
    for k in 0..samples {
        let (early, late) = force(out[k]);
        x = disc.phi() * &x + disc.g0() * late + disc.g1() * early;
        let y = disc.output().dot(&x);
        if diverged(y) {
            break;
        }
        out.push(quant.read(y));
    }
    Ok(out)
}

/// Every mass of `lp`'s device at `x0` moving at `v0`, no actuator force: states
/// `(y, v)` or `(x1, v1, x2, v2)`, then the lag's force.
fn initial_state(lp: &Loop, x0: f64, v0: f64) -> DVector<f64> {
    let mut x = DVector::zeros(lp.device_order());
    let masses = if lp.transmission().is_some() { 2 } else { 1 };
    for i in 0..masses {
        x[2 * i] = x0;
        x[2 * i + 1] = v0;
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The closed-form stop time is where the closed-form velocity vanishes.
    #[test]
    fn stop_time_zeroes_velocity() {
        for &delta in &[0.0, 1e-9, 0.1, 3.0] {
            let m = Mass {
                delta,
                coulomb: 0.0,
                stiction: 0.0,
            };
            for &(v0, f) in &[(1.0, -0.3), (-2.0, 0.7), (0.01, -5.0)] {
                let t = m.stop_time(v0, f);
                let v = m.free(State { x: 0.0, v: v0 }, f, t).v;
                // rounding of a few operations on O(1) values
                assert!(v.abs() < 1e-14 * v0.abs().max(1.0), "{delta} {v0} {f}: {v}");
            }
        }
    }

    /// Stuck while the force is within the static friction; breakaway beyond it.
    #[test]
    fn stick_and_breakaway() {
        let m = Mass {
            delta: 0.1,
            coulomb: 0.2,
            stiction: 0.3,
        };
        let s = State { x: 2.0, v: 0.0 };
        let stuck = m.advance(s, -0.29, 1.0);
        assert_eq!((stuck.x, stuck.v), (2.0, 0.0));
        let moved = m.advance(s, -0.31, 1.0);
        assert!(moved.v < 0.0 && moved.x < 2.0);
        // net force after breakaway: the applied force less the sliding friction (the same
        // arithmetic, so the same bits)
        let want = m.free(s, -0.31 + 0.2, 1.0);
        assert_eq!((moved.x, moved.v), (want.x, want.v));
    }
}
