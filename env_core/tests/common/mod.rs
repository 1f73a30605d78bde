//! Geometry written independently of rapier/parry for the scene tests: signed distances and
//! ray intersections of upright jars and axis-aligned wall boxes, in f64, and from them the
//! visibility of a jar and the invariants of a generated layout; a scripted reach through a
//! corridor; and an episode's observation for the episode tests.

#![allow(dead_code)]

use env_core::episode::{Episode, PROPRIO_LEN};
use env_core::scene::{
    Corridor, Cupboard, DepthCamera, HandCommand, JarShape, JarSpec, JarState, Layout, Scene,
    SceneConfig, WallBox,
};
use env_core::settings::Checked;

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

impl JarGeom {
    /// The jar standing where its spec puts it, at rest on the floor.
    pub fn at_rest(spec: &JarSpec) -> Self {
        Self {
            x: spec.x,
            y: spec.y,
            z_bottom: 0.0,
            yaw: spec.yaw,
            height: spec.height,
            shape: spec.shape,
        }
    }
}

/// Smallest t >= 0 where origin + t·dir enters an axis-aligned wall box, if any.
pub fn box_ray_hit(wall: &WallBox, origin: [f64; 3], dir: [f64; 3]) -> Option<f64> {
    let (mut t_in, mut t_out) = (0.0f64, f64::INFINITY);
    for i in 0..3 {
        let lo = wall.centre[i] - wall.half_extents[i];
        let hi = wall.centre[i] + wall.half_extents[i];
        slab(origin[i], dir[i], lo, hi, &mut t_in, &mut t_out)?;
    }
    (t_in <= t_out).then_some(t_in)
}

/// `(silhouette, visible)` pixels of `jars[index]` in the camera's image, by the f64 ray
/// intersections above (independent of the core's ray casts): the silhouette is the pixels
/// whose ray hits the jar alone, a silhouette pixel is visible when no wall or other jar is
/// hit strictly before it.
pub fn visible_pixels(
    camera: &DepthCamera,
    cupboard: &Cupboard,
    jars: &[JarSpec],
    index: usize,
) -> (usize, usize) {
    let geoms: Vec<JarGeom> = jars.iter().map(JarGeom::at_rest).collect();
    let k = camera.intrinsics();
    let origin = camera.position();
    let (mut silhouette, mut visible) = (0, 0);
    for v in 0..k.height {
        for u in 0..k.width {
            let dir = camera.pixel_direction(u, v);
            let Some(t) = geoms[index].ray_hit(origin, dir) else {
                continue;
            };
            silhouette += 1;
            let jar_before = geoms
                .iter()
                .enumerate()
                .any(|(i, g)| i != index && g.ray_hit(origin, dir).is_some_and(|s| s < t));
            let wall_before = cupboard
                .walls()
                .iter()
                .any(|w| box_ray_hit(w, origin, dir).is_some_and(|s| s < t));
            if !jar_before && !wall_before {
                visible += 1;
            }
        }
    }
    (silhouette, visible)
}

/// The gap between a corridor's inner edge and the side of the jar it leads to, m.
pub fn corridor_gap(corridor: &Corridor, jar: &JarSpec) -> f64 {
    if corridor.side > 0.0 {
        corridor.x[0] - (jar.x + jar.half_extent_x())
    } else {
        jar.x - jar.half_extent_x() - corridor.x[1]
    }
}

/// Asserts what every generated layout of `config` keeps, measured here and not taken from
/// the generator: the jar count in its range; `hidden_decoys` decoys, none the target; every
/// hidden jar (target and decoys) at least `target_min_depth` deep, in the camera's image
/// (over 20 silhouette pixels) and at most `max_visible_fraction` visible; bounding circles
/// `min_gap` apart and `wall_gap` from the side and back walls; one corridor per hidden jar,
/// inside the cupboard, from the opening to its jar's far side, `corridor_clearance` beside
/// it, holding no part of any other jar's bounding circle widened by `min_gap`.
pub fn check_generated_layout(config: &SceneConfig, layout: &Layout, seed: u64) {
    let tol = 1e-12;
    let c = &config.layout;
    let cupboard = Cupboard::new(&config.cupboard);
    let camera = DepthCamera::new(&config.camera).expect("camera");
    let jars = &layout.jars;
    let n = jars.len();
    assert!(
        (c.jar_count[0]..=c.jar_count[1]).contains(&n),
        "seed {seed}: {n} jars"
    );
    assert!(layout.target < n, "seed {seed}: target {}", layout.target);
    assert_eq!(
        layout.decoys.len(),
        c.hidden_decoys,
        "seed {seed}: decoys {:?}",
        layout.decoys
    );
    assert_eq!(layout.decoy_corridors.len(), layout.decoys.len());
    assert!(layout.decoys.windows(2).all(|w| w[0] < w[1]));
    assert!(layout.decoys.iter().all(|&d| d < n && d != layout.target));

    let half_w = 0.5 * cupboard.width();
    for (i, a) in jars.iter().enumerate() {
        let r = a.shape.bounding_radius();
        assert!(
            a.x - r >= -half_w + c.wall_gap - tol
                && a.x + r <= half_w - c.wall_gap + tol
                && a.y - r >= -tol
                && a.y + r <= cupboard.depth() - c.wall_gap + tol,
            "seed {seed}: jar {i} at ({}, {}) too near a wall",
            a.x,
            a.y
        );
        for (j, b) in jars[..i].iter().enumerate() {
            let d = (a.x - b.x).hypot(a.y - b.y);
            assert!(
                d >= r + b.shape.bounding_radius() + c.min_gap - tol,
                "seed {seed}: jars {j} and {i} {d} m apart"
            );
        }
    }

    let target_corridor = layout.corridor.expect("generated layouts have a corridor");
    let hidden = std::iter::once((layout.target, target_corridor)).chain(
        layout
            .decoys
            .iter()
            .copied()
            .zip(layout.decoy_corridors.iter().copied()),
    );
    for (index, corridor) in hidden {
        let jar = &jars[index];
        assert!(
            jar.y >= c.target_min_depth - tol,
            "seed {seed}: hidden jar {index} only {} m deep",
            jar.y
        );
        let (silhouette, visible) = visible_pixels(&camera, &cupboard, jars, index);
        assert!(
            silhouette > 20,
            "seed {seed}: hidden jar {index} barely in view ({silhouette} px)"
        );
        let fraction = visible as f64 / silhouette as f64;
        assert!(
            fraction <= c.max_visible_fraction,
            "seed {seed}: {visible}/{silhouette} = {fraction} of hidden jar {index} is visible"
        );

        assert!(corridor.x[0] >= -half_w - tol && corridor.x[1] <= half_w + tol);
        assert!((corridor.x[1] - corridor.x[0] - c.corridor_width).abs() < 1e-9);
        assert_eq!(corridor.y[0], 0.0);
        assert!((corridor.y[1] - (jar.y + jar.shape.bounding_radius())).abs() < 1e-12);
        let gap = corridor_gap(&corridor, jar);
        assert!(
            (gap - c.corridor_clearance).abs() < 1e-9,
            "seed {seed}: corridor {gap} m from hidden jar {index}'s side"
        );
        for (i, other) in jars.iter().enumerate() {
            if i != index {
                let d = corridor.distance([other.x, other.y]);
                assert!(
                    d >= other.shape.bounding_radius() + c.min_gap - tol,
                    "seed {seed}: jar {i} in the corridor of hidden jar {index}"
                );
            }
        }
    }
}

