//! The robust optimum of a set of devices and the robust verdict of one wall.
//!
//! # Method (robust `alpha_max`)
//!
//! A max-min problem in `beta` (docs/MODEL.md section 12): for each `beta` the robust limit
//! is the supremum of the intersection of the members' exact stable stiffness sets
//! ([`crate::search::stable_alphas`], in the set's reference normalization); the robust
//! `alpha_max` is its maximum over `beta`.
//!
//! 1. Start from a finite set `M` of members: every corner of every box (hand on and off).
//! 2. Solve the max-min over `M`: each member's own `alpha_max` ([`crate::alpha_max`]) gives
//!    its peak; if the lowest peak is stable for every other member of `M` at its `beta`, it
//!    is the answer (no member can do better than its own peak). Otherwise scan `beta` over
//!    the peaks' span (widened by a quarter each way) with 41 points and refine the best by
//!    golden-section search (Kiefer 1953) to `1e-13` of the span.
//! 3. At that `beta`, search the whole set for the member with the least room
//!    ([`super::sample`]: every corner, a coarse grid, then a coordinate search). If a member
//!    outside `M` cuts the optimum by more than a relative `1e-9`, add it to `M` and go to 2.
//! 4. Verify: the stiffness [`VERIFY_GAP`] below the optimum is shown stable for every member:
//!    proved by the box recursion of [`super::prove_wall`] when the set spreads parameters it
//!    encloses and the cells close within the budget, otherwise by the sampling argument of
//!    [`super::sample`]
//!    (not a proof; for a set without intervals, every
//!    member is one of `M` and the optimum is exact). A sample that fails joins `M` (step 2);
//!    cells the budget leaves unresolved lower the verified stiffness by their shortfall.

use std::cell::Cell;

use super::proof::{PROOF_BUDGET, ProofStop, prove_or_uncovered};
use super::sample::{Outcome, Probe, room};
use super::{DeviceSet, Member, intersect};
use crate::amax::{AmaxOptions, alpha_max};
use crate::error::{Error, Result};
use crate::golden::golden_max_above;
use crate::params::Wall;
use crate::search::{Interval, stable_alphas};
use crate::stability::{Checker, Options, Verdict};

/// How far below the search's optimum the verified stiffness of a set with intervals is
/// placed: a relative `1e-3`, so that the sampling argument has room to close (its cells
/// must shrink until the slope times the width is below the room) while the wall gives up
/// a tenth of a percent.
pub const VERIFY_GAP: f64 = 1e-3;

/// The most rounds of search and verification: each round adds the members that cut the
/// optimum; a round without one ends the search.
const MAX_ROUNDS: usize = 12;

/// A member joins the search only when it cuts the optimum by more than this (relative):
/// above the exact stable sets' rounding (`1e-13`), below anything a wall notices.
const CUT: f64 = 1e-9;

/// How the robust answer was shown to hold for the whole set.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case", tag = "method"))]
#[non_exhaustive]
pub enum Verification {
    /// A finite set: every member's exact stable set was intersected, which checks every
    /// member (a complete answer for a finite set).
    Exact {
        /// The members.
        members: usize,
    },
    /// Intervals: the sampling argument of [`super::sample`] held on every cell, after the
    /// box recursion of [`super::prove_wall`] stopped short of a proof.
    ///
    /// ```
    /// use stabound::robust::{ProofStop, Verification};
    ///
    /// let sampled = Verification::Sampled {
    ///     samples: 870,
    ///     cells: 357,
    ///     proof: ProofStop::Budget { cells: 1024, undecided: 517, smallest: 1.0 / 32.0 },
    /// };
    /// assert!(sampled.holds());
    /// let shown = sampled.describe();
    /// assert!(shown.contains("(not a proof; the box proof stopped: cell budget spent at 1024 cells"));
    /// assert!(shown.ends_with(
    ///     "with 517 undecided; the smallest undecided cell is still 3.125e-2 of its box's width \
    ///      in its widest parameter)"
    /// ));
    /// ```
    Sampled {
        /// Members evaluated.
        samples: usize,
        /// Cells at the end.
        cells: usize,
        /// Why the box recursion stopped short of a proof.
        proof: ProofStop,
    },
    /// Intervals the box recursion of [`super::prove_wall`] encloses: it proved the wall
    /// stable on every cell.
    Proved {
        /// Cells the box ended as.
        leaves: usize,
    },
    /// Intervals, and the sampling budget ran out: the verified stiffness was lowered by the
    /// cells' shortfall, and those cells are still not shown to hold.
    Unresolved {
        /// Members evaluated.
        samples: usize,
        /// The most negative bound of a cell (normalized stiffness).
        shortfall: f64,
    },
}

