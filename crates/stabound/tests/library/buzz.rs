//! The buzz simulation (encoder, force steps, Coulomb and static friction; docs/MODEL.md
//! section 10.3) against an independent one: a fine classical Runge-Kutta integration of the
//! device's differential equation with its own quantizers, wall law and friction, velocity
//! zeros found by bisection on the step length. Plus the limits: no quantizer and no
//! friction is the linear loop; a linearly unstable wall with no friction always buzzes or
//! diverges.

use stabound::buzz::{BuzzOptions, Outcome, Quantization, Start, buzz, readings};
use stabound::elements::{Hand, Loop};
use stabound::filter::VelocityFilter;
use stabound::model::Discretization;
use stabound::params::{Plant, Wall};
use stabound::search::alpha_limit;
use stabound::stability::{Checker, Options};

/// One case for the independent integration, normalized: counts, samples, forces in
/// counts per sample squared.
#[derive(Clone, Copy)]
struct Case {
    delta: f64,
    /// Whole samples of delay.
    n: usize,
    /// Fraction of the delay, a multiple of 1 / SUB.
    eps: f64,
    alpha: f64,
    beta: f64,
    encoder: bool,
    step: f64,
    coulomb: f64,
    stiction: f64,
    /// Hand: mass ratio, damping, stiffness (zero: none).
    hand: (f64, f64, f64),
    /// Low-pass pole of the velocity estimate (zero: the backward difference).
    pole: f64,
}

/// Runge-Kutta steps per sample: the device's time scales are at least a sample, so the
/// local error (h w)^5 stays near 1e-16 and positions agree with the exact motion to about
/// 1e-12 counts, far from the half-count edges where a reading could flip.
const SUB: usize = 1000;

impl Case {
    fn paper(delta: f64, d: f64, alpha: f64, beta: f64) -> Self {
        Self {
            delta,
            n: d.floor() as usize,
            eps: d - d.floor(),
            alpha,
            beta,
            encoder: true,
            step: 0.0,
            coulomb: 0.0,
            stiction: 0.0,
            hand: (0.0, 0.0, 0.0),
            pole: 0.0,
        }
    }

    fn accel(&self, x: f64, v: f64, f: f64, dir: f64) -> f64 {
        let (mu, dh, kh) = self.hand;
        (f - self.coulomb * dir - (self.delta + dh) * v - kh * x) / (1.0 + mu)
    }

