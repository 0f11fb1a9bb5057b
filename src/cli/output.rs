//! Where results go: stdout by default, or a file written whole or not at all.

use std::io::Write;
use std::path::Path;

/// Writes `bytes` to `path` atomically, or to stdout when `path` is `None`.
///
/// A broken pipe on stdout comes back as an `io::Error` of kind `BrokenPipe`, which
/// [`super::report`] turns into exit code 0.
pub fn emit(path: Option<&Path>, bytes: &[u8]) -> anyhow::Result<()> {
    match path {
        Some(p) => Ok(stabound::export::write_atomic(p, bytes)?),
        None => {
            let mut out = std::io::stdout().lock();
            out.write_all(bytes)?;
            out.flush()?;
            Ok(())
        }
    }
}
