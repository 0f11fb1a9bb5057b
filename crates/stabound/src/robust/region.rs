//! The robust stable region of a set of devices in the `(alpha, beta)` plane: the walls
//! stable for every member, the intersection of the members' stable regions (docs/MODEL.md
//! section 12).
//!
//! # Method
//!
//! Exact one-dimensional searches along lines of constant damping, as the robust
//! `alpha_max` uses them ([`super::robust_alpha_max`]):
//!
//! 1. The members: every member of a finite set; with intervals, first the sample of
//!    [`DeviceSet::sampled_members`] (ends and middle of each interval in every
//!    combination), then the members the search of step 3 finds.
//! 2. Each member's exact boundary ([`crate::boundary::exact`], D-decomposition) gives the
//!    dampings its region spans; the robust region lies within their intersection.
//! 3. At 64 dampings across it, the common stable stiffnesses: the intersection of the
//!    members' exact stable sets ([`crate::search::stable_alphas`], each in the reference
//!    normalization). Where they form several pieces the one reaching the largest stiffness
//!    is kept ([`RobustRegion::pieces`] counts them). With intervals the worst member need
//!    not be in the sample (a delay between the ends can empty the strip the ends leave),
//!    so at every damping the robust `alpha_max`'s search for the member with the least
//!    room (every corner, a coarse grid, a coordinate search by golden section) runs over
//!    the whole set at the strip's edges moved inward by `tol` (the upper edge, and the
//!    lower one where it is not `alpha = 0`, which bounds every member's set exactly): a
//!    member without room there cuts the strip by more than `tol`, is intersected, and the
//!    search runs again on the new edges, at most [`SEARCH_ROUNDS`] times per damping
//!    ([`RegionSearch`] counts the dampings where members still cut when they ran out).
//!    `tol` is the tolerance the region is drawn to: a member cutting less moves an edge by
//!    less than the drawing's own error.
//!    Below [`FIRST_PASS_TOL`] the region is drawn twice: first to [`FIRST_PASS_TOL`] with
//!    the search at every damping (cuts still counted from `tol`), recording at each the
//!    members that cut and, of the members outside the sample the search evaluated there,
//!    the one with the least room when it cuts the edge by more than half of `tol`; then to
//!    `tol`, with the search over the whole set at the scan and at the bisection of the
//!    ends, and at the dampings of the refinement as the two dampings of the first pass on
//!    either side recorded: where a member cut at one, the search near the members
//!    recorded there ([`Probe::least_room_near`]: the binding member moves little between
//!    neighbouring dampings); where none cut but a member was near cutting, that member's
//!    room is checked, and where it cuts, the search near it runs (a member that cuts only
//!    between two dampings of the first pass as it crosses into the strip); elsewhere the
//!    sample alone. A member that cuts only between two dampings of the first pass while
//!    cutting less than half of `tol` at both (or not at all), or far from the members
//!    recorded on either side, is missed, as a member cutting only between two dampings of
//!    a single pass would be; [`RegionSearch`] says how many dampings of the final pass
//!    were searched and checked.
//! 4. Where the common set becomes empty, the damping is found by bisection to `tol`;
//!    between consecutive dampings the chord is split while a midpoint's ends lie more than
//!    `tol` from it (at most 16 times), as the bisection engine refines its
//!    chords ([`crate::boundary::bisect`]).
//! 5. The polygon: the upper ends for increasing damping, then the lower ends back
//!    (counterclockwise, closed).
//! 6. With intervals, the box recursion of [`super::prove_wall`] is tried on up to
//!    [`PROOF_POINTS`] walls spread along the upper edge, each `tol` inside it: each one it
//!    proves is stable for every member of the set; the rest of the region rests on the
//!    search (a sample, not a proof). [`RegionSearch`] counts both.

use rayon::prelude::*;

use std::sync::Mutex;

use super::proof::{PROOF_BUDGET, prove_wall};
use super::sample::{Point, Probe, member_alphas};
use super::search::scaled_alphas;
use super::{DeviceSet, Member, intersect};
use crate::boundary::{Boundary, Engine, Piece, SweepOptions, Vertex, check_tol, trace};
use crate::error::{Error, Result};
use crate::params::Wall;
use crate::search::Interval;
use crate::stability::{Checker, Options};

/// Dampings of the first scan across the span of the members' regions: enough that a
/// region a sixtieth of the span wide is seen; the refinement does the rest.
const SCAN: usize = 64;

