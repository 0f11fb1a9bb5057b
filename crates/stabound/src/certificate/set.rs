//! Certified verdicts over a finite set of devices (`docs/MODEL.md` section 11): a hand that
//! can let go, lists of loop-element values (`one-of:LIST`), on one device (one mass,
//! damping and delay).
//!
//! A finite set is proved member by member: each member's loop gets the certificate of one
//! loop (one wall, a box of walls, a lookup table), and the certificate of kind `set` holds
//! the set (each element's alternatives as certificate inputs, `"none"` for a member without
//! the element: the hand let go) and every member's certificate, in the order of the
//! combinations of the alternatives (the first element outermost). The checker requires the
//! members to be every combination once and to agree on everything else (the one wall, box or
//! table), checks each member's certificate as that of one loop, and then the set's claim:
//!
//! - every member stable (for every wall of the box): stable for the set;
//! - a member proved unstable (every wall of the box unstable for it, with its count of roots
//!   outside): unstable for the set, since that member fails; otherwise a member marginal or
//!   not proved makes the set so;
//! - the robust `alpha_max` (the largest stiffness with one damping stable for every member)
//!   in `[alpha_lo, alpha_hi]`: the wall `(alpha_lo, beta)` certified stable for every member,
//!   and for one member, the binding one, the proof that no damping of the searched range is
//!   stable at `alpha_hi` or stiffer ([`super::certify_alpha_max`]'s upper half). No wall
//!   from `alpha_hi` on is then stable for the whole set.

use std::fmt::Write as _;

use rayon::prelude::*;

use super::limit::{above, grid_json, holds_optimum, stable_below};
use super::region::{BoxCertificate, BoxClaim, WallBox, certify_box};
use super::{
    AmaxCertificate, Certificate, Claim, certify, element_inputs, hex, nested, opening, seal,
};
use crate::devices::DeviceSet;
use crate::elements::Loop;
use crate::error::{Error, Result};
use crate::params::Wall;
use crate::stability::{Checker, Options, Verdict};

