//! Step responses of loops with elements (`sim::step_response`) against independent
//! routes: a fine classical Runge-Kutta integration of each element's continuous equations in
//! physical units, written out here, with the sampled, filtered, delayed and held wall force;
//! powers of the closed-loop state matrix `Discretization::state_matrix` about the static
//! deflection worked out here by hand; the limits in which an element disappears; the
//! stability verdicts of `Checker`.

use nalgebra::DVector;
use stabound::elements::{Actuator, Encoder, Hand, Loop, PhysicalElements, Transmission};
use stabound::filter::VelocityFilter;
use stabound::model::Discretization;
use stabound::params::{Delay, Device};
use stabound::sim::{StepOptions, step_response};
use stabound::stability::Checker;
use stabound::stability::{Options, Verdict};
use stabound::{AmaxOptions, alpha_max};

/// The paper's loop on `dev` (no element): the closed-form route of `step_response`.
fn paper(dev: &Device) -> Loop {
    Loop::physical(dev, &PhysicalElements::default()).unwrap()
}

const MASS: f64 = 0.1;
const PERIOD: f64 = 1e-3;

/// A loop in physical units, for the library and for the test's own model.
#[derive(Clone, Copy, Debug, Default)]
struct Case {
    damping: f64,
    delay_samples: f64,
    /// hand mass kg, damping N s/m, stiffness N/m
    hand: Option<(f64, f64, f64)>,
    /// handle mass kg, coupling stiffness N/m, coupling damping N s/m, encoder on the handle
    trans: Option<(f64, f64, f64, bool)>,
    /// actuator time constant, s
    lag: Option<f64>,
    /// low-pass cutoff, Hz
    cutoff: Option<f64>,
    /// moving-average window, samples
    average: Option<usize>,
    /// second-order low-pass cutoff, Hz
    butterworth: Option<f64>,
    /// wall stiffness N/m, damping N s/m
    wall: (f64, f64),
}

impl Case {
    fn device(&self) -> Device {
        Device::new(
            MASS,
            PERIOD,
            self.damping,
            Delay::Samples(self.delay_samples),
        )
        .unwrap()
    }

    fn library(&self) -> Loop {
        let mut e = PhysicalElements::default();
        if let Some((m, b, k)) = self.hand {
            e.hand_mass = Some(m);
            e.hand_damping = Some(b);
            e.hand_stiffness = Some(k);
        }
        if let Some((m2, kc, bc, on_handle)) = self.trans {
            e.handle_mass = Some(m2);
            e.transmission_stiffness = Some(kc);
            e.transmission_damping = Some(bc);
            e.encoder = Some(if on_handle {
                Encoder::Handle
            } else {
                Encoder::Motor
            });
        }
        e.actuator_time_constant = self.lag;
        e.velocity_filter_cutoff = self.cutoff.or(self.butterworth);
        e.velocity_filter_order = self.butterworth.map(|_| 2);
        e.velocity_filter_samples = self.average;
        let dev = self.device();
        Loop::new(dev.plant().unwrap())
            .with_physical(&dev, &e)
            .unwrap()
    }

    /// The static deflection of the sensed position, from the springs' balance at rest:
    /// the wall `K y`, the hand `k_h x_handle` to ground and the coupling `k_c (x2 - x1)`.
    fn static_deflection(&self, force: f64) -> f64 {
        let (k, _) = self.wall;
        let kh = self.hand.map_or(0.0, |h| h.2);
        match self.trans {
            // motor read: K x1 = k_c (x2 - x1), F = k_h x2 + K x1
            Some((_, kc, _, false)) => force / (k + kh * (1.0 + k / kc)),
            // one mass, or the handle read: F = (K + k_h) x2
            _ => force / (k + kh),
        }
    }

    /// `(x1, x2)` at rest for a sensed deflection `y` (equal without a transmission).
    fn rest_positions(&self, y: f64) -> (f64, f64) {
        let (k, _) = self.wall;
        match self.trans {
            Some((_, kc, _, false)) => (y, y * (1.0 + k / kc)),
            Some((_, kc, _, true)) => (y * (1.0 - k / kc), y),
            None => (y, y),
        }
    }