/// The most times one chord of the scan is halved: `2^16` segments per chord at most.
const MAX_DEPTH: usize = 16;

/// The most times the search for a member that cuts the strip runs at one damping (module
/// documentation, step 3): the search returns the member with the least room, so one
/// round finds the binding member and the next confirms it; more are for strips several
/// members cut in turn (both edges, or a member that splits the strip).
pub const SEARCH_ROUNDS: usize = 6;

/// The tolerance of the first pass of a searched region (module documentation, step 3):
/// the region is first drawn to this tolerance (or to `tol` when coarser) with the search
/// at every damping, a few thousand dampings; the final pass searches only where a member
/// cut in the first. A thousand times the default `tol`, still well below a drawing's
/// resolution, so that the first pass sees every stretch a member narrows by more than
/// its own chords' error.
pub const FIRST_PASS_TOL: f64 = 1e-6;

/// The most walls along the upper edge the box recursion is tried on (module
/// documentation, step 6): each costs up to [`PROOF_BUDGET`] cells, tens of microseconds
/// each, so a few seconds at most in all.
pub const PROOF_POINTS: usize = 16;

/// How the region of a set with intervals was found: the search over the set at every
/// damping and the walls the box recursion proved ([`RobustRegion::search`]).
///
/// ```
/// use stabound::elements::PhysicalElements;
/// use stabound::params::{Delay, Device};
/// use stabound::robust::{DeviceSet, Quantity, robust_region};
///
/// // delta = 2 and a delay anywhere in 1..3 samples: a delay between 2 and 3 binds where
/// // the ends and middle do not
/// let device = Device::new(1.0, 1.0, 2.0, Delay::Samples(1.0))?;
/// let set = DeviceSet::new(&device, &PhysicalElements::default())?
///     .with_interval(Quantity::Delay, 1.0, 3.0)?;
/// let r = robust_region(&set, 1e-5)?;
/// let s = r.search.as_ref().expect("an interval is searched");
/// assert!(!r.exact && s.found > 0 && s.unresolved == 0);
/// assert!(s.describe(1e-5).contains("proved by the box recursion"));
/// # Ok::<(), stabound::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct RegionSearch {
    /// Dampings at which the set was searched (both passes together).
    pub dampings: usize,
    /// The first pass's tolerance when the search ran in two passes ([`FIRST_PASS_TOL`]):
    /// every damping of a first pass drawn to it searched over the whole set, then the final
    /// pass as the first recorded (module documentation, step 3); `None` when every damping
    /// of the final pass was searched over the whole set.
    pub first_pass: Option<f64>,
    /// Of the final pass's dampings with common stable stiffnesses, how many were searched:
    /// over the whole set at its scan and the bisection of its ends, near the members that
    /// cut at the neighbouring dampings of the first pass elsewhere (all of them, over the
    /// whole set, without a first pass).
    pub final_searched: usize,
    /// Dampings of the final pass with common stable stiffnesses.
    pub final_dampings: usize,
    /// Dampings of the final pass between two of the first where no member cut the strip
    /// by `tol` but one cut it by more than half of that: the rooms of those members were
    /// checked there.
    pub checked: usize,
    /// Of those, the dampings where one of them cut the strip by more than `tol` (a member
    /// that cuts only between two dampings of the first pass): the set was searched near it.
    pub caught: usize,
    /// Members whose stable set the searches computed (all dampings together).
    pub evaluated: usize,
    /// Distinct members outside the sample that cut a strip by more than `tol`.
    pub found: usize,
    /// The member that cut deepest into the strip the members before it left, and by how
    /// much (normalized stiffness, measured `tol` inside the edge it cut; a member with no
    /// stable stiffness at that damping counts as cutting the whole strip and more).
    pub deepest: Option<(Member, f64)>,
    /// Dampings where a member still cut the strip after [`SEARCH_ROUNDS`] searches: there
    /// the region may be up to the next member's cut too large.
    pub unresolved: usize,
    /// Walls `tol` inside the upper edge the box recursion was tried on (none when the set
    /// spreads a parameter it does not enclose).
    pub proof_tried: usize,
    /// Of those, the walls proved stable for every member of the set.
    pub proved: usize,
}