impl Verification {
    /// One line for reports.
    pub fn describe(&self) -> String {
        match self {
            Verification::Exact { members } => {
                format!(
                    "checked for every member: the intersection of the {members} members' exact stable sets (complete for a finite set)"
                )
            }
            Verification::Sampled {
                samples,
                cells,
                proof,
            } => format!(
                "sampling argument: {samples} members in {cells} cells; Lipschitz bound of twice the steepest slope seen (not a proof; the box proof stopped: {})",
                proof.describe()
            ),
            Verification::Proved { leaves } => {
                format!("proved over the box: interval Schur-Cohn and Rouche on {leaves} cells")
            }
            Verification::Unresolved { samples, shortfall } => format!(
                "UNRESOLVED: after {samples} members some cells still fall short by {shortfall:e}"
            ),
        }
    }

    /// Why the box recursion stopped short of a proof, where the sampling argument then
    /// covered the set (`None` for an exact, proved or unresolved answer).
    ///
    /// ```
    /// use stabound::robust::{ProofStop, Verification};
    ///
    /// let sampled = Verification::Sampled { samples: 40, cells: 9, proof: ProofStop::Inseparable };
    /// assert_eq!(sampled.proof_stop(), Some(&ProofStop::Inseparable));
    /// assert_eq!(Verification::Proved { leaves: 33 }.proof_stop(), None);
    /// ```
    pub fn proof_stop(&self) -> Option<&ProofStop> {
        match self {
            Verification::Sampled { proof, .. } => Some(proof),
            _ => None,
        }
    }

    /// Whether the answer was shown to hold (exactly, by proof or by the sampling argument).
    pub fn holds(&self) -> bool {
        !matches!(self, Verification::Unresolved { .. })
    }
}

/// The robust optimum of a [`DeviceSet`]: the largest stiffness for which one damping is
/// stable for every member, in the set's reference normalization.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct RobustAmax {
    /// The max-min found by the search: the supremum of the robust stable stiffness at
    /// `beta_at_max` (on the boundary of the binding member, as `alpha_max` is).
    pub alpha_max: f64,
    /// The damping of the robust optimum.
    pub beta_at_max: f64,
    /// The stiffness shown stable at `beta_at_max` for every member: `alpha_max` for a finite
    /// set (every stiffness below it), [`VERIFY_GAP`] below it (or lower, when unresolved)
    /// with intervals.
    pub alpha_verified: f64,
    /// The members whose stable limit at `beta_at_max` is the optimum (within `1e-6`).
    pub binding: Vec<Member>,
    /// Every member whose stable set was computed.
    pub examined: usize,
    /// How the answer was shown to hold.
    pub verification: Verification,
}

/// A member's loop and its stable sets at any reference damping.
struct Judge {
    member: Member,
    checker: Checker,
    scale: f64,
    peak: (f64, f64),
}

impl Judge {
    fn new(member: Member, m_ref: f64, opts: &AmaxOptions) -> Result<Self> {
        let s = m_ref / member.device.mass;
        let limits = opts.with_beta_limits(
            opts.beta_min().map(|b| b * s),
            opts.beta_max().map(|b| b * s),
        )?;
        let lp = member.to_loop()?;
        let a = alpha_max(lp, &limits)?;
        Ok(Self {
            member,
            checker: Checker::new(lp, Options::default())?,
            scale: s,
            peak: (a.alpha_max / s, a.beta_at_max / s),
        })
    }

    /// The member's stable stiffnesses at reference damping `beta`, in reference units.
    fn alphas(&self, beta: f64) -> Result<Vec<Interval>> {
        scaled_alphas(&self.checker, self.scale, beta)
    }
}

