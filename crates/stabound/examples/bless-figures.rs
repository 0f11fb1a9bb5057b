//! Rewrites the golden CSVs of the paper's figures (`data/figures/figNN.csv`) and their
//! drawings (`docs/figures/figNN.svg`) from the current code, after an intended change; the
//! library test `figures_golden` compares both on every run. Review the difference
//! (`git diff data/figures docs/figures`, and the drawings as pictures) before committing it.
//!
//! Run with `cargo run --release -p stabound --example bless-figures`.

use std::path::{Path, PathBuf};

use stabound::figures::{FIGURES, figure};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../data/figures");
    std::fs::create_dir_all(&dir)?;
    let docs = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../docs/figures");
    std::fs::create_dir_all(&docs)?;
    for n in FIGURES {
        let fd = figure(n)?;
        write(&dir.join(format!("{}.csv", fd.name)), &fd.to_csv())?;
        write(&docs.join(format!("{}.svg", fd.name)), &fd.to_svg()?)?;
    }
    Ok(())
}

/// Writes `text` beside `path` and renames it over it: a file is old or new, never half.
fn write(path: &Path, text: &str) -> std::io::Result<()> {
    let mut tmp = path.as_os_str().to_owned();
    tmp.push(".tmp");
    std::fs::write(&tmp, text)?;
    std::fs::rename(&tmp, path)?;
    println!("wrote {}", path.display());
    Ok(())
}
