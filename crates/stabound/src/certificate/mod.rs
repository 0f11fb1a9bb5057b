//! Certified verdicts: a proof of a wall's stability verdict that a short, separate program
//! can replay (`docs/MODEL.md` section 11).
//!
//! The inputs are `f64` numbers, so exact rationals. The coefficients of the characteristic
//! polynomial `q` (section 3) involve `exp(-delta)` and the `phi` functions; each is enclosed
//! in an interval with outward rounding (the `interval` module: Taylor sums with rigorous
//! remainders), and `q`'s coefficients are assembled from them in interval arithmetic. The
//! Schur-Cohn recursion then runs on those enclosures (the `schur` module). A loop with
//! elements (hand, transmission, actuator lag, velocity filter) is enclosed through its
//! sampled device instead (the `device` module: the matrix exponential by scaling, Taylor
//! with a rigorous remainder and squaring; the determinant and adjugate by
//! Faddeev-LeVerrier). A regular recursion proves the count of roots outside the unit circle for every polynomial in the
//! enclosures, so for the exact model:
//!
//! - every reflection coefficient strictly inside `(-1, 1)`: **stable**;
//! - a regular recursion with some outside `[-1, 1]`: **unstable**, with the count of roots
//!   outside the circle;
//! - a coefficient of the monic `q` above the binomial bound `binom(n, k)`: **unstable**
//!   (some root outside; huge walls, whose recursion meets a root within rounding of the
//!   circle);
//! - otherwise, when the recursion on `q((1 + eps) z)` proves every root inside the radius
//!   `1 + eps` and the one on `q((1 - eps) z)` proves a root outside `1 - eps`: **marginal
//!   within eps** (the spectral radius is within `eps` of 1).
//!
//! The arithmetic is `f64` intervals only. It stops deciding where an enclosure's width reaches
//! the distance to the boundary: the coefficients are enclosed to a few units in the last place
//! relative to their size, and a reflection coefficient near 1 in modulus loses about
//! `-log2(1 - |r|)` bits at each later step. Walls whose spectral radius is within about
//! `1e-12` of 1 (farther near double roots, where the roots move by the square root of the
//! coefficients' error) are then certified as marginal within the band, or not at all
//! ([`Error::Numerical`]).
//!
//! Every certificate opens with its format, `"certificate": "stabound certificate 2"`, and
//! its kind; a kind over a box of parameters lists leaves of one shape (`docs/MODEL.md`
//! section 11). The certificate of one wall ([`Certificate::to_json`]) holds the inputs as
//! hex floats (C99 `%a` form), the model, the coefficient enclosures and the reflection coefficients' enclosures
//! (midpoint and radius), the claim, and a CRC-32 of the text before it, which catches any
//! changed character (CRC-32 detects every error burst of up to 32 bits). The checker
//! `tools/verify_certificate.py` recomputes the enclosures with its own series in exact
//! rational arithmetic and replays the recursion.

mod circle;
mod delays;
mod device;
mod limit;
mod region;
mod set;
mod table;
pub(crate) mod tangent;

// the rigorous arithmetic (a module of its own, which alpha_max and the robust proofs use
// too), under the names the certificates' files read it by
pub(crate) use crate::enclosure::{interval, schur};

pub(crate) use device::{
    DeviceSpread, ElementSpread, Scalar, fraction_family, parameter_family, parts_over,
    parts_spread,
};
pub(crate) use device::{second_derivatives, second_order_family};

pub use delays::{DelayCertificate, DelayClaim, certify_delays};
pub use limit::{AMAX_LEAVES, AmaxCertificate, certify_alpha_max};
pub use region::{BEYOND, BoxCertificate, BoxClaim, LeafClaim, WallBox, certify_box};
pub use set::{
    SetAmaxCertificate, SetCertificate, SetClaim, certify_set, certify_set_alpha_max,
    certify_set_box,
};
pub use table::{CELL_BOXES_CAP, DEFAULT_CELL_BOXES, TableCertificate, certify_table};

use std::fmt::Write as _;

use crate::elements::{Encoder, Loop};
use crate::error::{Error, Result};
use crate::filter::FilterKind;
use crate::params::Wall;
use crate::stability::MIN_MARGIN;
use interval::{DiscretizationEnclosure, FractionSlopes, Interval};
use schur::{Recursion, recursion, scaled};

