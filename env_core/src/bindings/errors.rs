//! Every Python exception the bindings raise is built here. A setting that does not exist or
//! is of the wrong type is a `TypeError` (as Python's own for a bad keyword argument); every
//! other core error (a setting out of range, a bad layout, a non-finite
//! action) is a `ValueError`; each message says what was expected and what came.

use pyo3::exceptions::{PyIndexError, PyTypeError, PyValueError};
use pyo3::prelude::*;

use crate::episode::EpisodeError;
use crate::gpis::GpisError;
use crate::scene::SceneError;
use crate::settings::SettingError;

impl From<SettingError> for PyErr {
    fn from(error: SettingError) -> Self {
        match error {
            SettingError::WrongType { .. } | SettingError::UnknownKey { .. } => {
                PyTypeError::new_err(error.to_string())
            }
            SettingError::OutOfRange { .. } => PyValueError::new_err(error.to_string()),
        }
    }
}

impl From<GpisError> for PyErr {
    fn from(error: GpisError) -> Self {
        // Every GPIS error is a bad argument value (shape, bounds, noise, capacity), and its
        // message already says what was expected and what came.
        PyValueError::new_err(error.to_string())
    }
}

impl From<SceneError> for PyErr {
    fn from(error: SceneError) -> Self {
        match error {
            SceneError::Setting(setting) => setting.into(),
            // A bad layout, camera pose or command: a bad value, and the message says
            // what was expected and what came.
            other => PyValueError::new_err(other.to_string()),
        }
    }
}

impl From<EpisodeError> for PyErr {
    fn from(error: EpisodeError) -> Self {
        // Every episode error is a bad value (configuration, action, a step after the end,
        // a buffer of the wrong size); a batch's error names its episode itself.
        PyValueError::new_err(error.to_string())
    }
}

/// The Python type name of `value`, for messages.
pub(crate) fn type_name(value: &Bound<'_, PyAny>) -> String {
    value
        .get_type()
        .name()
        .map_or_else(|_| "?".to_owned(), |n| n.to_string())
}

/// A `ValueError` for an array whose shape is not the one expected.
pub(crate) fn wrong_shape(what: &str, expected: &str, got: &[usize]) -> PyErr {
    PyValueError::new_err(format!(
        "{what} must have shape {expected}, got shape {}",
        shape_text(got)
    ))
}

/// A `TypeError` for an argument of the wrong type: what was expected and what came (its
/// type, and its shape for an array or its repr for anything else).
pub(crate) fn wrong_type(what: &str, expected: &str, value: &Bound<'_, PyAny>) -> PyErr {
    let described = match value.getattr("shape") {
        Ok(shape) => format!(
            "{} of shape {}",
            type_name(value),
            shape
                .repr()
                .map_or_else(|_| "?".to_owned(), |r| r.to_string())
        ),
        Err(_) => format!(
            "{} {}",
            type_name(value),
            value
                .repr()
                .map_or_else(|_| "?".to_owned(), |r| r.to_string())
        ),
    };
    PyTypeError::new_err(format!("{what} must be {expected}, got {described}"))
}

/// A `ValueError` for an argument of the right type and a wrong value.
pub(crate) fn wrong_value(what: &str, expected: &str, got: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(format!("{what} must be {expected}, got {got}"))
}

/// An `IndexError` for an episode index outside the batch.
pub(crate) fn episode_index_error(index: usize, len: usize) -> PyErr {
    PyIndexError::new_err(format!(
        "episode index must be from 0 to {}, got {index}",
        len.saturating_sub(1)
    ))
}

/// A shape as Python writes it: `(3,)`, `(4, 3)`.
pub(crate) fn shape_text(shape: &[usize]) -> String {
    match shape {
        [one] => format!("({one},)"),
        _ => {
            let dims: Vec<String> = shape.iter().map(usize::to_string).collect();
            format!("({})", dims.join(", "))
        }
    }
}
