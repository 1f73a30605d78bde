//! The Exploratory Hand: a wrist moved kinematically in the slice plane `(x, y, yaw)`, an arm
//! link behind it reaching out of the cupboard (towards −y at yaw 0), and a long finger on a
//! revolute joint (about z, at the wrist's front face) whose motor renders a low stiffness
//! and damping, so contact deflects the finger instead of shoving the jar. The joint angle is
//! the sensed deflection.
//!
//! Hand frame: +y is forward (the finger's direction), so at yaw θ the finger points along
//! `(−sin θ, cos θ)`. Motions that would bring the wrist, the arm or the finger (at its current
//! deflection) closer than `wall_margin` to a cupboard wall, or take the wrist out of its
//! workspace, are stopped at the last clear pose along the motion (bisection on exact shape
//! distances) and reported. The finger is included because a finger driven end-on into a wall
//! cannot deflect, and the joint and the wall contact would fight.

use rapier3d::parry::query;
use rapier3d::prelude::*;

use super::config::HandConfig;
use super::cupboard::{Cupboard, Wall, WallBox};
use super::error::SceneError;
use super::groups;

/// Gap between the wrist's front face and the finger's joint, m (keeps the finger's root
/// clear of the wrist when it deflects).
const JOINT_GAP: f64 = 0.002;
/// Bisection steps when a motion is blocked (resolution 2⁻¹⁶ of the motion).
const BISECTION_STEPS: usize = 16;
/// A part whose bounding box is this much farther than the margin from a wall is clear of
/// it without the exact (f32) shape distance; far above that distance's rounding (~1e-8 m),
/// so the quick test never changes a decision.
const QUICK_CLEAR_SLACK: f64 = 1e-6;

/// Distance from the wrist's centre to the finger's joint along the finger's direction, m:
/// the wrist's half extent plus the gap that keeps the finger's root clear of it. Planners
/// and experiments read it from here (through the bindings), never as a constant of their own.
pub fn joint_offset(config: &HandConfig) -> f64 {
    config.wrist_half_extent + JOINT_GAP
}

/// Distance from the wrist's centre to the undeflected fingertip, m.
pub fn reach(config: &HandConfig) -> f64 {
    joint_offset(config) + config.finger_length
}

/// A wrist pose in the slice plane.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HandPose {
    /// x, m.
    pub x: f64,
    /// y, m.
    pub y: f64,
    /// Rotation about z, rad; 0 points the finger along +y.
    pub yaw: f64,
}

impl HandPose {
    fn lerp(&self, other: &Self, s: f64) -> Self {
        Self {
            x: self.x + s * (other.x - self.x),
            y: self.y + s * (other.y - self.y),
            yaw: self.yaw + s * (other.yaw - self.yaw),
        }
    }
}

/// What stopped a hand motion.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Blocker {
    /// The wrist or arm reached a cupboard wall.
    Wall(Wall),
    /// The wrist reached the edge of its workspace.
    Workspace,
}

impl Blocker {
    /// `"floor"`, `"back"`, `"left"`, `"right"`, `"top"` or `"workspace"`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Wall(wall) => wall.name(),
            Self::Workspace => "workspace",
        }
    }
}

/// The hand's bodies, joint and kinematic state inside a physics world.
#[derive(Debug, Clone)]
pub(crate) struct Hand {
    config: HandConfig,
    z: f64,
    wrist_body: RigidBodyHandle,
    finger_body: Option<RigidBodyHandle>,
    finger_collider: ColliderHandle,
    pose: HandPose,
    wrist_shape: Cuboid,
    arm_shape: Cuboid,
    finger_shape: Cuboid,
    arm_offset: f64,
    walls: Vec<(WallBox, Pose, Cuboid)>,
}

