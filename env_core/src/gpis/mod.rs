//! Gaussian Process Implicit Surface (GPIS) in the 2D slice plane.
//!
//! Convention: f < 0 inside objects, f = 0 on surfaces, f > 0 in free space; a measured
//! outward normal is an observation of ∇f. The kernel is the thin-plate covariance with a
//! fixed ψ (see [`kernel`]); the posterior is kept exact and updated incrementally (see
//! [`map`]), with [`full_recompute`] as the from-scratch reference.

pub mod config;
pub mod error;
pub mod full_recompute;
pub mod grid;
pub mod kernel;
pub mod map;
pub mod observation;
mod rejecting_cholesky;
pub mod tiles;

pub use config::{GpisConfig, GpisDefaults, GPIS_DEFAULTS};
pub use error::GpisError;
pub use grid::GridSpec;
pub use kernel::{RowKind, ThinPlateKernel};
pub use map::{AddReport, Gpis, Prediction};
pub use observation::{Observation, Row};
pub use tiles::{run_each, PoolTiles, SerialTiles, TileRunner};
