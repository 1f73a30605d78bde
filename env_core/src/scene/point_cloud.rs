//! From a depth image to what the GPIS eats (paper §IV.A.1, Fig. 3): back-projection to a 3D
//! cloud, a horizontal cross-section slice at the map height flattened to 2D `(x, y)`,
//! deterministic thinning, and Gaussian white noise.

use rand::Rng;
use rand_distr::{Distribution, Normal};

use super::depth_camera::{DepthCamera, DepthImage};

/// Everything one look of the depth camera yields.
#[derive(Debug, Clone, PartialEq)]
pub struct DepthCapture {
    /// The depth image and its per-pixel labels.
    pub image: DepthImage,
    /// Back-projected points of every pixel with a return, world frame, m.
    pub cloud: Vec<[f64; 3]>,
    /// Label of each cloud point (jar index, or the cupboard/none labels).
    pub cloud_labels: Vec<i32>,
    /// The slice before noise: cloud points with `|z − slice_height| ≤ band/2`, flattened to
    /// `(x, y)` and thinned, m.
    pub slice_clean: Vec<[f64; 2]>,
    /// The slice observation: [`Self::slice_clean`] plus Gaussian noise, m.
    pub slice: Vec<[f64; 2]>,
    /// Label of each slice point.
    pub slice_labels: Vec<i32>,
}

/// How to cut, thin and perturb the slice.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SliceSpec {
    /// Height of the slice plane, m.
    pub height: f64,
    /// Full thickness of the band kept around it, m.
    pub band: f64,
    /// At most this many points survive the thinning.
    pub max_points: usize,
    /// Standard deviation of the noise on each coordinate, m.
    pub noise_std: f64,
}

/// Indices of `keep` of `n` items, spread evenly and deterministically (`⌊i·n/keep⌋`); all of
/// them when `n <= keep`. Cost: O(keep).
pub fn thin_indices(n: usize, keep: usize) -> Vec<usize> {
    if n <= keep {
        (0..n).collect()
    } else {
        (0..keep).map(|i| i * n / keep).collect()
    }
}

/// Back-projects, slices, thins and adds noise drawn from `rng`. Cost: O(W·H).
pub fn process_depth(
    camera: &DepthCamera,
    image: DepthImage,
    spec: SliceSpec,
    rng: &mut impl Rng,
) -> DepthCapture {
    let mut cloud = Vec::new();
    let mut cloud_labels = Vec::new();
    let mut in_band = Vec::new();
    let half_band = 0.5 * spec.band;
    for v in 0..image.height {
        for u in 0..image.width {
            let i = v * image.width + u;
            let depth = image.depth[i];
            if !depth.is_finite() {
                continue;
            }
            let p = camera.back_project(u, v, depth);
            if (p[2] - spec.height).abs() <= half_band {
                in_band.push(cloud.len());
            }
            cloud.push(p);
            cloud_labels.push(image.labels[i]);
        }
    }
    let kept: Vec<usize> = thin_indices(in_band.len(), spec.max_points)
        .into_iter()
        .map(|k| in_band[k])
        .collect();
    let slice_clean: Vec<[f64; 2]> = kept.iter().map(|&i| [cloud[i][0], cloud[i][1]]).collect();
    let slice_labels: Vec<i32> = kept.iter().map(|&i| cloud_labels[i]).collect();
    let slice = match Normal::new(0.0, spec.noise_std) {
        Ok(normal) if spec.noise_std > 0.0 => slice_clean
            .iter()
            .map(|p| [p[0] + normal.sample(rng), p[1] + normal.sample(rng)])
            .collect(),
        _ => slice_clean.clone(),
    };
    DepthCapture {
        image,
        cloud,
        cloud_labels,
        slice_clean,
        slice,
        slice_labels,
    }
}
