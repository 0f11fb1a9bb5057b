//! Writing results: one file per output format, and the atomic file write they all share.

pub mod c;
pub mod csv;
pub mod json;
pub mod rust;
pub mod table;
pub mod table_csv;

pub use table::{Cell, Table};

use std::io::Write;
use std::path::Path;

use crate::error::{Error, Result};

/// Writes `bytes` to `path` whole or not at all: into a temporary file in the same directory,
/// flushed to disk, then renamed over `path`. A failure or interruption midway leaves any
/// earlier file at `path` untouched and no partial file behind under that name.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let fail = |what: &str, e: std::io::Error| {
        Error::Io(format!(
            "cannot write {}: {what}: {e}; check that the directory exists and is writable",
            path.display()
        ))
    };
    let mut tmp = tempfile::Builder::new()
        .prefix(".stabound-")
        .suffix(".part")
        .tempfile_in(dir)
        .map_err(|e| fail("creating a temporary file", e))?;
    tmp.write_all(bytes).map_err(|e| fail("writing", e))?;
    tmp.as_file().sync_all().map_err(|e| fail("syncing", e))?;
    tmp.persist(path)
        .map_err(|e| fail("renaming the temporary file", e.error))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn writes_whole_file_and_replaces() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("out.csv");
        write_atomic(&p, b"a,b\n1,2\n").unwrap();
        write_atomic(&p, b"x\n").unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"x\n");
        // nothing else left in the directory
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
    }

    #[test]
    fn unwritable_directory_is_an_error() {
        let err = write_atomic(Path::new("/nonexistent-dir/x.csv"), b"x").unwrap_err();
        assert!(err.to_string().contains("/nonexistent-dir/x.csv"), "{err}");
    }
}
