//! The controller of the `probe` action mode: the agent chooses *where to probe* and this
//! observation-only controller drives the wrist there (the `wrist` mode, v0's, moves the
//! wrist directly). Its settings are [`ProbeConfig`] ([`super::probe_config`]).
//!
//! An action is three indices, a `MultiDiscrete([lanes, depths, sweeps])`:
//! - a lane `x` across the opening (`probe_lanes` evenly spaced lanes that keep the wrist
//!   [`LANE_WALL_CLEARANCE`] from the side walls);
//! - a wrist depth `y` into the cupboard (`probe_depths` depths from the opening to where the
//!   straight fingertip is [`DEPTH_BACK_CLEARANCE`] from the back wall);
//! - a sweep: the finger's turn at that depth (`probe_sweeps` angles evenly over
//!   `[-probe_max_angle, probe_max_angle]`; positive turns the finger towards +x).
//!
//! The controller moves only through space the hand can come and go by: it turns the finger
//! back to straight (`UNTURN`), and to change lanes it backs out until the fingertip is
//! outside the opening (`RETREAT`), moves sideways there (`SHIFT`) and goes straight in
//! along the new lane (`ENTER`); then it turns the finger at `probe_sweep_rate` per motion
//! (`SWEEP`). Each phase moves at most the hand's per-step bounds per motion, and every
//! motion is one step of the scene (the reward's terms and the time limit count motions).
//! It reads only what the observation holds (the wrist pose and whether the finger
//! touches), and stops the probe early when the finger touches something after a motion
//! that goes deeper or sweeps, and before such a motion while the finger touches (so it
//! never pushes on into a jar it found), when the hand is blocked, or when the episode
//! ends. A probe that makes no motion waits a step.
//!
//! Which lane is clear, how deep to go and which way to turn is the agent's decision: the
//! controller does not read the map, so every map mode gets the same controller.

use super::config::EpisodeConfig;
use super::error::EpisodeError;
use super::probe_config::ProbeConfig;
use crate::scene::hand::reach;
use crate::scene::{HandConfig, HandPose};

/// The wrist keeps this much room to the side walls in the outermost lanes, m.
pub const LANE_WALL_CLEARANCE: f64 = 0.005;
/// The straight fingertip stops this far from the back wall at the deepest depth, m.
pub const DEPTH_BACK_CLEARANCE: f64 = 0.005;
/// "Arrived" within this distance (m) or angle (rad).
const POSITION_TOLERANCE: f64 = 1e-6;

/// `count` evenly spaced values over `[low, high]` (the middle one for a count of 1).
fn spaced(index: usize, count: usize, low: f64, high: f64) -> f64 {
    if count <= 1 {
        0.5 * (low + high)
    } else {
        low + (high - low) * index as f64 / (count - 1) as f64
    }
}

/// One probe: go in along lane `x` to wrist depth `y`, then turn the wrist to `yaw`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Probe {
    /// Lane, m.
    pub x: f64,
    /// Wrist depth, m.
    pub y: f64,
    /// Yaw at the end of the sweep, rad (0 points the finger along +y; a turn towards +x
    /// is a negative yaw).
    pub yaw: f64,
}

/// The probes of a configuration by action index (see [`ProbeController::grid`]).
#[derive(Debug, Clone, PartialEq)]
pub struct ProbeGrid {
    /// The wrist's x in each lane (the first index), m.
    pub lanes: Vec<f64>,
    /// The wrist's y at each depth (the second index), m.
    pub depths: Vec<f64>,
    /// The wrist's yaw at the end of each sweep (the third index), rad.
    pub yaws: Vec<f64>,
    /// The wrist's y the controller backs out to before changing lanes, m.
    pub outside: f64,
    /// The controller's turn per motion while sweeping, rad.
    pub sweep_rate: f64,
}

/// Where the controller is in a probe.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Phase {
    /// Turning the finger back to straight.
    Unturn,
    /// Backing out until the fingertip is outside the opening.
    Retreat,
    /// Moving sideways outside the opening.
    Shift,
    /// Going straight in (or back) along the lane to the depth.
    Enter,
    /// Turning the finger at the depth.
    Sweep,
    /// At the probe's pose.
    Done,
}

