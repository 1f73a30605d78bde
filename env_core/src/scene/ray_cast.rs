//! Exact f64 ray casts against the scene's shapes, with rapier's query pipeline (its BVH and
//! collision-group filter) choosing the candidate colliders.
//!
//! Why not `QueryPipeline::cast_ray` alone: parry casts rays on cylinders with GJK in f32,
//! which at these scales lands up to ~3 mm off the surface for rays grazing a jar's rim (the
//! depth test caught points floating above jar tops). Cuboids (walls, square jars) and y-axis
//! cylinders (round jars) are intersected here in closed form; any other shape falls back to
//! parry.

use rapier3d::glamx::{DQuat, DVec3};
use rapier3d::parry::bounding_volume::BoundingVolume;
use rapier3d::parry::partitioning::BvhNode;
use rapier3d::parry::query::RayCast;
use rapier3d::prelude::*;

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

/// The first collider passing the query's filter that `ray` hits within `max_toi`, and the
/// distance. Candidates come from the query pipeline's BVH. Cost: O(log n + candidates).
pub fn first_hit(
    query: &QueryPipeline<'_>,
    ray: &Ray64,
    max_toi: f64,
) -> Option<(ColliderHandle, f64)> {
    let coarse = ray.to_parry();
    // The f32 AABB test is widened a little so that rounding never drops a true candidate.
    let reach = (max_toi + 1e-3) as Real;
    let mut best: Option<(ColliderHandle, f64)> = None;
    for leaf in query.bvh.leaves(|node: &BvhNode| {
        node.aabb()
            .loosened(1e-4)
            .intersects_local_ray(&coarse, reach)
    }) {
        let Some((collider, handle)) = query.colliders.get_unknown_gen(leaf) else {
            continue;
        };
        if !query.filter.test(query.bodies, handle, collider) {
            continue;
        }
        let limit = best.map_or(max_toi, |(_, t)| t);
        if let Some(t) = shape_toi(collider.shape(), collider.position(), ray, limit) {
            if best.is_none_or(|(_, b)| t < b) {
                best = Some((handle, t));
            }
        }
    }
    best
}
