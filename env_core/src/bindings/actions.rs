//! Actions from Python, converted once to the core's [`Action`]s with their shape checked
//! here (their values are checked once, by the core, before any episode moves).
//!
//! A wrist motion is any array-like of numbers: float64 and float32 numpy arrays (what
//! agents hand over) are read in place; anything else goes through `numpy.asarray` and, if
//! its dtype is integer or real float, a cast to float64 (a complex, string, datetime,
//! boolean or object action is refused). A probe's indices are integers: an int64 array is
//! read in place, any other integer array-like cast to int64, and a float one refused with
//! a `TypeError`. Cost O(N).

use numpy::{PyArrayDyn, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;

use super::errors::{shape_text, type_name, wrong_shape, wrong_value};
use crate::episode::{Action, ActionMode};

/// Reads `value` as actions of `mode` of `shape` (`[3]` for one action, `[n, 3]` for a
/// batch); `what` names it in errors ("action" or "actions").
pub(crate) fn actions_of(
    what: &str,
    value: &Bound<'_, PyAny>,
    shape: &[usize],
    mode: ActionMode,
) -> PyResult<Vec<Action>> {
    Ok(match mode {
        ActionMode::Wrist => action_rows(what, value, shape)?
            .into_iter()
            .map(Action::Wrist)
            .collect(),
        ActionMode::Probe => probe_rows(what, value, shape)?
            .into_iter()
            .map(Action::Probe)
            .collect(),
    })
}

/// Reads `value` as integer probe indices of `shape` into rows of 3.
fn probe_rows(what: &str, value: &Bound<'_, PyAny>, shape: &[usize]) -> PyResult<Vec<[i64; 3]>> {
    if let Ok(array) = value.cast::<PyArrayDyn<i64>>() {
        check_shape(what, array.shape(), shape)?;
        let array = array.try_readonly().map_err(|e| unreadable(what, e))?;
        let flat: Vec<i64> = array.as_array().iter().copied().collect();
        return Ok(flat.chunks_exact(3).map(|r| [r[0], r[1], r[2]]).collect());
    }
    let array = value
        .py()
        .import("numpy")?
        .call_method1("asarray", (value,))
        .map_err(|_| not_integers(what, value, None))?;
    let kind: String = array.getattr("dtype")?.getattr("kind")?.extract()?;
    if !matches!(kind.as_str(), "i" | "u") {
        let dtype = array.getattr("dtype")?.str()?.to_string();
        return Err(not_integers(what, value, Some(&dtype)));
    }
    let converted = array.call_method1("astype", ("int64",))?;
    probe_rows(what, &converted, shape)
}

fn not_integers(what: &str, value: &Bound<'_, PyAny>, dtype: Option<&str>) -> PyErr {
    let got = match dtype {
        Some(dtype) => format!("{} of dtype {dtype}", type_name(value)),
        None => type_name(value),
    };
    PyTypeError::new_err(format!(
        "{what} must be integers in the probe action mode (lane, depth and sweep indices, 3 \
         per env), got {got}"
    ))
}

/// Reads `value` as an array of `shape` (`[3]` for one action, `[n, 3]` for a batch) into
/// rows of 3 wrist motions; `what` names it in errors ("action" or "actions").
fn action_rows(what: &str, value: &Bound<'_, PyAny>, shape: &[usize]) -> PyResult<Vec<[f64; 3]>> {
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
        let not_numeric = || {
            let got = value.repr().map_or_else(|_| "?".into(), |r| r.to_string());
            wrong_value(what, NUMERIC, format!("{} {got}", type_name(value)))
        };
        let array = py
            .import("numpy")?
            .call_method1("asarray", (value,))
            .map_err(|_| not_numeric())?;
        // Only integers and real floats: numpy would also cast a complex action (dropping
        // its imaginary part), numeric strings, datetimes and booleans to float64.
        let kind: String = array.getattr("dtype")?.getattr("kind")?.extract()?;
        if !matches!(kind.as_str(), "i" | "u" | "f") {
            let dtype = array.getattr("dtype")?.str()?.to_string();
            return Err(wrong_value(
                what,
                NUMERIC,
                format!("{} of dtype {dtype}", type_name(value)),
            ));
        }
        let converted = array
            .call_method1("astype", ("float64",))
            .map_err(|_| not_numeric())?;
        if converted.cast::<PyArrayDyn<f64>>().is_err() {
            return Err(not_numeric());
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

const NUMERIC: &str = "numeric with 3 entries per env";

fn unreadable(what: &str, error: impl std::fmt::Display) -> PyErr {
    wrong_value(what, "a readable array", error)
}
