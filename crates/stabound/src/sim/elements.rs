//! Step responses of a loop with elements (hand, transmission, actuator lag, velocity
//! filter): exact at the samples and between them.
//!
//! The device is `x' = A x + b u + e f_H` in normalized time (the model document,
//! docs/MODEL.md, section 8): `u` the held, delayed wall force, `f_H = F_H T^2 / m` the
//! operator's constant force, `e` where it acts (the velocity of the mass the operator
//! holds). On every piece of a period where one held wall force acts both inputs are
//! constant, so one augmented matrix exponential `exp([[A, b, e], [0, 0, 0]] tau)` (Van Loan
//! 1978, the same route as [`crate::model::Discretization`]) gives the state after
//! that piece exactly: `x(tau) = e^{A tau} x0 + Gamma_b(tau) u + Gamma_e(tau) f_H`.

use std::collections::VecDeque;

use nalgebra::{DMatrix, DVector};

use super::{StepOptions, StepResponse, periods};
use crate::elements::{Continuous, Encoder, Loop};
use crate::error::{Error, Result};
use crate::filter::{FilterKind, VelocityFilter};
use crate::params::Device;

/// The exact state map of one piece of `tau` periods under constant inputs:
/// `x -> E x + g u + h` (`h` already carries the operator's force).
struct Piece {
    e: DMatrix<f64>,
    g: DVector<f64>,
    h: DVector<f64>,
}

impl Piece {
    fn new(cont: &Continuous, operator: &DVector<f64>, f_h: f64, tau: f64) -> Result<Self> {
        let (e, gammas) = cont.exp_inputs(&[&cont.b, operator], tau);
        // two inputs in, two gains out
        let (g, h) = (gammas[0].clone(), &gammas[1] * f_h);
        if e.iter()
            .chain(g.iter())
            .chain(h.iter())
            .any(|v| !v.is_finite())
        {
            return Err(Error::Numerical(
                "the device's matrix exponential is not finite; reduce the elements' stiffness or damping".into(),
            ));
        }
        Ok(Self { e, g, h })
    }

    fn advance(&self, x: &DVector<f64>, u: f64) -> DVector<f64> {
        &self.e * x + &self.g * u + &self.h
    }
}

/// The wall's velocity estimate `w_k = F(z) (1 - z^{-1}) y_k`, by the filter's own
/// recursion (the model document, section 8), starting from rest.
pub(crate) enum Estimate {
    /// `w_k = a w_{k-1} + (1 - a)(y_k - y_{k-1})`; `a = 0` is the backward difference.
    LowPass { pole: f64, w: f64, y: f64 },
    /// `w_k = (y_k - y_{k-N}) / N`, the last `N` positions newest first.
    Average { past: VecDeque<f64> },
    /// `Fd(q) w = Fn(q) v` with `v_k = y_k - y_{k-1}` (`q` the forward shift, `Fd` monic),
    /// solved for the newest `w`; the past `v` and `w` newest first.
    Recursion {
        num: Vec<f64>,
        den: Vec<f64>,
        v: VecDeque<f64>,
        w: VecDeque<f64>,
        y: f64,
    },
}

impl Estimate {
    fn new(filter: &VelocityFilter) -> Self {
        Self::resting_at(filter, 0.0)
    }

    /// The estimate of a device that has rested at `y0` (every past position `y0`, the
    /// estimate zero).
    pub(crate) fn resting_at(filter: &VelocityFilter, y0: f64) -> Self {
        match filter.kind() {
            FilterKind::LowPass { pole } => Self::LowPass {
                pole,
                w: 0.0,
                y: y0,
            },
            FilterKind::MovingAverage { samples } => Self::Average {
                past: std::iter::repeat_n(y0, samples).collect(),
            },
            // no filter: the backward difference, a moving average of one sample
            FilterKind::None => Self::Average {
                past: VecDeque::from([y0]),
            },
            // any other filter by its recursion
            _ => {
                let (num, den) = (filter.numerator(), filter.denominator());
                Self::Recursion {
                    v: std::iter::repeat_n(0.0, den.len()).collect(),
                    w: std::iter::repeat_n(0.0, den.len() - 1).collect(),
                    num,
                    den,
                    y: y0,
                }
            }
        }
    }

    pub(crate) fn next(&mut self, y_now: f64) -> f64 {
        match self {
            Self::LowPass { pole, w, y } => {
                *w = *pole * *w + (1.0 - *pole) * (y_now - *y);
                *y = y_now;
                *w
            }
            Self::Average { past } => {
                let n = past.len();
                let oldest = past.pop_back().unwrap_or(0.0);
                past.push_front(y_now);
                (y_now - oldest) / n as f64
            }
            Self::Recursion { num, den, v, w, y } => {
                v.pop_back();
                v.push_front(y_now - *y);
                *y = y_now;
                // w_k = sum_j Fn_j v_{k-f+j} - sum_{j<f} Fd_j w_{k-f+j}, f = deg Fd
                let f = den.len() - 1;
                let mut out = 0.0;
                for (j, nj) in num.iter().enumerate() {
                    out += nj * v[f - j];
                }
                for (j, dj) in den.iter().enumerate().take(f) {
                    out -= dj * w[f - 1 - j];
                }
                w.pop_back();
                w.push_front(out);
                out
            }
        }
    }
}

