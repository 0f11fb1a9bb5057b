//! A certified enclosure of `alpha_max` (`docs/MODEL.md` sections 5 and 11): a wall below it
//! certified stable, and above it a proof that no wall of the searched dampings is stable at
//! `alpha_hi` or any stiffer: a cap beyond which a linear necessary condition of Schur
//! stability fails for every damping of the range, and a box certificate that no wall between
//! `alpha_hi` and the cap is stable. Where the box's budget does not suffice, the proof is
//! the weaker one for the stiffness `alpha_hi` alone (a strip of one stiffness).
//!
//! # The cap
//!
//! `q = Q0 + alpha QA + beta QB` is monic of degree `m` (the top coefficient is `Q0`'s, 1).
//! A monic polynomial with every root inside the unit circle has `(-1)^m q(-1) = prod (1 +
//! r_i) > 0` and `|a_k| = |e_(m-k)(r)| < C(m, k)` (Jury's necessary conditions and the
//! elementary symmetric functions' bound). Each is `L(q) < c` for a linear form `L` (weights
//! in `{-1, 0, 1}`) and a constant `c`, so `L(q) = L(Q0) + alpha L(QA) + beta L(QB)` is
//! affine in the wall. When `L(QA) > 0` and `L(q) >= c` at `alpha_cap` for every `beta` of
//! the range (an interval of `beta`), it holds for every larger `alpha` too: no wall from
//! `alpha_cap` on is stable.

use std::fmt::Write as _;

use super::interval::Interval;
use super::region::{BoxCertificate, BoxClaim, WallBox, bisect};
use super::{Certificate, Claim, Masses, Parts, certify_member, hex, nested, seal};
use crate::amax::Amax;
use crate::elements::Loop;
use crate::error::{Error, Result};
use crate::params::Wall;
use crate::stability::DEFAULT_MARGIN;

/// The leaves the box above `alpha_max` (from `alpha_hi` to the cap) may be halved into, as
/// the command line and Python certify it: the paper's loop at `delta = 0.5`, `d = 1` or
/// `2.5` needs 8,512 to 13,636 leaves for the box; where this does not suffice, each strip
/// at `alpha_hi` alone is tried.
pub const AMAX_LEAVES: usize = 16384;

/// Relative steps below `alpha_max` tried for the stable wall, nearest first.
const BELOW: [f64; 3] = [1e-9, 1e-6, 1e-3];
/// Relative steps above `alpha_max` tried for the unstable strip, nearest first: the strip
/// passes close to the boundary near the optimal damping, where nearer strips need more
/// leaves.
pub(crate) const ABOVE: [f64; 4] = [1e-4, 1e-3, 1e-2, 1e-1];

/// A certified enclosure `[alpha_lo, alpha_hi]` of `alpha_max`: the wall `(alpha_lo,
/// beta_at_max)` is stable, and no wall `(alpha, beta)` with `alpha >= alpha_hi` and `beta`
/// in the searched range is stable ([`AmaxCertificate::every_stiffer_wall`]; where the budget
/// did not prove that, only every wall `(alpha_hi, beta)` is proved unstable).
///
/// ```
/// use stabound::certificate::{AMAX_LEAVES, certify_alpha_max};
/// use stabound::params::Plant;
/// use stabound::{AmaxOptions, alpha_max};
///
/// let plant = Plant::new(0.5, 1.0)?;
/// let amax = alpha_max(&plant, &AmaxOptions::default())?;
/// let cert = certify_alpha_max(&plant, &amax, (0.0, 1.0), AMAX_LEAVES)?;
/// let (lo, hi) = cert.bounds();
/// assert!(lo <= amax.alpha_max && amax.alpha_max < hi);
/// assert!(cert.every_stiffer_wall());
/// # Ok::<(), stabound::Error>(())
/// ```
#[derive(Debug, Clone)]
pub struct AmaxCertificate {
    below: Certificate,
    above: BoxCertificate,
    cap: Option<Cap>,
}

