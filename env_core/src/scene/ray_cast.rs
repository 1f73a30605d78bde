//! Exact f64 ray casts against the scene's shapes: what the depth camera and the visibility
//! measure see.
//!
//! The camera's targets are few (five walls, at most a few dozen jars), so each ray is tested
//! against every target's bounding box and cast exactly only where it meets one; the same
//! targets can be built from a layout at rest, without a physics world.
//!
//! Why not `QueryPipeline::cast_ray`: parry casts rays on cylinders with GJK in f32,
//! which at these scales lands up to ~3 mm off the surface for rays grazing a jar's rim (the
//! depth test caught points floating above jar tops). Cuboids (walls, square jars) and y-axis
//! cylinders (round jars) are intersected here in closed form; any other shape falls back to
//! parry.

use rapier3d::glamx::{DQuat, DVec3};
use rapier3d::prelude::*;

use super::cupboard::Cupboard;
use super::groups;
use super::jar::JarSpec;

/// Label of a target that is a cupboard wall (a jar's label is its index).
pub const LABEL_CUPBOARD: i32 = -1;

/// A ray in f64 with a unit direction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ray64 {
    /// Origin, m.
    pub origin: [f64; 3],
    /// Unit direction.
    pub dir: [f64; 3],
}

impl Ray64 {
    /// The same ray in f32, for BVH traversal and parry fallbacks.
    pub fn to_parry(&self) -> Ray {
        Ray::new(
            Vector::new(
                self.origin[0] as Real,
                self.origin[1] as Real,
                self.origin[2] as Real,
            ),
            Vector::new(
                self.dir[0] as Real,
                self.dir[1] as Real,
                self.dir[2] as Real,
            ),
        )
    }
}

/// Clips `[t_in, t_out]` by the slab `lo ≤ o + t·d ≤ hi`; `false` if it becomes empty.
fn slab(o: f64, d: f64, lo: f64, hi: f64, t_in: &mut f64, t_out: &mut f64) -> bool {
    if d == 0.0 {
        return (lo..=hi).contains(&o);
    }
    let (a, b) = ((lo - o) / d, (hi - o) / d);
    *t_in = t_in.max(a.min(b));
    *t_out = t_out.min(a.max(b));
    *t_in <= *t_out
}

/// Time of impact (distance, 0 if the origin is inside) of `ray` with `shape` placed at
/// `pose`, if within `max_toi`. Exact for cuboids and cylinders. Cost: O(1).
pub fn shape_toi(shape: &dyn Shape, pose: &Pose, ray: &Ray64, max_toi: f64) -> Option<f64> {
    let inverse: DQuat = pose.rotation.as_dquat().inverse();
    let o = inverse * (DVec3::from_array(ray.origin) - pose.translation.as_dvec3());
    let d = inverse * DVec3::from_array(ray.dir);
    let (mut t_in, mut t_out) = (0.0f64, max_toi);
    if let Some(cuboid) = shape.as_cuboid() {
        let h = cuboid.half_extents.as_dvec3();
        let hit = slab(o.x, d.x, -h.x, h.x, &mut t_in, &mut t_out)
            && slab(o.y, d.y, -h.y, h.y, &mut t_in, &mut t_out)
            && slab(o.z, d.z, -h.z, h.z, &mut t_in, &mut t_out);
        hit.then_some(t_in)
    } else if let Some(cylinder) = shape.as_cylinder() {
        let (r, hh) = (f64::from(cylinder.radius), f64::from(cylinder.half_height));
        if !slab(o.y, d.y, -hh, hh, &mut t_in, &mut t_out) {
            return None;
        }
        let a = d.x * d.x + d.z * d.z;
        let c = o.x * o.x + o.z * o.z - r * r;
        if a == 0.0 {
            return (c <= 0.0).then_some(t_in);
        }
        let b = o.x * d.x + o.z * d.z;
        let disc = b * b - a * c;
        if disc < 0.0 {
            return None;
        }
        let root = disc.sqrt();
        t_in = t_in.max((-b - root) / a);
        t_out = t_out.min((-b + root) / a);
        (t_in <= t_out).then_some(t_in)
    } else {
        shape
            .cast_ray(pose, &ray.to_parry(), max_toi as Real, true)
            .map(f64::from)
    }
}

/// One shape the depth camera can see, placed in the world, with its label and its
/// world bounding box (f64, slightly widened) for a quick rejection before the exact cast.
#[derive(Clone)]
struct RayTarget {
    pose: Pose,
    shape: SharedShape,
    label: i32,
    lo: [f64; 3],
    hi: [f64; 3],
}

