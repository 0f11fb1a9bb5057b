//! A proof that one wall is stable for every member of a box of devices (the box recursion
//! of docs/MODEL.md section 11, over the parameters of section 12).
//!
//! # Method
//!
//! For the paper's loop (no elements) whose set spreads only mass `m`, damping `b` and the
//! delay, a wall given in the set's reference normalization `(alpha, beta)` is, for the
//! member `(m, b, d)`, the polynomial `q = Q0 + alpha' QA + beta' QB` of section 3 with
//! `alpha' = alpha m_ref / m`, `beta' = beta m_ref / m` and `delta = b T / m`. Over a cell
//! `[m0, m1] x [b0, b1]` each of the three is enclosed in outward-rounded interval
//! arithmetic (they are monotone in `m` and `b`, so the cell maps into the box of the
//! enclosures); the discretization values `c = exp(-delta)`, `phi1`, `phi2` are enclosed over
//! the interval of `delta` by their monotonicity (`enclosure::interval`).
//!
//! A delay interval `[d0, d1]` is cut at the whole numbers into pieces `[n, n + 1]`; within
//! a piece the delay `n + eps` enters only through `phi1` and `phi2` at `eps` and `1 - eps`
//! (section 2), and the polynomial keeps the fractional form of degree `n + 4` for every
//! `eps` in `[0, 1]` (at `eps = 0` it is `z` times the integer delay's, at `eps = 1` the
//! delay `n + 1`'s), so the piece is one family. Over a sub-interval of `eps` the
//! coefficients are taken in centred form (`certificate::FractionFamily`; the mean-value
//! theorem): their enclosure at the sub-interval's centre plus the enclosure of their
//! derivative in `eps` over it times the offset from the centre, which overestimates their
//! range by a second-order term in the width (the direct enclosure, with `eps` and `1 - eps`
//! two independent intervals, by a first-order one). A delay in seconds becomes the interval
//! of `d = t / T`, widened by twice [`crate::params::WHOLE_SAMPLE_TOL`] for the snapping of
//! near-whole delays and the division's rounding.
//!
//! Each cell is first tried by Rouché's theorem around the midpoint polynomial
//! ([`rouche`]; for a cell of fractions along the derivative, [`rouche_along`], which
//! keeps the coefficients moving together with `eps`); failing that, the interval
//! Schur-Cohn recursion (`enclosure::schur`; Schur 1917, Cohn 1922) counts the roots
//! outside the unit circle for every polynomial in the enclosures at once: no root outside
//! and every step decided proves the cell; roots outside for all of them (or, in a
//! mean-value form, for the members at the cell's middle) refute it; an
//! undecided cell is bisected along the side whose halving narrows the enclosures most
//! ([`split`]), breadth-first, until the budget of cells runs out. That recursion
//! ([`recurse`]) is also the one over loops with elements (`proof_elements.rs`), which brings
//! only its enclosure of a cell's polynomials.

use std::collections::VecDeque;

use super::{DeviceSet, Quantity};
use crate::certificate::tangent::{MeanValueForm, Slope};
use crate::certificate::{
    DeviceSpread, FractionFamily, paper_fraction_family, paper_parts_over, parts_over,
};
use crate::elements::Loop;
use crate::enclosure::interval::Interval;
use crate::enclosure::schur::recursion;
use crate::error::Result;
use crate::params::{Delay, Device, WHOLE_SAMPLE_TOL, Wall};

/// The cells [`prove_wall`] examines at most when the verification of a robust answer
/// calls it. The cells concentrate where the room is least: a wall `1e-3` below the optimum
/// needs cells there whose enclosures spread less than that room: tens of cells for a delay
/// interval (its centred form), a few hundred for a box of mass and damping or of delay and
/// damping, one or two thousand for a box of two element parameters (a filter's cutoff and
/// an actuator lag, or a hand's mass and a cutoff), tens to several hundred for some boxes
/// of three (a hand's mass and damping and a cutoff; the mass, damping and a lag; the mass,
/// a cutoff and a lag); a box the budget cannot close keeps the sampling argument. Each cell costs tens of microseconds on the paper's loop and up to a
/// few tenths of a millisecond with elements in two parameters, so the budget costs a
/// second or two at most.
pub const PROOF_BUDGET: usize = 4096;

/// One cell of the box recursion: a mass interval, a damping interval and a delay interval
/// (each may be one value), in physical units and samples.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct ProofCell {
    /// `[lo, hi]` of the mass `m`, kg.
    pub mass: (f64, f64),
    /// `[lo, hi]` of the damping `b`, N s/m.
    pub damping: (f64, f64),
    /// `[lo, hi]` of the delay factor `d`, samples (for a cell of a delay interval, the
    /// whole samples plus the ends of the fraction, each sum rounded to nearest).
    pub delay: (f64, f64),
    /// `[lo, hi]` of the hand's mass (kg), damping (N s/m) and stiffness (N/m); all zero
    /// for a member without a hand.
    pub hand: [(f64, f64); 3],
    /// `[lo, hi]` of the velocity filter's cutoff (Hz), the actuator lag's time constant
    /// (s), the transmission's handle mass (kg), coupling stiffness (N/m) and coupling
    /// damping (N s/m) where the cell spreads them or the loop names them
    /// ([`super::proof_elements`]); all zero otherwise.
    pub elements: [(f64, f64); 5],
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
    /// Why the recursion stopped short of a proof (`None` when `proved`).
    pub stopped: Option<ProofStop>,
}

/// Why the box recursion ([`prove_wall`]) did not prove a wall over a set: what the
/// sampling argument that then covers the set reports beside it
/// ([`super::Verification::Sampled`]).
///
/// ```
/// use stabound::elements::PhysicalElements;
/// use stabound::params::{Delay, Device, Wall};
/// use stabound::robust::{DeviceSet, ProofStop, Quantity, prove_wall};
///
/// // a mass of 90 to 110 g, given one cell where the proof takes more
/// let device = Device::new(0.09, 1e-3, 0.0, Delay::Samples(1.0))?;
/// let set = DeviceSet::new(&device, &PhysicalElements::default())?
///     .with_interval(Quantity::Mass, 0.09, 0.11)?;
/// let p = prove_wall(&set, &Wall::new(0.1, 0.4)?, 1)?.expect("the paper's loop");
/// assert!(!p.proved);
/// let Some(ProofStop::Budget { cells, undecided, smallest }) = p.stopped else {
///     panic!("the budget ran out: {:?}", p.stopped);
/// };
/// // exact: the box itself, never split, spans the whole of its mass interval
/// assert_eq!((cells, undecided, smallest), (1, 1, 1.0));
/// assert!(prove_wall(&set, &Wall::new(0.1, 0.4)?, 1000)?.expect("paper").stopped.is_none());
/// assert!(ProofStop::Refuted.describe().contains("unstable"));
/// # Ok::<(), stabound::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case", tag = "reason"))]
#[non_exhaustive]
pub enum ProofStop {
    /// The cell budget was spent with cells still undecided.
    Budget {
        /// Cells examined (the budget).
        cells: usize,
        /// Cells left undecided.
        undecided: usize,
        /// The smallest undecided cell's size: the largest share of its box's width that
        /// one of its spread parameters still spans (for a delay, of one sample's width);
        /// `1` for a box never split.
        smallest: f64,
    },
    /// A cell of one member stayed undecided: the wall is so close to that member's
    /// stability boundary that the enclosures, even of one point, cannot separate it.
    Inseparable,
    /// A cell's members were shown to have roots outside the unit circle: the wall is
    /// unstable for some member (the sampling argument then finds it).
    Refuted,
    /// The set spreads a parameter the box recursion does not enclose.
    Uncovered {
        /// The parameter ([`Quantity::name`]).
        quantity: String,
    },
    /// The wall is no valid wall (a stiffness or damping out of range), so there is
    /// nothing to prove.
    InvalidWall,
}

impl ProofStop {
    /// One phrase for reports, after "the box proof stopped: ".
    pub fn describe(&self) -> String {
        match self {
            ProofStop::Budget {
                cells,
                undecided,
                smallest,
            } => format!(
                "cell budget spent at {cells} cells with {undecided} undecided; the smallest undecided cell is still {smallest:.3e} of its box's width in its widest parameter"
            ),
            ProofStop::Inseparable => {
                "a member so close to the stability boundary that the enclosures cannot separate it"
                    .into()
            }
            ProofStop::Refuted => "a cell was shown unstable for some member".into(),
            ProofStop::Uncovered { quantity } => {
                format!("the box recursion does not cover an interval of {quantity}")
            }
            ProofStop::InvalidWall => "the wall is not a valid wall".into(),
        }
    }
}

/// The delay of a cell: one delay factor, or `n` whole samples and a fraction in
/// `[e0, e1]` within `[0, 1]` (the fractional family of the module documentation).
#[derive(Debug, Clone, Copy)]
pub(super) enum CellDelay {
    Point(f64),
    Piece { n: usize, frac: (f64, f64) },
}

impl CellDelay {
    /// The delay factors of the cell, `[lo, hi]`.
    pub(super) fn span(self) -> (f64, f64) {
        match self {
            CellDelay::Point(d) => (d, d),
            CellDelay::Piece { n, frac } => (n as f64 + frac.0, n as f64 + frac.1),
        }
    }

