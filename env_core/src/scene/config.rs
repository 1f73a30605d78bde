//! Every setting of the cupboard scene, declared once: key, meaning, type, default and valid
//! range (`docs/DESIGN.md` §2 and §8). The [`settings!`](crate::settings!) tables are what the
//! bindings, the Python config, the docs and the stub read; [`SceneConfig::validate`] checks
//! each setting's range and then the relations between settings.
//!
//! Units are SI (metres, kilograms, seconds, radians), z up; the cupboard's open front is the
//! plane y = 0 and its interior is centred on x = 0.

use std::f64::consts::PI;

use super::camera_intrinsics::CameraIntrinsics;
use crate::settings;
use crate::settings::{Range, SettingError};

/// Which shape the hidden target jar has.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TargetShape {
    /// A cylinder.
    Round,
    /// A square cuboid.
    Square,
    /// Drawn like the other jars, from [`LayoutConfig::round_fraction`].
    Any,
}

crate::choice! {
    TargetShape {
        Round => "round",
        Square => "square",
        Any => "any",
    }
}

settings! {
    /// The shelf compartment: interior size and wall material.
    pub struct CupboardConfig {
        /// Interior width along x (centred on x = 0), m.
        width: f64 = 0.60 => "cupboard_width" in Range::LENGTH,
        /// Interior depth along y (open front at y = 0), m.
        depth: f64 = 0.30 => "cupboard_depth" in Range::LENGTH,
        /// Interior height along z (floor top at z = 0), m.
        height: f64 = 0.30 => "cupboard_height" in Range::LENGTH,
        /// Thickness of floor, back, side walls and top, m (thick walls keep a fast hand
        /// from tunnelling).
        wall_thickness: f64 = 0.05 => "wall_thickness" in Range::LENGTH,
        /// Friction coefficient of the walls.
        friction: f64 = 0.5 => "wall_friction" in Range::NON_NEGATIVE,
    }
    sections {}
    check_across = |_| Ok(());
}

/// Most jars a layout holds, target included: the top of `jar_count`'s range, and what an
/// explicit layout is checked against ([`super::layout::Layout::check`]).
pub const MAX_JARS: usize = 16;

/// Most hidden decoys a layout holds: the top of `hidden_decoys`' range.
pub const MAX_HIDDEN_DECOYS: usize = 3;

settings! {
    /// The seeded layout generator: jar population, hiding the target (and any decoys) and
    /// the corridors to them.
    pub struct LayoutConfig {
        /// Range of the number of jars, target included (an int n means exactly n).
        jar_count: [usize; 2] = [3, 7] => "jar_count" in Range::closed(1.0, MAX_JARS as f64),
        /// Probability that a non-target jar is round (else square).
        round_fraction: f64 = 0.5 => "round_fraction" in Range::UNIT,
        /// Shape of the target; 'any' draws it like the other jars.
        target_shape: TargetShape = TargetShape::Any => "target_shape" in Range::FINITE,
        /// Diameter range of round jars, m.
        round_diameter: [f64; 2] = [0.045, 0.055] => "round_diameter" in Range::LENGTH,
        /// Side range of square jars, m.
        square_side: [f64; 2] = [0.045, 0.050] => "square_side" in Range::LENGTH,
        /// Height range of every jar, m.
        jar_height: [f64; 2] = [0.10, 0.12] => "jar_height" in Range::LENGTH,
        /// Mass range of every jar, kg.
        jar_mass: [f64; 2] = [0.10, 0.20] => "jar_mass" in Range::PHYSICAL,
        /// Friction coefficient of the jars.
        jar_friction: f64 = 0.5 => "jar_friction" in Range::NON_NEGATIVE,
        /// Upper bound on the visible fraction of the target (and of each hidden decoy):
        /// visible silhouette pixels over silhouette pixels, both by ray casting through the
        /// depth camera's pixel grid.
        max_visible_fraction: f64 = 0.10 => "max_visible_fraction" in Range::UNIT,
        /// The centre of the target (and of each hidden decoy) is at least this deep (y), m.
        target_min_depth: f64 = 0.17 => "target_min_depth" in Range::NON_NEGATIVE_LENGTH,
        /// Non-target jars hidden like the target: each at least target_min_depth deep,
        /// behind its own occluder, at most max_visible_fraction visible and with its own
        /// corridor, so that neither the camera nor reachability tells the target from them.
        /// Each needs two jars (itself and its occluder): jar_count's low end must be at
        /// least 2 + 2 * hidden_decoys.
        hidden_decoys: usize = 0 => "hidden_decoys" in Range::closed(0.0, MAX_HIDDEN_DECOYS as f64),
        /// Minimum gap between the bounding circles of two jars, m.
        min_gap: f64 = 0.008 => "min_gap" in Range::NON_NEGATIVE_LENGTH,
        /// Minimum gap between a jar's bounding circle and a side or back wall, m.
        wall_gap: f64 = 0.008 => "wall_gap" in Range::NON_NEGATIVE_LENGTH,
        /// Width of the jar-free corridor from the opening to the side of the target (and of
        /// each hidden decoy), m.
        corridor_width: f64 = 0.07 => "corridor_width" in Range::LENGTH,
        /// Gap between a hidden jar's side and its corridor's inner edge, m.
        corridor_clearance: f64 = 0.005 => "corridor_clearance" in Range::NON_NEGATIVE_LENGTH,
        /// Attempts before the layout generator gives up.
        max_attempts: usize = 2000 => "max_attempts" in Range::AT_LEAST_ONE,
    }
    sections {}
    check_across = check_layout;
}

