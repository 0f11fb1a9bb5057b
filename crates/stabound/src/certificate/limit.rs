//! A certified enclosure of `alpha_max` (`docs/MODEL.md` sections 5 and 11): a wall below it
//! certified stable, and a strip of walls above it (one stiffness, every damping of the
//! searched range) certified unstable by a box certificate, so that no admissible damping
//! stabilizes that stiffness.

use std::fmt::Write as _;

use super::region::{BoxCertificate, BoxClaim, WallBox, certify_box};
use super::{Certificate, Claim, certify, hex, seal};
use crate::amax::Amax;
use crate::elements::Loop;
use crate::error::{Error, Result};
use crate::params::Wall;
use crate::stability::DEFAULT_MARGIN;

/// Relative steps below `alpha_max` tried for the stable wall, nearest first.
const BELOW: [f64; 3] = [1e-9, 1e-6, 1e-3];
/// Relative steps above `alpha_max` tried for the unstable strip, nearest first: the strip
/// passes close to the boundary near the optimal damping, where nearer strips need more
/// leaves.
const ABOVE: [f64; 4] = [1e-4, 1e-3, 1e-2, 1e-1];

/// A certified enclosure `[alpha_lo, alpha_hi]` of `alpha_max`: the wall `(alpha_lo,
/// beta_at_max)` is stable, and every wall `(alpha_hi, beta)` with `beta` in the searched
/// range is unstable.
///
/// ```
/// use stabound::certificate::certify_alpha_max;
/// use stabound::params::Plant;
/// use stabound::{AmaxOptions, alpha_max};
///
/// let plant = Plant::new(0.5, 1.0)?;
/// let amax = alpha_max(&plant, &AmaxOptions::default())?;
/// let cert = certify_alpha_max(&plant, &amax, (-0.5, 2.0), 1024)?;
/// let (lo, hi) = cert.bounds();
/// assert!(lo <= amax.alpha_max && amax.alpha_max < hi);
/// # Ok::<(), stabound::Error>(())
/// ```
#[derive(Debug, Clone)]
pub struct AmaxCertificate {
    below: Certificate,
    above: BoxCertificate,
}

/// Certifies an enclosure of `amax` (from [`crate::alpha_max`] on `lp`) for the dampings
/// `betas = (lo, hi)`: the nearest stable wall below it and the nearest unstable strip above
/// it that the certificates prove (strips halved into at most `max_leaves` leaves).
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
    if !(betas.0 <= b && b <= betas.1) {
        return Err(Error::InvalidParameter {
            name: "beta range",
            value: b,
            expected: format!(
                "the searched dampings [{}, {}] hold the optimum's damping",
                betas.0, betas.1
            ),
        });
    }
    // the farthest try's outcome says why none was certified stable
    let mut why = String::new();
    let below = BELOW
        .iter()
        .find_map(|r| {
            let wall = Wall::new(a * (1.0 - r), b).ok()?;
            match certify(lp, &wall, DEFAULT_MARGIN) {
                Ok(c) if c.claim() == Claim::Stable => Some(c),
                Ok(c) => {
                    why = match c.claim() {
                        Claim::Marginal { .. } => "certified marginal".into(),
                        _ => "certified unstable: the stable set at the optimum's damping does not reach up to it".into(),
                    };
                    None
                }
                Err(e) => {
                    why = e.to_string();
                    None
                }
            }
        })
        .ok_or_else(|| {
            Error::Numerical(format!(
                "no wall within 0.1 % below alpha_max is certified stable (at 0.1 % below: {why})"
            ))
        })?;
    for r in ABOVE {
        let hi = a * (1.0 + r);
        let strip = WallBox::new(Wall::new(hi, betas.0)?, Wall::new(hi, betas.1)?)?;
        let above = certify_box(lp, &strip, max_leaves)?;
        if above.claim() == BoxClaim::Unstable {
            return Ok(AmaxCertificate { below, above });
        }
    }
    Err(Error::Numerical(format!(
        "no stiffness within 10 % above alpha_max is certified unstable for every damping in [{}, {}] within {max_leaves} leaves; a larger budget may prove it",
        betas.0, betas.1
    )))
}

/// A certificate's JSON as a member of another: without its CRC (the outer one covers it),
/// indented one level.
fn nested(json: &str) -> String {
    let body = json.rfind(",\n  \"crc32\"").map_or(json, |i| &json[..i]);
    format!("{}\n  }}", body.replace('\n', "\n  "))
}

impl AmaxCertificate {
    /// The enclosure `(alpha_lo, alpha_hi)`.
    pub fn bounds(&self) -> (f64, f64) {
        (self.below.alpha, self.above.walls().alpha().0)
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
    /// The checker replays every row.
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
        let mut s =
            String::from("{\n  \"certificate\": \"stabound alpha_max grid certificate 1\",\n");
        s.push_str("  \"rows\": [");
        for (i, row) in rows.iter().enumerate() {
            s.push_str(if i == 0 { "\n    " } else { ",\n    " });
            s.push_str(&nested(&row.to_json()).replace('\n', "\n  "));
        }
        let _ = writeln!(s, "],\n  \"claim\": {{\"rows\": {}}},", rows.len());
        seal(s)
    }

    /// The certificate as JSON text: the stable wall's certificate, the unstable strip's,
    /// the enclosure, and a CRC-32 of the text before it.
    pub fn to_json(&self) -> String {
        let (lo, hi) = self.bounds();
        let mut s = String::from("{\n  \"certificate\": \"stabound alpha_max certificate 1\",\n");
        let _ = writeln!(s, "  \"stable_below\": {},", nested(&self.below.to_json()));
        let _ = writeln!(
            s,
            "  \"unstable_above\": {},",
            nested(&self.above.to_json())
        );
        let _ = writeln!(
            s,
            "  \"claim\": {{\"alpha_lo\": \"{}\", \"alpha_hi\": \"{}\"}},",
            hex(lo),
            hex(hi)
        );
        seal(s)
    }
}