impl Hand {
    /// Inserts the hand at its configured start pose; fails if that pose is not clear of the
    /// walls or outside the workspace.
    pub(crate) fn insert(
        world: &mut PhysicsWorld,
        config: &HandConfig,
        z: f64,
        cupboard: &Cupboard,
    ) -> Result<Self, SceneError> {
        let [x, y, yaw] = config.start;
        let pose = HandPose { x, y, yaw };
        let w = config.wrist_half_extent;
        let arm_offset = -(w + 0.5 * config.arm_length);
        let walls = cupboard
            .walls()
            .iter()
            .map(|wall| (*wall, wall.pose(), wall.shape()))
            .collect();
        let wrist_shape = Cuboid::new(Vector::splat(w as Real));
        let arm_shape = Cuboid::new(Vector::new(
            config.arm_half_width as Real,
            (0.5 * config.arm_length) as Real,
            config.arm_half_width as Real,
        ));
        let wrist_pose = Self::body_pose(pose, z);
        let wrist_body = world.insert_body(
            RigidBodyBuilder::kinematic_position_based()
                .pose(wrist_pose)
                .can_sleep(false),
        );
        let hand_collider = |shape: Cuboid, offset: f64| {
            ColliderBuilder::new(SharedShape::new(shape))
                .translation(Vector::new(0.0, offset as Real, 0.0))
                .friction(0.5)
                .collision_groups(groups::HAND)
                .user_data(0)
        };
        world.insert_collider(hand_collider(wrist_shape, 0.0), Some(wrist_body));
        world.insert_collider(hand_collider(arm_shape, arm_offset), Some(wrist_body));

        let joint_y = joint_offset(config);
        let l = config.finger_length;
        let finger_builder = ColliderBuilder::cuboid(
            config.finger_half_thickness as Real,
            (0.5 * l) as Real,
            config.finger_half_height as Real,
        )
        .friction(config.finger_friction as Real)
        .restitution(0.0)
        .collision_groups(groups::FINGER)
        .user_data(0);
        let (finger_body, finger_collider) = if config.rigid_finger {
            let collider = world.insert_collider(
                finger_builder
                    .translation(Vector::new(0.0, (joint_y + 0.5 * l) as Real, 0.0))
                    .mass(config.finger_mass as Real),
                Some(wrist_body),
            );
            (None, collider)
        } else {
            let finger_pose = wrist_pose * Pose::translation(0.0, joint_y as Real, 0.0);
            let body = world.insert_body(
                RigidBodyBuilder::dynamic()
                    .pose(finger_pose)
                    .gravity_scale(0.0)
                    .can_sleep(false),
            );
            let collider = world.insert_collider(
                finger_builder
                    .translation(Vector::new(0.0, (0.5 * l) as Real, 0.0))
                    .mass(config.finger_mass as Real),
                Some(body),
            );
            let joint = RevoluteJointBuilder::new(Vector::Z)
                .local_anchor1(Vector::new(0.0, joint_y as Real, 0.0))
                .local_anchor2(Vector::ZERO)
                .motor_model(MotorModel::ForceBased)
                .motor_position(
                    0.0,
                    config.finger_stiffness as Real,
                    config.finger_damping as Real,
                )
                .limits([-config.finger_limit as Real, config.finger_limit as Real])
                .contacts_enabled(false);
            world.insert_impulse_joint(wrist_body, body, joint);
            (Some(body), collider)
        };
        let hand = Self {
            config: config.clone(),
            z,
            wrist_body,
            finger_body,
            finger_collider,
            pose,
            wrist_shape,
            arm_shape,
            finger_shape: Cuboid::new(Vector::new(
                config.finger_half_thickness as Real,
                (0.5 * l) as Real,
                config.finger_half_height as Real,
            )),
            arm_offset,
            walls,
        };
        if hand.blocker(pose, 0.0).is_some() {
            return Err(SceneError::HandStartBlocked { x, y, yaw });
        }
        Ok(hand)
    }

