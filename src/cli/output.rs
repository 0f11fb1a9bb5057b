//! Where results go: stdout, or files written whole or not at all; every output path checked
//! before any work, in [`Plan::check`]; and what happens at start-up and on an interrupt.
//!
//! The rules for a file given as an output (`-o`, `--svg`, `figure --out`):
//!
//! - A symbolic link is written through: the file it points to is replaced (atomically,
//!   in that file's directory); the link itself stays.
//! - A character device (`/dev/null`, a terminal) or a FIFO with a reader is written
//!   directly, like stdout; a FIFO without a reader, a block device, a socket or a directory
//!   is refused.
//! - An existing file without write permission is refused, and so is a file in a directory
//!   that does not exist or cannot be written.
//! - Two outputs naming the same file (even through different spellings or links), or an
//!   output naming one of the input files, are refused.
//!
//! Each refusal is bad input (exit 2) and happens before any computation.

use std::fs::File;
use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use stabound::export::csv::CsvWriter;
use stabound::export::json::JsonRows;

use super::UsageError;
use super::atomic::{self, Pending};

/// Exit code after an interrupt (SIGINT, SIGTERM or SIGHUP): 128 + SIGINT, as shells report
/// Ctrl-C.
pub const INTERRUPTED: i32 = 130;

/// Whether file descriptor 1 was closed when the process started (`stabound ... >&-`).
static STDOUT_CLOSED: AtomicBool = AtomicBool::new(false);

/// Records whether stdout is closed, run by the C runtime before `main`: the Rust runtime
/// reopens closed standard descriptors on `/dev/null` before `main` runs (so that no file
/// opened later takes their number), after which writes to a closed stdout would vanish
/// without an error.
#[cfg(target_os = "linux")]
extern "C" fn record_closed_stdout() {
    // SAFETY: F_GETFD only queries the descriptor's flags; it fails with EBADF when closed.
    let closed = unsafe { nix::libc::fcntl(1, nix::libc::F_GETFD) } == -1;
    STDOUT_CLOSED.store(closed, Ordering::SeqCst);
}

#[cfg(target_os = "linux")]
#[used]
// SAFETY: a function pointer in .init_array is called once by the C runtime before main,
// with no arguments; the function only reads a descriptor's flags and stores an atomic.
#[unsafe(link_section = ".init_array")]
static RECORD_CLOSED_STDOUT: extern "C" fn() = record_closed_stdout;

/// Start-up, before any work:
///
/// - a run that would write its data to a closed stdout fails (exit 1) before any work
///   (see [`Plan::check`]);
/// - SIGXFSZ (a file size limit, `ulimit -f`) is ignored, so an oversized write fails with
///   an error message instead of killing the process;
/// - the worker threads are started, failing cleanly (exit 1) when they cannot be;
/// - on SIGINT, SIGTERM or SIGHUP (Ctrl-C, `kill`, Slurm's `scancel` or time limit) the
///   process removes any named temporary file of an output being written and exits with
///   [`INTERRUPTED`], unless every output is already in place, in which case the run ends
///   normally. The handler runs on its own thread (the `ctrlc` crate), so it may take the
///   lock that `atomic::commit` holds while putting the files in place.
pub fn init() -> anyhow::Result<()> {
    #[cfg(unix)]
    // SAFETY: installs SIG_IGN, no handler code.
    unsafe {
        let _ = nix::sys::signal::signal(
            nix::sys::signal::Signal::SIGXFSZ,
            nix::sys::signal::SigHandler::SigIgn,
        );
    }
    // two threads beside the pool's: the interrupt handler's and the time limit's watch
    super::threads::start(2)?;
    // failing to install (no thread for the handler) only loses the clean-up of named
    // temporary files, not the correctness of complete outputs, so it is not an error
    let _ = ctrlc::set_handler(|| {
        // the engines stop at their next poll and the run ends with the interrupt's exit
        // status ([`super::report`]); a computation without polls is ended after a moment
        if let Some(c) = RUN.get() {
            c.cancel();
            std::thread::sleep(INTERRUPT_GRACE);
        }
        let _ = atomic::stop_writes(|| std::process::exit(INTERRUPTED));
    });
    Ok(())
}

