//! `stabound figure`: the paper's figures as SVG plus the CSV behind each.

use std::path::PathBuf;
use std::time::Instant;

use rayon::prelude::*;
use stabound::figures::{FIGURES, FigureData, figure};

use super::UsageError;
use super::output::Plan;

/// Writes DIR/figNN.svg and DIR/figNN.csv for one of the paper's figures (5 to 11) or all.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Figure number (5, 6, 7, 8, 9, 10, 11) or `all`.
    which: String,
    /// Directory to write into (created if missing).
    #[arg(short = 'o', long = "output-dir", default_value = ".")]
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
    // the directory: an existing one, or created now, before any work
    if a.out.exists() && !a.out.is_dir() {
        return Err(UsageError(format!(
            "--output-dir {}: is not a directory; give a directory (created if missing)",
            a.out.display()
        ))
        .into());
    }
    std::fs::create_dir_all(&a.out).map_err(|e| {
        UsageError(format!(
            "--output-dir {}: cannot create the directory ({e})",
            a.out.display()
        ))
    })?;
    let paths: Vec<(u32, PathBuf, PathBuf)> = numbers
        .iter()
        .map(|&n| {
            let name = format!("fig{n:02}");
            let dir = &a.out;
            (
                n,
                dir.join(format!("{name}.svg")),
                dir.join(format!("{name}.csv")),
            )
        })
        .collect();
    let mut outputs = Plan::new();
    let slots: Vec<_> = paths
        .iter()
        .map(|(_, svg, csv)| {
            (
                outputs.file("--output-dir", svg),
                outputs.file("--output-dir", csv),
            )
        })
        .collect();
    let mut out = outputs.check()?;
    let start = Instant::now();
    // Figures are independent; compute them in parallel, collect in order.
    let data: Vec<FigureData> = numbers
        .par_iter()
        .map(|&n| figure(n))
        .collect::<stabound::Result<_>>()?;
    for ((fd, (svg_slot, csv_slot)), (n, _, _)) in data.iter().zip(&slots).zip(&paths) {
        if fd.name != format!("fig{n:02}") {
            anyhow::bail!("figure {n} is named {}, not fig{n:02}", fd.name);
        }
        out.write(*svg_slot, fd.to_svg()?.as_bytes())?;
        out.write(*csv_slot, fd.to_csv().as_bytes())?;
    }
    out.finish()?;
    for (_, svg, csv) in &paths {
        let show =
            |p: &PathBuf| stabound::export::text::escape(&p.display().to_string()).into_owned();
        eprintln!("wrote {} and {}", show(svg), show(csv));
    }
    eprintln!(
        "{} figure(s) in {:.2} s",
        data.len(),
        start.elapsed().as_secs_f64()
    );
    Ok(())
}
