//! Geometry written independently of rapier/parry for the scene tests: signed distances and
//! ray intersections of upright jars and axis-aligned wall boxes, in f64; and an episode's
//! observation for the episode tests.

#![allow(dead_code)]

use env_core::episode::{Episode, PROPRIO_LEN};
use env_core::scene::{JarShape, JarSpec, JarState, SceneConfig, WallBox};

/// An episode's observation: its map image and its proprio vector.
pub fn observe(episode: &Episode) -> (Vec<u8>, Vec<f32>) {
    let mut map = vec![0u8; episode.map_len()];
    let mut proprio = vec![0f32; PROPRIO_LEN];
    episode.write_map(&mut map).unwrap();
    episode.write_proprio(&mut proprio).unwrap();
    (map, proprio)
}

/// A jar's centre (x, y), yaw, height and shape from its current state (upright jars only).
pub struct JarGeom {
    pub x: f64,
    pub y: f64,
    pub z_bottom: f64,
    pub yaw: f64,
    pub height: f64,
    pub shape: JarShape,
}

impl JarGeom {
    pub fn of(state: &JarState) -> Self {
        let [qx, qy, qz, qw] = state.rotation;
        // Yaw of an (almost) upright quaternion.
        let yaw = 2.0 * qz.atan2(qw);
        assert!(
            qx.abs() < 1e-2 && qy.abs() < 1e-2,
            "jar not upright: {:?}",
            state.rotation
        );
        Self {
            x: state.position[0],
            y: state.position[1],
            z_bottom: state.position[2] - 0.5 * state.spec.height,
            yaw,
            height: state.spec.height,
            shape: state.spec.shape,
        }
    }

    /// Point in the jar's frame (origin at the bottom centre, z up).
    pub fn to_local(&self, p: [f64; 3]) -> [f64; 3] {
        let (dx, dy) = (p[0] - self.x, p[1] - self.y);
        let (s, c) = self.yaw.sin_cos();
        [c * dx + s * dy, -s * dx + c * dy, p[2] - self.z_bottom]
    }

    /// Signed distance of a 3D point to the jar's surface (negative inside).
    pub fn sdf(&self, p: [f64; 3]) -> f64 {
        let l = self.to_local(p);
        let hz = 0.5 * self.height;
        let qz = (l[2] - hz).abs() - hz;
        match self.shape {
            JarShape::Round { radius } => {
                let qr = l[0].hypot(l[1]) - radius;
                qr.max(0.0).hypot(qz.max(0.0)) + qr.max(qz).min(0.0)
            }
            JarShape::Square { half_side } => {
                let q = [l[0].abs() - half_side, l[1].abs() - half_side, qz];
                let outside = q.iter().map(|v| v.max(0.0).powi(2)).sum::<f64>().sqrt();
                outside + q[0].max(q[1]).max(q[2]).min(0.0)
            }
        }
    }

    /// Smallest t >= 0 where origin + t·dir enters the jar, if any.
    pub fn ray_hit(&self, origin: [f64; 3], dir: [f64; 3]) -> Option<f64> {
        let o = self.to_local(origin);
        let (s, c) = self.yaw.sin_cos();
        let d = [c * dir[0] + s * dir[1], -s * dir[0] + c * dir[1], dir[2]];
        let mut t_in = 0.0f64;
        let mut t_out = f64::INFINITY;
        // z slab.
        slab(o[2], d[2], 0.0, self.height, &mut t_in, &mut t_out)?;
        match self.shape {
            JarShape::Round { radius } => {
                let a = d[0] * d[0] + d[1] * d[1];
                let b = 2.0 * (o[0] * d[0] + o[1] * d[1]);
                let cc = o[0] * o[0] + o[1] * o[1] - radius * radius;
                if a < 1e-15 {
                    if cc > 0.0 {
                        return None;
                    }
                } else {
                    let disc = b * b - 4.0 * a * cc;
                    if disc < 0.0 {
                        return None;
                    }
                    let sq = disc.sqrt();
                    t_in = t_in.max((-b - sq) / (2.0 * a));
                    t_out = t_out.min((-b + sq) / (2.0 * a));
                }
            }
            JarShape::Square { half_side } => {
                slab(o[0], d[0], -half_side, half_side, &mut t_in, &mut t_out)?;
                slab(o[1], d[1], -half_side, half_side, &mut t_in, &mut t_out)?;
            }
        }
        (t_in <= t_out).then_some(t_in)
    }
}

fn slab(o: f64, d: f64, lo: f64, hi: f64, t_in: &mut f64, t_out: &mut f64) -> Option<()> {
    if d.abs() < 1e-15 {
        return (lo..=hi).contains(&o).then_some(());
    }
    let (a, b) = ((lo - o) / d, (hi - o) / d);
    *t_in = t_in.max(a.min(b));
    *t_out = t_out.min(a.max(b));
    (*t_in <= *t_out).then_some(())
}

/// Signed distance of a point to an axis-aligned wall box.
pub fn box_sdf(wall: &WallBox, p: [f64; 3]) -> f64 {
    let q: Vec<f64> = (0..3)
        .map(|i| (p[i] - wall.centre[i]).abs() - wall.half_extents[i])
        .collect();
    let outside = q.iter().map(|v| v.max(0.0).powi(2)).sum::<f64>().sqrt();
    outside + q[0].max(q[1]).max(q[2]).min(0.0)
}

/// Angle between two 2D vectors, degrees.
pub fn angle_deg(a: [f64; 2], b: [f64; 2]) -> f64 {
    let dot = a[0] * b[0] + a[1] * b[1];
    let cross = a[0] * b[1] - a[1] * b[0];
    cross.atan2(dot).abs().to_degrees()
}

/// A 0.11 m, 0.15 kg jar standing at `(x, y)` turned by `yaw`: the lone jar of the touch,
/// deflection and wall experiments.
pub fn test_jar(shape: JarShape, x: f64, y: f64, yaw: f64) -> JarSpec {
    JarSpec {
        shape,
        height: 0.11,
        mass: 0.15,
        x,
        y,
        yaw,
    }
}

/// Starts the wrist so the finger's edge is `gap` from the jar's −x side and the jar's centre
/// faces the finger 70 % along its length.
pub fn start_beside(config: &mut SceneConfig, jar: &JarSpec, gap: f64) {
    let x0 = jar.x - (jar.half_extent_x() + config.hand.finger_half_thickness + gap);
    let joint_offset = config.hand.wrist_half_extent + 0.002;
    config.hand.start = [x0, jar.y - 0.07 - joint_offset, 0.0];
}