/// The static deflection of the sensed position under `f_h` (normalized, like `alpha`), or
/// `None` when nothing holds the device (zero restoring stiffness).
///
/// At rest `w = 0` (every filter has `F(1) = 1`), the lag passes the force unchanged and
/// the velocities vanish, so the springs balance: one mass `y = f_h / (alpha + kappa_h)`;
/// a transmission read on the handle the same; read on the motor, the coupling spring
/// stretches by `alpha y / kappa_c`, so `y = f_h / (alpha + kappa_h (1 + alpha / kappa_c))`.
fn static_deflection(lp: &Loop, alpha: f64, f_h: f64) -> Option<f64> {
    let kh = lp.hand().map_or(0.0, |h| h.stiffness());
    let stiffness = match lp.transmission() {
        Some(t) if t.encoder() == Encoder::Motor => alpha + kh * (1.0 + alpha / t.stiffness()),
        _ => alpha + kh,
    };
    // exact: only a restoring stiffness of exactly zero leaves no equilibrium
    (stiffness != 0.0).then(|| f_h / stiffness)
}

/// The step response of a loop with elements on its `device` (see [`super::step_response`]):
/// exact piecewise solution by the augmented matrix exponential, each piece of a period one
/// step with the held wall force and the operator's force as constant inputs (each point
/// reached from the one before it, each sample from the one before it in two pieces, so the
/// samples do not depend on the points per period).
pub(super) fn general_step_response(
    device: &Device,
    lp: &Loop,
    stiffness: f64,
    wall_damping: f64,
    options: &StepOptions,
) -> Result<StepResponse> {
    let plant = device.plant()?;
    // exact: the same device gives the same plant bit for bit
    if *lp.plant() != plant {
        return Err(Error::InvalidRequest(format!(
            "the loop's plant (delta = {}, d = {}) is not the device's (delta = {}, d = {}); build the loop on the device's plant",
            lp.plant().delta(),
            lp.plant().d(),
            plant.delta(),
            plant.d()
        )));
    }
    let wall = device.wall(stiffness, wall_damping)?;
    let periods = periods(device, options)?;
    let per = options.points_per_period;
    let (alpha, beta) = (wall.alpha(), wall.beta());
    let f_h = options.force * device.period() * device.period() / device.mass();

    let cont = Continuous::new(lp);
    let operator = Continuous::operator_input(lp);
    let piece = |tau: f64| Piece::new(&cont, &operator, f_h, tau);
    let n = plant.whole_samples();
    let fractional = !plant.is_integer_delay();
    let eps = plant.fraction();
    // One period: the early force for eps, the late one for the rest (integer d: one piece).
    let (first, rest) = if fractional {
        (Some(piece(eps)?), piece(1.0 - eps)?)
    } else {
        (None, piece(1.0)?)
    };
    // Between the samples: a step of 1 / per, and the two parts of the one step that
    // straddles the switch at eps (if eps is not on the grid).
    let step = piece(1.0 / per as f64)?;
    let grid = |i: usize| i as f64 / per as f64;
    let straddle = if fractional {
        (1..per).find(|&i| grid(i - 1) < eps && eps < grid(i))
    } else {
        None
    };
    let split = match straddle {
        Some(i) => Some((piece(eps - grid(i - 1))?, piece(grid(i) - eps)?)),
        None => None,
    };
    let c = &cont.c;

    // The wall forces computed so far, newest first, zero before the start: after the push
    // at sample k, history[j] = u_{k-j}.
    let mut history: VecDeque<f64> = std::iter::repeat_n(0.0, n + 2).collect();
    let mut estimate = Estimate::new(lp.filter());
    let mut x = DVector::<f64>::zeros(cont.a.nrows());

    let mut r = StepResponse::at_rest(periods, per, device.period());
    for k in 0..periods {
        let y = c.dot(&x);
        let w = estimate.next(y);
        history.push_front(-(alpha * y + beta * w));
        history.pop_back();
        let late = history[n]; // u_{k-n}, acts on [eps, 1)
        let early = history[n + 1]; // u_{k-n-1}, acts on [0, eps)
        let t0 = k as f64;
        let mut z = x.clone();
        for i in 1..per {
            z = match (&split, straddle) {
                (Some((a, b)), Some(j)) if j == i => b.advance(&a.advance(&z, early), late),
                _ => step.advance(&z, if grid(i) <= eps { early } else { late }),
            };
            r.time.push((t0 + grid(i)) * device.period());
            r.position.push(c.dot(&z));
        }
        x = match &first {
            Some(first) => rest.advance(&first.advance(&x, early), late),
            None => rest.advance(&x, late),
        };
        let y_next = c.dot(&x);
        r.time.push((t0 + 1.0) * device.period());
        r.position.push(y_next);
        r.samples.push(y_next);
    }
    r.final_value = static_deflection(lp, alpha, f_h);
    Ok(r)
}