/// The run's [`stabound::Cancel`]: cancelled by an interrupt, with the time limit as its
/// deadline; installed around the subcommand ([`limited`]).
static RUN: std::sync::OnceLock<stabound::Cancel> = std::sync::OnceLock::new();

/// How long an interrupt lets the engines stop at their next poll before the process ends
/// regardless (a step without polls: a long simulation, a write to a stalled pipe).
const INTERRUPT_GRACE: Duration = Duration::from_millis(500);

/// How long past the time limit the engines have to stop at their next poll before the
/// process ends regardless.
const LIMIT_GRACE: Duration = Duration::from_secs(2);

/// The time limit of a run whose stderr is not a terminal and that gives no
/// `--time-limit`: a batch job or a script waits at most this long for an answer.
pub const DEFAULT_TIME_LIMIT: Duration = Duration::from_secs(600);

/// Whether the run's time limit is the default one (for the message when it runs out).
static DEFAULT_LIMIT: AtomicBool = AtomicBool::new(false);

/// Runs `work` with the run's [`stabound::Cancel`] installed: the engines return
/// [`stabound::Error::Cancelled`] on an interrupt or once `limit` has passed (`None`: no
/// limit), which [`super::report`] turns into the exit status. A watch thread ends the
/// process shortly after the limit if the work has not stopped by then (as an interrupt
/// does: no output file half written or put in place).
pub fn limited<T>(limit: Option<Duration>, default: bool, work: impl FnOnce() -> T) -> T {
    DEFAULT_LIMIT.store(default, Ordering::Relaxed);
    let cancel = RUN.get_or_init(|| match limit {
        Some(l) => stabound::Cancel::with_time_limit(l),
        None => stabound::Cancel::new(),
    });
    if let Some(l) = limit {
        stop_after(l + LIMIT_GRACE, l);
    }
    cancel.scope(work)
}

/// The message of a run stopped at its time limit of `seconds`.
pub fn time_limit_message(seconds: f64) -> String {
    let which = if DEFAULT_LIMIT.load(Ordering::Relaxed) {
        ", the default when stderr is not a terminal"
    } else {
        ""
    };
    format!(
        "stopped at the time limit (--time-limit {} s{which}) before the run was complete; raise --time-limit (0 for none) or ask for less (a coarser --tol, fewer values, fewer walls)",
        stabound::export::text::Shown(seconds)
    )
}

/// clap value parser of `--time-limit`: seconds, a finite number at least 0 and at most a
/// year (beyond that `Duration` arithmetic gains nothing); 0 (no limit) is `Duration::ZERO`.
pub fn time_limit(s: &str) -> Result<Duration, String> {
    /// A year in seconds.
    const MAX: f64 = 365.0 * 86_400.0;
    let v = super::args::finite(s)?;
    if !(0.0..=MAX).contains(&v) {
        return Err(format!(
            "'{s}' is no time limit: give seconds from 0 (no limit) to {MAX} (a year)"
        ));
    }
    Ok(Duration::from_secs_f64(v))
}

/// Ends the process at `at` with exit status 1 and the message of a run stopped at its
/// time `limit`, as an interrupt ends it (no output file half written or put in place); a
/// run whose outputs are all in place by then finishes normally. The watch runs on its own
/// thread: a backstop for work that does not poll the run's [`stabound::Cancel`].
fn stop_after(at: Duration, limit: Duration) {
    let watch = move || {
        std::thread::sleep(at);
        let _ = atomic::stop_writes(|| {
            clear_line();
            eprintln!("error: {}", time_limit_message(limit.as_secs_f64()));
            std::process::exit(1)
        });
    };
    // without a thread for the watch the run goes on unlimited: say so rather than fail
    if std::thread::Builder::new()
        .name("time-limit".into())
        .spawn(watch)
        .is_err()
    {
        eprintln!("warning: cannot start the --time-limit watch; the run is not limited");
    }
}

