//! `stabound scene`: check every wall of a scene file.

use std::path::PathBuf;

use clap::ValueEnum;
use stabound::scene::Scene;
use stabound::stability::{DEFAULT_MARGIN, Options};

use super::args::finite;
use super::output::Plan;

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Format {
    Text,
    Json,
}

/// The long help of `stabound scene`.
pub(super) const LONG_ABOUT: &str = "\
Check the walls of a scene file (TOML, or JSON for a `.json` file).\n\
\n\
The file lists devices (`[[device]]`: mass_kg, period_s, damping_Ns_per_m, and delay_s or\n\
delay_samples) and each device's walls (`[[device.wall]]`: stiffness_N_per_m,\n\
damping_Ns_per_m; `name` optional everywhere). Units are part of the key names; unknown\n\
keys, keys without units and missing keys are errors naming the line (exit 2). Example:\n\
data/scenes/phantom.toml. A number of the device (not period_s) or of an element may be\n\
a two-element array [LO, HI] (delay_samples = [1, 3]): the device is then a set of devices\n\
and each wall is judged for every member, as `check` does with LO..HI.\n\
\n\
For each wall it reports: the verdict (stable / marginal / unstable, by Schur-Cohn or,\n\
where its rounding guard cannot vouch, another method, with the marginal band\n\
--marginal-band); the spectral radius; K_lim(B), the largest stable stiffness at\n\
the wall's damping B, and the stiffness margin K / K_lim(B); the damping interval(s) that\n\
keep the wall's stiffness K stable; and the suggested damping B*, the damping at which\n\
the device reaches its maximum stable stiffness K_max (the B that maximizes K_lim(B), hence\n\
minimizes K / K_lim(B) for every K), with the margin K / K_max there.\n\
\n\
It computes only these quantities, with point tests and exact one-dimensional searches\n\
(D-decomposition crossings along one line, one Schur-Cohn test per piece between\n\
crossings), never a full stability boundary or a grid.\n\
";

/// Arguments of `stabound scene` (see [`LONG_ABOUT`]).
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The scene file (.toml, or .json).
    file: PathBuf,
    /// Output format.
    #[arg(long, value_enum, default_value = "text")]
    format: Format,
    /// Half-width of the marginal band around the unit circle: a spectral radius within this
    /// of 1 is reported as marginal.
    #[arg(long = "marginal-band", default_value_t = DEFAULT_MARGIN, value_parser = finite, allow_hyphen_values = true)]
    margin: f64,
    /// Exit status by verdict, for scripts: 3 if any wall is unstable, else 4 if any is
    /// marginal, else 0 (as `check --exit-status`). Errors keep 1 and 2.
    #[arg(long = "exit-status")]
    exit_status: bool,
    /// Write to this file instead of stdout.
    #[arg(short, long)]
    output: Option<PathBuf>,
}

pub fn run(a: Args) -> anyhow::Result<()> {
    let mut outputs = Plan::new();
    let data = outputs.data("-o", a.output.as_deref());
    outputs.input(&a.file);
    let mut out = outputs.check()?;
    let scene = Scene::read(&a.file)?;
    let options = Options {
        margin: a.margin,
        ..Options::default()
    };
    let report = scene.check(&options)?;
    let text = match a.format {
        Format::Text => report.to_text(),
        Format::Json => format!("{}\n", serde_json::to_string_pretty(&report)?),
    };
    out.write(data, text.as_bytes())?;
    out.finish()?;
    if a.exit_status {
        super::check::verdict_status(report.devices.iter().flat_map(|d| {
            let set = d.set.iter().flat_map(|s| s.walls.iter().map(|w| w.verdict));
            d.walls.iter().map(|w| w.verdict).chain(set)
        }))?;
    }
    Ok(())
}
