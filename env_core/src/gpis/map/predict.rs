//! The posterior at arbitrary points, off the grid: mean, variance and the mean's gradient.

use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_upper_triangular_in_place,
};
use faer::{Mat, Par};

use super::Gpis;
use crate::gpis::error::GpisError;
use crate::gpis::full_recompute::posterior_from_solved;
use crate::gpis::kernel::RowKind;

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

impl Gpis {
    /// Posterior mean, variance and mean gradient at arbitrary points inside the bounds.
    ///
    /// # Cost
    /// O(n²·M) for M points on n rows held (a triangular solve per point), plus O(n²) once.
    ///
    /// # Errors
    /// [`GpisError::NonFiniteInput`] for a non-finite point and
    /// [`GpisError::PointOutsideBounds`] for one outside the bounds, before any work.
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
}
