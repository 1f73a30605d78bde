//! pyo3 bindings: the compiled module `tactile_search._core`. Thin: convert, release the
//! GIL, call the pure-Rust core, convert back. Errors are mapped in [`errors`], array
//! arguments converted in [`arrays`]; [`geometry`] and [`prior`] expose the core's
//! geometry, metrics and depth prior as functions for the experiments.

mod arrays;
mod episode;
mod errors;
mod geometry;
mod gpis;
mod prior;
mod scene;

use pyo3::prelude::*;

/// The compiled core of `tactile_search`.
#[pymodule]
#[pyo3(name = "_core")]
fn core_module(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<gpis::PyGpis>()?;
    m.add_class::<scene::PyScene>()?;
    m.add_class::<episode::PyEpisodeBatch>()?;
    geometry::register(m)?;
    prior::register(m)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
