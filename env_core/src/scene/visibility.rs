//! How much of the target the depth camera sees, measured by ray casting, not assumed.
//!
//! Measure: cast the ray of every pixel of the camera's own grid whose ray can reach the
//! target. The target's *silhouette* is the set of pixels whose ray hits the target's shape
//! (tested alone); a silhouette pixel is *visible* when no wall or other jar is hit strictly
//! before the target along that ray. The visible fraction is visible / silhouette pixels (0 if
//! the silhouette is empty). The layout generator keeps it at most
//! [`crate::scene::LayoutConfig::max_visible_fraction`].

use super::cupboard::Cupboard;
use super::depth_camera::DepthCamera;
use super::jar::JarSpec;
use super::ray_cast::RayTargets;

/// Pixel counts of the target's silhouette and of its visible part.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Visibility {
    /// Pixels whose ray hits the target when it is alone.
    pub silhouette_pixels: usize,
    /// Silhouette pixels whose first hit is the target.
    pub visible_pixels: usize,
}

impl Visibility {
    /// visible / silhouette pixels, 0 for an empty silhouette.
    pub fn fraction(&self) -> f64 {
        if self.silhouette_pixels == 0 {
            0.0
        } else {
            self.visible_pixels as f64 / self.silhouette_pixels as f64
        }
    }
}

/// Pixel-index range `[lo, hi)` covering the projection of the target's bounding box, or the
/// whole image if a corner is behind the camera.
fn pixel_box(camera: &DepthCamera, jar: &JarSpec) -> ([usize; 2], [usize; 2]) {
    let k = camera.intrinsics();
    let full = ([0, 0], [k.width, k.height]);
    let r = jar.shape.bounding_radius();
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    for corner in 0..8 {
        let x = jar.x + if corner & 1 == 0 { -r } else { r };
        let y = jar.y + if corner & 2 == 0 { -r } else { r };
        let z = if corner & 4 == 0 { 0.0 } else { jar.height };
        let Some((uv, _)) = camera.project([x, y, z]) else {
            return full;
        };
        for i in 0..2 {
            lo[i] = lo[i].min(uv[i]);
            hi[i] = hi[i].max(uv[i]);
        }
    }
    let clamp = |value: f64, size: usize| value.max(0.0).min(size as f64) as usize;
    (
        [
            clamp(lo[0].floor() - 1.0, k.width),
            clamp(lo[1].floor() - 1.0, k.height),
        ],
        [
            clamp(hi[0].ceil() + 1.0, k.width),
            clamp(hi[1].ceil() + 1.0, k.height),
        ],
    )
}

/// Measures the visibility of `jars[target]` among `jars` and the cupboard's walls, with exact
/// ray casts on the shapes directly (the camera's [`RayTargets`] at rest: no physics world
/// needed). Cost: O(pixels under the target's projected box × (jars + walls)).
pub fn target_visibility(
    camera: &DepthCamera,
    cupboard: &Cupboard,
    jars: &[JarSpec],
    target: usize,
) -> Visibility {
    let targets = RayTargets::at_rest(cupboard, jars);
    let max_toi = camera.max_range();
    let ([u0, v0], [u1, v1]) = pixel_box(camera, &jars[target]);
    let mut result = Visibility::default();
    for v in v0..v1 {
        for u in u0..u1 {
            let (ray, _) = camera.pixel_ray(u, v);
            let Some(t_target) = targets.toi_on(target as i32, &ray, max_toi) else {
                continue;
            };
            result.silhouette_pixels += 1;
            // Blocked when a wall or another jar is hit strictly before the target.
            let blocked = targets
                .first_hit(&ray, t_target)
                .is_some_and(|(_, t)| t < t_target);
            if !blocked {
                result.visible_pixels += 1;
            }
        }
    }
    result
}
