//! Independent checks of the characteristic polynomial and the stability tests:
//! state-space eigenvalues against the roots of `q`, Schur-Cohn against eigenvalues,
//! continuity at delta -> 0 and at d -> integer.

use stabound::model::Discretization;
use stabound::params::{Plant, Wall};
use stabound::poly::{CharPoly, Complex};
use stabound::stability::{Checker, Method, Options, Verdict, schur_cohn, spectral_radius};
use stabound::stability::{eigenvalues_capped, poly_roots};

/// splitmix64: a small deterministic generator so the tests need no extra crate.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next()
    }
}

/// |q(z)| relative to the size of its terms: near rounding level means `z` is a root.
fn relative_residual(q: &[f64], z: Complex) -> f64 {
    let mut acc = Complex::new(0.0, 0.0);
    let mut scale = 0.0;
    let r = z.norm();
    for (i, &c) in q.iter().enumerate().rev() {
        acc = acc * z + c;
        scale += c.abs() * r.powi(i as i32);
    }
    acc.norm() / scale
}

/// The closed-loop state matrix is built from docs/MODEL.md section 2 without expanding `q`; its
/// eigenvalues must be roots of `q` (same count, each a root to rounding), fractional d too.
#[test]
fn state_space_eigenvalues_are_roots_of_q() {
    let mut rng = Rng(1);
    for _ in 0..400 {
        let delta = rng.range(0.0, 5.0);
        let d = if rng.next() < 0.3 {
            rng.range(0.0, 12.0).floor()
        } else {
            rng.range(0.0, 12.0)
        };
        let plant = Plant::new(delta, d).unwrap();
        let wall = Wall::new(rng.range(0.0, 2.0), rng.range(-1.0, 2.0)).unwrap();
        let cp = CharPoly::new(plant).unwrap();
        let q = cp.coefficients(&wall);
        let a = Discretization::new(plant).unwrap().state_matrix(&wall);
        let eig = eigenvalues_capped(a).unwrap();
        assert_eq!(eig.len(), cp.degree(), "delta {delta} d {d}");
        for z in &eig {
            // 1e-10: the residual of a backward-stable eigenvalue is O(n eps) relative to the
            // terms; clustered roots can cost a few digits more, not six.
            let res = relative_residual(&q, *z);
            assert!(
                res < 1e-10,
                "delta {delta} d {d} {wall:?}: {z} residual {res}"
            );
        }
        let roots = poly_roots(&q).unwrap();
        let (r1, r2) = (spectral_radius(&eig), spectral_radius(&roots));
        assert!((r1 - r2).abs() < 1e-6, "{r1} vs {r2}");
    }
}

/// Schur-Cohn and companion eigenvalues agree on 100,000 random points away from the
/// boundary (spectral radius farther than 1e-6 from 1), degrees 3 to 30.
#[test]
fn schur_cohn_agrees_with_eigenvalues() {
    let mut rng = Rng(2);
    let mut compared = 0;
    let mut per_degree = [0usize; 31];
    let mut buf = [0.0; stabound::poly::MAX_COEFFS];
    while compared < 100_000 {
        let delta = if rng.next() < 0.1 {
            0.0
        } else {
            rng.range(0.0, 6.0)
        };
        // d in [0, 27): degrees n + 3 (integer) and n + 4 (fractional) span 3..=30
        let d = if rng.next() < 0.3 {
            rng.range(0.0, 27.0).floor()
        } else {
            rng.range(0.0, 26.999)
        };
        let plant = Plant::new(delta, d).unwrap();
        let cp = CharPoly::new(plant).unwrap();
        // walls spread across and beyond the stable region of every (delta, d)
        let scale = 0.05 + delta;
        let wall = Wall::new(rng.range(0.0, 1.5 * scale), rng.range(-scale, 2.0 * scale)).unwrap();
        let q = cp.coefficients_into(&wall, &mut buf);
        let roots = poly_roots(q).unwrap();
        let rho = spectral_radius(&roots);
        if (rho - 1.0).abs() < 1e-6 {
            continue;
        }
        let sc = schur_cohn(q, 1.0).stable;
        assert_eq!(sc, rho < 1.0, "delta {delta} d {d} {wall:?} rho {rho}");
        per_degree[cp.degree()] += 1;
        compared += 1;
    }
    // every degree from 3 to 30 took part, with both verdicts overall
    for (deg, &n) in per_degree.iter().enumerate().skip(3) {
        assert!(n > 100, "degree {deg}: only {n} points");
    }
}

