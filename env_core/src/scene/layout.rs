//! The seeded layout generator: upright, non-overlapping jars (3–7 by default, up to
//! [`MAX_JARS`]), one of them the target, hidden from the depth camera behind an occluder,
//! with a jar-free corridor from the opening to the target's side so the finger can reach it
//! without pushing through other jars. With `hidden_decoys` = k > 0, k non-target jars are
//! hidden the same way, each behind its own occluder and with its own corridor, so that
//! neither looking nor reachability tells the target from them.
//!
//! Rejection sampling with a ChaCha8 stream seeded from the scene seed, so a seed always
//! gives the same layout. An attempt is kept only if:
//! - every jar's bounding circle is at least `min_gap` from every other and `wall_gap` from
//!   the side and back walls;
//! - every corridor (an axis-aligned lane `corridor_width` wide, from the opening `y = 0` to
//!   its hidden jar's far side, its inner edge `corridor_clearance` beside that jar) holds no
//!   part of any other jar's bounding circle, widened by `min_gap`;
//! - every hidden jar's visible fraction (see [`super::visibility`]) is at most
//!   `max_visible_fraction`.
//!
//! The hidden jars (the target, then the decoys) and their occluders are each drawn once per
//! attempt, and an attempt is dropped as soon as one does not fit (no retry within it): the
//! kept positions of the hidden jars are then independent draws from one distribution,
//! conditioned on constraints that treat every hidden jar alike, so the target's place among
//! them tells nothing beyond its size (the target's shape and size are drawn like a decoy's
//! when `target_shape` is 'any'). The remaining jars are drawn by rejection within the
//! attempt.

use rand::seq::SliceRandom;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::config::{LayoutConfig, TargetShape, MAX_JARS};
use super::cupboard::Cupboard;
use super::depth_camera::DepthCamera;
use super::error::SceneError;
use super::footprint::JarShape;
use super::jar::JarSpec;
use super::visibility::{target_visibility, Visibility};

/// A jar-free, axis-aligned lane in the slice plane from the opening to a hidden jar's side.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Corridor {
    /// `[x_min, x_max]`, m.
    pub x: [f64; 2],
    /// `[y_min, y_max]`: from the opening (0) to the hidden jar's far side, m.
    pub y: [f64; 2],
    /// +1 if the lane is on the hidden jar's +x side, −1 if on its −x side.
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

