//! Every conversion of a core error to a Python exception, in one place.

use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;

use crate::episode::EpisodeError;
use crate::gpis::GpisError;
use crate::scene::SceneError;

impl From<GpisError> for PyErr {
    fn from(error: GpisError) -> Self {
        // Every GPIS error is a bad argument value (shape, bounds, noise, capacity), and its
        // message already says what was expected and what came.
        PyValueError::new_err(error.to_string())
    }
}

impl From<SceneError> for PyErr {
    fn from(error: SceneError) -> Self {
        // Every scene error is a bad value (config entry, layout, command), and its message
        // says what was expected and what came.
        PyValueError::new_err(error.to_string())
    }
}

/// A `ValueError` naming the episode of a batch that failed: bad configuration, a
/// non-finite action or a step after the end are all bad values.
pub(crate) fn episode_error(index: usize, error: EpisodeError) -> PyErr {
    PyValueError::new_err(format!("episode {index}: {error}"))
}

/// A `ValueError` for an array whose shape is not the one expected.
pub(crate) fn wrong_shape(what: &str, expected: &str, got: &[usize]) -> PyErr {
    PyValueError::new_err(format!(
        "{what} must have shape {expected}, got shape {got:?}"
    ))
}

impl From<EpisodeError> for PyErr {
    fn from(error: EpisodeError) -> Self {
        // Episode errors outside a batch (the depth prior's settings and options) are bad
        // values; the message names the setting, the value and the range expected.
        PyValueError::new_err(error.to_string())
    }
}

/// A `TypeError` for an argument of the wrong kind: what was expected and what came.
pub(crate) fn wrong_kind(what: &str, expected: &str, got: &Bound<'_, PyAny>) -> PyErr {
    let kind = got
        .get_type()
        .name()
        .map_or_else(|_| "?".to_owned(), |n| n.to_string());
    let shape = got
        .getattr("shape")
        .ok()
        .and_then(|s| s.repr().ok())
        .map_or_else(String::new, |s| format!(" of shape {s}"));
    PyTypeError::new_err(format!("{what} must be {expected}, got {kind}{shape}"))
}

/// A `ValueError` for an argument of the right kind with a wrong value.
pub(crate) fn bad_value(what: &str, expected: &str, got: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(format!("{what} must be {expected}, got {got}"))
}
