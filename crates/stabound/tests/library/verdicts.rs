//! Confident verdicts only where a method can vouch for them: the walls where a verdict used
//! to be decided by rounding (huge walls, near-double roots, margins below rounding, roots
//! that did not converge), the library's refusals of bad input, and a seeded comparison of
//! every method with an independent reference: the Schur-Cohn recursion in fixed-point
//! arithmetic of about a thousand bits (`num-bigint`) on the same `f64` coefficients.

use num_bigint::{BigInt, Sign};
use stabound::params::{Delay, Device, Normalized, Plant, Wall};
use stabound::poly::{CharPoly, Complex};
use stabound::stability::{
    Checker, MIN_MARGIN, MarginalReason, Method, Options, Verdict, check, spectral_radius,
};

/// Every method a user can choose, and the certified last stage.
const METHODS: [Method; 6] = [
    Method::Auto,
    Method::SchurCohn,
    Method::Eigen,
    Method::StateSpace,
    Method::ArgumentPrinciple,
    Method::Certified,
];

fn analyze(alpha: f64, beta: f64, delta: f64, d: f64, method: Method) -> stabound::Analysis {
    let p = Normalized::new(alpha, beta, delta, d).unwrap();
    check(
        &p,
        &Options {
            method,
            ..Options::default()
        },
    )
    .unwrap_or_else(|e| panic!("{method:?} {p:?}: {e}"))
}

/// The reference's verdict of the `f64` polynomial of `checker` for `wall` at `margin`.
fn reference(checker: &Checker, wall: &Wall, margin: f64) -> Option<Verdict> {
    let q = checker.coefficients(wall);
    let inner = reference::schur_cohn(&q, 1.0, -margin)?;
    if inner {
        return Some(Verdict::Stable);
    }
    let outer = reference::schur_cohn(&q, 1.0, margin)?;
    Some(if outer {
        Verdict::Marginal
    } else {
        Verdict::Unstable
    })
}

/// Huge walls: the stiffness is far outside every stable region, and every root found must
/// be a number. Before, `f64::MAX` came out stable with spectral radius 0 and NaN roots
/// (NaN dropped by `f64::max`), and `1e163` at d = 2.5 stable by state-space eigenvalues.
/// The reference confirms a root outside the circle for these exact coefficients.
#[test]
fn huge_walls_are_unstable_with_finite_roots() {
    for (alpha, d) in [(f64::MAX, 1.0), (1e163, 2.5), (1e172, 1.0), (-1e300, 0.0)] {
        let c = Checker::new(Plant::new(0.5, d).unwrap(), Options::default()).unwrap();
        let wall = Wall::new(alpha, 0.0).unwrap();
        assert_eq!(reference(&c, &wall, 1e-9), Some(Verdict::Unstable));
        for method in METHODS {
            let a = analyze(alpha, 0.0, 0.5, d, method);
            assert_eq!(a.verdict, Verdict::Unstable, "{method:?} {alpha} {d}");
            assert!(
                a.spectral_radius.is_finite() && a.spectral_radius > 1.0,
                "{a:?}"
            );
            assert!(a.roots.iter().all(|z| z.re.is_finite() && z.im.is_finite()));
        }
    }
}

/// The step command's wall of 1e172 N/m on a 1 kg device sampled at 1 kHz is alpha = 1e166:
/// not stable, and its simulated response indeed does not settle.
#[test]
fn huge_physical_wall_is_not_stable() {
    let device = Device::new(1.0, 1e-3, 1.0, Delay::Samples(1.0)).unwrap();
    let plant = device.plant().unwrap();
    let wall = device.wall(1e172, 0.0).unwrap();
    let v = Checker::new(plant, Options::default())
        .unwrap()
        .verdict(&wall)
        .unwrap();
    assert_eq!(v, Verdict::Unstable);
    let lp = stabound::Loop::physical(&device, &Default::default()).unwrap();
    let r = stabound::sim::step_response(&lp, 1e172, 0.0, &Default::default()).unwrap();
    assert_eq!(r.settling_time(0.02), None);
}

