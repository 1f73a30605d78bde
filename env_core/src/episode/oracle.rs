//! A scripted oracle that knows the target: the upper-bound baseline, and the proof that
//! episodes are solvable. It drives the wrist to the generated layout's corridor, straight
//! in to the target's depth, then turns the finger towards the target until it touches; in
//! a task that claims it then claims the jar it touches, the target.
//! Stateless: the phase follows from the wrist's pose, so it can take over mid-episode.

use super::action_mode::Action;
use super::episode::Episode;

/// Wrist clearance from the corridor's edge, m.
const CLEARANCE: f64 = 0.002;
/// Yaw per step while turning towards the target, rad.
const TURN: f64 = 0.02;

/// The oracle's next action: a wrist motion in the environment's units ([−1, 1]³), or, in a
/// task that claims, a claim once the finger touches the target.
pub fn oracle_action(episode: &Episode) -> Action {
    let target = episode.scene().target();
    if episode.config().task.claims() && episode.touched_jar() == Some(target) {
        Action::Claim
    } else {
        Action::Wrist(oracle_motion(episode))
    }
}

/// The oracle's next wrist motion ([−1, 1]³). Without a corridor (a hand-made layout) it
/// heads straight for the target's depth.
pub fn oracle_motion(episode: &Episode) -> [f64; 3] {
    let scene = episode.scene();
    let hand = &episode.config().scene.hand;
    let layout = scene.layout();
    let target = layout.jars[layout.target];
    let reach = hand.wrist_half_extent + CLEARANCE + hand.finger_length;
    let (lane_x, side) = match layout.corridor {
        Some(corridor) => {
            let inner = if corridor.side > 0.0 {
                corridor.x[0]
            } else {
                corridor.x[1]
            };
            (
                inner + corridor.side * (hand.wrist_half_extent + CLEARANCE),
                corridor.side,
            )
        }
        None => (target.x, 1.0),
    };
    let pose = scene.hand_pose();
    let outside = pose.y < hand.start[1] + 1e-6;
    let to_x = lane_x - pose.x;
    let to_y = target.y - reach - pose.y;
    let step = hand.max_step_translation;
    let scale = |d: f64| (d / step).clamp(-1.0, 1.0);
    if outside && to_x.abs() > 1e-6 {
        [scale(to_x), 0.0, 0.0]
    } else if to_y > 1e-6 || to_x.abs() > 1e-6 {
        [scale(to_x), scale(to_y), 0.0]
    } else {
        [0.0, 0.0, (TURN * side / hand.max_step_yaw).clamp(-1.0, 1.0)]
    }
}