/// A necessary condition of Schur stability, `L(q) < c` (see the module documentation).
#[derive(Debug, Clone, Copy, PartialEq)]
enum Rule {
    /// `(-1)^m q(-1) > 0`: `L` has the weights `-(-1)^(m + k)`, `c = 0`.
    MinusOne,
    /// `sign a_k < C(m, k)`.
    Coefficient { k: usize, sign: i8 },
}

impl Rule {
    /// The weights of `L` on the coefficients (lowest power first) and the constant `c`, or
    /// `None` when `C(m, k)` is not an integer `f64` holds exactly.
    fn form(self, m: usize) -> Option<(Vec<f64>, f64)> {
        match self {
            Rule::MinusOne => {
                let w = (0..=m)
                    .map(|k| if (m + k).is_multiple_of(2) { -1.0 } else { 1.0 })
                    .collect();
                Some((w, 0.0))
            }
            Rule::Coefficient { k, sign } => {
                let mut w = vec![0.0; m + 1];
                w[k] = f64::from(sign);
                Some((w, binomial(m, k)?))
            }
        }
    }
}

/// `C(m, k)` when it is at most `2^53` (so exact as an `f64`), else `None`.
fn binomial(m: usize, k: usize) -> Option<f64> {
    let k = k.min(m - k) as u64;
    let mut c: u64 = 1;
    for i in 0..k {
        // exact: C(m, i) (m - i) / (i + 1) = C(m, i + 1), an integer
        c = c.checked_mul(m as u64 - i)? / (i + 1);
    }
    (c <= 1 << 53).then_some(c as f64)
}

/// The stiffness from which a [`Rule`] fails for every damping of the range.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Cap {
    alpha: f64,
    rule: Rule,
}

/// The smallest cap any rule proves for the dampings `betas` on the parts of a monic `q`,
/// or `None` (`q` not monic in the enclosures, or no rule's form grows with `alpha`).
fn cap(parts: &Parts, betas: (f64, f64)) -> Option<Cap> {
    let m = parts.0.len().checked_sub(1)?;
    // q is monic by construction (`z^(n+2) D(z) Fd(z)` leads, `D` and `Fd` monic); the
    // enclosures of a loop with elements may hold it only within their widths, and the
    // checker verifies it exactly
    let (top, wall) = parts.0[m];
    let holds = |x: Interval, v: f64| x.lo() <= v && v <= x.hi();
    let zero = |x: Interval| holds(x, 0.0);
    if !holds(top, 1.0) || wall.is_some_and(|(a, b)| !(zero(a) && zero(b))) {
        return None;
    }
    let beta = Interval::new(betas.0, betas.1);
    let rules = std::iter::once(Rule::MinusOne)
        .chain((0..m).flat_map(|k| [1, -1].map(|sign| Rule::Coefficient { k, sign })));
    rules
        .filter_map(|rule| {
            let (w, c) = rule.form(m)?;
            let (mut l0, mut la, mut lb) = (
                Interval::point(0.0),
                Interval::point(0.0),
                Interval::point(0.0),
            );
            for (&wk, &(v, wall)) in w.iter().zip(&parts.0) {
                if wk == 0.0 {
                    continue;
                }
                let wk = Interval::point(wk);
                l0 = l0 + wk * v;
                if let Some((a, b)) = wall {
                    la = la + wk * a;
                    lb = lb + wk * b;
                }
            }
            // (a NaN end gives a NaN cap, refused below as not finite)
            if la.lo() <= 0.0 {
                return None;
            }
            let c = Interval::point(c);
            let at = |b: f64| ((c - l0 - Interval::point(b) * lb) / la).hi();
            // 1e-9 above the solution: far above the enclosures' relative width (near
            // 1e-12 with elements), so the check over the interval of beta holds
            let alpha = at(betas.0).max(at(betas.1)).max(f64::MIN_POSITIVE) * (1.0 + 1e-9);
            let holds = (l0 + Interval::point(alpha) * la + beta * lb).lo() >= c.hi();
            (alpha.is_finite() && holds).then_some(Cap { alpha, rule })
        })
        .min_by(|x, y| x.alpha.total_cmp(&y.alpha))
}