impl RegionSearch {
    /// One line for reports: what was searched and found, and what was proved (`tol` the
    /// region's tolerance); the example on [`RegionSearch`] prints it.
    pub fn describe(&self, tol: f64) -> String {
        let mut s = match self.first_pass {
            None => format!(
                "the intersection over the ends and middle of each interval and the members a search over the whole set found at each of {} dampings ({} members evaluated, {} found cutting the strip by more than {tol:e}",
                self.dampings, self.evaluated, self.found
            ),
            Some(c) => format!(
                "the intersection over the ends and middle of each interval and the members a search over the whole set found at {} dampings: every damping of a first pass drawn to {c:e}, then at {} of the final pass's {} dampings: over the whole set at its scan and the bisection of its ends, near the members that cut at the first pass's neighbouring dampings elsewhere; at {} more the members that cut the edge by more than half of {tol:e} at the first pass's neighbouring dampings were checked, {} of which cut by more than {tol:e} ({} members evaluated, {} found cutting the strip by more than {tol:e}",
                self.dampings,
                self.final_searched,
                self.final_dampings,
                self.checked,
                self.caught,
                self.evaluated,
                self.found
            ),
        };
        if self.unresolved > 0 {
            s += &format!(
                "; search budget spent with a member still cutting at {} dampings",
                self.unresolved
            );
        }
        s += "); ";
        s += &if self.proof_tried == 0 {
            "sampled by the search, not proved (the box recursion does not enclose this set)"
                .to_string()
        } else {
            format!(
                "{} of {} walls {tol:e} inside the upper edge proved by the box recursion, the rest of the region sampled by the search (not proved)",
                self.proved, self.proof_tried
            )
        };
        s
    }
}

/// The robust stable region of a [`DeviceSet`] ([`robust_region`]).
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct RobustRegion {
    /// The region's boundary in the set's reference normalization (`delta` and `d` those of
    /// the reference member): a closed counterclockwise polyline.
    pub boundary: Boundary,
    /// The members intersected.
    pub members: Vec<Member>,
    /// Each member's own exact boundary, in the reference normalization, in the order of
    /// `members`.
    pub member_boundaries: Vec<Boundary>,
    /// Whether every member of the set was intersected (a finite set); `false` with
    /// intervals, where `members` are a sample and [`RobustRegion::search`] says what the
    /// search over the set added.
    pub exact: bool,
    /// With intervals: how the search over the set found the region and what the box
    /// recursion proved of it.
    pub search: Option<RegionSearch>,
    /// The most pieces the common stable stiffnesses formed at one damping (1 when the
    /// region is one strip per damping, as in every loop we know of).
    pub pieces: usize,
}

/// The members' checkers with their scales (`m_ref / m`), and with intervals the set the
/// search runs over.
struct Tests<'a> {
    members: &'a [(Checker, f64)],
    search: Option<Search<'a>>,
}

/// The search over a set with intervals (module documentation, step 3) and what it found.
struct Search<'a> {
    set: &'a DeviceSet,
    sample: &'a [Member],
    tol: f64,
    /// The first pass's dampings in increasing order, what its search found at each: `None`
    /// in a first pass or a single one (the full search at every damping).
    track: Option<Vec<Logged>>,
    found: Mutex<Found>,
}

/// A damping searched and what the search found there.
#[derive(Debug, Clone)]
struct Logged {
    beta: f64,
    /// Whether a member cut the strip there.
    cut: bool,
    /// The members outside the sample that cut the strip there, and of the members outside
    /// the sample the search evaluated, the one with the least room at its last targets
    /// when it cuts the edge by more than half of `tol` (a member near cutting).
    near: Vec<Point>,
}

/// How the set is searched at one damping of the final pass (module documentation, step 3).
enum Mode {
    /// The least-room search over the whole set.
    Full,
    /// The least-room search near these members (a member cut at a neighbouring damping of
    /// the first pass).
    Near(Vec<Point>),
    /// The rooms of these members alone (the ones nearest to cutting at the neighbouring
    /// dampings of the first pass, none of which cut); where one cuts, the search near them.
    Check(Vec<Point>),
    /// The sample alone.
    Sample,
}

/// What the searches found so far: the counts, the members outside the sample, and each
/// damping searched.
struct Found {
    stats: RegionSearch,
    members: Vec<Member>,
    log: Vec<Logged>,
}

