//! Where results go: stdout by default, or a file written whole or not at all; and what
//! happens on an interrupt.

use std::io::Write;
use std::path::Path;

/// Writes `bytes` to `path` atomically, or to stdout when `path` is `None`.
///
/// A broken pipe on stdout comes back as an `io::Error` of kind `BrokenPipe`, which
/// [`super::report`] turns into exit code 0.
pub fn emit(path: Option<&Path>, bytes: &[u8]) -> anyhow::Result<()> {
    emit_parts(path, &[bytes])
}

/// [`emit`] for data held in consecutive parts, written in order without joining them.
pub fn emit_parts<B: AsRef<[u8]>>(path: Option<&Path>, parts: &[B]) -> anyhow::Result<()> {
    match path {
        Some(p) => Ok(super::atomic::write_atomic_parts(p, parts)?),
        None => {
            let mut out = std::io::stdout().lock();
            for part in parts {
                out.write_all(part.as_ref())?;
            }
            out.flush()?;
            Ok(())
        }
    }
}

/// Exit code after an interrupt (SIGINT, SIGTERM or SIGHUP): 128 + SIGINT, as shells report
/// Ctrl-C.
pub const INTERRUPTED: i32 = 130;

/// On SIGINT, SIGTERM or SIGHUP (Ctrl-C, `kill`, Slurm's `scancel` or time limit): removes
/// the temporary file of any output being written, so that no `.stabound-*.part` file is
/// left and no output file appears half written, then exits with [`INTERRUPTED`]. The
/// handler runs on its own thread (the `ctrlc` crate), so it may take the lock that
/// `atomic::write_atomic` holds while renaming.
pub fn on_interrupt_clean_up() {
    // failing to install (a handler already set) only loses the clean-up, not correctness
    // of complete outputs, so it is not an error
    let _ = ctrlc::set_handler(|| super::atomic::stop_writes(|| std::process::exit(INTERRUPTED)));
}