/// Every hidden jar (the target and each decoy) has its own occluder, so even the smallest
/// layout must hold two jars per hidden jar.
fn check_layout(c: &LayoutConfig) -> Result<(), SettingError> {
    let fewest = c.jar_count[0];
    let needed = 2 + 2 * c.hidden_decoys;
    if c.hidden_decoys > 0 && fewest < needed {
        return Err(SettingError::out_of_range(
            "hidden_decoys",
            format!(
                "at most {} for jar_count {:?}: the target and each hidden decoy need an \
                 occluder in front of them, so jar_count's low end must be at least \
                 2 + 2 * hidden_decoys ({needed})",
                fewest.saturating_sub(2) / 2,
                c.jar_count,
            ),
            c.hidden_decoys,
        ));
    }
    Ok(())
}

settings! {
    /// The depth camera: image, pose, slice and sensor noise.
    pub struct CameraConfig {
        /// Image width, px.
        image_width: usize = 160 => "camera_width" in Range::closed(1.0, 4096.0),
        /// Image height, px.
        image_height: usize = 120 => "camera_height" in Range::closed(1.0, 4096.0),
        /// Horizontal field of view, rad (square pixels, principal point at the centre).
        hfov: f64 = 80f64.to_radians() => "camera_hfov" in Range::open(0.0, PI),
        /// Focal length along x, px; None derives it from camera_hfov.
        fx: Option<f64> = None => "camera_fx" in Range::POSITIVE,
        /// Focal length along y, px; None derives it from camera_hfov.
        fy: Option<f64> = None => "camera_fy" in Range::POSITIVE,
        /// Principal point x, px; None puts it at the image centre.
        cx: Option<f64> = None => "camera_cx" in Range::FINITE,
        /// Principal point y, px; None puts it at the image centre.
        cy: Option<f64> = None => "camera_cy" in Range::FINITE,
        /// Optical centre in the world, m.
        position: [f64; 3] = [0.0, -0.25, 0.075] => "camera_position" in Range::COORDINATE,
        /// A point on the optical axis, m; the image's up is the world's +z.
        look_at: [f64; 3] = [0.0, 0.30, 0.075] => "camera_look_at" in Range::COORDINATE,
        /// Rays longer than this return no depth, m.
        max_range: f64 = 2.0 => "camera_max_range" in Range::LENGTH,
        /// Full thickness (z) of the band around the slice height kept for the 2D slice, m.
        slice_band: f64 = 0.01 => "slice_band" in Range::LENGTH,
        /// Standard deviation of the Gaussian noise added to each slice coordinate, m.
        noise_std: f64 = 0.002 => "depth_noise_std" in Range::NON_NEGATIVE_LENGTH,
        /// The slice is thinned (evenly, deterministically) to at most this many points.
        max_slice_points: usize = 256 => "max_slice_points" in Range::AT_LEAST_ONE,
    }
    sections {}
    check_across = |_| Ok(());
}

