//! Output files written whole or not at all, and their clean-up on an interrupt.
//!
//! A file is first written into an unnamed temporary file in the directory of its final
//! name (Linux `O_TMPFILE`), flushed to disk, and only then given its name: linked in with
//! `linkat` through `/proc/self/fd` when the name is free, or linked under a temporary name
//! and renamed over the old file. A process killed in any way (SIGKILL, SIGXFSZ, a crash)
//! before that moment leaves nothing behind, since an unnamed file disappears with its last
//! descriptor. Where `O_TMPFILE` or `/proc` is missing, a named `.stabound-*.part` file
//! stands in; an interrupt handler calling [`stop_writes`] removes it, SIGKILL cannot.
//!
//! New files get mode `0666 & !umask`, as a shell redirect would give; a replaced file keeps
//! its mode.

use std::fs::File;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Mutex, MutexGuard};

/// The named temporary files being written right now (see [`stop_writes`]).
static PARTIAL_FILES: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Set once every output of the run is in place: an interrupt after that changes nothing,
/// and the run ends normally.
static COMMITTED: AtomicBool = AtomicBool::new(false);

fn partial_files() -> MutexGuard<'static, Vec<PathBuf>> {
    // a panic while holding the lock leaves the list itself valid
    PARTIAL_FILES
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// For an interrupt handler. Before the outputs are committed: stops every write of the
/// process for good, deletes the named temporary files, then runs `then` (typically
/// `std::process::exit`) with writes still stopped, so no output file can appear half
/// written or be put into place. After [`commit`] succeeded: does nothing and returns
/// `None`, so the run finishes normally with its outputs in place.
pub fn stop_writes<R>(then: impl FnOnce() -> R) -> Option<R> {
    let mut live = partial_files();
    if COMMITTED.load(Ordering::SeqCst) {
        return None;
    }
    for p in live.drain(..) {
        let _ = std::fs::remove_file(p);
    }
    Some(then())
}

/// The mode of a new file before the umask: `rw-rw-rw-`, as `open(2)` from a shell redirect.
#[cfg(unix)]
const NEW_FILE_MODE: u32 = 0o666;

/// A file written in full to a temporary place, waiting for [`commit`] to give it its name.
pub struct Pending {
    file: File,
    /// The final name (symbolic links already resolved).
    path: PathBuf,
    /// The directory of `path`, where the temporary file lives.
    dir: PathBuf,
    /// The temporary file's name when it has one (no `O_TMPFILE` support).
    named: Option<tempfile::TempPath>,
}

fn fail(path: &Path, what: &str, e: impl std::fmt::Display) -> anyhow::Error {
    anyhow::anyhow!("cannot write {}: {what}: {e}", path.display())
}

/// Writes `parts` in order into a temporary file in `dir` (the directory of `path`), with
/// mode `mode` (that of the file it replaces) or `0666 & !umask`, flushed to disk.
pub fn prepare<B: AsRef<[u8]>>(
    path: &Path,
    dir: &Path,
    mode: Option<u32>,
    parts: &[B],
) -> anyhow::Result<Pending> {
    let mut pending = start(path, dir)?;
    for part in parts {
        pending.write_all(part.as_ref())?;
    }
    pending.seal(mode)?;
    Ok(pending)
}

/// An empty temporary file in `dir` for the final name `path`, to be written with
/// [`Pending::write_all`] as the data is produced, then [`Pending::seal`]ed and given to
/// [`commit`]. Until then an interrupt or a failure leaves nothing behind (see the module
/// documentation).
pub fn start(path: &Path, dir: &Path) -> anyhow::Result<Pending> {
    create(path, dir)
}

impl Pending {
    /// Appends `bytes` to the temporary file. The error names the final file; its kind is
    /// that of the system's error.
    pub fn write_all(&mut self, bytes: &[u8]) -> std::io::Result<()> {
        self.file.write_all(bytes).map_err(|e| {
            std::io::Error::new(
                e.kind(),
                format!("cannot write {}: writing: {e}", self.path.display()),
            )
        })
    }