/// The double-root corner (beta near -delta, alpha near 0): two roots near z = 1 whose
/// positions the coefficients' rounding fixes only to about sqrt(eps) = 1.5e-8, fifteen
/// times the margin. Before, the state-space fallback decided them (the first unstable with
/// radius 1.0000000144, though the true radius is 1 - 1.43e-10). The reference shows the
/// `f64` polynomial's radius within 1e-7 of 1, so no side of the 1e-9 band can be vouched
/// for: every method must say marginal.
#[test]
fn double_root_corner_is_marginal() {
    for (alpha, beta, delta, d) in [
        (1e-12, -999999.999, 1e6, 2.5),
        (1e-300, -0.4999999995, 0.5, 0.0),
        (2.2250738585072014e-308, 1e-308, 1e-15, 1.0),
    ] {
        let c = Checker::new(Plant::new(delta, d).unwrap(), Options::default()).unwrap();
        let wall = Wall::new(alpha, beta).unwrap();
        // radius within 1e-7 of 1: not stable inside 1 - 1e-7, stable inside 1 + 1e-7
        assert_eq!(
            reference(&c, &wall, 1e-7),
            Some(Verdict::Marginal),
            "{wall:?}"
        );
        for method in METHODS {
            let a = analyze(alpha, beta, delta, d, method);
            assert_eq!(
                a.verdict,
                Verdict::Marginal,
                "{method:?} {alpha} {beta} {delta} {d}"
            );
            assert!(a.reason.is_some(), "{a:?}");
        }
    }
}

/// A margin below rounding (`1 + 1e-16 == 1`) is refused, with the smallest accepted one
/// in the message; the smallest accepted margin works and alpha = 0 is marginal there by
/// every method (z = 1 is a root of q whatever the rest: q(1) = alpha QA(1)).
#[test]
fn margins_below_rounding_are_refused() {
    let plant = Plant::new(0.5, 1.0).unwrap();
    for margin in [0.0, 1e-16, MIN_MARGIN / 2.0] {
        let opts = Options {
            margin,
            ..Options::default()
        };
        let e = Checker::new(plant, opts).unwrap_err();
        assert!(
            matches!(e, stabound::Error::InvalidParameter { name: "margin", .. }),
            "{e:?}"
        );
        assert!(e.to_string().contains(&format!("{MIN_MARGIN:e}")), "{e}");
    }
    for method in METHODS {
        let opts = Options {
            method,
            margin: MIN_MARGIN,
        };
        let v = Checker::new(plant, opts)
            .unwrap()
            .verdict(&Wall::new(0.0, 0.2).unwrap())
            .unwrap();
        assert_eq!(v, Verdict::Marginal, "{method:?}");
    }
}

/// alpha = beta = delta = 0 makes q = z^(n+2) (z - 1)^2 (c = 1): a double root at z = 1.
/// The state-space eigenvalues did not converge there and `check` failed on valid input;
/// now every method answers marginal with finite roots, two of them near 1 (a double root
/// is found to about sqrt(eps)) and the rest near 0 (a root of multiplicity n + 2 is found
/// to about eps^(1/(n+2))).
#[test]
fn defective_state_matrix_still_answers() {
    for d in [2.5, 12.5] {
        for method in METHODS {
            let a = analyze(0.0, 0.0, 0.0, d, method);
            assert_eq!(a.verdict, Verdict::Marginal, "{method:?} {d}");
            assert!((a.spectral_radius - 1.0).abs() < 1e-6, "{a:?}");
            let near_one = a.roots.iter().filter(|z| (*z - 1.0).norm() < 1e-6).count();
            assert_eq!(near_one, 2, "{method:?} {d} {:?}", a.roots);
            assert!(
                a.roots
                    .iter()
                    .all(|z| (*z - 1.0).norm() < 1e-6 || z.norm() < 0.5)
            );
        }
    }
    // the step command's device: delay 2.5 samples, no stiffness, no damping
    let device = Device::new(1.0, 1e-3, 0.0, Delay::Samples(2.5)).unwrap();
    let wall = device.wall(0.0, 0.0).unwrap();
    let c = Checker::new(device.plant().unwrap(), Options::default()).unwrap();
    assert_eq!(c.verdict(&wall).unwrap(), Verdict::Marginal);
}