/// Puts the next message on a line of its own, not after a progress bar.
pub fn clear_line() {
    if std::io::stderr().is_terminal() {
        eprint!("\r\x1b[2K");
    }
}

/// A progress bar on stderr that appears only when stderr is a terminal and the work has
/// taken more than a second: counted ([`Progress::new`], [`Progress::tick`]) where the work
/// comes in units, or a spinner with the elapsed time ([`Progress::spinner`]) around one
/// long library call.
pub struct Progress {
    bar: ProgressBar,
    start: Instant,
    shown: Arc<AtomicBool>,
    terminal: bool,
}

/// How long work runs before its progress is shown: shorter work gets no bar.
const SHOW_AFTER: Duration = Duration::from_secs(1);

impl Progress {
    /// A bar of `len` units.
    pub fn new(len: usize) -> Self {
        let bar = ProgressBar::hidden();
        bar.set_length(len as u64);
        Self {
            bar,
            start: Instant::now(),
            shown: Arc::new(AtomicBool::new(false)),
            terminal: std::io::stderr().is_terminal(),
        }
    }

    /// A spinner saying `what` is being computed, with the time it has taken, drawn from a
    /// second on (by a thread of its own: the work gives no ticks).
    pub fn spinner(what: String) -> Self {
        let p = Self::new(0);
        p.bar.set_style(
            ProgressStyle::with_template("{spinner} {msg} ({elapsed})")
                .unwrap_or_else(|_| ProgressStyle::default_spinner()),
        );
        p.bar.set_message(what);
        if p.terminal {
            let (bar, shown) = (p.bar.clone(), p.shown.clone());
            let _ = std::thread::Builder::new().spawn(move || {
                std::thread::sleep(SHOW_AFTER);
                if !bar.is_finished() && !shown.swap(true, Ordering::Relaxed) {
                    bar.set_draw_target(ProgressDrawTarget::stderr());
                    bar.enable_steady_tick(Duration::from_millis(200));
                }
            });
        }
        p
    }

    /// One unit done.
    pub fn tick(&self) {
        self.advance(1);
    }

    /// `n` units done.
    pub fn advance(&self, n: usize) {
        self.bar.inc(n as u64);
        if self.terminal
            && self.start.elapsed() > SHOW_AFTER
            && !self.shown.swap(true, Ordering::Relaxed)
        {
            self.bar.set_draw_target(ProgressDrawTarget::stderr());
        }
    }

    /// Clears the bar (or spinner) off the terminal.
    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }
}

/// One output of a run, as returned by [`Plan::data`] or [`Plan::file`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Slot(usize);

enum Dest {
    Stdout,
    /// A character device or FIFO, opened before the work and written directly.
    Stream(File),
    /// A regular file (existing or new), written whole or not at all.
    File {
        /// The path with every symbolic link resolved.
        real: PathBuf,
        dir: PathBuf,
        /// The mode of the file it replaces.
        mode: Option<u32>,
    },
}

/// The outputs (and inputs) of a run, collected before it is checked.
#[derive(Default)]
pub struct Plan<'a> {
    outs: Vec<(&'a str, Option<&'a Path>)>,
    inputs: Vec<&'a Path>,
}

impl<'a> Plan<'a> {
    /// An empty plan.
    pub fn new() -> Self {
        Self::default()
    }

    /// The run's data: the file given with `flag`, or stdout when `path` is `None`.
    pub fn data(&mut self, flag: &'a str, path: Option<&'a Path>) -> Slot {
        self.outs.push((flag, path));
        Slot(self.outs.len() - 1)
    }

    /// A file given with `flag`.
    pub fn file(&mut self, flag: &'a str, path: &'a Path) -> Slot {
        self.data(flag, Some(path))
    }

    /// A file the run reads, which no output may overwrite.
    pub fn input(&mut self, path: &'a Path) {
        self.inputs.push(path);
    }

