//! The direct `alpha_max` search of loops with elements against three independent routes:
//! the rightmost vertex of the loop's traced exact boundary, the paper's closed form for the
//! bare loop built through the general polynomial, and the eigenvalues of the closed loop's
//! state matrix (built from the sampled device and the wall law, not from the polynomial):
//! a wall a relative `1e-6` below `alpha_max` at its damping is stable, and `1e-4` above it
//! no damping in a fine scan with local refinement stabilizes the loop.

use stabound::amax::{AmaxOptions, alpha_max, amax_report, margin_alpha_max, recommend};
use stabound::boundary::{ExactOptions, exact};
use stabound::elements::{Actuator, Encoder, Hand, Loop, PhysicalElements, Transmission};
use stabound::filter::VelocityFilter;
use stabound::params::{Delay, Device, Plant, Wall};
use stabound::search::alpha_limit;
use stabound::stability::{Checker, Options};

/// The spectral radius of the closed loop's state matrix at `(alpha, beta)`, from its
/// eigenvalues (nalgebra's real Schur form).
fn radius(c: &Checker, alpha: f64, beta: f64) -> f64 {
    c.state_matrix(&Wall::new(alpha, beta).unwrap())
        .complex_eigenvalues()
        .iter()
        .map(|z| z.norm())
        .fold(0.0, f64::max)
}

fn checker(lp: &Loop) -> Checker {
    Checker::new(lp, Options::default()).unwrap()
}

/// The smallest spectral radius over `beta` at stiffness `alpha`: a scan of 4001 dampings
/// over `[-span, span]`, then golden-section refinement around each of the five best local
/// minima of the scan.
fn best_radius(c: &Checker, alpha: f64, span: f64) -> (f64, f64) {
    best_radius_within(c, alpha, -span, span)
}

/// The smallest spectral radius over `beta` in `[lo, hi]` at stiffness `alpha`, as
/// [`best_radius`].
fn best_radius_within(c: &Checker, alpha: f64, lo: f64, hi: f64) -> (f64, f64) {
    let n = 4000;
    let at = |i: usize| lo + (hi - lo) * i as f64 / n as f64;
    let r: Vec<f64> = (0..=n).map(|i| radius(c, alpha, at(i))).collect();
    let mut minima: Vec<usize> = (0..=n)
        .filter(|&i| (i == 0 || r[i] <= r[i - 1]) && (i == n || r[i] <= r[i + 1]))
        .collect();
    minima.sort_by(|&a, &b| r[a].total_cmp(&r[b]));
    let mut best = (f64::INFINITY, 0.0);
    for &i in minima.iter().take(5) {
        let (mut lo, mut hi) = (at(i.saturating_sub(1)), at((i + 1).min(n)));
        let g = 0.5 * (5f64.sqrt() - 1.0);
        for _ in 0..80 {
            let (u, v) = (hi - g * (hi - lo), lo + g * (hi - lo));
            if radius(c, alpha, u) <= radius(c, alpha, v) {
                hi = v;
            } else {
                lo = u;
            }
        }
        let b = 0.5 * (lo + hi);
        let rb = radius(c, alpha, b).min(r[i]);
        if rb < best.0 {
            best = (rb, b);
        }
    }
    best
}

/// `alpha_max` holds by the eigenvalues: `1e-6` below it at its damping is stable; `1e-4`
/// above it nothing in `[-span, span]` is.
fn assert_holds(name: &str, lp: &Loop, span: f64) {
    let m = alpha_max(lp, &AmaxOptions::default()).unwrap();
    let c = checker(lp);
    let below = radius(&c, m.alpha_max * (1.0 - 1e-6), m.beta_at_max);
    assert!(below < 1.0, "{name}: {m:?}: radius {below} below alpha_max");
    let (above, beta) = best_radius(&c, m.alpha_max * (1.0 + 1e-4), span);
    assert!(
        above > 1.0,
        "{name}: {m:?}: radius {above} at beta {beta} above alpha_max"
    );
}

fn plant(delta: f64, d: f64) -> Loop {
    Loop::new(Plant::new(delta, d).unwrap())
}