    /// Accelerations of the continuous device in physical units: states (x1, v1, x2, v2, f)
    /// (x2, v2 unused without a transmission, f without a lag), commanded force `u`.
    fn derivative(&self, s: &[f64; 5], u: f64, force: f64) -> [f64; 5] {
        let (mh, bh, kh) = self.hand.unwrap_or((0.0, 0.0, 0.0));
        let b = self.damping;
        let (drive, df) = match self.lag {
            Some(tau) => (s[4], (u - s[4]) / tau),
            None => (u, 0.0),
        };
        match self.trans {
            None => {
                let acc = (drive + force - (b + bh) * s[1] - kh * s[0]) / (MASS + mh);
                [s[1], acc, 0.0, 0.0, df]
            }
            Some((m2, kc, bc, _)) => {
                let coupling = kc * (s[0] - s[2]) + bc * (s[1] - s[3]);
                // the device's damping acts on the motor side (handle-side damping 0)
                let a1 = (drive - b * s[1] - coupling) / (MASS - m2);
                let a2 = (force - bh * s[3] - kh * s[2] + coupling) / (m2 + mh);
                [s[1], a1, s[3], a2, df]
            }
        }
    }

    fn sensed(&self, s: &[f64; 5]) -> f64 {
        match self.trans {
            Some((_, _, _, true)) => s[2],
            _ => s[0],
        }
    }

    /// The sensed position at every output point by RK4 with `sub` steps per output
    /// interval; the wall force at each sample from the filter's recursion on the sensed
    /// positions, delayed by d periods and held.
    fn runge_kutta(&self, force: f64, periods: usize, per: usize, sub: usize) -> Vec<f64> {
        let (k, bw) = self.wall;
        let d = self.delay_samples;
        let n = d.floor() as usize;
        let eps = d - d.floor();
        let h = PERIOD / (per * sub) as f64;
        let mut s = [0.0f64; 5];
        let mut out = vec![0.0];
        let mut forces: Vec<f64> = Vec::new();
        let mut ys: Vec<f64> = Vec::new();
        let mut w_prev = 0.0;
        let mut w_prev2 = 0.0;
        // scipy's coefficients (the golden file)
        let butter = self
            .butterworth
            .map(|fc| super::butterworth::scipy_butter(fc * PERIOD));
        let pole = self
            .cutoff
            .map(|fc| (-2.0 * std::f64::consts::PI * fc * PERIOD).exp());
        for p in 0..periods {
            let y = self.sensed(&s);
            ys.push(y);
            let past = |j: usize| if j <= p { ys[p - j] } else { 0.0 };
            // velocity estimate per period (position difference), as the wall sees it
            let w = match (pole, self.average) {
                _ if butter.is_some() => {
                    let (b, a) = butter.unwrap();
                    b[0] * (y - past(1)) + b[1] * (past(1) - past(2)) + b[2] * (past(2) - past(3))
                        - a[1] * w_prev
                        - a[2] * w_prev2
                }
                (Some(a), _) => a * w_prev + (1.0 - a) * (y - past(1)),
                (None, Some(nn)) => (y - past(nn)) / nn as f64,
                (None, None) => y - past(1),
            };
            w_prev2 = w_prev;
            w_prev = w;
            forces.push(-(k * y + bw * w / PERIOD));
            let held = |back: usize| if back <= p { forces[p - back] } else { 0.0 };
            let (late, early) = (held(n), held(n + 1));
            for i in 0..per {
                for j in 0..sub {
                    let tau = (i * sub + j) as f64 / (per * sub) as f64;
                    // eps is a multiple of 1 / per here: no step straddles the switch
                    let u = if tau < eps { early } else { late };
                    let f = |s: &[f64; 5]| self.derivative(s, u, force);
                    let add = |a: &[f64; 5], b: &[f64; 5], c: f64| {
                        std::array::from_fn::<f64, 5, _>(|q| a[q] + c * b[q])
                    };
                    let k1 = f(&s);
                    let k2 = f(&add(&s, &k1, 0.5 * h));
                    let k3 = f(&add(&s, &k2, 0.5 * h));
                    let k4 = f(&add(&s, &k3, h));
                    for q in 0..5 {
                        s[q] += h / 6.0 * (k1[q] + 2.0 * k2[q] + 2.0 * k3[q] + k4[q]);
                    }
                }
                out.push(self.sensed(&s));
            }
        }
        out
    }
}