/// The jars of one episode, which is the target, which are hidden decoys, and the corridors
/// to them.
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
    /// Indices in `jars` of the hidden decoys (non-target jars hidden like the target), in
    /// increasing order; empty unless `hidden_decoys` > 0.
    pub decoys: Vec<usize>,
    /// The clear lane to each hidden decoy: `decoy_corridors[i]` leads to `decoys[i]`
    /// (generated layouts have one per decoy; an explicit layout may have none).
    pub decoy_corridors: Vec<Corridor>,
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
            decoys: Vec::new(),
            decoy_corridors: Vec::new(),
        }
    }

    /// Every corridor: the target's (if any), then the decoys'.
    pub fn corridors(&self) -> impl Iterator<Item = &Corridor> {
        self.corridor.iter().chain(&self.decoy_corridors)
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
/// placed jars (bounding circles `min_gap` apart) and out of every corridor.
fn fits(
    jar: &JarSpec,
    placed: &[JarSpec],
    corridors: &[Corridor],
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
        && corridors
            .iter()
            .all(|corridor| corridor.distance([jar.x, jar.y]) >= r + config.min_gap)
        && placed.iter().all(|other| {
            (jar.x - other.x).hypot(jar.y - other.y)
                >= r + other.shape.bounding_radius() + config.min_gap
        })
}

/// Whether `corridor` holds no part of any of `placed` (bounding circles widened by
/// `min_gap`).
fn corridor_clear(corridor: &Corridor, placed: &[JarSpec], config: &LayoutConfig) -> bool {
    placed.iter().all(|jar| {
        corridor.distance([jar.x, jar.y]) >= jar.shape.bounding_radius() + config.min_gap
    })
}

/// The jar's position as a hidden jar: uniform over the part of the interior at least
/// `target_min_depth` deep where its bounding circle keeps `wall_gap` from the walls. False
/// (and nothing drawn) when that part is empty.
fn place_hidden(
    rng: &mut ChaCha8Rng,
    jar: &mut JarSpec,
    cupboard: &Cupboard,
    config: &LayoutConfig,
) -> bool {
    let r = jar.shape.bounding_radius();
    let half_w = 0.5 * cupboard.width();
    let x_range = [-half_w + config.wall_gap + r, half_w - config.wall_gap - r];
    let y_range = [
        config.target_min_depth,
        cupboard.depth() - config.wall_gap - r,
    ];
    if x_range[0] > x_range[1] || y_range[0] > y_range[1] {
        return false;
    }
    jar.x = uniform(rng, x_range);
    jar.y = uniform(rng, y_range);
    true
}

/// The lane beside a hidden jar: on the side away from the camera's axis first (the occluder
/// sits on the camera's side of the jar's line of sight, so that side stays free), else on
/// the other side; None when neither lies inside the cupboard. It depends on the jar's
/// position alone, so every hidden jar gets its lane by the same rule.
fn corridor_beside(
    jar: &JarSpec,
    cam_x: f64,
    cupboard: &Cupboard,
    config: &LayoutConfig,
) -> Option<Corridor> {
    let half_w = 0.5 * cupboard.width();
    let outer = if jar.x >= cam_x { 1.0 } else { -1.0 };
    let hx = jar.half_extent_x();
    let r = jar.shape.bounding_radius();
    [outer, -outer].into_iter().find_map(|side: f64| {
        let inner = jar.x + side * (hx + config.corridor_clearance);
        let far = inner + side * config.corridor_width;
        let x = [inner.min(far), inner.max(far)];
        (x[0] >= -half_w && x[1] <= half_w).then_some(Corridor {
            x,
            y: [0.0, jar.y + r],
            side,
        })
    })
}

/// Draws the occluder of a hidden jar: a non-target jar on the line of sight from the camera
/// to the hidden jar's centre (within 5 mm across it), in front of the hidden jar. None when
/// there is no room in front of it (nothing but the shape and size drawn then).
fn draw_occluder(
    rng: &mut ChaCha8Rng,
    config: &LayoutConfig,
    hidden: &JarSpec,
    camera: [f64; 3],
) -> Option<JarSpec> {
    let [cam_x, cam_y, _] = camera;
    let round = rng.random_bool(config.round_fraction);
    let mut occluder = sample_jar(rng, config, round);
    let r_h = hidden.shape.bounding_radius();
    let r_o = occluder.shape.bounding_radius();
    let y_range = [r_o, hidden.y - r_h - r_o - config.min_gap];
    if y_range[0] > y_range[1] {
        return None;
    }
    occluder.y = uniform(rng, y_range);
    let along = (occluder.y - cam_y) / (hidden.y - cam_y);
    occluder.x = cam_x + (hidden.x - cam_x) * along + uniform(rng, [-0.005, 0.005]);
    Some(occluder)
}

impl Layout {
    /// Generates the layout of `seed`. Cost: O(attempts × jars²) plus one visibility
    /// measurement per hidden jar of a candidate (about a millisecond each).
    ///
    /// With `hidden_decoys` = 0 the random stream is drawn in the order the generator has
    /// always drawn it, so every seed gives the layout it always gave (the pinned rollouts
    /// and recorded evaluations depend on it; `tests/scene_layouts_unchanged.rs`).
    pub fn generate(
        config: &LayoutConfig,
        cupboard: &Cupboard,
        camera: &DepthCamera,
        seed: u64,
    ) -> Result<Self, SceneError> {
        Self::generate_counted(config, cupboard, camera, seed).0
    }

    /// [`Self::generate`], and the attempts it made (the kept one included): what measures
    /// how hard a layout config is for the generator (`examples/layout_rates.rs`).
    pub fn generate_counted(
        config: &LayoutConfig,
        cupboard: &Cupboard,
        camera: &DepthCamera,
        seed: u64,
    ) -> (Result<Self, SceneError>, usize) {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let half_w = 0.5 * cupboard.width();
        let depth = cupboard.depth();
        let cam = camera.position();
        let decoy_count = config.hidden_decoys;
        let mut last_count = config.jar_count[0];
        'attempt: for attempt in 1..=config.max_attempts {
            let n = rng.random_range(config.jar_count[0]..=config.jar_count[1]);
            last_count = n;
            // Every hidden jar takes two jars of the count, itself and its occluder. A checked
            // config's counts always hold them (`jar_count`'s low end is at least
            // 2 + 2 * hidden_decoys); with an unchecked one no attempt succeeds.
            if decoy_count > 0 && n < 2 + 2 * decoy_count {
                continue;
            }
            let target_round = match config.target_shape {
                TargetShape::Round => true,
                TargetShape::Square => false,
                TargetShape::Any => rng.random_bool(config.round_fraction),
            };
            let mut target = sample_jar(&mut rng, config, target_round);
            if !place_hidden(&mut rng, &mut target, cupboard, config) {
                continue;
            }
            let Some(corridor) = corridor_beside(&target, cam[0], cupboard, config) else {
                continue;
            };
            let mut corridors = vec![corridor];
            let mut placed = vec![target];
            if n > 1 {
                let Some(occluder) = draw_occluder(&mut rng, config, &target, cam) else {
                    continue;
                };
                if !fits(&occluder, &placed, &corridors, cupboard, config) {
                    continue;
                }
                placed.push(occluder);
            }

            // Each decoy like the target: hidden, with its lane and its occluder.
            let mut decoys = Vec::with_capacity(decoy_count);
            for _ in 0..decoy_count {
                let round = rng.random_bool(config.round_fraction);
                let mut decoy = sample_jar(&mut rng, config, round);
                if !place_hidden(&mut rng, &mut decoy, cupboard, config) {
                    continue 'attempt;
                }
                let Some(lane) = corridor_beside(&decoy, cam[0], cupboard, config) else {
                    continue 'attempt;
                };
                if !fits(&decoy, &placed, &corridors, cupboard, config)
                    || !corridor_clear(&lane, &placed, config)
                {
                    continue 'attempt;
                }
                corridors.push(lane);
                decoys.push(placed.len());
                placed.push(decoy);
                let Some(occluder) = draw_occluder(&mut rng, config, &decoy, cam) else {
                    continue 'attempt;
                };
                if !fits(&occluder, &placed, &corridors, cupboard, config) {
                    continue 'attempt;
                }
                placed.push(occluder);
            }

            for _ in placed.len()..n {
                let round = rng.random_bool(config.round_fraction);
                let mut jar = sample_jar(&mut rng, config, round);
                let r = jar.shape.bounding_radius();
                let xr = [-half_w + config.wall_gap + r, half_w - config.wall_gap - r];
                let yr = [r, depth - config.wall_gap - r];
                let mut found = false;
                for _ in 0..200 {
                    jar.x = uniform(&mut rng, xr);
                    jar.y = uniform(&mut rng, yr);
                    if fits(&jar, &placed, &corridors, cupboard, config) {
                        found = true;
                        break;
                    }
                }
                if !found {
                    continue 'attempt;
                }
                placed.push(jar);
            }

            // The jars' order is drawn too, so that an index carries no information. Without
            // decoys only the target moves (to a uniform index), as it always has; with
            // decoys every jar is shuffled, so the target's index is distributed like each
            // decoy's.
            let mut order: Vec<usize> = (0..n).collect();
            if decoy_count == 0 {
                let target_index = rng.random_range(0..n);
                order.remove(0);
                order.insert(target_index, 0);
            } else {
                order.shuffle(&mut rng);
            }
            // `order[new] = old`; `position[old] = new`.
            let mut position = vec![0; n];
            for (new, &old) in order.iter().enumerate() {
                position[old] = new;
            }
            let jars: Vec<JarSpec> = order.iter().map(|&old| placed[old]).collect();
            let target_index = position[0];
            let mut hidden: Vec<(usize, Corridor)> = decoys
                .iter()
                .zip(&corridors[1..])
                .map(|(&old, &lane)| (position[old], lane))
                .collect();
            hidden.sort_by_key(|&(index, _)| index);

            let visibility = target_visibility(camera, cupboard, &jars, target_index);
            if visibility.fraction() > config.max_visible_fraction {
                continue;
            }
            for &(index, _) in &hidden {
                let decoy = target_visibility(camera, cupboard, &jars, index);
                if decoy.fraction() > config.max_visible_fraction {
                    continue 'attempt;
                }
            }
            let layout = Self {
                jars,
                target: target_index,
                corridor: Some(corridor),
                visibility,
                decoys: hidden.iter().map(|&(index, _)| index).collect(),
                decoy_corridors: hidden.iter().map(|&(_, lane)| lane).collect(),
            };
            return (Ok(layout), attempt);
        }
        let error = SceneError::LayoutNotFound {
            seed,
            attempts: config.max_attempts,
            jars: last_count,
            hidden_decoys: decoy_count,
            max_visible_fraction: config.max_visible_fraction,
        };
        (Err(error), config.max_attempts)
    }

    /// Checks an explicit layout: a valid target index, valid decoy indices (increasing, not
    /// the target) with no corridors or one each, 1 to [`MAX_JARS`] jars with finite positive
    /// sizes standing inside the interior and below its top, bounding circles not
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
        for (k, &decoy) in self.decoys.iter().enumerate() {
            if decoy >= self.jars.len() || decoy == self.target {
                return bad(format!(
                    "decoy indices must be < {} (the jar count) and not the target's ({}), got {}",
                    self.jars.len(),
                    self.target,
                    decoy
                ));
            }
            if k > 0 && decoy <= self.decoys[k - 1] {
                return bad(format!(
                    "decoy indices must be increasing, got {:?}",
                    self.decoys
                ));
            }
        }
        if !self.decoy_corridors.is_empty() && self.decoy_corridors.len() != self.decoys.len() {
            return bad(format!(
                "decoy_corridors must be empty or one per decoy ({}), got {}",
                self.decoys.len(),
                self.decoy_corridors.len()
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