    fn body_pose(pose: HandPose, z: f64) -> Pose {
        Pose::from_parts(
            Vector::new(pose.x as Real, pose.y as Real, z as Real),
            Rotation::from_rotation_z(pose.yaw as Real),
        )
    }

    /// What would block the wrist, the arm or the finger (held at deflection
    /// `finger_angle`) at `pose`, if anything. Each part is first tested by its bounding box
    /// (exact f64, a lower bound of the distance); only a part whose box comes within the
    /// margin of a wall gets the exact box distance. Cost: 15 box-box gaps, plus up to 15
    /// exact distances near walls.
    pub(crate) fn blocker(&self, pose: HandPose, finger_angle: f64) -> Option<Blocker> {
        let [[x0, x1], [y0, y1]] = self.config.workspace;
        if !(x0..=x1).contains(&pose.x) || !(y0..=y1).contains(&pose.y) {
            return Some(Blocker::Workspace);
        }
        let c = &self.config;
        let finger_yaw = pose.yaw + finger_angle;
        let along = |yaw: f64, length: f64| [-length * yaw.sin(), length * yaw.cos()];
        let arm_centre = along(pose.yaw, self.arm_offset);
        let joint = along(pose.yaw, self.joint_y());
        let finger_mid = along(finger_yaw, 0.5 * c.finger_length);
        let w = c.wrist_half_extent;
        // (centre offset from the wrist in the plane, yaw, half extents) of each part.
        let parts = [
            ([0.0, 0.0], pose.yaw, [w, w, w], &self.wrist_shape),
            (
                arm_centre,
                pose.yaw,
                [c.arm_half_width, 0.5 * c.arm_length, c.arm_half_width],
                &self.arm_shape,
            ),
            (
                [joint[0] + finger_mid[0], joint[1] + finger_mid[1]],
                finger_yaw,
                self.finger_half_extents(),
                &self.finger_shape,
            ),
        ];
        let exact_poses = self.part_poses(pose, finger_angle);
        let margin = c.wall_margin;
        for wall in &self.walls {
            for ((offset, yaw, half, shape), part_pose) in parts.iter().zip(&exact_poses) {
                let centre = [pose.x + offset[0], pose.y + offset[1], self.z];
                if !clear_of_wall(wall, (centre, *yaw, *half), part_pose, shape, margin) {
                    return Some(Blocker::Wall(wall.0.wall));
                }
            }
        }
        None
    }

    /// The finger's half extents (across, along, up), m.
    fn finger_half_extents(&self) -> [f64; 3] {
        let c = &self.config;
        [
            c.finger_half_thickness,
            0.5 * c.finger_length,
            c.finger_half_height,
        ]
    }

    /// The world poses of the wrist, the arm and the finger (held at deflection
    /// `finger_angle`) at wrist `pose`, composed in f32 as the bodies are. Cost: O(1).
    fn part_poses(&self, pose: HandPose, finger_angle: f64) -> [Pose; 3] {
        let wrist = Self::body_pose(pose, self.z);
        [
            wrist,
            wrist * Pose::translation(0.0, self.arm_offset as Real, 0.0),
            wrist
                * Pose::translation(0.0, self.joint_y() as Real, 0.0)
                * Pose::from_rotation(Rotation::from_rotation_z(finger_angle as Real))
                * Pose::translation(0.0, (0.5 * self.config.finger_length) as Real, 0.0),
        ]
    }

    /// The hand's parts at wrist `pose` with the finger at `finger_angle`: each part's world
    /// pose and shape, whether it is the finger, and the radius of its footprint's bounding
    /// circle in the slice plane (m). Cost: O(1).
    pub(crate) fn parts(
        &self,
        pose: HandPose,
        finger_angle: f64,
    ) -> [(Pose, &Cuboid, bool, f64); 3] {
        let [wrist, arm, finger] = self.part_poses(pose, finger_angle);
        let radius = |shape: &Cuboid| {
            let h = shape.half_extents;
            f64::from(h.x).hypot(f64::from(h.y))
        };
        [
            (wrist, &self.wrist_shape, false, radius(&self.wrist_shape)),
            (arm, &self.arm_shape, false, radius(&self.arm_shape)),
            (finger, &self.finger_shape, true, radius(&self.finger_shape)),
        ]
    }

