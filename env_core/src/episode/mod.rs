//! Mechanical-search episodes (`docs/DESIGN.md` §4): the scene plus the agent's map, reward and
//! episode end, and a batch of episodes stepped in parallel.
//!
//! - [`approach`]: the fingertip's path distance to the target (reward shaping).
//! - [`config`]: the episode's settings (reward weights, episode end; sections for the
//!   probes, the map and the scene).
//! - [`maps`]: the agent's map, one file per map mode behind one trait (the GPIS, the
//!   occupancy grid, none), with the map's settings, image channels and decoders.
//! - [`observation`]: the proprio field table, and its decoder.
//! - [`static_geometry`]: the geometry a planner may know, from the configuration alone.
//! - [`step_info`]: what a step did, and the field table of `info`.
//! - [`metrics`]: true footprints and the IoU of a map against them.
//! - [`level_set`], [`outline`]: the map's zero level set and its distance to the true
//!   outlines; [`map_score`]: the map task's score, a reconstruction of every episode's
//!   evidence scored against the truth.
//! - [`action_mode`]: what an action means (a wrist motion or a probe per step).
//! - [`probe`]: the `probe` action mode's controller (a lane, depth and sweep per step,
//!   carried out motion by motion); [`probe_config`]: its settings.
//! - [`registry`]: the registered environment ids, each a task and tier as settings.
//! - [`task`]: what the episode asks (search, identify) and the claim's rules.
//! - [`oracle`]: a scripted searcher that knows the target (the upper bound).
//! - [`Episode`]: reset, step, observations.
//! - [`EpisodeBatch`]: many episodes stepped on all cores.

pub mod action_mode;
pub mod approach;
pub mod batch;
pub mod config;
#[allow(clippy::module_inception)]
mod episode;
pub mod error;
pub mod level_set;
pub mod map_score;
pub mod maps;
pub mod metrics;
pub mod observation;
pub mod oracle;
pub mod outline;
pub mod probe;
pub mod probe_config;
pub mod registry;
pub mod static_geometry;
pub mod step_info;
pub mod task;

pub use action_mode::{Action, ActionMode};
pub use batch::{Command, EpisodeBatch};
pub use config::{EpisodeConfig, RewardConfig};
pub use episode::Episode;
pub use error::EpisodeError;
pub use maps::{MapConfig, MapMode};
pub use observation::{decode_proprio, Quantity, PROPRIO_FIELDS, PROPRIO_LEN};
pub use oracle::{oracle_action, oracle_motion};
pub use probe::{Probe, ProbeController, ProbeGrid};
pub use probe_config::ProbeConfig;
pub use static_geometry::StaticGeometry;
pub use step_info::{StepInfo, STEP_INFO_FIELDS};
pub use task::{Claim, Task};