/// What a certificate proves about the exact model.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub enum Claim {
    /// Every root of `q` lies strictly inside the unit circle.
    Stable,
    /// `outside` roots of `q` lie strictly outside the unit circle, none on it.
    Unstable {
        /// How many roots lie outside the circle (at least 1).
        outside: usize,
    },
    /// Some root of `q` lies outside the unit circle: coefficient `power` of the monic `q`
    /// exceeds `binom(degree, power)` in modulus, which no polynomial with every root in the
    /// closed unit disc can (its coefficients are elementary symmetric functions of the
    /// roots). This decides huge walls, whose other roots may lie within rounding of the
    /// circle.
    UnstableByCoefficient {
        /// The power of `z` whose coefficient is too large.
        power: usize,
    },
    /// The spectral radius lies in `(1 - eps, 1 + eps)`.
    Marginal {
        /// The half-width of the band.
        eps: f64,
    },
}

/// One recursion of the certificate: on `q(z)`, `q((1 + eps) z)` or `q((1 - eps) z)`.
#[derive(Debug, Clone)]
struct Run {
    /// `"1"`, `"1+eps"` or `"1-eps"`: the radius the roots are compared with.
    radius: &'static str,
    recursion: Recursion,
}

/// A certified verdict for one wall of the paper's loop.
///
/// ```
/// use stabound::certificate::{Claim, certify};
/// use stabound::params::{Plant, Wall};
///
/// let plant = Plant::new(0.5, 1.0)?;
/// let cert = certify(&plant, &Wall::new(0.1, 0.3)?, 1e-9)?;
/// assert_eq!(cert.claim(), Claim::Stable);
/// let cert = certify(&plant, &Wall::new(5.0, 0.3)?, 1e-9)?;
/// assert!(matches!(cert.claim(), Claim::Unstable { .. }));
/// assert!(cert.to_json().contains("\"verdict\": \"unstable\""));
/// # Ok::<(), stabound::Error>(())
/// ```
#[derive(Debug, Clone)]
pub struct Certificate {
    lp: Loop,
    alpha: f64,
    beta: f64,
    delta: f64,
    d: f64,
    /// For a member of a set of devices whose masses differ: its masses (`lp` is in the
    /// set's reference normalization).
    masses: Option<Masses>,
    /// Midpoint and radius of each coefficient of `q`, lowest power first.
    coefficients: Vec<(f64, f64)>,
    runs: Vec<Run>,
    claim: Claim,
}

/// A member of a set of devices whose masses differ, stated in the set's reference
/// normalization (`docs/MODEL.md` section 11): the reference mass and the member's, in kg.
/// The member's own loop is the stated one with every value in units of the mass (the
/// wall, `delta`, the hand's and the transmission's) times `reference / mass`, exactly:
/// the same physical wall and device seen in the member's own normalization.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Masses {
    pub(crate) reference: f64,
    pub(crate) mass: f64,
}

impl Masses {
    /// The members `"mass"` and `"reference_mass"` of a certificate's inputs, after a
    /// comma; empty without masses.
    fn json(masses: Option<Masses>) -> String {
        masses.map_or_else(String::new, |m| {
            format!(
                ", \"mass\": \"{}\", \"reference_mass\": \"{}\"",
                hex(m.mass),
                hex(m.reference)
            )
        })
    }
}

/// The enclosed parts of `q = Q0 + alpha QA + beta QB` (`docs/MODEL.md` section 3), lowest
/// power first: each coefficient's `Q0` part and, where the wall enters it, its `QA` and `QB`
/// parts. They depend on the loop only, so a set of walls shares them.
#[derive(Debug, Clone)]
pub(crate) struct Parts(pub(crate) Vec<(Interval, Option<(Interval, Interval)>)>);

impl Parts {
    /// The parts of `lp`'s polynomial: the paper's loop by its closed forms (section 2), a
    /// loop with elements by its matrix exponential (section 8; the `device` module).
    fn of(lp: &Loop) -> Self {
        if lp.is_paper() {
            let plant = lp.plant();
            paper_parts(plant.delta(), plant.d())
        } else {
            device::parts(lp)
        }
    }

