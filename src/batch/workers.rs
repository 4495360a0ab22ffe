//! The batch's worker threads. A call's worlds are shared by the calling thread and the workers
//! of a rayon pool; a worker takes part in a call only if it starts while the calling thread
//! still has worlds to take, so the caller never waits for a worker that has not started. On a
//! machine shared with other busy processes a worker may not be scheduled for milliseconds;
//! waiting for it would make every call that long.

use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// How long the workers keep polling for the next call after one ends before they go to sleep:
/// waking a sleeping worker costs a call tens of microseconds on this kind of machine, about a
/// tenth of a 64-world Hopper env step (Intel's OpenMP runtime spins 200 ms by default,
/// `KMP_BLOCKTIME`).
const LINGER: Duration = Duration::from_micros(200);

/// Bit of [`Shared::state`] set once the calling thread has run out of worlds: no worker joins
/// the call after it.
const CLOSED: u64 = 1 << 16;
/// Bits of [`Shared::state`] counting the workers that joined the call.
const JOINED: u64 = CLOSED - 1;
/// Where the call's number starts in [`Shared::state`].
const CALL_SHIFT: u32 = 17;

/// What the calling thread and the workers share from call to call.
#[derive(Default)]
struct Shared {
    /// The current call's number (from bit [`CALL_SHIFT`]), [`CLOSED`] and the number of
    /// workers that joined it.
    state: AtomicU64,
    /// Workers that joined the current call and have finished.
    finished: AtomicUsize,
}

impl Shared {
    /// Joins call `call` if it is still the current one and open.
    fn join(&self, call: u64) -> bool {
        let mut s = self.state.load(Ordering::Acquire);
        while s >> CALL_SHIFT == call && s & CLOSED == 0 {
            match self.state.compare_exchange_weak(s, s + 1, Ordering::AcqRel, Ordering::Acquire) {
                Ok(_) => return true,
                Err(now) => s = now,
            }
        }
        false
    }
}

/// Counts a joined worker as finished when dropped, even if its work unwinds.
struct Finished<'a>(&'a AtomicUsize);

impl Drop for Finished<'_> {
    fn drop(&mut self) {
        self.0.fetch_add(1, Ordering::Release);
    }
}

/// A call's work with its lifetime erased, so that a `'static` rayon job can carry it.
/// It is called only by a worker that joined the call, and [`Workers::run`] returns only
/// after every such worker has finished, so the work it points to outlives every use.
#[derive(Clone, Copy)]
struct Work(*const (dyn Fn(bool) + Sync + 'static));

// SAFETY: the pointee is `Sync`, and `Workers::run` keeps it alive while any job may use it
unsafe impl Send for Work {}

/// `n` rayon workers beside the calling thread.
pub struct Workers {
    pool: rayon::ThreadPool,
    n: usize,
    shared: Arc<Shared>,
}

impl Workers {
    /// A pool of `n` worker threads.
    pub fn new(n: usize) -> crate::error::Result<Workers> {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(n).build();
        let pool = pool.map_err(|e| crate::error::Error::Input(format!("cannot start the thread pool: {e}")))?;
        Ok(Workers { pool, n, shared: Arc::default() })
    }

    /// Calls `work(false)` on the calling thread and `work(true)` on each worker that starts
    /// before that returns; returns once they have all finished. `work` takes items from a
    /// shared queue until it is empty (the flag: from its back), so whoever runs does all.
    pub fn run(&self, work: &(dyn Fn(bool) + Sync)) {
        let shared = &*self.shared;
        let call = (shared.state.load(Ordering::Relaxed) >> CALL_SHIFT) + 1;
        shared.finished.store(0, Ordering::Relaxed);
        shared.state.store(call << CALL_SHIFT, Ordering::Release);
        // SAFETY: only the lifetime changes; see `Work`
        let job = Work(unsafe { std::mem::transmute::<*const (dyn Fn(bool) + Sync + '_), *const (dyn Fn(bool) + Sync + 'static)>(work) });
        for _ in 0..self.n {
            let shared = Arc::clone(&self.shared);
            self.pool.spawn(move || {
                let job = job;
                if shared.join(call) {
                    let _done = Finished(&shared.finished);
                    // SAFETY: joined before the call closed, so `run` is still waiting for us
                    unsafe { (*job.0)(true) };
                }
            });
        }
        work(false);
        let joined = (shared.state.fetch_or(CLOSED, Ordering::AcqRel) & JOINED) as usize;
        // the joined workers are on their last worlds: poll, then give the core away
        let mut polls = 0u32;
        while shared.finished.load(Ordering::Acquire) < joined {
            if polls < 1 << 12 {
                std::hint::spin_loop();
                polls += 1;
            } else {
                std::thread::yield_now();
            }
        }
        // the workers poll for the next call for a while instead of going to sleep at once
        for _ in 0..self.n {
            let shared = Arc::clone(&self.shared);
            let start = Instant::now();
            self.pool.spawn(move || {
                while shared.state.load(Ordering::Relaxed) >> CALL_SHIFT == call && start.elapsed() < LINGER {
                    std::hint::spin_loop();
                }
            });
        }
    }
}
