//! Tactile readings: finger–jar contacts as points of the slice plane with the jar's outward
//! unit normal.
//!
//! rapier's manifolds repeat points, include predicted (distance > 0) points, and order the
//! pair arbitrarily. So: take the jar's side of each manifold (its local contact point, placed
//! by the jar collider's current pose: no body-local solver anchors), keep points with
//! distance ≤ `max_distance`, project to `(x, y)`, merge readings on the same jar closer than
//! `merge_distance`, and sort, so the output does not depend on pair order. Noise is added
//! afterwards, to a copy.
//!
//! The normal is the jar's outward surface normal at the contact point, from its shape:
//! radial for a round jar, the face normal for a square one. The manifold normal is not used
//! directly because when the deflected finger's flat side meets a square jar's vertical edge
//! it is the *finger's* face normal; there the jar's normal is undefined and the face whose
//! normal is nearest the manifold normal is reported.

use rand::Rng;
use rand_distr::{Distribution, Normal};
use rapier3d::prelude::*;

use super::config::TouchConfig;

/// One tactile reading.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Contact {
    /// Contact point in the slice plane, m.
    pub point: [f64; 2],
    /// The jar's outward unit normal there, in the slice plane.
    pub normal: [f64; 2],
    /// Which jar was touched (ground truth, not part of the observation).
    pub jar: usize,
}

/// Points on a square jar's face within this distance of its vertical edge count as on the
/// edge, m.
const EDGE_TOLERANCE: Real = 1e-3;

/// The jar's outward unit normal at `p`, in the collider's local frame (parry's cylinder axis
/// is local y; a jar cuboid's height is local z). `contact_normal` (local, outward of the
/// jar) breaks the tie on a square jar's vertical edge.
fn outward_normal(shape: &dyn Shape, p: Vector, contact_normal: Vector) -> Option<Vector> {
    if shape.as_cylinder().is_some() {
        Vector::new(p.x, 0.0, p.z).try_normalize()
    } else if let Some(cuboid) = shape.as_cuboid() {
        let h = cuboid.half_extents;
        let x_face = Vector::new(p.x.signum(), 0.0, 0.0);
        let y_face = Vector::new(0.0, p.y.signum(), 0.0);
        let on_x = p.x.abs() >= h.x - EDGE_TOLERANCE;
        let on_y = p.y.abs() >= h.y - EDGE_TOLERANCE;
        let pick_x = match (on_x, on_y) {
            (true, true) => x_face.dot(contact_normal) >= y_face.dot(contact_normal),
            (true, false) => true,
            (false, true) => false,
            (false, false) => p.x.abs() / h.x >= p.y.abs() / h.y,
        };
        Some(if pick_x { x_face } else { y_face })
    } else {
        contact_normal.try_normalize()
    }
}

/// The deduplicated, noise-free contacts of the finger with jars, sorted by `(jar, x, y)`.
/// Cost: O(manifold points²) per jar, a handful in practice.
pub(crate) fn finger_contacts(
    world: &PhysicsWorld,
    finger: ColliderHandle,
    config: &TouchConfig,
) -> Vec<Contact> {
    // (sum of points, sum of normals, count, jar) per merged reading.
    let mut merged: Vec<([f64; 2], [f64; 2], usize, usize)> = Vec::new();
    for pair in world.contact_pairs_with(finger) {
        let finger_first = pair.collider1 == finger;
        let other = if finger_first {
            pair.collider2
        } else {
            pair.collider1
        };
        let Some(collider) = world.colliders.get(other) else {
            continue;
        };
        if collider.user_data == 0 {
            continue; // a wall
        }
        let jar = (collider.user_data - 1) as usize;
        let jar_pose = collider.position();
        for manifold in pair.manifolds() {
            let local_normal = if finger_first {
                manifold.local_n2
            } else {
                manifold.local_n1
            };
            for point in &manifold.points {
                if f64::from(point.dist) > config.max_distance {
                    continue;
                }
                let local_point = if finger_first {
                    point.local_p2
                } else {
                    point.local_p1
                };
                let Some(local_n) = outward_normal(collider.shape(), local_point, local_normal)
                else {
                    continue;
                };
                let n = jar_pose.rotation * local_n;
                let (nx, ny) = (f64::from(n.x), f64::from(n.y));
                let n_len = nx.hypot(ny);
                if n_len < 1e-3 {
                    continue; // a cap contact has no direction in the slice plane
                }
                let p = jar_pose.transform_point(local_point);
                let p = [f64::from(p.x), f64::from(p.y)];
                let normal = [nx / n_len, ny / n_len];
                let existing = merged.iter_mut().find(|(sum, _, count, j)| {
                    let c = [sum[0] / *count as f64, sum[1] / *count as f64];
                    *j == jar && (c[0] - p[0]).hypot(c[1] - p[1]) <= config.merge_distance
                });
                match existing {
                    Some((sum, nsum, count, _)) => {
                        sum[0] += p[0];
                        sum[1] += p[1];
                        nsum[0] += normal[0];
                        nsum[1] += normal[1];
                        *count += 1;
                    }
                    None => merged.push((p, normal, 1, jar)),
                }
            }
        }
    }
    let mut contacts: Vec<Contact> = merged
        .into_iter()
        .map(|(sum, nsum, count, jar)| {
            let len = nsum[0].hypot(nsum[1]).max(f64::MIN_POSITIVE);
            Contact {
                point: [sum[0] / count as f64, sum[1] / count as f64],
                normal: [nsum[0] / len, nsum[1] / len],
                jar,
            }
        })
        .collect();
    contacts.sort_by(|a, b| {
        a.jar
            .cmp(&b.jar)
            .then(a.point[0].total_cmp(&b.point[0]))
            .then(a.point[1].total_cmp(&b.point[1]))
    });
    contacts
}

/// A noisy copy: Gaussian noise on each point coordinate, and each normal rotated by a
/// Gaussian angle (so it stays a unit vector).
pub(crate) fn with_noise(
    contacts: &[Contact],
    config: &TouchConfig,
    rng: &mut impl Rng,
) -> Vec<Contact> {
    let point_noise = Normal::new(0.0, config.point_noise_std).ok();
    let angle_noise = Normal::new(0.0, config.normal_noise_std).ok();
    contacts
        .iter()
        .map(|c| {
            let mut out = *c;
            if let Some(noise) = point_noise.filter(|_| config.point_noise_std > 0.0) {
                out.point[0] += noise.sample(rng);
                out.point[1] += noise.sample(rng);
            }
            if let Some(noise) = angle_noise.filter(|_| config.normal_noise_std > 0.0) {
                let (s, co) = noise.sample(rng).sin_cos();
                let [nx, ny] = c.normal;
                out.normal = [co * nx - s * ny, s * nx + co * ny];
            }
            out
        })
        .collect()
}
