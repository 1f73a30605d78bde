//! Rust core of `tactile_search`: everything that runs per step of a mechanical-search episode.
//!
//! - [`gpis`]: the Gaussian Process Implicit Surface map (thin-plate kernel, value and
//!   gradient observations, exact incremental posterior on a grid).
//! - [`scene`]: the cupboard scene in rapier3d (jars with a hidden target, depth camera,
//!   Exploratory Hand with a compliant finger, touch readings, disturbance).
//! - [`settings`]: self-describing settings tables (key, doc, type, default, range) that
//!   the scene and episode configs declare once and everything else reads.
//! - [`episode`]: mechanical-search episodes (map from depth and touch, reward, episode end)
//!   and a batch of them stepped in parallel.
//! - [`planner`]: scripted teachers that read only the observation (the GPIS probe
//!   planner), run over a batch on every core.
//! - [`allocator`]: the global allocator (mimalloc, its options, and a count of the bytes
//!   the core holds).
//!
//! The pyo3 bindings live in the `bindings` module behind the `python` cargo feature, so that
//! `cargo test` builds and runs without a Python interpreter.

pub mod allocator;
pub mod episode;
pub mod gpis;
pub mod planner;
pub mod scene;
pub mod settings;

#[cfg(feature = "python")]
mod bindings;

#[global_allocator]
static ALLOCATOR: allocator::CoreAllocator = allocator::CoreAllocator;
