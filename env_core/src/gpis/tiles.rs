//! Who computes a grid update's tiles of cells: the map's own thread ([`SerialTiles`], the
//! default), or that thread with others that are free ([`TileRunner`] implementations such
//! as the episode batch's `SharedTiles`, which lets a batch's idle threads help the thread
//! that resets an episode instead of waiting for it).
//!
//! Cells are independent, so every tile's result is the same whichever thread computes it:
//! the map is bit for bit the same under any runner.

use std::fmt::Debug;

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
