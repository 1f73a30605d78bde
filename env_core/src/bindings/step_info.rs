//! The `info` of a step, from its field table ([`crate::episode::STEP_INFO_FIELDS`]):
//! `_core.step_info_fields()`, and one episode's info as a dict of Python scalars (the
//! single env's `info`; SB3's per-env dicts). Cost O(fields) per dict.

use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::episode::step_info::{InfoValue, StepInfo, STEP_INFO_FIELDS};

/// Every key of `info`: `[{"name", "dtype", "doc"}, ...]` (dtype: float64, bool or int64).
#[pyfunction]
pub(crate) fn step_info_fields(py: Python<'_>) -> PyResult<Bound<'_, PyList>> {
    let fields = PyList::empty(py);
    for field in STEP_INFO_FIELDS {
        let d = PyDict::new(py);
        d.set_item("name", field.name)?;
        d.set_item("dtype", field.dtype())?;
        d.set_item("doc", field.doc)?;
        fields.append(d)?;
    }
    Ok(fields)
}

/// `info` as a dict of Python scalars (float, bool, int), keys in table order.
pub(crate) fn info_dict<'py>(py: Python<'py>, info: &StepInfo) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for field in STEP_INFO_FIELDS {
        match field.value {
            InfoValue::Float(get) => d.set_item(field.name, get(info))?,
            InfoValue::Flag(get) => d.set_item(field.name, get(info))?,
            InfoValue::Count(_) | InfoValue::Index(_) => {
                d.set_item(field.name, field.value.integer(info))?
            }
        }
    }
    Ok(d)
}
