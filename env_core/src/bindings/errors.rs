//! Every conversion of a core error to a Python exception, in one place.

use pyo3::exceptions::PyValueError;
use pyo3::PyErr;

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

impl From<EpisodeError> for PyErr {
    fn from(error: EpisodeError) -> Self {
        // Every episode error is a bad value (configuration, action, a step after the end,
        // a buffer of the wrong size); a batch's error names its episode itself.
        PyValueError::new_err(error.to_string())
    }
}

/// A `ValueError` for an array whose shape is not the one expected.
pub(crate) fn wrong_shape(what: &str, expected: &str, got: &[usize]) -> PyErr {
    PyValueError::new_err(format!(
        "{what} must have shape {expected}, got shape {}",
        shape_text(got)
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
