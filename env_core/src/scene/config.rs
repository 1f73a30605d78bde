//! Every tunable number of the cupboard scene, with defaults from the design notes (§2) and
//! one `validate` that checks them all before anything is built.
//!
//! Units are SI (metres, kilograms, seconds, radians), z up; the cupboard's open front is the
//! plane y = 0 and its interior is centred on x = 0.

use super::depth_camera::CameraIntrinsics;
use super::error::SceneError;

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

impl TargetShape {
    /// Parses `"round"`, `"square"` or `"any"`.
    pub fn parse(text: &str) -> Result<Self, SceneError> {
        match text {
            "round" => Ok(Self::Round),
            "square" => Ok(Self::Square),
            "any" => Ok(Self::Any),
            _ => Err(SceneError::UnknownChoice {
                what: "target_shape",
                expected: "'round', 'square' or 'any'",
                value: text.to_owned(),
            }),
        }
    }

    /// The name [`Self::parse`] accepts.
    pub fn name(self) -> &'static str {
        match self {
            Self::Round => "round",
            Self::Square => "square",
            Self::Any => "any",
        }
    }
}

/// The shelf compartment: interior size and wall material.
#[derive(Debug, Clone, PartialEq)]
pub struct CupboardConfig {
    /// Interior width along x (centred on x = 0), m.
    pub width: f64,
    /// Interior depth along y (open front at y = 0), m.
    pub depth: f64,
    /// Interior height along z (floor top at z = 0), m.
    pub height: f64,
    /// Thickness of floor, back, side walls and top, m. Thick walls keep a fast hand from
    /// tunnelling.
    pub wall_thickness: f64,
    /// Friction coefficient of the walls.
    pub friction: f64,
}

impl Default for CupboardConfig {
    fn default() -> Self {
        Self {
            width: 0.60,
            depth: 0.30,
            height: 0.30,
            wall_thickness: 0.05,
            friction: 0.5,
        }
    }
}

/// The seeded layout generator: jar population, target hiding and the corridor to it.
#[derive(Debug, Clone, PartialEq)]
pub struct LayoutConfig {
    /// Inclusive range of the number of jars (target included), within 3..=7.
    pub jar_count: [usize; 2],
    /// Probability that a non-target jar is round (else square).
    pub round_fraction: f64,
    /// Shape of the target.
    pub target_shape: TargetShape,
    /// Diameter range of round jars, m.
    pub round_diameter: [f64; 2],
    /// Side range of square jars, m.
    pub square_side: [f64; 2],
    /// Height range of every jar, m.
    pub jar_height: [f64; 2],
    /// Mass range of every jar, kg.
    pub jar_mass: [f64; 2],
    /// Friction coefficient of the jars.
    pub jar_friction: f64,
    /// Upper bound on the target's visible fraction: visible silhouette pixels over
    /// silhouette pixels, both by ray casting through the depth camera's pixel grid.
    pub max_visible_fraction: f64,
    /// The target's centre is at least this deep (y), m.
    pub target_min_depth: f64,
    /// Minimum gap between the bounding circles of two jars, m.
    pub min_gap: f64,
    /// Minimum gap between a jar's bounding circle and a side or back wall, m.
    pub wall_gap: f64,
    /// Width of the jar-free corridor from the opening to the target's side, m.
    pub corridor_width: f64,
    /// Gap between the target's side and the corridor's inner edge, m.
    pub corridor_clearance: f64,
    /// Attempts before the generator gives up with [`SceneError::LayoutNotFound`].
    pub max_attempts: usize,
}

impl Default for LayoutConfig {
    fn default() -> Self {
        Self {
            jar_count: [3, 7],
            round_fraction: 0.5,
            target_shape: TargetShape::Any,
            round_diameter: [0.045, 0.055],
            square_side: [0.045, 0.050],
            jar_height: [0.10, 0.12],
            jar_mass: [0.10, 0.20],
            jar_friction: 0.5,
            max_visible_fraction: 0.10,
            target_min_depth: 0.17,
            min_gap: 0.008,
            wall_gap: 0.008,
            corridor_width: 0.07,
            corridor_clearance: 0.005,
            max_attempts: 2000,
        }
    }
}

