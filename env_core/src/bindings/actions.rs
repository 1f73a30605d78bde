//! Actions from Python: any array-like of floats, converted once to `[f64; 3]` rows with its
//! shape checked here (finiteness is checked once, by the core, before any episode moves).
//!
//! float64 and float32 numpy arrays (what agents hand over) are read in place; anything
//! else goes through `numpy.asarray(..., dtype=float64)` first. Cost O(N).

use numpy::{PyArrayDyn, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use super::errors::{shape_text, wrong_shape};
use super::scene::type_name;

/// Reads `value` as an array of `shape` (`[3]` for one action, `[n, 3]` for a batch) into
/// rows of 3; `what` names it in errors ("action" or "actions").
pub(crate) fn action_rows(
    what: &str,
    value: &Bound<'_, PyAny>,
    shape: &[usize],
) -> PyResult<Vec<[f64; 3]>> {
    let flat = if let Ok(array) = value.cast::<PyArrayDyn<f64>>() {
        check_shape(what, array.shape(), shape)?;
        let array = array.try_readonly().map_err(|e| unreadable(what, e))?;
        array.as_array().iter().copied().collect::<Vec<f64>>()
    } else if let Ok(array) = value.cast::<PyArrayDyn<f32>>() {
        check_shape(what, array.shape(), shape)?;
        let array = array.try_readonly().map_err(|e| unreadable(what, e))?;
        array.as_array().iter().map(|&v| f64::from(v)).collect()
    } else {
        let py = value.py();
        let converted = py
            .import("numpy")?
            .call_method1("asarray", (value, "float64"))
            .map_err(|_| {
                PyValueError::new_err(format!(
                    "{what} must be numeric with 3 entries per env, got {} {}",
                    type_name(value),
                    value.repr().map_or_else(|_| "?".into(), |r| r.to_string())
                ))
            })?;
        if converted.cast::<PyArrayDyn<f64>>().is_err() {
            return Err(PyValueError::new_err(format!(
                "{what} must be numeric with 3 entries per env, got {}",
                type_name(value)
            )));
        }
        return action_rows(what, &converted, shape);
    };
    Ok(flat.chunks_exact(3).map(|r| [r[0], r[1], r[2]]).collect())
}

fn check_shape(what: &str, got: &[usize], expected: &[usize]) -> PyResult<()> {
    if got == expected {
        Ok(())
    } else {
        Err(wrong_shape(what, &shape_text(expected), got))
    }
}

fn unreadable(what: &str, error: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(format!("{what} could not be read: {error}"))
}