/// One case of each element kind, and all of them together, far inside the stable region.
fn cases() -> Vec<(&'static str, Case)> {
    let base = Case {
        damping: 1.0,
        delay_samples: 1.0,
        wall: (2000.0, 10.0),
        ..Case::default()
    };
    vec![
        (
            "hand",
            Case {
                hand: Some((0.05, 2.0, 200.0)),
                delay_samples: 1.5,
                ..base
            },
        ),
        (
            "transmission, encoder on the motor",
            Case {
                trans: Some((0.03, 5e4, 5.0, false)),
                ..base
            },
        ),
        (
            "transmission, encoder on the handle, with a hand",
            Case {
                trans: Some((0.03, 5e4, 5.0, true)),
                hand: Some((0.02, 1.0, 100.0)),
                delay_samples: 0.5,
                ..base
            },
        ),
        (
            "actuator lag",
            Case {
                lag: Some(5e-4),
                ..base
            },
        ),
        (
            "low-pass filter",
            Case {
                cutoff: Some(100.0),
                ..base
            },
        ),
        (
            "second-order low-pass filter",
            Case {
                butterworth: Some(100.0),
                ..base
            },
        ),
        (
            "moving-average filter",
            Case {
                average: Some(3),
                delay_samples: 2.5,
                wall: (1000.0, 10.0),
                ..base
            },
        ),
        (
            "all together",
            Case {
                hand: Some((0.05, 2.0, 200.0)),
                trans: Some((0.03, 5e4, 5.0, false)),
                lag: Some(3e-4),
                cutoff: Some(150.0),
                delay_samples: 1.5,
                ..base
            },
        ),
    ]
}

/// The library's walls are all stable here with room to spare: at most half of the loop's
/// alpha_max, so neither route's rounding is amplified by a slowly decaying mode.
fn assert_far_inside(name: &str, c: &Case) {
    let dev = c.device();
    let lp = c.library();
    let wall = dev.wall(c.wall.0, c.wall.1).unwrap();
    let amax = alpha_max(lp, &AmaxOptions::default()).unwrap();
    assert!(
        wall.alpha() < 0.5 * amax.alpha_max,
        "{name}: alpha {} vs alpha_max {}",
        wall.alpha(),
        amax.alpha_max
    );
    let verdict = Checker::new(lp, Options::default())
        .unwrap()
        .verdict(&wall)
        .unwrap();
    assert_eq!(verdict, Verdict::Stable, "{name}");
}

/// At the samples and between them the exact simulation agrees with a fine RK4 integration
/// of the element's own equations.
#[test]
fn each_element_matches_runge_kutta() {
    let (force, periods, per) = (1.5, 30, 10);
    for (name, c) in cases() {
        assert_far_inside(name, &c);
        let options = StepOptions {
            force,
            duration: periods as f64 * PERIOD,
            points_per_period: per,
        };
        let r = step_response(
            &c.library().with_device(&c.device()).unwrap(),
            c.wall.0,
            c.wall.1,
            &options,
        )
        .unwrap();
        assert_eq!(r.position.len(), periods * per + 1, "{name}");
        let rk = c.runge_kutta(force, periods, per, 40);
        let scale = rk.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let worst = r
            .position
            .iter()
            .zip(&rk)
            .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        // RK4 at h = T / 400 = 2.5 us on modes no faster than 1.6e3 rad/s (the coupling) or
        // 1 / 0.3 ms (the lag): h w <= 0.013, a global error ~ (h w)^4 ~ 3e-8 of the
        // fastest mode's share, which the step barely excites (measured: at most 6e-14 of
        // the response's size); 1e-11 leaves room for other platforms' rounding and still
        // catches a wrong force path, gain or delay (errors of order 1).
        assert!(worst <= 1e-11 * scale, "{name}: {worst:e} vs {scale:e}");
        // the dense output passes through every sample
        for (i, &x) in r.samples.iter().enumerate() {
            assert_eq!(r.position[i * per], x, "{name} sample {i}");
        }
    }
}