/// The depth camera: intrinsics, pose, slice and sensor noise.
#[derive(Debug, Clone, PartialEq)]
pub struct CameraConfig {
    /// Pinhole intrinsics.
    pub intrinsics: CameraIntrinsics,
    /// Optical centre in the world, m.
    pub position: [f64; 3],
    /// A point on the optical axis; the image's up is the world's +z.
    pub look_at: [f64; 3],
    /// Rays longer than this return no depth, m.
    pub max_range: f64,
    /// Full thickness (z) of the band around the slice height kept for the 2D slice, m.
    pub slice_band: f64,
    /// Standard deviation of the Gaussian noise added to each slice coordinate, m.
    pub noise_std: f64,
    /// The slice is thinned (evenly, deterministically) to at most this many points.
    pub max_slice_points: usize,
}

impl Default for CameraConfig {
    fn default() -> Self {
        Self {
            intrinsics: CameraIntrinsics::from_hfov(160, 120, 80f64.to_radians()),
            position: [0.0, -0.25, 0.075],
            look_at: [0.0, 0.30, 0.075],
            max_range: 2.0,
            slice_band: 0.01,
            noise_std: 0.002,
            max_slice_points: 256,
        }
    }
}

/// The Exploratory Hand: kinematic wrist and arm, compliant finger.
#[derive(Debug, Clone, PartialEq)]
pub struct HandConfig {
    /// Start pose of the wrist `(x, y, yaw)`; yaw = 0 points the finger along +y (into the
    /// cupboard). The default puts the fingertip just outside the opening.
    pub start: [f64; 3],
    /// Largest |dx| and |dy| of one command, m; larger commands are clipped.
    pub max_step_translation: f64,
    /// Largest |dyaw| of one command, rad; larger commands are clipped.
    pub max_step_yaw: f64,
    /// Wrist workspace `[[x_min, x_max], [y_min, y_max]]`; motion leaving it is stopped.
    pub workspace: [[f64; 2]; 2],
    /// Half side of the cubic wrist, m.
    pub wrist_half_extent: f64,
    /// Length of the arm link behind the wrist, m.
    pub arm_length: f64,
    /// Half width (and half height) of the arm link, m.
    pub arm_half_width: f64,
    /// Finger length from the joint to the tip, m.
    pub finger_length: f64,
    /// Half thickness of the finger in the slice plane, m.
    pub finger_half_thickness: f64,
    /// Half height (z) of the finger, m.
    pub finger_half_height: f64,
    /// Finger mass, kg: the *rendered* inertia, light because the deflection sensed while
    /// the wrist starts or stops is inertial (about 0.1 rad after a jump to the maximum
    /// command at the defaults, gone within ~0.1 s); it scales with the square root of
    /// mass / stiffness.
    pub finger_mass: f64,
    /// Friction coefficient of the finger.
    pub finger_friction: f64,
    /// Joint stiffness rendered by the finger motor, N·m/rad. The contact force is
    /// `stiffness · deflection / lever` (lever: joint to contact), so it grows as a contact
    /// slides towards the joint; the default keeps it below what slides or tips a 0.1 kg jar
    /// for contacts beyond about a quarter of the finger.
    pub finger_stiffness: f64,
    /// Joint damping rendered by the finger motor, N·m·s/rad (the default is about 0.8 of
    /// critical for the default mass and stiffness).
    pub finger_damping: f64,
    /// Joint limit: the finger deflects within `[-limit, limit]`, rad.
    pub finger_limit: f64,
    /// A rigid finger (welded to the wrist, no joint): the intrusive baseline.
    pub rigid_finger: bool,
    /// Wrist and arm stop this far from a wall, m.
    pub wall_margin: f64,
}

impl Default for HandConfig {
    fn default() -> Self {
        Self {
            start: [0.0, -0.125, 0.0],
            max_step_translation: 0.01,
            max_step_yaw: 0.1,
            workspace: [[-0.45, 0.45], [-0.30, 0.30]],
            wrist_half_extent: 0.015,
            arm_length: 0.40,
            arm_half_width: 0.012,
            finger_length: 0.10,
            finger_half_thickness: 0.003,
            finger_half_height: 0.01,
            finger_mass: 0.005,
            finger_friction: 0.3,
            finger_stiffness: 0.02,
            finger_damping: 0.0009,
            finger_limit: 1.2,
            rigid_finger: false,
            wall_margin: 0.001,
        }
    }
}

