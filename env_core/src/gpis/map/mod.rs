//! The GPIS map: an exact posterior over f, kept on a grid and updated incrementally.
//!
//! State, for n accepted rows and G grid cells:
//! - L, the lower Cholesky factor of K + Σ (n × n);
//! - β = L⁻¹ (y − m);
//! - the grid cache V = L⁻¹ K*ᵀ, stored transposed (G × n) so that appending rows appends
//!   columns;
//! - the grid mean m + Vᵀβ and variance ψ³ − colsum(V ∘ V).
//!
//! Appending k rows with cross-covariance B (n × k), block C (k × k) and grid
//! cross-covariance K*₂ (G × k):
//!
//! ```text
//! L₂₁ = (L⁻¹ B)ᵀ,   L₂₂ = chol(C − L₂₁ L₂₁ᵀ)
//! β₂  = L₂₂⁻¹ (y₂ − m₂ − L₂₁ β)
//! V₂  = L₂₂⁻¹ (K*₂ᵀ − L₂₁ V)
//! mean += V₂ᵀ β₂,   variance −= colsum(V₂ ∘ V₂)
//! ```
//!
//! Cost O(k·n·G + k·n² + k²·G) per append instead of the O(n³ + n²·G) of a full recompute.
//!
//! One operation per file:
//! - [`append`]: the `add_*` calls; L and β grown chunk by chunk, the rejecting
//!   factorisation deciding which rows stay (the first three lines above);
//! - [`grid_update`]: the cache, mean and variance brought up to date once per `add`, in
//!   tiles of cells (the last two lines);
//! - [`predict`]: the posterior at arbitrary points;
//! - [`storage`]: how the storage is sized, grows, is kept by `clear` and copied.
//!
//! The map's settings and defaults are in [`crate::gpis::config`].

mod append;
mod grid_update;
mod predict;
mod storage;

pub use append::AddReport;
pub use predict::Prediction;

use faer::Mat;
use std::sync::Arc;

use crate::gpis::config::{GpisConfig, DEFAULT_PSI_FACTOR, MAX_PSI};
use crate::gpis::error::GpisError;
use crate::gpis::full_recompute::{full_posterior, GridPosterior};
use crate::gpis::grid::GridSpec;
use crate::gpis::kernel::ThinPlateKernel;
use crate::gpis::observation::Row;
use crate::gpis::tiles::{SerialTiles, TileRunner};
use storage::gigabytes_of_f64s;

/// A GPIS map over a rectangular domain with an exact incremental posterior on its grid.
#[derive(Debug)]
pub struct Gpis {
    grid: GridSpec,
    /// The cell centres' x and y coordinates, row-major, as two slices (the kernel columns
    /// vectorise over them).
    cell_xs: Vec<f64>,
    cell_ys: Vec<f64>,
    kernel: ThinPlateKernel,
    prior_mean: f64,
    max_rows: usize,
    rows: Vec<Row>,
    observed: Vec<f64>,
    noise_var: Vec<f64>,
    capacity: usize,
    chol: Mat<f64>,
    beta: Vec<f64>,
    /// Vᵀ in its first `rows.len()` columns; always `capacity` columns wide, so that an
    /// `add` writes its new columns in place instead of growing (and zero-filling) them.
    grid_cache_t: Mat<f64>,
    mean: Vec<f64>,
    variance: Vec<f64>,
    /// Who computes a grid update's tiles ([`SerialTiles`] unless [`Gpis::share_tiles`]).
    tiles: Arc<dyn TileRunner>,
}

