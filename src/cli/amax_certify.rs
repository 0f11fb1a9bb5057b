//! `stabound amax --certify`: an enclosure of alpha_max for each row of the grid (a delta
//! and a d, or a device's damping and delay, with or without loop elements), proved by one
//! certificate (the model document, docs/MODEL.md, section 11).

use rayon::prelude::*;
use stabound::alpha_max;
use stabound::certificate::{AmaxCertificate, certify_alpha_max};
use stabound::elements::Loop;
use stabound::export::DeviceScale;
use stabound::params::{Device, Plant};

use super::UsageError;
use super::args::{
    ElementArgs, Grid, MAX_STREAM_ROWS, RowFormat, SearchArgs, Shard, needs_physical, outward, plan,
};

/// Leaves the box above alpha_max (from alpha_hi to the cap) may be halved into, and, where
/// that does not suffice, each strip at alpha_hi alone: the paper's loop at `delta = 0.5`,
/// `d = 1` or `2.5` needs 8,512 to 13,636 leaves for the box.
const LEAVES: usize = 16384;

/// The rows (alpha_max, its damping and the certified enclosure; in physical units too when
/// the device was given) and the certificate: one row's own, or one holding every row's.
/// `unsupported`: an option the certificate does not cover was given.
pub(super) fn run(
    g: &Grid,
    search: &SearchArgs,
    elements: &ElementArgs,
    format: RowFormat,
    unsupported: bool,
) -> anyhow::Result<(String, String)> {
    let opts = search.options(g.device)?;
    let (Some(lo), Some(hi), false) = (opts.beta_min(), opts.beta_max(), unsupported) else {
        return Err(UsageError(
            "amax --certify proves an enclosure over a bounded damping range: give --beta-min and --beta-max (or --wall-damping-min and --wall-damping-max), and leave out quantizers, friction, --margin, --svg and --shard".into(),
        )
        .into());
    };
    let named = elements.named();
    if g.device.is_none() && (named.any() || !g.sets.is_empty()) {
        return Err(needs_physical("loop elements"));
    }
    // a limit in N s/m is widened by the normalization's rounding, so that the strip holds
    // every damping of the physical range
    let (wall_lo, wall_hi) = search.physical_limits();
    let wide = outward(lo, hi);
    let lo = if wall_lo { wide.0 } else { lo };
    let hi = if wall_hi { wide.1 } else { hi };
    let total = g.ds.len().saturating_mul(g.deltas.len());
    let what = format!("rows ({} d x {} delta)", g.ds.len(), g.deltas.len());
    plan(total, Shard::ALL, MAX_STREAM_ROWS, &what)?;
    let nx = g.deltas.len();
    // the loop of each row, d outer and delta inner, as amax orders its rows
    let loops = (0..total)
        .map(|k| -> anyhow::Result<Loop> {
            let (j, i) = (k % nx, k / nx);
            let Some((m, t)) = g.device else {
                return Ok(Loop::new(Plant::new(g.deltas[j], g.ds[i])?));
            };
            let (bs, delays) = &g.physical;
            let device = Device::new(m, t, bs[j], delays[i])?;
            match elements.device_set(&device, &g.sets, true)? {
                Some(set) if !set.is_single() => Err(UsageError(
                    "amax --certify proves an enclosure for one device per row: leave out sets of devices (an interval, one-of:LIST, or a hand that can let go: add --always-gripped if it never does)".into(),
                )
                .into()),
                Some(set) if k == 0 => {
                    eprintln!("note: {}", set.describe().join("; "));
                    elements.loop_on(&device)
                }
                _ => elements.loop_on(&device),
            }
        })
        .collect::<anyhow::Result<Vec<_>>>()?;
    let certified = loops
        .par_iter()
        .enumerate()
        .map(|(k, lp)| -> anyhow::Result<_> {
            let at = || format!("delta = {}, d = {}", g.deltas[k % nx], g.ds[k / nx]);
            let row = || -> stabound::Result<_> {
                let amax = alpha_max(*lp, &opts)?;
                let cert = certify_alpha_max(*lp, &amax, (lo, hi), LEAVES)?;
                Ok((amax, cert))
            };
            row().map_err(|e| anyhow::Error::new(e).context(at()))
        })
        .collect::<anyhow::Result<Vec<_>>>()?;
    let scale = g.device.map(|(mass, period)| DeviceScale { mass, period });
    let mut cols = vec![
        "delta",
        "d",
        "alpha_max",
        "beta_at_max",
        "alpha_lo_certified",
        "alpha_hi_certified",
    ];
    if scale.is_some() {
        cols.extend([
            "damping_Ns_per_m",
            "K_max_N_per_m",
            "B_at_max_Ns_per_m",
            "K_lo_certified_N_per_m",
            "K_hi_certified_N_per_m",
        ]);
    }
    let mut rows = Vec::with_capacity(total);
    for (k, (amax, cert)) in certified.iter().enumerate() {
        let (alo, ahi) = cert.bounds();
        let (x, d) = (g.deltas[k % nx], g.ds[k / nx]);
        let mut row = vec![x, d, amax.alpha_max, amax.beta_at_max, alo, ahi];
        if let Some(u) = scale {
            row.extend([
                u.try_damping(x)?,
                u.try_k(amax.alpha_max)?,
                u.try_b(amax.beta_at_max)?,
                u.try_k(alo)?,
                u.try_k(ahi)?,
            ]);
        }
        rows.push(row);
    }
    let text = match format {
        RowFormat::Json => {
            let objects: Vec<serde_json::Value> = rows
                .iter()
                .map(|row| {
                    let pairs = cols
                        .iter()
                        .zip(row)
                        .map(|(c, v)| (c.to_string(), (*v).into()));
                    serde_json::Value::Object(pairs.collect())
                })
                .collect();
            format!("{:#}\n", serde_json::Value::Array(objects))
        }
        RowFormat::Csv => {
            let mut s = cols.join(",");
            for row in &rows {
                let cells: Vec<String> = row.iter().map(f64::to_string).collect();
                s.push('\n');
                s.push_str(&cells.join(","));
            }
            s + "\n"
        }
    };
    let certs: Vec<AmaxCertificate> = certified.into_iter().map(|(_, c)| c).collect();
    let json = match certs.as_slice() {
        [one] => one.to_json(),
        all => AmaxCertificate::rows_json(all),
    };
    Ok((text, json))
}
