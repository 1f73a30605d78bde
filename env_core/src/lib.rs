//! Rust core of `tactile_search`: everything that runs per step of a mechanical-search episode.
//!
//! - [`gpis`]: the Gaussian Process Implicit Surface map (thin-plate kernel, value and
//!   gradient observations, exact incremental posterior on a grid).
//!
//! The pyo3 bindings live in the `python` module behind the `python` cargo feature, so that
//! `cargo test` builds and runs without a Python interpreter.

pub mod gpis;

#[cfg(feature = "python")]
mod python;
