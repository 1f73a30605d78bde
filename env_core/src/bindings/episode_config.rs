//! `_core.EpisodeConfig`: an episode's settings, checked once where they are made. The
//! batch takes it as it is (no dict goes back and forth, nothing is checked again); Python
//! reads its values with `as_dict()`.

use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyTuple};

use super::errors::wrong_type;
use super::settings::{config_dict, config_from, describe};
use crate::episode::EpisodeConfig;
use crate::settings::{Checked, Settings};

/// Every setting of an episode (the scene's included), checked: a key that is no setting or
/// a value of the wrong type raises `TypeError`, a value out of its range or against
/// another setting `ValueError`, each naming the key. Equal configs compare and hash equal;
/// it pickles as its settings.
#[pyclass(name = "EpisodeConfig", module = "tactile_search._core", frozen, eq)]
#[derive(Clone, PartialEq)]
pub struct PyEpisodeConfig {
    pub(super) checked: Checked<EpisodeConfig>,
}

/// The checked settings of `config`, which must be an `EpisodeConfig` (`TypeError`
/// otherwise).
pub(super) fn episode_config_of(config: &Bound<'_, PyAny>) -> PyResult<Checked<EpisodeConfig>> {
    Ok(config
        .cast::<PyEpisodeConfig>()
        .map_err(|_| wrong_type("config", "an EpisodeConfig", config))?
        .get()
        .checked
        .clone())
}

#[pymethods]
impl PyEpisodeConfig {
    /// The defaults updated by `settings` (a dict or None), then by keyword arguments: every
    /// key of `EpisodeConfig.settings()`. `caller` names the function the user called in
    /// the error for an unknown key (`CupboardSearchEnv() got an unexpected keyword
    /// argument ...`).
    #[new]
    #[pyo3(signature = (settings = None, *, caller = None, **kwargs))]
    fn py_new(
        settings: Option<&Bound<'_, PyAny>>,
        caller: Option<&str>,
        kwargs: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        Ok(Self {
            checked: config_from::<EpisodeConfig>(settings, kwargs, caller)?,
        })
    }

    /// The settings table (the scene's included): one dict per setting with key, type,
    /// default, range, choices and doc.
    #[staticmethod]
    fn settings(py: Python<'_>) -> PyResult<Bound<'_, PyList>> {
        describe::<EpisodeConfig>(py)
    }

    /// Every setting by key, as Python values (sequences as tuples).
    fn as_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        config_dict(py, &*self.checked)
    }

    fn __hash__(&self, py: Python<'_>) -> PyResult<isize> {
        PyTuple::new(py, self.as_dict(py)?.values())?.hash()
    }

    fn __repr__(&self) -> String {
        let changed: Vec<String> = self
            .checked
            .to_pairs()
            .into_iter()
            .zip(EpisodeConfig::default().to_pairs())
            .filter(|((_, value), (_, default))| value != default)
            .map(|((key, value), _)| format!("{key}={value}"))
            .collect();
        format!("EpisodeConfig({})", changed.join(", "))
    }

    fn __reduce__<'py>(
        slf: &Bound<'py, Self>,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyTuple>)> {
        let py = slf.py();
        let settings = slf.get().as_dict(py)?;
        Ok((
            slf.get_type().into_any(),
            PyTuple::new(py, [settings.into_any()])?,
        ))
    }
}