    /// Whether the finger at `pose` (held at `finger_angle`) is at least `margin` from every
    /// cupboard wall (the same test as [`Self::blocker`]'s, [`clear_of_wall`]). Cost: 5
    /// box-box gaps, plus an exact distance per near wall.
    pub(crate) fn finger_clear_of_walls(
        &self,
        finger_pose: &Pose,
        finger_yaw: f64,
        margin: f64,
    ) -> bool {
        let t = finger_pose.translation;
        let centre = [f64::from(t.x), f64::from(t.y), f64::from(t.z)];
        let bounds = (centre, finger_yaw, self.finger_half_extents());
        self.walls
            .iter()
            .all(|wall| clear_of_wall(wall, bounds, finger_pose, &self.finger_shape, margin))
    }

    /// Whether the finger is at rest relative to the wrist: deflected by at most
    /// `max_angle` (rad) and turning relative to the wrist by at most `max_rate` (rad/s).
    /// Always true for a rigid finger. Cost: O(1).
    pub(crate) fn finger_at_rest(
        &self,
        world: &PhysicsWorld,
        max_angle: f64,
        max_rate: f64,
    ) -> bool {
        let Some(finger) = self.finger_body.and_then(|h| world.bodies.get(h)) else {
            return true;
        };
        let Some(wrist) = world.bodies.get(self.wrist_body) else {
            return true;
        };
        let rate = f64::from(finger.angvel().z) - f64::from(wrist.angvel().z);
        self.finger_angle(world).abs() <= max_angle && rate.abs() <= max_rate
    }

    /// Carries the hand to `target` without physics: the wrist and the finger (keeping its
    /// pose relative to the wrist) are placed there, moving rigidly at the velocity of the
    /// motion from the current pose over `duration` seconds, as the bodies of a motion that
    /// touched nothing end it. For motions [`super::free_motion`] found clear only. Cost: O(1).
    pub(crate) fn carry(&mut self, world: &mut PhysicsWorld, target: HandPose, duration: f64) {
        let start = self.pose;
        let Some(old_wrist) = world.bodies.get(self.wrist_body).map(|b| *b.position()) else {
            return;
        };
        let new_wrist = Self::body_pose(target, self.z);
        let linvel = Vector::new(
            ((target.x - start.x) / duration) as Real,
            ((target.y - start.y) / duration) as Real,
            0.0,
        );
        let angvel = Vector::new(0.0, 0.0, ((target.yaw - start.yaw) / duration) as Real);
        let origin = new_wrist.translation;
        // A rigid motion's velocity at a body's centre of mass.
        let rigid = |body: &mut RigidBody, pose: Pose| {
            body.set_position(pose, true);
            let at_com = linvel + angvel.cross(body.center_of_mass() - origin);
            body.set_linvel(at_com, true);
            body.set_angvel(angvel, true);
        };
        if let Some(finger) = self.finger_body.and_then(|h| world.bodies.get_mut(h)) {
            let relative = old_wrist.inverse() * *finger.position();
            rigid(finger, new_wrist * relative);
        }
        if let Some(wrist) = world.bodies.get_mut(self.wrist_body) {
            rigid(wrist, new_wrist);
        }
        self.pose = target;
    }

