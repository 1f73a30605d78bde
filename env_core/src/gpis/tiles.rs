//! Who computes a grid update's tiles of cells: the map's own thread ([`SerialTiles`], the
//! default), or the rayon pool that thread works for ([`PoolTiles`]: an episode batch
//! lends its threads this way, so that a batch's idle threads help the one that resets an
//! episode instead of waiting for it).
//!
//! Cells are independent, so every tile's result is the same whichever thread computes it:
//! the map is bit for bit the same under any runner.

use std::fmt::Debug;
use std::sync::{Mutex, PoisonError};

use rayon::prelude::*;

/// Runs `work(t)` once for every tile `t` in `0..tiles`, on the calling thread and
/// possibly others, and returns when every call has returned.
pub trait TileRunner: Send + Sync + Debug {
    /// Calls `work(t)` for each `t` in `0..tiles`, each exactly once, in any order and on
    /// any threads; returns after the last call has returned.
    fn run(&self, tiles: usize, work: &(dyn Fn(usize) + Sync));
}

/// Every tile on the calling thread, in order.
#[derive(Debug, Clone, Copy, Default)]
pub struct SerialTiles;

impl TileRunner for SerialTiles {
    fn run(&self, tiles: usize, work: &(dyn Fn(usize) + Sync)) {
        (0..tiles).for_each(work);
    }
}

/// The tiles as a rayon parallel iterator on the pool the calling thread is a worker of,
/// whose idle workers steal them; on a thread of no pool, every tile on that thread (never
/// rayon's global pool, which a forked process would find without its threads). A panic
/// in a tile reaches the caller once the tiles other threads took have returned.
#[derive(Debug, Clone, Copy, Default)]
pub struct PoolTiles;

impl TileRunner for PoolTiles {
    fn run(&self, tiles: usize, work: &(dyn Fn(usize) + Sync)) {
        if rayon::current_thread_index().is_some() {
            (0..tiles).into_par_iter().for_each(work);
        } else {
            (0..tiles).for_each(work);
        }
    }
}

/// Hands each of `items` to `work` once, as the tiles of one `runner.run` (each item is
/// taken by whichever thread runs its tile): how a grid update gives out its tiles of
/// cells and a reset its independent pieces.
pub fn run_each<T: Send>(
    runner: &dyn TileRunner,
    items: impl IntoIterator<Item = T>,
    work: impl Fn(T) + Sync,
) {
    let slots: Vec<Mutex<Option<T>>> = items
        .into_iter()
        .map(|item| Mutex::new(Some(item)))
        .collect();
    runner.run(slots.len(), &|t| {
        let item = slots[t]
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .take();
        if let Some(item) = item {
            work(item);
        }
    });
}

#[cfg(test)]
mod tests {
    use std::panic::{self, AssertUnwindSafe};
    use std::sync::atomic::{AtomicUsize, Ordering};
    use std::thread;
    use std::time::Duration;

    use rayon::ThreadPoolBuilder;

    use super::*;

    #[test]
    fn every_tile_runs_once_and_idle_workers_take_some() {
        let pool = ThreadPoolBuilder::new().num_threads(2).build().unwrap();
        let counts: Vec<AtomicUsize> = (0..64).map(|_| AtomicUsize::new(0)).collect();
        let threads = Mutex::new(std::collections::HashSet::new());
        pool.install(|| {
            PoolTiles.run(counts.len(), &|t| {
                counts[t].fetch_add(1, Ordering::Relaxed);
                threads.lock().unwrap().insert(thread::current().id());
                thread::sleep(Duration::from_micros(200));
            })
        });
        assert!(counts.iter().all(|c| c.load(Ordering::Relaxed) == 1));
        assert_eq!(
            threads.lock().unwrap().len(),
            2,
            "one worker took every tile"
        );
    }

    #[test]
    fn outside_a_pool_the_tiles_run_on_the_calling_thread_in_order() {
        let order = Mutex::new(Vec::new());
        let caller = thread::current().id();
        PoolTiles.run(5, &|t| {
            assert_eq!(thread::current().id(), caller);
            order.lock().unwrap().push(t);
        });
        assert_eq!(*order.lock().unwrap(), [0, 1, 2, 3, 4]);
    }

    #[test]
    fn a_panicking_tile_reaches_the_caller_without_a_hang() {
        let pool = ThreadPoolBuilder::new().num_threads(2).build().unwrap();
        let worked = AtomicUsize::new(0);
        let caught = panic::catch_unwind(AssertUnwindSafe(|| {
            pool.install(|| {
                run_each(&PoolTiles, 0..8, |t| {
                    assert!(t != 2, "tile 2 fails");
                    worked.fetch_add(1, Ordering::Relaxed);
                })
            })
        }));
        assert!(caught.is_err(), "the panic was swallowed");
        assert!(worked.load(Ordering::Relaxed) < 8);
        // The pool still works.
        assert_eq!(pool.install(|| (0..4).into_par_iter().sum::<i32>()), 6);
    }
}
