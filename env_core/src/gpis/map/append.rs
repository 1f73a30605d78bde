//! Appending observations: the checks, then L and β grown chunk by chunk with the rejecting
//! factorisation deciding which rows stay (the first half of the update in the map's module
//! docs), then one grid update for every row kept ([`super::grid_update`]).

use faer::linalg::matmul::matmul;
use faer::linalg::triangular_solve::solve_lower_triangular_in_place;
use faer::{Accum, Mat, Par};

use super::Gpis;
use crate::gpis::error::GpisError;
use crate::gpis::observation::{noise_variance, Observation, Row};
use crate::gpis::rejecting_cholesky::{factor_rejecting, GroupOutcome, RejectingFactor, RowGroup};

/// Rows factored per step of an `add`. The grid is updated once per `add`, whatever the
/// chunks; the rejecting factorisation of a chunk costs O(chunk³), so keep it modest.
const CHUNK_ROWS: usize = 48;

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

impl Gpis {
    /// Adds value observations f(points[i]) = values[i] (0 when `values` is `None`).
    ///
    /// # Cost
    /// That of [`Gpis::add`] with k = `points.len()` rows.
    ///
    /// # Errors
    /// [`GpisError::NegativeParameter`] for a negative or non-finite `noise_std`,
    /// [`GpisError::LengthMismatch`] when `values` and `points` differ in length,
    /// [`GpisError::NonFiniteInput`] for a non-finite point or value, and those of
    /// [`Gpis::add`]. Nothing is added on error.
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
    ///
    /// # Cost
    /// That of [`Gpis::add`] with k = 3 · `points.len()` rows (a value and two gradient
    /// rows per contact).
    ///
    /// # Errors
    /// [`GpisError::NegativeParameter`] for a negative or non-finite noise,
    /// [`GpisError::LengthMismatch`] when `normals` and `points` differ in length,
    /// [`GpisError::NonFiniteInput`] for a non-finite point or normal,
    /// [`GpisError::ZeroNormal`] for a zero normal, and those of [`Gpis::add`]. Nothing is
    /// added on error.
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
    ///
    /// # Cost
    /// That of [`Gpis::add`] with k = 12 rows.
    ///
    /// # Errors
    /// [`GpisError::NegativeParameter`] for a negative or non-finite noise or a diameter
    /// that is not positive, [`GpisError::NonFiniteInput`] for a non-finite centre, and
    /// those of [`Gpis::add`]. Nothing is added on error.
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

    /// Adds observations in order; the report says which were kept, skipped as
    /// uninformative (below `skip_below_variance`) or rejected as degenerate (a pivot that
    /// is not positive, such as a duplicated noise-free point).
    ///
    /// # Cost
    /// O(k·n·G + k·n² + k²·G) for k new rows on n held and G grid cells, instead of the
    /// O(n³ + n²·G) of a full recompute; for an empty map the grid's solve, G·k²/2
    /// multiply-adds, is nearly all of it. Growing the storage, when k rows do not fit,
    /// copies it once: O(cap² + G·cap).
    ///
    /// # Errors
    /// Checked before any work, so that nothing is added on error:
    /// [`GpisError::NegativeParameter`] for a negative or non-finite threshold,
    /// [`GpisError::PointOutsideBounds`] for an observation outside the bounds,
    /// [`GpisError::CapacityExceeded`] when the rows could exceed `max_rows` (counting
    /// every row as if none were skipped), and [`GpisError::OutOfMemory`] when the storage
    /// for them cannot be allocated.
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

    /// Grows L and β by one chunk of observations (the first half of the module docs'
    /// update: L₂₁, L₂₂ and β₂); the grid follows in [`Self::update_grid`]. Cost
    /// O(k·n² + k²·n + k³) for a chunk of k rows on n held.
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
}
