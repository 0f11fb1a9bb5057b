//! `stabound check --certify` over a box of walls: the certified verdict for every wall of
//! the box (the model document, docs/MODEL.md, section 11), the report and the certificate.

use stabound::certificate::{BoxClaim, WallBox, certify_box};
use stabound::elements::Loop;
use stabound::params::{Normalized, Wall};
use stabound::stability::Verdict;

use super::{Args, Format, verdict_status};
use crate::cli::args::Span;
use stabound::params::outward;

/// The corners in `(alpha, beta)` of the box of physical walls normalized as `low` and
/// `high`; a side given as an interval is widened outward (see [`outward`]).
pub(super) fn widen(
    low: &Normalized,
    high: &Normalized,
    k: Span,
    b: Span,
) -> ((f64, f64), (f64, f64)) {
    let out = |lo: f64, hi: f64, s: Span| match s.interval() {
        None => (lo, hi),
        Some(_) => outward(lo, hi),
    };
    let (a0, a1) = out(low.alpha(), high.alpha(), k);
    let (b0, b1) = out(low.beta(), high.beta(), b);
    ((a0, b0), (a1, b1))
}

/// The report, the certificate and the exit status `--exit-status` asks for (0 stable, 3
/// unstable, 4 not proved).
pub(super) fn run(
    a: &Args,
    lp: Loop,
    (alo, blo): (f64, f64),
    (ahi, bhi): (f64, f64),
) -> anyhow::Result<(String, String, anyhow::Result<()>)> {
    let walls = WallBox::new(Wall::new(alo, blo)?, Wall::new(ahi, bhi)?)?;
    let cert = certify_box(lp, &walls, a.certify_leaves)?;
    let (stable, unstable, undecided) = cert.counts();
    let (verdict, name) = match cert.claim() {
        BoxClaim::Stable => (Verdict::Stable, "stable for every wall of the box"),
        BoxClaim::Unstable => (Verdict::Unstable, "unstable for every wall of the box"),
        _ => (Verdict::Marginal, "not proved for the whole box"),
    };
    let leaves = stable + unstable + undecided;
    let report = match a.format {
        Format::Text => format!(
            "box: alpha in [{alo}, {ahi}], beta in [{blo}, {bhi}]\nverdict: {name}\ncertified by: {leaves} boxes ({stable} stable, {unstable} unstable, {undecided} undecided; at most {} boxes)\n",
            a.certify_leaves
        ),
        Format::Json => format!(
            "{:#}\n",
            serde_json::json!({
                "alpha": [alo, ahi],
                "beta": [blo, bhi],
                "verdict": name,
                "boxes": {"stable": stable, "unstable": unstable, "undecided": undecided},
            })
        ),
    };
    let status = if a.exit_status {
        verdict_status([verdict])
    } else {
        Ok(())
    };
    Ok((report, cert.to_json(), status))
}