impl Gpis {
    /// An empty map (prior only).
    ///
    /// # Cost
    /// O(G) for G grid cells; row storage is allocated by the first `add`.
    ///
    /// # Errors
    /// [`GpisError::InvalidBounds`] and [`GpisError::InvalidShape`] for the grid,
    /// [`GpisError::PsiTooSmall`] and [`GpisError::PsiTooLarge`] for ψ,
    /// [`GpisError::NonFiniteParameter`] for the prior mean,
    /// [`GpisError::InvalidCapacity`] for `max_rows == 0`, and [`GpisError::OutOfMemory`]
    /// when the grid's storage cannot be allocated.
    pub fn new(config: GpisConfig) -> Result<Self, GpisError> {
        let grid = GridSpec::new(config.bounds, config.shape)?;
        let diagonal = grid.diagonal();
        let psi = config.psi.unwrap_or(DEFAULT_PSI_FACTOR * diagonal);
        if !(psi.is_finite() && psi >= diagonal) {
            return Err(GpisError::PsiTooSmall { psi, diagonal });
        }
        if psi > MAX_PSI {
            return Err(GpisError::PsiTooLarge { psi, max: MAX_PSI });
        }
        if !config.prior_mean.is_finite() {
            return Err(GpisError::NonFiniteParameter {
                what: "prior_mean",
                value: config.prior_mean,
            });
        }
        if config.max_rows == 0 {
            return Err(GpisError::InvalidCapacity {
                max_rows: config.max_rows,
            });
        }
        // The grid's own storage (centres, mean, variance), allocated fallibly: a grid too
        // large for this machine is an error, not an abort.
        let n_cells = grid.n_cells();
        let out_of_memory = |_| GpisError::OutOfMemory {
            what: "grid",
            gigabytes: gigabytes_of_f64s(4.0 * n_cells as f64),
        };
        let mut cell_xs = Vec::new();
        cell_xs.try_reserve_exact(n_cells).map_err(out_of_memory)?;
        cell_xs.extend(grid.cell_centres_iter().map(|c| c[0]));
        let mut cell_ys = Vec::new();
        cell_ys.try_reserve_exact(n_cells).map_err(out_of_memory)?;
        cell_ys.extend(grid.cell_centres_iter().map(|c| c[1]));
        let mut mean = Vec::new();
        mean.try_reserve_exact(n_cells).map_err(out_of_memory)?;
        let mut variance = Vec::new();
        variance.try_reserve_exact(n_cells).map_err(out_of_memory)?;
        let mut map = Self {
            grid,
            cell_xs,
            cell_ys,
            kernel: ThinPlateKernel::new(psi),
            prior_mean: config.prior_mean,
            max_rows: config.max_rows,
            rows: Vec::new(),
            observed: Vec::new(),
            noise_var: Vec::new(),
            capacity: 0,
            chol: Mat::zeros(0, 0),
            beta: Vec::new(),
            grid_cache_t: Mat::zeros(n_cells, 0),
            mean,
            variance,
            tiles: Arc::new(SerialTiles),
        };
        map.clear();
        Ok(map)
    }

    /// Lets `runner` compute the tiles of cells of every later grid update (with threads
    /// that would otherwise wait: the episode batch's). The map is bit for bit the same
    /// under any runner; a copy of the map shares it. Cost O(1).
    pub fn share_tiles(&mut self, runner: Arc<dyn TileRunner>) {
        self.tiles = runner;
    }

    /// The domain and its grid.
    pub fn grid(&self) -> &GridSpec {
        &self.grid
    }

    /// ψ.
    pub fn psi(&self) -> f64 {
        self.kernel.psi()
    }

    /// The kernel.
    pub fn kernel(&self) -> ThinPlateKernel {
        self.kernel
    }

    /// The constant prior mean of f.
    pub fn prior_mean(&self) -> f64 {
        self.prior_mean
    }

    /// Rows held.
    pub fn n_rows(&self) -> usize {
        self.rows.len()
    }

    /// Most rows the map will hold.
    pub fn max_rows(&self) -> usize {
        self.max_rows
    }

    /// Rows that can still be added.
    pub fn free_rows(&self) -> usize {
        self.max_rows - self.rows.len()
    }

    /// The rows held, in the order they were accepted.
    pub fn rows(&self) -> &[Row] {
        &self.rows
    }

    /// Posterior mean of f on the grid, row-major (H, W).
    pub fn mean_grid(&self) -> &[f64] {
        &self.mean
    }

    /// Posterior variance of f on the grid, row-major (H, W), clamped at 0.
    pub fn variance_grid(&self) -> &[f64] {
        &self.variance
    }

    /// The grid posterior recomputed from scratch over the rows held (the paper's
    /// approach). The reference for tests and benchmarks.
    ///
    /// # Cost
    /// O(n³/3) for the factorisation plus O(n²·G) for the grid.
    ///
    /// # Panics
    /// If K + Σ over the rows held is not positive definite when factored from scratch:
    /// every row was accepted with a positive pivot, so only round-off differing between
    /// the two factorisations could bring that about.
    pub fn recompute_from_scratch(&self) -> GridPosterior {
        full_posterior(
            self.kernel,
            self.prior_mean,
            &self.rows,
            &self.observed,
            &self.noise_var,
            &self.grid.cell_centres_iter().collect::<Vec<_>>(),
        )
    }
}
