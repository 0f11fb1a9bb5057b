//! Work off the calling thread that reacts to Ctrl-C.
//!
//! A computation runs on its own thread (its parallel parts on rayon's pool) while the
//! calling thread, with the interpreter detached, waits for it in short slices and runs
//! Python's signal handlers between them: Ctrl-C raises `KeyboardInterrupt` within a slice.
//! Per-element work stops at the next element (it watches the cancel flag); a single long
//! library call finishes on its thread, its result discarded. A computation that stops
//! without a result (a panic) is reported as `StaboundError`, never as a panic.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{RecvTimeoutError, sync_channel};
use std::time::Duration;

use pyo3::prelude::*;
use rayon::prelude::*;

use crate::StaboundError;

/// How often the waiting thread looks for Ctrl-C: well under the human reaction time, and
/// a few hundred wake-ups per minute cost nothing measurable.
const SLICE: Duration = Duration::from_millis(40);

/// `f(cancel)` on its own thread, with Ctrl-C watched (module docs).
pub fn interruptible<R, F>(py: Python<'_>, f: F) -> PyResult<R>
where
    R: Send + 'static,
    F: FnOnce(&AtomicBool) -> R + Send + 'static,
{
    let cancel = Arc::new(AtomicBool::new(false));
    let (tx, rx) = sync_channel(1);
    let flag = Arc::clone(&cancel);
    std::thread::Builder::new()
        .name("stabound".into())
        .spawn(move || {
            // the receiver may be gone (Ctrl-C): the result is then dropped
            let _ = tx.send(f(&flag));
        })
        .map_err(|e| StaboundError::new_err(format!("cannot start the computation: {e}")))?;
    let mut rx = rx;
    loop {
        // the receiver moves in and out: it is Send, not Sync
        let (got, back) = py.detach(move || (rx.recv_timeout(SLICE), rx));
        rx = back;
        match got {
            Ok(r) => return Ok(r),
            Err(RecvTimeoutError::Timeout) => {
                if let Err(e) = py.check_signals() {
                    cancel.store(true, Ordering::Relaxed);
                    return Err(e);
                }
            }
            Err(RecvTimeoutError::Disconnected) => {
                return Err(StaboundError::new_err(
                    "the computation stopped without a result (an internal error); please report it with the call that caused it",
                ));
            }
        }
    }
}

/// The library's error for a computation cut short by Ctrl-C (never seen by the caller:
/// the interrupt is raised instead).
fn cancelled() -> stabound::Error {
    stabound::Error::InvalidRequest("interrupted".into())
}

/// `f` of every item in parallel, in input order; each item starts only while `cancel` is
/// clear. On error: the index and error of the first failing item in input order.
pub fn par_map<T, R, F>(
    items: &[T],
    cancel: &AtomicBool,
    f: F,
) -> Result<Vec<R>, (usize, stabound::Error)>
where
    T: Sync,
    R: Send,
    F: Fn(&T) -> stabound::Result<R> + Sync,
{
    let out: Vec<stabound::Result<R>> = items
        .par_iter()
        .map(|x| {
            if cancel.load(Ordering::Relaxed) {
                Err(cancelled())
            } else {
                f(x)
            }
        })
        .collect();
    first_error(out)
}

/// All the values, or the index and error of the first failure in order.
pub fn first_error<R>(out: Vec<stabound::Result<R>>) -> Result<Vec<R>, (usize, stabound::Error)> {
    let mut values = Vec::with_capacity(out.len());
    for (i, r) in out.into_iter().enumerate() {
        values.push(r.map_err(|e| (i, e))?);
    }
    Ok(values)
}
