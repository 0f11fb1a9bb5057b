//! Certified boxes of walls: one verdict for every wall `(alpha, beta)` of a box
//! (`docs/MODEL.md` section 11).
//!
//! Each coefficient of `q = Q0 + alpha QA + beta QB` is affine in the wall and holds `alpha`
//! and `beta` once each, so interval arithmetic with the box's intervals for `alpha` and
//! `beta` encloses its range over the box. The Schur-Cohn recursion on those enclosures
//! (the `schur` module) then proves its count of roots outside the unit circle for every
//! polynomial in them, so for every wall of the box. Where a step is undecided, the box is
//! halved (on the side that widens the coefficients more) and each half tried again, breadth
//! first, up to a budget of leaves; the leaves left undecided at the end prove nothing.
//! The box is **stable** only when every leaf is proved stable.
//!
//! Plain intervals let each coefficient take its own `alpha` and `beta`, which loses their
//! correlation: with elements at fast sampling (roots crowded near `z = 1`) even a box of
//! relative width `1e-5` stays undecided. A leaf of a loop with elements that the
//! recursion over the box leaves undecided is therefore tried around its centre before it
//! is halved (the `circle` module): the recursion proves the centre's count of roots
//! outside, and Rouché's theorem on arcs of the unit circle proves that no root crosses
//! the circle anywhere in the leaf. The paper's loop keeps the first method only, so its
//! certificates are unchanged.
//!
//! The certificate lists the leaves ordered by their low corner, with their bounds, their
//! coefficient enclosures, their reflection coefficients' enclosures and their claims (a
//! leaf decided around its centre: the centre, the enclosures there, and the ends of its
//! arcs); the checker recomputes each leaf's enclosures, replays its recursion and arcs,
//! and checks that the leaves cover the box exactly.

use std::collections::VecDeque;
use std::fmt::Write as _;

use super::circle;
use super::interval::Interval;
use super::schur::{Recursion, recursion, scaled};
use super::{Masses, Parts, balls, hex, list_json, reflection_balls};
use crate::elements::Loop;
use crate::error::{Error, Result};
use crate::params::Wall;

/// A closed box of walls: `alpha` in `[alpha_lo, alpha_hi]`, `beta` in `[beta_lo, beta_hi]`
/// (either side may be a single value).
///
/// ```
/// use stabound::certificate::WallBox;
/// use stabound::params::Wall;
///
/// let b = WallBox::new(Wall::new(0.1, 0.2)?, Wall::new(0.2, 0.3)?)?;
/// assert_eq!(b.alpha(), (0.1, 0.2));
/// assert!(WallBox::new(Wall::new(0.2, 0.2)?, Wall::new(0.1, 0.3)?).is_err());
/// # Ok::<(), stabound::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WallBox {
    alpha: (f64, f64),
    beta: (f64, f64),
}

impl WallBox {
    /// The box with corners `low` and `high`.
    ///
    /// # Errors
    ///
    /// [`Error::InvalidParameter`] when a coordinate of `high` is below that of `low`.
    pub fn new(low: Wall, high: Wall) -> Result<Self> {
        for (name, lo, hi) in [
            ("alpha", low.alpha(), high.alpha()),
            ("beta", low.beta(), high.beta()),
        ] {
            if hi < lo {
                return Err(Error::InvalidParameter {
                    name,
                    value: hi,
                    expected: format!(
                        "the high end of a box of walls is at least its low end {lo}"
                    ),
                });
            }
        }
        Ok(Self {
            alpha: (low.alpha(), high.alpha()),
            beta: (low.beta(), high.beta()),
        })
    }

    /// The range of `alpha`.
    pub fn alpha(&self) -> (f64, f64) {
        self.alpha
    }

    /// The range of `beta`.
    pub fn beta(&self) -> (f64, f64) {
        self.beta
    }

    fn intervals(&self) -> (Interval, Interval) {
        let iv = |(lo, hi): (f64, f64)| Interval::new(lo, hi);
        (iv(self.alpha), iv(self.beta))
    }