/// What the depth camera sees: the cupboard's walls and the jars as exact ray targets, in
/// a fixed order (walls, then jars by index). Built from a layout at rest (the first look)
/// or from a world's current poses (a later look); both give the same targets at reset.
#[derive(Clone)]
pub struct RayTargets {
    targets: Vec<RayTarget>,
}

/// Widening of each target's bounding box, m: far above f32 pose rounding, so the quick
/// test never rejects a true hit.
const BOX_SLACK: f64 = 1e-4;

impl RayTargets {
    fn push(&mut self, pose: Pose, shape: SharedShape, label: i32) {
        let aabb = shape.compute_aabb(&pose);
        let (mins, maxs) = (aabb.mins.as_dvec3(), aabb.maxs.as_dvec3());
        self.targets.push(RayTarget {
            pose,
            shape,
            label,
            lo: (mins - BOX_SLACK).to_array(),
            hi: (maxs + BOX_SLACK).to_array(),
        });
    }

    /// The walls and the jars of `jars` at their poses in the layout (the scene at reset),
    /// labelled [`LABEL_CUPBOARD`] and by jar index. Cost: O(walls + jars).
    pub fn at_rest(cupboard: &Cupboard, jars: &[JarSpec]) -> Self {
        let mut targets = Self {
            targets: Vec::with_capacity(cupboard.walls().len() + jars.len()),
        };
        for wall in cupboard.walls() {
            targets.push(wall.pose(), SharedShape::new(wall.shape()), LABEL_CUPBOARD);
        }
        for (index, jar) in jars.iter().enumerate() {
            targets.push(
                jar.body_pose() * jar.collider_offset(),
                jar.shared_shape(),
                index as i32,
            );
        }
        targets
    }

    /// The walls and jars of `world` at their current poses (every collider the camera
    /// sees, in insertion order: walls, then jars). Cost: O(colliders).
    pub(crate) fn from_world(world: &PhysicsWorld) -> Self {
        let mut targets = Self {
            targets: Vec::with_capacity(world.colliders.len()),
        };
        for (_, collider) in world.colliders.iter() {
            if !collider.collision_groups().test(groups::CAMERA_VIEW) {
                continue;
            }
            let label = match collider.user_data {
                0 => LABEL_CUPBOARD,
                tag => (tag - 1) as i32,
            };
            targets.push(*collider.position(), collider.shared_shape().clone(), label);
        }
        targets
    }

    /// The smallest and largest value of `dot(p − origin, axis)` over the targets' bounding
    /// boxes: with `axis` a camera's optical axis, the range of z-depths anything can be
    /// seen at. `None` when there are no targets.
    pub fn extent_along(&self, origin: [f64; 3], axis: [f64; 3]) -> Option<[f64; 2]> {
        let mut range: Option<[f64; 2]> = None;
        for target in &self.targets {
            for corner in 0..8 {
                let p: [f64; 3] = std::array::from_fn(|i| {
                    if corner & (1 << i) == 0 {
                        target.lo[i]
                    } else {
                        target.hi[i]
                    }
                });
                let along: f64 = (0..3).map(|i| (p[i] - origin[i]) * axis[i]).sum();
                range = Some(match range {
                    None => [along, along],
                    Some([lo, hi]) => [lo.min(along), hi.max(along)],
                });
            }
        }
        range
    }

    /// Where `ray` meets the (first) target labelled `label` within `max_toi`, the others
    /// ignored. Cost: O(targets) label comparisons and one exact cast.
    pub fn toi_on(&self, label: i32, ray: &Ray64, max_toi: f64) -> Option<f64> {
        let target = self.targets.iter().find(|t| t.label == label)?;
        shape_toi(target.shape.as_ref(), &target.pose, ray, max_toi)
    }

    /// The label of the first target `ray` hits within `max_toi`, and the distance (ties go
    /// to the earlier target). Cost: O(targets), an exact cast only where the ray meets a
    /// target's bounding box.
    pub fn first_hit(&self, ray: &Ray64, max_toi: f64) -> Option<(i32, f64)> {
        let mut best: Option<(i32, f64)> = None;
        for target in &self.targets {
            let limit = best.map_or(max_toi, |(_, t)| t);
            let (mut t_in, mut t_out) = (0.0f64, limit);
            let meets_box = (0..3).all(|i| {
                slab(
                    ray.origin[i],
                    ray.dir[i],
                    target.lo[i],
                    target.hi[i],
                    &mut t_in,
                    &mut t_out,
                )
            });
            if !meets_box {
                continue;
            }
            if let Some(t) = shape_toi(target.shape.as_ref(), &target.pose, ray, limit) {
                if best.is_none_or(|(_, b)| t < b) {
                    best = Some((target.label, t));
                }
            }
        }
        best
    }
}
