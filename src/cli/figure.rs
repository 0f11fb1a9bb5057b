//! `stabound figure`: the paper's figures as SVG plus the CSV behind each.

use std::path::PathBuf;
use std::time::Instant;

use rayon::prelude::*;
use stabound::figures::{FIGURES, FigureData, figure};

use super::UsageError;
use super::output::emit;

/// Writes DIR/figNN.svg and DIR/figNN.csv for one of the paper's figures (5 to 11) or all.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Figure number (5, 6, 7, 8, 9, 10, 11) or `all`.
    which: String,
    /// Directory to write into (created if missing).
    #[arg(long, default_value = ".")]
    out: PathBuf,
}

pub fn run(a: Args) -> anyhow::Result<()> {
    let numbers: Vec<u32> = if a.which.eq_ignore_ascii_case("all") {
        FIGURES.to_vec()
    } else {
        let n: u32 = a.which.trim().parse().map_err(|_| {
            UsageError(format!(
                "'{}' is not a figure; give one of 5, 6, 7, 8, 9, 10, 11 or all",
                a.which
            ))
        })?;
        if !FIGURES.contains(&n) {
            return Err(UsageError(format!(
                "the paper has no figure {n} with data; give one of 5, 6, 7, 8, 9, 10, 11 or all"
            ))
            .into());
        }
        vec![n]
    };
    std::fs::create_dir_all(&a.out).map_err(|e| {
        anyhow::anyhow!(
            "cannot create the output directory {}: {e}",
            a.out.display()
        )
    })?;
    let start = Instant::now();
    // Figures are independent; compute them in parallel, collect in order.
    let data: Vec<FigureData> = numbers
        .par_iter()
        .map(|&n| figure(n))
        .collect::<stabound::Result<_>>()?;
    for fd in &data {
        let svg = a.out.join(format!("{}.svg", fd.name));
        let csv = a.out.join(format!("{}.csv", fd.name));
        emit(Some(&svg), fd.to_svg()?.as_bytes())?;
        emit(Some(&csv), fd.to_csv().as_bytes())?;
        eprintln!("wrote {} and {}", svg.display(), csv.display());
    }
    eprintln!(
        "{} figure(s) in {:.2} s",
        data.len(),
        start.elapsed().as_secs_f64()
    );
    Ok(())
}
