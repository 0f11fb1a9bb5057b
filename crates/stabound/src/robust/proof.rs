//! A proof that one wall is stable for every member of a box of devices (the box recursion
//! of docs/MODEL.md section 11, over the parameters of section 12).
//!
//! # Method
//!
//! For the paper's loop (no elements) whose set spreads only mass `m` and damping `b`, a
//! wall given in the set's reference normalization `(alpha, beta)` is, for the member
//! `(m, b)`, the polynomial `q = Q0 + alpha' QA + beta' QB` of section 3 with
//! `alpha' = alpha m_ref / m`, `beta' = beta m_ref / m` and `delta = b T / m`. Over a cell
//! `[m0, m1] x [b0, b1]` each of the three is enclosed in outward-rounded interval
//! arithmetic (they are monotone in `m` and `b`, so the cell maps into the box of the
//! enclosures); the discretization values `c = exp(-delta)`, `phi1`, `phi2` are enclosed over
//! the interval of `delta` by their monotonicity (`certificate::interval`). The interval
//! Schur-Cohn recursion (`certificate::schur`; Schur 1917, Cohn 1922) then counts the roots
//! outside the unit circle for every polynomial in the enclosures at once: no root outside
//! and every step decided proves the cell; roots outside for all of them refute it; an
//! undecided cell is bisected along its relatively widest side, breadth-first, until the
//! budget of cells runs out.

use std::collections::VecDeque;

use super::{DeviceSet, Quantity};
use crate::certificate::interval::Interval;
use crate::certificate::paper_parts_over;
use crate::certificate::schur::recursion;
use crate::error::Result;
use crate::params::Wall;

/// The cells [`prove_wall`] examines at most when the verification of a robust answer
/// calls it. The cells concentrate where the room is least: a wall `1e-3` below the optimum
/// needs cells of about that relative width there, about a thousand for one spread
/// parameter; two spread parameters multiply the cells along the binding edge and usually
/// exhaust the budget, and the answer keeps the sampling argument. Each cell costs tens of
/// microseconds, so the budget costs a fraction of a second at most.
pub const PROOF_BUDGET: usize = 4096;

/// One cell of the box recursion: a mass interval and a damping interval (each may be one
/// value), in physical units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ProofCell {
    /// `[lo, hi]` of the mass `m`, kg.
    pub mass: (f64, f64),
    /// `[lo, hi]` of the damping `b`, N s/m.
    pub damping: (f64, f64),
    /// Whether the wall was proved stable for every member of the cell.
    pub stable: bool,
}

/// The outcome of [`prove_wall`].
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct Proof {
    /// Whether the wall was proved stable for every member of the set.
    pub proved: bool,
    /// The leaves of the recursion: they cover each box of the set. When `proved`, each is
    /// stable; otherwise the refuted or undecided ones are not.
    pub leaves: Vec<ProofCell>,
    /// Cells examined (leaves and the cells bisected on the way).
    pub evaluated: usize,
}

/// One box of a qualifying set: its mass and damping intervals, the sampling period and the
/// delay factor (one value for the box).
struct PaperBox {
    mass: (f64, f64),
    damping: (f64, f64),
    period: f64,
    d: f64,
}

/// The boxes of `set` when the proof applies to it: the paper's loop only, no hand to let
/// go, and nothing spread over an interval but mass and damping.
fn boxes(set: &DeviceSet) -> Result<Option<Vec<PaperBox>>> {
    if set.may_let_go {
        return Ok(None);
    }
    let mut out = Vec::new();
    for v in set.variants() {
        let dev = v.base.device;
        if !v.base.to_loop()?.is_paper() {
            return Ok(None);
        }
        let mut b = PaperBox {
            mass: (dev.mass, dev.mass),
            damping: (dev.damping, dev.damping),
            period: dev.period,
            d: dev.plant()?.d(),
        };
        for &(q, lo, hi) in &v.dims {
            match q {
                Quantity::Mass => b.mass = (lo, hi),
                Quantity::Damping => b.damping = (lo, hi),
                _ => return Ok(None),
            }
        }
        out.push(b);
    }
    Ok(Some(out))
}

