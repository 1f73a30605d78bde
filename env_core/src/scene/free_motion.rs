//! The fast path of free motion: a hand command that provably touches nothing is carried out
//! without stepping the physics (`fast_free_motion`, DESIGN.md §2).
//!
//! A stepped command runs `substeps` physics steps; rapier detects contacts at the start of
//! each, from the poses the hand has then (the start pose and the intermediate substep
//! targets), and keeps a contact point only within its prediction distance (2 cm at the
//! defaults). So when, at each of those poses, the wrist, the arm and the finger are farther
//! than that from every jar and the finger from every wall, the stepped command has no
//! contact at all: no touch reading, no impulse on a jar, no jar woken. If, besides, no body
//! moves (every jar asleep or at rest, the finger at rest relative to the wrist) and no
//! substep target is blocked, the only physics left is the hand's own motion, which the
//! scene then makes in one placement ([`super::hand::Hand::carry`]): the same wrist pose,
//! step count and (empty) readings as the stepped command.
//!
//! What it does not reproduce: the stepped wrist starts and stops with a jump in velocity,
//! which swings the compliant finger on its joint by up to ~0.15 rad in free space; the
//! carried finger stays at rest relative to the wrist. A finger that is already swinging or
//! deflected, and jars that move, are left to the physics. Cost: a handful of bounding-circle
//! tests per jar and pose, exact (parry, f32) distances only for parts near a jar or wall.

use rapier3d::parry::query;
use rapier3d::prelude::*;

use super::hand::{Hand, HandPose};

/// A jar moving slower than this (m/s) counts as at rest.
pub(crate) const REST_SPEED: f64 = 1e-3;
/// A jar turning slower than this (rad/s) counts as at rest.
pub(crate) const REST_TURN_RATE: f64 = 1e-2;
/// The finger counts as at rest within this deflection (rad): its tip 0.2 mm off.
pub(crate) const REST_ANGLE: f64 = 2e-3;
/// The finger counts as at rest turning slower than this relative to the wrist (rad/s): a
/// swing of at most ~3e-3 rad at its natural frequency (~35 rad/s), its tip within 0.3 mm,
/// below the touch noise (0.5 mm).
pub(crate) const REST_FINGER_RATE: f64 = 0.1;
/// Clearance added to rapier's prediction distance, m: far above the f32 rounding of the
/// distances (~1e-7 m), so a rounding never hides a contact.
const CLEARANCE_SLACK: f64 = 1e-4;

/// A jar as the free-motion test sees it.
#[derive(Debug, Clone, Copy)]
pub(crate) struct JarObstacle {
    /// Its body.
    pub body: RigidBodyHandle,
    /// Its collider.
    pub collider: ColliderHandle,
    /// Radius of its footprint's bounding circle, m.
    pub radius: f64,
}

/// Whether every jar is asleep or at rest. Cost: O(jars).
pub(crate) fn jars_at_rest(world: &PhysicsWorld, jars: &[JarObstacle]) -> bool {
    jars.iter().all(|jar| {
        let body = &world.bodies[jar.body];
        body.is_sleeping()
            || (f64::from(body.linvel().length()) <= REST_SPEED
                && f64::from(body.angvel().length()) <= REST_TURN_RATE)
    })
}

/// Whether the hand at wrist `pose`, the finger at `finger_angle`, is farther than rapier's
/// prediction distance from every jar (all parts) and every wall (the finger; the wrist and
/// the arm are kinematic and meet the fixed walls without contact forces, and their wall
/// clearance is [`Hand::blocker`]'s). Cost: 3 bounding-circle tests per jar, exact
/// distances for the near ones.
pub(crate) fn clear_at(
    world: &PhysicsWorld,
    hand: &Hand,
    jars: &[JarObstacle],
    pose: HandPose,
    finger_angle: f64,
) -> bool {
    let margin = f64::from(world.integration_parameters.prediction_distance()) + CLEARANCE_SLACK;
    for (part_pose, shape, is_finger, radius) in hand.parts(pose, finger_angle) {
        let centre = part_pose.translation;
        for jar in jars {
            let collider = &world.colliders[jar.collider];
            let at = collider.position();
            // A lower bound of the distance: the footprints' bounding circles in the plane.
            let gap = f64::from(centre.x - at.translation.x)
                .hypot(f64::from(centre.y - at.translation.y))
                - radius
                - jar.radius;
            if gap >= margin {
                continue;
            }
            let clear = query::distance(at, collider.shape(), &part_pose, shape)
                .is_ok_and(|d| f64::from(d.distance) >= margin);
            if !clear {
                return false;
            }
        }
        if is_finger && !hand.finger_clear_of_walls(&part_pose, pose.yaw + finger_angle, margin) {
            return false;
        }
    }
    true
}