    /// Checks every output before any work (see the module documentation for the rules)
    /// and opens the streams among them.
    pub fn check(self) -> anyhow::Result<Outputs> {
        let mut dests = Vec::with_capacity(self.outs.len());
        let mut names = Vec::with_capacity(self.outs.len());
        let mut stdout_closed = None;
        for &(flag, path) in &self.outs {
            let dest = match path {
                None => {
                    if STDOUT_CLOSED.load(Ordering::SeqCst) {
                        stdout_closed = Some(flag);
                    }
                    Dest::Stdout
                }
                Some(p) => resolve(flag, p)?,
            };
            dests.push(dest);
            names.push(path.map(|p| (flag, p)));
        }
        // no two outputs into one file, and no output onto an input
        let ids: Vec<Option<Id>> = dests.iter().map(Id::of).collect();
        for (i, a) in ids.iter().enumerate() {
            let Some(a) = a else { continue };
            for (j, b) in ids.iter().enumerate().take(i) {
                if b.as_ref().is_some_and(|b| a.same(b)) {
                    let ((f1, p1), (f2, p2)) = (names[j].unwrap(), names[i].unwrap());
                    return Err(UsageError(format!(
                        "{f1} {} and {f2} {} are the same file; give different files",
                        p1.display(),
                        p2.display()
                    ))
                    .into());
                }
            }
            for input in &self.inputs {
                if Id::of_input(input).is_some_and(|b| a.same(&b)) {
                    let (f, p) = names[i].unwrap();
                    return Err(UsageError(format!(
                        "{f} {} is the input file {}; writing it would destroy the input: give another file",
                        p.display(),
                        input.display()
                    ))
                    .into());
                }
            }
        }
        // after the files, so that bad input (exit 2) is reported first
        if let Some(flag) = stdout_closed {
            anyhow::bail!(
                "stdout is closed, so the results would be lost; give {flag} FILE or redirect stdout"
            );
        }
        Ok(Outputs {
            dests,
            pending: Vec::new(),
        })
    }
}

/// What makes two outputs the same file: the resolved path, or the device and inode of an
/// existing file (which also catches hard links).
struct Id {
    real: Option<PathBuf>,
    inode: Option<(u64, u64)>,
}

impl Id {
    fn of(d: &Dest) -> Option<Id> {
        match d {
            Dest::File { real, .. } => Some(Id {
                real: Some(real.clone()),
                inode: inode(real),
            }),
            // writing the same character device twice (/dev/null) is harmless
            Dest::Stream(_) | Dest::Stdout => None,
        }
    }

    fn of_input(p: &Path) -> Option<Id> {
        Some(Id {
            real: std::fs::canonicalize(p).ok(),
            inode: inode(p),
        })
    }

    fn same(&self, o: &Id) -> bool {
        (self.real.is_some() && self.real == o.real)
            || (self.inode.is_some() && self.inode == o.inode)
    }
}

#[cfg(unix)]
fn inode(p: &Path) -> Option<(u64, u64)> {
    use std::os::unix::fs::MetadataExt;
    std::fs::metadata(p).ok().map(|m| (m.dev(), m.ino()))
}

#[cfg(not(unix))]
fn inode(_: &Path) -> Option<(u64, u64)> {
    None
}

/// Follows the symbolic links of `p` (at most 40, as the kernel does) to the path that
/// would be written, possibly not existing yet.
fn follow_links(p: &Path) -> std::io::Result<PathBuf> {
    let mut cur = p.to_path_buf();
    for _ in 0..40 {
        match std::fs::symlink_metadata(&cur) {
            Ok(m) if m.file_type().is_symlink() => {
                let to = std::fs::read_link(&cur)?;
                cur = match cur.parent() {
                    Some(dir) if to.is_relative() => dir.join(to),
                    _ => to,
                };
            }
            Ok(_) => return std::fs::canonicalize(&cur),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                let name = cur.file_name().ok_or_else(|| {
                    std::io::Error::new(std::io::ErrorKind::InvalidInput, "no file name")
                })?;
                let dir = match cur.parent() {
                    Some(d) if !d.as_os_str().is_empty() => d,
                    _ => Path::new("."),
                };
                return Ok(std::fs::canonicalize(dir)?.join(name));
            }
            Err(e) => return Err(e),
        }
    }
    Err(std::io::Error::other("too many levels of symbolic links"))
}