    /// The pieces `[n, n + 1]` that cover the delay factors `[lo, hi]`, `0 <= lo < hi`.
    pub(super) fn pieces(lo: f64, hi: f64) -> Vec<Self> {
        let mut out = Vec::new();
        let mut n = lo.floor();
        while n < hi {
            // exact: a number minus a whole number at most itself and above it less one
            // (the floor) is exact in binary floating point
            let e0 = if lo > n { lo - n } else { 0.0 };
            let e1 = if hi < n + 1.0 { hi - n } else { 1.0 };
            out.push(CellDelay::Piece {
                n: n as usize,
                frac: (e0, e1),
            });
            n += 1.0;
        }
        out
    }
}

/// One box of a qualifying set: the loop with elements at its low corner (`None`: the
/// paper's loop), its sides (mass, damping, then the hand's mass, damping and stiffness, in
/// physical units; one value where not spread), the sampling period and the delay factors
/// `[lo, hi]` (equal ends: one delay for the box).
struct ProofBox {
    elements: Option<Loop>,
    sides: Sides,
    period: f64,
    delay: (f64, f64),
}

/// The sides of a cell: `[lo, hi]` of the mass, damping, hand mass, hand damping and hand
/// stiffness.
type Sides = [(f64, f64); 5];

/// One cell of a box recursion: `[lo, hi]` of each of its `N` sides, and its delay.
pub(super) type Cell<const N: usize> = ([(f64, f64); N], CellDelay);

/// The cells a recursion starts from for a box of `sides` and the delay factors
/// `[lo, hi]`: the box, cut at whole delays.
pub(super) fn start<const N: usize>(sides: [(f64, f64); N], (lo, hi): (f64, f64)) -> Vec<Cell<N>> {
    // exact: equal ends are one delay, proved by the exact delay's own polynomial
    let delays = if lo == hi {
        vec![CellDelay::Point(lo)]
    } else {
        CellDelay::pieces(lo, hi)
    };
    delays.into_iter().map(|d| (sides, d)).collect()
}

/// The delay factors `[lo, hi]` of a delay interval `[lo, hi]` given in the units of `dev`'s
/// delay: samples as they are, seconds divided by the period and widened by twice
/// [`WHOLE_SAMPLE_TOL`] for the snapping of near-whole delays and the division's rounding.
pub(super) fn delay_factors(dev: &Device, lo: f64, hi: f64) -> (f64, f64) {
    match dev.delay {
        Delay::Samples(_) => (lo, hi),
        Delay::Seconds(_) => {
            let slack = 2.0 * WHOLE_SAMPLE_TOL;
            ((lo / dev.period - slack).max(0.0), hi / dev.period + slack)
        }
    }
}

/// The boxes of `set` when the proof applies to it: mass, damping and the delay spread on
/// the paper's loop; mass, damping and the hand's parameters on a loop with linear elements
/// (its delay one value; with a transmission, whose parameters are normalized by the mass,
/// the mass and damping one value too). The device let go is a box of its own.
fn boxes(set: &DeviceSet) -> Result<Option<Vec<ProofBox>>> {
    let mut out = Vec::new();
    for v in set.variants() {
        let dev = v.base.device;
        let lp = v.base.to_loop()?;
        let d = dev.plant()?.d();
        let e = &v.base.elements;
        let hand = |x: Option<f64>| {
            let x = x.unwrap_or(0.0);
            (x, x)
        };
        let mut b = ProofBox {
            elements: (!lp.is_paper()).then_some(lp),
            sides: [
                (dev.mass, dev.mass),
                (dev.damping, dev.damping),
                hand(e.hand_mass),
                hand(e.hand_damping),
                hand(e.hand_stiffness),
            ],
            period: dev.period,
            delay: (d, d),
        };
        for &(q, lo, hi) in &v.dims {
            let side = match q {
                Quantity::Mass => 0,
                Quantity::Damping => 1,
                Quantity::Delay if b.elements.is_none() => {
                    b.delay = delay_factors(&dev, lo, hi);
                    continue;
                }
                Quantity::Element(p) => match p.keyword {
                    "hand_mass" => 2,
                    "hand_damping" => 3,
                    "hand_stiffness" => 4,
                    _ => return Ok(None),
                },
                _ => return Ok(None),
            };
            if side < 2 && lp.transmission().is_some() {
                return Ok(None);
            }
            b.sides[side] = (lo, hi);
        }
        out.push(b);
    }
    Ok(Some(out))
}

/// The wall's polynomials over one cell: the enclosures of their coefficients, or their
/// mean-value form in the fraction of a delay or in a few parameters.
pub(super) enum Family {
    Plain(Vec<Interval>),
    Centred(MeanValueForm),
}

impl From<FractionFamily> for MeanValueForm {
    /// The form in the fraction of a delay alone (incomplete: [`split`] tries the cell's
    /// sides).
    fn from(f: FractionFamily) -> Self {
        MeanValueForm {
            centre: f.centre,
            slopes: vec![Slope {
                side: None,
                slope: f.slope,
                offset: f.offset,
            }],
            complete: false,
        }
    }
}

impl Family {
    /// The enclosures of the coefficients over the cell, lowest power first.
    pub(super) fn coefficients(&self) -> Vec<Interval> {
        match self {
            Family::Plain(c) => c.clone(),
            Family::Centred(f) => f.coefficients(),
        }
    }

    /// The side whose halving narrows a complete mean-value form most
    /// ([`MeanValueForm::widest`] in one side; in two sides or more, [`critical_side`]),
    /// `None` otherwise.
    fn widest(&self) -> Option<usize> {
        match self {
            Family::Plain(_) => None,
            Family::Centred(f) if sides(f) >= 2 => critical_side(f),
            Family::Centred(f) => f.widest(),
        }
    }

    /// The sum of the coefficients' radii ([`spread`]).
    fn spread(&self) -> f64 {
        match self {
            Family::Plain(c) => spread(c),
            Family::Centred(f) => spread(&f.coefficients()),
        }
    }
}

/// The number of sides a mean-value form is centred in.
fn sides(f: &MeanValueForm) -> usize {
    let mut seen: Vec<usize> = f.slopes.iter().filter_map(|s| s.side).collect();
    seen.sort_unstable();
    seen.dedup();
    seen.len()
}

/// For a complete mean-value form, the side whose halving takes most off what Rouché's test
/// must beat where it has least room: at the point `z` of the circle (of `4 COARSE` evenly
/// spaced) where `|p(z)| - sum_k reach_k (|S_k(z)| + rad S_k)` is least (`p` and `S_k` the
/// midpoint polynomials of the centre and the terms, `rad S_k` the sum of the terms'
/// coefficients' radii, which the test subtracts at every point), each term's
/// `reach_k (|S_k(z)| + rad S_k)` is credited to the sides whose halving shrinks it, by how
/// much: for a second-order form (`N` gradients, then the terms `t_k t_l`, `k <= l`, in
/// that order), half of a gradient's term to its side, three quarters of `t_k^2` to side
/// `k` and half of `t_k t_l` to each of `k` and `l`; for a first-order form each term to its
/// side. The side credited most is halved. Weighing only the midpoints' pull and crediting
/// a term `t_k t_l` to `k` alone halved the lag of a box of the mass, a cutoff and a lag
/// while the mass, whose second derivatives' radii then took most of the room, stayed
/// unhalved (the box did not close in 30,000 cells; this closes it in 637). In two sides
/// it beats [`MeanValueForm::widest`] (each side weighed by its coefficients' magnitudes over
/// the whole circle) too: at the paper's device and `--delay-samples 1`, the mass and lag
/// box behind a 30 Hz filter closes in 94 cells instead of 929, the cutoff and lag box in 92
/// instead of 180, the hand's mass and cutoff box in 24 instead of 577, and no two-side box
/// measured took more cells. `None` for an
/// incomplete form or an unbounded enclosure. Only the choice of side rests on these `f64`
/// values.
fn critical_side(f: &MeanValueForm) -> Option<usize> {
    if !f.complete {
        return None;
    }
    let mid = |c: &[Interval]| -> Option<Vec<(f64, f64)>> { c.iter().map(|c| c.ball()).collect() };
    let p = mid(&f.centre)?;
    // each term's midpoint polynomial, reach, side and sum of its coefficients' radii (the
    // same at every point of the circle, so summed once)
    type Term = (Vec<(f64, f64)>, f64, Option<usize>, f64);
    let slopes: Vec<Term> = f
        .slopes
        .iter()
        .map(|s| {
            let b = mid(&s.slope)?;
            let radii = b.iter().map(|&(_, r)| r).sum();
            Some((b, s.offset.mag(), s.side, radii))
        })
        .collect::<Option<_>>()?;
    let pulls = |z: (f64, f64)| {
        slopes.iter().map(move |(b, reach, side, radii)| {
            let (re, im) = weighted(b, z, |_| 1.0);
            (*side, reach * (re.hypot(im) + radii))
        })
    };
    let n = 4 * COARSE;
    let points: Vec<(f64, f64)> = (0..n)
        .map(|j| (2.0 * std::f64::consts::PI * j as f64 / n as f64).sin_cos())
        .collect();
    let moduli: Vec<f64> = points
        .iter()
        .map(|&z| {
            let (re, im) = weighted(&p, z, |_| 1.0);
            re.hypot(im)
        })
        .collect();
    let room = |j: usize| moduli[j] - pulls(points[j]).map(|(_, x)| x).sum::<f64>();
    // The pulls' sum is at most `sum_k reach_k (sum_i |S_k,i| + rad S_k)` anywhere on the
    // circle; its computed value exceeds that by the rounding of a few dozen operations on
    // terms of that size (relative 1e-14), which the factor `1 + 1e-9` covers. A point
    // whose `|p(z)|` less that bound exceeds the least room found so far has more room
    // itself (the computed subtraction is monotone in what it subtracts), so its pulls need
    // not be evaluated: the point found is the first of least room, as without the bound.
    let most = slopes
        .iter()
        .map(|(b, reach, _, radii)| reach * (b.iter().map(|&(m, _)| m.abs()).sum::<f64>() + radii))
        .sum::<f64>()
        * (1.0 + 1e-9);
    // the search starts at the least `|p(z)|`, where the least room is likely to be
    let start = (0..n).min_by(|&a, &b| moduli[a].total_cmp(&moduli[b]))?;
    let mut best = (room(start), start);
    for (j, &modulus) in moduli.iter().enumerate() {
        if j == start || modulus - most > best.0 {
            continue;
        }
        let r = room(j);
        if r.total_cmp(&best.0).then(j.cmp(&best.1)).is_lt() {
            best = (r, j);
        }
    }
    let least = points[best.1];
    // a second-order form lists its N gradients, then its terms `t_k t_l`, `k <= l`, in
    // order (`second_order_family`): halving side `k` halves its gradient's term and the
    // terms `t_k t_l`, and quarters `t_k^2`
    let dims = sides(f);
    let second = slopes.len() == dims + dims * (dims + 1) / 2;
    let names: Vec<Option<usize>> = slopes.iter().take(dims).map(|s| s.2).collect();
    let pairs = (0..dims).flat_map(|k| (k..dims).map(move |l| (k, l)));
    let mut weights: Vec<(usize, f64)> = Vec::new();
    let mut add = |side: Option<usize>, w: f64| -> Option<()> {
        let side = side?;
        match weights.iter_mut().find(|(s, _)| *s == side) {
            Some(x) => x.1 += w,
            None => weights.push((side, w)),
        }
        Some(())
    };
    let mut terms = pulls(least);
    if second {
        for pull in terms.by_ref().take(dims) {
            add(pull.0, 0.5 * pull.1)?;
        }
        for ((k, l), (side, pull)) in pairs.zip(terms) {
            if k == l {
                add(side, 0.75 * pull)?;
            } else {
                add(names[k], 0.5 * pull)?;
                add(names[l], 0.5 * pull)?;
            }
        }
    } else {
        for (side, pull) in terms {
            add(side, pull)?;
        }
    }
    weights
        .into_iter()
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(s, _)| s)
}