impl Phase {
    /// Whether `motion` in this phase presses the finger further into what it may touch
    /// (going deeper along the lane, or sweeping): a touch after such a motion ends the
    /// probe, and such a motion is not made while the finger touches, so the hand never
    /// pushes on into a jar the finger has found.
    pub fn presses(self, motion: &[f64; 3]) -> bool {
        match self {
            Self::Enter => motion[1] > 0.0,
            Self::Sweep => true,
            Self::Unturn | Self::Retreat | Self::Shift | Self::Done => false,
        }
    }
}

/// The probes of one configuration and the controller that carries them out.
#[derive(Debug, Clone)]
pub struct ProbeController {
    config: ProbeConfig,
    lane_edge: f64,
    deepest: f64,
    outside: f64,
    max_step: f64,
    max_yaw: f64,
}

impl ProbeController {
    /// The probes over a cupboard `width` × `depth` (m) for `hand`.
    pub fn new(config: &ProbeConfig, hand: &HandConfig, width: f64, depth: f64) -> Self {
        let reach = reach(hand);
        Self {
            config: config.clone(),
            lane_edge: (0.5 * width - hand.wrist_half_extent - LANE_WALL_CLEARANCE).max(0.0),
            deepest: (depth - reach - DEPTH_BACK_CLEARANCE).max(0.0),
            // The fingertip just outside the opening (and never deeper than the start).
            outside: (-reach).min(hand.start[1]),
            max_step: hand.max_step_translation,
            max_yaw: hand.max_step_yaw,
        }
    }

    /// The controller of an episode of `config` (its probe settings, hand and cupboard).
    pub fn for_episode(config: &EpisodeConfig) -> Self {
        let cupboard = &config.scene.cupboard;
        Self::new(
            &config.probe,
            &config.scene.hand,
            cupboard.width,
            cupboard.depth,
        )
    }

    /// Checks that `action` holds three indices within the counts.
    pub fn check(&self, action: &[i64; 3]) -> Result<(), EpisodeError> {
        for (index, (&value, count)) in action.iter().zip(self.config.counts()).enumerate() {
            if usize::try_from(value).map_or(true, |v| v >= count) {
                return Err(EpisodeError::ProbeIndex {
                    index,
                    value,
                    count,
                });
            }
        }
        Ok(())
    }

    /// The probe an action (checked by [`ProbeController::check`]) names.
    pub fn probe(&self, action: &[i64; 3]) -> Probe {
        let [lane, depth, sweep] = action.map(|v| usize::try_from(v).unwrap_or(0));
        Probe {
            x: self.lane(lane),
            y: self.depth(depth),
            yaw: self.sweep_yaw(sweep),
        }
    }

    /// The wrist's x in lane `index`.
    fn lane(&self, index: usize) -> f64 {
        spaced(index, self.config.lanes, -self.lane_edge, self.lane_edge)
    }

    /// The wrist's y at depth `index`.
    fn depth(&self, index: usize) -> f64 {
        spaced(index, self.config.depths, 0.0, self.deepest)
    }

    /// The wrist's yaw at the end of sweep `index` (a turn towards +x is a negative yaw).
    fn sweep_yaw(&self, index: usize) -> f64 {
        let c = &self.config;
        -spaced(index, c.sweeps, -c.max_angle, c.max_angle)
    }

    /// Every probe's coordinates, per action index, as [`ProbeController::probe`] gives
    /// them, and where the controller goes to change lanes: what a planner choosing probes
    /// needs to know of the controller.
    pub fn grid(&self) -> ProbeGrid {
        let c = &self.config;
        ProbeGrid {
            lanes: (0..c.lanes).map(|i| self.lane(i)).collect(),
            depths: (0..c.depths).map(|i| self.depth(i)).collect(),
            yaws: (0..c.sweeps).map(|i| self.sweep_yaw(i)).collect(),
            outside: self.outside,
            sweep_rate: c.sweep_rate,
        }
    }