    /// The parts of the loop a certificate states as `lp` with `masses` (see [`Masses`]):
    /// every value in units of the mass times `s = reference / mass`, enclosed, and `QA`,
    /// `QB` times `s` (the wall is in the reference normalization); `lp`'s own without.
    fn of_member(lp: &Loop, masses: Option<Masses>) -> Self {
        let Some(m) = masses else {
            return Self::of(lp);
        };
        let s = Interval::point(m.reference) / Interval::point(m.mass);
        let parts = if lp.is_paper() {
            let plant = lp.plant();
            paper_parts_over(Interval::point(plant.delta()) * s, plant.d())
        } else {
            device::parts_scaled(lp, s)
        };
        Parts(
            parts
                .0
                .into_iter()
                .map(|(v, wall)| (v, wall.map(|(a, b)| (a * s, b * s))))
                .collect(),
        )
    }

    /// The enclosures of `q`'s coefficients for every wall with `alpha` in `a` and `beta` in
    /// `b`: each coefficient is affine in the wall and holds each of them once, so interval
    /// arithmetic encloses its range over the box.
    pub(crate) fn at(&self, a: Interval, b: Interval) -> Vec<Interval> {
        self.0
            .iter()
            .map(|&(v, wall)| match wall {
                Some((qa, qb)) => v + (a * qa + b * qb),
                None => v,
            })
            .collect()
    }

    /// Every enclosure widened on both sides by `rel` times its width (`rel` a power of
    /// two, so the product is exact; the sum is rounded outward). An enclosure over a range
    /// of loops (an interval of `delta`) overestimates the range by the wrapping of interval
    /// arithmetic, and a checker that encloses the same range by its own operations (another
    /// order of sums, other squarings of the exponential) wraps differently, by a small
    /// fraction of the width: a claim made on the widened enclosures is one such a checker
    /// can reproduce. Widening only loses, so whatever is proved on the widened enclosures
    /// holds on the enclosed ones.
    pub(crate) fn widened(&self, rel: f64) -> Self {
        let widen = |x: Interval| {
            let width = (Interval::point(x.hi()) - Interval::point(x.lo())).hi();
            x + Interval::symmetric(width * rel)
        };
        Parts(
            self.0
                .iter()
                .map(|&(v, wall)| (widen(v), wall.map(|(a, b)| (widen(a), widen(b)))))
                .collect(),
        )
    }
}

/// The parts of `q` for the paper's loop (`docs/MODEL.md` section 3): `QA = z M`,
/// `QB = (z - 1) M`, `Q0 = z^(n+2) (z - 1)(z - c)`, divided by `z` for an integer delay.
fn paper_parts(delta: f64, d: f64) -> Parts {
    paper_parts_over(Interval::point(delta), d)
}

/// The parts of `q` for the paper's loop at every `delta` in the nonnegative interval `dl`
/// (the delay `d` exact): enclosures that hold for each such `delta`.
pub(crate) fn paper_parts_over(dl: Interval, d: f64) -> Parts {
    let eps = d - d.floor();
    // exact test on purpose: any nonzero fraction raises the degree (as `Plant::degree`)
    paper_parts_of(
        DiscretizationEnclosure::over(dl, eps),
        d.floor() as usize,
        eps > 0.0,
    )
}

/// The parts of `q` for the paper's loop at every `delta` in the nonnegative interval `dl`
/// and every delay `n + eps` with `eps` in `e`, a sub-interval of `[0, 1]`, all in the
/// fractional form (degree `n + 4`). At `eps = 0` that form is `z` times the integer
/// delay's polynomial (`phi1(0) = phi2(0) = 0` empty the oldest force's column), a root at
/// the origin more; at `eps = 1` it is the polynomial of the delay `n + 1`. So one family
/// covers every delay of `[n, n + 1]` with the same stability.
pub(crate) fn paper_parts_fractions(dl: Interval, n: usize, e: Interval) -> Parts {
    paper_parts_of(DiscretizationEnclosure::over_fractions(dl, e), n, true)
}

