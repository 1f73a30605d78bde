//! `_core.GpisCore`: the Rust GPIS behind `tactile_search.Gpis` (which validates Python
//! types and shapes first; this layer re-checks shapes so it is safe on its own).

use numpy::{PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use super::errors::wrong_shape;
use super::exclusive::Exclusive;
use super::prior::PyObservations;
use crate::gpis::{AddReport, Gpis, GpisConfig, GpisError};

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
#[pyclass(name = "GpisCore", module = "tactile_search._core", frozen)]
pub struct PyGpis {
    state: Exclusive<GpisState>,
}

/// The map and what its last `add_*` call did.
struct GpisState {
    gpis: Gpis,
    last_report: AddReport,
}

impl PyGpis {
    /// Runs `add` on the map with the GIL released and keeps its report.
    fn add(
        &self,
        py: Python<'_>,
        add: impl FnOnce(&mut Gpis) -> Result<AddReport, GpisError> + Send,
    ) -> PyResult<usize> {
        let mut state = self.state.lock()?;
        let gpis = &mut state.gpis;
        let report = py.detach(|| add(gpis))?;
        state.last_report = report;
        Ok(report.added_rows)
    }
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
            state: Exclusive::new(
                "GpisCore (the core of a Gpis map)",
                GpisState {
                    gpis: inner,
                    last_report: AddReport::default(),
                },
            ),
        })
    }

    /// Adds value observations; returns the number of rows added.
    #[pyo3(signature = (points, values, noise_std))]
    fn add_values(
        &self,
        py: Python<'_>,
        points: PyReadonlyArray2<'_, f64>,
        values: Option<PyReadonlyArray1<'_, f64>>,
        noise_std: f64,
    ) -> PyResult<usize> {
        let points = to_points("points", &points)?;
        let values: Option<Vec<f64>> = values.map(|v| v.as_array().to_vec());
        self.add(py, |gpis| {
            gpis.add_values(&points, values.as_deref(), noise_std)
        })
    }

    /// Adds contacts (point, outward normal); returns the number of rows added.
    #[pyo3(signature = (points, normals, noise_std, normal_noise_std, skip_below_variance))]
    fn add_contacts(
        &self,
        py: Python<'_>,
        points: PyReadonlyArray2<'_, f64>,
        normals: PyReadonlyArray2<'_, f64>,
        noise_std: f64,
        normal_noise_std: f64,
        skip_below_variance: Option<f64>,
    ) -> PyResult<usize> {
        let points = to_points("points", &points)?;
        let normals = to_points("normals", &normals)?;
        self.add(py, |gpis| {
            gpis.add_contacts(
                &points,
                &normals,
                noise_std,
                normal_noise_std,
                skip_below_variance,
            )
        })
    }

    /// Adds the paper's circle prior (four contacts on a circle); returns rows added.
    #[pyo3(signature = (centre, diameter, noise_std, normal_noise_std))]
    fn add_circle_prior(
        &self,
        py: Python<'_>,
        centre: [f64; 2],
        diameter: f64,
        noise_std: f64,
        normal_noise_std: f64,
    ) -> PyResult<usize> {
        self.add(py, |gpis| {
            gpis.add_circle_prior(centre, diameter, noise_std, normal_noise_std)
        })
    }

    /// Adds `observations` (e.g. from `depth_prior`) in one call, as the environment adds
    /// its prior; returns the number of rows added.
    fn add_observations(
        &self,
        py: Python<'_>,
        observations: PyRef<'_, PyObservations>,
    ) -> PyResult<usize> {
        let rows = &observations.rows;
        self.add(py, |gpis| gpis.add(rows, None))
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
        let state = self.state.lock()?;
        let inner = &state.gpis;
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
        let state = self.state.lock()?;
        let inner = &state.gpis;
        let posterior = py.detach(|| inner.recompute_from_scratch());
        let (h, w) = inner.grid().shape();
        Ok((
            PyArray1::from_vec(py, posterior.mean).reshape([h, w])?,
            PyArray1::from_vec(py, posterior.variance).reshape([h, w])?,
        ))
    }

    /// Forgets every observation (storage is kept for reuse).
    fn clear(&self) -> PyResult<()> {
        let mut state = self.state.lock()?;
        state.gpis.clear();
        state.last_report = AddReport::default();
        Ok(())
    }

    /// Posterior mean on the grid, (H, W).
    #[getter]
    fn mean<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let state = self.state.lock()?;
        let (h, w) = state.gpis.grid().shape();
        PyArray1::from_slice(py, state.gpis.mean_grid()).reshape([h, w])
    }

    /// Posterior variance on the grid, (H, W).
    #[getter]
    fn variance<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let state = self.state.lock()?;
        let (h, w) = state.gpis.grid().shape();
        PyArray1::from_slice(py, state.gpis.variance_grid()).reshape([h, w])
    }

    /// Centres of the grid cells as (x, y), (H·W, 2) in row-major cell order.
    #[getter]
    fn cell_centres<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let state = self.state.lock()?;
        let grid = state.gpis.grid();
        let flat: Vec<f64> = grid.cell_centres().into_iter().flatten().collect();
        PyArray1::from_vec(py, flat).reshape([grid.n_cells(), 2])
    }

    #[getter]
    fn psi(&self) -> PyResult<f64> {
        Ok(self.state.lock()?.gpis.psi())
    }

    #[getter]
    fn n_rows(&self) -> PyResult<usize> {
        Ok(self.state.lock()?.gpis.n_rows())
    }

    #[getter]
    fn max_rows(&self) -> PyResult<usize> {
        Ok(self.state.lock()?.gpis.max_rows())
    }

    #[getter]
    fn free_rows(&self) -> PyResult<usize> {
        Ok(self.state.lock()?.gpis.free_rows())
    }

    #[getter]
    fn prior_mean(&self) -> PyResult<f64> {
        Ok(self.state.lock()?.gpis.prior_mean())
    }

    #[getter]
    fn bounds(&self) -> PyResult<[[f64; 2]; 2]> {
        Ok(self.state.lock()?.gpis.grid().bounds())
    }

    #[getter]
    fn shape(&self) -> PyResult<(usize, usize)> {
        Ok(self.state.lock()?.gpis.grid().shape())
    }

    #[getter]
    fn memory_bytes(&self) -> PyResult<usize> {
        Ok(self.state.lock()?.gpis.memory_bytes())
    }

    /// What the last `add_*` call did, as a dict.
    #[getter]
    fn last_report<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let state = self.state.lock()?;
        let report = &state.last_report;
        let dict = PyDict::new(py);
        dict.set_item("added_rows", report.added_rows)?;
        dict.set_item("added_observations", report.added_observations)?;
        dict.set_item("skipped_uninformative", report.skipped_uninformative)?;
        dict.set_item("rejected_degenerate", report.rejected_degenerate)?;
        Ok(dict)
    }
}
