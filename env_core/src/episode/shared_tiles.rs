//! A batch's threads help each other with a GPIS grid update instead of waiting.
//!
//! In a batch step the threads take whole episodes; a reset with the GPIS map costs as much
//! as dozens of wrist steps, so the thread that takes it finishes last while the others
//! wait. Most of that reset is the grid update of the depth prior, in tiles of cells that
//! are independent ([`crate::gpis::tiles`]). The batch's episodes share one [`SharedTiles`]:
//! a thread updating a grid posts the job, takes tiles itself, and the batch's threads with
//! no episode left take the rest ([`SharedTiles::help_until`]). One job is open at a time,
//! until its last tile is taken; a second thread updating a grid meanwhile computes its own
//! tiles. A job may be posted from inside a tile: a reset's two pieces (the approach field,
//! then the map's prior) are a job, and the thread that takes the prior posts its grid
//! update while the other, done with the field, takes tiles of it (a poster waiting for its
//! job's last tiles works on the open job meanwhile). Results are bit for bit those of one
//! thread: a tile's cells come out the same wherever it runs.
//!
//! The second module of the project with `unsafe` code (after the allocator,
//! `allocator`): a posted job's work borrows the grid update's data, so its lifetime is
//! erased while other threads may call it. It holds because [`SharedTiles::run`] returns
//! (or unwinds) only after every tile taken has been worked, and no tile is taken after
//! that: the scoped-thread pattern of rayon's and crossbeam's scopes, which cannot serve
//! here since the batch's calling thread is not one of its pool's workers.

#![allow(unsafe_code)]

use std::panic::{self, AssertUnwindSafe};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Condvar, Mutex, MutexGuard, PoisonError};
use std::time::{Duration, Instant};

use crossbeam_utils::Backoff;

use crate::gpis::TileRunner;

/// How long a waiting helper sleeps at most before it looks again whether the run is done
/// (it is woken at once when a job is posted or the run ends; this only bounds a missed
/// wake-up).
const LOOK_AGAIN: Duration = Duration::from_millis(5);

/// The job board of a batch's threads.
#[derive(Debug, Default)]
pub struct SharedTiles {
    /// The job open for helpers, if any.
    open: Mutex<Option<Arc<Job>>>,
    /// Whether `open` holds a job: what a spinning helper reads instead of the lock.
    posted: AtomicBool,
    /// Signalled when a job is posted and when a run's last task is done.
    changed: Condvar,
}

/// One grid update's tiles.
struct Job {
    /// The work of one tile, its lifetime erased: valid until every tile is `done` (the
    /// posting thread does not return before).
    work: *const (dyn Fn(usize) + Sync + 'static),
    tiles: usize,
    /// The next tile to take.
    next: AtomicUsize,
    /// Tiles whose work has returned (or unwound).
    done: AtomicUsize,
}

// SAFETY: `work` points at a `Sync` closure that outlives every call made through it
// (`SharedTiles::run` waits for `done == tiles` before it returns and the closure goes);
// the counters are atomics.
unsafe impl Send for Job {}
// SAFETY: as for `Send`: shared access calls the `Sync` closure and touches atomics only.
unsafe impl Sync for Job {}

impl std::fmt::Debug for Job {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Job")
            .field("tiles", &self.tiles)
            .field("next", &self.next)
            .field("done", &self.done)
            .finish()
    }
}

/// Counts a taken tile as done when dropped, even if its work unwinds (the posting thread
/// then stops waiting, and the panic reaches the batch's caller through rayon).
struct CountDone<'a>(&'a AtomicUsize);

impl Drop for CountDone<'_> {
    fn drop(&mut self) {
        self.0.fetch_add(1, Ordering::Release);
    }
}

impl Job {
    /// Takes tiles and works them until none is left. The thread taking the last tile
    /// closes the job on `board`, so that a job posted from inside a tile (a reset's grid
    /// update, in a piece of the reset) finds the board free.
    fn work_through(&self, board: &SharedTiles) {
        loop {
            let tile = self.next.fetch_add(1, Ordering::Relaxed);
            if tile >= self.tiles {
                return;
            }
            if tile + 1 == self.tiles {
                board.close(self);
            }
            let _done = CountDone(&self.done);
            // SAFETY: `tile < tiles` was taken and is not yet done, so the posting thread
            // is still waiting in `run` and the closure is alive.
            unsafe { (*self.work)(tile) };
        }
    }
}

