//! Mechanical-search episodes (design notes §4): the scene plus the agent's map, reward and
//! episode end, and a batch of episodes stepped in parallel.
//!
//! - [`approach`]: the fingertip's path distance to the target (reward shaping).
//! - [`config`]: the map mode, grid, prior, noise and reward weights.
//! - [`prior`]: the GPIS prior from the depth camera's first look.
//! - [`occupancy`]: the plain evidence grid of the `occupancy` mode.
//! - [`map_image`]: the map as a uint8 image for the agent.
//! - [`metrics`]: true footprints and the IoU of a map against them.
//! - [`level_set`], [`outline`]: the map's zero level set and its distance to the true
//!   outlines.
//! - [`oracle`]: a scripted searcher that knows the target (the upper bound).
//! - [`Episode`]: reset, step, observations.
//! - [`EpisodeBatch`]: many episodes stepped on all cores.

pub mod approach;
pub mod batch;
pub mod config;
#[allow(clippy::module_inception)]
mod episode;
pub mod error;
pub mod level_set;
pub mod map_image;
pub mod metrics;
pub mod occupancy;
pub mod oracle;
pub mod outline;
pub mod prior;

pub use batch::EpisodeBatch;
pub use config::{EpisodeConfig, MapConfig, MapMode, RewardConfig};
pub use episode::{Episode, StepInfo, PROPRIO_LEN};
pub use error::EpisodeError;
pub use oracle::oracle_action;
