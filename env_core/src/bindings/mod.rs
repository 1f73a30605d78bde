//! pyo3 bindings: the compiled module `tactile_search._core`. Thin: convert, release the
//! GIL, call the pure-Rust core, convert back. Errors are mapped in [`errors`].

mod actions;
mod batch_arrays;
mod episode;
mod errors;
mod gpis;
mod observation;
mod scene;
mod step_info;

use pyo3::prelude::*;

/// The compiled core of `tactile_search`.
#[pymodule]
#[pyo3(name = "_core")]
fn core_module(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<gpis::PyGpis>()?;
    m.add_class::<scene::PyScene>()?;
    m.add_class::<episode::PyEpisodeBatch>()?;
    m.add_function(wrap_pyfunction!(observation::observation_layout, m)?)?;
    m.add_function(wrap_pyfunction!(step_info::step_info_fields, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
