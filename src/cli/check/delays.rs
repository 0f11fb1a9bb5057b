//! `stabound check --certify` over a set of devices that differ only in their delay
//! (`--delay-samples LO..HI`): the certified verdict of the wall at every delay of the
//! interval (the model document, docs/MODEL.md, section 11), the report and the certificate.

use stabound::certificate::{DelayClaim, certify_delays};
use stabound::elements::Loop;
use stabound::params::Wall;
use stabound::robust::{Quantity, Spread};
use stabound::stability::Verdict;

use super::{Args, Format, verdict_status};
use crate::cli::UsageError;

/// What a set of devices must be for a certificate (the refusal says it).
const SUPPORTED: &str = "--certify over a set of devices proves one wall of the paper's loop at every delay of an interval in samples (--delay-samples LO..HI), or one wall or box for every member of a finite set of loop-element values (one-of:LIST): give every other value as one number (no other LO..HI), and leave out the quantizers and friction (and, over delays, the loop elements)";

/// The delay interval `[lo, hi]` in samples of a set of devices of the paper's loop that
/// spreads nothing else.
///
/// # Errors
///
/// [`UsageError`] saying what is supported for any other set.
pub(super) fn interval(a: &Args) -> Result<(f64, f64), UsageError> {
    let sets = a.device_sets();
    let elements_one = a.loop_elements.one_device("check --certify").is_ok();
    match (sets.as_slice(), a.delay_samples.is_some(), elements_one) {
        ([(Quantity::Delay, Spread::Interval(lo, hi))], true, true)
            if !a.nonlinear.named().any() && !a.boxed() && !a.names_elements() =>
        {
            Ok((*lo, *hi))
        }
        _ => Err(UsageError(SUPPORTED.into())),
    }
}

/// The report, the certificate and the exit status `--exit-status` asks for (0 stable, 3
/// unstable, 4 not proved) of `wall` on the loop `lp` at every delay of `delays` (samples).
pub(super) fn run(
    a: &Args,
    lp: Loop,
    wall: &Wall,
    (lo, hi): (f64, f64),
) -> anyhow::Result<(String, String, anyhow::Result<()>)> {
    let cert = certify_delays(lp, wall, (lo, hi), a.certify_leaves)?;
    let (stable, unstable, undecided) = cert.counts();
    let (verdict, name) = match cert.claim() {
        DelayClaim::Stable => (Verdict::Stable, "stable at every delay of the set"),
        DelayClaim::Unstable => (Verdict::Unstable, "unstable at every delay of the set"),
        _ => (Verdict::Marginal, "not proved for every delay of the set"),
    };
    let cells = stable + unstable + undecided;
    let (alpha, beta) = (wall.alpha(), wall.beta());
    let report = match a.format {
        Format::Text => format!(
            "wall: alpha = {alpha}, beta = {beta}\ndevices: delay in [{lo}, {hi}] samples\nverdict: {name}\ncertified by: {cells} cells of delay ({stable} stable, {unstable} unstable, {undecided} undecided; at most {} cells)\n",
            a.certify_leaves
        ),
        Format::Json => format!(
            "{:#}\n",
            serde_json::json!({
                "alpha": alpha,
                "beta": beta,
                "delay_samples": [lo, hi],
                "verdict": name,
                "cells": {"stable": stable, "unstable": unstable, "undecided": undecided},
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
