//! Conversion helpers shared by the classes: seeds, and numpy arrays out of the core's
//! row-major data.

use numpy::{PyArray1, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyInt};

use super::errors::{wrong_type, wrong_value};

/// A seed: an int in [0, 2**64).
pub(crate) fn seed_of(seed: &Bound<'_, PyAny>) -> PyResult<u64> {
    if seed.is_instance_of::<PyBool>() || !seed.is_instance_of::<PyInt>() {
        return Err(wrong_type("seed", "an int", seed));
    }
    seed.extract::<u64>()
        .map_err(|_| wrong_value("seed", "an int from 0 to 2**64 - 1", seed))
}

/// A thread count: a positive integer (a Python or numpy int, not a bool), or None for
/// every core.
pub(crate) fn threads_of(threads: Option<&Bound<'_, PyAny>>) -> PyResult<Option<usize>> {
    match threads.filter(|t| !t.is_none()) {
        None => Ok(None),
        Some(threads) => positive_int("threads", "a positive int or None", threads).map(Some),
    }
}

/// A count `what`: a positive integer (a Python or numpy int, not a bool); `TypeError` for
/// another type, `ValueError` below 1.
pub(crate) fn count_of(what: &str, count: &Bound<'_, PyAny>) -> PyResult<usize> {
    positive_int(what, "a positive int", count)
}

fn positive_int(what: &str, expected: &str, value: &Bound<'_, PyAny>) -> PyResult<usize> {
    if value.is_instance_of::<PyBool>() {
        return Err(wrong_type(what, expected, value));
    }
    let whole: i128 = value
        .extract()
        .map_err(|_| wrong_type(what, expected, value))?;
    usize::try_from(whole)
        .ok()
        .filter(|&n| n >= 1)
        .ok_or_else(|| wrong_value(what, expected, value))
}

/// An (rows, cols) float64 array owning `flat` (row-major).
pub(crate) fn array2<'py>(
    py: Python<'py>,
    rows: usize,
    cols: usize,
    flat: Vec<f64>,
) -> PyResult<Bound<'py, PyAny>> {
    Ok(PyArray1::from_vec(py, flat)
        .reshape([rows, cols])?
        .into_any())
}

/// An (N, K) float64 array from N rows of K values.
pub(crate) fn rows_array<'py, const K: usize>(
    py: Python<'py>,
    rows: &[[f64; K]],
) -> PyResult<Bound<'py, PyAny>> {
    array2(py, rows.len(), K, rows.iter().flatten().copied().collect())
}
