//! A spice jar: its shape (round = cylinder, square = cuboid), size, mass and resting pose,
//! and how it becomes a dynamic rapier body standing upright on the shelf floor (z = 0).

use rapier3d::prelude::*;

use super::footprint::{Footprint, JarShape};
use super::groups;

/// One jar of a layout: shape, size, mass and its resting pose on the floor.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JarSpec {
    /// Cross-section.
    pub shape: JarShape,
    /// Height, m.
    pub height: f64,
    /// Mass, kg.
    pub mass: f64,
    /// Centre x, m.
    pub x: f64,
    /// Centre y, m.
    pub y: f64,
    /// Rotation about z, rad (only matters for square jars).
    pub yaw: f64,
}

impl JarSpec {
    /// Half the extent of the footprint along x at this yaw, m.
    pub fn half_extent_x(&self) -> f64 {
        match self.shape {
            JarShape::Round { radius } => radius,
            JarShape::Square { half_side } => {
                half_side * (self.yaw.cos().abs() + self.yaw.sin().abs())
            }
        }
    }

    /// The body pose at rest: centre at half height, rotated by yaw about z.
    pub fn body_pose(&self) -> Pose {
        Pose::from_parts(
            Vector::new(self.x as Real, self.y as Real, (0.5 * self.height) as Real),
            Rotation::from_rotation_z(self.yaw as Real),
        )
    }

    /// The collider's pose relative to its body. parry's cylinder axis is local y; a quarter
    /// turn about x stands it along world z.
    pub fn collider_offset(&self) -> Pose {
        match self.shape {
            JarShape::Round { .. } => {
                Pose::from_rotation(Rotation::from_rotation_x(std::f32::consts::FRAC_PI_2))
            }
            JarShape::Square { .. } => Pose::IDENTITY,
        }
    }

    /// The collision shape (in collider-local coordinates, see [`Self::collider_offset`]).
    pub fn shared_shape(&self) -> SharedShape {
        let half_height = (0.5 * self.height) as Real;
        match self.shape {
            JarShape::Round { radius } => SharedShape::cylinder(half_height, radius as Real),
            JarShape::Square { half_side } => {
                let h = half_side as Real;
                SharedShape::cuboid(h, h, half_height)
            }
        }
    }

    /// Inserts the jar as a dynamic body with one collider tagged `user_data = index + 1`;
    /// returns the body and collider handles.
    pub(crate) fn insert(
        &self,
        world: &mut PhysicsWorld,
        index: usize,
        friction: f64,
    ) -> (RigidBodyHandle, ColliderHandle) {
        let body = RigidBodyBuilder::dynamic().pose(self.body_pose());
        let collider = ColliderBuilder::new(self.shared_shape())
            .position(self.collider_offset())
            .mass(self.mass as Real)
            .friction(friction as Real)
            .restitution(0.0)
            .collision_groups(groups::JAR)
            .user_data(index as u128 + 1);
        world.insert(body, collider)
    }

    /// The jar's footprint placed at `(x, y, yaw)`.
    pub fn footprint_at(&self, x: f64, y: f64, yaw: f64) -> Footprint {
        Footprint {
            shape: self.shape,
            centre: [x, y],
            yaw,
        }
    }
}
