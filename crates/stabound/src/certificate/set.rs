//! Certified verdicts over a finite set of devices (`docs/MODEL.md` section 11): lists of
//! the device's mass, damping and delay and of loop-element values (`one-of:LIST`), and a
//! hand that can let go.
//!
//! A finite set is proved member by member: each member's loop gets the certificate of one
//! loop (one wall, a box of walls, a lookup table), and the certificate of kind `set` holds
//! the set (the alternatives of the device's parameters that differ and of each element as
//! certificate inputs, `"none"` for a member without the element: the hand let go) and every
//! member's certificate, in the order of the combinations of the alternatives (the first
//! outermost). Every member is stated in the normalization of the set's reference mass, so
//! that one wall (box, table) is one physical wall for all: where the masses differ, each
//! member's inputs add its mass and the reference mass, and the checker scales the member's
//! values in units of the mass by their quotient, exactly (`Masses`). The checker requires
//! the members to be every combination once and to agree on everything else (the one wall,
//! box or table, and the reference mass), checks each member's certificate as that of one
//! loop, and then the set's claim:
//!
//! - every member stable (for every wall of the box): stable for the set;
//! - a member proved unstable (every wall of the box unstable for it, with its count of roots
//!   outside): unstable for the set, since that member fails; otherwise a member marginal or
//!   not proved makes the set so;
//! - the robust `alpha_max` (the largest stiffness with one damping stable for every member)
//!   in `[alpha_lo, alpha_hi]`: the wall `(alpha_lo, beta)` certified stable for every member,
//!   and for one member, the binding one, the proof that no damping of the searched range is
//!   stable at `alpha_hi` or stiffer ([`super::certify_alpha_max`]'s upper half). No wall
//!   from `alpha_hi` on is then stable for the whole set. Where the optimum lies where two
//!   members' limits cross, no member alone has that proof: the range is cut into pieces
//!   meeting end to end, each with one member's proof over its dampings, so that every
//!   damping of the range has a member for which no wall from `alpha_hi` on is stable.

use std::fmt::Write as _;

use rayon::prelude::*;

use super::limit::{ABOVE, Cap, cap_json, grid_json, holds_optimum, stable_below, unstable_at};
use super::region::{BoxCertificate, BoxClaim, WallBox, bisect};
use super::{
    AmaxCertificate, Certificate, Claim, Masses, certify_member, element_inputs, hex, nested,
    opening, seal,
};
use crate::amax::{AmaxOptions, alpha_max};
use crate::devices::DeviceSet;
use crate::elements::Loop;
use crate::error::{Error, Result};
use crate::params::Wall;
use crate::stability::{Checker, Options, Verdict};

