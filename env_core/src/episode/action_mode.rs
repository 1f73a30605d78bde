//! What an action means: a wrist motion per step, or a probe per step carried out by the
//! controller of [`super::probe`]. An episode-level setting (`action_mode`, in
//! [`super::config::EpisodeConfig`]).

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
