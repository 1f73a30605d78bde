//! The pinhole depth camera: intrinsics, pose, the ray through each pixel and the depth image
//! rendered by ray casting through rapier's query pipeline.
//!
//! Camera frame (OpenCV): x right, y down, z along the optical axis. Pixel `(u, v)` (column,
//! row) has its centre at `(u + 0.5, v + 0.5)`. Depth is the z-depth along the optical axis,
//! so back-projection is `p_cam = depth · ((u + 0.5 − cx)/fx, (v + 0.5 − cy)/fy, 1)` and
//! `p_world = R · p_cam + t`.

use rapier3d::prelude::*;

use super::camera_intrinsics::CameraIntrinsics;
use super::config::CameraConfig;
use super::error::SceneError;
use super::groups;
use super::ray_cast::{first_hit, Ray64};

/// Label of a pixel whose ray hit a cupboard wall.
pub const LABEL_CUPBOARD: i32 = -1;
/// Label of a pixel whose ray hit nothing within range.
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
    /// Row-major: jar index, [`LABEL_CUPBOARD`] or [`LABEL_NONE`].
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

    /// Renders the depth image of the walls and jars (the hand is not seen) by casting one
    /// ray per pixel through rapier's query pipeline (its BVH picks the candidates, see
    /// [`super::ray_cast`] for the exact intersection). The world must have been stepped once
    /// (ray casts see nothing before the first step). Cost: O(W·H·log colliders).
    pub fn render(&self, world: &PhysicsWorld) -> DepthImage {
        let k = &self.intrinsics;
        let n = k.width * k.height;
        let mut depth = Vec::with_capacity(n);
        let mut labels = Vec::with_capacity(n);
        let filter = QueryFilter::new().groups(groups::CAMERA_VIEW);
        let query = world.query_pipeline_with_filter(filter);
        for v in 0..k.height {
            for u in 0..k.width {
                let (ray, to_depth) = self.pixel_ray(u, v);
                match first_hit(&query, &ray, self.max_range) {
                    Some((handle, toi)) => {
                        depth.push(toi * to_depth);
                        let tag = world.colliders.get(handle).map_or(0, |c| c.user_data);
                        labels.push(if tag == 0 {
                            LABEL_CUPBOARD
                        } else {
                            (tag - 1) as i32
                        });
                    }
                    None => {
                        depth.push(f64::NAN);
                        labels.push(LABEL_NONE);
                    }
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
