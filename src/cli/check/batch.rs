//! `stabound check --batch`: every wall of a CSV in one process, one output row per wall.

use std::io::Read;
use std::path::Path;

use anyhow::Context;
use rayon::prelude::*;
use stabound::export::report::shown_decided_radius;
use stabound::export::{Cell, Table, csv::to_csv_bytes, json::to_json_bytes};
use stabound::params::{Delay, Device, Normalized};
use stabound::stability::{Checker, Options};

use super::super::UsageError;
use super::super::args::{PHYSICAL_DEVICE, missing};
use super::super::output::Progress;
use super::{Args, Format, verdict_status};

/// The largest batch file read: a million walls at about 60 bytes each.
const MAX_INPUT_BYTES: u64 = 64 << 20;

/// How the file gives its walls.
enum Columns {
    /// `alpha,beta,delta,d`, at these positions.
    Normalized([usize; 4]),
    /// `stiffness_N_per_m,wall_damping_Ns_per_m` on one device.
    Physical([usize; 2], Device),
}

/// The output bytes of a batch, and the exit status `--exit-status` asks for once they are
/// written.
pub fn run(a: &Args, input: &Path) -> anyhow::Result<(Vec<u8>, anyhow::Result<()>)> {
    let given = [
        ("--alpha", a.alpha.is_some()),
        ("--beta", a.beta.is_some()),
        ("--delta", a.delta.is_some()),
        ("--d", a.d.is_some()),
        ("--stiffness", a.stiffness.is_some()),
        ("--wall-damping", a.wall_damping.is_some()),
    ];
    if let Some((flag, _)) = given.iter().find(|(_, v)| *v) {
        return Err(UsageError(format!(
            "--batch reads the walls from the file; drop {flag} (the device may be given by --mass --period --damping --delay|--delay-samples)"
        ))
        .into());
    }
    let label = if input.as_os_str() == "-" {
        "stdin".to_string()
    } else {
        input.display().to_string()
    };
    let text = read_input(input)?;
    let mut lines = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty());
    let Some((_, header)) = lines.next() else {
        return Err(UsageError(format!(
            "{}: empty; the first line must name the columns (alpha,beta,delta,d or stiffness_N_per_m,wall_damping_Ns_per_m)",
            label
        ))
        .into());
    };
    let names: Vec<&str> = header.split(',').map(str::trim).collect();
    let columns = columns(a, &names).with_context(|| format!("{}: line 1", label))?;
    let rows: Vec<(usize, Vec<f64>)> = lines
        .map(|(i, line)| {
            let cells: Vec<&str> = line.split(',').map(str::trim).collect();
            if cells.len() != names.len() {
                return Err(UsageError(format!(
                    "{}: line {}: {} fields where the header has {}",
                    label,
                    i + 1,
                    cells.len(),
                    names.len()
                )));
            }
            let values = cells
                .iter()
                .zip(&names)
                .map(|(c, n)| {
                    c.parse::<f64>()
                        .ok()
                        .filter(|v| v.is_finite())
                        .ok_or_else(|| {
                            UsageError(format!(
                                "{}: line {}: {n} = {c:?} is not a finite number",
                                label,
                                i + 1
                            ))
                        })
                })
                .collect::<Result<Vec<f64>, _>>()?;
            Ok((i + 1, values))
        })
        .collect::<Result<_, _>>()?;
    let options = Options {
        method: a.method.into(),
        margin: a.margin,
    };
    // Physical walls share one device, so one checker of its loop (with the elements named)
    // serves every row.
    let shared = match &columns {
        Columns::Physical(_, device) => Some(Checker::new(a.elements(device)?, options)?),
        Columns::Normalized(_) if a.names_elements() => {
            return Err(UsageError(
                "loop elements are given in physical units: give the walls as stiffness_N_per_m,wall_damping_Ns_per_m with the device options".into(),
            )
            .into());
        }
        Columns::Normalized(_) => None,
    };
    let progress = Progress::new(rows.len());
    let results: Vec<_> = rows
        .par_iter()
        .map(|(_, v)| {
            stabound::cancel::poll()?;
            progress.tick();
            let params = match &columns {
                Columns::Normalized([ia, ib, ix, id]) => {
                    Normalized::new(v[*ia], v[*ib], v[*ix], v[*id])?
                }
                Columns::Physical([ik, ib], device) => device.normalize(v[*ik], v[*ib])?,
            };
            let (plant, wall) = params.split()?;
            let own;
            let checker = match &shared {
                Some(checker) => checker,
                None => {
                    own = Checker::new(plant, options)?;
                    &own
                }
            };
            // the radius (from the roots: most of the time at long delays) only when printed
            let row = if a.verdict_only {
                let d = checker.decide(&wall)?;
                (d.verdict, d.method, None)
            } else {
                let (d, radius) = checker.decide_with_radius(&wall)?;
                let shown = shown_decided_radius(d.verdict, d.reason, radius, a.margin);
                (d.verdict, d.method, Some(shown))
            };
            Ok::<_, stabound::Error>((params, row))
        })
        .zip(&rows)
        .map(|(r, (line, _))| r.with_context(|| format!("{}: line {line}", label)))
        .collect::<Result<_, anyhow::Error>>()?;
    progress.finish();

    let physical = matches!(columns, Columns::Physical(..));
    let mut cols = Vec::new();
    if physical {
        cols.extend(["stiffness_N_per_m", "wall_damping_Ns_per_m"]);
    }
    cols.extend(["alpha", "beta", "delta", "d", "verdict"]);
    if !a.verdict_only {
        cols.push("spectral_radius");
    }
    cols.push("method");
    let mut table = Table::new(&cols);
    table.reserve(results.len());
    let mut cells = Vec::with_capacity(cols.len());
    for ((_, v), (p, (verdict, method, radius))) in rows.iter().zip(&results) {
        cells.clear();
        if let Columns::Physical([ik, ib], _) = &columns {
            cells.extend([Cell::Num(v[*ik]), Cell::Num(v[*ib])]);
        }
        cells.extend([
            Cell::Num(p.alpha()),
            Cell::Num(p.beta()),
            Cell::Num(p.delta()),
            Cell::Num(p.d()),
            Cell::Static(verdict.name()),
        ]);
        cells.extend(radius.map(Cell::Num));
        cells.push(Cell::Static(method.name()));
        table.push_cells(cells.drain(..));
    }
    let bytes = match a.format {
        Format::Json => to_json_bytes(&table),
        Format::Text => to_csv_bytes(&table),
    };
    let status = if a.exit_status {
        verdict_status(results.iter().map(|(_, (verdict, ..))| *verdict))
    } else {
        Ok(())
    };
    Ok((bytes, status))
}