/// Certifies an enclosure of `amax` (from [`crate::alpha_max`] on `lp`) for the dampings
/// `betas = (lo, hi)`: the nearest stable wall below it, and the nearest `alpha_hi` above it
/// from which the certificates prove that no wall up to the cap is stable (the box halved
/// into at most `max_leaves` leaves); failing that within the budget, the nearest unstable
/// strip at `alpha_hi` alone (also at most `max_leaves` leaves).
///
/// # Errors
///
/// [`Error::InvalidParameter`] for a damping range that is not finite and ordered or does not
/// hold the optimum's damping; [`Error::Numerical`] when no stable wall within 0.1 % below
/// or no unstable strip within 10 % above is proved.
pub fn certify_alpha_max(
    lp: impl Into<Loop>,
    amax: &Amax,
    betas: (f64, f64),
    max_leaves: usize,
) -> Result<AmaxCertificate> {
    let lp: Loop = lp.into();
    let (a, b) = (amax.alpha_max, amax.beta_at_max);
    holds_optimum(betas, b)?;
    let below = stable_below(&[(lp, None)], a, b)?.remove(0);
    above(lp, below, a, betas, max_leaves)?.ok_or_else(|| {
        Error::Numerical(format!(
            "no stiffness within 10 % above alpha_max is certified unstable for every damping in [{}, {}] within {max_leaves} leaves; a larger budget may prove it",
            betas.0, betas.1
        ))
    })
}

/// One certificate for several enclosures (the rows of a grid), each given as its own
/// certificate's JSON: the rows without their CRCs, in order, the count of rows as the claim,
/// and a CRC-32 of the text before it.
pub(crate) fn grid_json(rows: Vec<String>) -> String {
    let mut s = super::opening("alpha_max grid");
    s.push_str("  \"rows\": [");
    for (i, row) in rows.iter().enumerate() {
        s.push_str(if i == 0 { "\n    " } else { ",\n    " });
        s.push_str(&nested(row).replace('\n', "\n  "));
    }
    let _ = writeln!(s, "],\n  \"claim\": {{\"rows\": {}}},", rows.len());
    seal(s)
}

/// Refuses a damping range `betas` that does not hold the optimum's damping `beta`.
pub(crate) fn holds_optimum(betas: (f64, f64), beta: f64) -> Result<()> {
    if betas.0 <= beta && beta <= betas.1 {
        return Ok(());
    }
    Err(Error::InvalidParameter {
        name: "beta range",
        value: beta,
        expected: format!(
            "the searched dampings [{}, {}] hold the optimum's damping",
            betas.0, betas.1
        ),
    })
}

/// The certificates of the nearest wall below `alpha` at the damping `beta` ([`BELOW`])
/// that is certified stable on every loop of `loops` (one per loop, in order).
///
/// # Errors
///
/// [`Error::Numerical`] when no wall within 0.1 % below is certified stable on every loop.
pub(crate) fn stable_below(
    loops: &[(Loop, Option<Masses>)],
    alpha: f64,
    beta: f64,
) -> Result<Vec<Certificate>> {
    // the farthest try's outcome says why none was certified stable
    let mut why = String::new();
    for r in BELOW {
        let wall = Wall::new(alpha * (1.0 - r), beta)?;
        let mut certs = Vec::with_capacity(loops.len());
        for &(lp, masses) in loops {
            match certify_member(lp, masses, &wall, DEFAULT_MARGIN) {
                Ok(c) if c.claim() == Claim::Stable => certs.push(c),
                Ok(c) => {
                    why = match c.claim() {
                        Claim::Marginal { .. } => "certified marginal".into(),
                        _ => "certified unstable: the stable set at the optimum's damping does not reach up to it".into(),
                    };
                    break;
                }
                Err(e) => {
                    why = e.to_string();
                    break;
                }
            }
        }
        if certs.len() == loops.len() {
            return Ok(certs);
        }
    }
    Err(Error::Numerical(format!(
        "no wall within 0.1 % below alpha_max is certified stable (at 0.1 % below: {why})"
    )))
}