    /// The two halves of the box split at the midpoint of `alpha` (`true`) or `beta`, or
    /// `None` when that side has no `f64` strictly inside it.
    fn halves(&self, on_alpha: bool) -> Option<(Self, Self)> {
        let (lo, hi) = if on_alpha { self.alpha } else { self.beta };
        let mid = 0.5 * lo + 0.5 * hi;
        if !(lo < mid && mid < hi) {
            return None;
        }
        let (mut a, mut b) = (*self, *self);
        if on_alpha {
            (a.alpha.1, b.alpha.0) = (mid, mid);
        } else {
            (a.beta.1, b.beta.0) = (mid, mid);
        }
        Some((a, b))
    }
}

/// What a leaf of a box certificate proves for every wall in it.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub enum LeafClaim {
    /// Every root inside the unit circle.
    Stable,
    /// `outside` roots outside the circle of radius `1 + eps` (`eps = 0`: the unit circle),
    /// none on it; at least one, so the wall is unstable.
    Unstable {
        /// How many roots lie outside (at least 1).
        outside: usize,
        /// How far beyond the unit circle the counting circle lies (0 or [`BEYOND`]).
        eps: f64,
    },
    /// No wall of the leaf is stable: the recursion's first step that is not `|a_0| <
    /// |a_k|` has `|a_0| > |a_k|` for every wall (the `schur` module). Only the strips of
    /// [`crate::certificate::certify_alpha_max`] use it, where the count of roots outside
    /// changes inside the unstable set.
    NotStable,
    /// Nothing: the recursion stayed undecided within the budget.
    Undecided,
}

/// The radius `1 + BEYOND` of the second counting circle, for a leaf the recursion at the
/// unit circle leaves undecided: along a line of unstable walls the count of roots outside
/// changes where a root crosses the unit circle, which no count at that circle decides; a
/// root outside `1 + 1e-3` proves the wall unstable all the same. `1e-3` is far above the
/// enclosures' widths near the circle and below the distance at which unstable walls near
/// the boundary keep a root.
pub const BEYOND: f64 = 1e-3;

/// What a box certificate proves for the whole box.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum BoxClaim {
    /// Every wall of the box is stable.
    Stable,
    /// Every wall of the box is unstable.
    Unstable,
    /// No wall of the box is stable: every leaf is unstable or proved not stable.
    NotStable,
    /// Neither for the whole box: some leaves are undecided, or stable and unstable leaves
    /// both occur (the box crosses the boundary).
    NotProved,
}

/// One leaf of the bisection: its box, its coefficients' enclosures (over the box, or at
/// the centre of a leaf decided on the circle), its recursion, and the centre and arcs of a
/// leaf decided on the circle.
#[derive(Debug, Clone)]
struct Leaf {
    walls: WallBox,
    coefficients: Vec<(f64, f64)>,
    recursion: Option<Recursion>,
    claim: LeafClaim,
    circle: Option<Around>,
}

/// A leaf decided around its centre (the `circle` module): the centre wall and the ends of
/// the arcs that cover the unit circle.
#[derive(Debug, Clone)]
struct Around {
    centre: (f64, f64),
    arcs: Vec<f64>,
}

/// A certified verdict for every wall of a box (see the module documentation).
///
/// ```
/// use stabound::certificate::{BoxClaim, WallBox, certify_box};
/// use stabound::params::{Plant, Wall};
///
/// let plant = Plant::new(0.5, 1.0)?;
/// let inside = WallBox::new(Wall::new(0.1, 0.25)?, Wall::new(0.12, 0.3)?)?;
/// let cert = certify_box(&plant, &inside, 256)?;
/// assert_eq!(cert.claim(), BoxClaim::Stable);
/// // alpha = 2 is past the boundary at beta = 0.3
/// let crossing = WallBox::new(Wall::new(0.1, 0.3)?, Wall::new(2.0, 0.3)?)?;
/// assert_eq!(certify_box(&plant, &crossing, 64)?.claim(), BoxClaim::NotProved);
/// # Ok::<(), stabound::Error>(())
/// ```
#[derive(Debug, Clone)]
pub struct BoxCertificate {
    lp: Loop,
    /// For a member of a set of devices whose masses differ: its masses (`lp` and the walls
    /// are in the set's reference normalization).
    masses: Option<Masses>,
    walls: WallBox,
    leaves: Vec<Leaf>,
}

