//! The static geometry the probe planner knows: the episode configuration's
//! [`StaticGeometry`] (no ground truth of an episode) with the map's cell centres and the
//! largest sweep angle, under the names the planner's rules use.

use super::distance::CappedDistance;
use crate::episode::{EpisodeConfig, EpisodeError, ProbeController, StaticGeometry};

/// The cap of the planner's distances to a mask's cells (the seen surfaces, the cells that
/// may hold a jar), m.
pub const DISTANCE_CAP: f64 = 0.08;

/// Static sizes in metres (and radians); see [`StaticGeometry`] for each.
#[derive(Debug, Clone)]
pub struct PlannerGeometry {
    pub width: f64,
    pub depth: f64,
    pub wrist_half_extent: f64,
    pub arm_length: f64,
    pub arm_half_width: f64,
    pub finger_length: f64,
    pub finger_half_thickness: f64,
    pub joint_offset: f64,
    pub reach: f64,
    pub jar_radius: [f64; 2],
    pub target_min_depth: f64,
    pub wall_gap: f64,
    /// (H, W) of the map grid.
    pub grid_shape: (usize, usize),
    /// Side of a (square) map cell.
    pub cell: f64,
    /// The cells' centres, H·W row-major (row i along y, column j along x).
    pub xs: Vec<f64>,
    pub ys: Vec<f64>,
    /// The `probe` action mode's probes per action index: the wrist's x per lane, y per
    /// depth and yaw at the end of each sweep (a turn towards +x is a negative yaw).
    pub probe_lanes: Vec<f64>,
    pub probe_depths: Vec<f64>,
    pub probe_yaws: Vec<f64>,
    /// The wrist's y the probe controller backs out to before changing lanes.
    pub probe_outside: f64,
    /// The probe controller's turn per motion while sweeping, rad.
    pub probe_sweep_rate: f64,
    /// The largest sweep angle either way, rad.
    pub probe_max_angle: f64,
    /// The controller itself, which counts a probe's motions.
    pub controller: ProbeController,
    /// Per cell, the bearing of its centre from the camera (atan2 of x over y offsets) and
    /// its range, for the camera's shadows.
    pub camera_bearings: Vec<f64>,
    pub camera_ranges: Vec<f64>,
    /// The distance to the nearest cell of a mask, capped at `DISTANCE_CAP`, on this grid's
    /// cells (the clearance field's and the seen surfaces').
    pub distance: CappedDistance,
}

impl PlannerGeometry {
    /// The geometry of `config` (fails only on a config whose map grid does not build).
    pub fn of(config: &EpisodeConfig) -> Result<Self, EpisodeError> {
        let g = StaticGeometry::of(config)?;
        let (xs, ys) = g.cell_centres();
        let [cx, cy] = g.camera;
        let camera_bearings = xs
            .iter()
            .zip(&ys)
            .map(|(x, y)| (x - cx).atan2(y - cy))
            .collect();
        let camera_ranges = xs
            .iter()
            .zip(&ys)
            .map(|(x, y)| (x - cx).hypot(y - cy))
            .collect();
        Ok(Self {
            width: g.width,
            depth: g.depth,
            wrist_half_extent: g.wrist_half_extent,
            arm_length: g.arm_length,
            arm_half_width: g.arm_half_width,
            finger_length: g.finger_length,
            finger_half_thickness: g.finger_half_thickness,
            joint_offset: g.joint_offset,
            reach: g.reach,
            jar_radius: g.jar_radius,
            target_min_depth: g.target_min_depth,
            wall_gap: g.wall_gap,
            grid_shape: g.grid.shape(),
            cell: g.cell,
            xs,
            ys,
            probe_lanes: g.probes.lanes,
            probe_depths: g.probes.depths,
            probe_yaws: g.probes.yaws,
            probe_outside: g.probes.outside,
            probe_sweep_rate: g.probes.sweep_rate,
            probe_max_angle: config.probe.max_angle,
            controller: ProbeController::for_episode(config),
            camera_bearings,
            camera_ranges,
            distance: CappedDistance::new(g.cell, DISTANCE_CAP),
        })
    }

    /// The finger's direction at `yaw` (0 points along +y).
    pub fn forward(yaw: f64) -> [f64; 2] {
        [-yaw.sin(), yaw.cos()]
    }

    /// The finger's joint for the wrist at `wrist` turned to `yaw`.
    pub fn joint(&self, wrist: [f64; 2], yaw: f64) -> [f64; 2] {
        let forward = Self::forward(yaw);
        [
            wrist[0] + self.joint_offset * forward[0],
            wrist[1] + self.joint_offset * forward[1],
        ]
    }

    /// Every probe of the grid, `[lane, depth, sweep]`, in row-major order (the order of
    /// the action's index, [`PlannerGeometry::probe_index`]).
    pub fn probe_actions(&self) -> impl Iterator<Item = [usize; 3]> {
        let (depths, sweeps) = (self.probe_depths.len(), self.probe_yaws.len());
        (0..self.probe_lanes.len() * depths * sweeps).map(move |index| {
            [
                index / (depths * sweeps),
                index / sweeps % depths,
                index % sweeps,
            ]
        })
    }

    /// The row-major index of probe `[lane, depth, sweep]`.
    pub fn probe_index(&self, [lane, depth, sweep]: [usize; 3]) -> usize {
        (lane * self.probe_depths.len() + depth) * self.probe_yaws.len() + sweep
    }

    /// The probe a planner falls back to when nothing is worth a probe: straight in at the
    /// middle lane's opening.
    pub fn opening_probe(&self) -> [i64; 3] {
        [
            (self.probe_lanes.len() / 2) as i64,
            0,
            (self.probe_yaws.len() / 2) as i64,
        ]
    }
}
