//! Episode metrics: the true jar footprints on the map grid and the IoU of a map's interior
//! against them. The environment's `info["iou"]` and the paper's table both come from here.

use crate::gpis::GridSpec;
use crate::scene::{Footprint, JarState};

/// Yaw (rotation about z) of an upright-ish quaternion `(x, y, z, w)`.
pub fn yaw_of(rotation: [f64; 4]) -> f64 {
    let [x, y, z, w] = rotation;
    (2.0 * (w * z + x * y)).atan2(1.0 - 2.0 * (y * y + z * z))
}

/// A jar's footprint at its current pose (centre and yaw of its body now).
pub fn footprint_of(jar: &JarState) -> Footprint {
    jar.spec
        .footprint_at(jar.position[0], jar.position[1], yaw_of(jar.rotation))
}

/// Which cell centres lie inside a jar's footprint at its current pose. Each jar visits
/// only the cells of its bounding square. Cost O(G + jars · cells per jar).
pub fn footprint_mask(grid: &GridSpec, jars: &[JarState], out: &mut Vec<bool>) {
    footprint_mask_within(grid, jars, 0.0, out);
}

/// Which cell centres lie closer than `margin` (m) to a jar's footprint (inside it when
/// `margin` is 0), each jar visiting only its bounding square widened by `margin`.
pub fn footprint_mask_within(grid: &GridSpec, jars: &[JarState], margin: f64, out: &mut Vec<bool>) {
    footprints_mask(grid, jars.iter().map(footprint_of), margin, out);
}

/// [`footprint_mask_within`] for footprints given directly (the experiments' jars at
/// reset, synthetic jars). Writes H·W flags in row-major cell order into `out`.
pub fn footprints_mask(
    grid: &GridSpec,
    footprints: impl IntoIterator<Item = Footprint>,
    margin: f64,
    out: &mut Vec<bool>,
) {
    let (h, w) = grid.shape();
    out.clear();
    out.resize(h * w, false);
    let [[x0, x1], [y0, y1]] = grid.bounds();
    let (cell_w, cell_h) = ((x1 - x0) / w as f64, (y1 - y0) / h as f64);
    for footprint in footprints {
        let [x, y] = footprint.centre;
        let reach = footprint.shape.bounding_radius() + margin;
        let columns = |lo: f64, hi: f64, size: f64, n: usize| {
            let first = ((lo / size).floor().max(0.0) as usize).min(n);
            let last = ((hi / size).ceil().max(0.0) as usize).min(n);
            first..last
        };
        for i in columns(y - reach - y0, y + reach - y0, cell_h, h) {
            for j in columns(x - reach - x0, x + reach - x0, cell_w, w) {
                if footprint.signed_distance(grid.cell_centre(i, j)) < margin {
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

/// IoU of a map's interior (cells whose mean is below 0) against `truth`, as the
/// environment reports it in `info["iou"]`. Cost O(G).
pub fn interior_iou(mean: &[f64], truth: &[bool]) -> f64 {
    iou(mean.iter().map(|&m| m < 0.0), truth)
}
