//! Actions from Python: any array-like of floats, converted once to `[f64; 3]` rows with its
//! shape checked here (finiteness is checked once, by the core, before any episode moves).
//!
//! float64 and float32 numpy arrays (what agents hand over) are read in place; anything
//! else goes through `numpy.asarray` and, if its dtype is integer or real float, a cast to
//! float64 (a complex, string, datetime, boolean or object action is refused). Cost O(N).

use numpy::{PyArrayDyn, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::prelude::*;

use super::errors::{shape_text, type_name, wrong_shape, wrong_value};

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
