//! `stabound amax --certify`: an enclosure of alpha_max for one (delta, d) of the paper's
//! loop, proved by a certificate (the model document, docs/MODEL.md, section 11).

use stabound::certificate::certify_alpha_max;
use stabound::params::Plant;
use stabound::{Loop, alpha_max};

use super::UsageError;
use super::args::{Grid, RowFormat, SearchArgs};

/// Leaves each unstable strip may be halved into.
const LEAVES: usize = 4096;

/// The row (alpha_max, its damping and the certified enclosure) and the certificate.
/// `unsupported`: an option the certificate does not cover was given.
pub(super) fn run(
    g: &Grid,
    search: &SearchArgs,
    format: RowFormat,
    unsupported: bool,
) -> anyhow::Result<(String, String)> {
    let opts = search.options(g.device)?;
    let single = g.deltas.len() == 1 && g.ds.len() == 1 && g.device.is_none();
    let (Some(lo), Some(hi), true, false) = (opts.beta_min(), opts.beta_max(), single, unsupported)
    else {
        return Err(UsageError(
            "amax --certify proves an enclosure for one --delta and one --d of the paper's loop over a bounded damping range: give --beta-min and --beta-max, and leave out the device, loop elements, quantizers, --margin, --svg and --shard".into(),
        )
        .into());
    };
    let (delta, d) = (g.deltas[0], g.ds[0]);
    let lp = Loop::new(Plant::new(delta, d)?);
    let amax = alpha_max(lp, &opts)?;
    let cert = certify_alpha_max(lp, &amax, (lo, hi), LEAVES)?;
    let (alo, ahi) = cert.bounds();
    let rows = match format {
        RowFormat::Json => format!(
            "{:#}\n",
            serde_json::json!([{
                "delta": delta, "d": d, "alpha_max": amax.alpha_max,
                "beta_at_max": amax.beta_at_max, "alpha_lo_certified": alo,
                "alpha_hi_certified": ahi,
            }])
        ),
        RowFormat::Csv => format!(
            "delta,d,alpha_max,beta_at_max,alpha_lo_certified,alpha_hi_certified\n{delta},{d},{},{},{alo},{ahi}\n",
            amax.alpha_max, amax.beta_at_max
        ),
    };
    Ok((rows, cert.to_json()))
}
