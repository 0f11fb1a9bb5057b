//! `stabound amax --certify`: an enclosure of alpha_max for each row of the grid (a delta
//! and a d, or a device's damping and delay, with or without loop elements; or the robust
//! alpha_max of a finite set of devices), proved by one certificate (the model document,
//! docs/MODEL.md, section 11).

use rayon::prelude::*;
use stabound::alpha_max;
use stabound::certificate::{
    AMAX_LEAVES as LEAVES, AmaxCertificate, SetAmaxCertificate, certify_alpha_max,
    certify_set_alpha_max,
};
use stabound::elements::Loop;
use stabound::export::DeviceScale;
use stabound::export::text::numbers_shown;
use stabound::params::{Device, Plant, outward};
use stabound::robust::{DeviceSet, robust_alpha_max};

use super::UsageError;
use super::args::{
    ElementArgs, Grid, MAX_STREAM_ROWS, RowFormat, SearchArgs, Shard, needs_physical, plan,
};

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
    // the loop (or finite set of devices) of each row, d outer and delta inner, as amax
    // orders its rows
    let loops = (0..total)
        .map(|k| -> anyhow::Result<Row> {
            let (j, i) = (k % nx, k / nx);
            let Some((m, t)) = g.device else {
                return Ok(Row::One(Loop::new(Plant::new(g.deltas[j], g.ds[i])?)));
            };
            let (bs, delays) = &g.physical;
            let device = Device::new(m, t, bs[j], delays[i])?;
            match elements.device_set(&device, &g.sets, true)? {
                Some(set) if set.has_intervals() => Err(UsageError(
                    "amax --certify over a set of devices proves the robust alpha_max of a finite set (a hand that can let go, one-of:LIST loop-element values): give an interval's values as one-of:LIST".into(),
                )
                .into()),
                Some(set) if !set.is_single() => {
                    if k == 0 {
                        eprintln!("note: robust alpha_max of the set: {}", set.describe().join("; "));
                    }
                    Ok(Row::Set(set))
                }
                Some(set) if k == 0 => {
                    eprintln!("note: {}", set.describe().join("; "));
                    Ok(Row::One(elements.loop_on(&device)?))
                }
                _ => Ok(Row::One(elements.loop_on(&device)?)),
            }
        })
        .collect::<anyhow::Result<Vec<_>>>()?;
    let certified = loops
        .par_iter()
        .enumerate()
        .map(|(k, row)| -> anyhow::Result<_> {
            let at = || format!("delta = {}, d = {}", g.deltas[k % nx], g.ds[k / nx]);
            let proved = || -> stabound::Result<_> {
                Ok(match row {
                    Row::One(lp) => {
                        let amax = alpha_max(*lp, &opts)?;
                        let cert = certify_alpha_max(*lp, &amax, (lo, hi), LEAVES)?;
                        let optimum = (amax.alpha_max, amax.beta_at_max);
                        (optimum, cert.bounds(), Proof::One(Box::new(cert)))
                    }
                    Row::Set(set) => {
                        let r = robust_alpha_max(set, &opts)?;
                        let optimum = (r.alpha_max, r.beta_at_max);
                        let cert = certify_set_alpha_max(set, optimum, (lo, hi), LEAVES)?;
                        (optimum, cert.bounds(), Proof::Set(cert))
                    }
                })
            };
            proved().map_err(|e| anyhow::Error::new(e).context(at()))
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
    for (k, &((amax, bmax), (alo, ahi), _)) in certified.iter().enumerate() {
        let (x, d) = (g.deltas[k % nx], g.ds[k / nx]);
        let mut row = vec![x, d, amax, bmax, alo, ahi];
        if let Some(u) = scale {
            row.extend([
                u.try_damping(x)?,
                u.try_k(amax)?,
                u.try_b(bmax)?,
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
    let (mut ones, mut sets) = (Vec::new(), Vec::new());
    for (k, (_, _, proof)) in certified.into_iter().enumerate() {
        match proof {
            Proof::One(c) => ones.push(*c),
            Proof::Set(c) => {
                let row = (total > 1).then(|| (g.deltas[k % nx], g.ds[k / nx]));
                eprintln!("{}", upper_end(&c, row, scale)?);
                sets.push(c);
            }
        }
    }
    let json = if sets.is_empty() {
        AmaxCertificate::rows_json(&ones)
    } else {
        SetAmaxCertificate::rows_json(&sets)
    };
    Ok((text, json))
}

/// How a set's certificate proves the upper end of its enclosure (a message): one member's
/// proof over the whole damping range, or pieces of the range meeting end to end, each
/// proved for one member, told as the runs of consecutive pieces with one binding member
/// (their damping range in N s/m when the device is given, else normalized). `row`: the
/// row's `(delta, d)` when the grid has several.
fn upper_end(
    cert: &SetAmaxCertificate,
    row: Option<(f64, f64)>,
    scale: Option<DeviceScale>,
) -> anyhow::Result<String> {
    let at = row.map_or(String::new(), |(x, d)| format!(" (delta = {x}, d = {d})"));
    let pieces = cert.pieces();
    if let [(_, _, member)] = pieces.as_slice() {
        return Ok(format!(
            "note: the upper end of the robust alpha_max's enclosure{at} is one member's proof: {member} binds over the whole damping range"
        ));
    }
    // runs of consecutive pieces with one member: (lo, hi, member, pieces)
    let mut runs: Vec<(f64, f64, &str, usize)> = Vec::new();
    for &(lo, hi, member) in &pieces {
        match runs.last_mut() {
            Some(run) if run.2 == member => (run.1, run.3) = (hi, run.3 + 1),
            _ => runs.push((lo, hi, member, 1)),
        }
    }
    let unit = if scale.is_some() { " N s/m" } else { "" };
    let damping = |beta: f64| scale.map_or(Ok(beta), |u| u.try_b(beta));
    let mut told = Vec::with_capacity(runs.len());
    for (lo, hi, member, n) in runs {
        let count = if n == 1 {
            String::new()
        } else {
            format!(" ({n} pieces)")
        };
        told.push(format!(
            "[{}, {}]{unit} by {member}{count}",
            damping(lo)?,
            damping(hi)?
        ));
    }
    let stiffer = if cert.every_stiffer_wall() {
        " (nor any stiffer wall)"
    } else {
        ""
    };
    let text = format!(
        "note: the upper end of the robust alpha_max's enclosure{at} is proved in {} pieces of the damping range, each with no wall stable for its binding member at alpha_hi{stiffer}: {}",
        pieces.len(),
        told.join(", then ")
    );
    // the range's ends are widened outward, so an end may be a subnormal below 0
    Ok(numbers_shown(&text).into_owned())
}

/// A row's device: one loop, or a finite set of devices (a hand that can let go, one-of
/// lists of loop-element values).
enum Row {
    One(Loop),
    Set(DeviceSet),
}

/// A row's proof: the enclosure of one loop's alpha_max, or of a set's robust alpha_max.
enum Proof {
    One(Box<AmaxCertificate>),
    Set(SetAmaxCertificate),
}
