//! Coulomb and static friction on a device with elements (hand, transmission, actuator lag):
//! the continuous states integrated exactly between events (the model document,
//! docs/MODEL.md, section 10.1).
//!
//! The friction acts on the mass the commanded force drives (the device's mass with the
//! hand's when a hand is named, the motor side of a transmission): in the continuous model
//! `x' = A x + b u + e_f f` ([`Continuous`], states `(y, v, ...)`), `e_f` one over that mass
//! on its velocity `v = x[1]`. While the mass slides in direction `s` the friction is the
//! constant `-phi s`, so the motion over a piece is the exact map of one augmented matrix
//! exponential (Van Loan 1978, as [`crate::model::Discretization`]). While it sticks,
//! its position and velocity are held (their rows of `A` are zero) and the rest of the
//! device moves on; it breaks away when the net force on it, `(A[1,:] x + b[1] u) / e_f[1]`,
//! exceeds the static friction.
//!
//! Events are located inside the period: each piece of constant held force is cut into
//! [`SUBSTEPS`] equal steps; a step whose end has the velocity's sign reversed (sliding) or
//! the net force beyond the static friction (stuck) holds an event, found by the Illinois
//! variant of regula falsi on the exact motion at the trial time (a root of a smooth scalar
//! function: bracket and refine). An event whose function returns to its sign within one
//! step (two velocity zeros closer than `1 / SUBSTEPS` of a sample) is not seen.
//!
//! The whole steps apply the two maps of one step, computed once. The motion at a trial time
//! (any length) comes from the eigen decomposition of each dynamics' matrix, also computed
//! once ([`super::modal`]: a few complex exponentials a trial); where that decomposition is
//! defective or ill-conditioned, from the augmented exponential at the trial time.

use nalgebra::{DVector, SMatrix, SVector};

use super::modal::{Modal, Trajectory};
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

/// The most continuous states of a device: two masses and an actuator's lag.
const MAX_ORDER: usize = 5;

/// A device state, padded with zeros to [`MAX_ORDER`] (on the stack: the steps of a piece
/// allocate nothing).
type State = SVector<f64, MAX_ORDER>;

/// `v` padded with zeros.
fn padded(v: &DVector<f64>) -> State {
    State::from_fn(|i, _| v.get(i).copied().unwrap_or(0.0))
}

/// The exact map of a time `tau` under constant inputs: `x -> E x + g u + h f` (padded: the
/// rows and columns beyond the device's order are zero).
struct Map {
    e: SMatrix<f64, MAX_ORDER, MAX_ORDER>,
    g: State,
    h: State,
}

impl Map {
    fn apply(&self, x: &State, u: f64, f: f64) -> State {
        self.e * x + self.g * u + self.h * f
    }

    fn is_finite(&self) -> bool {
        self.e
            .iter()
            .chain(&self.g)
            .chain(&self.h)
            .all(|v| v.is_finite())
    }
}

/// One of the device's two linear dynamics (sliding or stuck) with its friction input, and
/// its eigen decomposition when that is well conditioned.
struct Dynamics {
    cont: Continuous,
    f_in: DVector<f64>,
    modal: Option<Modal>,
}

impl Dynamics {
    fn new(cont: Continuous, f_in: DVector<f64>) -> Self {
        let modal = Modal::new(&cont.a);
        Self { cont, f_in, modal }
    }

    /// The map of a time `tau`: one augmented matrix exponential.
    fn map(&self, tau: f64) -> Map {
        let (e, gs) = self.cont.exp_inputs(&[&self.cont.b, &self.f_in], tau);
        let input = |j: usize| gs.get(j).map_or(State::zeros(), padded);
        Map {
            e: SMatrix::from_fn(|i, j| e.get((i, j)).copied().unwrap_or(0.0)),
            g: input(0),
            h: input(1),
        }
    }

    /// The motion from `x` under the held force `u` and the friction force `f`.
    fn motion(&self, x: &State, u: f64, f: f64) -> Motion<'_> {
        match &self.modal {
            Some(m) => {
                let n = self.cont.a.nrows();
                let x = DVector::from_fn(n, |i, _| x[i]);
                Motion::Modal(m.start(&x, &(&self.cont.b * u + &self.f_in * f)))
            }
            None => Motion::Exponential {
                dynamics: self,
                x: *x,
                u,
                f,
            },
        }
    }
}

/// The motion of one piece at any time: by the eigen decomposition (a few complex
/// exponentials a time), or by a matrix exponential a time where that is not well
/// conditioned.
enum Motion<'a> {
    Modal(Trajectory<'a>),
    Exponential {
        dynamics: &'a Dynamics,
        x: State,
        u: f64,
        f: f64,
    },
}