/// The boundary tests' element loops (one per element, both encoder sides, both filters),
/// and a hand behind a low-pass filter, named for messages.
fn loops() -> Vec<(&'static str, Loop)> {
    let mut loops: Vec<_> = crate::loop_boundary::element_loops()
        .into_iter()
        .filter(|(name, _)| *name != "all elements")
        .collect();
    loops.push((
        "hand and filter",
        plant(0.5, 2.5)
            .with_hand(Hand::new(0.5, 0.05, 0.0).unwrap())
            .unwrap()
            .with_filter(VelocityFilter::low_pass(0.6).unwrap())
            .unwrap(),
    ));
    loops
}

/// The direct search against the rightmost vertex of the traced boundary at `1e-9`: every
/// vertex is on the boundary and the curve is within `tol` of its chords, so the true
/// maximum is at most `tol` (relative to the region's size, here about 1) above the vertex.
#[test]
fn direct_search_matches_the_traced_boundary() {
    for (name, lp) in loops() {
        let m = alpha_max(lp, &AmaxOptions::default()).unwrap();
        let b = exact(lp, &ExactOptions { tol: 1e-9 }).unwrap();
        let right = b
            .points
            .iter()
            .map(|p| p.x)
            .fold(f64::NEG_INFINITY, f64::max);
        let gap = m.alpha_max - right;
        assert!(
            (-1e-12..=2e-9).contains(&gap),
            "{name}: {m:?} vs vertex {right}"
        );
    }
}

/// The paper's loop through the general polynomial (the loop search) against the closed
/// form: the same point to `1e-9` relative, over delays short and long.
#[test]
fn paper_loop_through_the_general_polynomial() {
    for (delta, d) in [
        (0.0, 0.0),
        (0.1, 1.0),
        (1.0, 1.0),
        (0.5, 0.5),
        (3.0, 3.7),
        (11.25, 0.0),
        (30.0, 12.0),
        (0.01, 40.0),
    ] {
        let p = Plant::new(delta, d).unwrap();
        let want = alpha_max(p, &AmaxOptions::default()).unwrap();
        // a hand of zeros: the same device on the general polynomial
        let general = Loop::new(p)
            .with_hand(Hand::new(0.0, 0.0, 0.0).unwrap())
            .unwrap();
        let got = alpha_max(general, &AmaxOptions::default()).unwrap();
        let rel = (got.alpha_max - want.alpha_max).abs() / want.alpha_max;
        assert!(rel <= 1e-9, "({delta}, {d}): {got:?} vs {want:?}");
    }
}

/// Each element loop's `alpha_max` holds by the closed loop's eigenvalues.
#[test]
fn element_loops_hold_by_eigenvalues() {
    for (name, lp) in loops() {
        assert_holds(name, &lp, 20.0);
    }
}

/// The loop of a device in physical units with the elements `name` sets.
fn physical(
    mass: f64,
    period: f64,
    damping: f64,
    samples: f64,
    name: impl FnOnce(&mut PhysicalElements),
) -> Loop {
    let device = Device::new(mass, period, damping, Delay::Samples(samples)).unwrap();
    let mut named = PhysicalElements::default();
    name(&mut named);
    Loop::new(device.plant().unwrap())
        .with_physical(&device, &named)
        .unwrap()
}

/// Loops whose traced boundary did not close, or was refused as too large, now answer, and
/// their answers hold by the eigenvalues: a 16-sample moving average at no delay, a damped
/// hand at a delay of 9 samples, and a 0.1 Hz low-pass at `delta = 1000`.
#[test]
fn former_failures_answer_and_hold() {
    let average = physical(1.0, 1.0, 10.0, 0.0, |n| {
        n.velocity_filter_samples = Some(16)
    });
    assert_holds("16-sample average", &average, 400.0);
    let hand = physical(1.0, 1.0, 30.353117147339287, 9.0, |n| {
        n.hand_mass = Some(2.4121);
        n.hand_damping = Some(0.624);
        n.hand_stiffness = Some(0.131521);
    });
    assert_holds("damped hand at 9 samples", &hand, 200.0);
    let large = physical(1.0, 1.0, 1000.0, 1.0, |n| {
        n.velocity_filter_cutoff = Some(0.1)
    });
    assert_holds("delta 1000 behind a low-pass", &large, 8000.0);
}

