//! Typed errors of the episode layer; the Python bindings map them to `ValueError`.

use thiserror::Error;

use crate::gpis::GpisError;
use crate::scene::SceneError;

/// Everything that can go wrong when configuring or stepping an [`crate::episode::Episode`].
#[derive(Debug, Clone, PartialEq, Error)]
pub enum EpisodeError {
    /// The scene refused its configuration or a command.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// The GPIS map refused its configuration.
    #[error(transparent)]
    Gpis(#[from] GpisError),
    /// An episode parameter lies outside its allowed range.
    #[error("{what} must be {expected}, got {value}")]
    OutOfRange {
        /// Which parameter.
        what: &'static str,
        /// The allowed range, as text.
        expected: &'static str,
        /// Value given.
        value: f64,
    },
    /// The map grid must have square cells over the cupboard's interior and at least 36
    /// cells a side (the smallest image stable-baselines3's default CNN takes).
    #[error(
        "grid_shape must be (H, W) with H, W >= 36 and square cells over the {width} m x \
         {depth} m interior (W / H = {aspect}), got ({height_cells}, {width_cells})"
    )]
    GridShape {
        /// Cells along y.
        height_cells: usize,
        /// Cells along x.
        width_cells: usize,
        /// Interior width, m.
        width: f64,
        /// Interior depth, m.
        depth: f64,
        /// Required W / H.
        aspect: f64,
    },
    /// An action component was NaN or infinite.
    #[error("action[{index}] must be finite, got {value}")]
    NonFiniteAction {
        /// Component index (0 = dx, 1 = dy, 2 = dyaw).
        index: usize,
        /// Value given.
        value: f64,
    },
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
