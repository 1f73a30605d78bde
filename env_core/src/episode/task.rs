//! What an episode asks of the agent (`docs/DESIGN.md` §4.4): the rules of each task, in
//! one place, read by the episode (when it succeeds and ends, what the info reveals), the
//! action's layout (whether it carries a claim) and the settings' checks.
//!
//! - `search` (v0): touch the target; any touch of it succeeds and ends the episode.
//! - `identify`: the target is known only by its shape. Touching it pays nothing and ends
//!   nothing; the episode ends with a claim, an entry of the action that names the jar the
//!   finger is touching ([`Claim`]). The target's identity stays out of the observation and
//!   out of the info until the claim.
//! - `map`: no target. Within the time limit's motions, touch so that the episode's
//!   evidence reconstructs the cupboard's contents ([`super::map_score`]); the reward is the
//!   score's gain.

/// What an episode asks of the agent.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Task {
    /// Find the hidden target: a touch of it succeeds.
    Search,
    /// Find the jar of the target's shape among decoys and claim it by touch.
    Identify,
    /// Reconstruct the cupboard's contents by touch within the time limit.
    Map,
}

crate::choice! {
    Task {
        Search => "search",
        Identify => "identify",
        Map => "map",
    }
}

impl Task {
    /// Whether touching the target succeeds (and ends the episode).
    pub fn touch_succeeds(self) -> bool {
        self == Self::Search
    }

    /// Whether an action carries a claim entry after its motion or probe.
    pub fn claims(self) -> bool {
        self == Self::Identify
    }

    /// Whether the info may say where the target is before the episode ends
    /// (`target_distance`): only where the target is no secret (and there is one).
    pub fn reveals_target(self) -> bool {
        self == Self::Search
    }

    /// Whether the task has a target (the map task's layout has one jar generated as a
    /// target, which is a jar like any other there).
    pub fn has_target(self) -> bool {
        self != Self::Map
    }

    /// Whether the episode scores its reconstruction of the cupboard (and pays its gain).
    pub fn scores_map(self) -> bool {
        self == Self::Map
    }

    /// What the task asks, for the environments' docs.
    pub fn description(self) -> &'static str {
        match self {
            Self::Search => {
                "One jar, the target, stands behind the others so that the depth camera in \
                 front of the opening sees at most max_visible_fraction of it. The agent \
                 reaches in and touches it; the first touch of the target succeeds."
            }
            Self::Identify => {
                "The target is known only by its shape: it is the only jar of target_shape \
                 among jars of the other shape, and a decoy of the other shape is hidden as \
                 well as it is, so that looking cannot tell them apart. Touching the target \
                 pays nothing and ends nothing; the contact normals and the map show the \
                 shape of the jar the finger touches. The episode ends with a claim, the \
                 action's last entry, which names the jar the finger touches."
            }
            Self::Map => {
                "There is no target. Within max_steps wrist motions the agent touches the \
                 jars so that the episode's evidence, the depth camera's first look and every \
                 touch, reconstructs the cupboard's contents. The score is the same for every \
                 agent whatever map it observes: the core's exact GPIS of that evidence, \
                 scored against the jars' true footprints by the mean distance between its \
                 zero level set and the true outlines (map_score_mm, both directions, each \
                 point capped at 50 mm), whose shrink is the reward, and by IoU \
                 (map_score_iou); map_score_area is the distance's mean over the budget's \
                 motions (the area under it)."
            }
        }
    }

    /// How an episode of the task ends, for the environments' docs.
    pub fn episode_end(self) -> &'static str {
        match self {
            Self::Search => {
                "Termination: the finger touches the target (success) or a jar tips over \
                 (failure). Truncation: max_steps wrist motions."
            }
            Self::Identify => {
                "Termination: a claim (success if it names the target; otherwise \
                 wrong_claim, also when the finger touches no jar) or a jar tips over \
                 (failure). Truncation: max_steps wrist motions without a claim (failure). \
                 A claim makes no motion and is no step of the time limit."
            }
            Self::Map => {
                "Termination: a jar tips over. Truncation: max_steps wrist motions, the \
                 budget (success is never set; the score is the result)."
            }
        }
    }
}

/// How the claim entry of an action reads: in the `wrist` action mode the 4th entry of the
/// `Box(-1, 1, (4,))` action claims when it is above [`Claim::WRIST_THRESHOLD`]; in the
/// `probe` mode the 4th index of `MultiDiscrete([lanes, depths, sweeps, 2])` claims when it
/// is 1. A claiming action makes no motion: it names the jar the finger touches now.
pub struct Claim;

impl Claim {
    /// The wrist mode's claim entry claims above this value.
    pub const WRIST_THRESHOLD: f64 = 0.0;
    /// The probe mode's claim entry takes this many values: 0 (probe) or 1 (claim).
    pub const PROBE_CHOICES: usize = 2;

    /// Whether a wrist-mode claim entry claims.
    pub fn wrist_claims(entry: f64) -> bool {
        entry > Self::WRIST_THRESHOLD
    }
}

/// The jar a claim names: of the jars the finger touches now, the one whose contact lies
/// nearest the fingertip (`tip`); None when it touches no jar. Contacts are the scene's
/// true ones (`(point, jar)`).
pub fn claimed_jar(
    contacts: impl IntoIterator<Item = ([f64; 2], usize)>,
    tip: [f64; 2],
) -> Option<usize> {
    contacts
        .into_iter()
        .map(|(point, jar)| ((point[0] - tip[0]).hypot(point[1] - tip[1]), jar))
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(_, jar)| jar)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_claim_names_the_touched_jar_nearest_the_fingertip() {
        let contacts = [([0.10, 0.20], 3), ([0.02, 0.01], 5)];
        assert_eq!(claimed_jar(contacts, [0.0, 0.0]), Some(5));
        assert_eq!(claimed_jar([], [0.0, 0.0]), None);
    }

    #[test]
    fn only_search_succeeds_on_touch_and_only_identify_claims() {
        assert!(Task::Search.touch_succeeds() && !Task::Search.claims());
        assert!(!Task::Identify.touch_succeeds() && Task::Identify.claims());
        assert!(!Task::Identify.reveals_target());
    }

    #[test]
    fn only_the_map_task_scores_a_map_and_it_has_no_target() {
        assert!(Task::Map.scores_map() && !Task::Search.scores_map());
        assert!(!Task::Map.touch_succeeds() && !Task::Map.claims() && !Task::Map.reveals_target());
    }

    #[test]
    fn the_wrist_claim_entry_claims_above_zero() {
        assert!(Claim::wrist_claims(0.01));
        assert!(!Claim::wrist_claims(0.0) && !Claim::wrist_claims(-1.0));
    }
}