impl Found {
    /// Nothing found yet.
    fn new() -> Self {
        Self {
            stats: RegionSearch {
                dampings: 0,
                first_pass: None,
                final_searched: 0,
                final_dampings: 0,
                checked: 0,
                caught: 0,
                evaluated: 0,
                found: 0,
                deepest: None,
                unresolved: 0,
                proof_tried: 0,
                proved: 0,
            },
            members: Vec::new(),
            log: Vec::new(),
        }
    }
}

impl Search<'_> {
    /// How the set is searched at reference damping `beta`; `always`: in full whatever the
    /// first pass found (the scan and the bisection of the ends).
    fn mode(&self, beta: f64, always: bool) -> Mode {
        let Some(track) = self.track.as_ref().filter(|_| !always) else {
            return Mode::Full;
        };
        // the first pass's dampings on either side of beta
        let i = track.partition_point(|l| l.beta <= beta);
        let around = &track[i.saturating_sub(1)..(i + 1).min(track.len())];
        let mut hints: Vec<Point> = Vec::new();
        for p in around.iter().flat_map(|l| &l.near) {
            if !hints.contains(p) {
                hints.push(p.clone());
            }
        }
        if around.iter().any(|l| l.cut) {
            Mode::Near(hints)
        } else if hints.is_empty() {
            Mode::Sample
        } else {
            Mode::Check(hints)
        }
    }

    /// Narrows `common` (the sample's common stable stiffnesses at reference damping
    /// `beta`) by the members of the set that cut its last piece by more than `tol`, found
    /// as `mode` says.
    fn narrow(&self, beta: f64, mut common: Vec<Interval>, mode: &Mode) -> Result<Vec<Interval>> {
        let m_ref = self.set.device.mass;
        let mut probe = Probe::new(self.set, beta);
        let mut cuts: Vec<(Point, f64)> = Vec::new();
        let mut last_targets: Vec<f64> = Vec::new();
        let mut resolved = false;
        let (mut hints, mut check) = match mode {
            Mode::Full | Mode::Sample => (Vec::new(), false),
            Mode::Near(h) => (h.clone(), false),
            Mode::Check(h) => (h.clone(), true),
        };
        let full = matches!(mode, Mode::Full);
        for _ in 0..SEARCH_ROUNDS {
            let Some(top) = common.last().copied() else {
                resolved = true;
                break;
            };
            let targets = if top.hi - top.lo <= 2.0 * self.tol {
                vec![0.5 * (top.lo + top.hi)]
            } else if top.lo == 0.0 {
                // exact: alpha = 0 bounds every member's stable set (module documentation)
                vec![top.hi - self.tol]
            } else {
                vec![top.hi - self.tol, top.lo + self.tol]
            };
            let mut cut = None;
            last_targets.clone_from(&targets);
            for a in targets {
                let found = if full {
                    Some(probe.least_room_point(a, true)?)
                } else if check {
                    let mut b: Option<(Point, f64)> = None;
                    for h in &hints {
                        let r = probe.room_of(h, a)?;
                        if b.as_ref().is_none_or(|x| r < x.1) {
                            b = Some((h.clone(), r));
                        }
                    }
                    b
                } else {
                    probe.least_room_near(a, &hints)?
                };
                let Some((p, r)) = found else {
                    continue;
                };
                if r < 0.0 {
                    cut = Some((p, -r));
                    break;
                }
            }
            let Some((p, depth)) = cut else {
                resolved = true;
                break;
            };
            common = intersect(&common, &member_alphas(&probe.member(&p), m_ref, beta)?);
            // a member the check found cutting: search near it from here on
            check = false;
            if !hints.contains(&p) {
                hints.push(p.clone());
            }
            cuts.push((p, depth));
        }
        // the members that cut, and the one outside the sample nearest to cutting of those
        // evaluated, where it cuts the edge by more than half of tol (its room below half of
        // tol, where the member binding the edge has tol; rounding is far below that)
        let in_sample = |m: &Member| self.sample.contains(m);
        let threat = probe
            .least_evaluated(&last_targets, in_sample)
            .filter(|t| t.1 < 0.5 * self.tol)
            .map(|t| t.0);
        let mut near: Vec<Point> = Vec::new();
        for p in cuts.iter().map(|c| &c.0).chain(&threat) {
            if !near.contains(p) && !in_sample(&probe.member(p)) {
                near.push(p.clone());
            }
        }
        let mut f = self.found.lock().unwrap_or_else(|e| e.into_inner());
        let Found {
            stats,
            members: found,
            log,
        } = &mut *f;
        log.push(Logged {
            beta,
            cut: !cuts.is_empty(),
            near,
        });
        if matches!(mode, Mode::Check(_)) {
            stats.checked += 1;
            stats.caught += usize::from(!cuts.is_empty());
        }
        if !check {
            stats.dampings += 1;
        }
        stats.evaluated += probe.evaluated();
        if !resolved {
            stats.unresolved += 1;
        }
        for (p, depth) in cuts {
            let m = probe.member(&p);
            if !self.sample.contains(&m) && !found.contains(&m) {
                found.push(m);
            }
            if stats.deepest.as_ref().is_none_or(|d| depth > d.1) {
                stats.deepest = Some((m, depth));
            }
        }
        Ok(common)
    }
}

