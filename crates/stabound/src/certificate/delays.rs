//! Certified verdicts over a set of devices that differ in their delay: one wall, every
//! delay of an interval `[d0, d1]` (`docs/MODEL.md` section 11).
//!
//! The interval is cut at the whole numbers into pieces `[n, n + 1]`. Within a piece the
//! delay `n + eps` enters the polynomial only through the held force's sampling instant
//! `eps`, and the fractional form (degree `n + 4` for the paper's loop) holds for every
//! `eps` of `[0, 1]`: at `eps = 0` it is `z` times the whole delay's polynomial, at `eps =
//! 1` the delay `n + 1`'s, so a piece is one family with one stability count. A cell is a
//! sub-interval `[e0, e1]` of fractions of one piece: each coefficient of `q` is enclosed
//! over it in centred form (`super::FractionFamily`: its enclosure at the middle fraction
//! plus the enclosure of its derivative in `eps` over the cell times the offset, which
//! overestimates its range by a term second order in the cell's width; the direct
//! enclosure's first-order term leaves walls with a wide margin undecided even in cells of
//! `1e-3`). A cell is first decided around its centre: the Schur-Cohn recursion on the
//! centre's enclosures counts its roots outside the unit circle, and Rouché's theorem on
//! arcs of the circle (the `circle` module, with the slope as the direction of the
//! perturbation and the offset's magnitude as its radius) proves that no root crosses the
//! circle anywhere in the cell, so every delay of it has that count. Failing that, the
//! recursion on the cell's enclosures counts them for every delay at once. A cell neither
//! decides is halved, breadth first, up to a budget of cells. The paper's loop only: the checker
//! recomputes its values, `exp(-delta tau)`, `phi1` and `phi2`, over an interval of `tau`
//! by their monotonicity.
//!
//! The certificate lists the cells in order of delay, each with its whole samples, its
//! fractions and middle fraction, its claim, its coefficient enclosures (the centre's, with
//! the slope's and the ends of the arcs, for a cell decided around its centre) and its
//! reflection coefficients' enclosures; the checker recomputes each cell's enclosures from
//! its fractions, replays its recursion and its arcs, and checks that the cells tile the
//! delay interval exactly.

use std::collections::VecDeque;
use std::fmt::Write as _;

use super::circle::{Circle, MAX_ARCS};
use super::interval::Interval;
use super::schur::{Recursion, recursion};
use super::{Ball, FractionFamily, balls, hex, list_json, paper_fraction_family, reflection_balls};
use crate::elements::Loop;
use crate::error::{Error, Result};
use crate::params::{MAX_DELAY, Wall};

/// What a set certificate proves for the wall over the whole delay interval.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum DelayClaim {
    /// Stable at every delay of the interval.
    Stable,
    /// Unstable at every delay of the interval.
    Unstable,
    /// Neither proved within the budget of cells.
    NotProved,
}

/// One cell: `n` whole samples and the fractions `[e0, e1]`.
#[derive(Debug, Clone)]
struct Cell {
    n: usize,
    frac: (f64, f64),
    coefficients: Vec<Ball>,
    /// The recursion and the count of roots outside it proved (`None`: undecided).
    recursion: Option<Recursion>,
    outside: Option<usize>,
    /// Decided around the centre: the slope's enclosures and the arcs (the coefficients and
    /// the recursion are then the centre's).
    around: Option<Around>,
}

/// A certified verdict for one wall of the paper's loop over every delay of an interval.
///
/// ```
/// use stabound::certificate::{DelayClaim, certify_delays};
/// use stabound::params::{Plant, Wall};
///
/// // the paper's loop at delta = 0.5 and every delay from 1 to 3 samples
/// let plant = Plant::new(0.5, 1.0)?;
/// let cert = certify_delays(plant, &Wall::new(0.1, 0.3)?, (1.0, 3.0), 1024)?;
/// assert_eq!(cert.claim(), DelayClaim::Stable);
/// let (stable, unstable, undecided) = cert.counts();
/// assert!(stable >= 2 && unstable + undecided == 0);
/// assert!(cert.to_json().contains("\"kind\": \"delays\""));
/// # Ok::<(), stabound::Error>(())
/// ```
#[derive(Debug, Clone)]
pub struct DelayCertificate {
    lp: Loop,
    wall: Wall,
    delays: (f64, f64),
    cells: Vec<Cell>,
}

