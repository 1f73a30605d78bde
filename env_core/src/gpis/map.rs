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
//! Cost O(k·n·G + k·n²) per append instead of the O(n³ + n²·G) of a full recompute. Storage
//! grows by doubling up to `max_rows`; memory is about 8·(cap² + G·cap) bytes.
//!
//! An `add` first grows L and β chunk by chunk (the rejecting factorisation decides which
//! rows stay), then updates the grid once for every row it kept: one product with the old
//! cache and one triangular solve over all the new columns, rather than a product and a
//! solve per chunk, in tiles of cells. For the episode's depth prior (an empty map, about 130
//! rows on 3200 cells) that grid work is nearly all of the cost: G·k²/2 multiply-adds in
//! the solve.
//!
//! The tiles run on the map's thread, or on whatever threads its [`TileRunner`] lends
//! ([`Gpis::share_tiles`]: an episode batch's idle threads); each tile takes its own rows
//! of the new columns and of the grids, so the map is the same bit for bit.

use faer::linalg::matmul::matmul;
use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_upper_triangular_in_place,
};
use faer::reborrow::{Reborrow, ReborrowMut};
use faer::{Accum, Mat, MatMut, MatRef, Par};
use std::sync::Arc;

use super::error::GpisError;
use super::full_recompute::{full_posterior, posterior_from_solved, GridPosterior};
use super::grid::GridSpec;
use super::kernel::{RowKind, ThinPlateKernel};
use super::observation::{noise_variance, Observation, Row};
use super::rejecting_cholesky::{factor_rejecting, GroupOutcome, RejectingFactor, RowGroup};
use super::tiles::{run_each, SerialTiles, TileRunner};

/// Default ψ as a multiple of the bounds' diagonal (`docs/DESIGN.md` §3).
pub const DEFAULT_PSI_FACTOR: f64 = 1.5;

/// Rows factored per step of an `add`. The grid is updated once per `add`, whatever the
/// chunks; the rejecting factorisation of a chunk costs O(chunk³), so keep it modest.
const CHUNK_ROWS: usize = 48;

/// Grid cells updated together by an `add`: their slice of the new cache columns (256 × k
/// f64s, under 0.5 MB for k = 200) stays in the core's cache from the kernel columns through
/// the product, the solve and the fold, instead of the whole G × k panel being streamed
/// through memory once per step (cells are independent: the tiling changes results only by
/// rounding).
const CELL_TILE: usize = 256;

/// Smallest row capacity allocated once the first row arrives.
const MIN_CAPACITY: usize = 64;

/// The row capacity storage is sized for when `rows` rows must fit: half as many again, as
/// headroom, rounded up to a power of two (so that a map's storage takes few sizes). The
/// headroom matters for the episode's map: its depth prior alone fills 128 rows at the
/// defaults, and without room to spare nearly half the episodes grew the storage to 256 rows
/// with their first touches (a fresh 6.5 MB grid cache: page faults and a copy) and the next
/// `clear` gave it back, a fifth of a random probe's time in the kernel's page handling.
fn capacity_for(rows: usize) -> usize {
    (rows + rows / 2).next_power_of_two().max(MIN_CAPACITY)
}

/// The gigabytes (1e9 bytes) that `count` f64s take.
fn gigabytes_of_f64s(count: f64) -> f64 {
    count * std::mem::size_of::<f64>() as f64 / 1e9
}

/// Largest ψ: the kernel's values grow as ψ³, and sums of many of them must stay far from
/// f64's overflow (ψ³ = 1e300 leaves eight orders of magnitude).
pub const MAX_PSI: f64 = 1e100;

/// The defaults of a map and of its `add_*` calls as the Python API takes them
/// (`tactile_search.Gpis`, through `_core.gpis_defaults()`): the one place they are typed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GpisDefaults {
    /// ψ without one given: this times the bounds' diagonal ([`DEFAULT_PSI_FACTOR`]).
    pub psi_factor: f64,
    /// Constant prior mean of f.
    pub prior_mean: f64,
    /// Most rows the map will hold.
    pub max_rows: usize,
    /// Standard deviation of a value observation's noise, m (depth is noisier than touch).
    pub value_noise_std: f64,
    /// Standard deviation of a contact position's value noise, m.
    pub contact_noise_std: f64,
    /// Standard deviation of each contact-normal component's noise.
    pub normal_noise_std: f64,
    /// Diameter of the paper's circle prior, m (the paper's 0.03 m).
    pub circle_diameter: f64,
}