/// Each element's alternatives as certificate inputs (`"none"` for a member without it), in
/// the order hand, transmission, actuator, filter.
pub(crate) type Alternatives = Vec<(&'static str, Vec<String>)>;

/// The members of the finite set `set` as loops, with their names
/// ([`DeviceSet::describe_member`]).
///
/// # Errors
///
/// [`Error::InvalidRequest`] for a set with an interval, or whose members differ in mass,
/// damping or delay (their walls, or their inputs, would not be one).
pub(crate) fn set_loops(set: &DeviceSet) -> Result<Vec<(Loop, String)>> {
    if set.has_intervals() {
        return Err(Error::InvalidRequest(
            "a certificate over a set of devices covers a finite set (a hand that can let go, one-of lists); an interval of a parameter is not certified: give its values as a list".into(),
        ));
    }
    let reference = *set.reference().device();
    set.sampled_members()
        .into_iter()
        .map(|m| {
            // exact: a member of the reference's very device reads the walls unscaled
            if *m.device() != reference {
                return Err(Error::InvalidRequest(
                    "a certificate over a set of devices covers lists of loop-element values and a hand that can let go on one device: give the mass, damping and delay as one number each, or certify each device alone".into(),
                ));
            }
            Ok((m.to_loop()?, set.describe_member(&m)))
        })
        .collect()
}

/// Sorts the members in the order of the combinations of their elements' alternatives (each
/// element's values in order of first appearance, `"none"` for a member without it), the
/// first element outermost, and returns those alternatives: the set the certificate names.
///
/// # Errors
///
/// [`Error::Numerical`] when the members are not every combination once (a set's members
/// are: its lists combine freely, and the hand let go is the hand's alternative `"none"`).
pub(crate) fn product_order<T: Clone>(members: &mut [(Loop, T)]) -> Result<Alternatives> {
    let inputs: Vec<Vec<(&'static str, String)>> =
        members.iter().map(|(lp, _)| element_inputs(lp)).collect();
    // a member's value of the element `name`, "none" without it
    let value = |e: &[(&'static str, String)], name: &str| {
        e.iter()
            .find(|(k, _)| *k == name)
            .map_or_else(|| "\"none\"".to_string(), |(_, v)| v.clone())
    };
    let mut set: Alternatives = Vec::new();
    for name in ["hand", "transmission", "actuator", "filter"] {
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
        set.push((name, alternatives));
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
            "the set's {} members are not every combination of their elements' values once ({combinations} combinations); certify each device alone",
            keyed.len()
        )));
    }
    let sorted: Vec<(Loop, T)> = keyed.into_iter().map(|(_, m)| members[m].clone()).collect();
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

/// Certifies the verdict of `wall` for every member of the finite set `set` ([`certify`]
/// on each member's loop; the set's walls are its reference device's, which every member
/// shares).
///
/// # Errors
///
/// [`Error::InvalidRequest`] for a set with an interval or whose members differ in mass,
/// damping or delay; as [`certify`] for a member.
pub fn certify_set(set: &DeviceSet, wall: &Wall, margin: f64) -> Result<SetCertificate> {
    prove_members(set, |lp| Ok(Proof::Wall(certify(lp, wall, margin)?)))
}

/// Certifies the verdict of every wall of `walls` for every member of the finite set `set`
/// ([`certify_box`] on each member's loop, at most `max_leaves` leaves each).
///
/// # Errors
///
/// As [`certify_set`], and as [`certify_box`] for a member.
pub fn certify_set_box(
    set: &DeviceSet,
    walls: &WallBox,
    max_leaves: usize,
) -> Result<SetCertificate> {
    prove_members(set, |lp| {
        Ok(Proof::Box(certify_box(lp, walls, max_leaves)?))
    })
}

/// Each member's proof by `prove`, in parallel (each member's proof does not depend on the
/// others', so the result does not depend on the number of threads).
fn prove_members(
    set: &DeviceSet,
    prove: impl Fn(Loop) -> Result<Proof> + Send + Sync,
) -> Result<SetCertificate> {
    let mut members = set_loops(set)?;
    let alternatives = product_order(&mut members)?;
    let proofs = members
        .par_iter()
        .map(|(lp, _)| prove(*lp))
        .collect::<Result<Vec<_>>>()?;
    Ok(SetCertificate {
        set: alternatives,
        members: members
            .into_iter()
            .zip(proofs)
            .map(|((_, name), p)| (name, p))
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
/// member): the wall `(alpha_lo, beta)` certified stable for every member, and for the
/// binding member, the proof that no wall with a damping of the range is stable at
/// `alpha_hi` or stiffer (or, where the budget did not prove that, at `alpha_hi`).
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
/// # Ok::<(), stabound::Error>(())
/// ```
#[derive(Debug, Clone)]
pub struct SetAmaxCertificate {
    set: Alternatives,
    /// Every member's name and its certificate of the stable wall, in the order of the
    /// combinations.
    below: Vec<(String, Certificate)>,
    /// The binding member's index and its enclosure (its stable wall the set's).
    binding: (usize, AmaxCertificate),
}

/// Certifies an enclosure of the robust `alpha_max` of the finite set `set`, whose optimum
/// `(alpha, beta)` was found by a search over the dampings `betas` (as
/// [`crate::robust::robust_alpha_max`]'s `alpha_max` and `beta_at_max`): the nearest wall
/// below `alpha` at `beta` certified stable for every member, and above it the upper half of
/// [`super::certify_alpha_max`] for a binding member (the members unstable just above the
/// optimum by the double-precision test are tried first, then the rest), at most
/// `max_leaves` leaves.
///
/// # Errors
///
/// As [`certify_set`]; [`Error::InvalidParameter`] when `betas` does not hold `beta`;
/// [`Error::Numerical`] when no wall within 0.1 % below is certified stable for every
/// member, or no member alone proves the stiffness within 10 % above unstable for every
/// damping of the range (the robust optimum lies where two members' limits cross: each
/// alone is stable above it at some damping).
pub fn certify_set_alpha_max(
    set: &DeviceSet,
    (alpha, beta): (f64, f64),
    betas: (f64, f64),
    max_leaves: usize,
) -> Result<SetAmaxCertificate> {
    holds_optimum(betas, beta)?;
    let mut members = set_loops(set)?;
    let alternatives = product_order(&mut members)?;
    let loops: Vec<Loop> = members.iter().map(|(lp, _)| *lp).collect();
    let below = stable_below(&loops, alpha, beta)?;
    // the members unstable just above the optimum first: the binding ones
    let just_above = Wall::new(alpha * (1.0 + 1e-6), beta)?;
    let mut order: Vec<(bool, usize)> = Vec::with_capacity(loops.len());
    for (i, lp) in loops.iter().enumerate() {
        let v = Checker::new(*lp, Options::default())?.verdict(&just_above)?;
        order.push((v != Verdict::Unstable, i));
    }
    order.sort();
    for (_, i) in order {
        if let Some(proof) = above(loops[i], below[i].clone(), alpha, betas, max_leaves)? {
            return Ok(SetAmaxCertificate {
                set: alternatives,
                below: members
                    .into_iter()
                    .zip(below)
                    .map(|((_, name), c)| (name, c))
                    .collect(),
                binding: (i, proof),
            });
        }
    }
    Err(Error::Numerical(format!(
        "no member alone is certified unstable for every damping in [{}, {}] within 10 % above the robust alpha_max ({max_leaves} leaves each): the optimum may lie where two members' limits cross",
        betas.0, betas.1
    )))
}

impl SetAmaxCertificate {
    /// The enclosure `(alpha_lo, alpha_hi)` of the robust `alpha_max`.
    pub fn bounds(&self) -> (f64, f64) {
        self.binding.1.bounds()
    }

    /// Whether no wall from `alpha_hi` on (with a damping of the range) is proved stable for
    /// the binding member; otherwise every wall at `alpha_hi` is proved unstable for it.
    pub fn every_stiffer_wall(&self) -> bool {
        self.binding.1.every_stiffer_wall()
    }

    /// The binding member's name ([`DeviceSet::describe_member`]).
    pub fn binding(&self) -> &str {
        &self.below[self.binding.0].0
    }

    /// The number of members.
    pub fn members(&self) -> usize {
        self.below.len()
    }

    /// One certificate for several enclosures (the rows of a grid of device sets), as
    /// [`AmaxCertificate::rows_json`] writes those of single devices.
    pub fn rows_json(rows: &[Self]) -> String {
        grid_json(rows.iter().map(Self::to_json).collect())
    }

    /// The certificate as JSON text (kind `set`): the set, every member's certificate of the
    /// stable wall at `alpha_lo`, the binding member's enclosure as an `alpha_max`
    /// certificate (`binding`, its stable wall the member's), the claim (`alpha_lo`,
    /// `alpha_hi`, the count of `members` and the binding `member`) and a CRC-32 of the text
    /// before it.
    pub fn to_json(&self) -> String {
        let members: Vec<String> = self.below.iter().map(|(_, c)| c.to_json()).collect();
        let (lo, hi) = self.bounds();
        let (i, proof) = &self.binding;
        let extra = format!("  \"binding\": {},\n", nested(&proof.to_json()));
        let claim = format!(
            "\"alpha_lo\": \"{}\", \"alpha_hi\": \"{}\", \"members\": {}, \"member\": {i}",
            hex(lo),
            hex(hi),
            self.below.len()
        );
        set_json(&self.set, &members, &extra, &claim)
    }
}
