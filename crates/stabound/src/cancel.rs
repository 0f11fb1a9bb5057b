//! Stopping a long computation: a [`Cancel`] holds a flag and an optional deadline, and the
//! engines poll every installed one in their main loops (boundary tracing and bisection,
//! `alpha_max` and its tables, passivity, the robust searches), returning
//! [`Error::Cancelled`] soon after it is cancelled or its time runs out.
//!
//! A `Cancel` acts while it is installed. [`Cancel::scope`] installs it process-wide, so the
//! worker threads of a parallel engine see it too, and so does every other computation
//! running in the process meanwhile; [`Cancel::scope_on_own_threads`] runs the work on
//! threads of its own, and only they see it (a server answering several requests side by
//! side, each under its own time limit). Until one fires a poll is two relaxed
//! atomic loads (a deadline is watched by a thread of its own, which raises the flag), so
//! the engines run as fast as without it.
//!
//! ```
//! use std::time::Duration;
//! use stabound::{Cancel, Error, alpha_max, AmaxOptions, Plant};
//!
//! let plant = Plant::new(0.5, 1.0)?;
//! // cancelled before the work starts: the engine stops at its first poll
//! let cancel = Cancel::new();
//! cancel.cancel();
//! let stopped = cancel.scope(|| stabound::amax::amax_table(
//!     &[0.5, 1.0],
//!     &[1.0, 2.0],
//!     &stabound::amax::TableOptions::default(),
//! ));
//! assert!(matches!(stopped, Err(Error::Cancelled { time_limit: None })));
//! // a generous time limit changes nothing
//! let ample = Cancel::with_time_limit(Duration::from_secs(600));
//! let m = ample.scope(|| alpha_max(plant, &AmaxOptions::default()))?;
//! assert_eq!(m, alpha_max(plant, &AmaxOptions::default())?);
//! # Ok::<(), stabound::Error>(())
//! ```
//!
//! A request that runs for minutes (the passive region to a tolerance of `1e-12`) ends
//! soon after its time limit:
//!
//! ```
//! use std::time::{Duration, Instant};
//! use stabound::{Cancel, Error, VelocityFilter, passivity::compare};
//!
//! let start = Instant::now();
//! let limit = Cancel::with_time_limit(Duration::from_millis(200));
//! let r = limit.scope(|| compare(0.5, 1.0, VelocityFilter::none(), 1e-12));
//! assert!(matches!(r, Err(Error::Cancelled { time_limit: Some(_) })));
//! // the stop comes at the next poll: well before the minutes the request needs
//! assert!(start.elapsed() < Duration::from_secs(60));
//! ```

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, PoisonError, RwLock};
use std::time::{Duration, Instant};

use crate::error::{Error, Result};

/// A flag and an optional deadline that stop the engines while installed
/// ([`Cancel::scope`]). Clones share the flag: cancel one from another thread (an interrupt
/// handler, a user interface) to stop the computation running under another.
#[derive(Debug, Clone, Default)]
pub struct Cancel {
    inner: Arc<Inner>,
}

#[derive(Debug, Default)]
struct Inner {
    cancelled: AtomicBool,
    /// When the time runs out, and the limit it was set from (for the message).
    deadline: Option<(Instant, Duration)>,
}

/// How many [`Cancel`]s are installed: zero lets a poll return at once.
static INSTALLED: AtomicUsize = AtomicUsize::new(0);

/// Raised when a [`Cancel`] is cancelled or its deadline passes: only then does a poll look
/// at the installed ones. Lowered when the last installation ends.
static TRIPPED: AtomicBool = AtomicBool::new(false);

/// The [`Cancel`]s installed process-wide, innermost last.
static ACTIVE: RwLock<Vec<Arc<Inner>>> = RwLock::new(Vec::new());

thread_local! {
    /// The [`Cancel`] of the threads of [`Cancel::scope_on_own_threads`], set on each of
    /// them as it starts.
    static OWN: std::cell::RefCell<Option<Arc<Inner>>> = const { std::cell::RefCell::new(None) };
}

impl Cancel {
    /// A `Cancel` without a deadline: it stops the engines only once [`Cancel::cancel`] is
    /// called.
    pub fn new() -> Self {
        Self::default()
    }

    /// A `Cancel` whose time runs out `limit` from now (a limit too far ahead to represent
    /// never runs out).
    ///
    /// ```
    /// use std::time::Duration;
    /// let c = stabound::Cancel::with_time_limit(Duration::ZERO);
    /// assert!(c.is_cancelled());
    /// assert!(matches!(c.check(), Err(stabound::Error::Cancelled { time_limit: Some(_) })));
    /// ```
    pub fn with_time_limit(limit: Duration) -> Self {
        Self {
            inner: Arc::new(Inner {
                cancelled: AtomicBool::new(false),
                deadline: Instant::now().checked_add(limit).map(|at| (at, limit)),
            }),
        }
    }

    /// Stops every computation polling this `Cancel` (or a clone of it), from any thread.
    pub fn cancel(&self) {
        self.inner.cancelled.store(true, Ordering::Relaxed);
        TRIPPED.store(true, Ordering::Relaxed);
    }

