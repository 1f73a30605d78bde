//! The grid's half of an `add`: the cache's new columns, the mean and the variance brought up
//! to date once for every row the `add` kept, in tiles of cells.
//!
//! One product with the old cache and one triangular solve over all the new columns, rather
//! than a product and a solve per chunk. For the episode's depth prior (an empty map, about
//! 130 rows on 3200 cells) this is nearly all of an `add`'s cost: G·k²/2 multiply-adds in the
//! solve.
//!
//! The tiles run on the map's thread, or on whatever threads its [`TileRunner`] lends
//! ([`Gpis::share_tiles`]: an episode batch's idle threads); each tile takes its own rows of
//! the new columns and of the grids, so the map is the same bit for bit.
//!
//! [`TileRunner`]: crate::gpis::TileRunner

use faer::linalg::matmul::matmul;
use faer::linalg::triangular_solve::solve_lower_triangular_in_place;
use faer::reborrow::{Reborrow, ReborrowMut};
use faer::{Accum, MatMut, MatRef, Par};

use super::Gpis;
use crate::gpis::tiles::run_each;

/// Grid cells updated together by an `add`: their slice of the new cache columns (256 × k
/// f64s, under 0.5 MB for k = 200) stays in the core's cache from the kernel columns through
/// the product, the solve and the fold, instead of the whole G × k panel being streamed
/// through memory once per step (cells are independent: the tiling changes results only by
/// rounding).
const CELL_TILE: usize = 256;

/// One tile's share of a grid update: its first cell, its rows of the cache's new
/// columns, and its cells of the mean and variance grids.
struct GridTile<'a> {
    first: usize,
    cache: MatMut<'a, f64>,
    mean: &'a mut [f64],
    variance: &'a mut [f64],
}

impl Gpis {
    /// Brings the grid up to date with the rows from `held` on (the second half of the
    /// module docs' update, for every row one `add` kept):
    /// V₂ᵀ = (K*₂ − Vᵀ L₂₁ᵀ) L₂₂⁻ᵀ, computed as G × k in place in the cache's new columns,
    /// then mean += V₂ᵀ β₂ and variance −= colsum(V₂ ∘ V₂), clamped at 0.
    /// Cost O(G·k·held + G·k²) for k = `n_rows() - held`.
    pub(super) fn update_grid(&mut self, held: usize) {
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
