//! The extremes of the parameter space, each test against an independent
//! reference named in its comment, with the accuracy reached printed (`--nocapture`) and
//! bounded by an assertion.

use stabound::amax::{AmaxOptions, alpha_max};
use stabound::params::{Plant, Wall};
use stabound::poly::CharPoly;
use stabound::stability::{Checker, Method, Options, Verdict, spectral_radius};

const METHODS: [Method; 5] = Method::ALL;

fn checker(delta: f64, d: f64, method: Method) -> Checker {
    Checker::new(
        Plant::new(delta, d).unwrap(),
        Options {
            method,
            ..Options::default()
        },
    )
    .unwrap()
}

/// Spectral radius by the closed-loop state matrix (no polynomial expansion).
fn ss_radius(delta: f64, d: f64, w: Wall) -> f64 {
    let c = checker(delta, d, Method::StateSpace);
    spectral_radius(&c.roots(&w, Method::StateSpace).unwrap())
}

fn amax(delta: f64, d: f64) -> (f64, f64) {
    let a = alpha_max(Plant::new(delta, d).unwrap(), &AmaxOptions::default()).unwrap();
    (a.alpha_max, a.beta_at_max)
}

/// delta -> 0: reference is the closed form at delta = 0, d = 0, alpha_max = 12 - 8 sqrt 2
/// at beta = 2 sqrt 2 - 2 (paper Remark 4, docs/MODEL.md section 6), and continuity: alpha_max
/// moves by O(delta) (its slope d alpha_max / d delta is below 2 at delta = 0 by Fig. 10), so
/// at delta = 1e-300, 1e-12, 1e-6 it must equal the limit to 2 delta + 1e-11.
/// d = 1 against the published 0.1445 (4 digits).
#[test]
fn small_delta_limit() {
    let s2 = 2f64.sqrt();
    let (a_ref, b_ref) = (12.0 - 8.0 * s2, 2.0 * s2 - 2.0);
    for delta in [0.0, 1e-300, 1e-12, 1e-6] {
        let (a, b) = amax(delta, 0.0);
        let err = (a - a_ref).abs();
        eprintln!(
            "delta {delta:e}, d 0: alpha_max {a:.15} error {err:.1e}, beta error {:.1e}",
            (b - b_ref).abs()
        );
        assert!(err <= 2.0 * delta + 1e-11, "delta {delta}: {a} vs {a_ref}");
        assert!(
            (b - b_ref).abs() <= 10.0 * delta + 1e-7,
            "delta {delta}: beta {b} vs {b_ref}"
        );
        let (a1, _) = amax(delta, 1.0);
        eprintln!("delta {delta:e}, d 1: alpha_max {a1:.6} (published 0.1445)");
        assert!((a1 - 0.1445).abs() < 5e-5 + 2.0 * delta);
        // The points 1e-6 (plus the continuity allowance 2 delta) inside and outside the limit
        // are judged alike by every method.
        let h = 1e-6 + 2.0 * delta;
        for m in METHODS {
            let c = checker(delta, 0.0, m);
            let inside = c.verdict(&Wall::new(a_ref - h, b_ref).unwrap()).unwrap();
            let outside = c.verdict(&Wall::new(a_ref + h, b_ref).unwrap()).unwrap();
            assert_eq!(inside, Verdict::Stable, "{m:?} {delta}");
            assert_eq!(outside, Verdict::Unstable, "{m:?} {delta}");
        }
    }
}

/// Large delta: reference is eq. (22), alpha_max ~ g(d) delta, so alpha_max / delta at 1e3
/// and 1e4 agree to 1 % (the intercept is O(1)), and the state-space eigenvalues (independent
/// of the D-decomposition) confirm the point 1 % inside as stable and 1 % outside as unstable.
#[test]
fn large_delta() {
    for d in [0.0, 1.0, 2.5] {
        let mut ratios = Vec::new();
        for delta in [1e2, 1e3, 1e4] {
            let (a, b) = amax(delta, d);
            let (w_in, w_out) = (
                Wall::new(0.99 * a, b).unwrap(),
                Wall::new(1.01 * a, b).unwrap(),
            );
            let inside = ss_radius(delta, d, w_in);
            let outside = ss_radius(delta, d, w_out);
            eprintln!(
                "delta {delta:e} d {d}: alpha_max/delta {:.6}, radius inside 1 - {:.2e}, outside 1 + {:.2e}",
                a / delta,
                1.0 - inside,
                outside - 1.0
            );
            // At large delta the stable region's radius tends to 1 everywhere (the slow root
            // of the heavily damped mass): 1 % inside alpha_max is still strictly inside, but
            // may lie within the 1e-9 marginal band. Every method must give the state-space
            // verdict, and never a confident one of the wrong sign.
            assert!(inside < 1.0 && outside > 1.0, "delta {delta} d {d}");
            for m in METHODS {
                let c = checker(delta, d, m);
                let (vi, vo) = (c.verdict(&w_in).unwrap(), c.verdict(&w_out).unwrap());
                assert_ne!(vi, Verdict::Unstable, "{m:?}");
                assert_ne!(vo, Verdict::Stable, "{m:?}");
                if (1.0 - inside) > 1e-8 {
                    assert_eq!(vi, Verdict::Stable, "{m:?}");
                }
                if (outside - 1.0) > 1e-8 {
                    assert_eq!(vo, Verdict::Unstable, "{m:?}");
                }
            }
            ratios.push(a / delta);
        }
        let spread = (ratios[2] - ratios[1]).abs() / ratios[2];
        eprintln!(
            "d {d}: g(d) ~ {:.6}, relative change 1e3 -> 1e4 {spread:.1e}",
            ratios[2]
        );
        assert!(spread < 0.01, "d {d}: {ratios:?}");
    }
}

