//! What an action means: a wrist motion per step, or a probe per step carried out by the
//! controller of [`super::probe`]. An episode-level setting (`action_mode`, in
//! [`super::config::EpisodeConfig`]), and the action itself ([`Action`]), which carries
//! a probe's indices as integers, or a claim (the `identify` task, [`super::task`]).
//!
//! An action arrives as a row of numbers, the env's action space's: 3 entries, and a 4th,
//! the claim entry, in a task that claims ([`Action::from_wrist_row`],
//! [`Action::from_probe_row`]).

use super::error::EpisodeError;
use super::task::Claim;

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
    /// A claim (the `identify` task, in either action mode): it names the jar the finger
    /// touches now and ends the episode, making no motion.
    Claim,
}

impl Action {
    /// The mode this action belongs to (None for a claim, which either mode makes).
    pub fn mode(&self) -> Option<ActionMode> {
        match self {
            Self::Wrist(_) => Some(ActionMode::Wrist),
            Self::Probe(_) => Some(ActionMode::Probe),
            Self::Claim => None,
        }
    }

    /// The action of a `wrist`-mode row: `[dx, dy, dyaw]`, or with `claims` (a task that
    /// claims) `[dx, dy, dyaw, claim]`, a claim when its claim entry is above
    /// [`Claim::WRIST_THRESHOLD`]. The motion's values are checked when it is stepped.
    ///
    /// # Errors
    /// A row of another length, or a claim entry that is not finite.
    pub fn from_wrist_row(row: &[f64], claims: bool) -> Result<Self, EpisodeError> {
        check_row_length(row.len(), claims)?;
        if claims {
            if !row[3].is_finite() {
                return Err(EpisodeError::NonFiniteAction {
                    index: 3,
                    value: row[3],
                });
            }
            if Claim::wrist_claims(row[3]) {
                return Ok(Self::Claim);
            }
        }
        Ok(Self::Wrist([row[0], row[1], row[2]]))
    }

    /// The action of a `probe`-mode row: `[lane, depth, sweep]`, or with `claims`
    /// `[lane, depth, sweep, claim]`, a claim when its claim index is 1. The probe's indices
    /// are checked when it is stepped.
    ///
    /// # Errors
    /// A row of another length, or a claim index other than 0 or 1.
    pub fn from_probe_row(row: &[i64], claims: bool) -> Result<Self, EpisodeError> {
        check_row_length(row.len(), claims)?;
        if claims {
            match row[3] {
                0 => {}
                1 => return Ok(Self::Claim),
                value => {
                    return Err(EpisodeError::ProbeIndex {
                        index: 3,
                        value,
                        count: Claim::PROBE_CHOICES,
                    })
                }
            }
        }
        Ok(Self::Probe([row[0], row[1], row[2]]))
    }
}

impl Action {
    /// This action as a `wrist`-mode row (the inverse of [`Action::from_wrist_row`]): a
    /// motion's 3 entries and, with `claims`, a claim entry of −1 (no claim); a claim is
    /// no motion and a claim entry of 1. None for a probe.
    pub fn to_wrist_row(&self, claims: bool) -> Option<Vec<f64>> {
        let (motion, claim) = match *self {
            Self::Wrist(motion) => (motion, -1.0),
            Self::Claim => ([0.0; 3], 1.0),
            Self::Probe(_) => return None,
        };
        Some(motion.into_iter().chain(claims.then_some(claim)).collect())
    }
}

/// The entries of one action: 3, and the claim entry in a task that claims.
pub fn action_len(claims: bool) -> usize {
    3 + usize::from(claims)
}

fn check_row_length(len: usize, claims: bool) -> Result<(), EpisodeError> {
    let expected = action_len(claims);
    if len == expected {
        Ok(())
    } else {
        Err(EpisodeError::BufferLength {
            what: "action",
            expected,
            got: len,
        })
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_row_without_a_claim_entry_is_its_motion_or_probe() {
        assert_eq!(
            Action::from_wrist_row(&[0.1, 0.2, 0.3], false),
            Ok(Action::Wrist([0.1, 0.2, 0.3]))
        );
        assert_eq!(
            Action::from_probe_row(&[1, 2, 3], false),
            Ok(Action::Probe([1, 2, 3]))
        );
    }

    #[test]
    fn the_claim_entry_claims_or_leaves_the_motion() {
        assert_eq!(
            Action::from_wrist_row(&[0.1, 0.2, 0.3, 0.5], true),
            Ok(Action::Claim)
        );
        assert_eq!(
            Action::from_wrist_row(&[0.1, 0.2, 0.3, -0.5], true),
            Ok(Action::Wrist([0.1, 0.2, 0.3]))
        );
        assert_eq!(
            Action::from_probe_row(&[1, 2, 3, 1], true),
            Ok(Action::Claim)
        );
        assert_eq!(
            Action::from_probe_row(&[1, 2, 3, 0], true),
            Ok(Action::Probe([1, 2, 3]))
        );
    }

    #[test]
    fn a_wrist_row_reads_back_as_its_action() {
        for action in [Action::Wrist([0.1, -0.2, 0.3]), Action::Claim] {
            let row = action.to_wrist_row(true).expect("a wrist-mode action");
            assert_eq!(Action::from_wrist_row(&row, true), Ok(action));
        }
        assert_eq!(
            Action::Wrist([0.1, 0.2, 0.3]).to_wrist_row(false),
            Some(vec![0.1, 0.2, 0.3])
        );
        assert_eq!(Action::Probe([0, 0, 0]).to_wrist_row(true), None);
    }

    #[test]
    fn a_bad_claim_entry_or_row_length_is_refused() {
        assert!(matches!(
            Action::from_wrist_row(&[0.0, 0.0, 0.0, f64::NAN], true),
            Err(EpisodeError::NonFiniteAction { index: 3, .. })
        ));
        assert!(matches!(
            Action::from_probe_row(&[0, 0, 0, 2], true),
            Err(EpisodeError::ProbeIndex {
                index: 3,
                value: 2,
                count: 2
            })
        ));
        assert!(matches!(
            Action::from_wrist_row(&[0.0, 0.0, 0.0], true),
            Err(EpisodeError::BufferLength {
                expected: 4,
                got: 3,
                ..
            })
        ));
    }
}