impl Motion<'_> {
    fn at(&self, t: f64) -> State {
        match self {
            Motion::Modal(m) => padded(&m.at(t)),
            Motion::Exponential { dynamics, x, u, f } => dynamics.map(t).apply(x, *u, *f),
        }
    }

    fn component(&self, t: f64, j: usize) -> f64 {
        match self {
            Motion::Modal(m) => m.component(t, j),
            Motion::Exponential { .. } => self.at(t)[j],
        }
    }
}

/// The device with friction on its driven mass.
pub(super) struct FrictionDevice {
    slide: Dynamics,
    stuck: Dynamics,
    /// The driven mass's row of the sliding `A`, its input and its friction input: the
    /// net force on it at rest is `(a_v x + b_v u) / f_v`.
    a_v: State,
    b_v: f64,
    f_v: f64,
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
        if n > MAX_ORDER {
            return Err(Error::InvalidRequest(format!(
                "friction is modelled on devices of at most {MAX_ORDER} continuous states (two masses and an actuator lag)"
            )));
        }
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
        let a_v = State::from_fn(|j, _| if j < n { slide.a[(V, j)] } else { 0.0 });
        let (b_v, f_v) = (slide.b[V], f_in[V]);
        let mut dev = Self {
            slide: Dynamics::new(slide, f_in),
            // no friction force acts on a stuck mass (the constraint holds it)
            stuck: Dynamics::new(stuck, DVector::zeros(n)),
            a_v,
            b_v,
            f_v,
            coulomb,
            stiction,
            cache: Vec::new(),
        };
        for &tau in taus {
            if tau > 0.0 {
                let h = tau / SUBSTEPS as f64;
                let (s, k) = (dev.slide.map(h), dev.stuck.map(h));
                dev.cache.push((tau, s, k));
            }
        }
        if !dev
            .cache
            .iter()
            .all(|(_, s, k)| s.is_finite() && k.is_finite())
        {
            return Err(Error::Numerical(
                "the device's matrix exponential is not finite; reduce the elements' stiffness or damping".into(),
            ));
        }
        Ok(dev)
    }

    /// The net force on the driven mass at rest (normalized force units).
    fn net_force(&self, x: &State, u: f64) -> f64 {
        (self.a_v.dot(x) + self.b_v * u) / self.f_v
    }

    /// The state after `tau` (a piece length given to [`FrictionDevice::new`]) under the
    /// held force `u`; a velocity of exactly zero means the driven mass is at rest.
    pub(super) fn advance(&self, x: DVector<f64>, u: f64, tau: f64) -> DVector<f64> {
        let Some((_, slide, stuck)) = self.cache.iter().find(|c| c.0 == tau) else {
            // exact: the pieces are the lengths cached at construction, compared bit for bit
            return x;
        };
        let h = tau / SUBSTEPS as f64;
        let end = (0..SUBSTEPS).fold(padded(&x), |x, _| self.step(x, u, h, slide, stuck));
        DVector::from_fn(x.len(), |i, _| end[i])
    }

    /// One step of length `h` (its maps given), with stick and slip.
    fn step(&self, mut x: State, u: f64, h: f64, slide: &Map, stuck: &Map) -> State {
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
                let hold = |mut y: State| {
                    // the held position and velocity, exactly (not the exponential's rounding)
                    (y[0], y[V]) = (x[0], 0.0);
                    y
                };
                let motion = || self.stuck.motion(&x, u, 0.0);
                // exact: a whole step is the cached map's, compared bit for bit
                let end = if left == h {
                    hold(stuck.apply(&x, u, 0.0))
                } else {
                    hold(motion().at(left))
                };
                let f_end = self.net_force(&end, u);
                if f_end.abs() <= self.stiction {
                    return end;
                }
                let motion = motion();
                let g = |t: f64| self.net_force(&hold(motion.at(t)), u).abs() - self.stiction;
                let t = illinois(g, 0.0, left);
                let y = hold(motion.at(t));
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
            // exact: a whole step is the cached map's, compared bit for bit
            if left == h && !at_rest {
                let end = slide.apply(&x, u, f);
                if end[V] * dir > 0.0 {
                    return end;
                }
            }
            let motion = self.slide.motion(&x, u, f);
            if motion.component(left, V) * dir > 0.0 {
                return motion.at(left);
            }
            let t = illinois(|t| motion.component(t, V) * dir, 0.0, left);
            let mut y = motion.at(t);
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
