//! `_core.GpisCore`: the Rust GPIS behind `tactile_search.Gpis`, and `_core.gpis_defaults()`,
//! the defaults its signature shows. The constructor's arguments are checked here (the
//! wrapper passes them as they came): `TypeError` for the wrong kind, `ValueError` for a
//! wrong value, each naming the argument, what was expected and what came. The `add_*`
//! arguments come checked by the wrapper's array helpers; this layer re-checks shapes so it
//! is safe on its own.

use numpy::{PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat};

use super::errors::{type_name, wrong_shape};
use super::exclusive::Exclusive;
use super::prior::PyObservations;
use crate::gpis::{AddReport, Gpis, GpisConfig, GpisError, GPIS_DEFAULTS};

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

/// `value`'s type name and repr, as `float: nan`.
fn described(value: &Bound<'_, PyAny>) -> String {
    let repr = value
        .repr()
        .map_or_else(|_| "?".to_owned(), |r| r.to_string());
    format!("{}: {repr}", type_name(value))
}

/// How Python writes the float `v` (`nan`, `inf`, `0.5`).
fn float_text(py: Python<'_>, v: f64) -> String {
    PyFloat::new(py, v)
        .repr()
        .map_or_else(|_| v.to_string(), |r| r.to_string())
}

/// `isinstance(value, numbers.<abc>)` and not a bool.
fn is_number(value: &Bound<'_, PyAny>, abc: &str) -> PyResult<bool> {
    let class = value.py().import("numbers")?.getattr(abc)?;
    Ok(!value.is_instance_of::<PyBool>() && value.is_instance(&class)?)
}

/// A finite real scalar `what`.
fn real(what: &str, value: &Bound<'_, PyAny>) -> PyResult<f64> {
    if !is_number(value, "Real")? {
        return Err(PyTypeError::new_err(format!(
            "{what} must be a real number, got {}",
            described(value)
        )));
    }
    let v: f64 = value
        .py()
        .import("builtins")?
        .getattr("float")?
        .call1((value,))?
        .extract()?;
    if !v.is_finite() {
        return Err(PyValueError::new_err(format!(
            "{what} must be finite, got {}",
            float_text(value.py(), v)
        )));
    }
    Ok(v)
}

/// An integer `what` of at least 1 that fits in 64 bits.
fn count(what: &str, value: &Bound<'_, PyAny>) -> PyResult<usize> {
    if !is_number(value, "Integral")? {
        return Err(PyTypeError::new_err(format!(
            "{what} must be an integer, got {}",
            described(value)
        )));
    }
    let int = value.call_method0("__index__")?;
    if int.lt(1)? {
        return Err(PyValueError::new_err(format!(
            "{what} must be at least 1, got {int}"
        )));
    }
    let n: u64 = int.extract().map_err(|_| {
        PyValueError::new_err(format!(
            "{what} must fit in 64 bits (at most 2**64 - 1), got {int}"
        ))
    })?;
    usize::try_from(n).map_err(|_| {
        PyValueError::new_err(format!(
            "{what} must fit in this machine's word (at most {}), got {int}",
            usize::MAX
        ))
    })
}

/// A grid shape: two positive integers (H, W).
fn grid_shape(value: &Bound<'_, PyAny>) -> PyResult<(usize, usize)> {
    const EXPECTED: &str = "shape must be two positive integers (H, W)";
    let items: Vec<Bound<'_, PyAny>> = value
        .try_iter()
        .map_err(|_| PyTypeError::new_err(format!("{EXPECTED}, got {}", described(value))))?
        .collect::<PyResult<_>>()?;
    let [h, w] = items.as_slice() else {
        let repr = value.repr()?;
        return Err(PyValueError::new_err(format!("{EXPECTED}, got {repr}")));
    };
    Ok((count("shape[0]", h)?, count("shape[1]", w)?))
}