/// The stable stiffnesses of the member whose checker is `checker` at reference damping
/// `beta`, in reference units (`scale = m_ref / m`: the member sees `scale (alpha, beta)`).
pub(super) fn scaled_alphas(checker: &Checker, scale: f64, beta: f64) -> Result<Vec<Interval>> {
    let s = scale;
    Ok(stable_alphas(checker, s * beta)?
        .into_iter()
        .map(|i| Interval {
            lo: i.lo / s,
            hi: i.hi / s,
        })
        .collect())
}

/// The robust limit at `beta` (the supremum of the members' common stable stiffnesses,
/// `-inf` where they share none) where only a limit of at least `floor` is needed (`-inf`:
/// always the limit itself). The members are intersected starting with `first` (the member
/// with the lowest supremum of the last call, which it updates), and as soon as the
/// supremum of the intersection so far falls below `floor` that supremum is returned: the
/// limit is at most it (the intersection only shrinks), so below `floor` too. At or above
/// `floor` the value is the limit itself, the same in every order of the members (the
/// intersection of the same intervals: each end is one of theirs).
fn limit_above(judges: &[Judge], beta: f64, floor: f64, first: &Cell<usize>) -> Result<f64> {
    let n = judges.len();
    let mut common: Option<Vec<Interval>> = None;
    let mut lowest = (f64::INFINITY, first.get());
    for k in 0..n {
        let i = (first.get() + k) % n;
        let s = judges[i].alphas(beta)?;
        let top = s.last().map_or(f64::NEG_INFINITY, |x| x.hi);
        if top < lowest.0 {
            lowest = (top, i);
        }
        let c = match common {
            None => s,
            Some(c) => intersect(&c, &s),
        };
        let sup = c.last().map_or(f64::NEG_INFINITY, |x| x.hi);
        common = Some(c);
        // below floor (or empty, where no member after this one can add a stiffness back)
        if sup < floor || sup == f64::NEG_INFINITY {
            first.set(lowest.1);
            return Ok(sup);
        }
    }
    first.set(lowest.1);
    Ok(common
        .and_then(|c| c.last().map(|i| i.hi))
        .unwrap_or(f64::NEG_INFINITY))
}

/// The max-min over the finite set `judges` (module documentation, step 2).
fn max_min(judges: &[Judge], opts: &AmaxOptions) -> Result<(f64, f64)> {
    let lowest = judges
        .iter()
        .min_by(|x, y| x.peak.0.total_cmp(&y.peak.0))
        .ok_or_else(|| Error::InvalidRequest("the set has no member".into()))?;
    let (a0, b0) = lowest.peak;
    // the member that bound last is intersected first: below the floor it alone often
    // shows that a point cannot be the answer
    let first = Cell::new(0);
    let at_lowest = limit_above(judges, b0, a0 * (1.0 - CUT), &first)?;
    // the lowest peak bounds the robust optimum; within rounding of it, it is the optimum
    if at_lowest >= a0 * (1.0 - CUT) {
        return Ok((at_lowest.min(a0), b0));
    }
    let (mut lo, mut hi) = judges
        .iter()
        .fold((b0, b0), |(l, h), j| (l.min(j.peak.1), h.max(j.peak.1)));
    let span = hi - lo;
    let widen = 0.25 * span + 1e-3 * hi.abs().max(lo.abs()).max(1e-6);
    lo -= widen;
    hi += widen;
    if let Some(b) = opts.beta_min() {
        lo = lo.max(b);
    }
    if let Some(b) = opts.beta_max() {
        hi = hi.min(b);
    }
    const SCAN: usize = 41;
    let betas: Vec<f64> = (0..SCAN)
        .map(|i| lo + (hi - lo) * i as f64 / (SCAN - 1) as f64)
        .collect();
    // a value below the best before it only needs to be shown below it: the scan keeps the
    // greatest (the last of those tied), which it is not
    let mut vals: Vec<f64> = Vec::with_capacity(SCAN);
    for &b in &betas {
        let best = vals.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        vals.push(limit_above(judges, b, best, &first)?);
    }
    let (best, _) = vals
        .iter()
        .enumerate()
        .max_by(|x, y| x.1.total_cmp(y.1))
        .expect("the scan has points");
    let (l, h) = (
        betas[best.saturating_sub(1)],
        betas[(best + 1).min(SCAN - 1)],
    );
    let tol = 1e-13 * (hi - lo).max(f64::MIN_POSITIVE);
    let [(c, fc), (d, fd)] = golden_max_above(
        |b, rival| limit_above(judges, b, rival, &first),
        (l, h),
        |l, h, _| h - l > tol,
    )?
    .points;
    let mut cands = vec![(fc, c), (fd, d), (vals[best], betas[best])];
    for j in judges {
        let best = cands.iter().map(|x| x.0).fold(f64::NEG_INFINITY, f64::max);
        cands.push((limit_above(judges, j.peak.1, best, &first)?, j.peak.1));
    }
    let (a, b) = cands
        .into_iter()
        .max_by(|x, y| x.0.total_cmp(&y.0))
        .expect("candidates");
    if !a.is_finite() {
        return Err(Error::InvalidRequest(
            "no wall is stable for every member of the set: narrow the intervals or lists".into(),
        ));
    }
    Ok((a, b))
}

