//! Typed errors of the cupboard scene. Each says what was expected and what came; the Python
//! bindings map them to `ValueError` in one place (`bindings/errors.rs`).

use thiserror::Error;

use crate::settings::SettingError;

/// Everything that can go wrong when configuring, building or commanding a
/// [`crate::scene::Scene`].
#[derive(Debug, Clone, PartialEq, Error)]
pub enum SceneError {
    /// A setting is of the wrong type or out of its range (the message names its key).
    #[error(transparent)]
    Setting(#[from] SettingError),
    /// The camera's optical axis is undefined (eye equals target, or looks straight up/down).
    #[error(
        "camera_look_at must differ from camera_position and not lie straight above or \
         below it, got camera_position {position:?} and camera_look_at {look_at:?}"
    )]
    DegenerateCameraPose {
        /// Camera position given.
        position: [f64; 3],
        /// Look-at point given.
        look_at: [f64; 3],
    },
    /// The layout generator found no layout satisfying every constraint.
    #[error(
        "no layout with {jars} jar(s) hiding the target and {hidden_decoys} decoy(s) (visible \
         fraction <= {max_visible_fraction}) and keeping a clear corridor to each was found in \
         {attempts} attempts with seed {seed}; relax the layout config (fewer jars or hidden \
         decoys, larger max_visible_fraction, narrower corridor, larger cupboard)"
    )]
    LayoutNotFound {
        /// Seed given.
        seed: u64,
        /// Attempts made.
        attempts: usize,
        /// Jar count of the last attempt.
        jars: usize,
        /// Hidden decoys asked for.
        hidden_decoys: usize,
        /// The visibility bound.
        max_visible_fraction: f64,
    },
    /// An explicit layout is not valid (overlap, outside the cupboard, bad target index, ...).
    #[error("invalid layout: {reason}")]
    InvalidLayout {
        /// What is wrong with it.
        reason: String,
    },
    /// The hand's start pose already intersects a cupboard wall or leaves the workspace.
    #[error(
        "hand_start (x={x}, y={y}, yaw={yaw}) must leave the wrist and arm clear of the \
         cupboard walls and inside the workspace"
    )]
    HandStartBlocked {
        /// Start x.
        x: f64,
        /// Start y.
        y: f64,
        /// Start yaw.
        yaw: f64,
    },
    /// A hand command had a non-finite component.
    #[error("hand command {what} must be finite, got {value}")]
    NonFiniteCommand {
        /// `"dx"`, `"dy"` or `"dyaw"`.
        what: &'static str,
        /// Value given.
        value: f64,
    },
    /// A jar index is out of range.
    #[error("jar index must be < {count}, got {index}")]
    JarIndex {
        /// Index given.
        index: usize,
        /// Number of jars.
        count: usize,
    },
}