    /// Moves the wrist towards `target` for the next physics step, stopping at the last clear
    /// pose if the motion is blocked; returns the blocker. Cost: ≤ 17 clearance checks.
    pub(crate) fn advance(
        &mut self,
        world: &mut PhysicsWorld,
        target: HandPose,
    ) -> Option<Blocker> {
        let start = self.pose;
        let angle = self.finger_angle(world);
        let blocked = self.blocker(target, angle);
        let reached = match blocked {
            None => target,
            Some(_) => {
                let (mut lo, mut hi) = (0.0, 1.0);
                for _ in 0..BISECTION_STEPS {
                    let mid = 0.5 * (lo + hi);
                    if self.blocker(start.lerp(&target, mid), angle).is_none() {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                start.lerp(&target, lo)
            }
        };
        self.pose = reached;
        if let Some(body) = world.bodies.get_mut(self.wrist_body) {
            body.set_next_kinematic_position(Self::body_pose(reached, self.z));
        }
        blocked
    }

    fn joint_y(&self) -> f64 {
        joint_offset(&self.config)
    }

    /// The commanded wrist pose.
    pub(crate) fn pose(&self) -> HandPose {
        self.pose
    }

    /// The finger's collider.
    pub(crate) fn finger_collider(&self) -> ColliderHandle {
        self.finger_collider
    }

    /// Finger deflection: the joint angle (finger yaw relative to the wrist), rad, in
    /// `[−π, π]`; always 0 for a rigid finger.
    pub(crate) fn finger_angle(&self, world: &PhysicsWorld) -> f64 {
        let Some(finger) = self.finger_body.and_then(|h| world.bodies.get(h)) else {
            return 0.0;
        };
        let Some(wrist) = world.bodies.get(self.wrist_body) else {
            return 0.0;
        };
        let relative = wrist.rotation().inverse() * *finger.rotation();
        let angle = 2.0 * f64::from(relative.z).atan2(f64::from(relative.w));
        (angle + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI
    }

    /// The finger's world pose as `(x, y, yaw)` of its joint (equal to the wrist's front for a
    /// rigid finger).
    pub(crate) fn finger_pose(&self, world: &PhysicsWorld) -> HandPose {
        let joint_y = self.joint_y();
        let (s, c) = self.pose.yaw.sin_cos();
        HandPose {
            x: self.pose.x - s * joint_y,
            y: self.pose.y + c * joint_y,
            yaw: self.pose.yaw + self.finger_angle(world),
        }
    }
}

/// Whether a part of the hand is at least `margin` from a wall: first the gap to its
/// bounding box (`bounds`: centre, yaw about z, half extents; exact f64 and a lower bound of
/// the distance, see [`box_gap`]), then, only when that gap is within the margin, the exact
/// distance of its `shape` at `part_pose`. Cost: O(1), one parry distance at most.
fn clear_of_wall(
    (wall, wall_pose, wall_shape): &(WallBox, Pose, Cuboid),
    (centre, yaw, half): ([f64; 3], f64, [f64; 3]),
    part_pose: &Pose,
    shape: &Cuboid,
    margin: f64,
) -> bool {
    box_gap(wall, centre, yaw, half) >= margin + QUICK_CLEAR_SLACK
        || query::distance(wall_pose, wall_shape, part_pose, shape)
            .is_ok_and(|d| f64::from(d.distance) >= margin)
}

/// Distance between an axis-aligned wall slab and the bounding box of a box with half
/// extents `half` centred at `centre` and turned by `yaw` about z (0 when they overlap): a
/// lower bound of the distance between the wall and the box itself. Cost: O(1), f64.
fn box_gap(wall: &WallBox, centre: [f64; 3], yaw: f64, half: [f64; 3]) -> f64 {
    let (s, c) = yaw.sin_cos();
    let reach = [
        c.abs() * half[0] + s.abs() * half[1],
        s.abs() * half[0] + c.abs() * half[1],
        half[2],
    ];
    (0..3)
        .map(|i| {
            let gap = (centre[i] - wall.centre[i]).abs() - reach[i] - wall.half_extents[i];
            gap.max(0.0).powi(2)
        })
        .sum::<f64>()
        .sqrt()
}