impl Tests<'_> {
    /// The piece of the common stable stiffnesses at reference damping `beta` that reaches
    /// the largest stiffness, and how many pieces there are; `always`: search the whole set
    /// there whatever the first pass found (the scan and the bisection of the ends).
    fn at(&self, beta: f64, always: bool) -> Result<(Option<Interval>, usize)> {
        let mut common: Option<Vec<Interval>> = None;
        for (c, s) in self.members {
            let a = scaled_alphas(c, *s, beta)?;
            common = Some(match common {
                None => a,
                Some(x) => intersect(&x, &a),
            });
            if common.as_ref().is_some_and(Vec::is_empty) {
                break;
            }
        }
        let mut common = common.unwrap_or_default();
        if let Some(search) = &self.search
            && !common.is_empty()
        {
            let mode = search.mode(beta, always);
            {
                let mut f = search.found.lock().unwrap_or_else(|e| e.into_inner());
                f.stats.final_dampings += 1;
                f.stats.final_searched += usize::from(matches!(mode, Mode::Full | Mode::Near(_)));
            }
            if !matches!(mode, Mode::Sample) {
                common = search.narrow(beta, common, &mode)?;
            }
        }
        Ok((common.last().copied(), common.len()))
    }
}

/// A damping and the common stable stiffnesses there.
type Strip = (f64, Interval);