/// The paper loop's polynomial over a cell of fractions in centred form: for every `delta`
/// of the cell and every fraction `eps` in it, each coefficient of `q` lies in
/// `centre_i + slope_i (eps - e_c)`, `eps - e_c` in `offset`.
///
/// # Method
///
/// The mean-value theorem (the centred form of interval analysis: Moore, Kearfott and Cloud,
/// "Introduction to Interval Analysis", SIAM 2009, section 6.4): each coefficient `q_i` is a
/// smooth function of `eps`, so `q_i(eps) = q_i(e_c) + q_i'(xi) (eps - e_c)` for some `xi`
/// between `e_c` and `eps`, and `q_i'(xi)` lies in the enclosure of the derivative over the
/// whole cell. `centre` encloses the coefficients at the one fraction `e_c` (exact, so `eps`
/// and `1 - eps` are no longer two independent intervals), `slope` the derivatives
/// ([`FractionSlopes`]) over the cell. The overestimation of `centre + slope offset` over the
/// coefficients' true range is second order in the cell's width, where the direct enclosure's
/// ([`paper_parts_fractions`]) is first order.
#[derive(Debug, Clone)]
pub(crate) struct FractionFamily {
    /// The coefficients' enclosures at the centre fraction `e_c`, lowest power first.
    pub(crate) centre: Vec<Interval>,
    /// The enclosures of the coefficients' derivatives in the fraction over the cell.
    pub(crate) slope: Vec<Interval>,
    /// `[e0 - e_c, e1 - e_c]`, rounded outward.
    pub(crate) offset: Interval,
}

/// The centred form ([`FractionFamily`]) of the paper loop's polynomial under the wall
/// `(alpha, beta)` for every `delta` in `dl` and every delay `n + eps`, `eps` in `e` (a
/// sub-interval of `[0, 1]`), all in the fractional form as [`paper_parts_fractions`].
///
/// The derivatives: `Q0` does not depend on `eps`; with `u = 1 - eps`, `M2 = G0x`,
/// `M1 = phi1(1) G0v - c G0x + G1x` and `M0 = phi1(1) G1v - c G1x` have the derivatives
/// `-phi1(u)`, `(1 + c) phi1(u) - phi1(1) c(u)` and `phi1(1) c(u) - c phi1(u)`
/// ([`FractionSlopes`]).
pub(crate) fn paper_fraction_family(
    dl: Interval,
    n: usize,
    e: Interval,
    alpha: Interval,
    beta: Interval,
) -> FractionFamily {
    let mid = 0.5 * e.lo() + 0.5 * e.hi();
    let centre = paper_parts_fractions(dl, n, Interval::point(mid)).at(alpha, beta);
    let s = FractionSlopes::over(dl, e);
    let one = Interval::point(1.0);
    let m2 = -s.p1u;
    let m1 = (one + s.c) * s.p1u - s.p1 * s.cu;
    let m0 = s.p1 * s.cu - s.c * s.p1u;
    let zero = Interval::point(0.0);
    let (qa, qb) = fractional_wall([m0, m1, m2]);
    let slope = assemble([zero; 3], qa, qb, n + 2).at(alpha, beta);
    FractionFamily {
        centre,
        slope,
        offset: e - Interval::point(mid),
    }
}

/// The `QA` and `QB` parts of the fractional form's four lowest coefficients from `M0`,
/// `M1`, `M2` (`docs/MODEL.md` section 3: `QA = z M`, `QB = (z - 1) M`).
fn fractional_wall([m0, m1, m2]: [Interval; 3]) -> ([Interval; 4], [Interval; 4]) {
    let zero = Interval::point(0.0);
    ([zero, m0, m1, m2], [-m0, m0 - m1, m1 - m2, m2])
}

/// The parts of `q` from the enclosed discretization `e` with `n` whole samples of delay,
/// in the fractional form or the integer one.
fn paper_parts_of(e: DiscretizationEnclosure, n: usize, fractional: bool) -> Parts {
    let zero = Interval::point(0.0);
    let m2 = e.g0x;
    let m1 = e.p1 * e.g0v - e.c * e.g0x + e.g1x;
    let (qa, qb, low) = if fractional {
        let m0 = e.p1 * e.g1v - e.c * e.g1x;
        let (qa, qb) = fractional_wall([m0, m1, m2]);
        (qa, qb, n + 2)
    } else {
        ([zero, m1, m2, zero], [-m1, m1 - m2, m2, zero], n + 1)
    };
    let one = Interval::point(1.0);
    assemble([e.c, -(one + e.c), one], qa, qb, low)
}

