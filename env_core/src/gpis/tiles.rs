//! Who computes a grid update's tiles of cells: the map's own thread ([`SerialTiles`], the
//! default), or that thread with others that are free ([`TileRunner`] implementations such
//! as the episode batch's `SharedTiles`, which lets a batch's idle threads help the thread
//! that resets an episode instead of waiting for it).
//!
//! Cells are independent, so every tile's result is the same whichever thread computes it:
//! the map is bit for bit the same under any runner.

use std::fmt::Debug;
use std::sync::{Mutex, PoisonError};

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