/// Reads the whole batch input (a file or `-` for stdin), at most [`MAX_INPUT_BYTES`].
fn read_input(input: &Path) -> anyhow::Result<String> {
    let mut bytes = Vec::new();
    let limit = MAX_INPUT_BYTES + 1;
    if input.as_os_str() == "-" {
        std::io::stdin()
            .lock()
            .take(limit)
            .read_to_end(&mut bytes)
            .context("reading the walls from stdin")?;
    } else {
        let meta = std::fs::metadata(input)
            .map_err(|e| UsageError(format!("cannot read {}: {e}", input.display())))?;
        if !meta.is_file() {
            return Err(UsageError(format!(
                "{} is not a regular file; give a CSV file or - for stdin",
                input.display()
            ))
            .into());
        }
        std::fs::File::open(input)
            .and_then(|f| f.take(limit).read_to_end(&mut bytes))
            .map_err(|e| UsageError(format!("cannot read {}: {e}", input.display())))?;
    }
    if bytes.len() as u64 > MAX_INPUT_BYTES {
        return Err(UsageError(format!(
            "{} is larger than {} MiB; split it into several batches",
            input.display(),
            MAX_INPUT_BYTES >> 20
        ))
        .into());
    }
    String::from_utf8(bytes)
        .map_err(|_| UsageError(format!("{} is not UTF-8 text", input.display())).into())
}

/// Which columns hold the walls, and the device for physical ones.
fn columns(a: &Args, names: &[&str]) -> anyhow::Result<Columns> {
    let find = |want: &str| names.iter().position(|n| *n == want);
    let known = [
        "alpha",
        "beta",
        "delta",
        "d",
        "stiffness_N_per_m",
        "wall_damping_Ns_per_m",
    ];
    if let Some(n) = names.iter().find(|n| !known.contains(n)) {
        return Err(UsageError(format!(
            "unknown column {n:?}; the header names alpha,beta,delta,d or stiffness_N_per_m,wall_damping_Ns_per_m"
        ))
        .into());
    }
    if let (Some(k), Some(b)) = (find("stiffness_N_per_m"), find("wall_damping_Ns_per_m")) {
        if names.len() != 2 {
            return Err(UsageError(
                "give the walls either as alpha,beta,delta,d or as stiffness_N_per_m,wall_damping_Ns_per_m, not both".into(),
            )
            .into());
        }
        let delay = match (a.delay(), a.delay_samples()) {
            (Some(s), None) => Some(Delay::Seconds(s)),
            (None, Some(n)) => Some(Delay::Samples(n)),
            _ => None,
        };
        let (Some(m), Some(t), Some(damping), Some(delay)) =
            (a.mass(), a.period, a.damping(), delay)
        else {
            let device = [
                ("--mass", a.mass().is_some()),
                ("--period", a.period.is_some()),
                ("--damping", a.damping().is_some()),
                ("--delay|--delay-samples", delay.is_some()),
            ];
            return Err(missing(
                &device,
                &format!("walls in physical units need the device: {PHYSICAL_DEVICE}"),
            )
            .into());
        };
        let device = Device::new(m, t, damping, delay)?;
        device.plant()?;
        return Ok(Columns::Physical([k, b], device));
    }
    let missing: Vec<&str> = ["alpha", "beta", "delta", "d"]
        .into_iter()
        .filter(|n| find(n).is_none())
        .collect();
    if !missing.is_empty() || names.len() != 4 {
        return Err(UsageError(format!(
            "the header lacks {}; name alpha,beta,delta,d (or stiffness_N_per_m,wall_damping_Ns_per_m)",
            missing.join(", ")
        ))
        .into());
    }
    if [
        a.mass(),
        a.period,
        a.damping(),
        a.delay(),
        a.delay_samples(),
    ]
    .iter()
    .any(Option::is_some)
    {
        return Err(UsageError(
            "normalized walls carry their own delta and d; drop the device options".into(),
        )
        .into());
    }
    let at = |n| find(n).unwrap_or(0);
    Ok(Columns::Normalized([
        at("alpha"),
        at("beta"),
        at("delta"),
        at("d"),
    ]))
}
