//! Which probes of the grid the hand can make from a pose, asked probe by probe: the
//! clearance rules of [`super::probe_planner`]'s candidates, each part computed the first
//! time a probe needs it and kept for the others.
//!
//! A probe `[lane, depth, sweep]` is clear when the wrist can go straight in along its lane
//! to its depth ([`deepest_clear`]), its sweep is no wider than the largest safe turn there
//! towards its side ([`safe_angle`]), and it is not a wait (the hand already there). The
//! lane's depth, the turns at a position and the motions to it are shared by many probes;
//! a planner that scores probes first asks only for those of the few that could win.

use super::clearance::{
    deepest_clear, safe_angle, ClearanceField, FieldLayout, SweepMask, TurnProbe,
};
use super::geometry::PlannerGeometry;
use crate::episode::Probe;
use crate::scene::HandPose;

/// A pose is at a lane, or has not turned, within these (m, rad).
pub(super) const LANE_TOL: f64 = 1e-4;
pub(super) const YAW_TOL: f64 = 1e-3;

/// A probe as its finger path: in along lane `x` to wrist depth `y`, then a turn of
/// `angle` rad towards `side` (+1: +x).
#[derive(Debug, Clone, Copy)]
pub(super) struct SweptProbe {
    pub x: f64,
    pub y: f64,
    pub side: f64,
    pub angle: f64,
}

/// A probe the hand can make, with the motions the controller takes to make it.
pub(super) struct Candidate {
    pub action: [i64; 3],
    pub probe: SweptProbe,
    pub motions: f64,
}

/// The grid's probes as seen from one pose and one belief (see the module docs).
pub(super) struct Reachable<'a> {
    g: &'a PlannerGeometry,
    turns: &'a TurnProbe,
    /// The distance to the nearest cell that may hold a jar (the wrist and arm keep clear).
    field: ClearanceField,
    /// The cells the finger must not sweep into.
    solid: SweepMask,
    pose: HandPose,
    /// Per lane, once asked: how deep the wrist goes (`None`: blocked at the opening).
    deepest: Vec<Option<Option<f64>>>,
    /// Per (lane, depth), once asked: the largest safe turn towards −x and towards +x.
    safe: Vec<[Option<f64>; 2]>,
    /// Per (lane, depth), once any is asked: the motions to reach it and the pose they end
    /// in (the controller's [`approaches`](crate::episode::ProbeController::approaches)).
    approaches: Option<Vec<(usize, HandPose)>>,
}

impl<'a> Reachable<'a> {
    /// The probes from `pose` with the wrist and arm clear of `blocked` cells and the
    /// finger out of `solid_cells` (masks of the map's cells, row-major).
    pub(super) fn new(
        g: &'a PlannerGeometry,
        layout: &FieldLayout,
        turns: &'a TurnProbe,
        blocked: &[bool],
        solid_cells: &[bool],
        pose: HandPose,
    ) -> Self {
        let positions = g.probe_lanes.len() * g.probe_depths.len();
        Self {
            g,
            turns,
            field: ClearanceField::new(g, layout, blocked),
            solid: SweepMask::new(g, layout, solid_cells),
            pose,
            deepest: vec![None; g.probe_lanes.len()],
            safe: vec![[None; 2]; positions],
            approaches: None,
        }
    }

    /// Whether the wrist reaches `action`'s lane and depth straight in along the lane.
    pub(super) fn reaches_depth(&mut self, [lane, depth, _]: [usize; 3]) -> bool {
        let (g, field, solid) = (self.g, &self.field, &self.solid);
        let x = g.probe_lanes[lane];
        let deepest = *self.deepest[lane].get_or_insert_with(|| deepest_clear(g, field, solid, x));
        deepest.is_some_and(|deepest| g.probe_depths[depth] <= deepest + 1e-9)
    }

    /// Whether `action`'s sweep is no wider than the largest safe turn at its lane and
    /// depth, which the wrist must reach ([`Reachable::reaches_depth`]).
    pub(super) fn turn_is_safe(&mut self, [lane, depth, sweep]: [usize; 3]) -> bool {
        let g = self.g;
        let (side, angle) = turn_of(g.probe_yaws[sweep]);
        let index = usize::from(side > 0.0);
        let (turns, field, solid) = (self.turns, &self.field, &self.solid);
        let safe = *self.safe[lane * g.probe_depths.len() + depth][index]
            .get_or_insert_with(|| safe_angle(g, turns, field, solid, [lane, depth], side));
        angle <= safe + 1e-9
    }

    /// Whether `action` would leave the hand where it is (a wait: the scene does not change
    /// while the hand waits).
    pub(super) fn is_wait(&self, [lane, depth, sweep]: [usize; 3]) -> bool {
        let g = self.g;
        (self.pose.x - g.probe_lanes[lane]).abs() <= LANE_TOL
            && (self.pose.y - g.probe_depths[depth]).abs() <= LANE_TOL
            && (self.pose.yaw - g.probe_yaws[sweep]).abs() <= YAW_TOL
    }

    /// The motions the controller takes from the pose to reach `action`'s lane and depth,
    /// and the pose they end in: the part of its motions its sweep does not change.
    fn approach(&mut self, [lane, depth, _]: [usize; 3]) -> (usize, HandPose) {
        let (g, pose) = (self.g, self.pose);
        let approaches = self
            .approaches
            .get_or_insert_with(|| g.controller.approaches(pose));
        approaches[lane * g.probe_depths.len() + depth]
    }

    /// The fewest motions `action` can take: those to its lane and depth.
    pub(super) fn least_motions(&mut self, action: [usize; 3]) -> usize {
        self.approach(action).0
    }

    /// The motions the controller takes from the pose to carry out `action`.
    pub(super) fn motions(&mut self, action: [usize; 3]) -> usize {
        let g = self.g;
        let (approach, reached) = self.approach(action);
        let [lane, depth, sweep] = action;
        let (x, y, yaw) = (
            g.probe_lanes[lane],
            g.probe_depths[depth],
            g.probe_yaws[sweep],
        );
        approach + g.controller.motions(reached, &Probe { x, y, yaw })
    }

    /// `action` as a candidate, its motions counted, if the hand can make it.
    fn candidate(&mut self, action: [usize; 3]) -> Option<Candidate> {
        let clear = self.reaches_depth(action) && self.turn_is_safe(action);
        if !clear || self.is_wait(action) {
            return None;
        }
        let g = self.g;
        let (side, angle) = turn_of(g.probe_yaws[action[2]]);
        Some(Candidate {
            action: action.map(|i| i as i64),
            probe: SweptProbe {
                x: g.probe_lanes[action[0]],
                y: g.probe_depths[action[1]],
                side,
                angle,
            },
            motions: self.motions(action) as f64,
        })
    }

    /// Every probe of the grid the hand can make, in row-major order.
    pub(super) fn all(&mut self) -> Vec<Candidate> {
        let g = self.g;
        let mut reachable = Vec::new();
        for lane in 0..g.probe_lanes.len() {
            for depth in 0..g.probe_depths.len() {
                if !self.reaches_depth([lane, depth, 0]) {
                    break; // the depths rise: the deeper ones are out of reach too
                }
                for sweep in 0..g.probe_yaws.len() {
                    reachable.extend(self.candidate([lane, depth, sweep]));
                }
            }
        }
        reachable
    }
}

/// The side (+1: towards +x) and angle of a turn to wrist `yaw`: a negative yaw turns to +x.
pub(super) fn turn_of(yaw: f64) -> (f64, f64) {
    (if yaw < 0.0 { 1.0 } else { -1.0 }, yaw.abs())
}
