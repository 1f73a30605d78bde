//! The seeded layout generator: 3–7 upright, non-overlapping jars, one of them the target,
//! hidden from the depth camera behind an occluder, with a jar-free corridor from the opening
//! to the target's side so the finger can reach it without pushing through other jars.
//!
//! Rejection sampling with a ChaCha8 stream seeded from the scene seed, so a seed always
//! gives the same layout. An attempt is kept only if:
//! - every jar's bounding circle is at least `min_gap` from every other and `wall_gap` from
//!   the side and back walls;
//! - the corridor (an axis-aligned lane `corridor_width` wide, from the opening `y = 0` to the
//!   target's far side, its inner edge `corridor_clearance` beside the target) holds no part of
//!   any jar's bounding circle, widened by `min_gap`;
//! - the target's visible fraction (see [`super::visibility`]) is at most
//!   `max_visible_fraction`.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::config::{LayoutConfig, TargetShape, MAX_JARS};
use super::cupboard::Cupboard;
use super::depth_camera::DepthCamera;
use super::error::SceneError;
use super::footprint::JarShape;
use super::jar::JarSpec;
use super::visibility::{target_visibility, Visibility};

/// A jar-free, axis-aligned lane in the slice plane from the opening to the target's side.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Corridor {
    /// `[x_min, x_max]`, m.
    pub x: [f64; 2],
    /// `[y_min, y_max]`: from the opening (0) to the target's far side, m.
    pub y: [f64; 2],
    /// +1 if the lane is on the target's +x side, −1 if on its −x side.
    pub side: f64,
}

impl Corridor {
    /// Distance from a point to the lane (0 inside), m.
    pub fn distance(&self, point: [f64; 2]) -> f64 {
        let dx = (self.x[0] - point[0]).max(point[0] - self.x[1]).max(0.0);
        let dy = (self.y[0] - point[1]).max(point[1] - self.y[1]).max(0.0);
        dx.hypot(dy)
    }
}

/// The jars of one episode, which is the target, and the corridor to it.
#[derive(Debug, Clone, PartialEq)]
pub struct Layout {
    /// The jars, in body-insertion order.
    pub jars: Vec<JarSpec>,
    /// Index of the target in `jars`.
    pub target: usize,
    /// The clear lane to the target (generated layouts always have one).
    pub corridor: Option<Corridor>,
    /// The target's visibility from the camera, measured by ray casting.
    pub visibility: Visibility,
}

impl Layout {
    /// A layout of one jar, which is the target, with no corridor: the fixture of touch,
    /// deflection and wall experiments. Its visibility is measured when a scene is built
    /// from it ([`crate::scene::Scene::from_layout`]).
    pub fn lone_jar(jar: JarSpec) -> Self {
        Self {
            jars: vec![jar],
            target: 0,
            corridor: None,
            visibility: Visibility::default(),
        }
    }
}

fn uniform(rng: &mut ChaCha8Rng, [lo, hi]: [f64; 2]) -> f64 {
    lo + (hi - lo) * rng.random::<f64>()
}

fn sample_jar(rng: &mut ChaCha8Rng, config: &LayoutConfig, round: bool) -> JarSpec {
    let shape = if round {
        JarShape::Round {
            radius: 0.5 * uniform(rng, config.round_diameter),
        }
    } else {
        JarShape::Square {
            half_side: 0.5 * uniform(rng, config.square_side),
        }
    };
    let yaw = if round {
        0.0
    } else {
        uniform(rng, [0.0, std::f64::consts::FRAC_PI_2])
    };
    JarSpec {
        shape,
        height: uniform(rng, config.jar_height),
        mass: uniform(rng, config.jar_mass),
        x: 0.0,
        y: 0.0,
        yaw,
    }
}

/// Whether a jar at its position fits: inside the walls (with `wall_gap`), away from the
/// placed jars (bounding circles `min_gap` apart) and out of the corridor.
fn fits(
    jar: &JarSpec,
    placed: &[JarSpec],
    corridor: &Corridor,
    cupboard: &Cupboard,
    config: &LayoutConfig,
) -> bool {
    let r = jar.shape.bounding_radius();
    let half_w = 0.5 * cupboard.width();
    let inside = jar.x - r >= -half_w + config.wall_gap
        && jar.x + r <= half_w - config.wall_gap
        && jar.y - r >= 0.0
        && jar.y + r <= cupboard.depth() - config.wall_gap;
    inside
        && corridor.distance([jar.x, jar.y]) >= r + config.min_gap
        && placed.iter().all(|other| {
            (jar.x - other.x).hypot(jar.y - other.y)
                >= r + other.shape.bounding_radius() + config.min_gap
        })
}