/// Whether every jar of the layout of `seed` stands still through its first physics step
/// when simulated from the start (not asleep) with nothing touching it. Rarely (about one
/// round jar in 10,000) one does not: rapier's first contacts with the floor tip it by about
/// 0.2 rad, and with the jars asleep (the default) that happens whenever it wakes, whatever
/// woke it. Reach tests leave such layouts out, as they are no fault of the layout.
pub fn jars_stand_still(config: &SceneConfig, seed: u64) -> bool {
    let mut config = config.clone();
    config.physics.jars_start_asleep = false;
    let mut scene =
        Scene::new(&Checked::new(config).expect("valid settings"), seed).expect("scene builds");
    scene.idle(1);
    scene
        .jar_states()
        .iter()
        .all(|jar| jar.disturbance.tilt < 0.01)
}

/// Steps the wrist towards `(x, y)` in moves of at most 1 cm; returns false if blocked.
pub fn go_to(scene: &mut Scene, x: f64, y: f64) -> bool {
    for _ in 0..200 {
        let pose = scene.hand_pose();
        let (dx, dy) = (x - pose.x, y - pose.y);
        if dx.abs() < 1e-9 && dy.abs() < 1e-9 {
            return true;
        }
        let report = scene
            .step(HandCommand {
                dx: dx.clamp(-0.01, 0.01),
                dy: dy.clamp(-0.01, 0.01),
                dyaw: 0.0,
            })
            .expect("finite command");
        if report.blocked.is_some() {
            return false;
        }
    }
    false
}

/// A scripted reach of `layout.jars[index]` through `corridor`: the wrist into the corridor
/// 2 mm inside its edge next to the jar, straight in to the jar's depth less the finger's
/// reach, then a yaw towards the jar until the finger touches it. Panics (naming `seed`) if
/// the wrist is blocked or the finger never touches the jar; afterwards no other jar may
/// have moved 2 mm or tilted 0.05 rad.
pub fn reach_through(scene: &mut Scene, corridor: &Corridor, index: usize, seed: u64) {
    let hand = scene.config().hand.clone();
    let reach = hand.wrist_half_extent + 0.002 + hand.finger_length;
    let jar = scene.layout().jars[index];
    let inner = if corridor.side > 0.0 {
        corridor.x[0]
    } else {
        corridor.x[1]
    };
    let x = inner + corridor.side * (hand.wrist_half_extent + 0.002);
    let start_y = scene.hand_pose().y;
    assert!(
        go_to(scene, x, start_y),
        "seed {seed}: blocked outside the cupboard"
    );
    assert!(
        go_to(scene, x, jar.y - reach),
        "seed {seed}: blocked going in to jar {index}"
    );
    let mut touched = false;
    for _ in 0..30 {
        scene
            .step(HandCommand {
                dyaw: 0.02 * corridor.side,
                ..Default::default()
            })
            .expect("finite command");
        if scene.true_contacts().iter().any(|c| c.jar == index) {
            touched = true;
            break;
        }
    }
    assert!(touched, "seed {seed}: the finger never touched jar {index}");
    for (i, state) in scene.jar_states().iter().enumerate() {
        if i != index {
            assert!(
                state.disturbance.displacement < 2e-3 && state.disturbance.tilt < 0.05,
                "seed {seed}: jar {i} disturbed {:?} reaching jar {index}",
                state.disturbance
            );
        }
    }
}