/// At the sampling instants the deviation from the static deflection evolves as powers of
/// the independent closed-loop state matrix: `z_k - z* = S^k (z_0 - z*)` with `z_0 = 0` and
/// `z*` the rest state worked out here (device at rest at its static deflection, every held
/// force and the actuator's force `-alpha y*`, the filter's memory at rest).
#[test]
fn samples_follow_state_matrix_powers() {
    let force = 2.0;
    for (name, c) in cases() {
        if c.butterworth.is_some() {
            // its memory is the library's canonical form, whose rest state is not written
            // out here; its samples are held to Runge-Kutta and its roots to the literal
            // difference equation instead
            continue;
        }
        let dev = c.device();
        let lp = c.library();
        let wall = dev.wall(c.wall.0, c.wall.1).unwrap();
        let disc = Discretization::new(lp).unwrap();
        let s_mat = disc.state_matrix(&wall);
        let dim = disc.state_dim();
        let y_star = c.static_deflection(force);
        let u_star = -wall.alpha() * y_star; // normalized force at rest
        let (x1, x2) = c.rest_positions(y_star);
        let mut z_star = DVector::<f64>::zeros(dim);
        let order = lp.device_order();
        z_star[0] = x1;
        if c.trans.is_some() {
            z_star[2] = x2;
        }
        if c.lag.is_some() {
            z_star[order - 1] = u_star;
        }
        let n = c.delay_samples.floor() as usize;
        let held = n + usize::from(c.delay_samples.fract() > 0.0);
        for j in 0..held {
            z_star[order + j] = u_star;
        }
        let mem = order + held;
        match (c.cutoff, c.average) {
            (Some(fc), _) => {
                let a = (-2.0 * std::f64::consts::PI * fc * PERIOD).exp();
                // p = a w - (1 - a) y with w = 0 at rest
                z_star[mem] = -(1.0 - a) * y_star;
            }
            (None, Some(nn)) => (0..nn).for_each(|j| z_star[mem + j] = y_star),
            (None, None) => z_star[mem] = y_star,
        }
        assert_eq!(mem + c.average.unwrap_or(1), dim, "{name}: state layout");
        let options = StepOptions {
            force,
            duration: 0.06,
            points_per_period: 1,
        };
        let r =
            step_response(&lp.with_device(&dev).unwrap(), c.wall.0, c.wall.1, &options).unwrap();
        let final_value = r.final_value.unwrap();
        assert!(
            (final_value - y_star).abs() <= 1e-13 * y_star.abs(),
            "{name}: final {final_value:e} vs {y_star:e}"
        );
        let mut e = -z_star;
        let out = disc.output();
        for (k, &y) in r.samples.iter().enumerate() {
            let want = y_star + (0..order).map(|i| out[i] * e[i]).sum::<f64>();
            // 60 steps of well-conditioned updates on both routes: rounding below 1e-11
            // of the deflection
            assert!(
                (y - want).abs() <= 1e-11 * y_star.abs(),
                "{name} sample {k}: {y:e} vs {want:e}"
            );
            e = &s_mat * e;
        }
    }
}