/// Bounds ((x0, x1), (y0, y1)) with finite lower < upper along each axis.
fn bounds(value: &Bound<'_, PyAny>) -> PyResult<[[f64; 2]; 2]> {
    let py = value.py();
    let numpy = py.import("numpy")?;
    let kwargs = PyDict::new(py);
    kwargs.set_item("dtype", numpy.getattr("float64")?)?;
    let array = numpy
        .call_method("ascontiguousarray", (value,), Some(&kwargs))
        .map_err(|error| {
            PyTypeError::new_err(format!(
                "bounds must be an array of real numbers, got {}: {}",
                type_name(value),
                error.value(py)
            ))
        })?;
    let shape: Vec<usize> = array.getattr("shape")?.extract()?;
    if shape != [2, 2] {
        let shape = array.getattr("shape")?.repr()?;
        return Err(PyValueError::new_err(format!(
            "bounds must be ((x0, x1), (y0, y1)), got shape {shape}"
        )));
    }
    let flat: Vec<f64> = array.call_method0("ravel")?.extract()?;
    if let Some(i) = flat.iter().position(|v| !v.is_finite()) {
        return Err(PyValueError::new_err(format!(
            "bounds must be finite, got {} at index ({}, {})",
            float_text(py, flat[i]),
            i / 2,
            i % 2
        )));
    }
    let b = [[flat[0], flat[1]], [flat[2], flat[3]]];
    for (axis, [lower, upper]) in ["x", "y"].into_iter().zip(b) {
        // Finite here, so this is not (lower < upper).
        if lower >= upper {
            return Err(PyValueError::new_err(format!(
                "bounds along {axis} must have lower < upper, got ({}, {})",
                float_text(py, lower),
                float_text(py, upper)
            )));
        }
    }
    Ok(b)
}

/// `value` unless it is missing or None.
fn given<'a, 'py>(value: Option<&'a Bound<'py, PyAny>>) -> Option<&'a Bound<'py, PyAny>> {
    value.filter(|v| !v.is_none())
}

/// The defaults of `tactile_search.Gpis` (the map's and its `add_*` calls'):
/// `psi_factor`, `prior_mean`, `max_rows`, `value_noise_std`, `contact_noise_std`,
/// `normal_noise_std`, `circle_diameter`.
#[pyfunction]
pub(super) fn gpis_defaults(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    let d = PyDict::new(py);
    let g = GPIS_DEFAULTS;
    d.set_item("psi_factor", g.psi_factor)?;
    d.set_item("prior_mean", g.prior_mean)?;
    d.set_item("max_rows", g.max_rows)?;
    d.set_item("value_noise_std", g.value_noise_std)?;
    d.set_item("contact_noise_std", g.contact_noise_std)?;
    d.set_item("normal_noise_std", g.normal_noise_std)?;
    d.set_item("circle_diameter", g.circle_diameter)?;
    Ok(d)
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
    /// A map over `bounds` ((x0, x1), (y0, y1)) on an `shape` (H, W) grid. `psi` None is
    /// `psi_factor` (of `gpis_defaults()`) times the bounds' diagonal; `prior_mean` and
    /// `max_rows` must be given (`Gpis` passes the defaults of `gpis_defaults()`): None for
    /// either is a TypeError naming it, as for `Gpis`. Every argument is checked, in order.
    #[new]
    #[pyo3(signature = (bounds, shape, psi, prior_mean, max_rows))]
    fn new(
        bounds: &Bound<'_, PyAny>,
        shape: &Bound<'_, PyAny>,
        psi: Option<&Bound<'_, PyAny>>,
        prior_mean: &Bound<'_, PyAny>,
        max_rows: &Bound<'_, PyAny>,
    ) -> PyResult<Self> {
        let bounds = self::bounds(bounds)?;
        let shape = grid_shape(shape)?;
        let psi = given(psi).map(|v| real("psi", v)).transpose()?;
        let prior_mean = real("prior_mean", prior_mean)?;
        let max_rows = count("max_rows", max_rows)?;
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
