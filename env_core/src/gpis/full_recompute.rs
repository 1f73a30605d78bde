//! The GPIS posterior on a grid computed from scratch, as the paper does after every new
//! measurement. Cost O(n³/3) for the factorisation plus O(n²·G) for the grid. It is the
//! reference the incremental update is tested against, and the baseline of its benchmark.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::{cholesky_in_place, cholesky_in_place_scratch};
use faer::linalg::triangular_solve::solve_lower_triangular_in_place;
use faer::{Mat, MatRef, Par};

use super::kernel::{RowKind, ThinPlateKernel};
use super::observation::Row;

/// Posterior mean and variance on every grid cell, row-major.
#[derive(Debug, Clone, PartialEq)]
pub struct GridPosterior {
    /// Posterior mean of f.
    pub mean: Vec<f64>,
    /// Posterior variance of f, clamped at 0 against round-off.
    pub variance: Vec<f64>,
}

/// Builds K + Σ over `rows`, factors it, and evaluates the posterior at `cells`.
///
/// # Panics
/// If K + Σ is not positive definite. Rows accepted by [`crate::gpis::Gpis`] always give a
/// positive definite matrix; callers passing arbitrary rows must avoid exact duplicates.
pub fn full_posterior(
    kernel: ThinPlateKernel,
    prior_mean: f64,
    rows: &[Row],
    observed: &[f64],
    noise_var: &[f64],
    cells: &[[f64; 2]],
) -> GridPosterior {
    let n = rows.len();
    let mut factor = Mat::from_fn(n, n, |i, j| {
        let (a, b) = (&rows[i], &rows[j]);
        kernel.covariance(a.point, a.kind, b.point, b.kind)
            + if i == j { noise_var[i] } else { 0.0 }
    });
    let mut scratch = MemBuffer::new(cholesky_in_place_scratch::<f64>(
        n,
        Par::Seq,
        Default::default(),
    ));
    cholesky_in_place(
        factor.as_mut(),
        Default::default(),
        Par::Seq,
        MemStack::new(&mut scratch),
        Default::default(),
    )
    .expect("K + Σ of accepted rows is positive definite");

    let mut beta = Mat::from_fn(n, 1, |i, _| observed[i] - rows[i].prior_mean(prior_mean));
    solve_lower_triangular_in_place(factor.as_ref(), beta.as_mut(), Par::Seq);
    let mut cache = Mat::from_fn(n, cells.len(), |i, cell| {
        kernel.covariance(rows[i].point, rows[i].kind, cells[cell], RowKind::Value)
    });
    solve_lower_triangular_in_place(factor.as_ref(), cache.as_mut(), Par::Seq);

    let beta: Vec<f64> = beta.col(0).iter().copied().collect();
    let (mean, variance) = posterior_from_solved(
        cache.as_ref(),
        &beta,
        prior_mean,
        kernel.prior_variance(RowKind::Value),
    );
    GridPosterior { mean, variance }
}

/// Mean m + wᵀβ and variance ψ³ − |w|² (clamped at 0) for each column w of
/// `solved` = L⁻¹ K*ᵀ (n × M). Cost O(n·M).
pub(crate) fn posterior_from_solved(
    solved: MatRef<'_, f64>,
    beta: &[f64],
    prior_mean: f64,
    prior_variance: f64,
) -> (Vec<f64>, Vec<f64>) {
    let columns = solved.ncols();
    let mut mean = Vec::with_capacity(columns);
    let mut variance = Vec::with_capacity(columns);
    for c in 0..columns {
        let mut explained = 0.0;
        let mut reduction = 0.0;
        for (&v, &b) in solved.col(c).iter().zip(beta) {
            explained += v * b;
            reduction += v * v;
        }
        mean.push(prior_mean + explained);
        variance.push((prior_variance - reduction).max(0.0));
    }
    (mean, variance)
}
