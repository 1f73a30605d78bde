//! `_core.depth_prior` and `_core.Observations`: the environment's depth prior as a
//! function, so that experiments start their maps from the identical rows the environment
//! does (`GpisCore.add_observations` adds them in the same single call as the episode).

use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use super::arrays::{grid, points, vector};
use super::settings::config_from;
use crate::episode::maps::gpis::prior;
use crate::episode::EpisodeConfig;
use crate::gpis::Observation;

/// GP observations in the order they enter a map: values (one row each) and contacts
/// (three rows: value and normal). Read-only; add them with `Gpis.add_observations`.
#[pyclass(name = "Observations", module = "tactile_search._core", frozen)]
pub struct PyObservations {
    pub(super) rows: Vec<Observation>,
}

impl PyObservations {
    fn column<'py, const K: usize>(
        &self,
        py: Python<'py>,
        f: impl Fn(&Observation) -> [f64; K],
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let flat: Vec<f64> = self.rows.iter().flat_map(f).collect();
        PyArray1::from_vec(py, flat).reshape([self.rows.len(), K])
    }
}

#[pymethods]
impl PyObservations {
    fn __len__(&self) -> usize {
        self.rows.len()
    }

    /// GP rows they take (1 per value, 3 per contact).
    #[getter]
    fn n_rows(&self) -> usize {
        self.rows.iter().map(Observation::n_rows).sum()
    }

    /// Where each was made, (N, 2).
    #[getter]
    fn points<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.column(py, Observation::point)
    }

    /// True for a contact (value and normal), False for a value, (N,).
    #[getter]
    fn is_contact<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<bool>> {
        let flags = self
            .rows
            .iter()
            .map(|o| matches!(o, Observation::Contact { .. }));
        PyArray1::from_iter(py, flags)
    }

    /// Observed f (0 for a contact), (N,).
    #[getter]
    fn values<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        let values = self.rows.iter().map(|o| match *o {
            Observation::Value { value, .. } => value,
            Observation::Contact { .. } => 0.0,
        });
        PyArray1::from_iter(py, values)
    }

    /// Outward unit normal of a contact ((0, 0) for a value), (N, 2).
    #[getter]
    fn normals<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.column(py, |o| match *o {
            Observation::Value { .. } => [0.0, 0.0],
            Observation::Contact { normal, .. } => normal,
        })
    }

    /// Noise variance of the value row, (N,).
    #[getter]
    fn noise_var<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        let var = self.rows.iter().map(|o| match *o {
            Observation::Value { noise_var, .. } | Observation::Contact { noise_var, .. } => {
                noise_var
            }
        });
        PyArray1::from_iter(py, var)
    }

    /// Noise variance of each normal row of a contact (0 for a value), (N,).
    #[getter]
    fn normal_noise_var<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        let var = self.rows.iter().map(|o| match *o {
            Observation::Value { .. } => 0.0,
            Observation::Contact {
                normal_noise_var, ..
            } => normal_noise_var,
        });
        PyArray1::from_iter(py, var)
    }

    fn __repr__(&self) -> String {
        let contacts = self
            .rows
            .iter()
            .filter(|o| matches!(o, Observation::Contact { .. }))
            .count();
        format!(
            "Observations({} values, {contacts} contacts, {} rows)",
            self.rows.len() - contacts,
            self.n_rows()
        )
    }
}

/// The depth prior's observations for the slice `slice_points` (N, 2) seen from `camera`
/// (x, y), on the map grid `(bounds, shape)`, exactly as the environment starts its map
/// (`env_core/src/episode/maps/gpis/prior.rs`). `settings` are episode settings as the environment
/// takes them (the prior reads `circle_prior_diameter`, `map_depth_noise_std`,
/// `max_prior_depth_points`, `free_space_offset`, `prior_wall_clearance`,
/// `contact_noise_std`, `normal_noise_std` and `max_rows`); each defaults to the
/// environment's. The constant prior mean is the map's (`Gpis(prior_mean=...)`), not a row.
#[pyfunction]
#[pyo3(signature = (slice_points, camera, bounds, shape, **settings))]
pub(super) fn depth_prior(
    py: Python<'_>,
    slice_points: &Bound<'_, PyAny>,
    camera: &Bound<'_, PyAny>,
    bounds: &Bound<'_, PyAny>,
    shape: &Bound<'_, PyAny>,
    settings: Option<&Bound<'_, PyDict>>,
) -> PyResult<PyObservations> {
    let slice = points("slice_points", slice_points)?;
    let camera = vector("camera", camera, 2)?;
    let grid = grid(bounds, shape)?;
    let config = config_from::<EpisodeConfig>(None, settings, None)?;
    let camera = [camera[0], camera[1]];
    let rows = py.detach(|| prior::depth_prior(&slice, camera, &grid, &config.map))?;
    Ok(PyObservations { rows })
}

/// Registers the class and the function of this file on the module.
pub(super) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyObservations>()?;
    m.add_function(wrap_pyfunction!(depth_prior, m)?)?;
    Ok(())
}
