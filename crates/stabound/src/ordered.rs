//! Parallel work handed to a sink in order, as soon as each result and every one before it
//! are done: the streaming sweeps of boundaries and `alpha_max` rows.
//!
//! Method: `threads` worker loops on the rayon pool claim the next index, compute it and file
//! the result; whichever worker finds the next result in output order ready becomes the one
//! writer and hands results to the sink until it meets a gap (a classic ordered-completion
//! queue). No index is claimed more than [`LOOK_AHEAD`] times the thread count beyond the
//! next one to be written, so at most that many results are held: memory is proportional to
//! the thread count, not to the output, and the sink sees the same sequence whatever the
//! number of threads.

use std::collections::BTreeMap;
use std::sync::{Condvar, Mutex, MutexGuard};

/// How many results per thread may be computed ahead of the next one to be written: two
/// keeps every thread busy while the writer (one thread at a time) formats a result, and
/// holds at most a few curves' points.
const LOOK_AHEAD: usize = 2;

struct State<T, E> {
    /// Finished results waiting for their turn (at most the look-ahead of them).
    ready: BTreeMap<usize, std::result::Result<T, E>>,
    /// The next index the sink receives.
    next_emit: usize,
    /// The next index to be claimed by a worker.
    next_claim: usize,
    /// Whether a worker is handing results to the sink right now.
    writing: bool,
    /// The first error in output order (from the work or the sink): everything stops.
    error: Option<E>,
}

fn lock<S>(m: &Mutex<S>) -> MutexGuard<'_, S> {
    // a panic in a worker propagates through rayon::scope anyway; the state stays usable
    m.lock().unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// Runs `work(i)` for `i in 0..n` in parallel and passes each result to `sink(i, result)` in
/// increasing `i`. Stops at the first error in that order (of `work` or `sink`), which it
/// returns; results after it are dropped unwritten. With one item or one thread everything
/// runs on the calling thread, and the pool's workers are not woken.
pub(crate) fn for_each_ordered<T, E, W, S>(n: usize, work: W, mut sink: S) -> Result<(), E>
where
    T: Send,
    E: Send,
    W: Fn(usize) -> Result<T, E> + Sync,
    S: FnMut(usize, T) -> Result<(), E> + Send,
{
    // one item is never worth a thread: decided before asking for the thread count, which
    // would start the pool's workers
    let threads = if n <= 1 {
        1
    } else {
        rayon::current_num_threads().max(1)
    };
    if threads == 1 {
        for i in 0..n {
            sink(i, work(i)?)?;
        }
        return Ok(());
    }
    let window = LOOK_AHEAD * threads;
    let state = Mutex::new(State {
        ready: BTreeMap::new(),
        next_emit: 0,
        next_claim: 0,
        writing: false,
        error: None,
    });
    let turn = Condvar::new();
    let sink = Mutex::new(sink);
    let worker = || {
        loop {
            // claim an index within the window
            let i = {
                let mut st = lock(&state);
                loop {
                    if st.error.is_some() || st.next_claim >= n {
                        return;
                    }
                    if st.next_claim < st.next_emit + window {
                        break;
                    }
                    // The window is full: the result at `next_emit` is being computed by
                    // another worker, which wakes us once it has been written.
                    st = turn
                        .wait(st)
                        .unwrap_or_else(std::sync::PoisonError::into_inner);
                }
                st.next_claim += 1;
                st.next_claim - 1
            };
            let result = work(i);
            let mut st = lock(&state);
            st.ready.insert(i, result);
            if st.writing {
                continue;
            }
            st.writing = true;
            while st.error.is_none() {
                let next = st.next_emit;
                let Some(result) = st.ready.remove(&next) else {
                    break;
                };
                // the sink runs without the state lock, so that other workers can file
                // their results meanwhile
                drop(st);
                let outcome = result.and_then(|t| (lock(&sink))(next, t));
                st = lock(&state);
                match outcome {
                    Ok(()) => st.next_emit += 1,
                    Err(e) => {
                        st.error = Some(e);
                        st.ready.clear();
                    }
                }
                turn.notify_all();
            }
            st.writing = false;
        }
    };
    rayon::scope(|s| {
        for _ in 0..threads {
            s.spawn(|_| worker());
        }
    });
    let st = state
        .into_inner()
        .unwrap_or_else(std::sync::PoisonError::into_inner);
    match st.error {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every index reaches the sink once, in order, on pools of 1, 2 and 5 threads, with work
    /// of uneven length (later items often finish first).
    #[test]
    fn sink_sees_every_result_in_order() {
        for threads in [1, 2, 5] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let seen = pool.install(|| {
                let mut seen = Vec::new();
                for_each_ordered(
                    200,
                    |i| {
                        // uneven work: a short spin that depends on i
                        let mut x = 0u64;
                        for k in 0..((i * 7919) % 3000) as u64 {
                            x = x.wrapping_add(k * k);
                        }
                        std::hint::black_box(x);
                        Ok::<usize, ()>(i * 3)
                    },
                    |i, v| {
                        seen.push((i, v));
                        Ok(())
                    },
                )
                .unwrap();
                seen
            });
            let want: Vec<(usize, usize)> = (0..200).map(|i| (i, 3 * i)).collect();
            assert_eq!(seen, want, "{threads} threads");
        }
    }

    /// The first error in output order is returned, whoever finishes first, and nothing
    /// after it reaches the sink.
    #[test]
    fn first_error_in_order_stops_the_sink() {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(3)
            .build()
            .unwrap();
        let (r, seen) = pool.install(|| {
            let mut seen = Vec::new();
            let r = for_each_ordered(
                100,
                |i| if i == 40 || i == 70 { Err(i) } else { Ok(i) },
                |i, _| {
                    seen.push(i);
                    if i == 60 { Err(1000) } else { Ok(()) }
                },
            );
            (r, seen)
        });
        assert_eq!(r, Err(40));
        assert_eq!(seen, (0..40).collect::<Vec<_>>());
    }
}