/// Behind an 8-sample average the rightmost point is the tip of a thin wedge tilted off the
/// line of constant damping: at its damping no stiffness near it is stable, and 75 % of
/// `alpha_max` there is unstable (by the eigenvalues). The report says so (its stable set at
/// that damping does not reach `alpha_max`), and the best margin wall has every stiffness
/// from 75 % of it up to it stable at its damping.
#[test]
fn margin_wall_behind_a_wedge_is_stable() {
    let lp = physical(0.1, 1e-3, 50.0, 0.999, |n| {
        n.velocity_filter_samples = Some(8)
    });
    let c = checker(&lp);
    let opts = AmaxOptions::default();
    let r = amax_report(&lp, &opts).unwrap();
    let a = r.amax.alpha_max;
    assert!(
        !r.stable_alphas
            .iter()
            .any(|i| i.lo < 0.75 * a && i.hi >= a * (1.0 - 1e-9)),
        "{r:?}"
    );
    assert!(radius(&c, 0.75 * a, r.amax.beta_at_max) > 1.0);
    // every end of the reported set is on the boundary, by the eigenvalues
    for i in &r.stable_alphas {
        let w = i.hi - i.lo;
        assert!(
            radius(&c, i.lo + 1e-3 * w, r.amax.beta_at_max) < 1.0,
            "{i:?}"
        );
        assert!(
            radius(&c, i.hi - 1e-3 * w, r.amax.beta_at_max) < 1.0,
            "{i:?}"
        );
        assert!(
            radius(&c, i.hi + 1e-3 * w, r.amax.beta_at_max) > 1.0,
            "{i:?}"
        );
    }
    // the optimum needs negative damping: the best wall with beta >= 0 is beside it
    let nonneg = r.nonnegative.unwrap();
    assert!(nonneg.beta_at_max >= 0.0 && nonneg.alpha_max < r.amax.alpha_max);
    assert!(radius(&c, nonneg.alpha_max * (1.0 - 1e-6), nonneg.beta_at_max) < 1.0);

    let m = margin_alpha_max(&lp, &opts, 0.75).unwrap();
    assert!(m.alpha_max < r.amax.alpha_max);
    for k in 0..=400 {
        let a = m.alpha_max * (0.75 + 0.25 * (1.0 - 1e-6) * f64::from(k) / 400.0);
        let rho = radius(&c, a, m.beta_at_max);
        assert!(rho < 1.0, "{m:?}: radius {rho} at alpha {a}");
    }
}

/// The limit at a fixed damping is the top of the stable set there: stable `1e-6` below,
/// not `1e-6` above, by the eigenvalues.
#[test]
fn limit_at_a_damping_holds_by_eigenvalues() {
    for (name, lp) in loops() {
        let c = checker(&lp);
        let m = alpha_max(lp, &AmaxOptions::default()).unwrap();
        for f in [0.0, 0.5, 1.0, 1.5] {
            let beta = m.beta_at_max * f;
            let Some(a) = alpha_limit(&checker(&lp), beta).unwrap() else {
                continue;
            };
            assert!(
                radius(&c, a * (1.0 - 1e-6), beta) < 1.0,
                "{name} {beta}: {a}"
            );
            assert!(
                radius(&c, a * (1.0 + 1e-6), beta) > 1.0,
                "{name} {beta}: {a}"
            );
        }
    }
}