impl Layout {
    /// Generates the layout of `seed`. Cost: O(attempts × jars²) plus one visibility
    /// measurement per candidate (about a millisecond).
    pub fn generate(
        config: &LayoutConfig,
        cupboard: &Cupboard,
        camera: &DepthCamera,
        seed: u64,
    ) -> Result<Self, SceneError> {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let half_w = 0.5 * cupboard.width();
        let depth = cupboard.depth();
        let [cam_x, cam_y, _] = camera.position();
        let mut last_count = config.jar_count[0];
        for _ in 0..config.max_attempts {
            let n = rng.random_range(config.jar_count[0]..=config.jar_count[1]);
            last_count = n;
            let target_round = match config.target_shape {
                TargetShape::Round => true,
                TargetShape::Square => false,
                TargetShape::Any => rng.random_bool(config.round_fraction),
            };
            let mut target = sample_jar(&mut rng, config, target_round);
            let r_t = target.shape.bounding_radius();
            let x_range = [
                -half_w + config.wall_gap + r_t,
                half_w - config.wall_gap - r_t,
            ];
            let y_range = [config.target_min_depth, depth - config.wall_gap - r_t];
            if x_range[0] > x_range[1] || y_range[0] > y_range[1] {
                continue;
            }
            target.x = uniform(&mut rng, x_range);
            target.y = uniform(&mut rng, y_range);

            // The lane on the side away from the camera's axis first: the occluder sits on the
            // camera's side of the target's line of sight, so that side stays free.
            let outer = if target.x >= cam_x { 1.0 } else { -1.0 };
            let hx = target.half_extent_x();
            let corridor = [outer, -outer].into_iter().find_map(|side: f64| {
                let inner = target.x + side * (hx + config.corridor_clearance);
                let far = inner + side * config.corridor_width;
                let x = [inner.min(far), inner.max(far)];
                (x[0] >= -half_w && x[1] <= half_w).then_some(Corridor {
                    x,
                    y: [0.0, target.y + r_t],
                    side,
                })
            });
            let Some(corridor) = corridor else {
                continue;
            };

            let mut placed = vec![target];
            if n > 1 {
                // The occluder: on the line of sight from the camera to the target's centre.
                let round = rng.random_bool(config.round_fraction);
                let mut occluder = sample_jar(&mut rng, config, round);
                let r_o = occluder.shape.bounding_radius();
                let y_o_range = [r_o, target.y - r_t - r_o - config.min_gap];
                if y_o_range[0] > y_o_range[1] {
                    continue;
                }
                occluder.y = uniform(&mut rng, y_o_range);
                let along = (occluder.y - cam_y) / (target.y - cam_y);
                occluder.x =
                    cam_x + (target.x - cam_x) * along + uniform(&mut rng, [-0.005, 0.005]);
                if !fits(&occluder, &placed, &corridor, cupboard, config) {
                    continue;
                }
                placed.push(occluder);
            }
            let mut all_fit = true;
            for _ in 2..n {
                let round = rng.random_bool(config.round_fraction);
                let mut jar = sample_jar(&mut rng, config, round);
                let r = jar.shape.bounding_radius();
                let xr = [-half_w + config.wall_gap + r, half_w - config.wall_gap - r];
                let yr = [r, depth - config.wall_gap - r];
                let mut found = false;
                for _ in 0..200 {
                    jar.x = uniform(&mut rng, xr);
                    jar.y = uniform(&mut rng, yr);
                    if fits(&jar, &placed, &corridor, cupboard, config) {
                        found = true;
                        break;
                    }
                }
                if !found {
                    all_fit = false;
                    break;
                }
                placed.push(jar);
            }
            if !all_fit {
                continue;
            }
            // The target's index is drawn too, so that it carries no information.
            let target_index = rng.random_range(0..n);
            let target_spec = placed.remove(0);
            placed.insert(target_index, target_spec);
            let visibility = target_visibility(camera, cupboard, &placed, target_index);
            if visibility.fraction() > config.max_visible_fraction {
                continue;
            }
            return Ok(Self {
                jars: placed,
                target: target_index,
                corridor: Some(corridor),
                visibility,
            });
        }
        Err(SceneError::LayoutNotFound {
            seed,
            attempts: config.max_attempts,
            jars: last_count,
            max_visible_fraction: config.max_visible_fraction,
        })
    }

    /// Checks an explicit layout: a valid target index, 1 to [`MAX_JARS`] jars with finite
    /// positive sizes standing inside the interior and below its top, bounding circles not
    /// overlapping.
    pub fn check(&self, cupboard: &Cupboard) -> Result<(), SceneError> {
        let bad = |reason: String| Err(SceneError::InvalidLayout { reason });
        if self.jars.is_empty() || self.jars.len() > MAX_JARS {
            return bad(format!(
                "expected 1 to {MAX_JARS} jars, got {}",
                self.jars.len()
            ));
        }
        if self.target >= self.jars.len() {
            return bad(format!(
                "target index must be < {} (the jar count), got {}",
                self.jars.len(),
                self.target
            ));
        }
        let half_w = 0.5 * cupboard.width();
        for (i, jar) in self.jars.iter().enumerate() {
            let numbers = [
                jar.x,
                jar.y,
                jar.yaw,
                jar.height,
                jar.mass,
                jar.shape.half_width(),
            ];
            if numbers.iter().any(|v| !v.is_finite()) {
                return bad(format!("jar {i} has a non-finite number: {jar:?}"));
            }
            if jar.height <= 0.0 || jar.mass <= 0.0 || jar.shape.half_width() <= 0.0 {
                return bad(format!(
                    "jar {i} must have positive size and mass, got {jar:?}"
                ));
            }
            let e = jar.half_extent_x();
            if jar.x - e < -half_w
                || jar.x + e > half_w
                || jar.y - e < 0.0
                || jar.y + e > cupboard.depth()
            {
                return bad(format!(
                    "jar {i} at ({}, {}) must lie inside the interior: x from {} to {}, y from 0 to {}",
                    jar.x,
                    jar.y,
                    -half_w,
                    half_w,
                    cupboard.depth()
                ));
            }
            if jar.height >= cupboard.height() {
                return bad(format!(
                    "jar {i} height must be below the cupboard height {}, got {}",
                    cupboard.height(),
                    jar.height
                ));
            }
            for (j, other) in self.jars.iter().enumerate().take(i) {
                let d = (jar.x - other.x).hypot(jar.y - other.y);
                if d < jar.shape.bounding_radius() + other.shape.bounding_radius() {
                    return bad(format!("jars {j} and {i} overlap (centres {d} m apart)"));
                }
            }
        }
        Ok(())
    }
}