impl SharedTiles {
    fn lock_open(&self) -> MutexGuard<'_, Option<Arc<Job>>> {
        self.open.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// Takes `job` off the board if it is the one open.
    fn close(&self, job: &Job) {
        let mut open = self.lock_open();
        if open
            .as_ref()
            .is_some_and(|o| std::ptr::eq(Arc::as_ptr(o), job))
        {
            *open = None;
            self.posted.store(false, Ordering::Release);
        }
    }

    /// The job open for helpers, if any (a lock only when one was posted).
    fn open_job(&self) -> Option<Arc<Job>> {
        if self.posted.load(Ordering::Acquire) {
            self.lock_open().clone()
        } else {
            None
        }
    }

    /// Takes tiles of the jobs posted until `finished()` holds, then returns: what a batch
    /// thread with no episode left to take does. Between jobs it spins (then yields) for at
    /// most `spin`, then sleeps until a job is posted or [`SharedTiles::wake_all`] says the
    /// run may be over.
    pub fn help_until(&self, finished: impl Fn() -> bool, spin: Duration) {
        let (mut backoff, mut waiting) = (Backoff::new(), Instant::now());
        loop {
            if let Some(job) = self.open_job() {
                job.work_through(self);
                (backoff, waiting) = (Backoff::new(), Instant::now());
                continue;
            }
            if finished() {
                return;
            }
            if waiting.elapsed() < spin {
                backoff.snooze();
                continue;
            }
            let open = self.lock_open();
            if open.is_none() && !finished() {
                drop(
                    self.changed
                        .wait_timeout(open, LOOK_AGAIN)
                        .unwrap_or_else(PoisonError::into_inner),
                );
            }
        }
    }

    /// Wakes every helper waiting in [`SharedTiles::help_until`] to look at its condition
    /// again (call it after the condition may have changed).
    pub fn wake_all(&self) {
        let _open = self.lock_open();
        self.changed.notify_all();
    }
}

impl TileRunner for SharedTiles {
    fn run(&self, tiles: usize, work: &(dyn Fn(usize) + Sync)) {
        if tiles < 2 {
            (0..tiles).for_each(work);
            return;
        }
        // SAFETY: only the lifetime is erased; this function does not return before every
        // tile is done (below), and no call through the pointer starts after that.
        let work: *const (dyn Fn(usize) + Sync + 'static) = unsafe { std::mem::transmute(work) };
        let job = Arc::new(Job {
            work,
            tiles,
            next: AtomicUsize::new(0),
            done: AtomicUsize::new(0),
        });
        let posted = {
            let mut open = self.lock_open();
            let free = open.is_none();
            if free {
                *open = Some(Arc::clone(&job));
                self.posted.store(true, Ordering::Release);
                self.changed.notify_all();
            }
            free
        };
        // The caller's own tiles; a panic among them is raised again only after the helpers'
        // tiles are done, so no helper calls the work after it is gone. The tiles nobody
        // took by then are counted done unworked (the update is lost with the panic anyway).
        let own = panic::catch_unwind(AssertUnwindSafe(|| job.work_through(self)));
        if own.is_err() {
            while job.next.fetch_add(1, Ordering::Relaxed) < tiles {
                job.done.fetch_add(1, Ordering::Release);
            }
        }
        if posted {
            self.close(&job);
        }
        // The helpers' last tiles, each at most one tile's work; meanwhile the tiles of a
        // job one of them posted from inside its tile (the helper waits for those). A panic
        // in those is held until this job's tiles are done, as one of its own would be.
        let backoff = Backoff::new();
        let mut theirs = Ok(());
        while job.done.load(Ordering::Acquire) < tiles {
            match self.open_job() {
                Some(other) if own.is_ok() && theirs.is_ok() => {
                    theirs = panic::catch_unwind(AssertUnwindSafe(|| other.work_through(self)));
                }
                _ => backoff.snooze(),
            }
        }
        if let Err(payload) = own.and(theirs) {
            panic::resume_unwind(payload);
        }
    }
}

#[cfg(test)]
mod tests {
    use std::thread;