/// The eigenvalue routines refuse what they cannot do instead of panicking or returning
/// NaN as a root, and a NaN root makes the spectral radius NaN, not the largest other one.
#[test]
fn eigen_routines_refuse_bad_input() {
    assert_eq!(stabound::stability::aberth(&[]), None);
    assert_eq!(stabound::stability::aberth(&[1.0]), None);
    assert_eq!(stabound::stability::aberth(&[1.0, 0.0]), None);
    assert_eq!(stabound::stability::aberth(&[1.0, f64::NAN, 1.0]), None);
    let m = nalgebra::DMatrix::<f64>::zeros(2, 3);
    assert_eq!(stabound::stability::eigenvalues_capped(m), None);
    assert!(spectral_radius(&[Complex::new(f64::NAN, 0.0), Complex::new(0.5, 0.0)]).is_nan());
    assert_eq!(spectral_radius(&[]), 0.0);
    // coefficients near the top of the range: roots, if any, are numbers
    for c in [
        [f64::MAX, -f64::MAX, 1.0],
        [f64::MAX, f64::MAX, 1.0],
        [1.0, f64::MAX, 1.0],
        [-f64::MAX, 0.0, 1.0],
    ] {
        if let Ok(roots) = stabound::stability::poly_roots(&c) {
            assert_eq!(roots.len(), 2);
            assert!(
                roots.iter().all(|z| z.re.is_finite() && z.im.is_finite()),
                "{c:?} {roots:?}"
            );
        }
    }
}

/// `MarginalReason::WithinMargin` only where a root is shown to be in the band: alpha = 0
/// (z = 1 is a root) with a wall otherwise stable, by the guarded recursion.
#[test]
fn proven_marginal_says_so() {
    let c = Checker::new(Plant::new(0.5, 1.0).unwrap(), Options::default()).unwrap();
    let dec = c.decide(&Wall::new(0.0, 0.2).unwrap()).unwrap();
    assert_eq!(dec.verdict, Verdict::Marginal);
    assert_eq!(dec.reason, Some(MarginalReason::WithinMargin));
    let dec = c.decide(&Wall::new(0.1, 0.3).unwrap()).unwrap();
    assert_eq!((dec.verdict, dec.reason), (Verdict::Stable, None));
}