/// A stiff transmission (kappa_c = 1e6, the largest accepted) is the one-mass device: the
/// response approaches the paper's loop with the same total mass and damping.
#[test]
fn stiff_transmission_is_one_mass() {
    let dev = Device::new(MASS, PERIOD, 1.0, Delay::Samples(1.0)).unwrap();
    let (k, bw) = (3000.0, 10.0);
    let options = StepOptions {
        force: 1.0,
        duration: 0.05,
        points_per_period: 5,
    };
    let rigid = step_response(&paper(&dev), k, bw, &options).unwrap();
    let scale = rigid.position.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let mut gaps = Vec::new();
    for kappa in [1e4, 1e6] {
        for encoder in [Encoder::Motor, Encoder::Handle] {
            let t = Transmission::new(0.3, kappa, 0.0, 0.0, encoder).unwrap();
            let lp = Loop::new(dev.plant().unwrap())
                .with_transmission(t)
                .unwrap();
            let r = step_response(&lp.with_device(&dev).unwrap(), k, bw, &options).unwrap();
            let gap = r
                .position
                .iter()
                .zip(&rigid.position)
                .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()))
                / scale;
            gaps.push(gap);
        }
    }
    // The coupling's static stretch and its undamped ringing are both ~ alpha / kappa_c
    // relative (alpha = 3e-3 here): below 1e-5 at kappa_c = 1e4 and 1e-7 at 1e6, and
    // shrinking with kappa_c.
    assert!(gaps[0] < 1e-5 && gaps[1] < 1e-5, "{gaps:?}");
    assert!(gaps[2] < 1e-7 && gaps[3] < 1e-7, "{gaps:?}");
    assert!(gaps[2] < gaps[0] && gaps[3] < gaps[1], "{gaps:?}");
}

/// Elements that vanish give the paper's response (closed forms, `step_response`): a hand of
/// zero mass, damping and stiffness and a low-pass of pole 1e-12 (cutoff -> infinity) go
/// through the general route; a zero pole and a one-sample average are `F = 1` exactly.
#[test]
fn vanishing_elements_give_the_bare_loop() {
    for (b, d) in [(0.0, 1.0), (2.0, 1.5), (10.0, 0.25), (0.5, 3.0)] {
        let dev = Device::new(MASS, PERIOD, b, Delay::Samples(d)).unwrap();
        let (k, bw) = (4000.0, 20.0);
        let options = StepOptions {
            force: 1.0,
            duration: 0.04,
            points_per_period: 7,
        };
        let bare = step_response(&paper(&dev), k, bw, &options).unwrap();
        let scale = bare.position.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let plant = dev.plant().unwrap();
        let general = [
            Loop::new(plant).with_hand(Hand::new(0.0, 0.0, 0.0).unwrap()),
            Loop::new(plant).with_filter(VelocityFilter::low_pass(1e-12).unwrap()),
        ];
        for lp in general {
            let lp = lp.unwrap();
            assert!(!lp.is_paper());
            let r = step_response(&lp.with_device(&dev).unwrap(), k, bw, &options).unwrap();
            assert_eq!(r.time.len(), bare.time.len());
            for (i, (a, w)) in r.position.iter().zip(&bare.position).enumerate() {
                // the pole's 1e-12 and the matrix exponential's rounding, far below 1e-9
                assert!(
                    (a - w).abs() <= 1e-9 * scale,
                    "b {b} d {d} point {i}: {a:e} vs {w:e}"
                );
            }
            assert_eq!(r.time, bare.time);
            let fv = r.final_value.unwrap();
            assert!((fv - 1.0 / k).abs() <= 1e-14 / k, "{fv}");
        }
        for filter in [
            VelocityFilter::low_pass(0.0).unwrap(),
            VelocityFilter::moving_average(1).unwrap(),
        ] {
            let lp = Loop::new(plant).with_filter(filter).unwrap();
            let r = step_response(&lp.with_device(&dev).unwrap(), k, bw, &options).unwrap();
            assert_eq!(r, bare);
        }
    }
}