/// Long and fractional delays, d = 0 to 200: reference is the closed-loop state-space
/// eigenvalues (docs/MODEL.md section 7: well-conditioned where q's coefficients are not). The
/// points 2 % inside and outside alpha_max (at its beta) must get the verdict of the
/// state-space radius from every method, the guarded default included.
#[test]
fn long_delays() {
    for (delta, d) in [
        (0.5, 0.0),
        (1.0, 0.5),
        (0.5, 3.25),
        (1.0, 20.0),
        (2.0, 57.5),
        (1.0, 100.0),
        (5.0, 200.0),
    ] {
        let (a, b) = amax(delta, d);
        for f in [0.98, 1.02] {
            let w = Wall::new(f * a, b).unwrap();
            let r = ss_radius(delta, d, w);
            let expect = Verdict::from_radius(r, 1e-9);
            eprintln!("delta {delta} d {d}: alpha_max {a:.6e}, x{f}: state-space radius {r:.12}");
            assert_eq!(
                expect,
                if f < 1.0 {
                    Verdict::Stable
                } else {
                    Verdict::Unstable
                }
            );
            let methods: &[Method] = if d > 60.0 {
                &[Method::Auto, Method::Eigen]
            } else {
                &METHODS
            };
            for &m in methods {
                let dec = checker(delta, d, m).decide(&w).unwrap();
                eprintln!(
                    "   {m:?}: {:?} by {:?}, fallback {}",
                    dec.verdict, dec.method, dec.fallback
                );
                assert_eq!(dec.verdict, expect, "{m:?} delta {delta} d {d} x{f}");
            }
        }
    }
}

/// alpha -> 0: q(1) = alpha QA(1) (docs/MODEL.md section 4), so a real root sits at
/// 1 - alpha QA(1)/q0'(1) + O(alpha^2), with q0 = q at alpha = 0. Reference: that first-order
/// formula, evaluated from the polynomial's value and derivative at z = 1 (not from any root
/// finder), against the state-space eigenvalue nearest 1. At alpha = 1e-12 the root is inside
/// the marginal band: every method says marginal, never stable.
#[test]
fn alpha_near_zero() {
    for (delta, d, beta) in [(0.5, 1.0, 0.2), (0.0, 0.0, 0.3), (2.0, 4.5, 1.0)] {
        let cp = CharPoly::new(Plant::new(delta, d).unwrap()).unwrap();
        let q0 = cp.coefficients(&Wall::new(0.0, beta).unwrap());
        let qa: Vec<f64> = (0..q0.len()).map(|i| cp.qa(i)).collect();
        let dq0: f64 = q0.iter().enumerate().map(|(i, c)| i as f64 * c).sum();
        let qa1: f64 = qa.iter().sum();
        for alpha in [1e-12, 1e-8, 1e-5] {
            let w = Wall::new(alpha, beta).unwrap();
            let c = checker(delta, d, Method::StateSpace);
            let roots = c.roots(&w, Method::StateSpace).unwrap();
            let near = roots
                .iter()
                .map(|z| (z - 1.0).norm())
                .fold(f64::INFINITY, f64::min);
            let predicted = alpha * (qa1 / dq0).abs();
            let err = (near - predicted).abs();
            eprintln!(
                "delta {delta} d {d} alpha {alpha:e}: 1 - root {near:.3e}, first order {predicted:.3e}, error {err:.1e}"
            );
            // second order in alpha plus eigenvalue rounding (1e-13 near a simple root)
            assert!(
                err <= 1e-13 + 1e2 * alpha * alpha + 1e-3 * predicted,
                "{err}"
            );
            if predicted < 1e-9 {
                for m in METHODS {
                    assert_eq!(
                        checker(delta, d, m).verdict(&w).unwrap(),
                        Verdict::Marginal,
                        "{m:?}"
                    );
                }
            }
        }
    }
}