/// The pieces `(n, [e0, e1])` that cover the delays `[lo, hi]`, `0 <= lo < hi`, cut at the
/// whole numbers.
fn pieces(lo: f64, hi: f64) -> Vec<(usize, (f64, f64))> {
    let mut out = Vec::new();
    let mut n = lo.floor();
    while n < hi {
        // exact: a number minus a whole number at most itself and above it less one (its
        // floor) is exact in binary floating point
        let e0 = if lo > n { lo - n } else { 0.0 };
        let e1 = if hi < n + 1.0 { hi - n } else { 1.0 };
        out.push((n as usize, (e0, e1)));
        n += 1.0;
    }
    out
}

/// The paper loop's polynomial at damping `delta` under `wall` for every delay `n + eps`,
/// `eps` in `e` (the fractional form), in centred form around the fraction `mid`
/// ([`paper_fraction_family`]): `centre + slope (eps - mid)`.
fn enclose(delta: f64, wall: &Wall, n: usize, e: Interval) -> FractionFamily {
    let (a, b) = (Interval::point(wall.alpha()), Interval::point(wall.beta()));
    paper_fraction_family(Interval::point(delta), n, e, a, b)
}

/// The enclosures of `family`'s coefficients over its whole cell, `centre + slope offset`.
fn over_cell(family: &FractionFamily) -> Vec<Interval> {
    family
        .centre
        .iter()
        .zip(&family.slope)
        .map(|(&c, &s)| c + s * family.offset)
        .collect()
}

/// The count of roots outside the unit circle of every polynomial of `family`, decided
/// around its centre: the recursion on the centre's enclosures counts them, and Rouché's
/// theorem on arcs of the circle ([`Circle`], the slope as the direction and the offset's
/// magnitude as the radius) proves that no root crosses the circle within the cell. The
/// count, the centre's and the slope's enclosures as balls, the recursion and the arcs.
fn around_centre(family: &FractionFamily) -> Option<Around> {
    let (centre, q) = balls(family.centre.clone())?;
    let (slope, _) = balls(family.slope.clone())?;
    let recursion = recursion(&q);
    let outside = recursion.outside?;
    let arcs = Circle::ball_family(&centre, &slope, family.offset.mag()).cover(MAX_ARCS)?;
    Some(Around {
        outside,
        centre,
        slope,
        recursion,
        arcs,
    })
}

/// A cell decided around its centre ([`around_centre`]).
#[derive(Debug, Clone)]
struct Around {
    outside: usize,
    centre: Vec<Ball>,
    slope: Vec<Ball>,
    recursion: Recursion,
    arcs: Vec<f64>,
}

/// The centre fraction of the cell `[e0, e1]`, as [`paper_fraction_family`] takes it (the
/// same expression, so that the certificate records the fraction the enclosures used).
fn middle((e0, e1): (f64, f64)) -> f64 {
    0.5 * e0 + 0.5 * e1
}