    /// The next motion from wrist `pose` towards `probe`, as a wrist action in [−1, 1]³
    /// (the `wrist` mode's scale), and the phase it belongs to (`Done` with no motion
    /// when the wrist is there).
    pub fn next_motion(&self, pose: HandPose, probe: &Probe) -> (Phase, [f64; 3]) {
        let at_lane = (pose.x - probe.x).abs() <= POSITION_TOLERANCE;
        let at_depth = (pose.y - probe.y).abs() <= POSITION_TOLERANCE;
        let towards = |from: f64, to: f64, bound: f64| ((to - from) / bound).clamp(-1.0, 1.0);
        if !(at_lane && at_depth) {
            if pose.yaw.abs() > POSITION_TOLERANCE {
                return (
                    Phase::Unturn,
                    [0.0, 0.0, towards(pose.yaw, 0.0, self.max_yaw)],
                );
            }
            if !at_lane {
                if pose.y > self.outside + POSITION_TOLERANCE {
                    let dy = towards(pose.y, self.outside, self.max_step);
                    return (Phase::Retreat, [0.0, dy, 0.0]);
                }
                return (
                    Phase::Shift,
                    [towards(pose.x, probe.x, self.max_step), 0.0, 0.0],
                );
            }
            return (
                Phase::Enter,
                [0.0, towards(pose.y, probe.y, self.max_step), 0.0],
            );
        }
        if (pose.yaw - probe.yaw).abs() <= POSITION_TOLERANCE {
            return (Phase::Done, [0.0; 3]);
        }
        let turn = (probe.yaw - pose.yaw).clamp(-self.config.sweep_rate, self.config.sweep_rate);
        (Phase::Sweep, [0.0, 0.0, turn / self.max_yaw])
    }

    /// How many wrist motions the controller makes from `pose` to finish `probe` when
    /// nothing touches or blocks the hand: [`ProbeController::next_motion`] stepped on the
    /// kinematic pose (each motion moved in full), as [`crate::episode::Episode`] steps it.
    /// The cost a planner choosing probes weighs, from the controller itself. Cost O(motions).
    pub fn motions(&self, pose: HandPose, probe: &Probe) -> usize {
        self.motions_until(pose, probe, |phase| phase == Phase::Done)
            .0
    }

    /// The motions to reach `probe`'s lane and depth from `pose` (those before its sweep,
    /// which do not depend on the sweep) and the pose they end in, stepped as
    /// [`ProbeController::motions`] steps them: so `motions(pose, probe)` is the count plus
    /// `motions(end, probe)` for every sweep of that lane and depth.
    pub fn approach(&self, pose: HandPose, probe: &Probe) -> (usize, HandPose) {
        self.motions_until(pose, probe, |phase| {
            matches!(phase, Phase::Sweep | Phase::Done)
        })
    }

    /// [`ProbeController::approach`] from `pose` to every lane and depth of the grid, in
    /// row-major order (lane, then depth), at the cost of a few probes rather than one per
    /// lane and depth. The controller's phases run one after another, each moving one
    /// coordinate: the unturn (the yaw) and the retreat (y) do not depend on the lane, the
    /// shift (x) only on the lane, the entry (y) only on where it starts and the depth. So
    /// each phase is stepped once per lane or depth, by [`ProbeController::next_motion`]
    /// itself, and the counts added: the same counts and end poses, bit for bit (tested).
    pub fn approaches(&self, pose: HandPose) -> Vec<(usize, HandPose)> {
        let c = &self.config;
        let lanes: Vec<f64> = (0..c.lanes).map(|i| self.lane(i)).collect();
        let depths: Vec<f64> = (0..c.depths).map(|i| self.depth(i)).collect();
        let near = |a: f64, b: f64| (a - b).abs() <= POSITION_TOLERANCE;
        // Runs the motions of `phase` only, towards (x, y).
        let run = |from: HandPose, x: f64, y: f64, phase: Phase| {
            self.motions_until(from, &Probe { x, y, yaw: 0.0 }, |p| p != phase)
        };
        // The entry from `from` (at its lane) to every depth.
        let enter_all = |from: HandPose| -> Vec<(usize, HandPose)> {
            depths
                .iter()
                .map(|&y| run(from, from.x, y, Phase::Enter))
                .collect()
        };
        // The unturn, for every target but the pose's own lane and depth (where nothing
        // moves); x and y stay as they are.
        let (unturn, unturned) = run(pose, f64::NAN, f64::NAN, Phase::Unturn);
        let mut entries_here: Option<Vec<(usize, HandPose)>> = None;
        let mut entries_outside: Option<Vec<(usize, HandPose)>> = None;
        let mut approaches = Vec::with_capacity(lanes.len() * depths.len());
        for &x in &lanes {
            if near(pose.x, x) {
                // The pose's own lane: no retreat or shift, straight to the depth.
                let entries = entries_here.get_or_insert_with(|| enter_all(unturned));
                for (&y, &(enter, entered)) in depths.iter().zip(entries.iter()) {
                    approaches.push(if near(pose.y, y) {
                        (0, pose)
                    } else {
                        (unturn + enter, entered)
                    });
                }
                continue;
            }
            let (retreat, retreated) = run(unturned, x, f64::NAN, Phase::Retreat);
            let (shift, shifted) = run(retreated, x, f64::NAN, Phase::Shift);
            // The entry reads y alone (x stays at the lane): the same from every lane.
            let entries = entries_outside.get_or_insert_with(|| enter_all(shifted));
            for &(enter, entered) in entries.iter() {
                let end = HandPose {
                    x: shifted.x,
                    ..entered
                };
                approaches.push((unturn + retreat + shift + enter, end));
            }
        }
        approaches
    }

