//! The pinhole depth camera: intrinsics, pose, the ray through each pixel and the depth image
//! rendered by exact ray casts against the walls and jars ([`RayTargets`]).
//!
//! Camera frame (OpenCV): x right, y down, z along the optical axis. Pixel `(u, v)` (column,
//! row) has its centre at `(u + 0.5, v + 0.5)`. Depth is the z-depth along the optical axis,
//! so back-projection is `p_cam = depth · ((u + 0.5 − cx)/fx, (v + 0.5 − cy)/fy, 1)` and
//! `p_world = R · p_cam + t`.

use super::camera_intrinsics::CameraIntrinsics;
use super::config::CameraConfig;
use super::error::SceneError;
use super::ray_cast::{Ray64, RayTargets};

/// Rows are culled against the slice band widened by this, m: far above the rounding of a
/// back-projected point, so culling never drops a point that lies in the band.
const BAND_SLACK: f64 = 1e-6;

/// Label of a pixel whose ray hit nothing within range (a hit is labelled by its target:
/// a jar's index or [`LABEL_CUPBOARD`](super::ray_cast::LABEL_CUPBOARD)).
pub const LABEL_NONE: i32 = -2;

/// A depth image and, per pixel, what its ray hit (ground truth, not an observation).
#[derive(Debug, Clone, PartialEq)]
pub struct DepthImage {
    /// Columns.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// Row-major z-depth, m; NaN where the ray hit nothing within range.
    pub depth: Vec<f64>,
    /// Row-major: jar index, [`LABEL_CUPBOARD`](super::ray_cast::LABEL_CUPBOARD) or [`LABEL_NONE`].
    pub labels: Vec<i32>,
}

/// A posed pinhole depth camera.
#[derive(Debug, Clone, PartialEq)]
pub struct DepthCamera {
    intrinsics: CameraIntrinsics,
    position: [f64; 3],
    /// Columns: camera x (right), y (down), z (forward) in world coordinates.
    axes: [[f64; 3]; 3],
    max_range: f64,
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn norm(a: [f64; 3]) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}

fn scale(a: [f64; 3], s: f64) -> [f64; 3] {
    [a[0] * s, a[1] * s, a[2] * s]
}

impl DepthCamera {
    /// The camera of a config: optical centre at `position`, optical axis towards `look_at`,
    /// image up along world +z. Fails if the axis is undefined or (anti)parallel to z.
    pub fn new(config: &CameraConfig) -> Result<Self, SceneError> {
        let degenerate = || SceneError::DegenerateCameraPose {
            position: config.position,
            look_at: config.look_at,
        };
        let forward = sub(config.look_at, config.position);
        let length = norm(forward);
        if !(length.is_finite() && length > 1e-9) {
            return Err(degenerate());
        }
        let forward = scale(forward, 1.0 / length);
        let right = cross(forward, [0.0, 0.0, 1.0]);
        let right_norm = norm(right);
        if right_norm < 1e-6 {
            return Err(degenerate());
        }
        let right = scale(right, 1.0 / right_norm);
        let down = cross(forward, right);
        Ok(Self {
            intrinsics: config.intrinsics(),
            position: config.position,
            axes: [right, down, forward],
            max_range: config.max_range,
        })
    }

    /// The intrinsics.
    pub fn intrinsics(&self) -> &CameraIntrinsics {
        &self.intrinsics
    }

    /// The optical centre, m.
    pub fn position(&self) -> [f64; 3] {
        self.position
    }

    /// Rotation camera → world as a row-major 3×3 matrix (columns: right, down, forward).
    pub fn rotation(&self) -> [[f64; 3]; 3] {
        let [r, d, f] = self.axes;
        [[r[0], d[0], f[0]], [r[1], d[1], f[1]], [r[2], d[2], f[2]]]
    }

    /// Rays longer than this return no depth, m.
    pub fn max_range(&self) -> f64 {
        self.max_range
    }