    /// Gives the file mode `mode` (that of the file it replaces) or leaves `0666 & !umask`,
    /// and flushes it to disk: the file is then ready for [`commit`].
    pub fn seal(&mut self, mode: Option<u32>) -> anyhow::Result<()> {
        #[cfg(unix)]
        if let Some(m) = mode {
            use std::os::unix::fs::PermissionsExt;
            self.file
                .set_permissions(std::fs::Permissions::from_mode(m))
                .map_err(|e| fail(&self.path, "setting permissions", e))?;
        }
        #[cfg(not(unix))]
        let _ = mode;
        self.file
            .sync_all()
            .map_err(|e| fail(&self.path, "syncing", e))
    }
}

/// Checks that a file can be created in `dir`, by creating a temporary one and removing it
/// (unnamed where the system has them, so not even SIGKILL can leave it behind).
pub fn probe(dir: &Path) -> anyhow::Result<()> {
    let p = create(dir, dir)?;
    if let Some(named) = p.named {
        let tmp = named.to_path_buf();
        let mut live = partial_files();
        drop(named);
        live.retain(|q| q != &tmp);
    }
    Ok(())
}

/// An unnamed temporary file where the system has them, a named one otherwise.
fn create(path: &Path, dir: &Path) -> anyhow::Result<Pending> {
    create_with(path, dir, true)
}

/// [`create`], with unnamed files only when `unnamed` (tests pass `false` for the named path).
fn create_with(path: &Path, dir: &Path, unnamed: bool) -> anyhow::Result<Pending> {
    #[cfg(target_os = "linux")]
    if unnamed && Path::new("/proc/self/fd").is_dir() {
        use std::os::unix::fs::OpenOptionsExt;
        match std::fs::OpenOptions::new()
            .read(true)
            .write(true)
            .custom_flags(nix::libc::O_TMPFILE)
            .mode(NEW_FILE_MODE)
            .open(dir)
        {
            Ok(file) => {
                return Ok(Pending {
                    file,
                    path: path.to_path_buf(),
                    dir: dir.to_path_buf(),
                    named: None,
                });
            }
            // file systems and kernels without O_TMPFILE: fall back to a named file
            Err(e)
                if matches!(
                    e.raw_os_error(),
                    Some(nix::libc::EOPNOTSUPP | nix::libc::EISDIR | nix::libc::EINVAL)
                ) => {}
            Err(e) => return Err(fail(path, "creating a temporary file", e)),
        }
    }
    // created and registered under the lock, so an interrupt cannot fall in between
    let mut live = partial_files();
    let mut builder = tempfile::Builder::new();
    builder.prefix(".stabound-").suffix(".part");
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        // passed to open(2), which applies the umask
        builder.permissions(std::fs::Permissions::from_mode(NEW_FILE_MODE));
    }
    let tmp = builder
        .tempfile_in(dir)
        .map_err(|e| fail(path, "creating a temporary file", e))?;
    live.push(tmp.path().to_path_buf());
    let (file, named) = tmp.into_parts();
    Ok(Pending {
        file,
        path: path.to_path_buf(),
        dir: dir.to_path_buf(),
        named: Some(named),
    })
}

/// Gives every pending file its final name, under the lock the interrupt handler takes: an
/// interrupt comes either before (no new file in place, temporary files removed) or after
/// (every file in place, and the run ends normally with exit 0).
pub fn commit(pending: Vec<Pending>) -> anyhow::Result<()> {
    let mut live = partial_files();
    for p in pending {
        let Pending {
            file,
            path,
            dir,
            named,
        } = p;
        match named {
            Some(tmp) => {
                let tmp_path = tmp.to_path_buf();
                let result = tmp
                    .persist(&path)
                    .map_err(|e| fail(&path, "renaming the temporary file", e.error));
                live.retain(|q| q != &tmp_path);
                result?;
            }
            None => link_in(&file, &path, &dir, &mut live)?,
        }
        drop(file);
    }
    COMMITTED.store(true, Ordering::SeqCst);
    Ok(())
}