    fn motions_until(
        &self,
        mut pose: HandPose,
        probe: &Probe,
        stop: impl Fn(Phase) -> bool,
    ) -> (usize, HandPose) {
        let mut count = 0;
        loop {
            let (phase, [dx, dy, dyaw]) = self.next_motion(pose, probe);
            // Each phase converges in a bounded number of motions; this bound is a bug's.
            if stop(phase) || count >= MAX_PROBE_MOTIONS {
                return (count, pose);
            }
            pose.x += dx * self.max_step;
            pose.y += dy * self.max_step;
            pose.yaw += dyaw * self.max_yaw;
            count += 1;
        }
    }
}

/// More motions than any probe of a valid configuration takes (the farthest lane change
/// and the widest sweep at the slowest rates are a few thousand).
const MAX_PROBE_MOTIONS: usize = 1_000_000;

#[cfg(test)]
mod tests {
    use super::*;

    fn controller() -> ProbeController {
        ProbeController::new(&ProbeConfig::default(), &HandConfig::default(), 0.6, 0.3)
    }

    #[test]
    fn probes_span_the_opening_and_the_depth_symmetrically() {
        let c = controller();
        let first = c.probe(&[0, 0, 0]);
        let last = c.probe(&[28, 9, 8]);
        assert!((first.x + last.x).abs() < 1e-12 && last.x > 0.25);
        assert_eq!(first.y, 0.0);
        assert!((first.yaw - 1.0).abs() < 1e-12 && (last.yaw + 1.0).abs() < 1e-12);
        assert_eq!(c.probe(&[14, 0, 4]).x, 0.0);
        assert_eq!(c.probe(&[14, 0, 4]).yaw, 0.0);
    }

    #[test]
    fn the_grid_lists_every_probe_the_indices_name() {
        let c = controller();
        let grid = c.grid();
        let config = ProbeConfig::default();
        assert_eq!(
            [grid.lanes.len(), grid.depths.len(), grid.yaws.len()],
            config.counts()
        );
        for (lane, &x) in grid.lanes.iter().enumerate() {
            for (depth, &y) in grid.depths.iter().enumerate() {
                for (sweep, &yaw) in grid.yaws.iter().enumerate() {
                    let probe = c.probe(&[lane as i64, depth as i64, sweep as i64]);
                    assert_eq!(probe, Probe { x, y, yaw });
                }
            }
        }
        assert_eq!(grid.outside, c.outside);
        assert_eq!(grid.sweep_rate, config.sweep_rate);
    }

    #[test]
    fn indices_outside_the_counts_are_refused() {
        let c = controller();
        assert!(c.check(&[28, 9, 8]).is_ok());
        for bad in [[29, 0, 0], [0, -1, 0], [0, 0, 9]] {
            assert!(matches!(
                c.check(&bad),
                Err(EpisodeError::ProbeIndex { .. })
            ));
        }
    }