/// beta -> -delta at small alpha: the stable region's lowest point at alpha -> 0 is
/// beta = -delta (paper eq. 19). Reference: eq. (19) and the state-space radius (the point
/// with beta = -delta + 1e-2 is stable at alpha = 1e-4, the point with beta = -delta - 1e-2
/// unstable), and the exact 1-D search's lower end tends to -delta as alpha -> 0.
#[test]
fn beta_near_minus_delta() {
    for (delta, d) in [(0.5, 0.0), (1.0, 1.0), (3.0, 2.5)] {
        let alpha = 1e-4;
        let above = ss_radius(delta, d, Wall::new(alpha, -delta + 1e-2).unwrap());
        let below = ss_radius(delta, d, Wall::new(alpha, -delta - 1e-2).unwrap());
        assert!(above < 1.0 && below > 1.0, "{delta} {d}: {above} {below}");
        let c = checker(delta, d, Method::Auto);
        for a in [1e-3, 1e-5, 1e-7] {
            let lo = stabound::search::stable_betas(&c, a).unwrap()[0].lo;
            eprintln!(
                "delta {delta} d {d} alpha {a:e}: lowest stable beta {lo:.9}, eq. 19 gap {:.1e}",
                lo + delta
            );
            // the lower edge leaves (0, -delta) with a finite slope: |lo + delta| = O(alpha)
            assert!((lo + delta).abs() <= 50.0 * a, "{lo}");
        }
    }
}

/// Points on the boundary: exact D-decomposition walls wall_on_circle(theta) have the root
/// e^{i theta} by construction (Cramer's rule); on the part of the curve that bounds the
/// stable region every method must say marginal, never a confident stable/unstable.
/// Reference for the radius: state-space eigenvalues, to 1e-12.
#[test]
fn boundary_points_are_marginal() {
    for (delta, d) in [(0.0, 0.0), (0.5, 1.0), (1.0, 4.0), (0.3, 2.5), (1.0, 30.0)] {
        let plant = Plant::new(delta, d).unwrap();
        let b = stabound::boundary::exact(plant, &Default::default()).unwrap();
        let mut worst = 0.0f64;
        let step = (b.points.len() / 25).max(1);
        for p in b
            .points
            .iter()
            .step_by(step)
            .filter(|p| p.x > 1e-6 && p.piece == stabound::boundary::Piece::Curve)
        {
            let w = Wall::new(p.x, p.y).unwrap();
            let r = ss_radius(delta, d, w);
            worst = worst.max((r - 1.0).abs());
            assert!((r - 1.0).abs() < 1e-10, "{delta} {d} {p:?}: {r}");
            for m in METHODS {
                let v = checker(delta, d, m).verdict(&w).unwrap();
                assert_eq!(v, Verdict::Marginal, "{m:?} delta {delta} d {d} {p:?}");
            }
        }
        eprintln!("delta {delta} d {d}: boundary points |radius - 1| <= {worst:.1e}");
    }
}

/// The guard must trigger where Schur-Cohn's error bound cannot vouch for the verdict:
/// stable points at long delays (the z^(n+2) term puts many roots near the circle and the
/// recursion's gaps fall to 1e-10). There the argument-principle count decides (or, where it
/// cannot be proven, the state-space eigenvalues), its verdict agrees with the state-space
/// radius computed here separately, and the decision says which method it was.
#[test]
fn guard_triggers_and_falls_back() {
    let mut triggered = 0;
    for (delta, d) in [(1.0, 60.0), (10.0, 100.0), (0.1, 150.0)] {
        let (a, b) = amax(delta, d);
        let w = Wall::new(0.5 * a, b).unwrap();
        let r = ss_radius(delta, d, w);
        let dec = checker(delta, d, Method::Auto).decide(&w).unwrap();
        eprintln!("delta {delta} d {d}: {dec:?}, state-space radius {r}");
        assert_eq!(dec.verdict, Verdict::from_radius(r, 1e-9));
        if dec.fallback {
            assert_eq!(dec.method, Method::ArgumentPrinciple);
            triggered += 1;
        }
        let an = checker(delta, d, Method::Auto).analyze(&w).unwrap();
        assert_eq!(
            (an.method, an.fallback, an.requested),
            (dec.method, dec.fallback, Method::Auto)
        );
    }
    assert!(triggered >= 2, "guard triggered {triggered} times of 3");
    // Short delays: the guard vouches, Schur-Cohn decides alone.
    let w = Wall::new(0.1, 0.3).unwrap();
    let dec = checker(0.5, 1.0, Method::Auto).decide(&w).unwrap();
    assert_eq!((dec.method, dec.fallback), (Method::SchurCohn, false));
}