/// Links the unnamed file `file` in at `path`: directly when the name is free, else under a
/// temporary name in `dir` renamed over the old file (registered in `live` meanwhile).
#[cfg(target_os = "linux")]
fn link_in(file: &File, path: &Path, dir: &Path, live: &mut Vec<PathBuf>) -> anyhow::Result<()> {
    use nix::fcntl::{AT_FDCWD, AtFlags};
    use std::os::fd::AsRawFd;
    let proc_path = PathBuf::from(format!("/proc/self/fd/{}", file.as_raw_fd()));
    let link = |to: &Path| {
        nix::unistd::linkat(
            AT_FDCWD,
            &proc_path,
            AT_FDCWD,
            to,
            AtFlags::AT_SYMLINK_FOLLOW,
        )
    };
    match link(path) {
        Ok(()) => return Ok(()),
        Err(nix::errno::Errno::EEXIST) => {}
        Err(e) => return Err(fail(path, "linking the new file into place", e)),
    }
    // the name is taken (the old file): link under a fresh temporary name, then rename
    for attempt in 0u32.. {
        let tmp = dir.join(format!(".stabound-{}-{attempt}.part", std::process::id()));
        match link(&tmp) {
            Ok(()) => {
                live.push(tmp.clone());
                let result = std::fs::rename(&tmp, path)
                    .map_err(|e| fail(path, "renaming the temporary file", e));
                if result.is_err() {
                    let _ = std::fs::remove_file(&tmp);
                }
                live.retain(|q| q != &tmp);
                return result;
            }
            Err(nix::errno::Errno::EEXIST) if attempt < 100 => {}
            Err(e) => return Err(fail(path, "linking the new file", e)),
        }
    }
    unreachable!("the loop returns")
}

#[cfg(not(target_os = "linux"))]
fn link_in(_: &File, path: &Path, _: &Path, _: &mut Vec<PathBuf>) -> anyhow::Result<()> {
    Err(fail(
        path,
        "linking",
        "unnamed files are only made on Linux",
    ))
}

/// Writes `bytes` to the regular file (or new name) `path` whole or not at all: prepare and
/// commit in one step, for tests.
#[cfg(test)]
pub fn write_atomic(path: &Path, bytes: &[u8]) -> anyhow::Result<()> {
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    #[cfg(unix)]
    let mode = {
        use std::os::unix::fs::PermissionsExt;
        std::fs::metadata(path)
            .ok()
            .filter(std::fs::Metadata::is_file)
            .map(|m| m.permissions().mode() & 0o7777)
    };
    #[cfg(not(unix))]
    let mode = None;
    let p = prepare(path, dir, mode, &[bytes])?;
    let r = commit(vec![p]);
    COMMITTED.store(false, Ordering::SeqCst);
    r
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
    fn replaced_files_keep_mode() {
        use std::os::unix::fs::PermissionsExt;
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("out.csv");
        write_atomic(&p, b"1\n").unwrap();
        let mode = |p: &Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o777;
        std::fs::set_permissions(&p, std::fs::Permissions::from_mode(0o640)).unwrap();
        write_atomic(&p, b"2\n").unwrap();
        assert_eq!(mode(&p), 0o640);
        assert_eq!(std::fs::read(&p).unwrap(), b"2\n");
    }

    /// The named fallback (file systems without O_TMPFILE): the same whole file, the mode
    /// of the replaced file, and no `.part` file left.
    #[cfg(unix)]
    #[test]
    fn named_fallback_writes_whole_file() {
        use std::os::unix::fs::PermissionsExt;
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("out.csv");
        std::fs::write(&p, b"old\n").unwrap();
        std::fs::set_permissions(&p, std::fs::Permissions::from_mode(0o640)).unwrap();
        let mut pending = create_with(&p, dir.path(), false).unwrap();
        assert!(pending.named.is_some());
        pending.file.write_all(b"new\n").unwrap();
        pending
            .file
            .set_permissions(std::fs::Permissions::from_mode(0o640))
            .unwrap();
        commit(vec![pending]).unwrap();
        COMMITTED.store(false, Ordering::SeqCst);
        assert_eq!(std::fs::read(&p).unwrap(), b"new\n");
        let mode = std::fs::metadata(&p).unwrap().permissions().mode() & 0o777;
        assert_eq!(mode, 0o640);
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
    }

    #[test]
    fn unwritable_directory_is_an_error() {
        let err = write_atomic(Path::new("/nonexistent-dir/x.csv"), b"x").unwrap_err();
        assert!(err.to_string().contains("/nonexistent-dir/x.csv"), "{err}");
    }
}
