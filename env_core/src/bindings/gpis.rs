//! `_core.GpisCore`: the Rust GPIS behind `tactile_search.Gpis` (which validates Python
//! types and shapes first; this layer re-checks shapes so it is safe on its own).

use numpy::{PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use super::errors::wrong_shape;
use super::prior::PyObservations;
use crate::gpis::{AddReport, Gpis, GpisConfig};

/// An (H, W) grid and a second one of the same shape.
type GridPair<'py> = (Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<f64>>);

/// Copies an (N, 2) float64 array into points.
fn to_points(what: &str, array: &PyReadonlyArray2<'_, f64>) -> PyResult<Vec<[f64; 2]>> {
    let view = array.as_array();
    if view.ncols() != 2 {
        return Err(wrong_shape(what, "(N, 2)", view.shape()));
    }
    Ok(view.rows().into_iter().map(|r| [r[0], r[1]]).collect())
}

/// The exact incremental GPIS map (see `tactile_search.Gpis`).
#[pyclass(name = "GpisCore", module = "tactile_search._core")]
pub struct PyGpis {
    inner: Gpis,
    last_report: AddReport,
}

#[pymethods]
impl PyGpis {
    #[new]
    #[pyo3(signature = (bounds, shape, psi, prior_mean, max_rows))]
    fn new(
        bounds: [[f64; 2]; 2],
        shape: (usize, usize),
        psi: Option<f64>,
        prior_mean: f64,
        max_rows: usize,
    ) -> PyResult<Self> {
        let inner = Gpis::new(GpisConfig {
            bounds,
            shape,
            psi,
            prior_mean,
            max_rows,
        })?;
        Ok(Self {
            inner,
            last_report: AddReport::default(),
        })
    }

    /// Adds value observations; returns the number of rows added.
    #[pyo3(signature = (points, values, noise_std))]
    fn add_values(
        &mut self,
        py: Python<'_>,
        points: PyReadonlyArray2<'_, f64>,
        values: Option<PyReadonlyArray1<'_, f64>>,
        noise_std: f64,
    ) -> PyResult<usize> {
        let points = to_points("points", &points)?;
        let values: Option<Vec<f64>> = values.map(|v| v.as_array().to_vec());
        let inner = &mut self.inner;
        let report = py.detach(|| inner.add_values(&points, values.as_deref(), noise_std))?;
        self.last_report = report;
        Ok(report.added_rows)
    }

    /// Adds contacts (point, outward normal); returns the number of rows added.
    #[pyo3(signature = (points, normals, noise_std, normal_noise_std, skip_below_variance))]
    fn add_contacts(
        &mut self,
        py: Python<'_>,
        points: PyReadonlyArray2<'_, f64>,
        normals: PyReadonlyArray2<'_, f64>,
        noise_std: f64,
        normal_noise_std: f64,
        skip_below_variance: Option<f64>,
    ) -> PyResult<usize> {
        let points = to_points("points", &points)?;
        let normals = to_points("normals", &normals)?;
        let inner = &mut self.inner;
        let report = py.detach(|| {
            inner.add_contacts(
                &points,
                &normals,
                noise_std,
                normal_noise_std,
                skip_below_variance,
            )
        })?;
        self.last_report = report;
        Ok(report.added_rows)
    }

    /// Adds the paper's circle prior (four contacts on a circle); returns rows added.
    #[pyo3(signature = (centre, diameter, noise_std, normal_noise_std))]
    fn add_circle_prior(
        &mut self,
        centre: [f64; 2],
        diameter: f64,
        noise_std: f64,
        normal_noise_std: f64,
    ) -> PyResult<usize> {
        let report = self
            .inner
            .add_circle_prior(centre, diameter, noise_std, normal_noise_std)?;
        self.last_report = report;
        Ok(report.added_rows)
    }

    /// Adds `observations` (e.g. from `depth_prior`) in one call, as the environment adds
    /// its prior; returns the number of rows added.
    fn add_observations(
        &mut self,
        py: Python<'_>,
        observations: PyRef<'_, PyObservations>,
    ) -> PyResult<usize> {
        let rows = &observations.rows;
        let inner = &mut self.inner;
        let report = py.detach(|| inner.add(rows, None))?;
        self.last_report = report;
        Ok(report.added_rows)
    }

    /// Posterior (mean, variance, mean gradient) at (M, 2) points.
    #[allow(clippy::type_complexity)]
    fn predict<'py>(
        &self,
        py: Python<'py>,
        points: PyReadonlyArray2<'py, f64>,
    ) -> PyResult<(
        Bound<'py, PyArray1<f64>>,
        Bound<'py, PyArray1<f64>>,
        Bound<'py, PyArray2<f64>>,
    )> {
        let points = to_points("points", &points)?;
        let inner = &self.inner;
        let prediction = py.detach(|| inner.predict(&points))?;
        let m = points.len();
        let gradient: Vec<f64> = prediction.gradient.iter().flatten().copied().collect();
        Ok((
            PyArray1::from_vec(py, prediction.mean),
            PyArray1::from_vec(py, prediction.variance),
            PyArray1::from_vec(py, gradient).reshape([m, 2])?,
        ))
    }

    /// The grid posterior recomputed from scratch (reference and benchmark baseline).
    fn recompute_from_scratch<'py>(&self, py: Python<'py>) -> PyResult<GridPair<'py>> {
        let inner = &self.inner;
        let posterior = py.detach(|| inner.recompute_from_scratch());
        let (h, w) = self.inner.grid().shape();
        Ok((
            PyArray1::from_vec(py, posterior.mean).reshape([h, w])?,
            PyArray1::from_vec(py, posterior.variance).reshape([h, w])?,
        ))
    }

    /// Forgets every observation (storage is kept for reuse).
    fn clear(&mut self) {
        self.inner.clear();
        self.last_report = AddReport::default();
    }

    /// Posterior mean on the grid, (H, W).
    #[getter]
    fn mean<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let (h, w) = self.inner.grid().shape();
        PyArray1::from_slice(py, self.inner.mean_grid()).reshape([h, w])
    }

    /// Posterior variance on the grid, (H, W).
    #[getter]
    fn variance<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let (h, w) = self.inner.grid().shape();
        PyArray1::from_slice(py, self.inner.variance_grid()).reshape([h, w])
    }

    /// Centres of the grid cells as (x, y), (H·W, 2) in row-major cell order.
    #[getter]
    fn cell_centres<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let grid = self.inner.grid();
        let flat: Vec<f64> = grid.cell_centres().into_iter().flatten().collect();
        PyArray1::from_vec(py, flat).reshape([grid.n_cells(), 2])
    }

    #[getter]
    fn psi(&self) -> f64 {
        self.inner.psi()
    }

    #[getter]
    fn n_rows(&self) -> usize {
        self.inner.n_rows()
    }

    #[getter]
    fn max_rows(&self) -> usize {
        self.inner.max_rows()
    }

    #[getter]
    fn free_rows(&self) -> usize {
        self.inner.free_rows()
    }

    #[getter]
    fn prior_mean(&self) -> f64 {
        self.inner.prior_mean()
    }

    #[getter]
    fn bounds(&self) -> [[f64; 2]; 2] {
        self.inner.grid().bounds()
    }

    #[getter]
    fn shape(&self) -> (usize, usize) {
        self.inner.grid().shape()
    }

    #[getter]
    fn memory_bytes(&self) -> usize {
        self.inner.memory_bytes()
    }

    /// What the last `add_*` call did, as a dict.
    #[getter]
    fn last_report<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let report = &self.last_report;
        let dict = PyDict::new(py);
        dict.set_item("added_rows", report.added_rows)?;
        dict.set_item("added_observations", report.added_observations)?;
        dict.set_item("skipped_uninformative", report.skipped_uninformative)?;
        dict.set_item("rejected_degenerate", report.rejected_degenerate)?;
        Ok(dict)
    }
}