/// The wall's polynomials (lowest power first) over every member of one cell:
/// `alpha' = alpha m_ref / m`, `beta' = beta m_ref / m`, `delta = b T / m` and the hand's
/// `mu_h = m_h / m`, `delta_h = b_h T / m`, `kappa_h = k_h T^2 / m` (`docs/MODEL.md`
/// section 8), each in interval arithmetic; over a sub-interval of the fraction of a delay,
/// the centred form of [`FractionFamily`].
fn enclose(wall: &Wall, m_ref: f64, b: &ProofBox, (sides, delay): Cell<5>) -> Family {
    let side = |i: usize| Interval::new(sides[i].0, sides[i].1);
    let inv_m = Interval::point(1.0) / side(0);
    let scale = Interval::point(m_ref) * inv_m;
    let a = Interval::point(wall.alpha()) * scale;
    let beta = Interval::point(wall.beta()) * scale;
    let t = Interval::point(b.period);
    let delta = (side(1) * t * inv_m).nonneg();
    let parts = match (&b.elements, delay) {
        (None, CellDelay::Point(d)) => paper_parts_over(delta, d),
        (None, CellDelay::Piece { n, frac }) => {
            let e = Interval::new(frac.0, frac.1);
            return Family::Centred(paper_fraction_family(delta, n, e, a, beta).into());
        }
        (Some(lp), _) => {
            let hand = [
                (side(2) * inv_m).nonneg(),
                (side(3) * t * inv_m).nonneg(),
                (side(4) * t * t * inv_m).nonneg(),
            ];
            parts_over(lp, &DeviceSpread { delta, hand })
        }
    };
    Family::Plain(parts.at(a, beta))
}

/// The root count of the wall over the polynomials `family` of one cell: `Some(0)` proves it
/// stable, `Some(k > 0)` refutes it (`k` roots outside for every member, or, for a
/// mean-value form, for the members at the cell's middle, which its centre encloses: the
/// wall is then not stable over the cell either way), `None` leaves it undecided.
pub(super) fn outside(family: &Family) -> Option<usize> {
    let proved = match family {
        Family::Plain(c) => rouche(c),
        Family::Centred(f) => {
            let slopes: Vec<(&[Interval], f64)> = f
                .slopes
                .iter()
                .map(|s| (&s.slope[..], s.offset.mag()))
                .collect();
            rouche_along(&f.centre, &slopes)
        }
    };
    if proved {
        return Some(0);
    }
    if let Family::Centred(f) = family
        && let Some(k @ 1..) = recursion(&f.centre).outside
    {
        return Some(k);
    }
    recursion(&family.coefficients()).outside
}

/// The sum of the enclosures' radii: what [`rouche`] must beat, infinite when one is
/// unbounded.
fn spread(coeffs: &[Interval]) -> f64 {
    coeffs
        .iter()
        .map(|c| c.ball().map_or(f64::INFINITY, |(_, r)| r))
        .sum()
}

/// Whether every polynomial in the enclosures `coeffs` (lowest power first) has all its
/// roots inside the unit circle, by Rouché's theorem around their midpoints
/// ([`rouche_along`] with no slope).
fn rouche(coeffs: &[Interval]) -> bool {
    rouche_along(coeffs, &[])
}

/// Whether every polynomial `q = c + sum_k s_k t_k`, `c_i` in `centre[i]`, `s_k,i` in
/// `slopes[k].0[i]` (lowest powers first) and `|t_k| <= slopes[k].1` (the reach), has all its
/// roots inside the unit circle, by Rouché's theorem around the midpoint polynomial `p` of
/// `centre`: `p` is proved stable by the interval Schur-Cohn recursion (its coefficients are
/// exact), and on the circle `|p(z)|` exceeds
/// `sum_i rad c_i + sum_k reach_k (|S_k(z)| + sum_i rad s_k,i)`, `S_k` the midpoint polynomial
/// of `slopes[k]`, which bounds `|q(z) - p(z)|` for every such `q`; then `q` has as many roots
/// inside as `p` (the same degree, its top coefficient exact), all of them. The interval
/// recursion alone loses the correlation between its steps' coefficients; this test's cost in
/// width is only the radii, and for a mean-value form (a cell of fractions of a delay,
/// [`FractionFamily`], or of a few parameters, [`MeanValueForm`]) each slope enters through
/// `|S_k(z)|` at each point of the circle, not through each coefficient's own width: the
/// coefficients move together with the parameter. Where that falls short, zero is excluded
/// from the values the family (and every polynomial between it and `p`) takes at `z` by
/// their components along `p`'s direction `u` ([`ArcBounds::radial`]: `|x| >= Re(conj(u) x)`,
/// so `Re(conj(u) p) - sum_k reach_k |Re(conj(u) S_k)|` above the radii suffices): the
/// winding of the values around 0 on the circle, and so the count of roots inside, is `p`'s.
///
/// `|p| - sum_k reach_k |S_k|` on the circle is bounded below arc by arc
/// ([`ArcBounds::lower`]: from its value at the middle and the bound on its derivative in the
/// angle, or from Taylor's theorem to second or third order around the middle); an arc where
/// that falls short is halved ([`arc_clears`]), once every arc's middle clears. The points are evaluated in `f64`;
/// `1e-13 (sum_i |a_i| + sum_i i |a_i|)` bounds that rounding for each of `p` and the `S_k`
/// (Horner's error is at most `2 k` units of `2^-53` times `sum_i |a_i|` for degree `k`, and
/// the computed points lie within a few units of the circle), with a margin for degrees up to
/// several hundred that also covers the products by the reaches and the sums (each one
/// rounding of `2^-53` of the terms).
pub(super) fn rouche_along(centre: &[Interval], slopes: &[(&[Interval], f64)]) -> bool {
    let Some((bounds, family)) = arc_setup(centre, slopes) else {
        return false;
    };
    let h = std::f64::consts::PI / COARSE as f64;
    // the middles of the coarse arcs first: one at or below `need` refutes the test at once,
    // before any arc is halved
    let mut coarse = Vec::with_capacity(COARSE);
    for j in 0..COARSE {
        let theta = 2.0 * h * j as f64;
        let at = family.point(theta);
        if !bounds.clears_middle(&at) {
            return false;
        }
        coarse.push((theta, at));
    }
    coarse
        .into_iter()
        .all(|(theta, at)| arc_clears(&family, (theta, at), h, &bounds, DEPTH))
}