    #[test]
    fn a_lane_change_turns_back_then_retreats_then_shifts_then_enters_then_sweeps() {
        let c = controller();
        let probe = c.probe(&[20, 5, 0]);
        let mut pose = HandPose {
            x: 0.0,
            y: 0.1,
            yaw: 0.3,
        };
        let hand = HandConfig::default();
        let mut phases = vec![];
        for _ in 0..500 {
            let (phase, [dx, dy, dyaw]) = c.next_motion(pose, &probe);
            if phases.last() != Some(&phase) {
                phases.push(phase);
            }
            if phase == Phase::Done {
                break;
            }
            assert!(dx.abs() <= 1.0 && dy.abs() <= 1.0 && dyaw.abs() <= 1.0);
            pose.x += dx * hand.max_step_translation;
            pose.y += dy * hand.max_step_translation;
            pose.yaw += dyaw * hand.max_step_yaw;
        }
        use Phase::*;
        assert_eq!(phases, [Unturn, Retreat, Shift, Enter, Sweep, Done]);
        assert!((pose.x - probe.x).abs() < 1e-9 && (pose.y - probe.y).abs() < 1e-9);
    }

    #[test]
    fn the_motion_count_follows_the_controllers_own_path() {
        let c = controller();
        let hand = HandConfig::default();
        let start = HandPose {
            x: hand.start[0],
            y: hand.start[1],
            yaw: hand.start[2],
        };
        // Straight in from the start (y -0.125) to the opening (y 0) at 0.01 per motion.
        assert_eq!(c.motions(start, &c.probe(&[14, 0, 4])), 13);
        // Then the widest sweep, 1 rad at 0.05 per motion.
        let there = HandPose { y: 0.0, ..start };
        assert_eq!(c.motions(there, &c.probe(&[14, 0, 0])), 20);
        // A lane change counts every phase, as the stepped loop makes them.
        let probe = c.probe(&[20, 5, 0]);
        let mut pose = HandPose {
            x: 0.0,
            y: 0.1,
            yaw: 0.3,
        };
        let from = pose;
        let mut stepped = 0;
        loop {
            let (phase, [dx, dy, dyaw]) = c.next_motion(pose, &probe);
            if phase == Phase::Done {
                break;
            }
            pose.x += dx * hand.max_step_translation;
            pose.y += dy * hand.max_step_translation;
            pose.yaw += dyaw * hand.max_step_yaw;
            stepped += 1;
        }
        assert_eq!(c.motions(from, &probe), stepped);
        assert!(stepped > 40);
        assert_eq!(c.motions(pose, &probe), 0);
    }

    #[test]
    fn the_same_lane_goes_straight_to_the_new_depth() {
        let c = controller();
        let probe = c.probe(&[14, 2, 4]);
        let pose = HandPose {
            x: 0.0,
            y: 0.15,
            yaw: 0.0,
        };
        assert_eq!(c.next_motion(pose, &probe).0, Phase::Enter);
    }

    #[test]
    fn approaches_to_the_whole_grid_equal_each_approach_bit_for_bit() {
        let c = controller();
        let grid = c.grid();
        let mut poses = vec![
            HandPose {
                x: 0.0,
                y: -0.2,
                yaw: 0.0,
            },
            // At a lane and a depth of the grid, turned and not.
            HandPose {
                x: grid.lanes[3],
                y: grid.depths[4],
                yaw: 0.0,
            },
            HandPose {
                x: grid.lanes[3],
                y: grid.depths[4],
                yaw: grid.yaws[1],
            },
            HandPose {
                x: grid.lanes[28],
                y: grid.depths[0],
                yaw: grid.yaws[8],
            },
            // Near a lane, within the tolerance and beyond it.
            HandPose {
                x: grid.lanes[10] + 0.5e-6,
                y: 0.1,
                yaw: 0.3,
            },
            HandPose {
                x: grid.lanes[10] + 1e-3,
                y: 0.1,
                yaw: -0.3,
            },
        ];
        let mut state = 7u64;
        let mut uniform = |low: f64, high: f64| {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            low + (high - low) * ((state >> 11) as f64 / (1u64 << 53) as f64)
        };
        for _ in 0..40 {
            poses.push(HandPose {
                x: uniform(-0.3, 0.3),
                y: uniform(-0.25, 0.3),
                yaw: uniform(-1.0, 1.0),
            });
        }
        for pose in poses {
            let all = c.approaches(pose);
            assert_eq!(all.len(), grid.lanes.len() * grid.depths.len());
            for (lane, &x) in grid.lanes.iter().enumerate() {
                for (depth, &y) in grid.depths.iter().enumerate() {
                    let one = c.approach(pose, &Probe { x, y, yaw: 0.0 });
                    assert_eq!(
                        all[lane * grid.depths.len() + depth],
                        one,
                        "{pose:?} to {x}, {y}"
                    );
                }
            }
        }
    }
}