/// Turning finger contacts into tactile readings.
#[derive(Debug, Clone, PartialEq)]
pub struct TouchConfig {
    /// Manifold points farther apart than this (predicted contacts) are dropped, m.
    pub max_distance: f64,
    /// Readings on one jar closer than this in the slice plane are merged, m.
    pub merge_distance: f64,
    /// Standard deviation of the Gaussian noise on each contact coordinate, m.
    pub point_noise_std: f64,
    /// Standard deviation of the Gaussian rotation of each normal, rad.
    pub normal_noise_std: f64,
}

impl Default for TouchConfig {
    fn default() -> Self {
        Self {
            max_distance: 5e-4,
            merge_distance: 1e-3,
            point_noise_std: 5e-4,
            normal_noise_std: 0.02,
        }
    }
}

/// Time stepping of the physics.
#[derive(Debug, Clone, PartialEq)]
pub struct PhysicsConfig {
    /// Physics time step, s.
    pub dt: f64,
    /// Physics steps per hand command.
    pub substeps: usize,
    /// Solver iterations per physics step.
    pub solver_iterations: usize,
}

impl Default for PhysicsConfig {
    fn default() -> Self {
        Self {
            dt: 1.0 / 240.0,
            substeps: 4,
            solver_iterations: 8,
        }
    }
}

/// The whole scene configuration.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneConfig {
    /// Height (z) of the map plane: the camera slice and the hand live there, m.
    pub slice_height: f64,
    /// The cupboard.
    pub cupboard: CupboardConfig,
    /// The layout generator.
    pub layout: LayoutConfig,
    /// The depth camera.
    pub camera: CameraConfig,
    /// The hand.
    pub hand: HandConfig,
    /// The tactile readings.
    pub touch: TouchConfig,
    /// The time stepping.
    pub physics: PhysicsConfig,
}

impl Default for SceneConfig {
    fn default() -> Self {
        Self {
            slice_height: 0.055,
            cupboard: CupboardConfig::default(),
            layout: LayoutConfig::default(),
            camera: CameraConfig::default(),
            hand: HandConfig::default(),
            touch: TouchConfig::default(),
            physics: PhysicsConfig::default(),
        }
    }
}

fn finite(what: &'static str, value: f64) -> Result<(), SceneError> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(SceneError::NonFinite { what, value })
    }
}

fn positive(what: &'static str, value: f64) -> Result<(), SceneError> {
    finite(what, value)?;
    if value > 0.0 {
        Ok(())
    } else {
        Err(SceneError::OutOfRange {
            what,
            expected: "(0, inf)",
            value,
        })
    }
}

fn non_negative(what: &'static str, value: f64) -> Result<(), SceneError> {
    finite(what, value)?;
    if value >= 0.0 {
        Ok(())
    } else {
        Err(SceneError::OutOfRange {
            what,
            expected: "[0, inf)",
            value,
        })
    }
}

fn unit_interval(what: &'static str, value: f64) -> Result<(), SceneError> {
    finite(what, value)?;
    if (0.0..=1.0).contains(&value) {
        Ok(())
    } else {
        Err(SceneError::OutOfRange {
            what,
            expected: "[0, 1]",
            value,
        })
    }
}

fn positive_range(what: &'static str, range: [f64; 2]) -> Result<(), SceneError> {
    let [low, high] = range;
    if low.is_finite() && high.is_finite() && low > 0.0 && low <= high {
        Ok(())
    } else {
        Err(SceneError::InvalidRange {
            what,
            expected: "finite positive ends",
            low,
            high,
        })
    }
}

fn count(
    what: &'static str,
    value: usize,
    low: usize,
    high: usize,
    text: &'static str,
) -> Result<(), SceneError> {
    if (low..=high).contains(&value) {
        Ok(())
    } else {
        Err(SceneError::CountOutOfRange {
            what,
            expected: text,
            value,
        })
    }
}

