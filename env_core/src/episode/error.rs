//! Typed errors of the episode layer; the Python bindings map them to `ValueError`.

use thiserror::Error;

use crate::gpis::GpisError;
use crate::scene::SceneError;
use crate::settings::SettingError;

/// Everything that can go wrong when configuring or stepping an [`crate::episode::Episode`].
#[derive(Debug, Clone, PartialEq, Error)]
pub enum EpisodeError {
    /// The scene refused its configuration or a command.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// The GPIS map refused its configuration.
    #[error(transparent)]
    Gpis(#[from] GpisError),
    /// A setting is of the wrong type or out of its range (the message names its key).
    #[error(transparent)]
    Setting(#[from] SettingError),
    /// An action component was NaN or infinite.
    #[error("action[{index}] must be finite, got {value}")]
    NonFiniteAction {
        /// Component index (0 = dx, 1 = dy, 2 = dyaw, 3 = claim).
        index: usize,
        /// Value given.
        value: f64,
    },
    /// A `probe` mode action component is not an index within its count.
    #[error(
        "action[{index}] must be an integer from 0 to {} (the probe action mode's \
         [lane, depth, sweep] indices, then the claim index where the task claims), got \
         {value}", count.saturating_sub(1)
    )]
    ProbeIndex {
        /// Component index (0 = lane, 1 = depth, 2 = sweep, 3 = claim).
        index: usize,
        /// Value given.
        value: i64,
        /// The component's count (probe_lanes, probe_depths or probe_sweeps).
        count: usize,
    },
    /// An action of the other action mode (a wrist motion in the `probe` mode or a probe in
    /// the `wrist` mode).
    #[error("action must be a {expected} action (the episode's action_mode), got a {got} one")]
    WrongActionMode {
        /// The episode's mode.
        expected: &'static str,
        /// The action's mode.
        got: &'static str,
    },
    /// A claim in a task that takes none (only `identify` does).
    #[error("a claim is an action of the identify task; this episode's task is '{task}'")]
    ClaimOutsideIdentify {
        /// The episode's task.
        task: &'static str,
    },
    /// `step` was called on an episode that no reset has started.
    #[error("the episode has not started; call reset() before stepping")]
    NotReset,
    /// `step` was called on an episode that has ended (success or a tipped jar).
    #[error("the episode has ended (terminated); call reset() before stepping again")]
    Ended,
    /// Episode `index` of a batch failed.
    #[error("episode {index}: {source}")]
    InEpisode {
        /// Which episode of the batch.
        index: usize,
        /// What went wrong there.
        source: Box<EpisodeError>,
    },
    /// An output buffer has the wrong length.
    #[error("{what} buffer must hold {expected} values, got {got}")]
    BufferLength {
        /// Which buffer.
        what: &'static str,
        /// Values expected.
        expected: usize,
        /// Values given.
        got: usize,
    },
}

impl EpisodeError {
    /// This error, as having happened in episode `index` of a batch.
    pub fn in_episode(self, index: usize) -> Self {
        Self::InEpisode {
            index,
            source: Box::new(self),
        }
    }
}
