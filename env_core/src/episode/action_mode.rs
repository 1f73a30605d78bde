//! What an action means: a wrist motion per step, or a probe per step carried out by the
//! controller of [`super::probe`]. An episode-level setting (`action_mode`, in
//! [`super::config::EpisodeConfig`]).

use crate::settings::Choice;

/// What an action means.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ActionMode {
    /// v0: a wrist motion per step, `Box(-1, 1, (3,))` scaled by the hand's bounds.
    Wrist,
    /// A probe per step (lane, depth, sweep indices), driven by the controller.
    Probe,
}

impl Choice for ActionMode {
    const NAMES: &'static [&'static str] = &["wrist", "probe"];
    const ANNOTATION: &'static str = "Literal['wrist', 'probe']";
    const EXPECTED: &'static str = "'wrist' or 'probe'";

    fn from_index(index: usize) -> Self {
        [Self::Wrist, Self::Probe][index]
    }

    fn index(self) -> usize {
        self as usize
    }
}