impl CameraConfig {
    /// The pinhole intrinsics: from the image size and field of view, with any explicit
    /// focal length or principal point put over them.
    pub fn intrinsics(&self) -> CameraIntrinsics {
        let derived = CameraIntrinsics::from_hfov(self.image_width, self.image_height, self.hfov);
        CameraIntrinsics {
            fx: self.fx.unwrap_or(derived.fx),
            fy: self.fy.unwrap_or(derived.fy),
            cx: self.cx.unwrap_or(derived.cx),
            cy: self.cy.unwrap_or(derived.cy),
            ..derived
        }
    }
}

settings! {
    /// The Exploratory Hand: kinematic wrist and arm, compliant finger.
    pub struct HandConfig {
        /// Start pose of the wrist (x, y, yaw); yaw = 0 points the finger along +y (into the
        /// cupboard). The default puts the fingertip just outside the opening.
        start: [f64; 3] = [0.0, -0.125, 0.0] => "hand_start" in Range::COORDINATE,
        /// Largest |dx| and |dy| of one command, m; larger commands are clipped.
        max_step_translation: f64 = 0.01 => "max_step_translation" in Range::LENGTH,
        /// Largest |dyaw| of one command, rad; larger commands are clipped.
        max_step_yaw: f64 = 0.1 => "max_step_yaw" in Range::left_open(0.0, PI),
        /// Wrist workspace (x_min, x_max, y_min, y_max), m; motion leaving it is stopped.
        workspace: [[f64; 2]; 2] = [[-0.45, 0.45], [-0.30, 0.30]] => "workspace" in Range::COORDINATE,
        /// Half side of the cubic wrist, m.
        wrist_half_extent: f64 = 0.015 => "wrist_half_extent" in Range::LENGTH,
        /// Length of the arm link behind the wrist, m.
        arm_length: f64 = 0.40 => "arm_length" in Range::LENGTH,
        /// Half width (and half height) of the arm link, m.
        arm_half_width: f64 = 0.012 => "arm_half_width" in Range::LENGTH,
        /// Finger length from the joint to the tip, m.
        finger_length: f64 = 0.10 => "finger_length" in Range::LENGTH,
        /// Half thickness of the finger in the slice plane, m.
        finger_half_thickness: f64 = 0.003 => "finger_half_thickness" in Range::LENGTH,
        /// Half height (z) of the finger, m.
        finger_half_height: f64 = 0.01 => "finger_half_height" in Range::LENGTH,
        /// Finger mass, kg: the rendered inertia, light because the deflection sensed while
        /// the wrist starts or stops is inertial (about 0.1 rad after a jump to the largest
        /// command at the defaults, gone within about 0.1 s); it scales with the square root
        /// of mass over stiffness.
        finger_mass: f64 = 0.005 => "finger_mass" in Range::PHYSICAL,
        /// Friction coefficient of the finger.
        finger_friction: f64 = 0.3 => "finger_friction" in Range::NON_NEGATIVE,
        /// Joint stiffness rendered by the finger motor, N m/rad. The contact force is
        /// stiffness times deflection over the lever (joint to contact); the default keeps it
        /// below what slides or tips a 0.1 kg jar for contacts beyond about a quarter of the
        /// finger.
        finger_stiffness: f64 = 0.02 => "finger_stiffness" in Range::PHYSICAL,
        /// Joint damping rendered by the finger motor, N m s/rad (the default is about 0.8 of
        /// critical for the default mass and stiffness).
        finger_damping: f64 = 0.0009 => "finger_damping" in Range::closed(0.0, 1e6),
        /// Joint limit: the finger deflects within (-limit, limit), rad.
        finger_limit: f64 = 1.2 => "finger_limit" in Range::open(0.0, PI),
        /// A rigid finger (welded to the wrist, no joint): the intrusive baseline.
        rigid_finger: bool = false => "rigid_finger" in Range::FINITE,
        /// Wrist and arm stop this far from a wall, m.
        wall_margin: f64 = 0.001 => "wall_margin" in Range::NON_NEGATIVE_LENGTH,
    }
    sections {}
    check_across = |_| Ok(());
}