/// The robust optimum of `set` within the beta limits of `opts` (in the set's reference
/// normalization): method in the module documentation.
///
/// ```
/// use stabound::elements::PhysicalElements;
/// use stabound::params::{Delay, Device};
/// use stabound::robust::{DeviceSet, robust_alpha_max};
/// use stabound::AmaxOptions;
///
/// // a hand on the handle: the free device is a member too
/// let device = Device::new(0.1, 1e-3, 0.0, Delay::Samples(1.0))?;
/// let mut hand = PhysicalElements::default();
/// hand.hand_mass = Some(0.3);
/// let set = DeviceSet::new(&device, &hand)?;
/// let r = robust_alpha_max(&set, &AmaxOptions::default())?;
/// let free = stabound::alpha_max(&device.plant()?, &AmaxOptions::default())?;
/// assert!(r.alpha_max <= free.alpha_max * (1.0 + 1e-9));
/// assert!(r.verification.holds());
/// # Ok::<(), stabound::Error>(())
/// ```
///
/// # Errors
///
/// As [`crate::alpha_max`] for a member; [`Error::InvalidRequest`] when no wall is stable
/// for every member.
pub fn robust_alpha_max(set: &DeviceSet, opts: &AmaxOptions) -> Result<RobustAmax> {
    let m_ref = set.device.mass;
    let mut judges: Vec<Judge> = Vec::new();
    let add = |judges: &mut Vec<Judge>, m: Member| -> Result<()> {
        if !judges.iter().any(|j| j.member == m) {
            judges.push(Judge::new(m, m_ref, opts)?);
        }
        Ok(())
    };
    for v in set.variants() {
        for c in v.corners() {
            add(&mut judges, v.member(&c))?;
        }
    }
    if let [one] = &judges[..]
        && set.variants().len() == 1
    {
        // one member: its own alpha_max is the answer, as the loop alone gives it
        return Ok(RobustAmax {
            alpha_max: one.peak.0,
            beta_at_max: one.peak.1,
            alpha_verified: one.peak.0,
            binding: vec![one.member],
            examined: 1,
            verification: Verification::Exact { members: 1 },
        });
    }
    let intervals = set.has_intervals();
    let mut examined = 0;
    for _ in 0..MAX_ROUNDS {
        crate::cancel::poll()?;
        let (a, b) = max_min(&judges, opts)?;
        let mut probe = Probe::new(set, b);
        if intervals {
            let (worst, r) = probe.least_room(a)?;
            if r < -CUT * a.abs() {
                examined += probe.evaluated();
                add(&mut judges, worst)?;
                continue;
            }
        }
        let target = if intervals { a * (1.0 - VERIFY_GAP) } else { a };
        let proof = if intervals {
            Some(proved(set, target, b)?)
        } else {
            None
        };
        let (verified, verification) = if let Some(Ok(leaves)) = proof {
            (target, Verification::Proved { leaves })
        } else if let Some(Err(stop)) = proof {
            let mut t = target;
            let mut outcome = probe.verify(t)?;
            for _ in 0..3 {
                match outcome {
                    Outcome::Short { shortfall, .. } => {
                        t += 2.0 * shortfall;
                        outcome = probe.verify(t)?;
                    }
                    _ => break,
                }
            }
            match outcome {
                Outcome::Fails(m) => {
                    examined += probe.evaluated();
                    add(&mut judges, *m)?;
                    continue;
                }
                Outcome::Holds { samples, cells } => (
                    t,
                    Verification::Sampled {
                        samples,
                        cells,
                        proof: stop,
                    },
                ),
                Outcome::Short { samples, shortfall } => {
                    (t, Verification::Unresolved { samples, shortfall })
                }
            }
        } else {
            (
                target,
                Verification::Exact {
                    members: judges.len(),
                },
            )
        };
        examined += probe.evaluated();
        let mut binding = Vec::new();
        for j in &judges {
            let r = room(&j.alphas(b)?, a * (1.0 - 1e-7));
            if r <= 2e-6 * a.abs() {
                binding.push(j.member);
            }
        }
        return Ok(RobustAmax {
            alpha_max: a,
            beta_at_max: b,
            alpha_verified: verified,
            binding,
            examined: examined + judges.len(),
            verification,
        });
    }
    Err(Error::Numerical(format!(
        "the robust search kept finding members that lower the optimum after {MAX_ROUNDS} rounds; narrow the intervals"
    )))
}