/// Checks one output path and decides how it is written.
fn resolve(flag: &str, p: &Path) -> anyhow::Result<Dest> {
    let bad = |why: String| -> anyhow::Error {
        UsageError(format!("{flag} {}: {why}", p.display())).into()
    };
    if p.as_os_str().is_empty() {
        return Err(bad("empty file name".into()));
    }
    match std::fs::metadata(p) {
        Ok(m) if m.is_dir() => Err(bad("is a directory; give a file name".into())),
        Ok(m) if m.is_file() => {
            let real =
                follow_links(p).map_err(|e| bad(format!("cannot resolve the path ({e})")))?;
            if m.permissions().readonly() || !writable(&real) {
                return Err(bad(
                    "the file is read-only; make it writable or give another file".into(),
                ));
            }
            #[cfg(unix)]
            let mode = {
                use std::os::unix::fs::PermissionsExt;
                Some(m.permissions().mode() & 0o7777)
            };
            #[cfg(not(unix))]
            let mode = None;
            in_directory(real, mode, &bad)
        }
        Ok(m) => open_stream(p, &m).map(Dest::Stream).map_err(bad),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            // a new file, or a link to one: the directory must exist and be writable
            let real = match follow_links(p) {
                Ok(r) => r,
                Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                    let dir = real_parent(p);
                    return Err(bad(format!(
                        "directory {} does not exist; create it first",
                        dir.display()
                    )));
                }
                Err(e) => return Err(bad(format!("cannot resolve the path ({e})"))),
            };
            in_directory(real, None, &bad)
        }
        Err(e) => Err(bad(format!("cannot be checked ({e})"))),
    }
}