/// The GPIS API's defaults (see [`GpisDefaults`]).
pub const GPIS_DEFAULTS: GpisDefaults = GpisDefaults {
    psi_factor: DEFAULT_PSI_FACTOR,
    prior_mean: 0.0,
    max_rows: 4096,
    value_noise_std: 0.002,
    contact_noise_std: 0.0005,
    normal_noise_std: 0.05,
    circle_diameter: 0.03,
};

/// How a map is built. `psi: None` means [`DEFAULT_PSI_FACTOR`] × the bounds' diagonal.
#[derive(Debug, Clone, PartialEq)]
pub struct GpisConfig {
    /// `[[x0, x1], [y0, y1]]` in metres.
    pub bounds: [[f64; 2]; 2],
    /// Grid shape (H, W).
    pub shape: (usize, usize),
    /// The kernel's ψ; must be at least the bounds' diagonal.
    pub psi: Option<f64>,
    /// Constant prior mean of f (positive = free space).
    pub prior_mean: f64,
    /// Most rows the map will ever hold.
    pub max_rows: usize,
}

/// What an `add` call did.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct AddReport {
    /// GP rows appended.
    pub added_rows: usize,
    /// Observations appended.
    pub added_observations: usize,
    /// Observations skipped because the variance at their point was below the threshold.
    pub skipped_uninformative: usize,
    /// Observations rejected because their pivot was not positive (e.g. a duplicate).
    pub rejected_degenerate: usize,
}

/// Posterior at arbitrary points.
#[derive(Debug, Clone, PartialEq)]
pub struct Prediction {
    /// Posterior mean of f.
    pub mean: Vec<f64>,
    /// Posterior variance of f (clamped at 0 against round-off).
    pub variance: Vec<f64>,
    /// Gradient of the posterior mean, ∇E[f]: with f ≈ a signed distance near surfaces,
    /// it points away from objects.
    pub gradient: Vec<[f64; 2]>,
}

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

/// One tile's share of a grid update: its first cell, its rows of the cache's new
/// columns, and its cells of the mean and variance grids.
struct GridTile<'a> {
    first: usize,
    cache: MatMut<'a, f64>,
    mean: &'a mut [f64],
    variance: &'a mut [f64],
}

impl Clone for Gpis {
    /// A copy with the same spare capacity: faer's `Mat::clone` allocates exactly the n × n
    /// in use of the factor (the grid cache is `capacity` columns wide already), and without
    /// re-reserving every later append to the copy would reallocate and copy the factor
    /// (measured 5× slower appends at n = 1000, when the cache grew the same way).
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
    /// An empty map (prior only). Fails on bad bounds, shape, ψ, prior mean or capacity.
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

    /// Forgets every observation, keeping storage for reuse: [`capacity_for`] as many rows
    /// as the map held. Storage of twice that or more, grown by an unusually large map, is
    /// released, so a map reused across episodes holds what its last episode needed, not the
    /// most any episode ever did (a soak of 10^6 steps saw memory creep otherwise).
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

    /// Lets `runner` compute the tiles of cells of every later grid update (with threads
    /// that would otherwise wait: the episode batch's). The map is bit for bit the same
    /// under any runner; a copy of the map shares it.
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

    /// Bytes held by the map's numeric state (factor, grid cache, grids, row data).
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

    /// Adds value observations f(points[i]) = values[i] (0 when `values` is `None`).
    pub fn add_values(
        &mut self,
        points: &[[f64; 2]],
        values: Option<&[f64]>,
        noise_std: f64,
    ) -> Result<AddReport, GpisError> {
        let noise_var = noise_variance("noise_std", noise_std)?;
        if let Some(values) = values {
            if values.len() != points.len() {
                return Err(GpisError::LengthMismatch {
                    what: "values",
                    expected: points.len(),
                    got: values.len(),
                });
            }
        }
        let observations = points
            .iter()
            .enumerate()
            .map(|(i, &p)| Observation::value(i, p, values.map_or(0.0, |v| v[i]), noise_var))
            .collect::<Result<Vec<_>, _>>()?;
        self.add(&observations, None)
    }

    /// Adds contacts: f(points[i]) = 0 and ∇f(points[i]) = normals[i] / |normals[i]|.
    /// With `skip_below_variance`, a contact whose posterior variance at its point (given
    /// everything before it, including earlier contacts of this call) is below the
    /// threshold is skipped.
    pub fn add_contacts(
        &mut self,
        points: &[[f64; 2]],
        normals: &[[f64; 2]],
        noise_std: f64,
        normal_noise_std: f64,
        skip_below_variance: Option<f64>,
    ) -> Result<AddReport, GpisError> {
        let noise_var = noise_variance("noise_std", noise_std)?;
        let normal_noise_var = noise_variance("normal_noise_std", normal_noise_std)?;
        if normals.len() != points.len() {
            return Err(GpisError::LengthMismatch {
                what: "normals",
                expected: points.len(),
                got: normals.len(),
            });
        }
        let observations = points
            .iter()
            .zip(normals)
            .enumerate()
            .map(|(i, (&p, &n))| Observation::contact(i, p, n, noise_var, normal_noise_var))
            .collect::<Result<Vec<_>, _>>()?;
        self.add(&observations, skip_below_variance)
    }