/// The constants of [`rouche_along`]'s arc bounds for the family `centre` along `slopes`,
/// and its evaluation of a point of the circle; `None` when an enclosure or a reach is
/// unbounded or the midpoint polynomial is not proved stable.
fn arc_setup(centre: &[Interval], slopes: &[(&[Interval], f64)]) -> Option<(ArcBounds, ArcFamily)> {
    let to_balls = |c: &[Interval]| c.iter().map(|c| c.ball()).collect::<Option<Vec<_>>>();
    let balls = to_balls(centre)?;
    let mut moves: Vec<(Vec<(f64, f64)>, f64)> = Vec::with_capacity(slopes.len());
    for &(slope, reach) in slopes {
        let b = to_balls(slope)?;
        if !reach.is_finite() {
            return None;
        }
        moves.push((b, reach));
    }
    let mid: Vec<Interval> = balls.iter().map(|&(m, _)| Interval::point(m)).collect();
    if recursion(&mid).outside != Some(0) {
        return None;
    }
    // each sum of a few nonnegative terms rounds by far less than the factor 1 + 1e-12
    let widen = 1.0 + 1e-12;
    let radii = |b: &[(f64, f64)]| b.iter().map(|&(_, r)| r).sum::<f64>() * widen;
    let size = |b: &[(f64, f64)]| b.iter().map(|&(m, _)| m.abs()).sum::<f64>() * widen;
    let steep = |b: &[(f64, f64)]| {
        b.iter()
            .enumerate()
            .map(|(i, &(m, _))| i as f64 * m.abs())
            .sum::<f64>()
            * widen
    };
    // each slope's rounding, radii and steepness, times its reach, summed over the slopes
    let (mut moved_rounding, mut moved_radii, mut moved_steep) = (0.0, 0.0, 0.0);
    for (b, reach) in &moves {
        moved_rounding += reach * 1e-13 * (size(b) + steep(b)) * widen;
        moved_radii += reach * radii(b) * widen;
        moved_steep += reach * steep(b) * widen;
    }
    let rounding = 1e-13 * (size(&balls) + steep(&balls)) + moved_rounding;
    let need = radii(&balls) + moved_radii + rounding;
    let curve = |b: &[(f64, f64)]| {
        b.iter()
            .enumerate()
            .map(|(i, &(m, _))| (i * i) as f64 * m.abs())
            .sum::<f64>()
            * widen
    };
    let cubic = |b: &[(f64, f64)]| {
        b.iter()
            .enumerate()
            .map(|(i, &(m, _))| (i * i * i) as f64 * m.abs())
            .sum::<f64>()
            * widen
    };
    // the slopes' curvature and the rounding of their derivatives, times their reaches
    let (mut moved_curve, mut moved_speed_rounding) = (0.0, 0.0);
    for (b, reach) in &moves {
        moved_curve += reach * curve(b) * widen;
        moved_speed_rounding += reach * 1e-13 * (steep(b) + curve(b)) * widen;
    }
    let bounds = ArcBounds {
        need,
        steep: steep(&balls),
        curve: curve(&balls),
        // Horner's rounding for the derivative, whose coefficients are i p_i
        rounding: 1e-13 * (steep(&balls) + curve(&balls)),
        cubic: cubic(&balls),
        // and for the second derivative, whose coefficients are i^2 p_i
        bend_rounding: 1e-13 * (curve(&balls) + cubic(&balls)),
        steep_s: moved_steep,
        curve_s: moved_curve,
        speed_rounding_s: moved_speed_rounding,
    };
    Some((bounds, ArcFamily { balls, moves }))
}

/// The midpoint polynomial `p` of [`rouche_along`]'s family and its slopes' midpoint
/// polynomials `S` with their reaches, as balls `(midpoint, radius)`, lowest power first.
struct ArcFamily {
    balls: Vec<(f64, f64)>,
    moves: Vec<(Vec<(f64, f64)>, f64)>,
}

/// `sum_i w(i) a_i z^i` at `z = cos + i sin` by Horner's rule, for the midpoints `a_i` of
/// `b`.
fn weighted(b: &[(f64, f64)], (sin, cos): (f64, f64), w: impl Fn(usize) -> f64) -> (f64, f64) {
    let (mut re, mut im) = (0.0f64, 0.0f64);
    for (i, &(m, _)) in b.iter().enumerate().rev() {
        (re, im) = (re * cos - im * sin + w(i) * m, re * sin + im * cos);
    }
    (re, im)
}

impl ArcFamily {
    /// What the arc bounds need at `z = exp(i theta)` ([`ArcPoint`]).
    fn point(&self, theta: f64) -> ArcPoint {
        let (sin, cos) = theta.sin_cos();
        let (mut re, mut im, mut dre, mut dim) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
        for (i, &(m, _)) in self.balls.iter().enumerate().rev() {
            (re, im) = (re * cos - im * sin + m, re * sin + im * cos);
            (dre, dim) = (dre * cos - dim * sin + i as f64 * m, dre * sin + dim * cos);
        }
        let modulus = re.hypot(im);
        let speed = dre.hypot(dim);
        // the distance from 0 to the line through p along D (the tangent's direction is
        // i D, and |Im(conj(i D) p)| = |Re(conj(D) p)|); the dot product rounds by a few
        // units of |p| |D|, so of |p| after the division
        let perp = if speed > 0.0 {
            ((re * dre + im * dim).abs() / speed - 1e-14 * modulus).max(0.0)
        } else {
            modulus
        };
        // the foot of that perpendicular: p + foot i D, i D = (-dim, dre)
        let foot = if speed > 0.0 {
            (re * dim - im * dre) / (speed * speed)
        } else {
            0.0
        };
        // the unit vector u along p (shortened by 1e-14 so that its computed length is at
        // most 1): each slope's pull along it, |Re(conj(u) S)|, plus 1e-14 |S| for the
        // rounding of that dot product
        let u = if modulus > 0.0 {
            let s = (1.0 - 1e-14) / modulus;
            (re * s, im * s)
        } else {
            (0.0, 0.0)
        };
        let (mut pull, mut radial) = (0.0, 0.0);
        for (b, reach) in &self.moves {
            let (re, im) = weighted(b, (sin, cos), |_| 1.0);
            let size = re.hypot(im);
            pull += reach * size;
            radial += reach * ((u.0 * re + u.1 * im).abs() + 1e-14 * size);
        }
        // each sum of a few nonnegative terms rounds by far less than the factor 1 + 1e-12
        let radial = radial * (1.0 + 1e-12);
        ArcPoint {
            p: (re, im),
            tangent: (-dim, dre),
            modulus,
            perp,
            foot,
            speed,
            pull,
            along: (u.0 * dim - u.1 * dre).abs(),
            radial,
        }
    }

    /// What the third-order arc bound needs besides at `z = exp(i theta)` ([`ArcBend`]):
    /// computed only for an arc whose first- and second-order bounds fall short.
    fn bend(&self, theta: f64) -> ArcBend {
        let z = theta.sin_cos();
        let (re, im) = weighted(&self.balls, z, |i| (i * i) as f64);
        let pull_speed = self.moves.iter().fold(0.0, |s, (b, reach)| {
            let (re, im) = weighted(b, z, |i| i as f64);
            s + reach * re.hypot(im)
        });
        ArcBend {
            bend: re.hypot(im),
            pull_speed,
        }
    }
}

/// What [`rouche_along`] knows at one point `z = exp(i theta)` of the circle, in `f64`:
/// `p(z)` and its derivative in the angle `i D(z)` (`D = sum_i i p_i z^i`), `|p(z)|`, the
/// distance from 0 to the line `p(z) + t i D(z)` and the `t` of its foot, `|D(z)|`,
/// `reach |S(z)|` summed over the slopes, and, for `u` the unit vector along `p(z)`,
/// `|Re(conj(u) i D(z))|` and `reach |Re(conj(u) S(z))|` summed over the slopes (with their
/// rounding): the component of each along `p`.
struct ArcPoint {
    p: (f64, f64),
    tangent: (f64, f64),
    modulus: f64,
    perp: f64,
    foot: f64,
    speed: f64,
    pull: f64,
    along: f64,
    radial: f64,
}

/// What the third-order arc bound knows besides at one point of the circle: the modulus of
/// `p`'s second derivative in the angle `|sum_i i^2 p_i z^i|`, and `reach |S'(z)|` summed
/// over the slopes (`S'` the derivative in the angle, `i sum_i i S_i z^i`).
struct ArcBend {
    bend: f64,
    pull_speed: f64,
}

/// The constants of [`rouche_along`]'s arc bounds: what the margin must exceed (the radii and
/// the rounding of `p` and `S`), `sum_i i |p_i|`, `sum_i i^2 |p_i|` and `sum_i i^3 |p_i|`
/// (bounds on the first, second and third derivatives of `p` in the angle), the rounding of
/// `D` and of the second derivative, and, summed over the slopes, `reach sum_i i |S_i|` and
/// `reach sum_i i^2 |S_i|` (bounds on `reach |S|`'s first and second derivatives) and the
/// rounding of `reach |S'|`.
struct ArcBounds {
    need: f64,
    steep: f64,
    curve: f64,
    rounding: f64,
    cubic: f64,
    bend_rounding: f64,
    steep_s: f64,
    curve_s: f64,
    speed_rounding_s: f64,
}

