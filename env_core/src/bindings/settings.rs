//! The generic glue between Python and the core's settings tables: any config with a
//! [`Settings`] table is built from a dict and/or keyword arguments, read back as a dict, and
//! described (key, type, default, range, doc) for the Python side to build its config class,
//! signatures, docs and stub from. No key is listed here.

use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{
    PyBool, PyByteArray, PyBytes, PyDict, PyFloat, PyFrozenSet, PyInt, PyList, PySet, PyString,
    PyTuple,
};

use super::errors::{type_name, wrong_type};
use crate::settings::{Checked, SettingValue, Settings};

/// The Python value as a [`SettingValue`]; `TypeError` for anything a setting never takes
/// (a dict, a set, bytes, an object).
pub(super) fn to_setting_value(key: &str, value: &Bound<'_, PyAny>) -> PyResult<SettingValue> {
    if value.is_none() {
        Ok(SettingValue::Null)
    } else if value.is_instance_of::<PyBool>() {
        Ok(SettingValue::Bool(value.extract()?))
    } else if value.is_instance_of::<PyInt>() {
        value
            .extract::<i64>()
            .map(SettingValue::Int)
            .map_err(|_| PyValueError::new_err(format!("{key} must fit in 64 bits, got {value}")))
    } else if value.is_instance_of::<PyFloat>() {
        Ok(SettingValue::Float(value.extract()?))
    } else if value.is_instance_of::<PyString>() {
        Ok(SettingValue::Text(value.extract()?))
    } else if value.is_instance_of::<PyDict>()
        || value.is_instance_of::<PySet>()
        || value.is_instance_of::<PyFrozenSet>()
        || value.is_instance_of::<PyBytes>()
        || value.is_instance_of::<PyByteArray>()
    {
        // A mapping, an unordered set (its order is not the user's) or bytes (not numbers).
        Err(not_a_setting_value(key, value))
    } else if let Ok(items) = value.try_iter() {
        let items = items
            .map(|item| to_setting_value(key, &item?))
            .collect::<PyResult<Vec<_>>>()?;
        Ok(SettingValue::List(items))
    } else if let Ok(number) = value.extract::<i64>() {
        // numpy integers (through __index__).
        Ok(SettingValue::Int(number))
    } else if let Ok(number) = value.extract::<f64>() {
        // numpy floats and other numbers (through __float__).
        Ok(SettingValue::Float(number))
    } else {
        Err(not_a_setting_value(key, value))
    }
}

fn not_a_setting_value(key: &str, value: &Bound<'_, PyAny>) -> PyErr {
    wrong_type(
        key,
        "a bool, int, float, str, None or a sequence of these",
        value,
    )
}

/// The [`SettingValue`] as a Python value (a list becomes a tuple).
pub(super) fn to_python<'py>(py: Python<'py>, value: &SettingValue) -> PyResult<Bound<'py, PyAny>> {
    Ok(match value {
        SettingValue::Bool(v) => PyBool::new(py, *v).to_owned().into_any(),
        SettingValue::Int(v) => v.into_pyobject(py)?.into_any(),
        SettingValue::Float(v) => v.into_pyobject(py)?.into_any(),
        SettingValue::Text(v) => v.into_pyobject(py)?.into_any(),
        SettingValue::Null => py.None().into_bound(py),
        SettingValue::List(items) => {
            let items = items
                .iter()
                .map(|item| to_python(py, item))
                .collect::<PyResult<Vec<_>>>()?;
            PyTuple::new(py, items)?.into_any()
        }
    })
}

/// A config `C` from its defaults, then `config` (a dict or None), then keyword arguments;
/// a key given in both is an error. Each key is looked up before its value is read (a key
/// that is no setting is a `TypeError`, as Python's for an unexpected keyword, prefixed by
/// `caller()` when given: the function the user called), every value is type checked and
/// the whole config checked, once: the result is what the core's constructors take. Errors
/// name the key as typed.
pub(super) fn config_from<C: Settings>(
    config: Option<&Bound<'_, PyAny>>,
    kwargs: Option<&Bound<'_, PyDict>>,
    caller: Option<&str>,
) -> PyResult<Checked<C>> {
    let mut pairs: Vec<(String, SettingValue)> = Vec::new();
    if let Some(config) = config.filter(|c| !c.is_none()) {
        let dict = config.cast::<PyDict>().map_err(|_| {
            PyTypeError::new_err(format!(
                "config must be a dict or None, got {}",
                type_name(config)
            ))
        })?;
        pairs.extend(entries::<C>(dict, caller)?);
    }
    if let Some(kwargs) = kwargs {
        for (key, value) in entries::<C>(kwargs, caller)? {
            if pairs.iter().any(|(k, _)| *k == key) {
                return Err(PyValueError::new_err(format!(
                    "setting {key:?} was given both in the config dict and as a keyword argument"
                )));
            }
            pairs.push((key, value));
        }
    }
    Ok(C::from_pairs(
        pairs.iter().map(|(k, v)| (k.as_str(), v.clone())),
    )?)
}

fn entries<C: Settings>(
    dict: &Bound<'_, PyDict>,
    caller: Option<&str>,
) -> PyResult<Vec<(String, SettingValue)>> {
    dict.iter()
        .map(|(key, value)| {
            let key: String = key.extract().map_err(|_| {
                PyTypeError::new_err(format!("setting keys must be str, got {}", type_name(&key)))
            })?;
            if let Err(unknown) = C::setting(&key) {
                return Err(match caller {
                    Some(caller) => PyTypeError::new_err(format!("{caller}() {unknown}")),
                    None => unknown.into(),
                });
            }
            let value = to_setting_value(&key, &value)?;
            Ok((key, value))
        })
        .collect()
}

/// Every setting of `config` by key: a dict that [`config_from`] takes back.
pub(super) fn config_dict<'py, C: Settings>(
    py: Python<'py>,
    config: &C,
) -> PyResult<Bound<'py, PyDict>> {
    let dict = PyDict::new(py);
    for (key, value) in config.to_pairs() {
        dict.set_item(key, to_python(py, &value)?)?;
    }
    Ok(dict)
}

/// The table of `C` for Python: one dict per setting with `key`, `type` (the annotation),
/// `default`, `range` (interval notation; None for choices and bools), `choices` (tuple of
/// str) and `doc`.
pub(super) fn describe<'py, C: Settings>(py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
    let defaults = C::default();
    let rows = PyList::empty(py);
    for setting in C::table() {
        let row = PyDict::new(py);
        row.set_item("key", setting.key)?;
        row.set_item("type", setting.annotation)?;
        row.set_item("default", to_python(py, &setting.get(&defaults))?)?;
        let numeric = setting.choices.is_empty() && setting.annotation != "bool";
        row.set_item("range", numeric.then(|| setting.range.to_string()))?;
        row.set_item("choices", PyTuple::new(py, setting.choices)?)?;
        row.set_item("doc", setting.doc)?;
        rows.append(row)?;
    }
    Ok(rows)
}