/// Behind a slow second-order low-pass (`f_c T = 0.03`) at `delta = 0.1` the rightmost
/// point is the tip of a sliver a few thousandths wide in `beta` between the curve's stretch
/// next to its pole (where it runs off to infinity) and another branch, whose scanned chords
/// miss the stretch by more than the sliver's width. The sliver is tilted off the line of
/// constant damping (its edges leave the tip at slopes of about `-7.5` and `-20` in the
/// plane), so the walls a relative `1e-6` below the tip lie beside its damping:
/// `alpha_max` holds by the closed loop's eigenvalues, a wall `1e-6` below it within
/// `2e-5` relative of its damping is stable (the best of a fine scan with golden-section
/// refinement), and `1e-4` above it no damping is, in a scan over `[-20, 20]` and in a scan
/// a thousand times finer within `0.02` of the optimum's damping, at one and at half a
/// sample of delay.
#[test]
fn sliver_beside_a_pole_of_the_curve() {
    for d in [1.0, 0.5] {
        let lp = plant(0.1, d)
            .with_filter(VelocityFilter::butterworth(0.03).unwrap())
            .unwrap();
        let m = alpha_max(lp, &AmaxOptions::default()).unwrap();
        let c = checker(&lp);
        let b = m.beta_at_max;
        // the fan of the neighbour tests reaches 16 relative steps of the damping's size
        let reach = 20.0 * 1e-6 * (m.alpha_max + b.abs());
        let (below, at) = best_radius_within(&c, m.alpha_max * (1.0 - 1e-6), b - reach, b + reach);
        assert!(
            below < 1.0,
            "d = {d}: {m:?}: radius {below} at beta {at} below alpha_max"
        );
        let above = m.alpha_max * (1.0 + 1e-4);
        for (lo, hi) in [(-20.0, 20.0), (b - 0.02, b + 0.02)] {
            let (rho, beta) = best_radius_within(&c, above, lo, hi);
            assert!(
                rho > 1.0,
                "d = {d}: {m:?}: radius {rho} at beta {beta} above alpha_max"
            );
        }
    }
}

/// A deterministic generator of uniform numbers in `[0, 1)` (64-bit LCG, Knuth's MMIX
/// constants; the top 53 bits).
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }

    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next()
    }
}

/// A random loop: plant, then each element with probability one half.
fn random_loop(g: &mut Lcg) -> Option<Loop> {
    let delta = 10f64.powf(g.range(-2.0, 1.5));
    let d = (g.range(0.0, 6.0) * 4.0).round() / 4.0 + if g.next() < 0.3 { 0.37 } else { 0.0 };
    let mut lp = Loop::new(Plant::new(delta, d).ok()?);
    if g.next() < 0.5 {
        let kappa = if g.next() < 0.5 {
            0.0
        } else {
            g.range(0.0, 0.05)
        };
        lp = lp
            .with_hand(Hand::new(g.range(0.1, 3.0), g.range(0.0, 1.0), kappa).ok()?)
            .ok()?;
    }
    if g.next() < 0.4 {
        let enc = if g.next() < 0.5 {
            Encoder::Motor
        } else {
            Encoder::Handle
        };
        let t = Transmission::new(
            g.range(0.1, 0.6),
            10f64.powf(g.range(0.5, 3.0)),
            g.range(0.0, 1.0),
            g.range(0.0, delta),
            enc,
        )
        .ok()?;
        lp = lp.with_transmission(t).ok()?;
    }
    if g.next() < 0.3 {
        lp = lp
            .with_actuator(Actuator::new(g.range(0.1, 3.0)).ok()?)
            .ok()?;
    }
    let f = g.next();
    if f < 0.3 {
        lp = lp
            .with_filter(VelocityFilter::low_pass(g.range(0.0, 0.95)).ok()?)
            .ok()?;
    } else if f < 0.5 {
        let n = 2 + (g.next() * 10.0) as usize;
        lp = lp
            .with_filter(VelocityFilter::moving_average(n).ok()?)
            .ok()?;
    }
    Some(lp)
}

