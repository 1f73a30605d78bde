//! pyo3 bindings: the compiled module `tactile_search._core`, the seam between the pure-Rust
//! core and Python. Thin: convert, release the GIL, call the core, convert back.
//!
//! - [`convert`]: seeds, numpy arrays out of the core's data.
//! - [`errors`]: every Python exception the bindings raise, and the type names their
//!   messages show.
//! - [`settings`]: the generic glue over the core's settings tables (no key is listed here).
//! - [`arrays`]: array arguments checked and converted.
//! - [`decode`]: the map image's and the proprio vector's meaning and the static geometry,
//!   for planners (`EpisodeBatch.decode_map`, `.decode_proprio`, `.geometry`).
//! - [`geometry`], [`prior`]: the core's geometry, metrics and depth prior as functions,
//!   so experiments run what the environment runs.
//! - one file per class: [`gpis`] (`GpisCore`), [`scene`] (`Scene`), [`episode`]
//!   (`EpisodeBatch`), [`planner`] (`ProbePlanner`, `IdentifyPlanner`, `MapPlanner`).

mod actions;
mod arrays;
mod batch_arrays;
mod convert;
mod decode;
mod episode;
mod episode_config;
mod errors;
mod exclusive;
mod geometry;
mod gpis;
mod observation;
mod planner;
mod prior;
mod registry;
mod scene;
mod settings;
mod step_info;

use pyo3::prelude::*;

/// Bytes the core holds now, every live block of its allocator (`env_core::allocator`):
/// glibc's `mallinfo2` counts none of them.
#[pyfunction]
fn allocated_bytes() -> usize {
    crate::allocator::allocated_bytes()
}

/// The compiled core of `tactile_search`.
#[pymodule]
#[pyo3(name = "_core")]
fn core_module(m: &Bound<'_, PyModule>) -> PyResult<()> {
    crate::allocator::configure();
    m.add_class::<gpis::PyGpis>()?;
    m.add_function(wrap_pyfunction!(gpis::gpis_defaults, m)?)?;
    m.add_class::<scene::PyScene>()?;
    m.add_class::<episode_config::PyEpisodeConfig>()?;
    m.add_class::<episode::PyEpisodeBatch>()?;
    m.add_class::<planner::PyProbePlanner>()?;
    m.add_class::<planner::PyIdentifyPlanner>()?;
    m.add_class::<planner::PyMapPlanner>()?;
    geometry::register(m)?;
    prior::register(m)?;
    m.add_function(wrap_pyfunction!(observation::observation_layout, m)?)?;
    m.add_function(wrap_pyfunction!(step_info::step_info_fields, m)?)?;
    m.add_function(wrap_pyfunction!(registry::registered_envs, m)?)?;
    m.add_function(wrap_pyfunction!(allocated_bytes, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