    /// Adds the paper's circle prior: four contacts on a circle of `diameter` around
    /// `centre` with outward normals (see [`Observation::circle_prior`]).
    pub fn add_circle_prior(
        &mut self,
        centre: [f64; 2],
        diameter: f64,
        noise_std: f64,
        normal_noise_std: f64,
    ) -> Result<AddReport, GpisError> {
        let observations = Observation::circle_prior(
            centre,
            diameter,
            noise_variance("noise_std", noise_std)?,
            noise_variance("normal_noise_std", normal_noise_std)?,
        )?;
        self.add(&observations, None)
    }

    /// Adds observations in order. Nothing is added if any point is outside the bounds, the
    /// threshold is invalid, or the rows could exceed `max_rows` (checked before any work,
    /// counting every row as if none were skipped).
    pub fn add(
        &mut self,
        observations: &[Observation],
        skip_below_variance: Option<f64>,
    ) -> Result<AddReport, GpisError> {
        if let Some(threshold) = skip_below_variance {
            if !(threshold.is_finite() && threshold >= 0.0) {
                return Err(GpisError::NegativeParameter {
                    what: "skip_below_variance",
                    value: threshold,
                });
            }
        }
        for (i, obs) in observations.iter().enumerate() {
            self.grid.check_inside(i, obs.point())?;
        }
        let requested: usize = observations.iter().map(Observation::n_rows).sum();
        if self.rows.len() + requested > self.max_rows {
            return Err(GpisError::CapacityExceeded {
                capacity: self.max_rows,
                current: self.rows.len(),
                requested,
            });
        }
        self.reserve_rows(self.rows.len() + requested)?;
        let held = self.rows.len();
        let mut report = AddReport::default();
        let mut start = 0;
        while start < observations.len() {
            let mut end = start;
            let mut chunk_rows = 0;
            while end < observations.len()
                && (end == start || chunk_rows + observations[end].n_rows() <= CHUNK_ROWS)
            {
                chunk_rows += observations[end].n_rows();
                end += 1;
            }
            self.factor_chunk(&observations[start..end], skip_below_variance, &mut report);
            start = end;
        }
        self.update_grid(held);
        Ok(report)
    }

