//! Starting the worker threads: room for them is made sure of before any is spawned.
//!
//! A thread that the Rust runtime cannot give its signal stack panics inside the runtime,
//! before any code of ours runs on it. Under a tight address-space limit (`ulimit -v`) that
//! panic's own message can then run out of memory while it holds the runtime's output lock,
//! and the process waits on that lock forever: the thread pool never reports ready and the
//! run hangs instead of failing. So the address space the threads will take is reserved
//! and released first; when the reservation fails, the run fails cleanly (exit 1) before
//! any thread exists.

use anyhow::anyhow;

/// Stack the runtime gives a thread when `RUST_MIN_STACK` does not say otherwise (the
/// standard library's default, which the thread pool keeps).
const DEFAULT_STACK: usize = 2 << 20;

/// Address space a thread takes beside its stack: the stack's guard page, the runtime's
/// signal stack and its guard page (a few pages each), the C library's thread block and
/// thread-local storage, and the thread's first allocations. Their sum is some tens of
/// KiB on Linux; a quarter of a MiB leaves room for larger signal stacks (`AT_MINSIGSTKSZ`
/// grows with the vector registers) without refusing a limit that fits by much.
const PER_THREAD_EXTRA: usize = 256 << 10;

/// Address space the process takes between the reservation and its last thread's start
/// beside the threads themselves (the main thread's stack growing, the allocations of
/// start-up and of the thread pool), with room to spare.
const HEADROOM: usize = 1 << 20;

/// Starts the global thread pool, after making sure the address space for its threads, for
/// `other_threads` more (the interrupt handler's, the time limit's watch) and for
/// [`HEADROOM`] can be had.
pub fn start(other_threads: usize) -> anyhow::Result<()> {
    let threads = pool_size() + other_threads;
    let stack = std::env::var("RUST_MIN_STACK")
        .ok()
        .and_then(|s| s.trim().parse::<usize>().ok())
        .unwrap_or(DEFAULT_STACK);
    let need = threads
        .saturating_mul(stack.saturating_add(PER_THREAD_EXTRA))
        .saturating_add(HEADROOM);
    if !reservable(need) {
        return Err(anyhow!(
            "cannot start the worker threads (no room for {threads} thread stacks of {} KiB); raise the memory limit (ulimit -v), or set RAYON_NUM_THREADS=1",
            stack >> 10
        ));
    }
    rayon::ThreadPoolBuilder::new().build_global().map_err(|e| {
        anyhow!(
            "cannot start the worker threads ({e}); raise the memory or thread limit, or set RAYON_NUM_THREADS=1"
        )
    })
}

/// The number of worker threads the pool will start: `RAYON_NUM_THREADS` when it is a
/// positive number, else the available parallelism (the pool's own rule).
fn pool_size() -> usize {
    std::env::var("RAYON_NUM_THREADS")
        .ok()
        .and_then(|s| s.trim().parse::<usize>().ok())
        .filter(|&n| n > 0)
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
}

/// Whether `bytes` of address space can be mapped now; the mapping is released at once.
#[cfg(unix)]
fn reservable(bytes: usize) -> bool {
    use nix::libc;
    // SAFETY: an anonymous, inaccessible, private mapping at an address the kernel picks
    // touches no existing memory; it is unmapped below with the same length.
    let p = unsafe {
        libc::mmap(
            std::ptr::null_mut(),
            bytes.max(1),
            libc::PROT_NONE,
            libc::MAP_PRIVATE | libc::MAP_ANONYMOUS | libc::MAP_NORESERVE,
            -1,
            0,
        )
    };
    if p == libc::MAP_FAILED {
        return false;
    }
    // SAFETY: `p` is the mapping made above, of this length, and nothing refers to it.
    unsafe { libc::munmap(p, bytes.max(1)) };
    true
}

/// Elsewhere the thread pool's own error is the only check.
#[cfg(not(unix))]
fn reservable(_bytes: usize) -> bool {
    true
}