/// The enclosure with the stable wall `below` under `alpha` on `lp`: the nearest stiffness
/// above `alpha` ([`ABOVE`]) from which no wall with a damping of `betas` is stable up to the
/// cap, or failing that the nearest strip at that stiffness proved unstable; `None` when
/// neither is proved within `max_leaves` leaves.
pub(crate) fn above(
    lp: Loop,
    below: Certificate,
    alpha: f64,
    betas: (f64, f64),
    max_leaves: usize,
) -> Result<Option<AmaxCertificate>> {
    for capped in [true, false] {
        for r in ABOVE {
            if let Some((above, cap)) =
                unstable_at((lp, None), alpha * (1.0 + r), betas, capped, max_leaves)?
            {
                return Ok(Some(AmaxCertificate { below, above, cap }));
            }
        }
    }
    Ok(None)
}

/// The proof on `lp` that no wall with a damping of `betas` is stable at the stiffness `hi`:
/// when `capped`, at `hi` or stiffer (the box from `hi` up to the cap proved not stable, and
/// the cap's rule), else at `hi` alone (the strip proved unstable); `None` when not proved
/// within `max_leaves` leaves (or, when `capped`, no rule gives a cap). `lp` is stated with
/// its masses (a member of a set of devices whose masses differ, see [`Masses`]).
pub(crate) fn unstable_at(
    (lp, masses): (Loop, Option<Masses>),
    hi: f64,
    betas: (f64, f64),
    capped: bool,
    max_leaves: usize,
) -> Result<Option<(BoxCertificate, Option<Cap>)>> {
    if !capped {
        let strip = WallBox::new(Wall::new(hi, betas.0)?, Wall::new(hi, betas.1)?)?;
        let above = bisect((lp, masses), &strip, max_leaves, false)?;
        return Ok((above.claim() == BoxClaim::Unstable).then_some((above, None)));
    }
    let Some(cap) = cap(&Parts::of_member(&lp, masses), betas) else {
        return Ok(None);
    };
    let walls = WallBox::new(
        Wall::new(hi, betas.0)?,
        Wall::new(hi.max(cap.alpha), betas.1)?,
    )?;
    let above = bisect((lp, masses), &walls, max_leaves, true)?;
    let proved = matches!(above.claim(), BoxClaim::Unstable | BoxClaim::NotStable);
    Ok(proved.then_some((above, Some(cap))))
}

/// A cap as the certificate's member `"cap"` holds it: its stiffness and its rule.
pub(crate) fn cap_json(cap: &Cap) -> String {
    let rule = match cap.rule {
        Rule::MinusOne => "\"rule\": \"q(-1)\"".to_string(),
        Rule::Coefficient { k, sign } => {
            format!("\"rule\": \"coefficient\", \"k\": {k}, \"sign\": {sign}")
        }
    };
    format!("{{\"alpha\": \"{}\", {rule}}}", hex(cap.alpha))
}

impl AmaxCertificate {
    /// The enclosure of the stable wall `below` and the box `above` (with the cap `cap`).
    pub(crate) fn new(below: Certificate, above: BoxCertificate, cap: Option<Cap>) -> Self {
        AmaxCertificate { below, above, cap }
    }

    /// The enclosure `(alpha_lo, alpha_hi)`.
    pub fn bounds(&self) -> (f64, f64) {
        (self.below.alpha, self.above.walls().alpha().0)
    }

    /// Whether the certificate proves that no wall from `alpha_hi` on (with a damping of the
    /// range) is stable; otherwise it proves that every wall at `alpha_hi` is unstable.
    pub fn every_stiffer_wall(&self) -> bool {
        self.cap.is_some()
    }

