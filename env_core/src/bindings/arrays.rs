//! Conversion of array arguments (points, vectors, grids, masks, bounds, grid shapes) for
//! the function bindings: numpy arrays or nested sequences in, checked plain Rust values
//! out, every refusal a `TypeError` or `ValueError` saying what was expected and what came.

use numpy::{PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray2};
use pyo3::prelude::*;

use super::errors::{wrong_type, wrong_value};
use crate::gpis::GridSpec;

/// The rows of a 2-D float array `what` (any float dtype or nested sequence), or a
/// `TypeError`; rows must have `columns` entries and be finite.
pub(super) fn matrix(
    what: &str,
    value: &Bound<'_, PyAny>,
    columns: usize,
) -> PyResult<(usize, Vec<f64>)> {
    let expected = format!("a 2-D float array of shape (N, {columns})");
    let array = as_float_array(value).map_err(|_| wrong_type(what, &expected, value))?;
    let array = array
        .cast_into::<PyArray2<f64>>()
        .map_err(|e| wrong_type(what, &expected, e.into_inner().as_any()))?;
    let readonly: PyReadonlyArray2<'_, f64> = array.readonly();
    let view = readonly.as_array();
    if view.ncols() != columns {
        return Err(wrong_value(
            what,
            &expected,
            format!("shape {:?}", view.shape()),
        ));
    }
    let flat: Vec<f64> = view.iter().copied().collect();
    check_finite(what, &flat)?;
    Ok((view.nrows(), flat))
}

/// (N, 2) points.
pub(super) fn points(what: &str, value: &Bound<'_, PyAny>) -> PyResult<Vec<[f64; 2]>> {
    let (_, flat) = matrix(what, value, 2)?;
    Ok(flat.chunks_exact(2).map(|c| [c[0], c[1]]).collect())
}

/// An (H, W) float grid, finite, as H·W row-major values and (H, W).
pub(super) fn grid_values(
    what: &str,
    value: &Bound<'_, PyAny>,
) -> PyResult<(Vec<f64>, (usize, usize))> {
    let expected = "a 2-D float array of shape (H, W)";
    let array = as_float_array(value).map_err(|_| wrong_type(what, expected, value))?;
    let array = array
        .cast_into::<PyArray2<f64>>()
        .map_err(|e| wrong_type(what, expected, e.into_inner().as_any()))?;
    let readonly = array.readonly();
    let view = readonly.as_array();
    let flat: Vec<f64> = view.iter().copied().collect();
    check_finite(what, &flat)?;
    Ok((flat, (view.nrows(), view.ncols())))
}

/// A float vector of `len` finite entries.
pub(super) fn vector(what: &str, value: &Bound<'_, PyAny>, len: usize) -> PyResult<Vec<f64>> {
    let expected = format!("a 1-D float array of length {len}");
    let array = as_float_array(value).map_err(|_| wrong_type(what, &expected, value))?;
    let array = array
        .cast_into::<PyArray1<f64>>()
        .map_err(|e| wrong_type(what, &expected, e.into_inner().as_any()))?;
    let values = array.readonly().as_array().to_vec();
    if values.len() != len {
        return Err(wrong_value(
            what,
            &expected,
            format!("length {}", values.len()),
        ));
    }
    check_finite(what, &values)?;
    Ok(values)
}

/// A boolean (H, W) mask as H·W row-major flags.
pub(super) fn mask(
    what: &str,
    value: &Bound<'_, PyAny>,
    shape: (usize, usize),
) -> PyResult<Vec<bool>> {
    let expected = format!("a 2-D bool array of shape {shape:?}");
    let numpy = value.py().import("numpy")?;
    let is_bool = numpy
        .call_method1("asarray", (value,))
        .and_then(|a| a.getattr("dtype"))
        .and_then(|d| d.getattr("kind"))
        .and_then(|k| k.extract::<String>())
        .is_ok_and(|k| k == "b");
    if !is_bool {
        return Err(wrong_type(what, &expected, value));
    }
    let array = numpy
        .call_method1("asarray", (value,))?
        .cast_into::<PyArray2<bool>>()
        .map_err(|e| wrong_type(what, &expected, e.into_inner().as_any()))?;
    let readonly = array.readonly();
    let view = readonly.as_array();
    if (view.nrows(), view.ncols()) != shape {
        return Err(wrong_value(
            what,
            &expected,
            format!("shape {:?}", view.shape()),
        ));
    }
    Ok(view.iter().copied().collect())
}

/// Map bounds `((x0, x1), (y0, y1))` and a grid shape `(H, W)` as a checked grid.
pub(super) fn grid(bounds: &Bound<'_, PyAny>, shape: &Bound<'_, PyAny>) -> PyResult<GridSpec> {
    let bounds: [[f64; 2]; 2] = bounds
        .extract()
        .map_err(|_| wrong_type("bounds", "((x0, x1), (y0, y1)) of floats", bounds))?;
    let shape = grid_shape(shape)?;
    Ok(GridSpec::new(bounds, shape)?)
}

/// A grid shape `(H, W)` of positive ints.
pub(super) fn grid_shape(shape: &Bound<'_, PyAny>) -> PyResult<(usize, usize)> {
    let (h, w): (Bound<'_, PyAny>, Bound<'_, PyAny>) = shape
        .extract()
        .map_err(|_| wrong_type("shape", "a pair of ints (H, W)", shape))?;
    Ok((count("shape[0]", &h)?, count("shape[1]", &w)?))
}

/// A positive int `what`.
pub(super) fn count(what: &str, value: &Bound<'_, PyAny>) -> PyResult<usize> {
    if value.is_instance_of::<pyo3::types::PyBool>()
        || !value.is_instance_of::<pyo3::types::PyInt>()
    {
        return Err(wrong_type(what, "a positive int", value));
    }
    value
        .extract::<usize>()
        .ok()
        .filter(|&n| n > 0)
        .ok_or_else(|| wrong_value(what, "a positive int", value))
}

/// `numpy.asarray(value, dtype=float64)`, or the error numpy raised.
fn as_float_array<'py>(value: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
    if value.is_instance_of::<pyo3::types::PyString>() {
        return Err(pyo3::exceptions::PyTypeError::new_err(
            "a string is not an array",
        ));
    }
    let numpy = value.py().import("numpy")?;
    let kwargs = pyo3::types::PyDict::new(value.py());
    kwargs.set_item("dtype", numpy.getattr("float64")?)?;
    numpy.call_method("asarray", (value,), Some(&kwargs))
}

fn check_finite(what: &str, values: &[f64]) -> PyResult<()> {
    match values.iter().position(|v| !v.is_finite()) {
        None => Ok(()),
        Some(i) => Err(wrong_value(
            what,
            "finite everywhere",
            format!("{} at flat index {i}", values[i]),
        )),
    }
}
