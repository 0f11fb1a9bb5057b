//! Rewrites the golden CSVs of the paper's figures (`data/figures/figNN.csv`) from the
//! current code, after an intended change; the library test `figures_golden` compares them
//! on every run. Review the difference (`git diff data/figures`) before committing it.
//!
//! Run with `cargo run --release -p stabound --example bless-figures`.

use std::path::PathBuf;

use stabound::figures::{FIGURES, figure};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../data/figures");
    std::fs::create_dir_all(&dir)?;
    for n in FIGURES {
        let fd = figure(n)?;
        let path = dir.join(format!("{}.csv", fd.name));
        // written beside the file and renamed over it: a file is old or new, never half
        let tmp = dir.join(format!(".{}.csv.tmp", fd.name));
        std::fs::write(&tmp, fd.to_csv())?;
        std::fs::rename(&tmp, &path)?;
        println!("wrote {}", path.display());
    }
    Ok(())
}
