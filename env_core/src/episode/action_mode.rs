//! What an action means: a wrist motion per step, or a probe per step carried out by the
//! controller of [`super::probe`]. An episode-level setting (`action_mode`, in
//! [`super::config::EpisodeConfig`]), and the action itself ([`Action`]), which carries
//! a probe's indices as integers.

/// What an action means.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ActionMode {
    /// v0: a wrist motion per step, `Box(-1, 1, (3,))` scaled by the hand's bounds.
    Wrist,
    /// A probe per step (lane, depth, sweep indices), driven by the controller.
    Probe,
}

crate::choice! {
    ActionMode {
        Wrist => "wrist",
        Probe => "probe",
    }
}

/// One step's action, of its episode's [`ActionMode`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Action {
    /// A wrist motion `[dx, dy, dyaw]` in [−1, 1]³ (clipped), scaled by the hand's bounds.
    Wrist([f64; 3]),
    /// A probe's `[lane, depth, sweep]` indices, each within its count.
    Probe([i64; 3]),
}

impl Action {
    /// The mode this action belongs to.
    pub fn mode(&self) -> ActionMode {
        match self {
            Self::Wrist(_) => ActionMode::Wrist,
            Self::Probe(_) => ActionMode::Probe,
        }
    }
}

impl From<[f64; 3]> for Action {
    fn from(motion: [f64; 3]) -> Self {
        Self::Wrist(motion)
    }
}

impl From<[i64; 3]> for Action {
    fn from(indices: [i64; 3]) -> Self {
        Self::Probe(indices)
    }
}