    /// Whether it was cancelled or its time has run out.
    pub fn is_cancelled(&self) -> bool {
        self.inner.check().is_err()
    }

    /// [`Error::Cancelled`] once cancelled or past the deadline, else `Ok(())`: for loops of
    /// one's own around the engines.
    ///
    /// ```
    /// let c = stabound::Cancel::new();
    /// assert!(c.check().is_ok());
    /// c.clone().cancel();
    /// assert!(c.check().is_err());
    /// ```
    pub fn check(&self) -> Result<()> {
        self.inner.check()
    }

    /// Runs `f` with this `Cancel` installed: every engine `f` calls (on any thread) polls it
    /// and returns [`Error::Cancelled`] soon after it is cancelled or its time runs out.
    /// Installations nest; each ends with its scope, also when `f` panics.
    pub fn scope<R>(&self, f: impl FnOnce() -> R) -> R {
        let installed = self.install(true);
        let out = f();
        drop(installed);
        out
    }

    /// Runs `f` on a thread pool of its own (`threads` threads; 0: one per core) whose
    /// threads alone poll this `Cancel`: when it fires, the engines `f` calls stop, and
    /// computations running meanwhile on other threads go on. The parallel engines `f`
    /// calls run on that pool, so `f` also shares no worker with them.
    ///
    /// ```
    /// use stabound::{Cancel, Error, alpha_max, AmaxOptions, Plant};
    ///
    /// let plant = Plant::new(0.5, 1.0)?;
    /// let stopped = Cancel::new();
    /// stopped.cancel();
    /// // a cancelled computation on its own threads, another one beside it
    /// let (own, beside) = rayon::join(
    ///     || stopped.scope_on_own_threads(1, || {
    ///         stabound::amax::amax_table(&[0.5, 1.0], &[1.0, 2.0], &Default::default())
    ///     }),
    ///     || alpha_max(plant, &AmaxOptions::default()),
    /// );
    /// assert!(matches!(own, Ok(Err(Error::Cancelled { time_limit: None }))));
    /// assert!(beside.is_ok());
    /// # Ok::<(), stabound::Error>(())
    /// ```
    ///
    /// # Errors
    ///
    /// [`Error::Io`] when the threads cannot be started (too little memory, a limit on the
    /// number of threads); `f` has not run then.
    pub fn scope_on_own_threads<R: Send>(
        &self,
        threads: usize,
        f: impl FnOnce() -> R + Send,
    ) -> Result<R> {
        let inner = self.inner.clone();
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .start_handler(move |_| OWN.with(|own| *own.borrow_mut() = Some(inner.clone())))
            .build()
            .map_err(|e| {
                Error::Io(format!(
                    "cannot start the threads of a computation ({e}); free memory or threads, or run fewer computations at once"
                ))
            })?;
        let installed = self.install(false);
        let out = pool.install(f);
        drop(installed);
        Ok(out)
    }

    /// Installs this `Cancel` (process-wide when `global`, else counted only, for the
    /// threads that carry it in [`OWN`]) and starts the watch of its deadline; the
    /// installation ends when the value returned is dropped.
    fn install(&self, global: bool) -> Installed {
        let mut installed = {
            let mut active = ACTIVE.write().unwrap_or_else(PoisonError::into_inner);
            if global {
                active.push(self.inner.clone());
            }
            INSTALLED.fetch_add(1, Ordering::SeqCst);
            Installed {
                inner: global.then(|| self.inner.clone()),
                watch: None,
            }
        };
        if self.inner.cancelled.load(Ordering::Relaxed) {
            TRIPPED.store(true, Ordering::SeqCst);
        }
        if let Some((at, _)) = self.inner.deadline {
            let done = Arc::new(AtomicBool::new(false));
            let until = done.clone();
            let watch = move || {
                while !until.load(Ordering::SeqCst) {
                    let now = Instant::now();
                    if now >= at {
                        TRIPPED.store(true, Ordering::SeqCst);
                        return;
                    }
                    std::thread::park_timeout(at - now);
                }
            };
            match std::thread::Builder::new()
                .name("deadline".into())
                .spawn(watch)
            {
                Ok(h) => installed.watch = Some((h.thread().clone(), done)),
                // without a watch every poll reads the clock: slower, still stopping
                Err(_) => TRIPPED.store(true, Ordering::SeqCst),
            }
        }
        installed
    }
}

/// One installation of a [`Cancel`], ended when dropped (also when the work panics).
struct Installed {
    /// The `Cancel` when installed process-wide (in [`ACTIVE`]).
    inner: Option<Arc<Inner>>,
    /// The thread raising [`TRIPPED`] at the deadline, told to end with the scope.
    watch: Option<(std::thread::Thread, Arc<AtomicBool>)>,
}