/// The root count of the wall over one cell: `Some(0)` proves it stable, `Some(k > 0)`
/// refutes it for every member, `None` leaves it undecided.
fn outside(
    wall: &Wall,
    m_ref: f64,
    b: &PaperBox,
    m: (f64, f64),
    damp: (f64, f64),
) -> Option<usize> {
    let inv_m = Interval::point(1.0) / Interval::new(m.0, m.1);
    let scale = Interval::point(m_ref) * inv_m;
    let a = Interval::point(wall.alpha()) * scale;
    let beta = Interval::point(wall.beta()) * scale;
    let delta = (Interval::new(damp.0, damp.1) * Interval::point(b.period) * inv_m).nonneg();
    let coeffs = paper_parts_over(delta, b.d).at(a, beta);
    if rouche(&coeffs) {
        return Some(0);
    }
    recursion(&coeffs).outside
}

/// Whether every polynomial in the enclosures `coeffs` (lowest power first) has all its
/// roots inside the unit circle, by Rouché's theorem around their midpoints: the midpoint
/// polynomial `p` is proved stable by the interval Schur-Cohn recursion (its coefficients are
/// exact), and on the circle `|p(z)|` exceeds `sum_i rad_i`, which bounds `|q(z) - p(z)|` for
/// every `q` in the enclosures; then `q` has as many roots inside as `p`, all of them. The
/// interval recursion alone loses the correlation between its steps' coefficients; this
/// test's cost in width is only the radii.
///
/// `|p|` on the circle is bounded below arc by arc: on an arc of half-width `h` it is at least
/// its value at the middle less `h sum_i i |a_i|` (the bound on its derivative in the angle);
/// an arc where that falls short is halved ([`arc_clears`]). The points are evaluated
/// in `f64`; `1e-13 (sum_i |a_i| + sum_i i |a_i|)` bounds that rounding (Horner's error is at
/// most `2 k` units of `2^-53` times `sum_i |a_i|` for degree `k`, and the computed points lie
/// within a few units of the circle), with a margin for degrees up to several hundred.
fn rouche(coeffs: &[Interval]) -> bool {
    let Some(balls) = coeffs.iter().map(|c| c.ball()).collect::<Option<Vec<_>>>() else {
        return false;
    };
    let mid: Vec<Interval> = balls.iter().map(|&(m, _)| Interval::point(m)).collect();
    if recursion(&mid).outside != Some(0) {
        return false;
    }
    // each sum of a few nonnegative terms rounds by far less than the factor 1 + 1e-12
    let widen = 1.0 + 1e-12;
    let spread: f64 = balls.iter().map(|&(_, r)| r).sum::<f64>() * widen;
    let size: f64 = balls.iter().map(|&(m, _)| m.abs()).sum();
    let slope: f64 = balls
        .iter()
        .enumerate()
        .map(|(i, &(m, _))| i as f64 * m.abs())
        .sum::<f64>()
        * widen;
    let need = spread + 1e-13 * (size + slope);
    let modulus = |theta: f64| {
        let (sin, cos) = theta.sin_cos();
        let (mut re, mut im) = (0.0f64, 0.0f64);
        for &(m, _) in balls.iter().rev() {
            (re, im) = (re * cos - im * sin + m, re * sin + im * cos);
        }
        re.hypot(im)
    };
    let h = std::f64::consts::PI / COARSE as f64;
    (0..COARSE).all(|j| arc_clears(&modulus, 2.0 * h * j as f64, h, slope, need, DEPTH))
}

/// Whether `|p| > need` on the arc of angles `[theta - h, theta + h]`, where `|p|` changes
/// by at most `slope` per radian: from its value at the middle, or by halving the arc at
/// most `depth` more times (only where the bound is short, so near the minimum).
fn arc_clears(
    modulus: &impl Fn(f64) -> f64,
    theta: f64,
    h: f64,
    slope: f64,
    need: f64,
    depth: u32,
) -> bool {
    let v = modulus(theta);
    if v <= need {
        return false;
    }
    if v - slope * h > need {
        return true;
    }
    depth > 0
        && arc_clears(modulus, theta - 0.5 * h, 0.5 * h, slope, need, depth - 1)
        && arc_clears(modulus, theta + 0.5 * h, 0.5 * h, slope, need, depth - 1)
}

/// Arcs of the circle for the first lower bound of `|p|` in [`rouche`].
const COARSE: usize = 64;

/// The most halvings of an arc in [`rouche`]: arcs down to `pi / 64 / 2^16` (about 7e-7
/// rad) near the minimum; a cell that needs finer ones has too little room for its width
/// and is split instead.
const DEPTH: u32 = 16;

