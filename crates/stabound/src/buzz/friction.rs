//! Coulomb and static friction on a device with elements (hand, transmission, actuator lag):
//! the continuous states integrated exactly between events (the model document,
//! docs/MODEL.md, section 10.1).
//!
//! The friction acts on the mass the commanded force drives (the device's mass with the
//! hand's when a hand is named, the motor side of a transmission): in the continuous model
//! `x' = A x + b u + e_f f` ([`Continuous`], states `(y, v, ...)`), `e_f` one over that mass
//! on its velocity `v = x[1]`. While the mass slides in direction `s` the friction is the
//! constant `-phi s`, so the motion over a piece is the exact map of one augmented matrix
//! exponential (Van Loan 1978, as [`crate::elements::LoopDiscretization`]). While it sticks,
//! its position and velocity are held (their rows of `A` are zero) and the rest of the
//! device moves on; it breaks away when the net force on it, `(A[1,:] x + b[1] u) / e_f[1]`,
//! exceeds the static friction.
//!
//! Events are located inside the period: each piece of constant held force is cut into
//! [`SUBSTEPS`] equal steps; a step whose end has the velocity's sign reversed (sliding) or
//! the net force beyond the static friction (stuck) holds an event, found by the Illinois
//! variant of regula falsi on the exact map at the trial time (a root of a smooth scalar
//! function: bracket and refine). An event whose function returns to its sign within one
//! step (two velocity zeros closer than `1 / SUBSTEPS` of a sample) is not seen.

use nalgebra::{DMatrix, DVector};

use crate::elements::{Continuous, Loop};
use crate::error::{Error, Result};

/// Steps per piece of constant held force in which events are bracketed.
///
/// The device's time constants are at least a few samples where the loop is of interest,
/// so a velocity holds one sign over 1/32 of a sample except at its zeros.
pub(super) const SUBSTEPS: usize = 32;

/// Regula falsi iterations at most; the Illinois variant converges superlinearly, so 60
/// reach the rounding of the trial time long before.
const MAX_ITER: usize = 60;

/// The exact map of a time `tau` under constant inputs: `x -> E x + g u + h f`.
struct Map {
    e: DMatrix<f64>,
    g: DVector<f64>,
    h: DVector<f64>,
}

impl Map {
    fn of(cont: &Continuous, f_in: &DVector<f64>, tau: f64) -> Self {
        let (e, mut gs) = cont.exp_inputs(&[&cont.b, f_in], tau);
        let h = gs.pop().unwrap_or_else(|| DVector::zeros(e.nrows()));
        let g = gs.pop().unwrap_or_else(|| DVector::zeros(e.nrows()));
        Self { e, g, h }
    }

    fn apply(&self, x: &DVector<f64>, u: f64, f: f64) -> DVector<f64> {
        &self.e * x + &self.g * u + &self.h * f
    }
}

/// The device with friction on its driven mass.
pub(super) struct FrictionDevice {
    slide: Continuous,
    stuck: Continuous,
    /// Friction input `e_f` (one over the driven mass on its velocity).
    f_in: DVector<f64>,
    /// The same, zero: no friction force acts on a stuck mass (the constraint holds it).
    f_none: DVector<f64>,
    coulomb: f64,
    stiction: f64,
    /// Maps over one step of each piece length in use: `(length, sliding, stuck)`.
    cache: Vec<(f64, Map, Map)>,
}

/// Index of the driven mass's velocity in the continuous states.
const V: usize = 1;

impl FrictionDevice {
    /// The device of `lp` with Coulomb friction `coulomb` and static friction `stiction`
    /// (normalized), the piece lengths `taus` cached.
    pub(super) fn new(lp: &Loop, coulomb: f64, stiction: f64, taus: &[f64]) -> Result<Self> {
        let slide = Continuous::new(lp);
        let n = slide.a.nrows();
        let mu = lp.hand().map_or(0.0, |h| h.mass_ratio());
        let driven = match lp.transmission() {
            None => 1.0 + mu,
            Some(t) => 1.0 - t.handle_ratio(),
        };
        let mut f_in = DVector::zeros(n);
        f_in[V] = 1.0 / driven;
        let mut stuck = slide.clone();
        for j in 0..n {
            stuck.a[(0, j)] = 0.0;
            stuck.a[(V, j)] = 0.0;
        }
        stuck.b[0] = 0.0;
        stuck.b[V] = 0.0;
        let mut dev = Self {
            slide,
            stuck,
            f_none: DVector::zeros(n),
            f_in,
            coulomb,
            stiction,
            cache: Vec::new(),
        };
        for &tau in taus {
            if tau > 0.0 {
                let h = tau / SUBSTEPS as f64;
                let (s, k) = (dev.slide_map(h), dev.stuck_map(h));
                dev.cache.push((tau, s, k));
            }
        }
        let finite = dev.cache.iter().all(|(_, s, k)| {
            s.e.iter()
                .chain(s.g.iter())
                .chain(s.h.iter())
                .chain(k.e.iter())
                .all(|v| v.is_finite())
        });
        if !finite {
            return Err(Error::Numerical(
                "the device's matrix exponential is not finite; reduce the elements' stiffness or damping".into(),
            ));
        }
        Ok(dev)
    }