impl SceneConfig {
    /// Checks every parameter; the first bad one is reported. Cost: O(1).
    pub fn validate(&self) -> Result<(), SceneError> {
        positive("slice_height", self.slice_height)?;

        let c = &self.cupboard;
        positive("cupboard.width", c.width)?;
        positive("cupboard.depth", c.depth)?;
        positive("cupboard.height", c.height)?;
        positive("cupboard.wall_thickness", c.wall_thickness)?;
        non_negative("cupboard.friction", c.friction)?;
        if self.slice_height >= c.height {
            return Err(SceneError::OutOfRange {
                what: "slice_height",
                expected: "(0, cupboard.height)",
                value: self.slice_height,
            });
        }

        let l = &self.layout;
        let [lo, hi] = l.jar_count;
        count("jar_count low", lo, 1, 7, "[1, 7]")?;
        count("jar_count high", hi, lo, 7, "[jar_count low, 7]")?;
        unit_interval("round_fraction", l.round_fraction)?;
        positive_range("round_diameter", l.round_diameter)?;
        positive_range("square_side", l.square_side)?;
        positive_range("jar_height", l.jar_height)?;
        positive_range("jar_mass", l.jar_mass)?;
        non_negative("jar_friction", l.jar_friction)?;
        unit_interval("max_visible_fraction", l.max_visible_fraction)?;
        non_negative("target_min_depth", l.target_min_depth)?;
        non_negative("min_gap", l.min_gap)?;
        non_negative("wall_gap", l.wall_gap)?;
        positive("corridor_width", l.corridor_width)?;
        non_negative("corridor_clearance", l.corridor_clearance)?;
        count("max_attempts", l.max_attempts, 1, usize::MAX, "[1, inf)")?;
        if l.jar_height[0] <= self.slice_height {
            return Err(SceneError::OutOfRange {
                what: "slice_height",
                expected: "(0, shortest jar height) so the slice cuts every jar",
                value: self.slice_height,
            });
        }

        let cam = &self.camera;
        cam.intrinsics.validate()?;
        for (i, v) in cam.position.iter().chain(cam.look_at.iter()).enumerate() {
            finite(
                if i < 3 {
                    "camera position"
                } else {
                    "camera look_at"
                },
                *v,
            )?;
        }
        positive("camera max_range", cam.max_range)?;
        positive("slice_band", cam.slice_band)?;
        non_negative("depth noise_std", cam.noise_std)?;
        count(
            "max_slice_points",
            cam.max_slice_points,
            1,
            usize::MAX,
            "[1, inf)",
        )?;

        let h = &self.hand;
        for v in h.start {
            finite("hand start", v)?;
        }
        positive("max_step_translation", h.max_step_translation)?;
        positive("max_step_yaw", h.max_step_yaw)?;
        for (axis, [a, b]) in [
            ("workspace x", h.workspace[0]),
            ("workspace y", h.workspace[1]),
        ] {
            if !(a.is_finite() && b.is_finite() && a < b) {
                return Err(SceneError::InvalidRange {
                    what: axis,
                    expected: "finite ends",
                    low: a,
                    high: b,
                });
            }
        }
        positive("wrist_half_extent", h.wrist_half_extent)?;
        positive("arm_length", h.arm_length)?;
        positive("arm_half_width", h.arm_half_width)?;
        positive("finger_length", h.finger_length)?;
        positive("finger_half_thickness", h.finger_half_thickness)?;
        positive("finger_half_height", h.finger_half_height)?;
        positive("finger_mass", h.finger_mass)?;
        non_negative("finger_friction", h.finger_friction)?;
        positive("finger_stiffness", h.finger_stiffness)?;
        non_negative("finger_damping", h.finger_damping)?;
        finite("finger_limit", h.finger_limit)?;
        if !(h.finger_limit > 0.0 && h.finger_limit < std::f64::consts::PI) {
            return Err(SceneError::OutOfRange {
                what: "finger_limit",
                expected: "(0, pi)",
                value: h.finger_limit,
            });
        }
        non_negative("wall_margin", h.wall_margin)?;
        let hand_half_height = h
            .wrist_half_extent
            .max(h.arm_half_width)
            .max(h.finger_half_height);
        if self.slice_height - hand_half_height <= 0.0
            || self.slice_height + hand_half_height >= c.height
        {
            return Err(SceneError::OutOfRange {
                what: "slice_height",
                expected: "a height where the hand clears the floor and the top",
                value: self.slice_height,
            });
        }

        let t = &self.touch;
        non_negative("touch max_distance", t.max_distance)?;
        non_negative("touch merge_distance", t.merge_distance)?;
        non_negative("touch point_noise_std", t.point_noise_std)?;
        non_negative("touch normal_noise_std", t.normal_noise_std)?;

        let p = &self.physics;
        positive("dt", p.dt)?;
        if p.dt > 0.02 {
            return Err(SceneError::OutOfRange {
                what: "dt",
                expected: "(0, 0.02] s (larger steps make the light finger unstable)",
                value: p.dt,
            });
        }
        count("substeps", p.substeps, 1, 1000, "[1, 1000]")?;
        count("solver_iterations", p.solver_iterations, 1, 100, "[1, 100]")?;
        Ok(())
    }
}