    /// One classical Runge-Kutta step of length `h` with the friction's direction fixed.
    fn rk4(&self, x: f64, v: f64, f: f64, dir: f64, h: f64) -> (f64, f64) {
        let a = |x, v| self.accel(x, v, f, dir);
        let (k1x, k1v) = (v, a(x, v));
        let (k2x, k2v) = (v + 0.5 * h * k1v, a(x + 0.5 * h * k1x, v + 0.5 * h * k1v));
        let (k3x, k3v) = (v + 0.5 * h * k2v, a(x + 0.5 * h * k2x, v + 0.5 * h * k2v));
        let (k4x, k4v) = (v + h * k3v, a(x + h * k3x, v + h * k3v));
        (
            x + h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x),
            v + h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v),
        )
    }

    /// Advances `(x, v, stuck)` by `h` under the held force `f`, with stick and slip: a
    /// velocity that changes sign inside the step is stopped where it vanishes (bisection
    /// on the step length), and the mass sticks there while the net force on it (the held
    /// force and the hand's spring) is at most the static friction.
    fn step(&self, (x, v, stuck): (f64, f64, bool), f: f64, h: f64) -> (f64, f64, bool) {
        let friction = self.stiction > 0.0;
        if !friction {
            let (x, v) = self.rk4(x, v, f, 0.0, h);
            return (x, v, false);
        }
        if stuck || v == 0.0 {
            // the net force on the mass at rest: the held force and the hand's spring
            let net = f - self.hand.2 * x;
            if net.abs() <= self.stiction {
                return (x, 0.0, true);
            }
            let (x, v) = self.rk4(x, 0.0, f, net.signum(), h);
            return (x, v, false);
        }
        let dir = v.signum();
        let (x1, v1) = self.rk4(x, v, f, dir, h);
        if v1 * dir > 0.0 {
            return (x1, v1, false);
        }
        let (mut lo, mut hi) = (0.0, h);
        for _ in 0..80 {
            let mid = 0.5 * (lo + hi);
            if self.rk4(x, v, f, dir, mid).1 * dir > 0.0 {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        let (xs, _) = self.rk4(x, v, f, dir, hi);
        self.step((xs, 0.0, false), f, h - hi)
    }

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

    /// The readings over `samples` samples from rest at `x0` (or moving at `v0`).
    fn integrate(&self, x0: f64, v0: f64, samples: usize) -> Vec<f64> {
        let h = 1.0 / SUB as f64;
        let mut s = (x0, v0, false);
        let mut y = vec![self.read(x0)];
        let mut forces: Vec<f64> = Vec::new();
        let (mut w, mut y_prev) = (0.0, y[0]);
        for k in 0..samples {
            let yk = y[k];
            w = self.pole * w + (1.0 - self.pole) * (yk - y_prev);
            y_prev = yk;
            forces.push(self.hold(-(self.alpha * yk + self.beta * w)));
            let held = |j: isize| if j < 0 { 0.0 } else { forces[j as usize] };
            let late = held(k as isize - self.n as isize);
            let early = held(k as isize - self.n as isize - 1);
            for i in 0..SUB {
                let f = if (i as f64) < self.eps * SUB as f64 {
                    early
                } else {
                    late
                };
                s = self.step(s, f, h);
            }
            y.push(self.read(s.0));
        }
        y
    }

    fn quantization(&self) -> Quantization {
        Quantization::new(self.encoder, self.step, self.coulomb, self.stiction).unwrap()
    }

    fn library(&self) -> Loop {
        let plant = Plant::new(self.delta, self.n as f64 + self.eps).unwrap();
        let mut lp = Loop::new(plant);
        if self.hand != (0.0, 0.0, 0.0) {
            let (mu, dh, kh) = self.hand;
            lp = lp.with_hand(Hand::new(mu, dh, kh).unwrap()).unwrap();
        }
        if self.pole > 0.0 {
            lp = lp
                .with_filter(VelocityFilter::low_pass(self.pole).unwrap())
                .unwrap();
        }
        lp
    }
}

/// The stiffness `1 / s` of the way to the stiffness limit at damping `beta`.
fn inside(delta: f64, d: f64, beta: f64, s: f64) -> f64 {
    let c = Checker::new(Plant::new(delta, d).unwrap(), Options::default()).unwrap();
    alpha_limit(&c, beta).unwrap().unwrap() / s
}

fn cases() -> Vec<(&'static str, Case, Start)> {
    let near = inside(0.1, 1.0, 0.3, 1.3);
    let mut out = vec![
        (
            "stable, encoder",
            Case::paper(0.1, 1.0, 0.1, 0.3),
            Start::Rest(3.0),
        ),
        (
            "1.3 inside the stiffness limit, encoder",
            Case::paper(0.1, 1.0, near, 0.3),
            Start::Rest(3.0),
        ),
        (
            "undamped, impact",
            Case::paper(0.0, 1.0, inside(0.0, 1.0, 0.4, 1.5), 0.4),
            Start::Impact(1.0),
        ),
    ];
    let mut c = Case::paper(0.1, 1.0, near, 0.3);
    (c.coulomb, c.stiction) = (0.01, 0.015);
    out.push(("friction and stiction", c, Start::Rest(10.0)));
    let mut c = Case::paper(0.05, 0.5, inside(0.05, 0.5, 0.3, 1.2), 0.3);
    (c.coulomb, c.stiction) = (0.02, 0.02);
    out.push(("half a sample of delay, friction", c, Start::Rest(3.0)));
    let mut c = Case::paper(0.1, 1.0, 1.3 * inside(0.1, 1.0, 0.3, 1.0), 0.3);
    (c.coulomb, c.stiction) = (0.05, 0.08);
    out.push(("unstable wall, friction", c, Start::Rest(3.0)));
    let mut c = Case::paper(0.1, 1.0, near, 0.3);
    c.step = 0.02;
    out.push(("force steps and encoder", c, Start::Rest(3.0)));
    let mut c = Case::paper(0.1, 2.0, 0.6 * inside(0.1, 2.0, 0.2, 1.0), 0.2);
    (c.encoder, c.step, c.coulomb, c.stiction) = (false, 0.01, 0.004, 0.004);
    out.push((
        "force steps and friction, no encoder",
        c,
        Start::Impact(2.0),
    ));
    let mut c = Case::paper(0.1, 1.0, 0.08, 0.2);
    (c.hand, c.pole) = ((0.5, 0.05, 0.01), 0.3);
    out.push(("hand and low-pass filter, encoder", c, Start::Rest(10.0)));
    // friction with the elements: the hand's continuous states integrated between events
    let mut c = Case::paper(0.1, 1.0, 0.08, 0.2);
    (c.hand, c.coulomb, c.stiction) = ((0.5, 0.05, 0.01), 0.004, 0.006);
    out.push(("hand and friction, encoder", c, Start::Rest(10.0)));
    let mut c = Case::paper(0.1, 1.0, 0.08, 0.2);
    (c.pole, c.coulomb, c.stiction) = (0.3, 0.004, 0.006);
    out.push((
        "low-pass filter and friction, encoder",
        c,
        Start::Rest(10.0),
    ));
    let mut c = Case::paper(0.05, 0.5, 0.06, 0.25);
    (c.hand, c.pole, c.coulomb, c.stiction) = ((0.3, 0.02, 0.005), 0.2, 0.003, 0.003);
    out.push((
        "hand, filter and friction, half a sample of delay",
        c,
        Start::Impact(2.0),
    ));
    let mut c = Case::paper(0.1, 1.0, 0.05, 0.2);
    (c.encoder, c.hand, c.coulomb, c.stiction) = (false, (0.5, 0.05, 0.01), 0.002, 0.004);
    out.push(("hand and friction, no encoder", c, Start::Rest(10.0)));
    out
}

/// The library's readings equal the independent integration's, count for count.
#[test]
fn readings_match_independent_integration() {
    let samples = 600;
    for (name, case, start) in cases() {
        let (x0, v0) = match start {
            Start::Rest(x) => (x, 0.0),
            Start::Impact(v) => (0.0, v),
            _ => unreachable!(),
        };
        let want = case.integrate(x0, v0, samples);
        let got = readings(
            case.library(),
            &Wall::new(case.alpha, case.beta).unwrap(),
            &case.quantization(),
            start,
            samples,
        )
        .unwrap();
        // The library stops a run that passes 1e9 counts; the reference runs on.
        if got.len() < want.len() {
            assert!(
                want[got.len()].abs() > 1e8,
                "{name}: stopped at {}",
                got.len()
            );
        }
        // Up to a million counts: there RK4's relative 1e-12 is a millionth of a count.
        for (k, (g, w)) in got
            .iter()
            .zip(&want)
            .take_while(|(_, w)| w.abs() < 1e6)
            .enumerate()
        {
            if case.encoder {
                // integer readings: exactly equal
                assert_eq!(g, w, "{name}: sample {k}");
            } else {
                // exact closed form against RK4 at 1000 steps a sample (see SUB)
                assert!(
                    (g - w).abs() < 1e-9 * w.abs().max(1.0),
                    "{name}: sample {k}: {g} vs {w}"
                );
            }
        }
        // every case moves: the comparison is not of two constant sequences
        assert!(want.iter().any(|y| *y != want[0]), "{name}");
    }
}

/// Friction on the single mass by the elements' route (a hand of zero mass, damping and
/// stiffness: the continuous states, the matrix exponential and located events) reads what
/// the closed-form route of the paper's mass reads, count for count.
#[test]
fn friction_routes_agree() {
    for &(delta, d, beta, s, phi, stick) in &[
        (0.1, 1.0, 0.3, 1.3, 0.01, 0.015),
        (0.05, 0.5, 0.3, 1.2, 0.02, 0.02),
        (0.1, 1.0, 0.3, 0.8, 0.05, 0.08),
        (0.0, 2.0, 0.2, 1.1, 0.005, 0.01),
    ] {
        let plant = Plant::new(delta, d).unwrap();
        let wall = Wall::new(inside(delta, d, beta, s), beta).unwrap();
        let q = Quantization::new(true, 0.0, phi, stick).unwrap();
        let bare = Loop::new(plant);
        let zero_hand = bare.with_hand(Hand::new(0.0, 0.0, 0.0).unwrap()).unwrap();
        for start in [Start::Rest(3.0), Start::Rest(10.0), Start::Impact(1.0)] {
            let a = readings(bare, &wall, &q, start, 2000).unwrap();
            let b = readings(zero_hand, &wall, &q, start, 2000).unwrap();
            assert_eq!(a, b, "{delta} {d} {beta} {s} {start:?}");
            assert!(a.iter().any(|y| *y != a[0]));
        }
    }
}

/// No quantizer and no friction is the linear loop: the readings follow the powers of the
/// closed loop's state matrix (built from the exponential discretization, not the closed
/// forms the simulation uses: a hand of no mass, damping or stiffness leaves the device as it
/// is and takes the exponential's route), decaying on a stable wall and growing on an unstable one.
#[test]
fn no_quantizer_is_the_linear_loop() {
    let none = Quantization::new(false, 0.0, 0.0, 0.0).unwrap();
    for &(delta, d, beta, s) in &[
        (0.1, 1.0, 0.3, 1.5),
        (0.1, 1.0, 0.3, 0.9),
        (1.0, 0.0, 0.2, 1.2),
        (0.5, 2.5, 0.3, 0.95),
    ] {
        let alpha = inside(delta, d, beta, s);
        let plant = Plant::new(delta, d).unwrap();
        let wall = Wall::new(alpha, beta).unwrap();
        let y = readings(plant, &wall, &none, Start::Rest(1.0), 300).unwrap();
        let nothing = Hand::new(0.0, 0.0, 0.0).unwrap();
        let held = Loop::new(plant).with_hand(nothing).unwrap();
        assert!(!held.is_paper());
        let disc = Discretization::new(held).unwrap();
        let m = disc.state_matrix(&wall);
        let dim = m.nrows();
        let mut z = nalgebra::DVector::<f64>::zeros(dim);
        z[0] = 1.0; // position
        z[dim - 1] = 1.0; // the previous sample equals the first
        for (k, &yk) in y.iter().enumerate() {
            let scale = z[0].abs().max(1.0);
            // two exact discretizations by different routes: rounding, amplified by at most
            // the growth of 300 steps
            assert!(
                (yk - z[0]).abs() < 1e-8 * scale,
                "{delta} {d} {s} k {k}: {yk} vs {}",
                z[0]
            );
            z = &m * z;
        }
        let last = y.last().unwrap().abs();
        if s > 1.0 {
            assert!(last < 1e-2, "stable {delta} {d} {s}: {last}");
        } else {
            // started at 1: grown (the slowest case, 5 % inside, reaches about 7)
            assert!(last > 2.0, "unstable {delta} {d} {s}: {last}");
        }
    }
}

/// A wall the linear loop calls unstable, with an encoder and no friction, always ends
/// buzzing or diverged, whatever the start.
#[test]
fn unstable_without_friction_buzzes_or_diverges() {
    let q = Quantization::new(true, 0.0, 0.0, 0.0).unwrap();
    for &(delta, d, beta) in &[
        (0.0, 1.0, 0.4),
        (0.1, 1.0, 0.3),
        (1.0, 0.0, 0.5),
        (0.3, 1.5, 0.2),
    ] {
        for &s in &[0.95, 0.8, 0.5] {
            let plant = Plant::new(delta, d).unwrap();
            let wall = Wall::new(inside(delta, d, beta, s), beta).unwrap();
            let r = buzz(plant, &wall, &q, &BuzzOptions::default()).unwrap();
            assert!(
                r.runs.iter().all(|run| run.outcome != Outcome::Rest),
                "{delta} {d} {beta} {s}: {r:?}"
            );
        }
    }
}

/// A friction above every force the wall can apply near rest sticks the mass at its start:
/// a constant offset, not buzz.
#[test]
fn strong_friction_sticks_at_an_offset() {
    let plant = Plant::new(0.1, 1.0).unwrap();
    let wall = Wall::new(inside(0.1, 1.0, 0.3, 1.1), 0.3).unwrap();
    // the wall's force at 3 counts is about 3 alpha < 3
    let q = Quantization::new(true, 0.0, 2.0, 3.5).unwrap();
    let r = buzz(plant, &wall, &q, &BuzzOptions::default()).unwrap();
    assert!(!r.sustained(), "{r:?}");
    for run in &r.runs {
        if let Start::Rest(x0) = run.start {
            assert_eq!(run.peak_counts, x0, "{run:?}");
        }
    }
}

/// The buzz-free search at one damping: the wall it returns is quiet under the protocol,
/// below the linear limit, and a stiffer wall within the bracket's last step or beyond, up
/// to the linear limit, buzzes (the switch the bisection located).
#[test]
fn buzz_free_stiffness_is_quiet_and_a_stiffer_wall_buzzes() {
    use stabound::buzz::{BuzzFreeOptions, Nonlinear, buzz_free_alpha};
    use stabound::elements::PhysicalElements;
    use stabound::params::{Delay, Device};
    let device = Device::new(0.1, 1e-3, 10.0, Delay::Samples(1.0)).unwrap();
    let lp = Loop::physical(&device, &PhysicalElements::default()).unwrap();
    let mut n = Nonlinear::default();
    n.encoder_resolution = Some(1e-5);
    let opts = BuzzFreeOptions::default();
    let beta = 0.3;
    let r = buzz_free_alpha(lp, &n, beta, &opts, &|| ())
        .unwrap()
        .unwrap();
    let alpha = r.alpha.unwrap();
    assert!(alpha < r.linear_alpha);
    let judge = |a: f64| {
        let q = n.normalize(&device, device.stiffness(a)).unwrap();
        buzz(
            lp,
            &Wall::new(a, beta).unwrap(),
            &q,
            &BuzzOptions::default(),
        )
        .unwrap()
        .sustained()
    };
    assert!(!judge(alpha));
    // the bracket's buzzing end lies within a factor 1 + tol above
    let hi = alpha * (1.0 + opts.tol);
    let stiffer = (0..=20).map(|i| hi + (r.linear_alpha - hi) * i as f64 / 20.0);
    assert!(stiffer.clone().any(judge), "no buzz above {alpha}");
}

/// The loops with elements tested at the limits.
fn element_loops() -> Vec<(&'static str, Loop)> {
    use stabound::elements::Encoder;
    use stabound::elements::{Actuator, Transmission};
    let plant = Plant::new(0.1, 1.0).unwrap();
    let bare = Loop::new(plant);
    vec![
        (
            "hand",
            bare.with_hand(Hand::new(0.5, 0.05, 0.01).unwrap()).unwrap(),
        ),
        (
            "transmission",
            bare.with_transmission(Transmission::new(0.3, 4.0, 0.05, 0.0, Encoder::Motor).unwrap())
                .unwrap(),
        ),
        (
            "actuator lag",
            bare.with_actuator(Actuator::new(0.2).unwrap()).unwrap(),
        ),
    ]
}

/// Friction tending to zero on a loop with elements: the friction route (exact pieces,
/// located events) reads what the linear discretization reads with the encoder alone, count
/// for count, on a stable and an unstable wall.
#[test]
fn vanishing_friction_with_elements_is_the_quantized_linear_loop() {
    let encoder = Quantization::new(true, 0.0, 0.0, 0.0).unwrap();
    let tiny = Quantization::new(true, 0.0, 1e-13, 1e-13).unwrap();
    for (name, lp) in element_loops() {
        let c = Checker::new(lp, Options::default()).unwrap();
        let limit = alpha_limit(&c, 0.2).unwrap().unwrap();
        for s in [1.3, 0.9] {
            let wall = Wall::new(limit / s, 0.2).unwrap();
            let a = readings(lp, &wall, &encoder, Start::Rest(10.0), 400).unwrap();
            let b = readings(lp, &wall, &tiny, Start::Rest(10.0), 400).unwrap();
            let n = a.len().min(b.len());
            assert_eq!(a[..n], b[..n], "{name} {s}");
            assert!(a.iter().any(|y| *y != a[0]), "{name} {s}");
        }
    }
}

/// With elements too, a wall the linear loop calls unstable, with an encoder and no
/// friction, ends buzzing or diverged from every start.
#[test]
fn unstable_with_elements_without_friction_buzzes_or_diverges() {
    let q = Quantization::new(true, 0.0, 0.0, 0.0).unwrap();
    for (name, lp) in element_loops() {
        let c = Checker::new(lp, Options::default()).unwrap();
        let limit = alpha_limit(&c, 0.2).unwrap().unwrap();
        for s in [0.95, 0.7] {
            let wall = Wall::new(limit / s, 0.2).unwrap();
            let r = buzz(lp, &wall, &q, &BuzzOptions::default()).unwrap();
            assert!(
                r.runs.iter().all(|run| run.outcome != Outcome::Rest),
                "{name} {s}: {r:?}"
            );
        }
    }
}

/// A real wall whose quiet stiffnesses are not one interval: on the paper's device (0.1 kg,
/// 1 ms, 10 N s/m, one sample of delay) with a 10 um encoder at B = 30 N s/m, the protocol
/// finds K = 5450 N/m buzzing and K = 5500 N/m quiet above it (seen in a scan of K in steps
/// of 50 N/m). A search whose scan is fine enough to see such bands reports a quiet
/// stiffness beyond a buzzing one, returns a quiet wall below it, and a wall within the
/// bracket's last step above the answer buzzes.
#[test]
fn quiet_stiffnesses_that_are_not_one_interval() {
    use stabound::buzz::{BuzzFreeOptions, Nonlinear, buzz_free_alpha};
    use stabound::elements::PhysicalElements;
    use stabound::params::{Delay, Device};
    let device = Device::new(0.1, 1e-3, 10.0, Delay::Samples(1.0)).unwrap();
    let lp = Loop::physical(&device, &PhysicalElements::default()).unwrap();
    let mut n = Nonlinear::default();
    n.encoder_resolution = Some(1e-5);
    let b = 30.0;
    let quiet = |k: f64| {
        let q = n.normalize(&device, k).unwrap();
        let wall = device.wall(k, b).unwrap();
        !buzz(lp, &wall, &q, &BuzzOptions::default())
            .unwrap()
            .sustained()
    };
    assert!(!quiet(5450.0) && quiet(5500.0));
    let mut opts = BuzzFreeOptions::default();
    opts.scan_points = 200;
    let r = buzz_free_alpha(lp, &n, device.beta(b), &opts, &|| ())
        .unwrap()
        .unwrap();
    let alpha = r.alpha.unwrap();
    let beyond = r
        .quiet_beyond
        .expect("a quiet stiffness above a buzzing one");
    let (k, k_beyond) = (device.stiffness(alpha), device.stiffness(beyond));
    // by its definition the answer lies below every buzzing wall, 5450 N/m among them
    assert!(k < 5450.0 && k < k_beyond, "{k} {k_beyond}");
    assert!(quiet(k) && quiet(k_beyond), "{k} {k_beyond}");
    // the bracket's buzzing end lies within a factor 1 + tol above the answer
    let stiffer = (1..=10).map(|i| k * (1.0 + opts.tol * i as f64 / 10.0));
    assert!(stiffer.clone().any(|k| !quiet(k)), "no buzz just above {k}");
}