impl Drop for Installed {
    fn drop(&mut self) {
        if let Some((thread, done)) = &self.watch {
            done.store(true, Ordering::SeqCst);
            thread.unpark();
        }
        let mut active = ACTIVE.write().unwrap_or_else(PoisonError::into_inner);
        if let Some(inner) = &self.inner
            && let Some(i) = active.iter().rposition(|c| Arc::ptr_eq(c, inner))
        {
            active.remove(i);
        }
        // under the lock, so that an installation beginning meanwhile counts itself after
        if INSTALLED.fetch_sub(1, Ordering::SeqCst) == 1 {
            TRIPPED.store(false, Ordering::SeqCst);
        }
    }
}

impl Inner {
    fn check(&self) -> Result<()> {
        if self.cancelled.load(Ordering::Relaxed) {
            return Err(Error::Cancelled { time_limit: None });
        }
        match self.deadline {
            Some((at, limit)) if Instant::now() >= at => Err(Error::Cancelled {
                time_limit: Some(limit.as_secs_f64()),
            }),
            _ => Ok(()),
        }
    }
}

/// The engines' poll, also for loops of one's own around them: [`Error::Cancelled`] when an
/// installed [`Cancel`] is cancelled or past its deadline. Two relaxed atomic loads until
/// one of them fires (then a shared lock and a clock read), so it may sit in any loop whose
/// pass does a point test.
///
/// ```
/// use stabound::cancel::{Cancel, poll};
/// assert!(poll().is_ok());
/// let c = Cancel::new();
/// let walls_done = c.scope(|| {
///     let mut n = 0;
///     for _ in 0..10 {
///         if poll().is_err() {
///             break;
///         }
///         n += 1;
///         if n == 3 {
///             c.cancel();
///         }
///     }
///     n
/// });
/// assert_eq!(walls_done, 3);
/// ```
#[inline]
pub fn poll() -> Result<()> {
    if INSTALLED.load(Ordering::Relaxed) == 0 || !TRIPPED.load(Ordering::Relaxed) {
        return Ok(());
    }
    ACTIVE
        .read()
        .unwrap_or_else(PoisonError::into_inner)
        .iter()
        .try_for_each(|c| c.check())?;
    OWN.with(|own| own.borrow().as_ref().map_or(Ok(()), |c| c.check()))
}

/// [`poll`] for a predicate that cannot return an error (a point test answering `bool`):
/// `true` once the computation should stop; the caller then answers the cheapest way and
/// its engine returns the error at its next [`poll`].
#[inline]
pub(crate) fn stopped() -> bool {
    poll().is_err()
}

// Installing a cancelled `Cancel` would stop the other tests of this process running at the
// same time: polls of installed ones are tested in the doc examples (a process each) and by
// the command line's time limit.
#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_cancel_is_seen_through_its_clones() {
        let c = Cancel::new();
        assert!(c.check().is_ok());
        let other = c.clone();
        std::thread::scope(|s| s.spawn(|| other.cancel()).join().unwrap());
        assert_eq!(c.check(), Err(Error::Cancelled { time_limit: None }));
    }

    #[test]
    fn a_deadline_runs_out() {
        let c = Cancel::with_time_limit(Duration::from_millis(20));
        assert!(c.check().is_ok());
        std::thread::sleep(Duration::from_millis(30));
        assert!(matches!(
            c.check(),
            Err(Error::Cancelled { time_limit: Some(l) }) if (l - 0.02).abs() < 1e-12
        ));
        // beyond what an Instant can hold: never
        assert!(Cancel::with_time_limit(Duration::MAX).check().is_ok());
    }

    /// A deadline on threads of its own stops the work there, and a poll on any other thread
    /// meanwhile (here the caller's, with the deadline past) still answers `Ok`.
    #[test]
    fn own_threads_alone_see_their_cancel() {
        let limit = Cancel::with_time_limit(Duration::from_millis(50));
        let (stopped_after, outside) = std::thread::scope(|s| {
            let outside = s.spawn(|| {
                std::thread::sleep(Duration::from_millis(200));
                poll()
            });
            let stopped = limit
                .scope_on_own_threads(1, || {
                    let start = Instant::now();
                    while poll().is_ok() {
                        std::thread::sleep(Duration::from_millis(1));
                        // a poll that never fires would fail the test rather than hang it
                        if start.elapsed() > Duration::from_secs(60) {
                            break;
                        }
                    }
                    start.elapsed()
                })
                .unwrap();
            (stopped, outside.join().unwrap())
        });
        assert!(stopped_after < Duration::from_secs(60));
        assert!(outside.is_ok());
        // and once the scope has ended, the polls of this thread are as before
        assert!(poll().is_ok());
    }

    #[test]
    fn a_scope_ends_also_on_panic() {
        let c = Cancel::new();
        let installed = |c: &Cancel| {
            let active = ACTIVE.read().unwrap_or_else(PoisonError::into_inner);
            active.iter().any(|i| Arc::ptr_eq(i, &c.inner))
        };
        assert!(c.scope(|| installed(&c) && poll().is_ok()));
        assert!(!installed(&c));
        let caught = std::panic::catch_unwind(|| c.scope(|| panic!("inside")));
        assert!(caught.is_err());
        assert!(!installed(&c));
    }
}