settings! {
    /// Turning finger contacts into tactile readings.
    pub struct TouchConfig {
        /// Manifold points farther apart than this (predicted contacts) are dropped, m.
        max_distance: f64 = 5e-4 => "touch_max_distance" in Range::NON_NEGATIVE_LENGTH,
        /// Readings on one jar closer than this in the slice plane are merged, m.
        merge_distance: f64 = 1e-3 => "touch_merge_distance" in Range::NON_NEGATIVE_LENGTH,
        /// Standard deviation of the Gaussian noise on each contact coordinate, m.
        point_noise_std: f64 = 5e-4 => "touch_point_noise_std" in Range::NON_NEGATIVE_LENGTH,
        /// Standard deviation of the Gaussian rotation of each contact normal, rad.
        normal_noise_std: f64 = 0.02 => "touch_normal_noise_std" in Range::NON_NEGATIVE,
    }
    sections {}
    check_across = |_| Ok(());
}

settings! {
    /// Time stepping of the physics.
    pub struct PhysicsConfig {
        /// Physics time step, s; `dt` times `substeps` is the time one hand command takes (1/60 s
        /// at the defaults).
        dt: f64 = 1.0 / 120.0 => "dt" in Range::left_open(0.0, 0.02),
        /// Physics steps per hand command. Two of 1/120 s cost half of four of 1/240 s; a
        /// compliant finger sweeping along a jar then slides it about 0.1 mm instead of
        /// 0.02 mm (the scene's bound is 2 mm). The `physics_tradeoffs` example measures
        /// each choice.
        substeps: usize = 2 => "substeps" in Range::closed(1.0, 1000.0),
        /// Solver iterations per physics step (rapier runs each as a small substep of the
        /// velocity solve). Four keep every contact property the scene's tests check; eight
        /// halve a swept jar's slide at about 1.5 times the step's cost.
        solver_iterations: usize = 4 => "solver_iterations" in Range::closed(1.0, 100.0),
        /// Jars start asleep, where the layout placed them: a jar nothing touches costs no
        /// contact or solver work and cannot drift, and the first touch (finger, arm or
        /// another jar) wakes it. False simulates every jar from the first step.
        jars_start_asleep: bool = true => "jars_start_asleep" in Range::FINITE,
        /// Hand commands that provably touch nothing are made without stepping the physics:
        /// when no jar moves, the finger rests on its joint, no substep is blocked and, at
        /// every pose where a stepped command would look for contacts, the hand is farther
        /// than rapier's prediction distance (2 cm) from every jar (and the finger from every
        /// wall). Same wrist pose, steps and (empty) readings; the finger is carried
        /// undeflected instead of swinging from the wrist's starts and stops, which can, rarely,
        /// change how an episode goes on. Free motion then costs no physics steps. False steps
        /// every command.
        fast_free_motion: bool = true => "fast_free_motion" in Range::FINITE,
    }
    sections {}
    check_across = |_| Ok(());
}

settings! {
    /// The whole scene configuration.
    pub struct SceneConfig {
        /// Height (z) of the map plane: the camera slice and the hand live there, m.
        slice_height: f64 = 0.055 => "slice_height" in Range::LENGTH,
    }
    sections {
        /// The cupboard.
        cupboard: CupboardConfig,
        /// The layout generator.
        layout: LayoutConfig,
        /// The depth camera.
        camera: CameraConfig,
        /// The hand.
        hand: HandConfig,
        /// The tactile readings.
        touch: TouchConfig,
        /// The time stepping.
        physics: PhysicsConfig,
    }
    check_across = check_scene;
}

/// The slice must cut every jar, and the hand must clear the floor and the top there.
fn check_scene(c: &SceneConfig) -> Result<(), SettingError> {
    let slice = c.slice_height;
    let shortest_jar = c.layout.jar_height[0];
    if slice >= shortest_jar {
        return Err(SettingError::out_of_range(
            "slice_height",
            format!("below the shortest jar (jar_height low end {shortest_jar}) so the slice cuts every jar"),
            slice,
        ));
    }
    let h = &c.hand;
    let hand_half_height = h
        .wrist_half_extent
        .max(h.arm_half_width)
        .max(h.finger_half_height);
    if slice - hand_half_height <= 0.0 || slice + hand_half_height >= c.cupboard.height {
        return Err(SettingError::out_of_range(
            "slice_height",
            format!(
                "> {hand_half_height} and < cupboard_height - {hand_half_height} so the hand \
                 (half height {hand_half_height}) clears the floor and the top"
            ),
            slice,
        ));
    }
    Ok(())
}