    /// The stiffness from which a linear necessary condition of stability fails for every
    /// damping of the range, when [`AmaxCertificate::every_stiffer_wall`] holds: the box of
    /// walls proved not stable runs from `alpha_hi` up to it (or is the strip at `alpha_hi`
    /// when the cap lies below).
    pub fn cap(&self) -> Option<f64> {
        self.cap.map(|c| c.alpha)
    }

    /// The damping of the wall certified stable at `alpha_lo`.
    pub fn beta_below(&self) -> f64 {
        self.below.beta
    }

    /// The dampings `(lo, hi)` of the strip certified unstable at `alpha_hi`.
    pub fn dampings(&self) -> (f64, f64) {
        self.above.walls().beta()
    }

    /// One certificate for several enclosures (the rows of a grid of devices), as JSON
    /// text: each row's certificate as [`AmaxCertificate::to_json`] writes it (without its
    /// CRC), in order, the count of rows as the claim, and a CRC-32 of the text before it.
    /// The checker replays every row. A single row is its own certificate
    /// ([`AmaxCertificate::to_json`]), as a grid of one row is written.
    ///
    /// ```
    /// use stabound::certificate::{AmaxCertificate, certify_alpha_max};
    /// use stabound::params::Plant;
    /// use stabound::{AmaxOptions, alpha_max};
    ///
    /// let rows = [0.5, 1.0]
    ///     .iter()
    ///     .map(|&delta| {
    ///         let plant = Plant::new(delta, 1.0)?;
    ///         let amax = alpha_max(&plant, &AmaxOptions::default())?;
    ///         certify_alpha_max(&plant, &amax, (-0.5, 2.0), 1024)
    ///     })
    ///     .collect::<Result<Vec<_>, _>>()?;
    /// let json = AmaxCertificate::rows_json(&rows);
    /// assert!(json.contains("\"claim\": {\"rows\": 2}"));
    /// # Ok::<(), stabound::Error>(())
    /// ```
    pub fn rows_json(rows: &[Self]) -> String {
        match rows {
            [one] => one.to_json(),
            _ => grid_json(rows.iter().map(Self::to_json).collect()),
        }
    }

    /// The certificate as JSON text: the stable wall's certificate, the box's above it
    /// (from `alpha_hi` to the cap, or the strip at `alpha_hi` alone), the cap and its rule
    /// when there is one, the enclosure (with `"stiffer": "none stable"` when the cap is
    /// there), and a CRC-32 of the text before it.
    pub fn to_json(&self) -> String {
        let (lo, hi) = self.bounds();
        let mut s = super::opening("alpha_max");
        let _ = writeln!(s, "  \"stable_below\": {},", nested(&self.below.to_json()));
        let _ = writeln!(
            s,
            "  \"unstable_above\": {},",
            nested(&self.above.to_json())
        );
        if let Some(cap) = &self.cap {
            let _ = writeln!(s, "  \"cap\": {},", cap_json(cap));
        }
        let _ = write!(
            s,
            "  \"claim\": {{\"alpha_lo\": \"{}\", \"alpha_hi\": \"{}\"",
            hex(lo),
            hex(hi)
        );
        if self.cap.is_some() {
            s.push_str(", \"stiffer\": \"none stable\"");
        }
        s.push_str("},\n");
        seal(s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `C(m, k)` against Pascal's triangle (sums only), and `None` past `2^53`.
    #[test]
    fn binomials_match_pascals_triangle() {
        let mut row = vec![1u64];
        for m in 1..=60usize {
            let next: Vec<u64> = (0..=m)
                .map(|k| {
                    let left = if k > 0 { row[k - 1] } else { 0 };
                    left + row.get(k).copied().unwrap_or(0)
                })
                .collect();
            row = next;
            for (k, &c) in row.iter().enumerate() {
                let want = (c <= 1 << 53).then_some(c as f64);
                assert_eq!(binomial(m, k), want, "C({m}, {k})");
            }
        }
    }
}
