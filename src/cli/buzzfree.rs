//! The buzz-free stiffness beside the linear alpha_max, for `amax` and `table` when an
//! encoder resolution, a force resolution or a friction is named: one row per (delay,
//! damping) node of the grid, in physical units with the normalized values beside them.

use std::sync::atomic::{AtomicUsize, Ordering};

use stabound::buzz::{
    BuzzFree, BuzzFreeOptions, DAMPING_GRID, Nonlinear, SCAN_POINTS, buzz_free_alpha_max,
};
use stabound::elements::{Loop, PhysicalElements};
use stabound::export::Table;
use stabound::export::csv::to_csv_bytes;
use stabound::export::json::to_json_bytes;
use stabound::params::Device;

use super::UsageError;
use super::args::{ElementArgs, Grid, needs_physical};
use super::output::{Outputs, Progress, Slot};

/// Walls judged per damping, about: the scan, and the bisection of one step of its grid
/// (a ratio of 1.58) down to 1 + 1e-3 (9 halvings of its logarithm).
const WALLS_PER_DAMPING: usize = SCAN_POINTS + 9;

/// The columns: the node, the linear alpha_max and its damping, the buzz-free stiffness at
/// that damping, and the largest over the damping with its damping.
const COLUMNS: [&str; 14] = [
    "damping_Ns_per_m",
    "d",
    "K_max",
    "B",
    "K_buzz_free_at_B",
    "K_buzz_free",
    "B_buzz_free",
    "delta",
    "alpha_max",
    "beta_at_max",
    "alpha_buzz_free_at_beta",
    "alpha_buzz_free",
    "beta_buzz_free",
    "protocol_runs",
];

/// Writes the buzz-free rows of `g` into `data` (the answer of `amax` and `table` when a
/// quantizer or friction is named), with the method on stderr, and finishes the outputs.
pub fn answer(
    g: &Grid,
    elements: &ElementArgs,
    nonlinear: &Nonlinear,
    json: bool,
    mut out: Outputs,
    data: Slot,
) -> anyhow::Result<()> {
    if let Some((q, _)) = g.sets.first() {
        return Err(UsageError(format!(
            "the buzz-free stiffness answers for one device: give the {} as one number (sets, LO..HI or one-of:LIST, are for the linear loop)",
            q.name()
        ))
        .into());
    }
    elements.one_device("the buzz-free stiffness")?;
    let bytes = rows(g, &elements.named(), nonlinear, json)?;
    eprintln!("note: {}", method_note());
    out.write(data, &bytes)?;
    out.finish()
}

/// The rows for every node of `g` with the elements `named` and the quantizers and friction
/// `nonlinear`, as CSV or JSON bytes; a progress bar on stderr (a terminal, after a second).
fn rows(
    g: &Grid,
    named: &PhysicalElements,
    nonlinear: &Nonlinear,
    json: bool,
) -> anyhow::Result<Vec<u8>> {
    let Some((mass, period)) = g.device else {
        return Err(needs_physical("quantizers and friction"));
    };
    let (bs, delays) = &g.physical;
    let options = BuzzFreeOptions::default();
    let nodes = g.ds.len() * g.deltas.len();
    let progress = Progress::new(nodes * DAMPING_GRID.len() * WALLS_PER_DAMPING);
    let runs = AtomicUsize::new(0);
    let tick = || {
        runs.fetch_add(1, Ordering::Relaxed);
        progress.tick();
    };
    let mut table = Table::new(&COLUMNS);
    for (i, &d) in g.ds.iter().enumerate() {
        for (j, &delta) in g.deltas.iter().enumerate() {
            let device = Device::new(mass, period, bs[j], delays[i])?;
            let lp = Loop::physical(&device, named)?;
            runs.store(0, Ordering::Relaxed);
            let r = buzz_free_alpha_max(lp, nonlinear, &options, &tick)?;
            for f in r.at_beta_star.iter().chain(&r.best) {
                not_one_interval(&device, f);
            }
            let at = r.at_beta_star.and_then(|b| b.alpha).unwrap_or(f64::NAN);
            let (best, best_beta) = r
                .best
                .and_then(|b| b.alpha.map(|a| (a, b.beta)))
                .unwrap_or((f64::NAN, f64::NAN));
            table.push_numbers(&[
                device.damping(),
                d,
                device.stiffness(r.alpha_max),
                device.wall_damping(r.beta_at_max),
                device.stiffness(at),
                device.stiffness(best),
                device.wall_damping(best_beta),
                delta,
                r.alpha_max,
                r.beta_at_max,
                at,
                best,
                best_beta,
                runs.load(Ordering::Relaxed) as f64,
            ]);
        }
    }
    progress.finish();
    Ok(if json {
        to_json_bytes(&table)
    } else {
        to_csv_bytes(&table)
    })
}

/// A warning when the scan found a quiet stiffness above a buzzing one at `f`'s damping:
/// the buzz-free stiffness is the top of the first quiet run, and a stiffer quiet band
/// exists beyond a buzzing one.
fn not_one_interval(device: &Device, f: &BuzzFree) {
    if let (Some(top), Some(beyond)) = (f.alpha, f.quiet_beyond) {
        eprintln!(
            "warning: b = {} N s/m, B = {} N s/m: the quiet stiffnesses are not one interval: K = {} N/m is quiet again above the buzz-free K = {} N/m, with buzzing walls between",
            device.damping(),
            device.wall_damping(f.beta),
            device.stiffness(beyond),
            device.stiffness(top)
        );
    }
}

/// What the rows mean, for a message beside them.
fn method_note() -> String {
    format!(
        "buzz-free stiffness: the largest K with every softer wall quiet, by a scan of {SCAN_POINTS} points on log K and bisection at the top of the first quiet run, with the buzz protocol as the oracle (rest at 1, 3, 10 counts and an impact; 20,000 samples, the last 4,000 judged), to 1e-3 of K, at B and over the dampings {:?} x B; an empty cell: none found",
        DAMPING_GRID
    )
}