/// Certifies the verdict of `wall` on the paper's loop `lp` at every delay `d` of `[d0, d1]`
/// (in sampling periods; the delay of `lp` itself is not used), halving cells of delay
/// where the recursion is undecided, at most `max_cells` cells (module documentation).
///
/// ```
/// use stabound::certificate::{DelayClaim, certify_delays};
/// use stabound::elements::{Hand, Loop};
/// use stabound::params::{Plant, Wall};
///
/// let plant = Plant::new(0.5, 1.0)?;
/// // too stiff at every delay from 1 to 3 samples
/// let cert = certify_delays(plant, &Wall::new(1.5, 0.3)?, (1.0, 3.0), 1024)?;
/// assert_eq!(cert.claim(), DelayClaim::Unstable);
/// // stable at 1 sample, unstable at 3: neither claim holds for the whole interval
/// let cert = certify_delays(plant, &Wall::new(0.25, 0.3)?, (1.0, 3.0), 64)?;
/// assert_eq!(cert.claim(), DelayClaim::NotProved);
/// // a loop with elements is refused
/// let hand = Loop::new(plant).with_hand(Hand::new(0.2, 0.1, 0.01)?)?;
/// assert!(certify_delays(hand, &Wall::new(0.1, 0.3)?, (1.0, 3.0), 64).is_err());
/// # Ok::<(), stabound::Error>(())
/// ```
///
/// # Errors
///
/// [`Error::InvalidParameter`] for delays outside `0 <= d0 < d1 <= MAX_DELAY` or a budget
/// of 0; [`Error::InvalidRequest`] for a loop with elements (not covered: their matrix
/// exponential over an interval of the fraction is not yet written for the checker);
/// [`Error::Numerical`] when a coefficient's enclosure overflows.
pub fn certify_delays(
    lp: impl Into<Loop>,
    wall: &Wall,
    (d0, d1): (f64, f64),
    max_cells: usize,
) -> Result<DelayCertificate> {
    let lp: Loop = lp.into();
    if !lp.is_paper() {
        return Err(Error::InvalidRequest(
            "a certificate over an interval of delays covers the paper's loop: leave out the loop elements, or certify each delay on its own".into(),
        ));
    }
    if max_cells == 0 {
        return Err(Error::InvalidParameter {
            name: "max_cells",
            value: 0.0,
            expected: "a budget of at least one cell".into(),
        });
    }
    if !(d0 >= 0.0 && d0 < d1 && d1 <= MAX_DELAY) {
        return Err(Error::InvalidParameter {
            name: "delay",
            value: d1,
            expected: format!(
                "an interval of delays from d0 >= 0 to d1 > d0, at most {MAX_DELAY} samples (got {d0}..{d1})"
            ),
        });
    }
    let mut queue: VecDeque<(usize, (f64, f64))> = pieces(d0, d1).into();
    let mut cells = Vec::new();
    while let Some((n, frac)) = queue.pop_front() {
        crate::cancel::poll()?;
        let family = enclose(lp.plant().delta(), wall, n, Interval::new(frac.0, frac.1));
        if let Some(around) = around_centre(&family) {
            cells.push(Cell {
                n,
                frac,
                coefficients: around.centre.clone(),
                outside: Some(around.outside),
                recursion: Some(around.recursion.clone()),
                around: Some(around),
            });
            continue;
        }
        let (coefficients, q) = balls(over_cell(&family)).ok_or_else(|| {
            Error::Numerical(
                "a coefficient's enclosure over a cell of delays overflows: the wall is too large to certify".into(),
            )
        })?;
        let rec = recursion(&q);
        let mid = middle(frac);
        // a cell is halved while the budget holds its two halves and the middle splits it
        let room = cells.len() + queue.len() + 2 <= max_cells;
        if rec.outside.is_none() && room && frac.0 < mid && mid < frac.1 {
            queue.push_back((n, (frac.0, mid)));
            queue.push_back((n, (mid, frac.1)));
            continue;
        }
        cells.push(Cell {
            n,
            frac,
            coefficients,
            outside: rec.outside,
            recursion: rec.outside.map(|_| rec),
            around: None,
        });
    }
    cells.sort_by(|a, b| {
        (a.n, a.frac.0)
            .partial_cmp(&(b.n, b.frac.0))
            .expect("finite")
    });
    Ok(DelayCertificate {
        lp,
        wall: *wall,
        delays: (d0, d1),
        cells,
    })
}

impl DelayCertificate {
    /// What the certificate proves.
    pub fn claim(&self) -> DelayClaim {
        match self.counts() {
            (_, 0, 0) => DelayClaim::Stable,
            (0, _, 0) => DelayClaim::Unstable,
            _ => DelayClaim::NotProved,
        }
    }