    use super::*;

    #[test]
    fn every_tile_runs_once_while_helpers_take_some() {
        let board = SharedTiles::default();
        let finished = AtomicBool::new(false);
        let counts: Vec<AtomicUsize> = (0..64).map(|_| AtomicUsize::new(0)).collect();
        let helped = AtomicUsize::new(0);
        let poster = thread::current().id();
        thread::scope(|scope| {
            for _ in 0..3 {
                scope.spawn(|| {
                    board.help_until(|| finished.load(Ordering::Acquire), Duration::ZERO)
                });
            }
            for _ in 0..20 {
                board.run(counts.len(), &|t| {
                    counts[t].fetch_add(1, Ordering::Relaxed);
                    if thread::current().id() != poster {
                        helped.fetch_add(1, Ordering::Relaxed);
                    }
                    thread::sleep(Duration::from_micros(50));
                });
            }
            finished.store(true, Ordering::Release);
            board.wake_all();
        });
        assert!(counts.iter().all(|c| c.load(Ordering::Relaxed) == 20));
        assert!(helped.load(Ordering::Relaxed) > 0, "no helper took a tile");
        assert!(board.lock_open().is_none(), "a job was left open");
    }

    /// A reset's pieces are a job whose long, last piece posts the grid's job: taking the
    /// last piece frees the board, so the inner job is shared too, whichever thread runs
    /// the long piece (the other, done with the short one, takes its tiles: the poster of
    /// the outer job while it waits, or a helper).
    #[test]
    fn a_job_posted_from_inside_a_tile_is_shared_too() {
        let board = SharedTiles::default();
        let finished = AtomicBool::new(false);
        let counts: Vec<AtomicUsize> = (0..17).map(|_| AtomicUsize::new(0)).collect();
        let shared = AtomicUsize::new(0);
        thread::scope(|scope| {
            scope.spawn(|| board.help_until(|| finished.load(Ordering::Acquire), Duration::ZERO));
            for _ in 0..20 {
                board.run(2, &|piece| {
                    if piece == 0 {
                        counts[16].fetch_add(1, Ordering::Relaxed);
                        return;
                    }
                    let runner = thread::current().id();
                    board.run(16, &|t| {
                        counts[t].fetch_add(1, Ordering::Relaxed);
                        if thread::current().id() != runner {
                            shared.fetch_add(1, Ordering::Relaxed);
                        }
                        thread::sleep(Duration::from_micros(50));
                    });
                });
            }
            finished.store(true, Ordering::Release);
            board.wake_all();
        });
        assert!(counts.iter().all(|c| c.load(Ordering::Relaxed) == 20));
        assert!(
            shared.load(Ordering::Relaxed) > 0,
            "no inner tile was shared"
        );
        assert!(board.lock_open().is_none(), "a job was left open");
    }

    #[test]
    fn a_panicking_tile_reaches_the_poster_without_a_hang() {
        let board = SharedTiles::default();
        let worked = AtomicUsize::new(0);
        let caught = panic::catch_unwind(AssertUnwindSafe(|| {
            board.run(8, &|t| {
                assert!(t != 2, "tile 2 fails");
                worked.fetch_add(1, Ordering::Relaxed);
            });
        }));
        assert!(caught.is_err(), "the panic was swallowed");
        assert_eq!(
            worked.load(Ordering::Relaxed),
            2,
            "tiles after the panic ran"
        );
        assert!(board.lock_open().is_none(), "a job was left open");
    }

    #[test]
    fn a_second_job_posted_meanwhile_runs_on_its_own_thread() {
        let board = SharedTiles::default();
        let counts: Vec<AtomicUsize> = (0..16).map(|_| AtomicUsize::new(0)).collect();
        thread::scope(|scope| {
            for _ in 0..2 {
                scope.spawn(|| {
                    for _ in 0..50 {
                        board.run(counts.len(), &|t| {
                            counts[t].fetch_add(1, Ordering::Relaxed);
                        });
                    }
                });
            }
        });
        assert!(counts.iter().all(|c| c.load(Ordering::Relaxed) == 100));
    }
}