/// The parts of `q = z^low q0(z) + alpha QA + beta QB`, `q0` of degree 2 and `QA`, `QB` of
/// degree 3, lowest power first.
fn assemble(q0: [Interval; 3], qa: [Interval; 4], qb: [Interval; 4], low: usize) -> Parts {
    let zero = Interval::point(0.0);
    Parts(
        (0..=low + 2)
            .map(|i| {
                let v = match i.checked_sub(low) {
                    Some(k) => q0[k],
                    None => zero,
                };
                (v, (i < 4).then(|| (qa[i], qb[i])))
            })
            .collect(),
    )
}

/// An enclosure as (midpoint, radius).
type Ball = (f64, f64);

/// The coefficients' enclosures as balls (midpoint, radius) and as the intervals those
/// balls are, or `None` when one overflows.
fn balls(enclosed: Vec<Interval>) -> Option<(Vec<Ball>, Vec<Interval>)> {
    let balls = enclosed
        .into_iter()
        .map(Interval::ball)
        .collect::<Option<Vec<_>>>()?;
    let q = balls
        .iter()
        .map(|&(m, r)| Interval::from_ball(m, r))
        .collect();
    Some((balls, q))
}

/// Certifies the verdict of `wall` on the loop `lp` (`docs/MODEL.md` section 11): stable,
/// unstable with the count of roots outside, or marginal within `margin`.
///
/// The paper's loop is enclosed by its closed forms (section 2); a loop with elements by
/// its matrix exponential with a rigorous remainder (section 8; the `device` module).
///
/// ```
/// use stabound::certificate::{Claim, certify};
/// use stabound::elements::{Hand, Loop};
/// use stabound::filter::VelocityFilter;
/// use stabound::params::{Plant, Wall};
///
/// let lp = Loop::new(Plant::new(0.5, 1.5)?)
///     .with_hand(Hand::new(0.2, 0.1, 0.01)?)?
///     .with_filter(VelocityFilter::low_pass(0.8)?)?;
/// let cert = certify(lp, &Wall::new(0.05, 0.2)?, 1e-9)?;
/// assert_eq!(cert.claim(), Claim::Stable);
/// assert!(cert.to_json().contains("\"pole\": \"0x1.999999999999ap-1\""));
/// # Ok::<(), stabound::Error>(())
/// ```
///
/// # Errors
///
/// [`Error::InvalidParameter`] for a margin outside `[MIN_MARGIN, 0.5)`;
/// [`Error::Numerical`] when `f64` interval arithmetic decides none of the three claims
/// (the spectral radius is too close to `1 +- margin`, or the coefficients overflow).
pub fn certify(lp: impl Into<Loop>, wall: &Wall, margin: f64) -> Result<Certificate> {
    certify_member(lp.into(), None, wall, margin)
}