/// Each element's alternatives as certificate inputs (`"none"` for a member without it), in
/// the order hand, transmission, actuator, filter.
pub(crate) type Alternatives = Vec<(&'static str, Vec<String>)>;

/// A member's loop as its certificate states it: in the set's reference normalization,
/// with its masses where the set's masses differ (`Masses`).
pub(crate) type Stated = (Loop, Option<Masses>);

/// A member of a finite set: its loop as its certificate states it, its own loop with the
/// scale `m_ref / m` that takes the reference normalization's walls to its own (in double
/// precision: for the searches that guide the proofs, which do not rely on them), and its
/// name ([`DeviceSet::describe_member`]).
#[derive(Debug, Clone)]
pub(crate) struct SetMember {
    pub(crate) stated: Stated,
    own: (Loop, f64),
    pub(crate) name: String,
}

/// The members of the finite set `set`, each stated in the set's reference normalization
/// (the reference member's mass; its walls are the set's): a member of another mass with
/// its masses, its values in units of the mass then scaled exactly by the checker.
///
/// # Errors
///
/// [`Error::InvalidRequest`] for a set with an interval; as [`Loop::physical`] for a member
/// at the reference mass.
pub(crate) fn set_loops(set: &DeviceSet) -> Result<Vec<SetMember>> {
    if set.has_intervals() {
        return Err(Error::InvalidRequest(
            "a certificate over a set of devices covers a finite set (a hand that can let go, one-of lists); an interval of a parameter is not certified: give its values as a list".into(),
        ));
    }
    let reference = set.reference().device().mass;
    let members = set.sampled_members();
    // exact: a member of the reference's mass is stated as it is
    let differ = members.iter().any(|m| m.device().mass != reference);
    members
        .into_iter()
        .map(|m| {
            let mut device = *m.device();
            let own = (m.to_loop()?, reference / device.mass);
            device.mass = reference;
            let masses = differ.then_some(Masses {
                reference,
                mass: m.device().mass,
            });
            Ok(SetMember {
                stated: (Loop::physical(&device, m.elements())?, masses),
                own,
                name: set.describe_member(&m),
            })
        })
        .collect()
}

/// The device's parameters a set's members may differ in, before the elements: the mass,
/// the damping `delta` and the delay `d` (in the reference normalization).
const DEVICE: [&str; 3] = ["mass", "delta", "d"];

/// Sorts the members in the order of the combinations of their parameters' alternatives
/// (the device's mass, damping and delay where they differ, then each element's values; in
/// order of first appearance, `"none"` for a member without the element), the first
/// outermost, and returns those alternatives: the set the certificate names. `stated` gives
/// a member's loop as its certificate states it.
///
/// # Errors
///
/// [`Error::Numerical`] when the members are not every combination once (a set's members
/// are: its lists combine freely, and the hand let go is the hand's alternative `"none"`;
/// a transmission's named damping share normalizes with the damping, so that the two do
/// not combine freely).
pub(crate) fn product_order<E: Clone>(
    members: &mut [E],
    stated: impl Fn(&E) -> Stated,
) -> Result<Alternatives> {
    let quoted = |x: f64| format!("\"{}\"", hex(x));
    let inputs: Vec<Vec<(&'static str, String)>> = members
        .iter()
        .map(|e| {
            let (lp, masses) = stated(e);
            let plant = lp.plant();
            let mut v: Vec<(&'static str, String)> = masses
                .map(|m| ("mass", quoted(m.mass)))
                .into_iter()
                .collect();
            v.push(("delta", quoted(plant.delta())));
            v.push(("d", quoted(plant.d())));
            v.extend(element_inputs(&lp));
            v
        })
        .collect();
    // a member's value of the element `name`, "none" without it
    let value = |e: &[(&'static str, String)], name: &str| {
        e.iter()
            .find(|(k, _)| *k == name)
            .map_or_else(|| "\"none\"".to_string(), |(_, v)| v.clone())
    };
    let mut set: Alternatives = Vec::new();
    for name in DEVICE
        .into_iter()
        .chain(["hand", "transmission", "actuator", "filter"])
    {
        if inputs.iter().all(|e| e.iter().all(|(k, _)| *k != name)) {
            continue;
        }
        let mut alternatives: Vec<String> = Vec::new();
        for e in &inputs {
            let v = value(e, name);
            if !alternatives.contains(&v) {
                alternatives.push(v);
            }
        }
        // a device parameter the members share belongs to the one loop they agree on
        if alternatives.len() > 1 || !DEVICE.contains(&name) {
            set.push((name, alternatives));
        }
    }
    let index = |e: &[(&'static str, String)]| -> Vec<usize> {
        set.iter()
            .map(|(name, alts)| {
                let v = value(e, name);
                alts.iter().position(|a| *a == v).unwrap_or(0)
            })
            .collect()
    };
    let mut keyed: Vec<(Vec<usize>, usize)> = inputs
        .iter()
        .enumerate()
        .map(|(m, e)| (index(e), m))
        .collect();
    keyed.sort();
    let combinations: usize = set.iter().map(|(_, a)| a.len()).product();
    if keyed.len() != combinations || keyed.windows(2).any(|w| w[0].0 == w[1].0) {
        return Err(Error::Numerical(format!(
            "the set's {} members are not every combination of their parameters' values once ({combinations} combinations); certify each device alone",
            keyed.len()
        )));
    }
    let sorted: Vec<E> = keyed.into_iter().map(|(_, m)| members[m].clone()).collect();
    members.clone_from_slice(&sorted);
    Ok(set)
}

/// A certificate of kind `set`: the set's alternatives, each member's certificate (JSON, one
/// loop's kind), the members named `extra` (after a comma and newline each, or empty) and the
/// claim's members `claim`, sealed.
pub(crate) fn set_json(set: &Alternatives, members: &[String], extra: &str, claim: &str) -> String {
    let mut s = opening("set");
    let alts: Vec<String> = set
        .iter()
        .map(|(k, v)| format!("\"{k}\": [{}]", v.join(", ")))
        .collect();
    let _ = writeln!(s, "  \"set\": {{{}}},", alts.join(",\n          "));
    s.push_str("  \"members\": [");
    for (i, m) in members.iter().enumerate() {
        s.push_str(if i == 0 { "\n    " } else { ",\n    " });
        s.push_str(&nested(m).replace('\n', "\n  "));
    }
    let _ = writeln!(s, "],\n{extra}  \"claim\": {{{claim}}},");
    seal(s)
}

/// What a certificate over a finite set of devices proves for the set.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum SetClaim {
    /// Every member is stable (at every wall of the box).
    Stable,
    /// Member `member` is unstable (at every wall of the box), so the set is.
    Unstable {
        /// The failing member's index in [`SetCertificate::member`]'s order.
        member: usize,
    },
    /// No member is proved unstable, and member `member` is marginal (its spectral radius
    /// within the band of 1), the others stable or marginal.
    Marginal {
        /// The member's index.
        member: usize,
    },
    /// No member is proved unstable, and member `member`'s box is not proved.
    NotProved {
        /// The member's index.
        member: usize,
    },
}

/// One member's proof: for one wall or for a box of walls.
#[derive(Debug, Clone)]
enum Proof {
    Wall(Certificate),
    Box(BoxCertificate),
}

impl Proof {
    /// The member's verdict's rank: 0 stable, 1 marginal, 2 not proved, 3 unstable.
    fn rank(&self) -> u8 {
        match self {
            Proof::Wall(c) => match c.claim() {
                Claim::Stable => 0,
                Claim::Marginal { .. } => 1,
                _ => 3,
            },
            Proof::Box(b) => match b.claim() {
                BoxClaim::Stable => 0,
                BoxClaim::Unstable => 3,
                _ => 2,
            },
        }
    }

    fn to_json(&self) -> String {
        match self {
            Proof::Wall(c) => c.to_json(),
            Proof::Box(b) => b.to_json(),
        }
    }
}

/// A certified verdict of one wall, or of every wall of a box, for every member of a finite
/// set of devices (see the module documentation).
///
/// ```
/// use stabound::certificate::{SetClaim, certify_set};
/// use stabound::elements::PhysicalElements;
/// use stabound::params::{Delay, Device};
/// use stabound::robust::DeviceSet;
///
/// // a 0.1 kg device at 1 kHz held by a 0.3 kg hand that can let go
/// let device = Device::new(0.1, 0.001, 0.0, Delay::Samples(1.0))?;
/// let mut hand = PhysicalElements::default();
/// hand.hand_mass = Some(0.3);
/// hand.hand_damping = Some(2.0);
/// hand.hand_stiffness = Some(300.0);
/// let set = DeviceSet::new(&device, &hand)?;
/// let cert = certify_set(&set, &device.wall(1000.0, 5.0)?, 1e-9)?;
/// assert_eq!(cert.claim(), SetClaim::Stable);
/// assert_eq!(cert.members(), 2);
/// assert!(cert.to_json().contains("\"kind\": \"set\""));
/// # Ok::<(), stabound::Error>(())
/// ```
#[derive(Debug, Clone)]
pub struct SetCertificate {
    set: Alternatives,
    /// Every member's name and proof, in the order of the combinations.
    members: Vec<(String, Proof)>,
}

/// Certifies the verdict of `wall` for every member of the finite set `set` (as
/// [`super::certify`] on each member's loop; the wall is in the normalization of the set's
/// reference device, one physical wall for every member).
///
/// # Errors
///
/// [`Error::InvalidRequest`] for a set with an interval; as [`super::certify`] for a member.
pub fn certify_set(set: &DeviceSet, wall: &Wall, margin: f64) -> Result<SetCertificate> {
    prove_members(set, |(lp, masses)| {
        Ok(Proof::Wall(certify_member(lp, masses, wall, margin)?))
    })
}

/// Certifies the verdict of every wall of `walls` for every member of the finite set `set`
/// ([`super::certify_box`] on each member's loop, at most `max_leaves` leaves each).
///
/// # Errors
///
/// As [`certify_set`], and as [`super::certify_box`] for a member.
pub fn certify_set_box(
    set: &DeviceSet,
    walls: &WallBox,
    max_leaves: usize,
) -> Result<SetCertificate> {
    prove_members(set, |stated| {
        Ok(Proof::Box(bisect(stated, walls, max_leaves, false)?))
    })
}

/// Each member's proof by `prove`, in parallel (each member's proof does not depend on the
/// others', so the result does not depend on the number of threads).
fn prove_members(
    set: &DeviceSet,
    prove: impl Fn(Stated) -> Result<Proof> + Send + Sync,
) -> Result<SetCertificate> {
    let mut members = set_loops(set)?;
    let alternatives = product_order(&mut members, |m| m.stated)?;
    let proofs = members
        .par_iter()
        .map(|m| prove(m.stated))
        .collect::<Result<Vec<_>>>()?;
    Ok(SetCertificate {
        set: alternatives,
        members: members
            .into_iter()
            .zip(proofs)
            .map(|(m, p)| (m.name, p))
            .collect(),
    })
}

impl SetCertificate {
    /// What the certificate proves for the set: the worst member's verdict (unstable before
    /// not proved before marginal before stable), the first such member named.
    pub fn claim(&self) -> SetClaim {
        let worst = self
            .members
            .iter()
            .map(|(_, p)| p.rank())
            .max()
            .unwrap_or(0);
        let member = self
            .members
            .iter()
            .position(|(_, p)| p.rank() == worst)
            .unwrap_or(0);
        match worst {
            0 => SetClaim::Stable,
            1 => SetClaim::Marginal { member },
            2 => SetClaim::NotProved { member },
            _ => SetClaim::Unstable { member },
        }
    }

    /// The number of members.
    pub fn members(&self) -> usize {
        self.members.len()
    }

    /// Member `i`'s name ([`DeviceSet::describe_member`]), or `None` past the last.
    pub fn member(&self, i: usize) -> Option<&str> {
        self.members.get(i).map(|(name, _)| name.as_str())
    }

    /// The certificate as JSON text (kind `set`): the set, each member's certificate (one
    /// wall's or a box's, without its own CRC), the claim (`verdict` and the count of
    /// `members`, and the `member` that decides it unless stable) and a CRC-32 of the text
    /// before it.
    pub fn to_json(&self) -> String {
        let members: Vec<String> = self.members.iter().map(|(_, p)| p.to_json()).collect();
        let n = self.members.len();
        let claim = match self.claim() {
            SetClaim::Stable => format!("\"verdict\": \"stable\", \"members\": {n}"),
            SetClaim::Unstable { member } => {
                format!("\"verdict\": \"unstable\", \"members\": {n}, \"member\": {member}")
            }
            SetClaim::Marginal { member } => {
                format!("\"verdict\": \"marginal\", \"members\": {n}, \"member\": {member}")
            }
            SetClaim::NotProved { member } => {
                format!("\"verdict\": \"not proved\", \"members\": {n}, \"member\": {member}")
            }
        };
        set_json(&self.set, &members, "", &claim)
    }
}

/// A certified enclosure `[alpha_lo, alpha_hi]` of the robust `alpha_max` of a finite set of
/// devices (the largest stiffness with one damping of the searched range stable for every
/// member): the wall `(alpha_lo, beta)` certified stable for every member, and the proof that
/// no wall with a damping of the range is stable at `alpha_hi` or stiffer (or, where the
/// budget did not prove that, at `alpha_hi`): by one binding member over the whole range, or,
/// where the optimum lies where members' limits cross, by pieces of the range, each proved
/// for one member.
///
/// ```
/// use stabound::certificate::certify_set_alpha_max;
/// use stabound::elements::PhysicalElements;
/// use stabound::params::{Delay, Device};
/// use stabound::robust::{DeviceSet, robust_alpha_max};
/// use stabound::AmaxOptions;
///
/// let device = Device::new(0.1, 0.001, 0.0, Delay::Samples(1.0))?;
/// let mut hand = PhysicalElements::default();
/// hand.hand_mass = Some(0.3);
/// hand.hand_damping = Some(2.0);
/// hand.hand_stiffness = Some(300.0);
/// let set = DeviceSet::new(&device, &hand)?;
/// let opts = AmaxOptions::default().with_beta_limits(Some(0.0), Some(1.0))?;
/// let robust = robust_alpha_max(&set, &opts)?;
/// let optimum = (robust.alpha_max, robust.beta_at_max);
/// let cert = certify_set_alpha_max(&set, optimum, (0.0, 1.0), 16_384)?;
/// let (lo, hi) = cert.bounds();
/// assert!(lo <= robust.alpha_max && robust.alpha_max < hi);
/// assert_eq!(cert.binding(), "hand off");
/// // the dampings proved in pieces, end to end, all for the hand let go
/// let pieces = cert.pieces();
/// assert_eq!((pieces[0].0, pieces[pieces.len() - 1].1), (0.0, 1.0));
/// assert!(pieces.iter().all(|p| p.2 == "hand off"));
/// # Ok::<(), stabound::Error>(())
/// ```
#[derive(Debug, Clone)]
pub struct SetAmaxCertificate {
    set: Alternatives,
    /// Every member's name and its certificate of the stable wall, in the order of the
    /// combinations.
    below: Vec<(String, Certificate)>,
    /// The pieces of the damping range, in increasing damping, each meeting the next, all at
    /// one `alpha_hi` and all capped or none.
    pieces: Vec<Piece>,
}

/// A piece of the damping range (its box's) proved for member `member`: no wall of it
/// stable at `alpha_hi` (with `cap`, none up to the cap, and the cap's rule beyond).
#[derive(Debug, Clone)]
struct Piece {
    member: usize,
    above: BoxCertificate,
    cap: Option<Cap>,
}

/// The points of the guide's grid over the damping range: the members' limits are sampled
/// at `GRID + 1` dampings to find where each member binds. 64 intervals resolve limits that
/// cross a few times; where a piece's proof fails it is halved anyway.
const GRID: u32 = 64;
/// The most halvings of pieces whose proofs failed, at one stiffness: each failed proof
/// costs up to the budget of leaves, so the halvings are few.
const MAX_HALVINGS: usize = 8;

/// Certifies an enclosure of the robust `alpha_max` of the finite set `set`, whose optimum
/// `(alpha, beta)` was found by a search over the dampings `betas` (as
/// [`crate::robust::robust_alpha_max`]'s `alpha_max` and `beta_at_max`): the nearest wall
/// below `alpha` at `beta` certified stable for every member, and above it, at the nearest
/// stiffness `alpha_hi` of [`super::certify_alpha_max`]'s steps, the proof that no wall with a
/// damping of the range is stable there (first from `alpha_hi` up to a cap, for every step;
/// then at `alpha_hi` alone). Each step tries one member over the whole range (the members
/// unstable just above the optimum by the double-precision test first), then pieces of the
/// range: cut where the member of the smallest `alpha_max` at that damping (the binding one,
/// sampled at 65 dampings and the changes located by bisection in double precision) changes,
/// each piece proved for its binding member or, failing that, for another member whose
/// sampled limits lie below `alpha_hi`, or halved (at most 8 halvings). Each proof takes at
/// most `max_leaves` leaves.
///
/// # Errors
///
/// As [`certify_set`]; [`Error::InvalidParameter`] when `betas` does not hold `beta`;
/// [`Error::Numerical`] when no wall within 0.1 % below is certified stable for every
/// member, or no stiffness within 10 % above is proved unstable for every damping of the
/// range by the members' proofs.
pub fn certify_set_alpha_max(
    set: &DeviceSet,
    (alpha, beta): (f64, f64),
    betas: (f64, f64),
    max_leaves: usize,
) -> Result<SetAmaxCertificate> {
    holds_optimum(betas, beta)?;
    let mut members = set_loops(set)?;
    let alternatives = product_order(&mut members, |m| m.stated)?;
    let stated: Vec<Stated> = members.iter().map(|m| m.stated).collect();
    let below = stable_below(&stated, alpha, beta)?;
    // the members unstable just above the optimum first: the binding ones (each in its own
    // normalization)
    let mut order: Vec<(bool, usize)> = Vec::with_capacity(members.len());
    for (i, m) in members.iter().enumerate() {
        let (lp, s) = m.own;
        let just_above = Wall::new(alpha * (1.0 + 1e-6) * s, beta * s)?;
        let v = Checker::new(lp, Options::default())?.verdict(&just_above)?;
        order.push((v != Verdict::Unstable, i));
    }
    order.sort();
    let order: Vec<usize> = order.into_iter().map(|(_, i)| i).collect();
    let guide = Guide::new(&members, betas)?;
    for capped in [true, false] {
        for r in ABOVE {
            let hi = alpha * (1.0 + r);
            let mut cover = Cover {
                members: &members,
                guide: &guide,
                hi,
                capped,
                max_leaves,
                halvings: 0,
            };
            if let Some(pieces) = cover.whole(&order)? {
                return Ok(SetAmaxCertificate {
                    set: alternatives,
                    below: members
                        .into_iter()
                        .zip(below)
                        .map(|(m, c)| (m.name, c))
                        .collect(),
                    pieces,
                });
            }
        }
    }
    Err(Error::Numerical(format!(
        "no stiffness within 10 % above the robust alpha_max is certified unstable for every damping in [{}, {}], whole or in pieces each proved for one member ({max_leaves} leaves each, at most {MAX_HALVINGS} halvings); a larger budget may prove it",
        betas.0, betas.1
    )))
}

/// Each member's `alpha_max` at the dampings of a grid over the range, in double precision:
/// where each member binds, to choose the pieces and their members (the proofs do not
/// depend on it being right).
struct Guide {
    betas: Vec<f64>,
    /// `limits[j][i]`: member `i`'s `alpha_max` at `betas[j]` (0 with no stable wall there).
    limits: Vec<Vec<f64>>,
}

/// Member `m`'s `alpha_max` at the damping `beta` alone, in the set's reference
/// normalization, in double precision (its own loop's at `beta m_ref / m`, scaled back);
/// 0 where no wall at that damping is stable (or none was found).
fn limit_at(m: &SetMember, beta: f64) -> f64 {
    let (lp, s) = m.own;
    AmaxOptions::default()
        .with_beta_limits(Some(beta * s), Some(beta * s))
        .and_then(|opts| alpha_max(lp, &opts))
        .map_or(0.0, |a| a.alpha_max / s)
}

impl Guide {
    /// Every member's limit at `GRID + 1` dampings spread evenly over `betas` (ends
    /// included), in parallel (each is computed alone, so the guide does not depend on the
    /// number of threads).
    fn new(members: &[SetMember], betas: (f64, f64)) -> Result<Guide> {
        // the ends exactly: the pieces must reach them
        let grid: Vec<f64> = (0..=GRID)
            .map(|j| match j {
                0 => betas.0,
                GRID => betas.1,
                _ => betas.0 + (betas.1 - betas.0) * f64::from(j) / f64::from(GRID),
            })
            .collect();
        let limits = grid
            .par_iter()
            .map(|&b| members.iter().map(|m| limit_at(m, b)).collect())
            .collect();
        Ok(Guide {
            betas: grid,
            limits,
        })
    }

    /// The member of the smallest limit at grid point `j` (the first such).
    fn binding(&self, j: usize) -> usize {
        let row = &self.limits[j];
        (0..row.len())
            .min_by(|&a, &b| row[a].total_cmp(&row[b]))
            .unwrap_or(0)
    }

    /// The grid point nearest the middle of `range`.
    fn nearest(&self, range: (f64, f64)) -> usize {
        let mid = 0.5 * (range.0 + range.1);
        (0..self.betas.len())
            .min_by(|&a, &b| {
                (self.betas[a] - mid)
                    .abs()
                    .total_cmp(&(self.betas[b] - mid).abs())
            })
            .unwrap_or(0)
    }

    /// The largest limit of member `i` over the grid points within `[lo, hi]` and at its
    /// ends (computed there), the grid's own where an end is a grid point.
    fn worst(&self, members: &[SetMember], i: usize, (lo, hi): (f64, f64)) -> f64 {
        self.betas
            .iter()
            .zip(&self.limits)
            .filter(|(b, _)| lo <= **b && **b <= hi)
            .map(|(_, row)| row[i])
            .chain([lo, hi].map(|b| limit_at(&members[i], b)))
            .fold(0.0, f64::max)
    }

    /// The pieces of the range where one member binds: `(lo, hi, member)` in increasing
    /// damping, each cut where the binding member changes between two grid points, located
    /// by bisection on which of the two members' limits is smaller (to the precision of an
    /// `f64`, at most 60 halvings).
    fn pieces(&self, members: &[SetMember]) -> Vec<(f64, f64, usize)> {
        let n = self.betas.len();
        let mut out: Vec<(f64, f64, usize)> = Vec::new();
        let mut start = (self.betas[0], self.binding(0));
        for j in 1..n {
            let m = self.binding(j);
            if m == start.1 {
                continue;
            }
            let (mut a, mut b) = (self.betas[j - 1], self.betas[j]);
            let (pa, pb) = (&members[start.1], &members[m]);
            for _ in 0..60 {
                let mid = 0.5 * (a + b);
                if mid <= a || mid >= b {
                    break;
                }
                if limit_at(pa, mid) <= limit_at(pb, mid) {
                    a = mid;
                } else {
                    b = mid;
                }
            }
            out.push((start.0, a, start.1));
            start = (a, m);
        }
        out.push((start.0, self.betas[n - 1], start.1));
        out
    }
}

/// Covering the damping range with pieces proved unstable at one stiffness.
struct Cover<'a> {
    members: &'a [SetMember],
    guide: &'a Guide,
    hi: f64,
    capped: bool,
    max_leaves: usize,
    /// The pieces halved so far (at most [`MAX_HALVINGS`]).
    halvings: usize,
}

impl Cover<'_> {
    /// The whole range proved by one member (those of `order` whose sampled limits lie below
    /// `hi`, in that order), else by the guide's pieces; `None` when not proved.
    fn whole(&mut self, order: &[usize]) -> Result<Option<Vec<Piece>>> {
        let range = (
            self.guide.betas[0],
            self.guide.betas[self.guide.betas.len() - 1],
        );
        for &i in order {
            if self.guide.worst(self.members, i, range) < self.hi
                && let Some(piece) = self.prove(i, range)?
            {
                return Ok(Some(vec![piece]));
            }
        }
        if self.members.len() < 2 {
            return Ok(None);
        }
        let mut pieces = Vec::new();
        for (lo, hi, member) in self.guide.pieces(self.members) {
            match self.piece((lo, hi), member)? {
                Some(mut more) => pieces.append(&mut more),
                None => return Ok(None),
            }
        }
        Ok(Some(pieces))
    }

    /// The dampings `range` proved for `first`, else for another member whose sampled limits
    /// there lie below `hi` (smallest first), else in halves, while the budget of pieces
    /// lasts.
    fn piece(&mut self, range: (f64, f64), first: usize) -> Result<Option<Vec<Piece>>> {
        let mut others: Vec<(f64, usize)> = (0..self.members.len())
            .filter(|&i| i != first)
            .map(|i| (self.guide.worst(self.members, i, range), i))
            .filter(|&(w, _)| w < self.hi)
            .collect();
        others.sort_by(|a, b| a.0.total_cmp(&b.0));
        for i in std::iter::once(first).chain(others.into_iter().map(|(_, i)| i)) {
            if let Some(p) = self.prove(i, range)? {
                return Ok(Some(vec![p]));
            }
        }
        let mid = 0.5 * (range.0 + range.1);
        if self.halvings >= MAX_HALVINGS || mid <= range.0 || mid >= range.1 {
            return Ok(None);
        }
        self.halvings += 1;
        let mut out = Vec::new();
        for half in [(range.0, mid), (mid, range.1)] {
            let j = self.guide.nearest(half);
            let Some(mut p) = self.piece(half, self.guide.binding(j))? else {
                return Ok(None);
            };
            out.append(&mut p);
        }
        Ok(Some(out))
    }

    /// Member `i`'s proof over the dampings `range` at `hi`.
    fn prove(&self, i: usize, range: (f64, f64)) -> Result<Option<Piece>> {
        let proof = unstable_at(
            self.members[i].stated,
            self.hi,
            range,
            self.capped,
            self.max_leaves,
        )?;
        Ok(proof.map(|(above, cap)| Piece {
            member: i,
            above,
            cap,
        }))
    }
}

impl SetAmaxCertificate {
    /// The enclosure `(alpha_lo, alpha_hi)` of the robust `alpha_max`.
    pub fn bounds(&self) -> (f64, f64) {
        let lo = self.below.first().map_or(f64::NAN, |(_, c)| c.alpha);
        let hi = self
            .pieces
            .first()
            .map_or(f64::NAN, |p| p.above.walls().alpha().0);
        (lo, hi)
    }

    /// Whether no wall from `alpha_hi` on (with a damping of the range) is proved stable for
    /// the set; otherwise every wall at `alpha_hi` is proved unstable for a member.
    pub fn every_stiffer_wall(&self) -> bool {
        self.pieces.iter().all(|p| p.cap.is_some())
    }

    /// The name ([`DeviceSet::describe_member`]) of the member whose piece of the damping
    /// range holds the damping of the stable wall (the first such): over the whole range, the
    /// binding member.
    pub fn binding(&self) -> &str {
        let beta = self.below.first().map_or(f64::NAN, |(_, c)| c.beta);
        let piece = self
            .pieces
            .iter()
            .find(|p| {
                let (lo, hi) = p.above.walls().beta();
                lo <= beta && beta <= hi
            })
            .or(self.pieces.first());
        piece.map_or("", |p| self.below[p.member].0.as_str())
    }

    /// The pieces of the damping range, in increasing damping: `(lo, hi, member)`, each
    /// proved for the member named (no wall with a damping of `[lo, hi]` stable for it at
    /// `alpha_hi`, or stiffer when [`SetAmaxCertificate::every_stiffer_wall`] holds); one
    /// piece when one member binds over the whole range.
    pub fn pieces(&self) -> Vec<(f64, f64, &str)> {
        self.pieces
            .iter()
            .map(|p| {
                let (lo, hi) = p.above.walls().beta();
                (lo, hi, self.below[p.member].0.as_str())
            })
            .collect()
    }

    /// The number of members.
    pub fn members(&self) -> usize {
        self.below.len()
    }

    /// One certificate for several enclosures (the rows of a grid of device sets), as
    /// [`AmaxCertificate::rows_json`] writes those of single devices (a single row its own
    /// certificate).
    pub fn rows_json(rows: &[Self]) -> String {
        match rows {
            [one] => one.to_json(),
            _ => grid_json(rows.iter().map(Self::to_json).collect()),
        }
    }

    /// The certificate as JSON text (kind `set`): the set, every member's certificate of the
    /// stable wall at `alpha_lo`; with one piece, the binding member's enclosure as an
    /// `alpha_max` certificate (`binding`, its stable wall the member's) and the claim
    /// (`alpha_lo`, `alpha_hi`, the count of `members` and the binding `member`); with more,
    /// the `pieces` (each its `member`, its box above as `unstable_above` and its `cap` when
    /// there is one) and the claim (`alpha_lo`, `alpha_hi`, the count of `members`, the
    /// dampings the pieces cover as `beta`, and `"stiffer": "none stable"` when every piece
    /// is capped); and a CRC-32 of the text before it.
    pub fn to_json(&self) -> String {
        let members: Vec<String> = self.below.iter().map(|(_, c)| c.to_json()).collect();
        let (lo, hi) = self.bounds();
        let n = self.below.len();
        let claim = format!(
            "\"alpha_lo\": \"{}\", \"alpha_hi\": \"{}\", \"members\": {n}",
            hex(lo),
            hex(hi)
        );
        if let [one] = self.pieces.as_slice() {
            let proof =
                AmaxCertificate::new(self.below[one.member].1.clone(), one.above.clone(), one.cap);
            let extra = format!("  \"binding\": {},\n", nested(&proof.to_json()));
            let claim = format!("{claim}, \"member\": {}", one.member);
            return set_json(&self.set, &members, &extra, &claim);
        }
        let mut extra = String::from("  \"pieces\": [");
        for (k, p) in self.pieces.iter().enumerate() {
            extra.push_str(if k == 0 { "\n    " } else { ",\n    " });
            let _ = write!(extra, "{{\"member\": {}, ", p.member);
            if let Some(cap) = &p.cap {
                let _ = write!(extra, "\"cap\": {}, ", cap_json(cap));
            }
            let above = nested(&p.above.to_json()).replace('\n', "\n    ");
            let _ = write!(extra, "\"unstable_above\": {above}}}");
        }
        extra.push_str("],\n");
        let pieces = self.pieces();
        let (first, last) = (pieces[0].0, pieces[pieces.len() - 1].1);
        let stiffer = if self.every_stiffer_wall() {
            ", \"stiffer\": \"none stable\""
        } else {
            ""
        };
        let range = format!(", \"beta\": [\"{}\", \"{}\"]", hex(first), hex(last));
        set_json(
            &self.set,
            &members,
            &extra,
            &format!("{claim}{range}{stiffer}"),
        )
    }
}
