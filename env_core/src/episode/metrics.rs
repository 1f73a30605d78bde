//! Episode metrics: the true jar footprints on the map grid and the IoU of a map's interior
//! against them.

use crate::gpis::GridSpec;
use crate::scene::JarState;

/// Yaw (rotation about z) of an upright-ish quaternion `(x, y, z, w)`.
pub fn yaw_of(rotation: [f64; 4]) -> f64 {
    let [x, y, z, w] = rotation;
    (2.0 * (w * z + x * y)).atan2(1.0 - 2.0 * (y * y + z * z))
}

/// Which cell centres lie inside a jar's footprint at its current pose. Cost O(G · jars).
pub fn footprint_mask(grid: &GridSpec, jars: &[JarState], out: &mut Vec<bool>) {
    out.clear();
    let poses: Vec<(f64, f64, f64)> = jars
        .iter()
        .map(|j| (j.position[0], j.position[1], yaw_of(j.rotation)))
        .collect();
    let (h, w) = grid.shape();
    for i in 0..h {
        for j in 0..w {
            let p = grid.cell_centre(i, j);
            let inside = jars
                .iter()
                .zip(&poses)
                .any(|(jar, &(x, y, yaw))| jar.spec.footprint_distance(p, x, y, yaw) < 0.0);
            out.push(inside);
        }
    }
}

/// Intersection over union of two masks; 1 when both are empty.
pub fn iou(estimate: impl Iterator<Item = bool>, truth: &[bool]) -> f64 {
    let (mut intersection, mut union) = (0usize, 0usize);
    for (e, &t) in estimate.zip(truth) {
        intersection += usize::from(e && t);
        union += usize::from(e || t);
    }
    if union == 0 {
        1.0
    } else {
        intersection as f64 / union as f64
    }
}