    /// Grows the storage to hold `rows` rows: to [`capacity_for`] them, at least doubling,
    /// or says how much it needed if the allocation fails (the map is left as it was).
    fn reserve_rows(&mut self, rows: usize) -> Result<(), GpisError> {
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

    /// Grows L and β by one chunk of observations (the first half of the module docs'
    /// update: L₂₁, L₂₂ and β₂); the grid follows in [`Self::update_grid`].
    fn factor_chunk(
        &mut self,
        observations: &[Observation],
        skip_below_variance: Option<f64>,
        report: &mut AddReport,
    ) {
        let kernel = self.kernel;
        let n = self.rows.len();
        let mut new_rows = Vec::new();
        let mut new_observed = Vec::new();
        let mut new_noise = Vec::new();
        let mut groups = Vec::with_capacity(observations.len());
        for obs in observations {
            let first = new_rows.len();
            for (row, value, noise_var) in obs.rows() {
                new_rows.push(row);
                new_observed.push(value);
                new_noise.push(noise_var);
            }
            groups.push(RowGroup {
                rows: first..new_rows.len(),
                skip_below_variance,
                value_noise_var: new_noise[first],
            });
        }
        let k = new_rows.len();
        let cov = |a: &Row, b: &Row| kernel.covariance(a.point, a.kind, b.point, b.kind);

        // W = L⁻¹ B, so that L₂₁ = Wᵀ.
        let mut w = Mat::from_fn(n, k, |i, c| cov(&self.rows[i], &new_rows[c]));
        solve_lower_triangular_in_place(self.chol.as_ref(), w.as_mut(), Par::Seq);

        // Schur complement C − L₂₁ L₂₁ᵀ, factored with rejection of bad observations.
        let mut schur = Mat::from_fn(k, k, |a, b| {
            cov(&new_rows[a], &new_rows[b]) + if a == b { new_noise[a] } else { 0.0 }
        });
        matmul(
            schur.as_mut(),
            Accum::Add,
            w.transpose(),
            w.as_ref(),
            -1.0,
            Par::Seq,
        );
        let prior_scale: Vec<f64> = (0..k)
            .map(|a| kernel.prior_variance(new_rows[a].kind) + new_noise[a])
            .collect();
        let RejectingFactor {
            accepted,
            factor,
            outcomes,
        } = factor_rejecting(schur.as_ref(), &prior_scale, &groups);
        for outcome in outcomes {
            match outcome {
                GroupOutcome::Accepted => report.added_observations += 1,
                GroupOutcome::Uninformative => report.skipped_uninformative += 1,
                GroupOutcome::Degenerate => report.rejected_degenerate += 1,
            }
        }
        let kept = accepted.len();
        if kept == 0 {
            return;
        }
        report.added_rows += kept;

        // β₂ = L₂₂⁻¹ (y₂ − m₂ − L₂₁ β).
        let mut beta_new = Mat::from_fn(kept, 1, |c, _| {
            let row = &new_rows[accepted[c]];
            let explained: f64 = (0..n).map(|i| w[(i, accepted[c])] * self.beta[i]).sum();
            new_observed[accepted[c]] - row.prior_mean(self.prior_mean) - explained
        });
        solve_lower_triangular_in_place(factor.as_ref(), beta_new.as_mut(), Par::Seq);

        // Grow L by [L₂₁ L₂₂], then record the rows.
        // `add` reserved storage for every row it could add: no allocation here.
        debug_assert!(n + kept <= self.capacity);
        self.chol.resize_with(n + kept, n + kept, |i, j| {
            if i < n {
                0.0
            } else if j < n {
                w[(j, accepted[i - n])]
            } else if j <= i {
                factor[(i - n, j - n)]
            } else {
                0.0
            }
        });
        for (c, &a) in accepted.iter().enumerate() {
            self.rows.push(new_rows[a]);
            self.observed.push(new_observed[a]);
            self.noise_var.push(new_noise[a]);
            self.beta.push(beta_new[(c, 0)]);
        }
    }

    /// Brings the grid up to date with the rows from `held` on (the second half of the
    /// module docs' update, for every row one `add` kept):
    /// V₂ᵀ = (K*₂ − Vᵀ L₂₁ᵀ) L₂₂⁻ᵀ, computed as G × k in place in the cache's new columns,
    /// then mean += V₂ᵀ β₂ and variance −= colsum(V₂ ∘ V₂), clamped at 0.
    fn update_grid(&mut self, held: usize) {
        let n = self.rows.len();
        let k = n - held;
        if k == 0 {
            return;
        }
        let kernel = self.kernel;
        let n_cells = self.cell_xs.len();
        let l21 = self.chol.as_ref().submatrix(held, 0, k, held);
        let l22 = self.chol.as_ref().submatrix(held, held, k, k);
        let (rows, beta) = (&self.rows[held..], &self.beta[held..]);
        let (cell_xs, cell_ys) = (&self.cell_xs, &self.cell_ys);
        // `add` reserved storage for every row it could add.
        let (old_cache, rest) = self.grid_cache_t.as_mut().split_at_col_mut(held);
        let old_cache = old_cache.rb();
        // Each tile's share of the new columns and of the grids.
        let mut tiles = Vec::with_capacity(n_cells.div_ceil(CELL_TILE));
        let mut cache_rest = rest.subcols_mut(0, k);
        let (mut mean_rest, mut variance_rest) = (&mut self.mean[..], &mut self.variance[..]);
        let mut first = 0;
        while first < n_cells {
            let cells = CELL_TILE.min(n_cells - first);
            let (cache, cache_tail) = cache_rest.split_at_row_mut(cells);
            let (mean, mean_tail) = mean_rest.split_at_mut(cells);
            let (variance, variance_tail) = variance_rest.split_at_mut(cells);
            tiles.push(GridTile {
                first,
                cache,
                mean,
                variance,
            });
            (cache_rest, mean_rest, variance_rest) = (cache_tail, mean_tail, variance_tail);
            first += cells;
        }
        let update_tile = |tile: GridTile<'_>| {
            let GridTile {
                first,
                mut cache,
                mean,
                variance,
            } = tile;
            let cells = mean.len();
            for (c, row) in rows.iter().enumerate() {
                kernel.value_column(
                    &cell_xs[first..first + cells],
                    &cell_ys[first..first + cells],
                    row.point,
                    row.kind,
                    column_mut(&mut cache, c),
                );
            }
            if held > 0 {
                matmul(
                    cache.rb_mut(),
                    Accum::Add,
                    old_cache.subrows(first, cells),
                    l21.transpose(),
                    -1.0,
                    Par::Seq,
                );
            }
            solve_lower_triangular_in_place(l22, cache.rb_mut().transpose_mut(), Par::Seq);
            fold_into_grids(cache.rb(), beta, mean, variance);
        };
        run_each(self.tiles.as_ref(), tiles, update_tile);
    }