impl ArcBounds {
    /// A lower bound of `|p| - reach |S|` on the arc of half-width `h` around `at`. Two bounds
    /// of `|p|` on the arc, the larger taken: its value at the middle less `h sum_i i |p_i|`
    /// (first order); and Taylor's theorem to second order, `p(theta + t) = p + t i D + R`
    /// with `|R| <= t^2 / 2 sum_i i^2 |p_i|`, where `|p + t i D|`, `|t| <= h`, is at least the
    /// distance from 0 to that segment (the computed `D` off by at most its rounding, times
    /// `h`): the distance to its line, and when the line's foot lies beyond the segment the
    /// distance to the nearer end, at least `|p| - h |D|` either way. The end's modulus
    /// rounds by a few units of `|p| + h |D|`, and so does its choice when the computed foot
    /// is a few units off the end (the end is then within that of the foot), which
    /// `1e-14 (|p| + h |D|)` covers. A third bound takes Taylor's theorem to third order,
    /// `p(theta + t) = p + t i D + t^2 / 2 p'' + R3` with `|R3| <= |t|^3 / 6 sum_i i^3 |p_i|`
    /// and `p''` the second derivative at the middle (its computed modulus off by at most its
    /// rounding): where `p` has small coefficients' cancellations on the circle, its
    /// curvature there is far below `sum_i i^2 |p_i|`, and longer arcs clear.
    ///
    /// `reach |S|` grows by at most `h reach sum_i i |S_i|`, and by at most
    /// `h reach |S'| + h^2 / 2 reach sum_i i^2 |S_i|` (Taylor's theorem to second order
    /// around the middle, `|S'|` off by at most its rounding); the smaller is taken. The
    /// third-order bound and the second of these need `bend`; without it, the others alone.
    fn lower(&self, at: &ArcPoint, h: f64, bend: Option<&ArcBend>) -> f64 {
        let first = at.modulus - h * self.steep;
        let segment = if at.foot.abs() > h {
            let t = h.copysign(at.foot);
            let end = (at.p.0 + t * at.tangent.0).hypot(at.p.1 + t * at.tangent.1);
            end - 1e-14 * (at.modulus + h * at.speed)
        } else {
            at.perp
        };
        let line = segment.max(at.perp).max(at.modulus - h * at.speed) - h * self.rounding;
        let second = line - 0.5 * h * h * self.curve;
        let radial = self.radial(at, h);
        let Some(b) = bend else {
            return (first.max(second) - at.pull - h * self.steep_s).max(radial);
        };
        let third =
            line - 0.5 * h * h * (b.bend + self.bend_rounding) - h * h * h / 6.0 * self.cubic;
        let growth = (h * self.steep_s)
            .min(h * (b.pull_speed + self.speed_rounding_s) + 0.5 * h * h * self.curve_s);
        (first.max(second).max(third) - at.pull - growth).max(radial)
    }

    /// A lower bound on the arc of half-width `h` around `at` of the distance from 0 to the
    /// values the family can take there less `need`'s radii, by the members' components
    /// along `u`, the unit vector along `p` at the middle (zero exclusion: for every unit
    /// `u`, `|x| >= Re(conj(u) x)`). On the arc `Re(conj(u) p)` is at least its value
    /// `|p|` at the middle less `h |Re(conj(u) i D)|` (with `D`'s rounding) and
    /// `h^2 / 2 sum_i i^2 |p_i|` (Taylor's theorem to second order), and each slope's
    /// `reach |Re(conj(u) S)|` grows by at most `h reach sum_i i |S_i|`. Where the slopes
    /// move `p` across its direction, not along it (a parameter that turns the value on
    /// the circle without bringing it nearer 0), this is far above [`Self::lower`]'s
    /// `|p| - reach |S|`.
    fn radial(&self, at: &ArcPoint, h: f64) -> f64 {
        at.modulus * (1.0 - 2e-14)
            - h * (at.along + self.rounding)
            - 0.5 * h * h * self.curve
            - at.radial
            - h * self.steep_s
    }

    /// Whether `|p| - reach |S|` at the middle of an arc exceeds `need`: what every arc
    /// needs before its bounds are tried.
    fn clears_middle(&self, at: &ArcPoint) -> bool {
        let middle = (at.modulus - at.pull).max(at.modulus * (1.0 - 2e-14) - at.radial);
        !middle.is_nan() && middle > self.need
    }
}

/// Whether `|p| - reach |S| > need` on the arc of angles `[theta - h, theta + h]`, `at` its
/// middle (`family.point(theta)`): from the bounds of [`ArcBounds::lower`] around its
/// middle (the third-order one only when the others fall short), or by halving the arc at
/// most `depth` more times (only where the bound is short, so near the minimum).
fn arc_clears(
    family: &ArcFamily,
    (theta, at): (f64, ArcPoint),
    h: f64,
    bounds: &ArcBounds,
    depth: u32,
) -> bool {
    if !bounds.clears_middle(&at) {
        return false;
    }
    // the third-order bound with no curvature and no growth of the slopes at the middle
    // is the most it can give; only then is that curvature worth computing
    let flat = ArcBend {
        bend: 0.0,
        pull_speed: 0.0,
    };
    if bounds.lower(&at, h, None) > bounds.need
        || (bounds.lower(&at, h, Some(&flat)) > bounds.need
            && bounds.lower(&at, h, Some(&family.bend(theta))) > bounds.need)
    {
        return true;
    }
    let half = |theta: f64| (theta, family.point(theta));
    depth > 0
        && arc_clears(family, half(theta - 0.5 * h), 0.5 * h, bounds, depth - 1)
        && arc_clears(family, half(theta + 0.5 * h), 0.5 * h, bounds, depth - 1)
}

/// Arcs of the circle for the first lower bound of `|p|` in [`rouche`].
const COARSE: usize = 64;

/// The most halvings of an arc in [`rouche`]: arcs down to `pi / 64 / 2^16` (about 7e-7
/// rad) near the minimum; a cell that needs finer ones has too little room for its width
/// and is split instead.
const DEPTH: u32 = 16;

/// Proves `wall` (in the set's reference normalization, as [`super::robust_check`] takes
/// it) stable for every member of `set` by the box recursion (module documentation),
/// examining at most `budget` cells (at most 1024 for a box of three or more parameters of
/// a loop with elements). A set of loops with elements that spreads more than the
/// hand's parameters (a delay, a first- or second-order filter's cutoff, an actuator lag, a
/// transmission's parameters and the share of the damping its loop names, the mass or
/// damping under a transmission) goes to the recursion over loops with elements
/// (`proof_elements.rs`). `None` when the set is outside both: an interval of the share of
/// the damping the loop does not name (the motor's when the handle's is named, or the
/// other way round).
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
/// // a delay that jitters between 1 and 3 samples, fractions included
/// let paper = Device::new(1.0, 1.0, 0.5, Delay::Samples(1.0))?;
/// let jitter = DeviceSet::new(&paper, &PhysicalElements::default())?
///     .with_interval(Quantity::Delay, 1.0, 3.0)?;
/// assert!(prove_wall(&jitter, &Wall::new(0.15, 0.25)?, 1000)?.expect("paper").proved);
/// // a hand of 0.2 to 0.5 kg, and the device let go
/// let mut hand = PhysicalElements::default();
/// hand.hand_mass = Some(0.2);
/// hand.hand_stiffness = Some(300.0);
/// let users = DeviceSet::new(&device, &hand)?
///     .with_interval(Quantity::element("hand_mass")?, 0.2, 0.5)?;
/// assert!(prove_wall(&users, &Wall::new(0.1, 0.4)?, 1000)?.expect("a hand").proved);
/// // a first-order velocity filter whose cutoff is anywhere in 30..60 Hz
/// let mut filter = PhysicalElements::default();
/// filter.velocity_filter_cutoff = Some(30.0);
/// let cutoffs = DeviceSet::new(&device, &filter)?
///     .with_interval(Quantity::element("velocity_filter_cutoff")?, 30.0, 60.0)?;
/// assert!(prove_wall(&cutoffs, &Wall::new(0.01, 0.2)?, 1000)?.expect("a filter").proved);
/// // an actuator lag whose time constant is anywhere in 0.3..0.6 ms, near its robust optimum
/// let mut lag = PhysicalElements::default();
/// lag.actuator_time_constant = Some(3e-4);
/// let lags = DeviceSet::new(&device, &lag)?
///     .with_interval(Quantity::element("actuator_time_constant")?, 3e-4, 6e-4)?;
/// assert!(prove_wall(&lags, &Wall::new(0.087, 0.35)?, 1000)?.expect("a lag").proved);
/// # Ok::<(), stabound::Error>(())
/// ```
///
/// # Errors
///
/// As [`crate::elements::Loop::physical`] for a member; [`crate::Error::Cancelled`] when
/// cancelled.
pub fn prove_wall(set: &DeviceSet, wall: &Wall, budget: usize) -> Result<Option<Proof>> {
    Ok(prove_or_uncovered(set, wall, budget)?.ok())
}

/// [`prove_wall`], or the first parameter the set spreads that neither box recursion
/// encloses (where [`prove_wall`] gives `None`), found by the one pass over the set's boxes
/// that the recursion builds its cells from.
///
/// # Errors
///
/// As [`prove_wall`].
pub(super) fn prove_or_uncovered(
    set: &DeviceSet,
    wall: &Wall,
    budget: usize,
) -> Result<std::result::Result<Proof, Quantity>> {
    let Some(boxes) = boxes(set)? else {
        return super::proof_elements::prove_wall(set, wall, budget);
    };
    let m_ref = set.device.mass;
    let leaf = |(sides, delay): Cell<5>, stable| ProofCell {
        mass: sides[0],
        damping: sides[1],
        delay: delay.span(),
        hand: [sides[2], sides[3], sides[4]],
        elements: [(0.0, 0.0); 5],
        stable,
    };
    let cells = boxes.iter().map(|b| (b, start(b.sides, b.delay), budget));
    recurse(cells, |b, c| enclose(wall, m_ref, b, c), leaf, budget).map(Ok)
}