/// The robust stable region of `set` in the `(alpha, beta)` plane, to `tol` (normalized
/// units): method in the module documentation.
///
/// ```
/// use stabound::elements::PhysicalElements;
/// use stabound::params::{Delay, Device};
/// use stabound::robust::{DeviceSet, robust_region};
///
/// // the paper's device, its delay one sample or two
/// let device = Device::new(1.0, 1.0, 0.5, Delay::Samples(1.0))?;
/// let set = DeviceSet::new(&device, &PhysicalElements::default())?
///     .with_values(stabound::robust::Quantity::Delay, &[1.0, 2.0])?;
/// let r = robust_region(&set, 1e-6)?;
/// assert!(r.exact && r.members.len() == 2);
/// // the intersection is no larger than either member's region
/// let smallest = r.member_boundaries.iter().map(|b| b.area()).fold(f64::INFINITY, f64::min);
/// assert!(r.boundary.area() <= smallest * (1.0 + 1e-3));
/// # Ok::<(), stabound::Error>(())
/// ```
///
/// # Errors
///
/// An invalid `tol` ([`crate::boundary::check_tol`]); a member's exact boundary's errors;
/// [`Error::InvalidRequest`] when no wall is stable for every member.
pub fn robust_region(set: &DeviceSet, tol: f64) -> Result<RobustRegion> {
    let tol = check_tol(tol)?;
    let m_ref = set.reference().device().mass;
    let mut members: Vec<Member> = Vec::new();
    for m in set.sampled_members() {
        if !members.contains(&m) {
            members.push(m);
        }
    }
    let opts = SweepOptions {
        engine: Engine::Exact,
        tol,
    };
    let traced: Vec<(Checker, f64, Boundary)> = members
        .par_iter()
        .map(|m| -> Result<_> {
            let lp = m.to_loop()?;
            let s = m_ref / m.device.mass;
            let mut b = trace(lp, &opts)?;
            for p in &mut b.points {
                p.x /= s;
                p.y /= s;
            }
            Ok((Checker::new(lp, Options::default())?, s, b))
        })
        .collect::<Result<_>>()?;
    let span = traced
        .iter()
        .fold((f64::NEG_INFINITY, f64::INFINITY), |r, (_, _, b)| {
            let (lo, hi) = b
                .points
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), p| {
                    (l.min(p.y), h.max(p.y))
                });
            (r.0.max(lo), r.1.min(hi))
        });
    // NaN ends (a member without points) count as no span
    if span.0.partial_cmp(&span.1) != Some(std::cmp::Ordering::Less) {
        return Err(no_region());
    }
    let mut member_boundaries = Vec::with_capacity(traced.len());
    let checkers: Vec<(Checker, f64)> = traced
        .into_iter()
        .map(|(c, s, b)| {
            member_boundaries.push(b);
            (c, s)
        })
        .collect();
    let search = |track, found| Search {
        set,
        sample: &members,
        tol,
        track,
        found: Mutex::new(found),
    };
    let empty = Found::new();
    let tests = if set.has_intervals() && tol < FIRST_PASS_TOL {
        // two passes (module documentation, step 3): every damping of the first searched
        // over the whole set, then as it recorded
        let first = Tests {
            members: &checkers,
            search: Some(search(None, empty)),
        };
        draw(&first, span, FIRST_PASS_TOL)?;
        let s = first.search.expect("searched");
        let mut found = s.found.into_inner().unwrap_or_else(|e| e.into_inner());
        let mut track = std::mem::take(&mut found.log);
        track.sort_by(|a, b| a.beta.total_cmp(&b.beta));
        found.stats.first_pass = Some(FIRST_PASS_TOL);
        found.stats.final_dampings = 0;
        found.stats.final_searched = 0;
        Tests {
            members: &checkers,
            search: Some(search(Some(track), found)),
        }
    } else {
        Tests {
            members: &checkers,
            search: set.has_intervals().then(|| search(None, empty)),
        }
    };
    let (strips, pieces) = draw(&tests, span, tol)?;
    let reference = set.reference().to_loop()?;
    let mut points: Vec<Vertex> = strips
        .iter()
        .map(|&(b, i)| Vertex {
            x: i.hi,
            y: b,
            piece: Piece::Bisection,
        })
        .collect();
    let lower: Vec<Vertex> = strips
        .iter()
        .rev()
        .map(|&(b, i)| Vertex {
            x: i.lo,
            y: b,
            // exact: the stable sets start at alpha = 0 itself when z = 1 bounds them
            piece: if i.lo == 0.0 {
                Piece::AlphaZero
            } else {
                Piece::Bisection
            },
        })
        .collect();
    points.extend(lower);
    points.push(points[0]);
    let search = match tests.search {
        None => None,
        Some(s) => {
            let Found {
                mut stats,
                members: found,
                ..
            } = s.found.into_inner().unwrap_or_else(|e| e.into_inner());
            stats.found = found.len();
            let (tried, proved) = prove_points(set, &strips, tol)?;
            stats.proof_tried = tried;
            stats.proved = proved;
            Some(stats)
        }
    };
    Ok(RobustRegion {
        boundary: Boundary {
            delta: reference.plant().delta(),
            d: reference.plant().d(),
            tol,
            points,
            fallback: None,
        },
        members,
        member_boundaries,
        exact: !set.has_intervals(),
        search,
        pieces,
    })
}

/// The error when no wall is stable for every member.
fn no_region() -> Error {
    Error::InvalidRequest(
        "no wall is stable for every member of the set: narrow the intervals or lists".into(),
    )
}

