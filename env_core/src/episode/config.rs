//! Every setting of an episode, declared once (`docs/DESIGN.md` §4 and §8): the reward and the
//! episode end, with the probes', the map's ([`super::maps::MapConfig`], beside the map
//! modes) and the scene's settings as sections. The settings table is what the
//! environment's keyword arguments, its docs and the stub are made from.

use super::action_mode::ActionMode;
use super::maps::MapConfig;
use super::probe_config::{check_sweep_rate, ProbeConfig};
use super::task::Task;
use crate::scene::{SceneConfig, TargetShape};
use crate::settings;
use crate::settings::{Choice, Range, SettingError};

settings! {
    /// Reward weights. Each term is reported on its own in the step info.
    pub struct RewardConfig {
        /// Paid once when the finger touches the target.
        success: f64 = 1.0 => "reward_success" in Range::NON_NEGATIVE,
        /// Paid (negated) every step.
        step_cost: f64 = 0.01 => "reward_step_cost" in Range::NON_NEGATIVE,
        /// Per metre the jars' summed planar displacement from their start grows in a step,
        /// negated (a step that moves jars back towards their start costs nothing and earns
        /// nothing back).
        displacement: f64 = 10.0 => "reward_displacement" in Range::NON_NEGATIVE,
        /// Paid (negated) when a jar tips over. A tip ends the episode, so it must cost more
        /// than the step costs it saves (max_steps times reward_step_cost = 2 at the
        /// defaults), or knocking a jar over early is the cheapest way out of a hard layout.
        tip: f64 = 3.0 => "reward_tip" in Range::NON_NEGATIVE,
        /// Paid (negated) when a claim (the identify task) names a jar other than the
        /// target, or no jar; a correct claim is paid reward_success.
        wrong_claim: f64 = 1.0 => "reward_wrong_claim" in Range::NON_NEGATIVE,
        /// Per mm the map task's outline distance (map_score_mm) shrinks in a step; a
        /// growth costs as much.
        map: f64 = 0.1 => "reward_map" in Range::NON_NEGATIVE,
        /// Shaping, per metre the fingertip's path distance to the target shrinks in a step:
        /// over an episode it adds reward_approach times (start distance - final distance),
        /// so it also pays for ending nearer the target and, with discounting, for getting
        /// nearer sooner (not policy-invariant). 0 leaves the task's reward alone.
        approach: f64 = 0.0 => "reward_approach" in Range::NON_NEGATIVE,
    }
    sections {}
    check_across = |_| Ok(());
}

settings! {
    /// One episode's configuration: its own settings, then the map, the reward and the
    /// scene.
    pub struct EpisodeConfig {
        /// What the episode asks: 'search' (v0: a touch of the hidden target succeeds),
        /// 'identify' (the target is the only jar of its shape, target_shape, among jars of
        /// the other; a touch of it pays nothing, and the episode ends with a claim, the
        /// action's 4th entry, naming the jar the finger touches) or 'map' (no target:
        /// touch so that the evidence reconstructs the cupboard within max_steps; the
        /// reward is the score's gain).
        task: Task = Task::Search => "task" in Range::FINITE,
        /// Episode length: the time limit (truncation) and the scale of the time-left entry
        /// of the proprioception.
        max_steps: usize = 200 => "max_steps" in Range::AT_LEAST_ONE,
        /// A jar whose axis leans more than this from vertical has tipped over, rad.
        tip_angle: f64 = 0.5 => "tip_angle" in Range::left_open(0.0, 1.6),
        /// What an action is: 'wrist' (v0: a wrist motion per step, Box(-1, 1, (3,))) or
        /// 'probe' (a lane, depth and sweep per step, MultiDiscrete([probe_lanes,
        /// probe_depths, probe_sweeps]), driven there by an observation-only controller;
        /// every motion is a step of max_steps and of the reward).
        action_mode: ActionMode = ActionMode::Wrist => "action_mode" in Range::FINITE,
    }
    sections {
        /// The probes of the `probe` action mode.
        probe: ProbeConfig,
        /// The map.
        map: MapConfig,
        /// The reward.
        reward: RewardConfig,
        /// The physical scene.
        scene: SceneConfig,
    }
    check_across = check_across;
}

/// The grid's cells must be square, a probe's sweep no faster than the hand turns, and the
/// task's target one that its rule can tell apart.
fn check_across(c: &EpisodeConfig) -> Result<(), SettingError> {
    check_grid(c)?;
    check_sweep_rate(&c.probe, &c.scene.hand)?;
    check_task(c)
}

/// In the identify task the target is known by its shape alone: it must be the only jar of
/// its shape, so target_shape names one and round_fraction gives every other jar the other;
/// and a decoy must be hidden as well as it, or looking would tell which hidden jar it is.
fn check_task(c: &EpisodeConfig) -> Result<(), SettingError> {
    if c.task != Task::Identify {
        return Ok(());
    }
    let layout = &c.scene.layout;
    if layout.hidden_decoys == 0 {
        return Err(SettingError::out_of_range(
            "hidden_decoys",
            "at least 1 in the identify task (a decoy hidden as well as the target, so that \
             only touch tells them apart)",
            0,
        ));
    }
    let others_round = match layout.target_shape {
        TargetShape::Square => 1.0,
        TargetShape::Round => 0.0,
        TargetShape::Any => {
            return Err(SettingError::out_of_range(
                "target_shape",
                "'square' or 'round' in the identify task (the target is the only jar of its \
                 shape)",
                "'any'",
            ))
        }
    };
    if layout.round_fraction == others_round {
        Ok(())
    } else {
        Err(SettingError::out_of_range(
            "round_fraction",
            format!(
                "{others_round} in the identify task with target_shape='{}' (every other jar \
                 of the other shape, so that the shape names the target)",
                layout.target_shape.name()
            ),
            layout.round_fraction,
        ))
    }
}

/// The grid's cells must be square over the cupboard's interior.
fn check_grid(c: &EpisodeConfig) -> Result<(), SettingError> {
    let (h, w) = c.map.grid_shape;
    let (width, depth) = (c.scene.cupboard.width, c.scene.cupboard.depth);
    let aspect = width / depth;
    if (w as f64 / h as f64 - aspect).abs() < 1e-9 * aspect {
        Ok(())
    } else {
        Err(SettingError::out_of_range(
            "grid_shape",
            format!(
                "(H, W) with square cells over the {width} m x {depth} m interior \
                 (W / H = {aspect})"
            ),
            format!("({h}, {w})"),
        ))
    }
}

impl EpisodeConfig {
    /// The map's bounds `[[x0, x1], [y0, y1]]`: the cupboard's interior in the slice plane.
    pub fn map_bounds(&self) -> [[f64; 2]; 2] {
        let half_width = self.scene.cupboard.width / 2.0;
        [[-half_width, half_width], [0.0, self.scene.cupboard.depth]]
    }
}