/// The number of cells on which the box recursion ([`super::prove_wall`]) proved the wall
/// `(alpha, beta)` for every member of `set`, or why it did not: the set is outside it, the
/// wall is no valid wall, the budget ran out, or a cell could not be decided.
fn proved(set: &DeviceSet, alpha: f64, beta: f64) -> Result<std::result::Result<usize, ProofStop>> {
    let Ok(wall) = Wall::new(alpha, beta) else {
        return Ok(Err(ProofStop::InvalidWall));
    };
    Ok(match prove_or_uncovered(set, &wall, PROOF_BUDGET)? {
        Ok(p) if p.proved => Ok(p.leaves.len()),
        // the recursion names its reason whenever it does not prove
        Ok(p) => Err(p.stopped.unwrap_or(ProofStop::Inseparable)),
        Err(q) => Err(ProofStop::Uncovered {
            quantity: q.name().into(),
        }),
    })
}

/// The robust verdict of one wall.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum RobustCheck {
    /// Stable for every member, shown as the [`Verification`] says.
    Stable(Verification),
    /// A member on which the wall is not stable, and its verdict there.
    Fails(Box<Member>, Verdict),
    /// Not shown either way: the sampling budget ran out (shortfall in normalized stiffness).
    Undecided {
        /// Members evaluated.
        samples: usize,
        /// The most negative bound of a cell.
        shortfall: f64,
    },
}

impl RobustCheck {
    /// The verdict for the whole set: stable when stable for every member, the failing
    /// member's verdict, or marginal when undecided (neither shown).
    pub fn verdict(&self) -> Verdict {
        match self {
            RobustCheck::Stable(_) => Verdict::Stable,
            RobustCheck::Fails(_, v) => *v,
            RobustCheck::Undecided { .. } => Verdict::Marginal,
        }
    }

    /// How the verdict was reached, in one line for reports.
    pub fn describe(&self) -> String {
        match self {
            RobustCheck::Stable(how) => how.describe(),
            RobustCheck::Fails(..) => "a member on which the wall is not stable".into(),
            RobustCheck::Undecided { samples, shortfall } => format!(
                "UNDECIDED: after {samples} members some cells of the set still fall short by {shortfall:e}"
            ),
        }
    }

    /// The member the wall fails on, if it does.
    pub fn failing(&self) -> Option<&Member> {
        match self {
            RobustCheck::Fails(m, _) => Some(m),
            _ => None,
        }
    }
}