/// Certifies the verdict of every wall of `walls` on the loop `lp`, halving undecided boxes
/// until they are decided or there are `max_leaves` leaves (Moore-style branch and bound:
/// Moore, Kearfott and Cloud, "Introduction to Interval Analysis", SIAM 2009, ch. 9).
///
/// # Errors
///
/// [`Error::InvalidParameter`] for a budget of 0 leaves; [`Error::Numerical`] when the
/// coefficients' enclosures overflow `f64` (walls near `1e308`).
pub fn certify_box(
    lp: impl Into<Loop>,
    walls: &WallBox,
    max_leaves: usize,
) -> Result<BoxCertificate> {
    bisect((lp.into(), None), walls, max_leaves, false)
}

/// [`certify_box`] on the loop stated as `lp` with its masses (a member of a set of devices
/// whose masses differ, see [`Masses`]), and with `not_stable` also leaves proved
/// [`LeafClaim::NotStable`] where the count of roots outside is undecided.
pub(crate) fn bisect(
    (lp, masses): (Loop, Option<Masses>),
    walls: &WallBox,
    max_leaves: usize,
    not_stable: bool,
) -> Result<BoxCertificate> {
    if max_leaves == 0 {
        return Err(Error::InvalidParameter {
            name: "max_leaves",
            value: 0.0,
            expected: "a budget of at least one box".into(),
        });
    }
    let parts = Parts::of_member(&lp, masses);
    // how much a unit of alpha and of beta widens the coefficients: the side to halve
    let weight = |pick: fn(&(Interval, Interval)) -> Interval| {
        parts
            .0
            .iter()
            .filter_map(|(_, w)| w.as_ref().map(|w| pick(w).mag()))
            .fold(0.0f64, f64::max)
    };
    let (wa, wb) = (weight(|w| w.0), weight(|w| w.1));
    let mut leaves = Vec::new();
    // breadth first, so that a budget too small for the box spreads over all of it
    let mut queue = VecDeque::from([*walls]);
    let mut count = 1usize;
    while let Some(b) = queue.pop_front() {
        let (a, be) = b.intervals();
        let (coefficients, q) = balls(parts.at(a, be)).ok_or_else(|| {
            Error::Numerical(
                "a coefficient's enclosure over the box overflows: the walls are too large to certify as a box".into(),
            )
        })?;
        let mut rec = recursion(&q);
        let mut claim = match rec.outside {
            Some(0) => LeafClaim::Stable,
            Some(outside) => LeafClaim::Unstable { outside, eps: 0.0 },
            None => LeafClaim::Undecided,
        };
        if let (LeafClaim::Undecided, true, Some(j)) = (claim, not_stable, rec.first_greater) {
            rec.reflections.truncate(j + 1);
            claim = LeafClaim::NotStable;
        }
        if claim == LeafClaim::Undecided {
            let radius = Interval::point(1.0) + Interval::point(BEYOND);
            let beyond = recursion(&scaled(&q, radius));
            if let Some(outside @ 1..) = beyond.outside {
                (rec, claim) = (
                    beyond,
                    LeafClaim::Unstable {
                        outside,
                        eps: BEYOND,
                    },
                );
            }
        }
        if claim == LeafClaim::Undecided
            && !lp.is_paper()
            && let Some(leaf) = around_centre(&parts, &b)
        {
            leaves.push(leaf);
            continue;
        }
        if claim == LeafClaim::Undecided && count < max_leaves {
            let on_alpha = (b.alpha.1 - b.alpha.0) * wa >= (b.beta.1 - b.beta.0) * wb;
            let split = b.halves(on_alpha).or_else(|| b.halves(!on_alpha));
            if let Some((lo, hi)) = split {
                count += 1;
                queue.push_back(lo);
                queue.push_back(hi);
                continue;
            }
        }
        leaves.push(Leaf {
            walls: b,
            coefficients,
            recursion: (claim != LeafClaim::Undecided).then_some(rec),
            claim,
            circle: None,
        });
    }
    leaves.sort_by(|x, y| {
        let key = |l: &Leaf| (l.walls.alpha.0, l.walls.beta.0);
        key(x)
            .partial_cmp(&key(y))
            .unwrap_or(std::cmp::Ordering::Equal)
    });
    Ok(BoxCertificate {
        lp,
        masses,
        walls: *walls,
        leaves,
    })
}