/// Proves `wall` (in the set's reference normalization, as [`super::robust_check`] takes
/// it) stable for every member of `set` by the box recursion (module documentation),
/// examining at most `budget` cells. `None` when the set is outside what the recursion
/// handles: a loop with elements, a hand that may let go, or a spread delay or element
/// parameter.
///
/// ```
/// use stabound::elements::PhysicalElements;
/// use stabound::params::{Delay, Device, Wall};
/// use stabound::robust::{DeviceSet, Quantity, prove_wall};
///
/// let device = Device::new(0.09, 1e-3, 0.0, Delay::Samples(1.0))?;
/// let set = DeviceSet::new(&device, &PhysicalElements::default())?
///     .with_interval(Quantity::Mass, 0.09, 0.11)?;
/// let p = prove_wall(&set, &Wall::new(0.1, 0.4)?, 1000)?.expect("the paper's loop");
/// assert!(p.proved);
/// # Ok::<(), stabound::Error>(())
/// ```
///
/// # Errors
///
/// As [`crate::elements::Loop::physical`] for a member.
pub fn prove_wall(set: &DeviceSet, wall: &Wall, budget: usize) -> Result<Option<Proof>> {
    let Some(boxes) = boxes(set)? else {
        return Ok(None);
    };
    let m_ref = set.device.mass;
    let mut leaves = Vec::new();
    let mut evaluated = 0;
    let mut proved = true;
    for b in &boxes {
        let mut queue = VecDeque::from([(b.mass, b.damping)]);
        while let Some((m, damp)) = queue.pop_front() {
            evaluated += 1;
            let count = if proved && evaluated <= budget {
                outside(wall, m_ref, b, m, damp)
            } else {
                None
            };
            let leaf = |stable| ProofCell {
                mass: m,
                damping: damp,
                stable,
            };
            match count {
                Some(0) => leaves.push(leaf(true)),
                Some(_) => {
                    proved = false;
                    leaves.push(leaf(false));
                }
                None if !proved || evaluated >= budget => {
                    proved = false;
                    leaves.push(leaf(false));
                }
                None => {
                    // split the side widest relative to the box's own
                    let rel = |c: (f64, f64), whole: (f64, f64)| {
                        if whole.1 > whole.0 {
                            (c.1 - c.0) / (whole.1 - whole.0)
                        } else {
                            0.0
                        }
                    };
                    let (rm, rb) = (rel(m, b.mass), rel(damp, b.damping));
                    if rm <= 0.0 && rb <= 0.0 {
                        // one member and still undecided: nothing to split
                        proved = false;
                        leaves.push(leaf(false));
                    } else if rm >= rb {
                        let mid = 0.5 * (m.0 + m.1);
                        queue.push_back(((m.0, mid), damp));
                        queue.push_back(((mid, m.1), damp));
                    } else {
                        let mid = 0.5 * (damp.0 + damp.1);
                        queue.push_back((m, (damp.0, mid)));
                        queue.push_back((m, (mid, damp.1)));
                    }
                }
            }
        }
    }
    Ok(Some(Proof {
        proved,
        leaves,
        evaluated,
    }))
}
#[cfg(test)]
mod tests {
    use super::*;

    /// `(z - r1)(z - r2)` with every coefficient widened by `rad`, lowest power first.
    fn widened(r1: f64, r2: f64, rad: f64) -> Vec<Interval> {
        [r1 * r2, -(r1 + r2), 1.0]
            .iter()
            .map(|&c| Interval::from_ball(c, rad))
            .collect()
    }

    /// Rouche's test proves a family whose every member is stable and refuses one that holds
    /// an unstable member: roots 0.9 and -0.5 move by at most about `rad / 0.1` for
    /// coefficient changes `rad`, so `1e-3` keeps them inside; a root at 0.999 leaves the
    /// circle when the constant term grows by `1e-2` (`p(1) = 1.5e-3`); a root at 1.1 is
    /// outside already.
    #[test]
    fn rouche_proves_only_stable_families() {
        assert!(rouche(&widened(0.9, -0.5, 1e-3)));
        assert!(!rouche(&widened(0.999, -0.5, 1e-2)));
        assert!(!rouche(&widened(1.1, -0.5, 1e-9)));
        assert!(!rouche(&[Interval::ENTIRE, Interval::point(1.0)]));
    }
}