fn real_parent(p: &Path) -> PathBuf {
    match p.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// A regular file at `real` (links resolved), whose directory must be writable.
fn in_directory(
    real: PathBuf,
    mode: Option<u32>,
    bad: &dyn Fn(String) -> anyhow::Error,
) -> anyhow::Result<Dest> {
    let dir = real_parent(&real);
    if !dir.is_dir() {
        return Err(bad(format!(
            "directory {} does not exist; create it first",
            dir.display()
        )));
    }
    if !writable(&dir) || atomic::probe(&dir).is_err() {
        return Err(bad(format!(
            "no file can be created in directory {}",
            dir.display()
        )));
    }
    Ok(Dest::File { real, dir, mode })
}

/// Whether this process may write `p` (`access(2)`, which also says no on a read-only file
/// system).
#[cfg(unix)]
fn writable(p: &Path) -> bool {
    nix::unistd::access(p, nix::unistd::AccessFlags::W_OK).is_ok()
}

#[cfg(not(unix))]
fn writable(_: &Path) -> bool {
    true
}

/// Opens a character device or a FIFO with a reader for writing; refuses anything else.
#[cfg(unix)]
fn open_stream(p: &Path, m: &std::fs::Metadata) -> Result<File, String> {
    use std::os::unix::fs::{FileTypeExt, OpenOptionsExt};
    let t = m.file_type();
    if t.is_char_device() {
        return std::fs::OpenOptions::new()
            .write(true)
            .open(p)
            .map_err(|e| format!("cannot open the device for writing ({e})"));
    }
    if t.is_fifo() {
        // non-blocking, so that a FIFO nobody reads is refused instead of waited on
        let f = std::fs::OpenOptions::new()
            .write(true)
            .custom_flags(nix::libc::O_NONBLOCK)
            .open(p)
            .map_err(|e| {
                if e.raw_os_error() == Some(nix::libc::ENXIO) {
                    "is a FIFO that nobody reads; start its reader first or give a regular file"
                        .to_string()
                } else {
                    format!("cannot open the FIFO for writing ({e})")
                }
            })?;
        // then blocking again, so that a full pipe waits for its reader
        nix::fcntl::fcntl(
            &f,
            nix::fcntl::FcntlArg::F_SETFL(nix::fcntl::OFlag::empty()),
        )
        .map_err(|e| format!("cannot set up the FIFO ({e})"))?;
        return Ok(f);
    }
    Err("is neither a regular file, a character device nor a FIFO; give a regular file".to_string())
}

#[cfg(not(unix))]
fn open_stream(_: &Path, _: &std::fs::Metadata) -> Result<File, String> {
    Err("is not a regular file; give a regular file".to_string())
}

/// The checked outputs of a run (see [`Plan::check`]).
pub struct Outputs {
    dests: Vec<Dest>,
    pending: Vec<Pending>,
}

impl Outputs {
    /// Writes `bytes` to `slot`.
    pub fn write(&mut self, slot: Slot, bytes: &[u8]) -> anyhow::Result<()> {
        self.write_parts(slot, &[bytes])
    }

    /// Writes data held in consecutive parts to `slot`, in order, without joining them. A
    /// file is prepared in full but put in place only by [`Outputs::finish`]; stdout and
    /// streams are written at once. A broken pipe comes back as an `io::Error` of kind
    /// `BrokenPipe`, which [`super::report`] turns into exit code 0.
    pub fn write_parts<B: AsRef<[u8]>>(&mut self, slot: Slot, parts: &[B]) -> anyhow::Result<()> {
        match &mut self.dests[slot.0] {
            Dest::Stdout => {
                let mut out = std::io::stdout().lock();
                if out.is_terminal() {
                    preview(&mut out, parts)?;
                } else {
                    for part in parts {
                        out.write_all(part.as_ref())?;
                    }
                }
                out.flush()?;
            }
            Dest::Stream(f) => {
                for part in parts {
                    f.write_all(part.as_ref())?;
                }
                f.flush()?;
            }
            Dest::File { real, dir, mode } => {
                let p = atomic::prepare(real, dir, *mode, parts)?;
                self.pending.push(p);
            }
        }
        Ok(())
    }

    /// Opens `slot` for data written as it is produced, through [`Stream`]'s `Write`: a file
    /// goes into its temporary file, given its name only by [`Outputs::finish`] after
    /// [`Outputs::close`] (so it is still written whole or not at all); stdout and streams
    /// are written at once (a terminal gets the same preview as [`Outputs::write_parts`]).
    pub fn stream(&mut self, slot: Slot) -> anyhow::Result<Stream> {
        let to = match &self.dests[slot.0] {
            Dest::Stdout => To::Stdout(std::io::stdout().is_terminal().then(Preview::default)),
            Dest::Stream(f) => To::Stream(
                f.try_clone()
                    .map_err(|e| anyhow::anyhow!("cannot write the output stream: {e}"))?,
            ),
            Dest::File { real, dir, mode } => To::File(atomic::start(real, dir)?, *mode),
        };
        Ok(Stream { to })
    }

    /// Ends a [`Stream`]: flushes it, and readies its file for [`Outputs::finish`].
    pub fn close(&mut self, stream: Stream) -> anyhow::Result<()> {
        match stream.to {
            To::Stdout(preview) => {
                let mut out = std::io::stdout().lock();
                if let Some(p) = preview {
                    p.finish(&mut out)?;
                }
                out.flush()?;
            }
            To::Stream(mut f) => f.flush()?,
            To::File(mut pending, mode) => {
                pending.seal(mode)?;
                self.pending.push(pending);
            }
        }
        Ok(())
    }

    /// Puts every prepared file in place at once: an interrupt before leaves none of them,
    /// an interrupt after changes nothing.
    pub fn finish(self) -> anyhow::Result<()> {
        atomic::commit(self.pending)
    }
}

/// One output being written as the data is produced (see [`Outputs::stream`]).
pub struct Stream {
    to: To,
}

enum To {
    /// With the preview's state when stdout is a terminal.
    Stdout(Option<Preview>),
    Stream(File),
    /// The temporary file and the mode it gets.
    File(Pending, Option<u32>),
}

impl Write for Stream {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.write_all(buf)?;
        Ok(buf.len())
    }

    fn write_all(&mut self, buf: &[u8]) -> std::io::Result<()> {
        match &mut self.to {
            To::Stdout(None) => std::io::stdout().lock().write_all(buf),
            To::Stdout(Some(p)) => p.push(&mut std::io::stdout().lock(), buf),
            To::Stream(f) => f.write_all(buf),
            To::File(pending, _) => pending.write_all(buf),
        }
    }

    fn flush(&mut self) -> std::io::Result<()> {
        match &mut self.to {
            To::Stdout(_) => std::io::stdout().lock().flush(),
            To::Stream(f) => f.flush(),
            To::File(..) => Ok(()),
        }
    }
}