/// delta -> 0: coefficients at delta = 1e-300, 1e-12, 1e-6 approach those at delta = 0
/// linearly (the q form is analytic in delta), for integer and fractional d.
#[test]
fn continuous_at_zero_damping() {
    for &d in &[0.0, 1.0, 2.5, 4.0, 7.3] {
        let wall = Wall::new(0.2, 0.4).unwrap();
        let q0 = CharPoly::new(Plant::new(0.0, d).unwrap())
            .unwrap()
            .coefficients(&wall);
        for &delta in &[1e-300, 1e-12, 1e-6] {
            let q = CharPoly::new(Plant::new(delta, d).unwrap())
                .unwrap()
                .coefficients(&wall);
            for (a, b) in q.iter().zip(&q0) {
                // first-order change: coefficients are O(1) with O(1) derivatives in delta
                assert!(
                    (a - b).abs() <= 4.0 * delta + 1e-15,
                    "d {d} delta {delta}: {a} vs {b}"
                );
            }
        }
        // the verdicts and spectral radii agree too
        let c0 = Checker::new(Plant::new(0.0, d).unwrap(), Options::default()).unwrap();
        let c1 = Checker::new(Plant::new(1e-12, d).unwrap(), Options::default()).unwrap();
        let w = Wall::new(0.05, 0.3).unwrap();
        let (r0, r1) = (
            c0.spectral_radius_schur_cohn(&w),
            c1.spectral_radius_schur_cohn(&w),
        );
        assert!((r0 - r1).abs() < 1e-9, "d {d}: {r0} vs {r1}");
    }
}

/// d -> n from below: the degree stays n + 3 and the coefficients converge to the integer
/// case. From above: the degree is n + 4 and q -> z q_n (the undivided form).
#[test]
fn continuous_across_integer_delay() {
    let wall = Wall::new(0.3, 0.5).unwrap();
    for &delta in &[0.0, 0.3, 2.0] {
        for n in 1..5usize {
            let qn = CharPoly::new(Plant::new(delta, n as f64).unwrap())
                .unwrap()
                .coefficients(&wall);
            for &h in &[1e-6, 1e-9, 1e-12] {
                let below = CharPoly::new(Plant::new(delta, n as f64 - h).unwrap())
                    .unwrap()
                    .coefficients(&wall);
                let above = CharPoly::new(Plant::new(delta, n as f64 + h).unwrap())
                    .unwrap()
                    .coefficients(&wall);
                assert_eq!(below.len(), qn.len());
                assert_eq!(above.len(), qn.len() + 1);
                // coefficients are smooth in eps with O(1) derivatives: change O(h)
                for (i, &c) in qn.iter().enumerate() {
                    assert!((below[i] - c).abs() <= 4.0 * h, "below {i}");
                    assert!((above[i + 1] - c).abs() <= 4.0 * h, "above {i}");
                }
                assert!(above[0].abs() <= 4.0 * h);
            }
        }
    }
}

/// The three methods reach the same verdict on points clearly inside or outside, across
/// fractional delays (the state space is the independent route for eps > 0).
#[test]
fn methods_agree_on_verdicts() {
    let mut rng = Rng(3);
    let mut n = 0;
    while n < 2000 {
        let plant = Plant::new(rng.range(0.0, 3.0), rng.range(0.0, 8.0)).unwrap();
        let wall = Wall::new(rng.range(0.0, 1.0), rng.range(-0.5, 1.5)).unwrap();
        let verdict = |method| {
            Checker::new(
                plant,
                Options {
                    method,
                    margin: 1e-6,
                },
            )
            .unwrap()
            .verdict(&wall)
            .unwrap()
        };
        let v = verdict(Method::StateSpace);
        if v == Verdict::Marginal {
            continue;
        }
        assert_eq!(verdict(Method::SchurCohn), v, "{plant:?} {wall:?}");
        assert_eq!(verdict(Method::Eigen), v, "{plant:?} {wall:?}");
        assert_eq!(verdict(Method::ArgumentPrinciple), v, "{plant:?} {wall:?}");
        n += 1;
    }
}