/// [`certify`] on the loop stated as `lp` with `masses` (a member of a set of devices whose
/// masses differ, see [`Masses`]).
pub(crate) fn certify_member(
    lp: Loop,
    masses: Option<Masses>,
    wall: &Wall,
    margin: f64,
) -> Result<Certificate> {
    if !(MIN_MARGIN..0.5).contains(&margin) {
        return Err(Error::InvalidParameter {
            name: "margin",
            value: margin,
            expected: format!("a certificate's band is in [{MIN_MARGIN:e}, 0.5)"),
        });
    }
    let plant = lp.plant();
    let (alpha, beta, delta, d) = (wall.alpha(), wall.beta(), plant.delta(), plant.d());
    let undecided = |why: &str| {
        Error::Numerical(format!(
            "the verdict could not be certified in double-precision interval arithmetic: {why}; a wider marginal band may certify it as marginal"
        ))
    };
    let enclosed = Parts::of_member(&lp, masses).at(Interval::point(alpha), Interval::point(beta));
    let (balls, q) =
        balls(enclosed).ok_or_else(|| undecided("a coefficient's enclosure overflows"))?;
    let at_one = recursion(&q);
    let (runs, claim) = match at_one.outside {
        Some(0) => (vec![run("1", at_one)], Claim::Stable),
        Some(outside) => (vec![run("1", at_one)], Claim::Unstable { outside }),
        None => {
            if let Some(power) = coefficient_bound(&q) {
                return Ok(Certificate {
                    lp,
                    alpha,
                    beta,
                    delta,
                    d,
                    masses,
                    coefficients: balls,
                    runs: Vec::new(),
                    claim: Claim::UnstableByCoefficient { power },
                });
            }
            let one = Interval::point(1.0);
            let eps = Interval::point(margin);
            let above = recursion(&scaled(&q, one + eps));
            let below = recursion(&scaled(&q, one - eps));
            if above.outside != Some(0) || below.outside.is_none_or(|k| k < 1) {
                let n = q.len() - 1;
                let step = n + 1 - at_one.reflections.len();
                return Err(undecided(&format!(
                    "the Schur-Cohn recursion stopped at degree {step} of {n}: either the spectral radius is too close to the edges of the marginal band, or the enclosures widened too much on the way (polynomials of degree above about 40, i.e. delays above about 35 samples, or lightly damped elements with roots near the unit circle); there is no higher precision to fall back on"
                )));
            }
            (
                vec![run("1+eps", above), run("1-eps", below)],
                Claim::Marginal { eps: margin },
            )
        }
    };
    Ok(Certificate {
        lp,
        alpha,
        beta,
        delta,
        d,
        masses,
        coefficients: balls,
        runs,
        claim,
    })
}

/// The lowest power `k` whose coefficient exceeds `binom(n, k)` in modulus for every value of
/// its enclosure (see [`Claim::UnstableByCoefficient`]), the binomials enclosed too.
fn coefficient_bound(q: &[Interval]) -> Option<usize> {
    let n = q.len() - 1;
    let mut binom = Interval::point(1.0);
    for (k, c) in q.iter().enumerate() {
        if k > 0 {
            binom = binom * Interval::point((n - k + 1) as f64) / Interval::point(k as f64);
        }
        if c.mig() > binom.mag() {
            return Some(k);
        }
    }
    None
}

fn run(radius: &'static str, recursion: Recursion) -> Run {
    Run { radius, recursion }
}

/// `x` in C99 `%a` form as glibc prints it, trailing zeros of the fraction dropped:
/// `0x1.8p-1`, `-0x1p+0`, `0x0p+0`, subnormals as `0x0.0000000000001p-1022`.
fn hex(x: f64) -> String {
    let bits = x.to_bits();
    let sign = if bits >> 63 == 1 { "-" } else { "" };
    let field = ((bits >> 52) & 0x7ff) as i32;
    let mant = bits & ((1u64 << 52) - 1);
    if field == 0 && mant == 0 {
        return format!("{sign}0x0p+0");
    }
    let (lead, exp) = if field == 0 {
        (0, -1022)
    } else {
        (1, field - 1023)
    };
    let frac = format!("{mant:013x}");
    let frac = frac.trim_end_matches('0');
    let dot = if frac.is_empty() { "" } else { "." };
    format!("{sign}0x{lead}{dot}{frac}p{exp:+}")
}

