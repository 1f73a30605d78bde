//! Episode metrics: the true jar footprints on the map grid and the IoU of a map's interior
//! against them.

use crate::gpis::GridSpec;
use crate::scene::JarState;

/// Yaw (rotation about z) of an upright-ish quaternion `(x, y, z, w)`.
pub fn yaw_of(rotation: [f64; 4]) -> f64 {
    let [x, y, z, w] = rotation;
    (2.0 * (w * z + x * y)).atan2(1.0 - 2.0 * (y * y + z * z))
}

/// Which cell centres lie inside a jar's footprint at its current pose. Each jar visits
/// only the cells of its bounding square. Cost O(G + jars · cells per jar).
pub fn footprint_mask(grid: &GridSpec, jars: &[JarState], out: &mut Vec<bool>) {
    footprint_mask_within(grid, jars, 0.0, out);
}

/// Which cell centres lie closer than `margin` (m) to a jar's footprint (inside it when
/// `margin` is 0), each jar visiting only its bounding square widened by `margin`.
pub fn footprint_mask_within(grid: &GridSpec, jars: &[JarState], margin: f64, out: &mut Vec<bool>) {
    let (h, w) = grid.shape();
    out.clear();
    out.resize(h * w, false);
    let [[x0, x1], [y0, y1]] = grid.bounds();
    let (cell_w, cell_h) = ((x1 - x0) / w as f64, (y1 - y0) / h as f64);
    for jar in jars {
        let (x, y, yaw) = (jar.position[0], jar.position[1], yaw_of(jar.rotation));
        let reach = jar.spec.shape.bounding_radius() + margin;
        let columns = |lo: f64, hi: f64, size: f64, n: usize| {
            let first = ((lo / size).floor().max(0.0) as usize).min(n);
            let last = ((hi / size).ceil().max(0.0) as usize).min(n);
            first..last
        };
        for i in columns(y - reach - y0, y + reach - y0, cell_h, h) {
            for j in columns(x - reach - x0, x + reach - x0, cell_w, w) {
                if jar
                    .spec
                    .footprint_distance(grid.cell_centre(i, j), x, y, yaw)
                    < margin
                {
                    out[i * w + j] = true;
                }
            }
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