    fn slide_map(&self, tau: f64) -> Map {
        Map::of(&self.slide, &self.f_in, tau)
    }

    fn stuck_map(&self, tau: f64) -> Map {
        Map::of(&self.stuck, &self.f_none, tau)
    }

    /// The net force on the driven mass at rest (normalized force units).
    fn net_force(&self, x: &DVector<f64>, u: f64) -> f64 {
        let accel = self.slide.a.row(V).dot(&x.transpose()) + self.slide.b[V] * u;
        accel / self.f_in[V]
    }

    /// The state after `tau` (a piece length given to [`FrictionDevice::new`]) under the
    /// held force `u`; a velocity of exactly zero means the driven mass is at rest.
    pub(super) fn advance(&self, x: DVector<f64>, u: f64, tau: f64) -> DVector<f64> {
        let Some((_, slide, stuck)) = self.cache.iter().find(|c| c.0 == tau) else {
            // exact: the pieces are the lengths cached at construction, compared bit for bit
            return x;
        };
        let h = tau / SUBSTEPS as f64;
        (0..SUBSTEPS).fold(x, |x, _| self.step(x, u, h, slide, stuck))
    }

    /// One step of length `h` (its maps given), with stick and slip.
    fn step(&self, mut x: DVector<f64>, u: f64, h: f64, slide: &Map, stuck: &Map) -> DVector<f64> {
        let mut left = h;
        // the direction of a breakaway just located (its force is at the static friction
        // within the root's rounding, so it is not decided again)
        let mut breakaway: Option<f64> = None;
        // Each event stops the mass or breaks it away; a few per step at most (a stop, a
        // breakaway, a stop): more is a chattering contact, left where it is.
        for _ in 0..6 {
            if left <= 0.0 {
                return x;
            }
            // exact: zero velocity is only ever set, never computed
            let at_rest = x[V] == 0.0;
            let force = if at_rest { self.net_force(&x, u) } else { 0.0 };
            if at_rest && breakaway.is_none() && force.abs() <= self.stiction {
                // stuck: until the net force passes the static friction
                let hold = |map: &Map| {
                    let mut y = map.apply(&x, u, 0.0);
                    // the held position and velocity, exactly (not the exponential's rounding)
                    (y[0], y[V]) = (x[0], 0.0);
                    y
                };
                let end = if left == h {
                    hold(stuck)
                } else {
                    hold(&self.stuck_map(left))
                };
                let f_end = self.net_force(&end, u);
                if f_end.abs() <= self.stiction {
                    return end;
                }
                let g = |t: f64| self.net_force(&hold(&self.stuck_map(t)), u).abs() - self.stiction;
                let t = illinois(g, 0.0, left);
                let y = hold(&self.stuck_map(t));
                breakaway = Some(f_end.signum());
                x = y;
                left -= t;
                continue;
            }
            let dir = match breakaway.take() {
                Some(d) => d,
                None if at_rest => force.signum(),
                None => x[V].signum(),
            };
            let f = -self.coulomb * dir;
            let end = if left == h && !at_rest {
                slide.apply(&x, u, f)
            } else {
                self.slide_map(left).apply(&x, u, f)
            };
            if end[V] * dir > 0.0 {
                return end;
            }
            let g = |t: f64| self.slide_map(t).apply(&x, u, f)[V] * dir;
            let t = illinois(g, 0.0, left);
            let mut y = self.slide_map(t).apply(&x, u, f);
            y[V] = 0.0;
            x = y;
            left -= t;
        }
        x
    }
}

/// A root of `g` in `(lo, hi)` where `g(lo) > 0 >= g(hi)` (or the reverse): the Illinois
/// variant of regula falsi, to the rounding of `t`. The root found is the bracketed one
/// nearest `lo` when `g` has one root in the bracket.
fn illinois(g: impl Fn(f64) -> f64, lo: f64, hi: f64) -> f64 {
    let (mut a, mut b) = (lo, hi);
    let (mut fa, mut fb) = (g(a), g(b));
    if fa == 0.0 {
        // a motion that starts at the root (from rest): the sign just after it is the
        // opposite of the end's, so only the weight stands in for it
        fa = -fb;
    }
    let mut side = 0;
    for _ in 0..MAX_ITER {
        let c = if fb != fa {
            (a * fb - b * fa) / (fb - fa)
        } else {
            0.5 * (a + b)
        };
        let c = if c > a && c < b { c } else { 0.5 * (a + b) };
        let fc = g(c);
        if fc == 0.0 || (b - a) <= 4.0 * f64::EPSILON * b.abs().max(1e-300) {
            return c;
        }
        if (fc > 0.0) == (fa > 0.0) {
            a = c;
            fa = fc;
            if side == -1 {
                fb *= 0.5;
            }
            side = -1;
        } else {
            b = c;
            fb = fc;
            if side == 1 {
                fa *= 0.5;
            }
            side = 1;
        }
    }
    b
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn illinois_finds_roots() {
        let t = illinois(|t| 0.3 - t, 0.0, 1.0);
        assert!((t - 0.3).abs() < 1e-15);
        let t = illinois(|t| (t * 3.0).cos(), 0.0, 1.0);
        assert!((t - std::f64::consts::PI / 6.0).abs() < 1e-14);
    }
}