/// The box recursion over `boxes`, each with the cells it starts from and the most cells it
/// may examine itself (module documentation): each cell's polynomials `enclose`d are
/// decided by [`outside`], an undecided cell is halved by [`split`] and its halves queued,
/// breadth-first, until every cell is decided, one is refuted, or `budget` cells in all (or
/// the box's own share) are examined; `leaf` describes a decided (or abandoned) cell. A box's
/// share keeps one box that does not close from spending the cells another needs (a hand's
/// box and the device let go).
///
/// # Errors
///
/// [`crate::Error::Cancelled`] when cancelled.
pub(super) fn recurse<'a, B: 'a, const N: usize>(
    boxes: impl IntoIterator<Item = (&'a B, Vec<Cell<N>>, usize)>,
    enclose: impl Fn(&B, Cell<N>) -> Family,
    leaf: impl Fn(Cell<N>, bool) -> ProofCell,
    budget: usize,
) -> Result<Proof> {
    let mut leaves = Vec::new();
    let mut evaluated = 0;
    let mut proved = true;
    // the first reason a cell went undecided, and the cells the budget left (count, the
    // smallest's share of its box)
    let mut stopped = None;
    let mut left = (0, f64::INFINITY);
    for (b, cells, own) in boxes {
        let whole = cells.first().map(|c| c.0);
        let mut queue = VecDeque::from(cells);
        // the cells this box may still examine: its share, within what the budget has left
        let limit = own.min(budget.saturating_sub(evaluated));
        let mut mine = 0;
        while let Some(cell) = queue.pop_front() {
            crate::cancel::poll()?;
            evaluated += 1;
            mine += 1;
            let enclosed = |c| enclose(b, c);
            let family = (proved && mine <= limit).then(|| enclosed(cell));
            match family.as_ref().and_then(outside) {
                Some(0) => leaves.push(leaf(cell, true)),
                Some(_) => {
                    proved = false;
                    stopped.get_or_insert(ProofStop::Refuted);
                    leaves.push(leaf(cell, false));
                }
                None if !proved || mine >= limit => {
                    if proved || matches!(stopped, Some(ProofStop::Budget { .. })) {
                        let share = whole.map_or(1.0, |w| share_of_box(&cell, &w));
                        left = (left.0 + 1, f64::min(left.1, share));
                        // the share that ran out first
                        let cells = match stopped {
                            Some(ProofStop::Budget { cells, .. }) => cells,
                            _ => limit,
                        };
                        stopped = Some(ProofStop::Budget {
                            cells,
                            undecided: left.0,
                            smallest: left.1,
                        });
                    }
                    proved = false;
                    leaves.push(leaf(cell, false));
                }
                // the side to halve is weighed only for a cell that is halved
                None => match split(cell, family.as_ref().and_then(Family::widest), |c| {
                    enclosed(c).spread()
                }) {
                    Some((one, two)) => {
                        queue.push_back(one);
                        queue.push_back(two);
                    }
                    None => {
                        // one member and still undecided: nothing to split
                        proved = false;
                        stopped.get_or_insert(ProofStop::Inseparable);
                        leaves.push(leaf(cell, false));
                    }
                },
            }
        }
    }
    Ok(Proof {
        proved,
        leaves,
        evaluated,
        stopped,
    })
}

/// The largest share of its box's width `whole` that one of `cell`'s spread sides spans
/// (a delay piece's fraction: of one sample), `1` where nothing is spread.
fn share_of_box<const N: usize>(cell: &Cell<N>, whole: &[(f64, f64); N]) -> f64 {
    let (sides, delay) = cell;
    let mut share: Option<f64> = match delay {
        CellDelay::Piece { frac, .. } => Some(frac.1 - frac.0),
        CellDelay::Point(_) => None,
    };
    for (s, w) in sides.iter().zip(whole) {
        if w.1 > w.0 {
            let r = (s.1 - s.0) / (w.1 - w.0);
            share = Some(share.map_or(r, |x| x.max(r)));
        }
    }
    share.unwrap_or(1.0)
}

/// The two halves of `cell` across the side whose halving narrows the enclosures most
/// (`spread` of the lower half, `enclosed`; ties to the first side, the delay last), or
/// `None` for a cell of one member. The room [`rouche`] needs is what the
/// enclosures' radii take, so the side that contributes most of them is the one worth
/// halving, however wide it is relative to the box. A `hint` (the side a complete
/// mean-value form names, [`MeanValueForm::widest`]) is taken when that side can be halved,
/// without enclosing the halves.
fn split<const N: usize>(
    cell: Cell<N>,
    hint: Option<usize>,
    enclosed: impl Fn(Cell<N>) -> f64,
) -> Option<(Cell<N>, Cell<N>)> {
    let (sides, delay) = cell;
    let half = |c: (f64, f64)| {
        let mid = 0.5 * (c.0 + c.1);
        ((c.0, mid), (mid, c.1))
    };
    let across = |i: usize| {
        let (lo, hi) = half(sides[i]);
        let (mut one, mut two) = (sides, sides);
        one[i] = lo;
        two[i] = hi;
        ((one, delay), (two, delay))
    };
    let spread = |i: usize| sides[i].1 > sides[i].0;
    if let Some(i) = hint.filter(|&i| i < N && spread(i)) {
        return Some(across(i));
    }
    let mut halves: Vec<_> = (0..N).filter(|&i| spread(i)).map(across).collect();
    if let CellDelay::Piece { n, frac } = delay
        && frac.1 > frac.0
    {
        let (lo, hi) = half(frac);
        let piece = |frac| CellDelay::Piece { n, frac };
        halves.push(((sides, piece(lo)), (sides, piece(hi))));
    }
    if halves.len() < 2 {
        return halves.pop();
    }
    halves
        .into_iter()
        .map(|h| (enclosed(h.0), h))
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(_, h)| h)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::certificate::paper_parts_fractions;
    use crate::params::Plant;
    use crate::stability::{Checker, Options};

    /// The coefficients of `q` for the paper's loop at `(delta, d)` by the `f64` route
    /// (`model.rs` and the polynomial of section 3), lowest power first.
    fn point_coefficients(delta: f64, d: f64, wall: &Wall) -> Vec<f64> {
        Checker::new(Plant::new(delta, d).unwrap(), Options::default())
            .unwrap()
            .coefficients(wall)
    }

    /// Whether each enclosure holds the matching value, to a relative `1e-13` of the
    /// largest coefficient: the `f64` route rounds each coefficient by a few units of that.
    fn encloses(enclosures: &[Interval], values: &[f64]) -> bool {
        let scale = values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        enclosures.len() == values.len()
            && enclosures
                .iter()
                .zip(values)
                .all(|(e, &v)| e.contains(v, 1e-13 * scale))
    }

    /// The fractional family of `n` whole samples holds, at the fraction 0, `z` times the
    /// integer delay's polynomial and, at the fraction 1, the polynomial of `n + 1` samples:
    /// one family covers `[n, n + 1]` (module documentation).
    #[test]
    fn fractional_family_meets_the_whole_delays() {
        let wall = Wall::new(0.2, 0.3).unwrap();
        let (a, b) = (Interval::point(0.2), Interval::point(0.3));
        for delta in [0.0, 0.5, 3.0] {
            for n in [0usize, 1, 4] {
                let dl = Interval::point(delta);
                let at_zero = paper_parts_fractions(dl, n, Interval::point(0.0)).at(a, b);
                let mut shifted = vec![0.0];
                shifted.extend(point_coefficients(delta, n as f64, &wall));
                assert!(encloses(&at_zero, &shifted), "{delta} {n}: {at_zero:?}");
                let at_one = paper_parts_fractions(dl, n, Interval::point(1.0)).at(a, b);
                let next = point_coefficients(delta, n as f64 + 1.0, &wall);
                assert!(encloses(&at_one, &next), "{delta} {n}: {at_one:?}");
            }
        }
    }

    /// An enclosure over a cell of damping and fraction holds every member's coefficients
    /// (a grid of 11 x 11 members of each of several cells, fractions at the cells' ends
    /// included), and it narrows as the cell does (first order in its width).
    #[test]
    fn fraction_enclosures_hold_every_member() {
        let wall = Wall::new(0.15, 0.25).unwrap();
        let (a, b) = (Interval::point(0.15), Interval::point(0.25));
        for (n, e0, e1) in [(1usize, 0.0, 0.25), (2, 0.3, 0.35), (1, 0.9, 1.0 - 1e-9)] {
            for (d0, d1) in [(0.3, 0.3), (0.3, 0.8), (2.0, 2.1)] {
                let cell =
                    paper_parts_fractions(Interval::new(d0, d1), n, Interval::new(e0, e1)).at(a, b);
                for i in 0..=10 {
                    for j in 0..=10 {
                        let delta = d0 + (d1 - d0) * f64::from(i) / 10.0;
                        let eps = e0 + (e1 - e0) * f64::from(j) / 10.0;
                        let mut q = point_coefficients(delta, n as f64 + eps, &wall);
                        // exact: the fraction 0 is the integer delay, one degree less
                        if eps == 0.0 {
                            q.insert(0, 0.0);
                        }
                        assert!(encloses(&cell, &q), "{delta} {n} {eps}: {cell:?} {q:?}");
                    }
                }
            }
        }
        let width = |w: f64| {
            paper_parts_fractions(Interval::point(0.5), 2, Interval::new(0.5, 0.5 + w))
                .at(a, b)
                .iter()
                .map(|c| c.ball().unwrap().1)
                .fold(0.0, f64::max)
        };
        // halving the cell ten times narrows the enclosure by about 2^10; 500 leaves room
        // for the rounding floor
        assert!(width(0.1 / 1024.0) < width(0.1) / 500.0);
    }

    /// An enclosure over a cell of mass, damping and the hand's mass, damping and stiffness
    /// (a 50 Hz velocity filter fixed) holds the `f64` coefficients of the members at the
    /// cell's corners and centre.
    #[test]
    fn hand_enclosures_hold_every_member() {
        use crate::elements::PhysicalElements;
        use crate::params::Device;
        let named = PhysicalElements {
            hand_mass: Some(0.2),
            hand_damping: Some(1.0),
            hand_stiffness: Some(200.0),
            velocity_filter_cutoff: Some(50.0),
            ..Default::default()
        };
        let device = Device::new(0.1, 1e-3, 0.5, Delay::Samples(1.5)).unwrap();
        let lp = Loop::physical(&device, &named).unwrap();
        let sides = [
            (0.1, 0.12),
            (0.5, 0.7),
            (0.2, 0.25),
            (1.0, 1.5),
            (200.0, 260.0),
        ];
        let b = ProofBox {
            elements: Some(lp),
            sides,
            period: 1e-3,
            delay: (1.5, 1.5),
        };
        let wall = Wall::new(0.3, 0.2).unwrap();
        let cell = enclose(&wall, 0.1, &b, (sides, CellDelay::Point(1.5))).coefficients();
        for corner in 0..=32u32 {
            // 32: the centre; below it, the corners
            let at = |i: usize| {
                let (lo, hi) = sides[i];
                if corner == 32 {
                    0.5 * (lo + hi)
                } else if corner >> i & 1 == 1 {
                    hi
                } else {
                    lo
                }
            };
            let dev = Device::new(at(0), 1e-3, at(1), Delay::Samples(1.5)).unwrap();
            let mut e = named;
            (e.hand_mass, e.hand_damping, e.hand_stiffness) =
                (Some(at(2)), Some(at(3)), Some(at(4)));
            let s = 0.1 / at(0);
            let q = Checker::new(Loop::physical(&dev, &e).unwrap(), Options::default())
                .unwrap()
                .coefficients(&Wall::new(0.3 * s, 0.2 * s).unwrap());
            assert!(encloses(&cell, &q), "{corner}: {cell:?} {q:?}");
        }
    }

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

    /// The centred form over a cell of fractions holds every member's coefficients (11 x 11
    /// members of each cell, its ends included), and over a narrow cell its width is the
    /// coefficients' own spread across the cell, not a multiple of it: at a cell of width
    /// `1e-3` each coefficient's enclosure is within 1 % (plus the rounding floor) of the
    /// range its members take, where the direct enclosure is several times wider.
    #[test]
    fn centred_fraction_form_holds_every_member_and_is_tight() {
        let wall = Wall::new(0.15, 0.25).unwrap();
        let (a, b) = (Interval::point(0.15), Interval::point(0.25));
        let members = |n: usize, dl: (f64, f64), fr: (f64, f64), i: u32, j: u32| {
            let delta = dl.0 + (dl.1 - dl.0) * f64::from(i) / 10.0;
            let eps = fr.0 + (fr.1 - fr.0) * f64::from(j) / 10.0;
            let mut q = point_coefficients(delta, n as f64 + eps, &wall);
            // exact: the fraction 0 is the integer delay, one degree less
            if eps == 0.0 {
                q.insert(0, 0.0);
            }
            q
        };
        for (n, e0, e1) in [(1usize, 0.0, 0.25), (2, 0.3, 0.35), (1, 0.9, 1.0 - 1e-9)] {
            for dl in [(0.3, 0.3), (0.3, 0.8), (2.0, 2.1)] {
                let e = Interval::new(e0, e1);
                let f = paper_fraction_family(Interval::new(dl.0, dl.1), n, e, a, b);
                let cell = MeanValueForm::from(f).coefficients();
                for i in 0..=10 {
                    for j in 0..=10 {
                        let q = members(n, dl, (e0, e1), i, j);
                        assert!(encloses(&cell, &q), "{dl:?} {n} {j}: {cell:?} {q:?}");
                    }
                }
            }
        }
        let (n, fr, dl) = (2usize, (0.6, 0.601), (0.5, 0.5));
        let e = Interval::new(fr.0, fr.1);
        let centred = MeanValueForm::from(paper_fraction_family(Interval::point(0.5), n, e, a, b))
            .coefficients();
        let direct = paper_parts_fractions(Interval::point(0.5), n, e).at(a, b);
        let samples: Vec<Vec<f64>> = (0..=10).map(|j| members(n, dl, fr, 0, j)).collect();
        let mut wider = 0.0f64;
        for k in 0..4 {
            let values = samples.iter().map(|q| q[k]);
            let lo = values.clone().fold(f64::INFINITY, f64::min);
            let hi = values.fold(f64::NEG_INFINITY, f64::max);
            let width = |c: Interval| c.hi() - c.lo();
            // the coefficients are monotone over so narrow a cell (their derivatives do not
            // vanish there), so the sampled ends are the range; 1e-15 is the rounding floor
            assert!(width(centred[k]) <= 1.01 * (hi - lo) + 1e-15, "{k}");
            wider = wider.max(width(direct[k]) / width(centred[k]));
        }
        assert!(wider > 2.0, "{wider}");
    }

    /// A mean-value form whose centre has a root outside the circle refutes the wall,
    /// however wide its slope: the family `(z - 1.1)(z + 0.5) + t (1 + z)`, `|t| <= 1`, holds
    /// stable members (`t = 0.55`: `z^2 - 0.05 z`) and unstable ones (`t = 0`), so neither
    /// Rouche's test nor the interval recursion over its coefficients decides it, and its
    /// centre alone refutes it with the one root outside; with the centre's roots at `0.9`
    /// and `-0.5` the same slope leaves it undecided.
    #[test]
    fn an_unstable_centre_refutes_a_mean_value_cell() {
        let form = |r1: f64| {
            Family::Centred(MeanValueForm {
                centre: widened(r1, -0.5, 0.0),
                slopes: vec![Slope {
                    side: Some(0),
                    slope: vec![
                        Interval::point(1.0),
                        Interval::point(1.0),
                        Interval::point(0.0),
                    ],
                    offset: Interval::new(-1.0, 1.0),
                }],
                complete: true,
            })
        };
        assert_eq!(outside(&form(1.1)), Some(1));
        assert_eq!(recursion(&form(1.1).coefficients()).outside, None);
        assert_eq!(outside(&form(0.9)), None);
    }

    /// Rouché's test along a slope: `q = (1 + t) p` has the roots of `p` for every `|t| < 1`,
    /// which the coefficient-wise test cannot see (the radii `|t| |p_i|` add up to more than
    /// `min |p|` on the circle) and the test along the slope proves; `q = p + t` with
    /// `|t| <= 0.2` holds `p - 0.15`, which has the root 1 (`p(1) = 0.15`), and is refused.
    #[test]
    fn rouche_along_a_slope_sees_the_members_move_together() {
        let p = widened(0.9, -0.5, 0.0);
        let spread: Vec<Interval> = p.iter().map(|c| *c * Interval::new(-0.5, 0.5)).collect();
        assert!(!rouche(
            &p.iter()
                .zip(&spread)
                .map(|(&c, &s)| c + s)
                .collect::<Vec<_>>()
        ));
        assert!(rouche_along(&p, &[(&p, 0.5)]));
        let one = [Interval::point(1.0)];
        assert!(!rouche_along(&p, &[(&one, 0.2)]));
        assert!(rouche_along(&p, &[(&one, 0.1)]));
        // two slopes add up: each alone has room, together they reach the root at 1
        assert!(!rouche_along(&p, &[(&one, 0.1), (&one, 0.1)]));
        assert!(rouche_along(&p, &[(&one, 0.05), (&one, 0.05)]));
    }

    /// The second-order arc bound takes the distance from 0 to the tangent segment, not only
    /// to its line: at `p = 1` moving along `i D = 1 + i` over `|t| <= 0.1` the line's foot
    /// (`t = -0.5`) lies beyond the segment, whose least modulus, sampled at 10,001 points,
    /// is `|0.9 - 0.1 i| = 0.9055`, above the line's distance `0.7071` and `|p| - h |D| =
    /// 0.8586`; the bound (no curvature, rounding or slope) reaches it within the rounding
    /// allowance and never exceeds it.
    #[test]
    fn arc_bound_reaches_the_tangent_segment() {
        let (p, w, h) = ((1.0f64, 0.0f64), (1.0f64, 1.0f64), 0.1f64);
        let speed = w.0.hypot(w.1);
        let at = ArcPoint {
            p,
            tangent: w,
            modulus: 1.0,
            perp: (p.0 * w.1 - p.1 * w.0).abs() / speed,
            foot: -(p.0 * w.0 + p.1 * w.1) / (speed * speed),
            speed,
            pull: 0.0,
            // p is along u = 1, so i D's component along it is Re(1 + i) = 1; no slope
            along: 1.0,
            radial: 0.0,
        };
        let bounds = ArcBounds {
            need: 0.0,
            // the first-order bound, 1 - 0.1 * 10 = 0, stays out of the way
            steep: 10.0,
            curve: 0.0,
            rounding: 0.0,
            cubic: 0.0,
            bend_rounding: 0.0,
            steep_s: 0.0,
            curve_s: 0.0,
            speed_rounding_s: 0.0,
        };
        let least = (0..=10_000)
            .map(|j| {
                let t = -h + 2.0 * h * f64::from(j) / 10_000.0;
                (p.0 + t * w.0).hypot(p.1 + t * w.1)
            })
            .fold(f64::INFINITY, f64::min);
        let lower = bounds.lower(&at, h, None);
        assert!(lower <= least, "{lower} {least}");
        // the allowance is 1e-14 (|p| + h |D|)
        assert!(lower > least - 1e-13, "{lower} {least}");
        assert!(lower > 1.0 - h * speed + 0.04, "{lower}");
    }

    /// The arc bounds never claim more room than there is: for polynomials with a pair of
    /// roots `rho exp(+-i phi)` near the circle and one at `-0.5`, the minimum of `|p|` on the
    /// circle is sampled at 200,000 points. The sampled minimum is at least the true one, so
    /// coefficient radii adding to 1.01 times it exceed the true minimum and a sound lower
    /// bound cannot prove them; the samples are 3.1e-5 rad apart, so the sampled minimum
    /// exceeds the true one by under 2 % even at `rho = 0.9999` (`|p|` grows as
    /// `sqrt((1 - rho)^2 + t^2)` times a smooth factor near the root's angle), and radii
    /// adding to 0.9 times it leave room that the arcs must find.
    #[test]
    fn rouche_arcs_claim_no_more_room_than_there_is() {
        for (rho, phi) in [(0.99, 0.3), (0.999, 1.2), (0.995, 2.9), (0.9999, 0.05)] {
            let (a, b) = (-2.0 * rho * f64::cos(phi), rho * rho);
            // (z^2 + a z + b)(z + 0.5), lowest power first
            let p = [0.5 * b, b + 0.5 * a, a + 0.5, 1.0];
            let least = (0..200_000)
                .map(|j| {
                    let theta = std::f64::consts::TAU * f64::from(j) / 200_000.0;
                    let (sin, cos) = theta.sin_cos();
                    let (mut re, mut im) = (0.0f64, 0.0f64);
                    for &c in p.iter().rev() {
                        (re, im) = (re * cos - im * sin + c, re * sin + im * cos);
                    }
                    re.hypot(im)
                })
                .fold(f64::INFINITY, f64::min);
            let family = |share: f64| -> Vec<Interval> {
                p.iter()
                    .map(|&c| Interval::from_ball(c, share * least / 4.0))
                    .collect()
            };
            assert!(!rouche(&family(1.01)), "{rho} {phi}: {least}");
            assert!(rouche(&family(0.9)), "{rho} {phi}: {least}");
        }
    }

    /// The arc bounds along slopes claim no more room than there is either: for the
    /// polynomials of [`rouche_arcs_claim_no_more_room_than_there_is`] and a slope
    /// `S = 0.3 - 0.2 z + 0.1 z^2 + 0.05 z^3` whose reach takes a third of `min |p|`, the
    /// minimum of `|p| - reach |S|` on the circle is sampled at 200,000 points, as is the
    /// largest `|p|` (a bound on the spacing's error: both moduli change by at most
    /// `sum_i i |a_i|` per radian, under 8 for these coefficients, so by under `1.3e-4` of
    /// the spacing `3.1e-5`; the sampled minimum exceeds the true one by at most that, under
    /// 2 % of the minimum at these roots). Radii adding to 1.01 times the least distance
    /// from 0 to the members' values `p + t S`, `|t| <= reach` (sampled the same way; the
    /// bound along `p`'s direction may claim up to that, no more), are refused; 0.9 times
    /// the least `|p| - reach |S|`, proved. The slope enters by its value and its derivative
    /// on each arc (the second-order growth of `reach |S|`), which the test exercises.
    #[test]
    fn rouche_arcs_along_a_slope_claim_no_more_room_than_there_is() {
        let slope = [0.3, -0.2, 0.1, 0.05];
        let modulus = |c: &[f64], theta: f64| {
            let (sin, cos) = theta.sin_cos();
            let (mut re, mut im) = (0.0f64, 0.0f64);
            for &a in c.iter().rev() {
                (re, im) = (re * cos - im * sin + a, re * sin + im * cos);
            }
            re.hypot(im)
        };
        for (rho, phi) in [(0.99, 0.3), (0.999, 1.2), (0.995, 2.9), (0.9999, 0.05)] {
            let (a, b) = (-2.0 * rho * f64::cos(phi), rho * rho);
            let p = [0.5 * b, b + 0.5 * a, a + 0.5, 1.0];
            let angles = (0..200_000).map(|j| std::f64::consts::TAU * f64::from(j) / 200_000.0);
            let least_p = angles
                .clone()
                .map(|t| modulus(&p, t))
                .fold(f64::INFINITY, f64::min);
            let most_s = angles
                .clone()
                .map(|t| modulus(&slope, t))
                .fold(0.0, f64::max);
            let reach = least_p / (3.0 * most_s);
            let least = angles
                .clone()
                .map(|t| modulus(&p, t) - reach * modulus(&slope, t))
                .fold(f64::INFINITY, f64::min);
            assert!(least > 0.5 * least_p, "{rho} {phi}: {least} {least_p}");
            // the least distance from 0 to the members' values p + t S, |t| <= reach: to
            // the segment, its foot clamped to the ends (the same spacing argument holds)
            let value = |c: &[f64], theta: f64| {
                let (sin, cos) = theta.sin_cos();
                let (mut re, mut im) = (0.0f64, 0.0f64);
                for &a in c.iter().rev() {
                    (re, im) = (re * cos - im * sin + a, re * sin + im * cos);
                }
                (re, im)
            };
            let nearest = angles
                .map(|t| {
                    let ((pr, pi), (sr, si)) = (value(&p, t), value(&slope, t));
                    let foot = (-(pr * sr + pi * si) / (sr * sr + si * si)).clamp(-reach, reach);
                    (pr + foot * sr).hypot(pi + foot * si)
                })
                .fold(f64::INFINITY, f64::min);
            assert!(nearest >= least, "{rho} {phi}: {nearest} {least}");
            let s: Vec<Interval> = slope.iter().map(|&c| Interval::point(c)).collect();
            let family = |room: f64| -> Vec<Interval> {
                p.iter()
                    .map(|&c| Interval::from_ball(c, room / 4.0))
                    .collect()
            };
            assert!(
                !rouche_along(&family(1.01 * nearest), &[(&s, reach)]),
                "{rho} {phi}"
            );
            assert!(
                rouche_along(&family(0.9 * least), &[(&s, reach)]),
                "{rho} {phi}"
            );
        }
    }

    /// The third-order arc bound never exceeds the least `|p|` on its arc, and it is what
    /// lets longer arcs clear near a root close to the circle: for `p` of
    /// [`rouche_arcs_claim_no_more_room_than_there_is`] with the root pair at `0.999
    /// exp(+-1.2 i)`, on arcs of half-width `1e-3` to `3e-2` around 41 angles near the root,
    /// the bound stays below the least `|p|` sampled at 2,001 points of the arc (that
    /// sampled least is at least the true one), and at the widest arcs around the root's
    /// angle it exceeds the second-order bound alone (`sum_i i^2 |p_i|` for the curvature)
    /// somewhere.
    #[test]
    fn third_order_arc_bound_holds_and_gains() {
        let (rho, phi) = (0.999f64, 1.2f64);
        let (a, b) = (-2.0 * rho * phi.cos(), rho * rho);
        let p: Vec<Interval> = [0.5 * b, b + 0.5 * a, a + 0.5, 1.0]
            .iter()
            .map(|&c| Interval::point(c))
            .collect();
        let value = |theta: f64| {
            let (sin, cos) = theta.sin_cos();
            let (mut re, mut im) = (0.0f64, 0.0f64);
            for c in p.iter().rev() {
                (re, im) = (re * cos - im * sin + c.lo(), re * sin + im * cos);
            }
            re.hypot(im)
        };
        let (bounds, family) = arc_setup(&p, &[]).expect("p is stable");
        let mut gains = 0;
        for h in [1e-3, 3e-3, 1e-2, 3e-2] {
            for k in 0..=40 {
                let theta = phi - 0.1 + 0.2 * f64::from(k) / 40.0;
                let at = family.point(theta);
                let least = (0..=2000)
                    .map(|j| value(theta - h + 2.0 * h * f64::from(j) / 2000.0))
                    .fold(f64::INFINITY, f64::min);
                let lower = bounds.lower(&at, h, Some(&family.bend(theta)));
                assert!(lower <= least, "{h} {theta}: {lower} {least}");
                if lower > bounds.lower(&at, h, None) + 1e-9 {
                    gains += 1;
                }
            }
        }
        assert!(gains > 0);
    }
}