    /// Posterior mean, variance and mean gradient at arbitrary points inside the bounds.
    /// Cost O(n²·M) for M points.
    pub fn predict(&self, points: &[[f64; 2]]) -> Result<Prediction, GpisError> {
        for (i, &p) in points.iter().enumerate() {
            if !(p[0].is_finite() && p[1].is_finite()) {
                return Err(GpisError::NonFiniteInput {
                    what: "points",
                    index: i,
                    value: p.to_vec(),
                });
            }
            self.grid.check_inside(i, p)?;
        }
        let kernel = self.kernel;
        let n = self.rows.len();
        let m = points.len();
        let mut solved = Mat::from_fn(n, m, |i, c| {
            let row = &self.rows[i];
            kernel.covariance(row.point, row.kind, points[c], RowKind::Value)
        });
        solve_lower_triangular_in_place(self.chol.as_ref(), solved.as_mut(), Par::Seq);
        let (mean, variance) = posterior_from_solved(
            solved.as_ref(),
            &self.beta,
            self.prior_mean,
            kernel.prior_variance(RowKind::Value),
        );
        // α = L⁻ᵀ β = (K + Σ)⁻¹ (y − m); ∇E[f](x) = Σᵢ cov(∇f(x), rowᵢ) αᵢ.
        let mut alpha = Mat::from_fn(n, 1, |i, _| self.beta[i]);
        solve_upper_triangular_in_place(self.chol.transpose(), alpha.as_mut(), Par::Seq);
        let gradient = points
            .iter()
            .map(|&p| {
                let mut g = [0.0; 2];
                for (axis, kind) in [RowKind::GradX, RowKind::GradY].into_iter().enumerate() {
                    g[axis] = self
                        .rows
                        .iter()
                        .enumerate()
                        .map(|(i, row)| {
                            kernel.covariance(p, kind, row.point, row.kind) * alpha[(i, 0)]
                        })
                        .sum();
                }
                g
            })
            .collect();
        Ok(Prediction {
            mean,
            variance,
            gradient,
        })
    }

    /// The grid posterior recomputed from scratch over the rows held (the paper's
    /// approach, O(n³ + n²·G)). The reference for tests and benchmarks.
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

/// mean += X β and variance −= rowsum(X ∘ X), clamped at 0, for the cache's new columns X
/// (G × k): four columns per pass, so the grids are read and written k/4 times, not k.
fn fold_into_grids(columns: MatRef<'_, f64>, beta: &[f64], mean: &mut [f64], variance: &mut [f64]) {
    let cells = mean.len();
    let column = |c: usize| {
        &columns
            .col(c)
            .try_as_col_major()
            .expect("the grid cache is column-major")
            .as_slice()[..cells]
    };
    let variance = &mut variance[..cells];
    let mut c = 0;
    while c + 4 <= columns.ncols() {
        let (x0, x1, x2, x3) = (column(c), column(c + 1), column(c + 2), column(c + 3));
        let (b0, b1, b2, b3) = (beta[c], beta[c + 1], beta[c + 2], beta[c + 3]);
        for i in 0..cells {
            let (v0, v1, v2, v3) = (x0[i], x1[i], x2[i], x3[i]);
            mean[i] += (v0 * b0 + v1 * b1) + (v2 * b2 + v3 * b3);
            variance[i] -= (v0 * v0 + v1 * v1) + (v2 * v2 + v3 * v3);
        }
        c += 4;
    }
    for c in c..columns.ncols() {
        let (x, b) = (column(c), beta[c]);
        for i in 0..cells {
            mean[i] += x[i] * b;
            variance[i] -= x[i] * x[i];
        }
    }
    for v in variance {
        *v = v.max(0.0);
    }
}

/// Column `c` of a column-major matrix view as a slice (the grid cache's columns are
/// contiguous: its rows are the grid's cells).
fn column_mut<'a>(matrix: &'a mut MatMut<'_, f64>, c: usize) -> &'a mut [f64] {
    matrix
        .rb_mut()
        .col_mut(c)
        .try_as_col_major_mut()
        .expect("the grid cache is column-major")
        .as_slice_mut()
}