/// The elements of `lp` as certificate inputs: (name, JSON object), in the order hand,
/// transmission, actuator, filter; empty for the paper's loop. Normalized values
/// (`docs/MODEL.md` section 8) as hex floats; the second-order filter by its stored
/// coefficients, which are the filter the loop runs.
fn element_inputs(lp: &Loop) -> Vec<(&'static str, String)> {
    let mut out = Vec::new();
    if lp.is_paper() {
        return out;
    }
    let list = |v: &[f64]| {
        let items: Vec<String> = v.iter().map(|&x| format!("\"{}\"", hex(x))).collect();
        format!("[{}]", items.join(", "))
    };
    if let Some(h) = lp.hand() {
        out.push((
            "hand",
            format!(
                "{{\"mu_h\": \"{}\", \"delta_h\": \"{}\", \"kappa_h\": \"{}\"}}",
                hex(h.mass_ratio()),
                hex(h.damping()),
                hex(h.stiffness())
            ),
        ));
    }
    if let Some(t) = lp.transmission() {
        let encoder = match t.encoder() {
            Encoder::Handle => "handle",
            _ => "motor",
        };
        out.push((
            "transmission",
            format!(
                "{{\"r\": \"{}\", \"kappa_c\": \"{}\", \"delta_c\": \"{}\", \"delta_2\": \"{}\", \"encoder\": \"{encoder}\"}}",
                hex(t.handle_ratio()),
                hex(t.stiffness()),
                hex(t.damping()),
                hex(t.handle_damping())
            ),
        ));
    }
    if let Some(a) = lp.actuator() {
        out.push(("actuator", format!("{{\"tau\": \"{}\"}}", hex(a.tau()))));
    }
    let f = lp.filter();
    if !f.is_identity() {
        let text = match f.kind() {
            FilterKind::LowPass { pole } => format!("{{\"pole\": \"{}\"}}", hex(pole)),
            FilterKind::MovingAverage { samples } => format!("{{\"samples\": {samples}}}"),
            _ => format!(
                "{{\"numerator\": {}, \"denominator\": {}}}",
                list(&f.numerator()),
                list(&f.denominator())
            ),
        };
        out.push(("filter", text));
    }
    out
}

/// CRC-32 (IEEE 802.3, as zlib's `crc32`) of `bytes`.
fn crc32(bytes: &[u8]) -> u32 {
    let mut h = crc32fast::Hasher::new();
    h.update(bytes);
    h.finalize()
}

fn ball_json(out: &mut String, (mid, rad): (f64, f64)) {
    let _ = write!(
        out,
        "{{\"mid\": \"{}\", \"rad\": \"{}\"}}",
        hex(mid),
        hex(rad)
    );
}

/// The reflection coefficients' enclosures as balls (an unbounded one, which no decided step
/// has, as the whole `f64` range).
fn reflection_balls(rec: &Recursion) -> Vec<(f64, f64)> {
    rec.reflections
        .iter()
        .map(|r| r.ball().unwrap_or((0.0, f64::MAX)))
        .collect()
}

fn list_json(out: &mut String, indent: &str, items: &[(f64, f64)]) {
    out.push('[');
    for (i, &b) in items.iter().enumerate() {
        out.push_str(if i == 0 { "\n" } else { ",\n" });
        out.push_str(indent);
        ball_json(out, b);
    }
    out.push(']');
}

/// The ends of the arcs of a set decided around its centre, as the member `"arcs"` (hex
/// floats) after a comma.
fn arcs_json(out: &mut String, arcs: &[f64]) {
    let ends: Vec<String> = arcs.iter().map(|&u| format!("\"{}\"", hex(u))).collect();
    let _ = write!(out, ",\n     \"arcs\": [{}]", ends.join(", "));
}

/// The opening of any certificate's JSON: the format and its version ([`FORMAT`]) and the
/// kind of certificate.
fn opening(kind: &str) -> String {
    format!("{{\n  \"certificate\": \"{FORMAT}\",\n  \"kind\": \"{kind}\",\n")
}

/// The format and version every certificate names: one general format (`docs/MODEL.md`
/// section 11), whose earlier version the checker no longer reads.
const FORMAT: &str = "stabound certificate 2";