/// The strips of the region over the dampings `span` to `tol` (module documentation, steps
/// 3 and 4) and the most pieces the common stable stiffnesses formed at one damping.
fn draw(tests: &Tests, span: (f64, f64), tol: f64) -> Result<(Vec<Strip>, usize)> {
    let none = no_region;
    let betas: Vec<f64> = (0..SCAN)
        .map(|i| span.0 + (span.1 - span.0) * (i as f64 + 0.5) / SCAN as f64)
        .collect();
    let scan: Vec<(Option<Interval>, usize)> = betas
        .par_iter()
        .map(|&b| tests.at(b, true))
        .collect::<Result<_>>()?;
    let mut pieces = scan.iter().map(|s| s.1).max().unwrap_or(0);
    // the longest run of dampings with common stable stiffnesses
    let (mut best, mut run) = ((0, 0), None::<usize>);
    for i in 0..=SCAN {
        match (scan.get(i).and_then(|s| s.0), run) {
            (Some(_), None) => run = Some(i),
            (None, Some(start)) => {
                if i - start > best.1 - best.0 {
                    best = (start, i);
                }
                run = None;
            }
            _ => {}
        }
    }
    if best.1 == best.0 {
        return Err(none());
    }
    if scan.iter().filter(|s| s.0.is_some()).count() > best.1 - best.0 {
        // the common set is empty between two runs: count them as pieces too
        pieces = pieces.max(2);
    }
    let (first, last) = (best.0, best.1 - 1);
    let strip = |i: usize| -> Strip { (betas[i], scan[i].0.expect("inside the run")) };
    // the ends of the run, by bisection between an empty damping and a stable one
    let end = |empty: f64, mut inside: Strip| -> Result<Strip> {
        let mut out = empty;
        while (out - inside.0).abs() > tol {
            let mid = 0.5 * (out + inside.0);
            match tests.at(mid, true)?.0 {
                Some(i) => inside = (mid, i),
                None => out = mid,
            }
        }
        Ok(inside)
    };
    let lo_end = end(
        if first == 0 { span.0 } else { betas[first - 1] },
        strip(first),
    )?;
    let hi_end = end(
        if last + 1 == SCAN {
            span.1
        } else {
            betas[last + 1]
        },
        strip(last),
    )?;
    let mut nodes: Vec<Strip> = vec![lo_end];
    nodes.extend((first..=last).map(strip));
    nodes.push(hi_end);
    nodes.dedup_by(|a, b| a.0 == b.0);
    let refined: Vec<Vec<Strip>> = nodes
        .par_windows(2)
        .map(|w| {
            let mut out = Vec::new();
            refine(tests, w[0], w[1], tol, 0, &mut out)?;
            Ok(out)
        })
        .collect::<Result<_>>()?;
    let mut strips: Vec<Strip> = vec![nodes[0]];
    for seg in refined {
        strips.extend(seg);
    }
    Ok((strips, pieces))
}

/// The box recursion on up to [`PROOF_POINTS`] walls `tol` inside the upper edge, spread
/// evenly over `strips` (module documentation, step 6): how many were tried and how many
/// proved. None is tried when the recursion does not enclose the set.
fn prove_points(set: &DeviceSet, strips: &[Strip], tol: f64) -> Result<(usize, usize)> {
    let walls: Vec<Wall> = strips
        .iter()
        .filter(|(_, i)| i.hi - i.lo > 2.0 * tol)
        .filter_map(|&(b, i)| Wall::new(i.hi - tol, b).ok())
        .collect();
    if walls.is_empty() {
        return Ok((0, 0));
    }
    let n = walls.len().min(PROOF_POINTS);
    let picked: Vec<Wall> = (0..n)
        .map(|k| walls[(k * (walls.len() - 1)) / (n - 1).max(1)])
        .collect();
    let outcomes: Vec<Option<bool>> = picked
        .par_iter()
        .map(|w| Ok(prove_wall(set, w, PROOF_BUDGET)?.map(|p| p.proved)))
        .collect::<Result<_>>()?;
    if outcomes.iter().any(Option::is_none) {
        return Ok((0, 0));
    }
    Ok((n, outcomes.iter().filter(|o| **o == Some(true)).count()))
}