/// Whether `wall` (in the set's reference normalization) is stable for every member of
/// `set`: the member with the least room is searched (corners, grid, coordinate search),
/// then the box recursion of [`super::prove_wall`] proves the wall over the boxes when the set
/// qualifies, else the sampling argument of [`super::sample`] covers them; a member without room is
/// judged by its point test ([`Checker::verdict`]).
///
/// ```
/// use stabound::elements::PhysicalElements;
/// use stabound::params::{Delay, Device, Wall};
/// use stabound::robust::{DeviceSet, Quantity, RobustCheck, robust_check};
///
/// let device = Device::new(1.0, 1.0, 0.5, Delay::Samples(1.0))?;
/// let set = DeviceSet::new(&device, &PhysicalElements::default())?
///     .with_interval(Quantity::Delay, 1.0, 3.0)?;
/// assert!(matches!(robust_check(&set, &Wall::new(0.05, 0.3)?)?, RobustCheck::Stable(_)));
/// assert!(matches!(robust_check(&set, &Wall::new(0.4, 0.3)?)?, RobustCheck::Fails(..)));
/// # Ok::<(), stabound::Error>(())
/// ```
///
/// # Errors
///
/// As [`crate::search::stable_alphas`] for a member.
pub fn robust_check(set: &DeviceSet, wall: &Wall) -> Result<RobustCheck> {
    let mut probe = Probe::new(set, wall.beta());
    let a = wall.alpha();
    let fails = |m: Member| -> Result<Option<RobustCheck>> {
        let s = set.device.mass / m.device.mass;
        let v = Checker::new(m.to_loop()?, Options::default())?
            .verdict(&Wall::new(a * s, wall.beta() * s)?)?;
        Ok((v != Verdict::Stable).then_some(RobustCheck::Fails(Box::new(m), v)))
    };
    let (worst, r) = probe.least_room(a)?;
    if r <= 0.0
        && let Some(f) = fails(worst)?
    {
        return Ok(f);
    }
    if !set.has_intervals() {
        return Ok(RobustCheck::Stable(Verification::Exact {
            members: probe.evaluated(),
        }));
    }
    let stop = match proved(set, a, wall.beta())? {
        Ok(leaves) => return Ok(RobustCheck::Stable(Verification::Proved { leaves })),
        Err(stop) => stop,
    };
    Ok(match probe.verify(a)? {
        Outcome::Holds { samples, cells } => RobustCheck::Stable(Verification::Sampled {
            samples,
            cells,
            proof: stop,
        }),
        Outcome::Fails(m) => match fails(*m)? {
            Some(f) => f,
            None => RobustCheck::Undecided {
                samples: probe.evaluated(),
                shortfall: 0.0,
            },
        },
        Outcome::Short { samples, shortfall } => RobustCheck::Undecided { samples, shortfall },
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::elements::PhysicalElements;
    use crate::params::{Delay, Device};
    use crate::robust::Quantity;

    /// A set that spreads an encoder's resolution (a quantizer the linear loop leaves out,
    /// so neither box recursion encloses it): the proof stops as uncovered, naming the
    /// parameter, after one pass over the set's boxes; the answer is then the sampling
    /// argument's, which says why.
    #[test]
    fn an_uncovered_parameter_stops_the_proof_after_one_pass() {
        let device = Device::new(0.1, 1e-3, 1.0, Delay::Samples(1.0)).unwrap();
        let set = DeviceSet::new(&device, &PhysicalElements::default())
            .unwrap()
            .with_interval(Quantity::element("encoder_resolution").unwrap(), 1e-6, 2e-6)
            .unwrap();
        let before = super::super::proof_elements::BUILT.with(|n| n.get());
        let stop = proved(&set, 0.01, 0.1).unwrap();
        let after = super::super::proof_elements::BUILT.with(|n| n.get());
        let uncovered = ProofStop::Uncovered {
            quantity: "encoder resolution".into(),
        };
        assert_eq!(stop, Err(uncovered.clone()));
        assert_eq!(after - before, 1);
        let wall = Wall::new(0.01, 0.1).unwrap();
        let RobustCheck::Stable(how) = robust_check(&set, &wall).unwrap() else {
            panic!("a soft wall on the paper's device is stable");
        };
        assert_eq!(how.proof_stop(), Some(&uncovered));
        assert!(how.describe().ends_with(
            "(not a proof; the box proof stopped: the box recursion does not cover an interval of encoder resolution)"
        ));
    }
}