/// The opening of a certificate's JSON: its format and kind, the model, and the elements of
/// `lp` as certificate inputs (see [`element_inputs`]).
fn head(kind: &str, lp: &Loop) -> (String, Vec<(&'static str, String)>) {
    let mut s = opening(kind);
    let elements = element_inputs(lp);
    let _ = writeln!(s, "  {},", model_json(&elements));
    (s, elements)
}

/// The member `"model"` of a loop with the elements `elements` (certificate inputs, see
/// [`element_inputs`]): the loop's kind, its elements' names and its polynomial.
fn model_json(elements: &[(&'static str, String)]) -> String {
    if elements.is_empty() {
        return "\"model\": {\"loop\": \"paper\", \"elements\": [], \"polynomial\": \"q(z) = z^(n+2) (z - 1)(z - c) + ((alpha + beta) z - beta) (N0(z) z + N1(z)), divided by z for integer d (docs/MODEL.md sections 2-3)\"}".into();
    }
    let names: Vec<String> = elements.iter().map(|(k, _)| format!("\"{k}\"")).collect();
    format!(
        "\"model\": {{\"loop\": \"elements\", \"elements\": [{}], \"polynomial\": \"q(z) = z^(n+2) D(z) Fd(z) + N(z) (alpha z Fd(z) + beta (z - 1) Fn(z)), D = det(z I - Phi), N = c^T adj(z I - Phi) (G0 z + G1), the common powers of z divided out (docs/MODEL.md section 8)\"}}",
        names.join(", ")
    )
}

/// A certificate's JSON as a member of another: without its CRC (the outer one covers it),
/// indented one level.
fn nested(json: &str) -> String {
    let body = json.rfind(",\n  \"crc32\"").map_or(json, |i| &json[..i]);
    format!("{}\n  }}", body.replace('\n', "\n  "))
}

/// Closes a certificate's JSON with the CRC-32 of the text before it.
fn seal(mut s: String) -> String {
    let crc = crc32(s.as_bytes());
    let _ = write!(s, "  \"crc32\": \"{crc:08x}\"\n}}\n");
    s
}

impl Certificate {
    /// What the certificate proves.
    pub fn claim(&self) -> Claim {
        self.claim
    }

    /// Degree of the characteristic polynomial.
    pub fn degree(&self) -> usize {
        self.coefficients.len() - 1
    }

    /// The certificate as JSON text (see the module documentation), ending in a newline.
    pub fn to_json(&self) -> String {
        let (mut s, elements) = head("stability", &self.lp);
        let _ = write!(
            s,
            "  \"inputs\": {{\"alpha\": \"{}\", \"beta\": \"{}\", \"delta\": \"{}\", \"d\": \"{}\"",
            hex(self.alpha),
            hex(self.beta),
            hex(self.delta),
            hex(self.d)
        );
        s.push_str(&Masses::json(self.masses));
        for (k, v) in &elements {
            let _ = write!(s, ", \"{k}\": {v}");
        }
        s.push_str("},\n");
        let _ = writeln!(s, "  \"degree\": {},", self.degree());
        s.push_str("  \"coefficients\": ");
        list_json(&mut s, "    ", &self.coefficients);
        s.push_str(",\n  \"recursions\": [");
        for (i, run) in self.runs.iter().enumerate() {
            s.push_str(if i == 0 { "\n" } else { ",\n" });
            let outside = run.recursion.outside.unwrap_or(0);
            let _ = write!(
                s,
                "    {{\"radius\": \"{}\", \"outside\": {outside}, \"reflections\": ",
                run.radius
            );
            list_json(&mut s, "      ", &reflection_balls(&run.recursion));
            s.push('}');
        }
        s.push_str("],\n  \"claim\": ");
        match self.claim {
            Claim::Stable => s.push_str("{\"verdict\": \"stable\"}"),
            Claim::Unstable { outside } => {
                let _ = write!(s, "{{\"verdict\": \"unstable\", \"outside\": {outside}}}");
            }
            Claim::UnstableByCoefficient { power } => {
                let _ = write!(
                    s,
                    "{{\"verdict\": \"unstable\", \"coefficient_above_binomial\": {power}}}"
                );
            }
            Claim::Marginal { eps } => {
                let _ = write!(
                    s,
                    "{{\"verdict\": \"marginal\", \"eps\": \"{}\"}}",
                    hex(eps)
                );
            }
        }
        s.push_str(",\n");
        seal(s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hex_floats_in_c99_form() {
        assert_eq!(hex(1.0), "0x1p+0");
        assert_eq!(hex(-1.5), "-0x1.8p+0");
        assert_eq!(hex(0.1), "0x1.999999999999ap-4");
        assert_eq!(hex(0.0), "0x0p+0");
        assert_eq!(hex(-0.0), "-0x0p+0");
        assert_eq!(hex(f64::from_bits(1)), "0x0.0000000000001p-1022");
        assert_eq!(hex(f64::MAX), "0x1.fffffffffffffp+1023");
    }

    /// zlib's check value of the CRC-32 (the CRC of "123456789").
    #[test]
    fn crc_is_zlibs() {
        assert_eq!(crc32(b"123456789"), 0xcbf4_3926);
    }
}