/// Rows of named columns written to a [`Stream`] as they are produced: CSV (the header with
/// the first rows) or one JSON array of objects. Cells go in column order; a row ends after
/// its last column; [`RowStream::flush`] writes what has been formatted, through one reused
/// buffer.
pub struct RowStream {
    stream: Stream,
    csv: Option<CsvWriter>,
    json: Option<(JsonRows, Vec<u8>)>,
    columns: usize,
    col: usize,
    /// A keyed text field for the JSON of the row being written, after its columns.
    extra: Option<(&'static str, String)>,
}

impl RowStream {
    /// Rows of `columns` into `slot`, as JSON when `json`, else CSV.
    pub fn new(
        out: &mut Outputs,
        slot: Slot,
        columns: &[&str],
        json: bool,
    ) -> anyhow::Result<Self> {
        Ok(Self {
            stream: out.stream(slot)?,
            csv: (!json).then(|| CsvWriter::new(columns, 0)),
            json: json.then(|| (JsonRows::new(columns), Vec::new())),
            columns: columns.len(),
            col: 0,
            extra: None,
        })
    }

    fn cell(
        &mut self,
        csv: impl FnOnce(&mut CsvWriter),
        json: impl FnOnce(&JsonRows, &mut Vec<u8>, usize),
    ) {
        if let Some(w) = &mut self.csv {
            csv(w);
        }
        if let Some((w, buf)) = &mut self.json {
            if self.col == 0 {
                w.begin_row(buf);
            }
            json(w, buf, self.col);
            if self.col + 1 == self.columns {
                if let Some((key, text)) = self.extra.take() {
                    // writing to a Vec cannot fail
                    buf.push(b',');
                    let _ = serde_json::to_writer(&mut *buf, key);
                    buf.push(b':');
                    let _ = serde_json::to_writer(&mut *buf, &text);
                }
                w.end_row(buf);
            }
        }
        self.col = (self.col + 1) % self.columns.max(1);
    }

    /// The next cell, a number.
    pub fn num(&mut self, v: f64) {
        self.cell(|w| w.num(v), |w, buf, col| w.num(buf, col, v));
    }

    /// The next cell, text.
    pub fn text(&mut self, s: &str) {
        self.cell(|w| w.text(s), |w, buf, col| w.text(buf, col, s));
    }

    /// A text field `key` in the JSON object of the next row (or the row being written),
    /// after its columns; CSV rows keep their fixed columns and leave it out.
    pub fn json_field(&mut self, key: &'static str, text: String) {
        if self.json.is_some() {
            self.extra = Some((key, text));
        }
    }

    /// Writes the rows formatted so far.
    pub fn flush(&mut self) -> std::io::Result<()> {
        if let Some(w) = &mut self.csv {
            w.write_to(&mut self.stream)?;
        }
        if let Some((_, buf)) = &mut self.json {
            self.stream.write_all(buf)?;
            buf.clear();
        }
        Ok(())
    }

