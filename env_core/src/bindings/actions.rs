//! Actions from Python, converted once to the core's [`Action`]s with their shape checked
//! here (their values are checked once, by the core, before any episode moves).
//!
//! A wrist motion is any array-like of numbers: float64 and float32 numpy arrays (what
//! agents hand over) are read in place; anything else goes through `numpy.asarray` and, if
//! its dtype is integer or real float, a cast to float64 (a complex, string, datetime,
//! boolean or object action is refused). A probe's indices are integers: an int64 array is
//! read in place, any other integer array-like cast to int64, and a float one refused with
//! a `TypeError`. Each row becomes an action by the core's rule
//! ([`Action::from_wrist_row`], [`Action::from_probe_row`]: a 4th entry, the claim, where
//! the task claims). Cost O(N).

use numpy::{PyArrayDyn, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;

use super::errors::{shape_text, type_name, wrong_shape, wrong_value};
use crate::episode::action_mode::action_len;
use crate::episode::{Action, ActionMode, EpisodeError};

/// Reads `value` as the actions of `episodes` episodes of `mode` (None: one action, of
/// shape `[len]`; Some(n): a batch of shape `[n, len]`, `len` 3, or 4 where the task
/// `claims`); `what` names it in errors ("action" or "actions"). A row the core refuses
/// (a bad claim entry) is a `ValueError` naming its episode in a batch.
pub(crate) fn actions_of(
    what: &str,
    value: &Bound<'_, PyAny>,
    episodes: Option<usize>,
    mode: ActionMode,
    claims: bool,
) -> PyResult<Vec<Action>> {
    let len = action_len(claims);
    let shape: Vec<usize> = episodes.into_iter().chain([len]).collect();
    let in_batch = |i: usize, e: EpisodeError| match episodes {
        Some(_) => PyErr::from(e.in_episode(i)),
        None => PyErr::from(e),
    };
    match mode {
        ActionMode::Wrist => action_rows(what, value, &shape)?
            .chunks_exact(len)
            .enumerate()
            .map(|(i, row)| Action::from_wrist_row(row, claims).map_err(|e| in_batch(i, e)))
            .collect(),
        ActionMode::Probe => probe_rows(what, value, &shape)?
            .chunks_exact(len)
            .enumerate()
            .map(|(i, row)| Action::from_probe_row(row, claims).map_err(|e| in_batch(i, e)))
            .collect(),
    }
}

/// Reads `value` as integer probe indices of `shape`, flat.
fn probe_rows(what: &str, value: &Bound<'_, PyAny>, shape: &[usize]) -> PyResult<Vec<i64>> {
    if let Ok(array) = value.cast::<PyArrayDyn<i64>>() {
        check_shape(what, array.shape(), shape)?;
        let array = array.try_readonly().map_err(|e| unreadable(what, e))?;
        return Ok(array.as_array().iter().copied().collect());
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
        "{what} must be integers in the probe action mode (lane, depth and sweep indices, \
         and the claim index where the task claims), got {got}"
    ))
}

/// Reads `value` as a float64 array of `shape`, flat; `what` names it in errors.
fn action_rows(what: &str, value: &Bound<'_, PyAny>, shape: &[usize]) -> PyResult<Vec<f64>> {
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
    Ok(flat)
}

fn check_shape(what: &str, got: &[usize], expected: &[usize]) -> PyResult<()> {
    if got == expected {
        Ok(())
    } else {
        Err(wrong_shape(what, &shape_text(expected), got))
    }
}

const NUMERIC: &str = "numeric, a row of entries per env";

fn unreadable(what: &str, error: impl std::fmt::Display) -> PyErr {
    wrong_value(what, "a readable array", error)
}
