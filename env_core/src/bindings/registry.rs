//! The registered environment ids, from the core's table, for the Python package to
//! register with gymnasium.

use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use super::settings::to_python;
use crate::episode::registry::REGISTERED_ENVS;
use crate::settings::Choice;

/// Every registered environment: `[{"id", "task", "summary", "settings", "description",
/// "episode_end", "history"}, ...]`, the settings a dict over the defaults (the task
/// included), the description and episode end its task's.
#[pyfunction]
pub(crate) fn registered_envs(py: Python<'_>) -> PyResult<Bound<'_, PyList>> {
    let envs = PyList::empty(py);
    for env in REGISTERED_ENVS {
        let settings = PyDict::new(py);
        for (key, preset) in env.settings {
            settings.set_item(key, to_python(py, &preset.value())?)?;
        }
        let d = PyDict::new(py);
        d.set_item("id", env.id)?;
        d.set_item("task", env.task.name())?;
        d.set_item("summary", env.summary)?;
        d.set_item("settings", settings)?;
        d.set_item("description", env.task.description())?;
        d.set_item("episode_end", env.task.episode_end())?;
        d.set_item("history", env.history)?;
        envs.append(d)?;
    }
    Ok(envs)
}