/// Beyond the loop's alpha_max (found by `alpha_max`, confirmed by `Checker`) the
/// response grows; at half of it the response settles to the static deflection.
#[test]
fn unstable_grows_stable_settles() {
    let dev = Device::new(MASS, PERIOD, 1.0, Delay::Samples(1.0)).unwrap();
    let lp = Loop::new(dev.plant().unwrap())
        .with_hand(Hand::physical(&dev, 0.05, 1.0, 50.0).unwrap())
        .unwrap()
        .with_actuator(Actuator::physical(2e-4, PERIOD).unwrap())
        .unwrap()
        .with_filter(VelocityFilter::low_pass_cutoff(100.0, PERIOD).unwrap())
        .unwrap();
    let amax = alpha_max(lp, &AmaxOptions::default()).unwrap();
    let checker = Checker::new(lp, Options::default()).unwrap();
    let options = StepOptions {
        force: 1.0,
        duration: 0.5,
        points_per_period: 2,
    };
    for (factor, stable) in [(1.5, false), (0.5, true)] {
        let wall = stabound::Wall::new(factor * amax.alpha_max, amax.beta_at_max).unwrap();
        let verdict = checker.verdict(&wall).unwrap();
        assert_eq!(verdict == Verdict::Stable, stable, "{factor}: {verdict:?}");
        let (k, bw) = (dev.stiffness(wall.alpha()), dev.wall_damping(wall.beta()));
        let r = step_response(&lp.with_device(&dev).unwrap(), k, bw, &options).unwrap();
        let target = r.final_value.unwrap();
        let dev_of = |xs: &[f64]| xs.iter().fold(0.0f64, |m, x| m.max((x - target).abs()));
        let tenth = r.samples.len() / 10;
        let (early, late) = (
            dev_of(&r.samples[..tenth]),
            dev_of(&r.samples[r.samples.len() - tenth..]),
        );
        if stable {
            assert!(late < 1e-6 * target.abs(), "{late:e}");
            assert!(r.settling_time(0.02).is_some());
        } else {
            assert!(late > 1e3 * early, "{early:e} -> {late:e}");
            assert!(r.settling_time(0.02).is_none());
        }
    }
}

/// What cannot be simulated is refused with a typed error.
#[test]
fn refuses_what_it_cannot_simulate() {
    let dev = Device::new(MASS, PERIOD, 1.0, Delay::Samples(1.0)).unwrap();
    let other = Device::new(MASS, PERIOD, 2.0, Delay::Samples(1.0)).unwrap();
    let lp = Loop::new(other.plant().unwrap())
        .with_hand(Hand::new(0.5, 0.0, 0.0).unwrap())
        .unwrap();
    let opts = StepOptions::default();
    // a loop on another device's plant is not this device's loop
    assert!(matches!(
        lp.with_device(&dev),
        Err(stabound::Error::InvalidRequest(_))
    ));
    // a loop in normalized units has no device to simulate
    assert!(matches!(
        step_response(&lp, 1000.0, 0.0, &opts),
        Err(stabound::Error::InvalidRequest(_))
    ));
    let lp = lp.with_plant(dev.plant().unwrap()).unwrap();
    let long = StepOptions {
        duration: 1e4,
        ..opts
    };
    assert!(matches!(
        step_response(&lp.with_device(&dev).unwrap(), 1000.0, 0.0, &long),
        Err(stabound::Error::InvalidRequest(_))
    ));
    let none = StepOptions {
        points_per_period: 0,
        ..opts
    };
    assert!(step_response(&lp.with_device(&dev).unwrap(), 1000.0, 0.0, &none).is_err());
    let nan = StepOptions {
        force: f64::NAN,
        ..opts
    };
    assert!(step_response(&lp.with_device(&dev).unwrap(), 1000.0, 0.0, &nan).is_err());
    assert!(step_response(&lp.with_device(&dev).unwrap(), f64::INFINITY, 0.0, &opts).is_err());
    // no stiffness holds the device: no final value
    let r = step_response(&lp.with_device(&dev).unwrap(), 0.0, 0.0, &opts).unwrap();
    assert_eq!(r.final_value, None);
}
