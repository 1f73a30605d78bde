//! The static geometry a planner may know, from an episode's configuration alone (no scene
//! is built, nothing of an episode's ground truth): the cupboard, the camera's position, the
//! hand's sizes, start pose, workspace and per-step bounds, the layout's jar sizes and
//! margins, the map grid with its cells' centres, and the `probe` action mode's probes.
//!
//! Every value is what the scene and the map use (they read the same settings), computed in
//! f64 in the order the docs state, so a planner that reads it here gets the numbers, bit
//! for bit, it would get by building a scene and deriving them itself. Cost: O(1), and
//! O(G) for the cell centres.

use super::config::EpisodeConfig;
use super::error::EpisodeError;
use super::probe::{ProbeController, ProbeGrid};
use crate::gpis::GridSpec;
use crate::scene::hand::{joint_offset, reach};

/// The static geometry of an episode's configuration (see the module docs). Metres and
/// radians.
#[derive(Debug, Clone, PartialEq)]
pub struct StaticGeometry {
    /// Interior width along x (centred on x = 0).
    pub width: f64,
    /// Interior depth along y (open front at y = 0).
    pub depth: f64,
    /// The depth camera's optical centre (x, y).
    pub camera: [f64; 2],
    /// The wrist's start pose (x, y, yaw).
    pub start: [f64; 3],
    /// The wrist's workspace ((x_min, x_max), (y_min, y_max)).
    pub workspace: [[f64; 2]; 2],
    /// Largest |dx| and |dy| of one wrist motion.
    pub max_step_translation: f64,
    /// Largest |dyaw| of one wrist motion.
    pub max_step_yaw: f64,
    /// Half side of the cubic wrist.
    pub wrist_half_extent: f64,
    /// Length of the arm link behind the wrist.
    pub arm_length: f64,
    /// Half width of the arm link.
    pub arm_half_width: f64,
    /// Finger length from the joint to the tip.
    pub finger_length: f64,
    /// Half thickness of the finger in the slice plane.
    pub finger_half_thickness: f64,
    /// The finger's deflection limit.
    pub finger_limit: f64,
    /// Wrist centre to the finger's joint ([`joint_offset`]).
    pub joint_offset: f64,
    /// Wrist centre to the undeflected fingertip: `joint_offset + finger_length`.
    pub reach: f64,
    /// The smallest and largest radius of a jar's bounding circle:
    /// `(0.5 min(round_diameter_min, square_side_min),
    /// 0.5 max(round_diameter_max, sqrt(2) square_side_max))`.
    pub jar_radius: [f64; 2],
    /// The target's centre is at least this deep (y).
    pub target_min_depth: f64,
    /// Minimum gap between a jar's bounding circle and a side or back wall.
    pub wall_gap: f64,
    /// The map grid: the cupboard's interior in (H, W) cells, the map's own [`GridSpec`].
    pub grid: GridSpec,
    /// Side of a (square) map cell: `depth / H`.
    pub cell: f64,
    /// |mean| that saturates the map's mean channel.
    pub mean_scale: f64,
    /// Standard deviation that saturates the map's std channel.
    pub std_scale: f64,
    /// The `probe` action mode's probes by action index, as its controller carries them out
    /// (whatever the action mode of `config`).
    pub probes: ProbeGrid,
}

impl StaticGeometry {
    /// The geometry of `config`; fails only where the map's grid does (a config that does
    /// not validate).
    pub fn of(config: &EpisodeConfig) -> Result<Self, EpisodeError> {
        let scene = &config.scene;
        let (hand, layout) = (&scene.hand, &scene.layout);
        let [round, square] = [layout.round_diameter, layout.square_side];
        let [px, py, _] = scene.camera.position;
        Ok(Self {
            width: scene.cupboard.width,
            depth: scene.cupboard.depth,
            camera: [px, py],
            start: hand.start,
            workspace: hand.workspace,
            max_step_translation: hand.max_step_translation,
            max_step_yaw: hand.max_step_yaw,
            wrist_half_extent: hand.wrist_half_extent,
            arm_length: hand.arm_length,
            arm_half_width: hand.arm_half_width,
            finger_length: hand.finger_length,
            finger_half_thickness: hand.finger_half_thickness,
            finger_limit: hand.finger_limit,
            joint_offset: joint_offset(hand),
            reach: reach(hand),
            jar_radius: [
                0.5 * round[0].min(square[0]),
                0.5 * round[1].max(2f64.sqrt() * square[1]),
            ],
            target_min_depth: layout.target_min_depth,
            wall_gap: layout.wall_gap,
            grid: GridSpec::new(config.map_bounds(), config.map.grid_shape)?,
            cell: scene.cupboard.depth / config.map.grid_shape.0 as f64,
            mean_scale: config.map.mean_scale,
            std_scale: config.map.std_scale,
            probes: ProbeController::for_episode(config).grid(),
        })
    }

    /// The cells' centres `(xs, ys)`, each H·W row-major (row i along y, column j along x),
    /// as the map grid has them ([`GridSpec::cell_centre`]). Cost O(G).
    pub fn cell_centres(&self) -> (Vec<f64>, Vec<f64>) {
        self.grid.cell_centres_iter().map(|[x, y]| (x, y)).unzip()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cell_centres_are_the_map_grids_and_reach_the_hands() {
        let config = EpisodeConfig::default();
        let g = StaticGeometry::of(&config).unwrap();
        let (xs, ys) = g.cell_centres();
        let (h, w) = g.grid.shape();
        assert_eq!((h, w), config.map.grid_shape);
        assert_eq!((xs.len(), ys.len()), (h * w, h * w));
        // Row i along y, column j along x, from the interior's corner (-width/2, 0).
        for (i, j) in [
            (0, 0),
            (0, w - 1),
            (h - 1, 0),
            (h - 1, w - 1),
            (h / 2, w / 3),
        ] {
            let x = -0.5 * g.width + (j as f64 + 0.5) * g.width / w as f64;
            let y = (i as f64 + 0.5) * g.depth / h as f64;
            assert_eq!((xs[i * w + j], ys[i * w + j]), (x, y));
        }
        assert_eq!(g.reach, g.joint_offset + g.finger_length);
        assert!((g.cell - g.width / w as f64).abs() < 1e-15);
        assert!(g.jar_radius[0] < g.jar_radius[1]);
    }
}
