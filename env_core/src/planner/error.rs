//! Why a planner cannot act.

use thiserror::Error;

use crate::episode::maps::DecodeError;
use crate::episode::EpisodeError;

/// Why a planner cannot act.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum PlannerError {
    /// The planner reads one map mode.
    #[error("the planner needs map='{wanted}', got map='{got}'")]
    NeedsMap {
        /// The map it reads.
        wanted: &'static str,
        /// The settings' map.
        got: &'static str,
    },
    /// The planner chooses probes.
    #[error("the planner needs action_mode='probe', got action_mode='{0}'")]
    NeedsProbeActions(&'static str),
    /// A planner for one task, given the settings of another.
    #[error("the {planner} planner needs task='{task}', got task='{got}'")]
    NeedsTask {
        /// The planner.
        planner: &'static str,
        /// The task it plans for.
        task: &'static str,
        /// The settings' task.
        got: &'static str,
    },
    /// The identify planner claims the square jar.
    #[error("the identify planner claims the square jar: it needs target_shape='square', got target_shape='{0}'")]
    NeedsSquareTarget(&'static str),
    /// `act` or `follow` before the episode's first observation.
    #[error("the planner has no episode: reset it with the episode's first observation")]
    NotReset,
    /// An observation's map image is not of the planner's configuration.
    #[error("the map image has {got}, expected {expected}")]
    Image {
        /// What the configuration's map image holds.
        expected: String,
        /// What came.
        got: String,
    },
    /// A configuration or action the episode refuses.
    #[error(transparent)]
    Episode(#[from] EpisodeError),
}

impl From<DecodeError> for PlannerError {
    fn from(error: DecodeError) -> Self {
        Self::Image {
            expected: error.expected,
            got: error.got,
        }
    }
}
