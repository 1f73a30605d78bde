//! `_core.observation_layout()`: the observation's field table, for the docstring, the
//! decoders and the tests (one source: [`crate::episode::observation`] for the proprio
//! entries, each map mode's channels in [`crate::episode::maps`]). Cost: a few dicts.

use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::episode::observation::PROPRIO_FIELDS;
use crate::episode::MapMode;
use crate::settings::Choice;

/// The observation layout: `{"proprio": [{"name", "index", "scale", "meaning", "mirror"}, ...],
/// "map_channels": [{"mode", "channel", "name", "encoding"}, ...]}`.
#[pyfunction]
pub(crate) fn observation_layout(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    let proprio = PyList::empty(py);
    for (index, field) in PROPRIO_FIELDS.iter().enumerate() {
        let d = PyDict::new(py);
        d.set_item("name", field.name)?;
        d.set_item("index", index)?;
        d.set_item("scale", field.scale)?;
        d.set_item("meaning", field.meaning)?;
        d.set_item("mirror", field.mirror)?;
        proprio.append(d)?;
    }
    let channels = PyList::empty(py);
    for mode in (0..MapMode::NAMES.len()).map(MapMode::from_index) {
        for (index, channel) in mode.kind().channels.iter().enumerate() {
            let d = PyDict::new(py);
            d.set_item("mode", mode.name())?;
            d.set_item("channel", index)?;
            d.set_item("name", channel.name)?;
            d.set_item("encoding", channel.encoding)?;
            channels.append(d)?;
        }
    }
    let layout = PyDict::new(py);
    layout.set_item("proprio", proprio)?;
    layout.set_item("map_channels", channels)?;
    Ok(layout)
}
