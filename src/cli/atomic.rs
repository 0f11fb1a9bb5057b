//! Output files written whole or not at all, and their clean-up on an interrupt.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard};

/// The temporary files [`write_atomic`] is writing right now (see [`stop_writes`]).
static PARTIAL_FILES: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

fn partial_files() -> MutexGuard<'static, Vec<PathBuf>> {
    // a panic while holding the lock leaves the list itself valid
    PARTIAL_FILES
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// Stops every [`write_atomic`] of the process for good and deletes their temporary files,
/// then runs `then` (typically `std::process::exit`) with writes still stopped. For an
/// interrupt handler: afterwards no output file can appear half written or be renamed into
/// place, and no `.stabound-*.part` file is left behind. Returns `then`'s value; writes stay
/// blocked only while `then` runs.
pub fn stop_writes<R>(then: impl FnOnce() -> R) -> R {
    let mut live = partial_files();
    for p in live.drain(..) {
        let _ = std::fs::remove_file(p);
    }
    then()
}

/// Writes `bytes` to `path` whole or not at all: into a temporary file
/// (`.stabound-*.part`) in the same directory, flushed to disk, then renamed over `path`. A
/// failure or interruption midway leaves any earlier file at `path` untouched and no partial
/// file behind under that name; an interrupt handler calling [`stop_writes`] also removes
/// the temporary file. A new file gets mode 0644 (readable by all, like `cp` or a shell
/// redirect would give under the usual umask); a replaced file keeps its permissions.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> anyhow::Result<()> {
    write_atomic_parts(path, &[bytes])
}

/// [`write_atomic`] for data held in consecutive parts (such as
/// `stabound::export::csv::boundaries_csv_chunks`), written in order without joining them first.
pub fn write_atomic_parts<B: AsRef<[u8]>>(path: &Path, parts: &[B]) -> anyhow::Result<()> {
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let fail = |what: &str, e: std::io::Error| {
        anyhow::anyhow!(
            "cannot write {}: {what}: {e}; check that the directory exists and is writable",
            path.display()
        )
    };
    let mut tmp = {
        // created and registered under the lock, so an interrupt cannot fall in between
        let mut live = partial_files();
        let tmp = tempfile::Builder::new()
            .prefix(".stabound-")
            .suffix(".part")
            .tempfile_in(dir)
            .map_err(|e| fail("creating a temporary file", e))?;
        live.push(tmp.path().to_path_buf());
        tmp
    };
    let tmp_path = tmp.path().to_path_buf();
    let written = (|| {
        for part in parts {
            tmp.write_all(part.as_ref())
                .map_err(|e| fail("writing", e))?;
        }
        let permissions = match std::fs::metadata(path) {
            Ok(m) if m.is_file() => Some(m.permissions()),
            _ => new_file_permissions(),
        };
        if let Some(p) = permissions {
            tmp.as_file()
                .set_permissions(p)
                .map_err(|e| fail("setting permissions", e))?;
        }
        tmp.as_file().sync_all().map_err(|e| fail("syncing", e))
    })();
    // renamed under the lock: an interrupt either comes before (temporary file removed,
    // nothing at `path`) or after (complete file at `path`)
    let mut live = partial_files();
    let result = written.and_then(|()| {
        tmp.persist(path)
            .map(drop)
            .map_err(|e| fail("renaming the temporary file", e.error))
    });
    live.retain(|p| p != &tmp_path);
    result
}

#[cfg(unix)]
fn new_file_permissions() -> Option<std::fs::Permissions> {
    use std::os::unix::fs::PermissionsExt;
    Some(std::fs::Permissions::from_mode(0o644))
}

#[cfg(not(unix))]
fn new_file_permissions() -> Option<std::fs::Permissions> {
    None
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

    #[cfg(unix)]
    #[test]
    fn new_files_0644_replaced_files_keep_mode() {
        use std::os::unix::fs::PermissionsExt;
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("out.csv");
        write_atomic(&p, b"1\n").unwrap();
        let mode = |p: &Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o777;
        assert_eq!(mode(&p), 0o644);
        std::fs::set_permissions(&p, std::fs::Permissions::from_mode(0o600)).unwrap();
        write_atomic(&p, b"2\n").unwrap();
        assert_eq!(mode(&p), 0o600);
        assert_eq!(std::fs::read(&p).unwrap(), b"2\n");
    }

    #[test]
    fn unwritable_directory_is_an_error() {
        let err = write_atomic(Path::new("/nonexistent-dir/x.csv"), b"x").unwrap_err();
        assert!(err.to_string().contains("/nonexistent-dir/x.csv"), "{err}");
    }
}