/// A sweep of random loops (hands, transmissions, lags, filters, delays): every one answers;
/// where the report's stable set at the optimum's damping reaches `alpha_max`,
/// `alpha_max (1 - 1e-6)` there is stable by the closed loop's eigenvalues (where it does
/// not, the optimum is a tilted wedge's tip, and the eigenvalues confirm that wall
/// unstable); `1e-4` above `alpha_max` no damping in a dense scan over a span well beyond the
/// region stabilizes; the recommended 75 % wall is stable by the checker and by the
/// eigenvalues over its whole range, from the margin wall to `1e-6` below its top; and
/// `1e-6` below the recommended top at its damping is stable.
#[test]
fn random_loops_recommend_stable_walls() {
    let mut g = Lcg(0x005e_ed0f_a1fa);
    let opts = AmaxOptions::default();
    let (mut checked, mut tips, mut lowered) = (0, 0, 0);
    while checked < 300 {
        let Some(lp) = random_loop(&mut g) else {
            continue;
        };
        let r = amax_report(&lp, &opts).unwrap_or_else(|e| panic!("{lp:?}: {e}"));
        let m = r.amax;
        let c = checker(&lp);
        let top = m.alpha_max * (1.0 - 1e-6);
        let rho = radius(&c, top, m.beta_at_max);
        if r.stable_alphas.iter().any(|i| i.contains(top)) {
            assert!(rho < 1.0, "{lp:?}: {m:?}: radius {rho}");
        } else {
            assert!(rho > 1.0, "{lp:?}: {r:?}: radius {rho}");
            tips += 1;
        }
        // the region's dampings lie well inside this span (they scale with delta, the
        // optimum's damping and alpha_max)
        let span = 10.0 * (1.0 + lp.plant().delta() + m.beta_at_max.abs() + m.alpha_max);
        let (above, beta) = best_radius(&c, m.alpha_max * (1.0 + 1e-4), span);
        assert!(above > 1.0, "{lp:?}: {m:?}: radius {above} at beta {beta}");
        let w = recommend(&lp, &opts, 0.75).unwrap_or_else(|e| panic!("{lp:?}: {e}"));
        assert_eq!(w.report, r);
        assert!(w.top.alpha_max <= m.alpha_max);
        assert_eq!(w.wall.alpha(), 0.75 * w.top.alpha_max);
        if !w.at_optimum() {
            lowered += 1;
            assert_eq!(w.top, margin_alpha_max(&lp, &opts, 0.75).unwrap());
        }
        for k in 0..=20 {
            let a = w.top.alpha_max * (0.75 + 0.25 * (1.0 - 1e-6) * f64::from(k) / 20.0);
            let rho = radius(&c, a, w.top.beta_at_max);
            assert!(rho < 1.0, "{lp:?}: {w:?}: radius {rho} at {a}");
        }
        checked += 1;
    }
    // the sweep reaches the wedges it is about, and most optima are ordinary
    assert!(tips > 0 && tips < checked / 4, "{tips} of {checked}");
    assert!(lowered >= tips, "{lowered} lowered, {tips} tips");
}

/// The recommendation behind the wedge: not the fraction of `alpha_max` (unstable there),
/// a lower top at another damping, checked stable; the same wall [`margin_alpha_max`] gives.
#[test]
fn recommendation_behind_a_wedge() {
    let lp = physical(0.1, 1e-3, 50.0, 0.999, |n| {
        n.velocity_filter_samples = Some(8)
    });
    let opts = AmaxOptions::default();
    let w = recommend(&lp, &opts, 0.75).unwrap();
    assert!(!w.at_optimum() && !w.one_range());
    assert_eq!(w.top, margin_alpha_max(&lp, &opts, 0.75).unwrap());
    let c = checker(&lp);
    assert!(
        radius(
            &c,
            0.75 * w.report.amax.alpha_max,
            w.report.amax.beta_at_max
        ) > 1.0
    );
    assert!(radius(&c, w.wall.alpha(), w.wall.beta()) < 1.0);
    // the paper's loop: the paper's rule, the same bits as alpha_max
    let bare = plant(0.0, 1.0);
    let p = recommend(&bare, &opts, 0.75).unwrap();
    let a = alpha_max(bare, &opts).unwrap();
    assert!(p.at_optimum() && p.one_range() && p.report.nonnegative.is_none());
    assert_eq!(
        (p.wall.alpha(), p.wall.beta()),
        (0.75 * a.alpha_max, a.beta_at_max)
    );
    assert!(recommend(&bare, &opts, 0.0).is_err() && recommend(&bare, &opts, 1.5).is_err());
}