/// The leaf `b` decided around its centre, or `None` (the `circle` module).
fn around_centre(parts: &Parts, b: &WallBox) -> Option<Leaf> {
    let c = circle::around_centre(parts, None, b.alpha, b.beta)?;
    let claim = match c.outside {
        0 => LeafClaim::Stable,
        outside => LeafClaim::Unstable { outside, eps: 0.0 },
    };
    Some(Leaf {
        walls: *b,
        coefficients: c.coefficients,
        recursion: Some(c.recursion),
        claim,
        circle: Some(Around {
            centre: c.centre,
            arcs: c.arcs,
        }),
    })
}

impl BoxCertificate {
    /// What the certificate proves for the whole box.
    pub fn claim(&self) -> BoxClaim {
        let all = |f: fn(LeafClaim) -> bool| self.leaves.iter().all(|l| f(l.claim));
        if all(|c| c == LeafClaim::Stable) {
            BoxClaim::Stable
        } else if all(|c| matches!(c, LeafClaim::Unstable { .. })) {
            BoxClaim::Unstable
        } else if all(|c| matches!(c, LeafClaim::Unstable { .. } | LeafClaim::NotStable)) {
            BoxClaim::NotStable
        } else {
            BoxClaim::NotProved
        }
    }

    /// The number of leaves proved stable, proved unstable and left undecided (a leaf proved
    /// not stable is none of them).
    pub fn counts(&self) -> (usize, usize, usize) {
        let count = |f: fn(LeafClaim) -> bool| self.leaves.iter().filter(|l| f(l.claim)).count();
        (
            count(|c| c == LeafClaim::Stable),
            count(|c| matches!(c, LeafClaim::Unstable { .. })),
            count(|c| c == LeafClaim::Undecided),
        )
    }

    /// The box the certificate answers for.
    pub fn walls(&self) -> &WallBox {
        &self.walls
    }