/// The strips strictly after `a` up to and including `b`, the chord split while a
/// midpoint's ends lie more than `tol` from it (module documentation, step 4).
fn refine(
    tests: &Tests,
    a: Strip,
    b: Strip,
    tol: f64,
    depth: usize,
    out: &mut Vec<Strip>,
) -> Result<()> {
    let mid = 0.5 * (a.0 + b.0);
    if depth < MAX_DEPTH
        && (b.0 - a.0) > tol
        && let (Some(m), _) = tests.at(mid, false)?
    {
        let off = (m.lo - 0.5 * (a.1.lo + b.1.lo))
            .abs()
            .max((m.hi - 0.5 * (a.1.hi + b.1.hi)).abs());
        if off > tol {
            refine(tests, a, (mid, m), tol, depth + 1, out)?;
            refine(tests, (mid, m), b, tol, depth + 1, out)?;
            return Ok(());
        }
    }
    out.push(b);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::elements::{Loop, PhysicalElements};
    use crate::params::{Delay, Device};
    use crate::robust::Quantity;

    /// Whether the wall `(k, b)` is stable on 1 kg at `T = 1 s`, damping 2 N s/m, a delay of
    /// `d` samples: every eigenvalue of the closed-loop state matrix (nalgebra's Schur form,
    /// not the Schur-Cohn tests the region uses) inside the unit circle.
    fn stable(d: f64, k: f64, b: f64) -> bool {
        let device = Device::new(1.0, 1.0, 2.0, Delay::Samples(d)).unwrap();
        let lp = Loop::physical(&device, &PhysicalElements::default()).unwrap();
        let m = Checker::new(lp, Options::default())
            .unwrap()
            .state_matrix(&device.wall(k, b).unwrap());
        let schur = m.try_schur(1e-14, 10_000).expect("Schur form converges");
        schur.complex_eigenvalues().iter().all(|z| z.norm() < 1.0)
    }

    /// A member that cuts the strip only between two dampings of the first pass: a first
    /// pass that found no member cutting at the dampings on either side, only the member
    /// near cutting there (delta = 2, a delay near 2.9 of 1..3 samples). The final pass
    /// checks that member, finds it cutting and searches near it: the strip is the one the
    /// search over the whole set gives (to `tol`), its upper edge moved `tol` inward is
    /// stable at 401 delays of [1, 3] by eigenvalues, while the sample's strip alone holds a
    /// wall unstable at one of them.
    #[test]
    fn a_member_cutting_between_first_pass_dampings_is_caught() {
        let tol = 1e-9;
        let device = Device::new(1.0, 1.0, 2.0, Delay::Samples(1.0)).unwrap();
        let set = DeviceSet::new(&device, &PhysicalElements::default())
            .unwrap()
            .with_interval(Quantity::Delay, 1.0, 3.0)
            .unwrap();
        let members = set.sampled_members();
        let checkers: Vec<(Checker, f64)> = members
            .iter()
            .map(|m| {
                let c = Checker::new(m.to_loop().unwrap(), Options::default()).unwrap();
                (c, 1.0 / m.device.mass)
            })
            .collect();
        let search = |track| Search {
            set: &set,
            sample: &members,
            tol,
            track,
            found: Mutex::new(Found::new()),
        };
        let sample = Tests {
            members: &checkers,
            search: None,
        };
        // the damping where the search over the whole set cuts the sample's strip deepest
        let mut best: Option<(f64, Interval, Interval, Point)> = None;
        for i in 0..=24 {
            let beta = 1.0 + 0.05 * f64::from(i);
            let (Some(own), _) = sample.at(beta, false).unwrap() else {
                continue;
            };
            let full = Tests {
                members: &checkers,
                search: Some(search(None)),
            };
            let (Some(cut), _) = full.at(beta, false).unwrap() else {
                continue;
            };
            let log = full.search.unwrap().found.into_inner().unwrap().log;
            let Some(p) = log.first().and_then(|l| l.near.first().cloned()) else {
                continue;
            };
            if best
                .as_ref()
                .is_none_or(|b| own.hi - cut.hi > b.1.hi - b.2.hi)
            {
                best = Some((beta, own, cut, p));
            }
        }
        let (beta, own, cut, p) = best.expect("a member outside the sample cuts");
        assert!(own.hi - cut.hi > 1e-3, "{own:?} {cut:?}");
        // the first pass as constructed: no cut on either side, the member near cutting
        let track = vec![
            Logged {
                beta: beta - 1e-3,
                cut: false,
                near: vec![p.clone()],
            },
            Logged {
                beta: beta + 1e-3,
                cut: false,
                near: vec![p],
            },
        ];
        let checked = Tests {
            members: &checkers,
            search: Some(search(Some(track))),
        };
        let (Some(got), _) = checked.at(beta, false).unwrap() else {
            panic!("no strip at {beta}")
        };
        let stats = checked.search.unwrap().found.into_inner().unwrap().stats;
        assert_eq!((stats.checked, stats.caught), (1, 1), "{stats:?}");
        assert!(
            (got.hi - cut.hi).abs() <= tol && (got.lo - cut.lo).abs() <= tol,
            "{got:?} against the full search's {cut:?}"
        );
        let delays: Vec<f64> = (0..=400).map(|i| 1.0 + f64::from(i) / 200.0).collect();
        for &d in &delays {
            assert!(stable(d, got.hi - tol, beta), "d = {d} at {beta}");
        }
        assert!(
            delays.iter().any(|&d| !stable(d, own.hi - tol, beta)),
            "the sample's strip {own:?} holds at every delay"
        );
    }
}