    /// The cells proved stable, proved unstable and left undecided.
    pub fn counts(&self) -> (usize, usize, usize) {
        let count =
            |f: fn(Option<usize>) -> bool| self.cells.iter().filter(|c| f(c.outside)).count();
        (
            count(|o| o == Some(0)),
            count(|o| matches!(o, Some(1..))),
            count(|o| o.is_none()),
        )
    }

    /// The certificate as JSON text (see the module documentation), ending in a newline.
    pub fn to_json(&self) -> String {
        let (mut s, elements) = super::head("delays", &self.lp);
        let _ = write!(
            s,
            "  \"inputs\": {{\"alpha\": \"{}\", \"beta\": \"{}\", \"delta\": \"{}\", \"d\": [\"{}\", \"{}\"]",
            hex(self.wall.alpha()),
            hex(self.wall.beta()),
            hex(self.lp.plant().delta()),
            hex(self.delays.0),
            hex(self.delays.1)
        );
        for (k, v) in &elements {
            let _ = write!(s, ", \"{k}\": {v}");
        }
        s.push_str("},\n  \"leaves\": [");
        for (i, cell) in self.cells.iter().enumerate() {
            s.push_str(if i == 0 { "\n" } else { ",\n" });
            let _ = write!(
                s,
                "    {{\"box\": {{\"n\": {}, \"eps\": [\"{}\", \"{}\"]}}, \"centre\": {{\"eps\": \"{}\"}}, \"claim\": ",
                cell.n,
                hex(cell.frac.0),
                hex(cell.frac.1),
                hex(middle(cell.frac))
            );
            match cell.outside {
                Some(0) => s.push_str("\"stable\""),
                Some(k) => {
                    let _ = write!(s, "\"unstable\", \"outside\": {k}");
                }
                None => s.push_str("\"undecided\""),
            }
            s.push_str(",\n     \"coefficients\": ");
            list_json(&mut s, "      ", &cell.coefficients);
            s.push_str(",\n     \"reflections\": ");
            let refl = cell.recursion.as_ref().map(reflection_balls);
            list_json(&mut s, "      ", refl.as_deref().unwrap_or_default());
            if let Some(around) = &cell.around {
                s.push_str(",\n     \"slope\": ");
                list_json(&mut s, "      ", &around.slope);
                super::arcs_json(&mut s, &around.arcs);
            }
            s.push('}');
        }
        let (stable, unstable, undecided) = self.counts();
        let verdict = match self.claim() {
            DelayClaim::Stable => "stable",
            DelayClaim::Unstable => "unstable",
            DelayClaim::NotProved => "not proved",
        };
        let _ = writeln!(
            s,
            "],\n  \"claim\": {{\"verdict\": \"{verdict}\", \"stable\": {stable}, \"unstable\": {unstable}, \"undecided\": {undecided}}},"
        );
        super::seal(s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::Plant;

    #[test]
    fn pieces_cut_at_whole_delays() {
        assert_eq!(pieces(1.0, 3.0), vec![(1, (0.0, 1.0)), (2, (0.0, 1.0))]);
        assert_eq!(pieces(1.25, 2.5), vec![(1, (0.25, 1.0)), (2, (0.0, 0.5))]);
        assert_eq!(pieces(0.0, 0.5), vec![(0, (0.0, 0.5))]);
    }

    /// The cells tile the delays in order, and a budget of one cell leaves the wall
    /// unproved where halving is needed.
    #[test]
    fn cells_tile_the_delays() {
        let plant = Plant::new(0.5, 1.0).unwrap();
        let wall = Wall::new(0.1, 0.3).unwrap();
        let cert = certify_delays(plant, &wall, (1.25, 3.0), 1024).unwrap();
        let mut end = (1usize, 0.25);
        for c in &cert.cells {
            let at = if end.1 == 1.0 { (end.0 + 1, 0.0) } else { end };
            assert_eq!((c.n, c.frac.0), at);
            end = (c.n, c.frac.1);
        }
        assert_eq!(end, (2, 1.0));
        assert!(certify_delays(plant, &wall, (3.0, 1.0), 8).is_err());
        assert!(certify_delays(plant, &wall, (1.0, 3.0), 0).is_err());
    }
}