    /// Writes the rest (the header of an empty output, the end of the JSON array) and
    /// closes the stream.
    pub fn finish(mut self, out: &mut Outputs) -> anyhow::Result<()> {
        if let Some((w, buf)) = &mut self.json {
            w.finish(buf);
        }
        self.flush()?;
        out.close(self.stream)
    }
}

/// The terminal preview of streamed data: the first [`TERMINAL_LINES`] + 1 lines are held;
/// if no more come they are written whole at the end, else the first [`PREVIEW_LINES`] are
/// written and the rest only counted. The same output as [`preview`].
#[derive(Default)]
struct Preview {
    held: Vec<u8>,
    lines: usize,
    cut: bool,
}

impl Preview {
    fn push(&mut self, out: &mut impl Write, buf: &[u8]) -> std::io::Result<()> {
        let new = buf.iter().filter(|&&b| b == b'\n').count();
        self.lines += new;
        if self.cut {
            return Ok(());
        }
        self.held.extend_from_slice(buf);
        if self.lines > TERMINAL_LINES {
            self.cut = true;
            let end = self
                .held
                .iter()
                .enumerate()
                .filter(|&(_, &b)| b == b'\n')
                .nth(PREVIEW_LINES - 1)
                .map_or(self.held.len(), |(i, _)| i + 1);
            out.write_all(&self.held[..end])?;
            out.flush()?;
            self.held = Vec::new();
        }
        Ok(())
    }

    fn finish(self, out: &mut impl Write) -> std::io::Result<()> {
        if !self.cut {
            return out.write_all(&self.held);
        }
        eprintln!(
            "({} more lines not shown on a terminal; redirect stdout to a file or give -o FILE for all of them)",
            self.lines - PREVIEW_LINES
        );
        Ok(())
    }
}

/// Data longer than this many lines is not poured onto a terminal whole.
const TERMINAL_LINES: usize = 200;
/// How many lines of such data a terminal is shown.
const PREVIEW_LINES: usize = 20;

/// Writes `parts` to a terminal: whole when short, else the first [`PREVIEW_LINES`] lines
/// and, on stderr, how many more there are and how to get them (a boundary at the default
/// tolerance has some 30,000 rows, which nobody reads on a screen). Pipes and files always
/// get everything.
fn preview<B: AsRef<[u8]>>(out: &mut impl Write, parts: &[B]) -> std::io::Result<()> {
    let lines: usize = parts
        .iter()
        .map(|p| p.as_ref().iter().filter(|&&b| b == b'\n').count())
        .sum();
    if lines <= TERMINAL_LINES {
        for part in parts {
            out.write_all(part.as_ref())?;
        }
        return Ok(());
    }
    let mut left = PREVIEW_LINES;
    for part in parts {
        let bytes = part.as_ref();
        let mut end = 0;
        for (i, &b) in bytes.iter().enumerate() {
            if b == b'\n' {
                left -= 1;
                end = i + 1;
                if left == 0 {
                    break;
                }
            }
        }
        if left == 0 {
            out.write_all(&bytes[..end])?;
            break;
        }
        out.write_all(bytes)?;
    }
    out.flush()?;
    eprintln!(
        "({} more lines not shown on a terminal; redirect stdout to a file or give -o FILE for all of them)",
        lines - PREVIEW_LINES
    );
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A keyed text field goes into the JSON object of its row only, after the columns;
    /// CSV keeps its fixed columns.
    #[test]
    fn json_field_is_in_its_row_only() {
        let dir = std::env::temp_dir().join(format!("rowstream-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        for json in [true, false] {
            let path = dir.join(if json { "rows.json" } else { "rows.csv" });
            let mut plan = Plan::new();
            let slot = plan.data("-o", Some(&path));
            let mut out = plan.check().unwrap();
            let mut rows = RowStream::new(&mut out, slot, &["x", "y"], json).unwrap();
            rows.num(1.0);
            rows.num(2.0);
            rows.json_field("note", "a \"quoted\" why".into());
            rows.num(3.0);
            rows.num(4.0);
            rows.num(5.0);
            rows.num(6.0);
            rows.finish(&mut out).unwrap();
            out.finish().unwrap();
            let text = std::fs::read_to_string(&path).unwrap();
            let want = if json {
                "[\n{\"x\":1.0,\"y\":2.0},\n{\"x\":3.0,\"y\":4.0,\"note\":\"a \\\"quoted\\\" why\"},\n{\"x\":5.0,\"y\":6.0}\n]\n"
            } else {
                "x,y\n1,2\n3,4\n5,6\n"
            };
            assert_eq!(text, want);
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