/// Uniform numbers in `[0, 1)` from a fixed seed (xorshift64).
fn rng(mut seed: u64) -> impl FnMut() -> f64 {
    move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Seeded walls of five kinds against the reference: near the boundary (a wall with a root
/// exactly on the circle, moved by 1e-3 to 1e-15 relative), huge walls, the double-root
/// corner, margins down to `MIN_MARGIN`, and long delays (d up to 500, one case in 25). A
/// confident verdict of any method must agree with the reference wherever the reference
/// decides (it gives up only when a reflection coefficient is within its own error bound of
/// 1, about 2^-900); a verdict proven marginal must be marginal there too. The rate of
/// marginal verdicts that could not be decided is printed (`--nocapture`).
#[test]
fn verdicts_agree_with_the_reference() {
    let mut rnd = rng(0x9e37_79b9_7f4a_7c15);
    let kinds = [
        "edge",
        "huge",
        "corner",
        "tiny-margin",
        "long-delay",
        "ordinary",
    ];
    // per kind and method: [checked, undecided marginal]
    let mut stats = vec![[[0usize; 2]; 6]; kinds.len()];
    let mut reference_gave_up = 0;
    let cases = 1000;
    let mut confident = 0;
    for case in 0..cases {
        let kind = if case % 25 == 24 {
            4
        } else {
            [0, 1, 2, 3, 5][case % 5]
        };
        let log_uniform = |u: f64, lo: f64, hi: f64| 10f64.powf(lo + (hi - lo) * u);
        let mut margin = 1e-9;
        let (delta, d, wall) = match kind {
            0 | 3 | 4 => {
                let delta = if rnd() < 0.2 {
                    0.0
                } else {
                    log_uniform(rnd(), -3.0, 1.5)
                };
                let d = match kind {
                    4 => 100.0 + (400.0 * rnd()).round() + if rnd() < 0.5 { 0.5 } else { 0.0 },
                    _ => (8.0 * rnd() * 4.0).round() / 4.0,
                };
                if kind == 3 {
                    margin = MIN_MARGIN * log_uniform(rnd(), 0.0, 3.0);
                }
                let poly = CharPoly::new(Plant::new(delta, d).unwrap()).unwrap();
                let theta = 0.05 + 3.0 * rnd();
                let Some(w) = poly.wall_on_circle(theta) else {
                    continue;
                };
                let s = if rnd() < 0.5 { -1.0 } else { 1.0 };
                // half anywhere from 1e-15 to 1e-3, half near the band's edges
                let rel = if rnd() < 0.5 {
                    log_uniform(rnd(), -15.0, -3.0)
                } else {
                    margin * log_uniform(rnd(), -1.0, 1.0)
                };
                (
                    delta,
                    d,
                    Wall::new(w.alpha() * (1.0 + s * rel), w.beta()).unwrap(),
                )
            }
            1 => {
                let sa = if rnd() < 0.8 { 1.0 } else { -1.0 };
                let alpha = sa * log_uniform(rnd(), 50.0, 308.2).min(f64::MAX);
                let beta = if rnd() < 0.5 {
                    0.0
                } else {
                    (rnd() - 0.5) * log_uniform(rnd(), 0.0, 308.0)
                };
                (
                    log_uniform(rnd(), -3.0, 2.0),
                    (8.0 * rnd()).round() / 2.0,
                    Wall::new(alpha, beta).unwrap(),
                )
            }
            2 => {
                let delta = log_uniform(rnd(), -15.0, 9.0);
                let beta = -delta * (1.0 + (rnd() - 0.5) * log_uniform(rnd(), -15.0, -6.0));
                let alpha = log_uniform(rnd(), -300.0, -6.0);
                (
                    delta,
                    (4.0 * rnd()).round() / 2.0,
                    Wall::new(alpha, beta).unwrap(),
                )
            }
            _ => (
                5.0 * rnd(),
                (10.0 * rnd() * 2.0).round() / 2.0,
                Wall::new(5.0 * rnd() - 0.5, 2.0 * rnd() - 0.5).unwrap(),
            ),
        };
        let plant = Plant::new(delta, d).unwrap();
        let base = Checker::new(
            plant,
            Options {
                margin,
                ..Options::default()
            },
        )
        .unwrap();
        let Some(want) = reference(&base, &wall, margin) else {
            reference_gave_up += 1;
            continue;
        };
        // Eigenvalues of degree 500 cost a second or more: for long delays only the methods
        // whose common path has no eigenvalues.
        let methods: &[Method] = if kind == 4 && case % 75 != 74 {
            &[Method::Auto, Method::SchurCohn, Method::ArgumentPrinciple]
        } else {
            &METHODS
        };
        for &method in methods {
            let c = Checker::new(plant, Options { method, margin }).unwrap();
            let dec = c.decide(&wall).unwrap();
            let k = METHODS.iter().position(|&m| m == method).unwrap();
            stats[kind][k][0] += 1;
            match (dec.verdict, dec.reason) {
                (Verdict::Marginal, Some(MarginalReason::Undecided)) => stats[kind][k][1] += 1,
                (v, _) => {
                    confident += usize::from(v != Verdict::Marginal);
                    assert_eq!(
                        v, want,
                        "{method:?} ({:?}) {kind}: delta {delta} d {d} {wall:?} margin {margin}",
                        dec.method
                    )
                }
            }
        }
    }
    eprintln!("reference gave up on {reference_gave_up} of {cases} walls");
    eprintln!("{confident} confident verdicts, all agreeing with the reference");
    eprintln!("undecided marginal verdicts / walls checked, by kind and method:");
    for (kind, row) in kinds.iter().zip(&stats) {
        let cells: Vec<String> = METHODS
            .iter()
            .zip(row)
            .map(|(m, [n, u])| format!("{} {u}/{n}", m.name()))
            .collect();
        eprintln!("  {kind:12} {}", cells.join(", "));
    }
    assert!(reference_gave_up < cases / 10);
    // not vacuous: most walls away from the corner get a confident verdict
    assert!(confident > cases, "{confident}");
}

/// The reference: Schur-Cohn in fixed point with `F` fraction bits on big integers.
mod reference {
    use super::*;

    /// Fraction bits: `f64` values down to `2^-1074` and their products with radius powers
    /// are exact at the start.
    const F: u64 = 1200;

    fn fixed(x: f64) -> BigInt {
        // x = m 2^e exactly with integer m
        let bits = x.to_bits();
        let exp = ((bits >> 52) & 0x7ff) as i64;
        let frac = bits & ((1u64 << 52) - 1);
        let (m, e) = if exp == 0 {
            (frac, -1074)
        } else {
            (frac | (1u64 << 52), exp - 1075)
        };
        let m = BigInt::from(m) * if x < 0.0 { -1 } else { 1 };
        let shift = e + F as i64;
        if shift >= 0 {
            m << shift as u64
        } else {
            m >> (-shift) as u64
        }
    }

    fn one() -> BigInt {
        BigInt::from(1) << F
    }

    fn mul(a: &BigInt, b: &BigInt) -> BigInt {
        (a * b) >> F
    }

    fn div(a: &BigInt, b: &BigInt) -> BigInt {
        (a << F) / b
    }

    /// log2 of |a| as a fixed-point value (minus infinity for 0), to about one unit.
    fn lg(a: &BigInt) -> f64 {
        if a.sign() == Sign::NoSign {
            f64::NEG_INFINITY
        } else {
            a.bits() as f64 - F as f64
        }
    }

    /// Whether every root of `sum c_i z^i` lies inside `|z| < base + offset`, or `None` when
    /// a reflection coefficient is within the running error bound of 1 (the guard's first-
    /// order bound of the library's Schur-Cohn, with the unit roundoff 2^-F, in log2).
    pub fn schur_cohn(c: &[f64], base: f64, offset: f64) -> Option<bool> {
        let n = c.len() - 1;
        let r = fixed(base) + fixed(offset);
        let mut a: Vec<BigInt> = Vec::with_capacity(n + 1);
        let mut p = one();
        for &ci in c {
            a.push(mul(&fixed(ci), &p));
            p = mul(&p, &r);
        }
        let lead = a[n].clone();
        if lead.sign() == Sign::NoSign {
            return None;
        }
        for x in a.iter_mut() {
            *x = div(x, &lead);
        }
        a[n] = one();
        let amax = |a: &[BigInt]| a.iter().map(lg).fold(f64::NEG_INFINITY, f64::max);
        // error of the entries, log2: the radius powers and the division, n + 2 roundings
        let mut le = -(F as f64) + ((n + 2) as f64).log2() + amax(&a).max(0.0) + 2.0;
        for deg in (1..=n).rev() {
            let k = a[0].clone();
            let gap = one() - BigInt::from(k.magnitude().clone());
            let lgap = lg(&gap);
            if le + 2.0 >= lgap {
                return None;
            }
            if gap.sign() == Sign::Minus {
                return Some(false);
            }
            let dd = one() - mul(&k, &k);
            let (lk, ld, la) = (lg(&k), lg(&dd), amax(&a[..=deg]).max(0.0));
            let l1k = lk.max(0.0) + 1.0;
            let t1 = le + l1k + la + 1.0 - ld;
            let t2 = le + 1.0 + lk + la + l1k - 2.0 * ld;
            let t3 = -(F as f64) + 3.0 + la + l1k - ld;
            le = t1.max(t2).max(t3) + 2.0;
            let next: Vec<BigInt> = (0..deg)
                .map(|j| div(&(&a[j + 1] - mul(&k, &a[deg - 1 - j])), &dd))
                .collect();
            a = next;
            // monic by construction: (1 - k^2) / (1 - k^2)
            a[deg - 1] = one();
        }
        Some(true)
    }

    /// The reference decides known polynomials: (z - 0.5)(z + 0.9)(z - 0.99) is stable, the
    /// same with 1.01 is not, and a root 1e-12 inside the circle is resolved.
    #[test]
    fn reference_decides_known_roots() {
        // (z - 0.5)(z + 0.9)(z - r) = z^3 - e1 z^2 + e2 z - e3
        let p = |r: f64| {
            let e1 = 0.5 - 0.9 + r;
            let e2 = 0.5 * -0.9 + 0.5 * r - 0.9 * r;
            let e3 = 0.5 * -0.9 * r;
            [-e3, e2, -e1, 1.0]
        };
        assert_eq!(schur_cohn(&p(0.99), 1.0, 0.0), Some(true));
        assert_eq!(schur_cohn(&p(1.01), 1.0, 0.0), Some(false));
        assert_eq!(schur_cohn(&p(1.0 - 1e-12), 1.0, 0.0), Some(true));
        assert_eq!(schur_cohn(&p(1.0 - 1e-12), 1.0, -1e-11), Some(false));
        assert_eq!(schur_cohn(&[0.5, 1.0], 1.0, 0.0), Some(true));
        assert_eq!(schur_cohn(&[-1.5, 1.0], 1.0, 0.0), Some(false));
    }
}
