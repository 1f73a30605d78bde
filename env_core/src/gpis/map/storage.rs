//! The map's storage: how many rows it is sized for, how it grows, what `clear` keeps and
//! what a copy reserves.
//!
//! The factor L (cap × cap), the grid cache (G × cap) and the per-row data are sized for a
//! row capacity `cap` that grows by at least doubling up to `max_rows`, so an `add` writes
//! in place instead of reallocating; memory is about 8·(cap² + G·cap) bytes. Every
//! allocation is fallible: a map too large for the machine is a [`GpisError::OutOfMemory`],
//! not an abort.

use faer::Mat;
use std::sync::Arc;

use super::Gpis;
use crate::gpis::error::GpisError;
use crate::gpis::kernel::RowKind;
use crate::gpis::observation::Row;

/// Smallest row capacity allocated once the first row arrives.
const MIN_CAPACITY: usize = 64;

/// The row capacity storage is sized for when `rows` rows must fit: half as many again, as
/// headroom, rounded up to a power of two (so that a map's storage takes few sizes). The
/// headroom matters for the episode's map: its depth prior alone fills 128 rows at the
/// defaults, and without room to spare nearly half the episodes would grow the storage to
/// 256 rows with their first touches (a fresh 6.5 MB grid cache: page faults and a copy)
/// and give it back at the next `clear`.
fn capacity_for(rows: usize) -> usize {
    (rows + rows / 2).next_power_of_two().max(MIN_CAPACITY)
}

/// The gigabytes (1e9 bytes) that `count` f64s take.
pub(super) fn gigabytes_of_f64s(count: f64) -> f64 {
    count * std::mem::size_of::<f64>() as f64 / 1e9
}

impl Clone for Gpis {
    /// A copy with the same spare capacity: faer's `Mat::clone` allocates exactly the n × n
    /// in use of the factor (the grid cache is `capacity` columns wide already), and without
    /// re-reserving every later append to the copy would reallocate and copy the factor.
    ///
    /// # Cost
    /// O(cap² + G·cap) to copy the storage.
    fn clone(&self) -> Self {
        let mut copy = Self {
            grid: self.grid.clone(),
            cell_xs: self.cell_xs.clone(),
            cell_ys: self.cell_ys.clone(),
            kernel: self.kernel,
            prior_mean: self.prior_mean,
            max_rows: self.max_rows,
            rows: self.rows.clone(),
            observed: self.observed.clone(),
            noise_var: self.noise_var.clone(),
            capacity: 0,
            chol: self.chol.clone(),
            beta: self.beta.clone(),
            grid_cache_t: self.grid_cache_t.clone(),
            mean: self.mean.clone(),
            variance: self.variance.clone(),
            tiles: Arc::clone(&self.tiles),
        };
        // A failed reservation is tried again, with its error, by the copy's next `add`.
        copy.reserve_rows(self.capacity).ok();
        copy
    }
}

impl Gpis {
    /// Forgets every observation, keeping storage for reuse: [`capacity_for`] as many rows
    /// as the map held. Storage of twice that or more, grown by an unusually large map, is
    /// released, so a map reused across episodes holds what its last episode needed, not
    /// the most any episode ever did (memory would otherwise creep over a long run).
    ///
    /// # Cost
    /// O(G) to reset the grids; reallocating, when storage is released, O(cap² + G·cap).
    ///
    /// # Errors
    /// None: a failed reallocation leaves the map with no rows reserved, and the next `add`
    /// reserves them again (and reports [`GpisError::OutOfMemory`] if that fails too).
    pub fn clear(&mut self) {
        let n_cells = self.cell_xs.len();
        let kept = capacity_for(self.rows.len());
        self.rows.clear();
        self.observed.clear();
        self.noise_var.clear();
        self.beta.clear();
        if self.capacity >= 2 * kept {
            self.rows.shrink_to(kept);
            self.observed.shrink_to(kept);
            self.noise_var.shrink_to(kept);
            self.beta.shrink_to(kept);
            self.chol = Mat::zeros(0, 0);
            self.grid_cache_t = Mat::zeros(n_cells, 0);
            self.capacity = 0;
            // A failed reservation is tried again, with its error, by the next `add`.
            self.allocate(kept.min(self.max_rows)).ok();
        }
        self.chol.truncate(0, 0);
        self.mean.clear();
        self.mean.resize(n_cells, self.prior_mean);
        self.variance.clear();
        self.variance
            .resize(n_cells, self.kernel.prior_variance(RowKind::Value));
    }

    /// Bytes held by the map's numeric state (factor, grid cache, grids, row data).
    ///
    /// # Cost
    /// O(1).
    pub fn memory_bytes(&self) -> usize {
        let f64s = self.capacity * self.capacity
            + self.cell_xs.len() * self.capacity
            + self.cell_xs.len() * 4
            + self.rows.capacity() * 2
            + self.observed.capacity()
            + self.noise_var.capacity()
            + self.beta.capacity();
        f64s * std::mem::size_of::<f64>() + self.rows.capacity() * std::mem::size_of::<Row>()
    }

    /// Grows the storage to hold `rows` rows: to [`capacity_for`] them, at least doubling,
    /// or says how much it needed if the allocation fails (the map is left as it was).
    pub(super) fn reserve_rows(&mut self, rows: usize) -> Result<(), GpisError> {
        if rows <= self.capacity {
            return Ok(());
        }
        self.allocate(capacity_for(rows).max(2 * self.capacity).min(self.max_rows))
    }

    /// Grows the factor's, the cache's and the row data's storage to `capacity` rows (at
    /// least what they hold), or says how much it needed if the allocation fails.
    fn allocate(&mut self, capacity: usize) -> Result<(), GpisError> {
        let out_of_memory = |_| GpisError::OutOfMemory {
            what: "factor and grid cache",
            gigabytes: gigabytes_of_f64s(capacity as f64 * (capacity + self.cell_xs.len()) as f64),
        };
        self.chol
            .try_reserve(capacity, capacity)
            .map_err(out_of_memory)?;
        self.grid_cache_t
            .try_reserve(self.cell_xs.len(), capacity)
            .map_err(out_of_memory)?;
        // Reserved above: this fills the new columns without reallocating.
        self.grid_cache_t
            .resize_with(self.cell_xs.len(), capacity, |_, _| 0.0);
        // The per-row data too, so that the storage is the capacity's, whatever the pushes.
        let spare = capacity - self.rows.len();
        let out_of_memory = |_| GpisError::OutOfMemory {
            what: "row data",
            gigabytes: gigabytes_of_f64s(6.0 * capacity as f64),
        };
        self.rows.try_reserve_exact(spare).map_err(out_of_memory)?;
        self.observed
            .try_reserve_exact(spare)
            .map_err(out_of_memory)?;
        self.noise_var
            .try_reserve_exact(spare)
            .map_err(out_of_memory)?;
        self.beta.try_reserve_exact(spare).map_err(out_of_memory)?;
        self.capacity = capacity;
        Ok(())
    }
}