    /// The certificate as JSON text, ending in a newline: the inputs (the box as `lo`, `hi`
    /// hex floats), the model, the degree of `q`, the leaves by their low corner (each with
    /// its box, claim, coefficient balls and reflection balls), the claim for the box and a
    /// CRC-32 of the text before it.
    pub fn to_json(&self) -> String {
        let (mut s, elements) = super::head("box", &self.lp);
        let pair = |(lo, hi): (f64, f64)| format!("[\"{}\", \"{}\"]", hex(lo), hex(hi));
        let plant = self.lp.plant();
        let _ = write!(
            s,
            "  \"inputs\": {{\"alpha\": {}, \"beta\": {}, \"delta\": \"{}\", \"d\": \"{}\"",
            pair(self.walls.alpha),
            pair(self.walls.beta),
            hex(plant.delta()),
            hex(plant.d())
        );
        s.push_str(&Masses::json(self.masses));
        for (k, v) in &elements {
            let _ = write!(s, ", \"{k}\": {v}");
        }
        s.push_str("},\n");
        let _ = writeln!(s, "  \"degree\": {},", self.lp.degree());
        s.push_str("  \"leaves\": [");
        for (i, leaf) in self.leaves.iter().enumerate() {
            s.push_str(if i == 0 { "\n" } else { ",\n" });
            let _ = write!(
                s,
                "    {{\"box\": {{\"alpha\": {}, \"beta\": {}}}, \"claim\": ",
                pair(leaf.walls.alpha),
                pair(leaf.walls.beta)
            );
            match leaf.claim {
                LeafClaim::Stable => s.push_str("\"stable\""),
                LeafClaim::Unstable { outside, eps } => {
                    let _ = write!(s, "\"unstable\", \"outside\": {outside}");
                    if eps > 0.0 {
                        let _ = write!(s, ", \"eps\": \"{}\"", hex(eps));
                    }
                }
                LeafClaim::NotStable => s.push_str("\"not stable\""),
                LeafClaim::Undecided => s.push_str("\"undecided\""),
            }
            if let Some(around) = &leaf.circle {
                let (a, b) = around.centre;
                let _ = write!(
                    s,
                    ", \"centre\": {{\"alpha\": \"{}\", \"beta\": \"{}\"}}",
                    hex(a),
                    hex(b)
                );
            }
            s.push_str(",\n     \"coefficients\": ");
            list_json(&mut s, "      ", &leaf.coefficients);
            s.push_str(",\n     \"reflections\": ");
            let refl = leaf.recursion.as_ref().map(reflection_balls);
            list_json(&mut s, "      ", refl.as_deref().unwrap_or_default());
            if let Some(around) = &leaf.circle {
                super::arcs_json(&mut s, &around.arcs);
            }
            s.push('}');
        }
        let (stable, unstable, undecided) = self.counts();
        let verdict = match self.claim() {
            BoxClaim::Stable => "stable",
            BoxClaim::Unstable => "unstable",
            BoxClaim::NotStable => "not stable",
            BoxClaim::NotProved => "not proved",
        };
        let _ = write!(
            s,
            "],\n  \"claim\": {{\"verdict\": \"{verdict}\", \"stable\": {stable}, \"unstable\": {unstable}, \"undecided\": {undecided}"
        );
        // written only where it occurs, so that certificates without such leaves keep
        // their form
        let not_stable = self.leaves.len() - stable - unstable - undecided;
        if not_stable > 0 {
            let _ = write!(s, ", \"not stable\": {not_stable}");
        }
        s.push_str("},\n");
        super::seal(s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::Plant;
    use crate::stability::{Checker, Options, Verdict};

    /// Every leaf's claim agrees with the double-precision verdict at its corners and centre,
    /// and the leaves tile the box (their areas add up to the box's).
    #[test]
    fn leaves_agree_with_point_verdicts_and_tile_the_box() {
        let plant = Plant::new(0.5, 1.0).unwrap();
        let walls =
            WallBox::new(Wall::new(0.1, 0.25).unwrap(), Wall::new(1.5, 0.3).unwrap()).unwrap();
        let cert = certify_box(plant, &walls, 300).unwrap();
        assert_eq!(cert.claim(), BoxClaim::NotProved);
        let (stable, unstable, _) = cert.counts();
        assert!(stable > 0 && unstable > 0, "{:?}", cert.counts());
        let checker = Checker::new(plant, Options::default()).unwrap();
        let mut area = 0.0;
        for leaf in &cert.leaves {
            let ((a0, a1), (b0, b1)) = (leaf.walls.alpha, leaf.walls.beta);
            area += (a1 - a0) * (b1 - b0);
            let want = match leaf.claim {
                LeafClaim::Stable => Verdict::Stable,
                LeafClaim::Unstable { .. } => Verdict::Unstable,
                _ => continue,
            };
            for (a, b) in [
                (a0, b0),
                (a1, b1),
                (a0, b1),
                (a1, b0),
                (0.5 * (a0 + a1), 0.5 * (b0 + b1)),
            ] {
                let v = checker.verdict(&Wall::new(a, b).unwrap()).unwrap();
                assert_eq!(v, want, "{a} {b}");
            }
        }
        assert!((area - 1.4 * 0.05).abs() < 1e-12, "{area}");
    }
}