    /// World direction of the ray through pixel `(u, v)`, scaled so that its component along
    /// the optical axis is 1 (so `position + depth · dir` is the back-projected point).
    pub fn pixel_direction(&self, u: usize, v: usize) -> [f64; 3] {
        let k = &self.intrinsics;
        let xc = (u as f64 + 0.5 - k.cx) / k.fx;
        let yc = (v as f64 + 0.5 - k.cy) / k.fy;
        let [r, d, f] = self.axes;
        std::array::from_fn(|i| r[i] * xc + d[i] * yc + f[i])
    }

    /// Back-projects pixel `(u, v)` at z-depth `depth` to the world, m.
    pub fn back_project(&self, u: usize, v: usize, depth: f64) -> [f64; 3] {
        let dir = self.pixel_direction(u, v);
        std::array::from_fn(|i| self.position[i] + depth * dir[i])
    }

    /// Projects a world point to continuous pixel coordinates `(u, v)` (pixel centres at
    /// half-integers) and its z-depth; `None` if it is not in front of the camera.
    pub fn project(&self, point: [f64; 3]) -> Option<([f64; 2], f64)> {
        let rel = sub(point, self.position);
        let [r, d, f] = self.axes;
        let dot = |a: [f64; 3]| a[0] * rel[0] + a[1] * rel[1] + a[2] * rel[2];
        let z = dot(f);
        if z <= 1e-9 {
            return None;
        }
        let k = &self.intrinsics;
        Some(([k.fx * dot(r) / z + k.cx, k.fy * dot(d) / z + k.cy], z))
    }

    /// The unit-direction ray through pixel `(u, v)` and the factor turning its distance
    /// into z-depth.
    pub fn pixel_ray(&self, u: usize, v: usize) -> (Ray64, f64) {
        let dir = self.pixel_direction(u, v);
        let length = norm(dir);
        let ray = Ray64 {
            origin: self.position,
            dir: scale(dir, 1.0 / length),
        };
        (ray, 1.0 / length)
    }

    /// Renders the depth image of `targets` (the walls and jars; the hand is never a
    /// target), one exact ray cast per pixel. Cost: O(W·H·targets) bounding-box tests.
    pub fn render(&self, targets: &RayTargets) -> DepthImage {
        self.render_rows(targets, |_| true)
    }

    /// Renders only the rows whose rays can return a point with world z in `z_band`
    /// (`[lo, hi]`, m) from where `targets` are; every other pixel reads as nothing hit
    /// (NaN, [`LABEL_NONE`]). The points in the band, their order and their labels are
    /// exactly those of [`Self::render`]: this is all a slice at that height needs. A row's
    /// rays share one world z per z-depth (the image's up is world +z), so a row is cast
    /// when its z over the targets' z-depth range meets the band. Cost: the cast rows only
    /// (about a twelfth of the image for the default slice).
    pub fn render_band(&self, targets: &RayTargets, z_band: [f64; 2]) -> DepthImage {
        let Some([near, far]) = targets.extent_along(self.position, self.axes[2]) else {
            return self.render_rows(targets, |_| false);
        };
        let near = near.max(0.0);
        let k = &self.intrinsics;
        let [_, down, forward] = self.axes;
        let reaches_band = |v: usize| {
            let yc = (v as f64 + 0.5 - k.cy) / k.fy;
            let dz = down[2] * yc + forward[2];
            let (a, b) = (self.position[2] + near * dz, self.position[2] + far * dz);
            a.min(b) <= z_band[1] + BAND_SLACK && a.max(b) >= z_band[0] - BAND_SLACK
        };
        self.render_rows(targets, reaches_band)
    }

    fn render_rows(&self, targets: &RayTargets, cast_row: impl Fn(usize) -> bool) -> DepthImage {
        let k = &self.intrinsics;
        let n = k.width * k.height;
        let mut depth = vec![f64::NAN; n];
        let mut labels = vec![LABEL_NONE; n];
        for v in (0..k.height).filter(|&v| cast_row(v)) {
            for u in 0..k.width {
                let (ray, to_depth) = self.pixel_ray(u, v);
                if let Some((label, toi)) = targets.first_hit(&ray, self.max_range) {
                    depth[v * k.width + u] = toi * to_depth;
                    labels[v * k.width + u] = label;
                }
            }
        }
        DepthImage {
            width: k.width,
            height: k.height,
            depth,
            labels,
        }
    }
}
