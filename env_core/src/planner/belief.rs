//! The probe planner's belief over the cupboard for one episode: the GPIS mean and std of
//! the newest observation, the camera's shadows, the cells the finger swept without contact
//! (no jar can stand there) and the jars it touched (not the target: touching the target
//! ends the episode). From these it gives
//!
//! - [`Belief::hiding_weight`]: where the target's centre may be (in a shadow wide enough
//!   for a jar, deep enough, not swept, not a touched jar), weighted by the GPIS std;
//! - [`Belief::blocked`]: cells that may hold jar material, which the wrist and arm must
//!   keep clear of.
//!
//! A negative mean counts as a jar only where the std is low: far from the data the GPIS
//! extrapolates (behind the jars it often dips below zero). Where the target may hide is
//! judged on the camera's map (`seen`): a touch pulls the mean below zero well beyond the
//! touched jar, so touched jars are excluded by their estimated centres instead.

use super::geometry::PlannerGeometry;

/// Angular resolution of the shadow sweep, rad.
const ANGLE_BIN: f64 = 0.004;
/// A target's centre is at least this far behind the surface that hides it, m.
const HIDDEN_DEPTH: f64 = 0.035;
/// Half width (m) of the shadow needed on each side of a hidden jar's centre.
const SHADOW_HALF_WIDTH: f64 = 0.015;
/// The mean below which a cell counts as (touched or seen) jar, m...
pub const SOLID_MEAN: f64 = 0.002;
/// ...where the std is below this (elsewhere a negative mean is the GPIS extrapolating), m.
const SOLID_STD: f64 = 0.02;
/// Two touches nearer than this (m) estimate one jar.
const SAME_JAR: f64 = 0.02;

/// The belief of one episode (see the module docs). Grids are row-major over the map's
/// cells.
#[derive(Debug, Clone)]
pub struct Belief {
    mean: Vec<f64>,
    std: Vec<f64>,
    /// Range behind the nearest seen surface on each cell's camera ray (−∞ if none).
    behind: Vec<f64>,
    /// The least of `behind` over the rays through the centre and ±`SHADOW_HALF_WIDTH`.
    behind_wide: Vec<f64>,
    /// Distance to the nearest cell the camera saw as jar (capped).
    from_seen: Vec<f64>,
    swept: Vec<bool>,
    touched: Vec<[f64; 2]>,
}

impl Belief {
    /// The belief of the first observation's decoded map (`mean`, `std`, m).
    pub fn new(g: &PlannerGeometry, mean: Vec<f64>, std: Vec<f64>) -> Self {
        let seen: Vec<bool> = solid_cells(&mean, &std, 0.0);
        let (behind, behind_wide) = depth_behind_surfaces(g, &seen);
        let (rows, cols) = g.grid_shape;
        let from_seen = g.distance.of(&seen, rows, cols);
        let cells = mean.len();
        Self {
            mean,
            std,
            behind,
            behind_wide,
            from_seen,
            swept: vec![false; cells],
            touched: Vec::new(),
        }
    }

    /// The map of a new observation (decoded).
    pub fn update(&mut self, mean: Vec<f64>, std: Vec<f64>) {
        self.mean = mean;
        self.std = std;
    }

    /// Per cell, the range behind the nearest surface the camera saw on its ray (−∞ where
    /// the ray met none).
    pub fn behind(&self) -> &[f64] {
        &self.behind
    }

    /// Per cell, whether the finger swept it without touching (no jar centre there).
    pub fn swept(&self) -> &[bool] {
        &self.swept
    }

    /// Cells the map is confident are inside or on a jar (mean below `level`).
    pub fn solid(&self, level: f64) -> Vec<bool> {
        solid_cells(&self.mean, &self.std, level)
    }

    /// How near a finger that touched nothing rules out a jar centre: the smallest jar
    /// radius, less a quarter cell (cell centres stand for their whole cell).
    pub fn sweep_radius(g: &PlannerGeometry) -> f64 {
        g.jar_radius[0] - 0.25 * g.cell
    }

    /// Remembers that the finger segment `joint` to `tip` touched nothing: no jar centre
    /// lies within [`Belief::sweep_radius`] of it.
    pub fn sweep_finger(&mut self, g: &PlannerGeometry, joint: [f64; 2], tip: [f64; 2]) {
        let radius = Self::sweep_radius(g);
        let d = [tip[0] - joint[0], tip[1] - joint[1]];
        let length2 = d[0] * d[0] + d[1] * d[1];
        // Cells farther than the radius (and a margin far above rounding) outside the
        // segment's bounding box are farther than the radius from it.
        let reach = radius + 1e-9;
        let [x_low, x_high] = [joint[0].min(tip[0]) - reach, joint[0].max(tip[0]) + reach];
        let [y_low, y_high] = [joint[1].min(tip[1]) - reach, joint[1].max(tip[1]) + reach];
        for (k, swept) in self.swept.iter_mut().enumerate() {
            let (x, y) = (g.xs[k], g.ys[k]);
            if x < x_low || x > x_high || y < y_low || y > y_high {
                continue;
            }
            let t = if length2 == 0.0 {
                0.0
            } else {
                (((x - joint[0]) * d[0] + (y - joint[1]) * d[1]) / length2).clamp(0.0, 1.0)
            };
            let distance = (x - joint[0] - t * d[0]).hypot(y - joint[1] - t * d[1]);
            *swept |= distance <= radius;
        }
    }

    /// Remembers that no jar centre lies in the cells where `cells` is set.
    pub fn mark_swept(&mut self, cells: impl Iterator<Item = (usize, bool)>) {
        for (k, covered) in cells {
            self.swept[k] |= covered;
        }
    }

    /// Remembers a touched jar (not the target) by its centre estimated from the contact
    /// `point` and the outward `normal`.
    pub fn add_touch(&mut self, g: &PlannerGeometry, point: [f64; 2], normal: [f64; 2]) {
        let radius = (g.jar_radius[0] + g.jar_radius[1]) / 2.0;
        let centre = [point[0] - normal[0] * radius, point[1] - normal[1] * radius];
        if self
            .touched
            .iter()
            .all(|c| (centre[0] - c[0]).hypot(centre[1] - c[1]) > SAME_JAR)
        {
            self.touched.push(centre);
        }
    }

    fn near_touched(&self, g: &PlannerGeometry, radius: f64) -> Vec<bool> {
        let mut near = vec![false; self.swept.len()];
        for &[cx, cy] in &self.touched {
            for (k, cell) in near.iter_mut().enumerate() {
                let (dx, dy) = (g.xs[k] - cx, g.ys[k] - cy);
                // hypot is at least each leg: a leg beyond the radius puts the cell beyond it.
                *cell |= dx.abs() <= radius && dy.abs() <= radius && dx.hypot(dy) <= radius;
            }
        }
        near
    }

    /// Where the target's centre may be, weighted by the GPIS std (0 elsewhere). `relaxed`
    /// drops the shadow and depth conditions (when nothing else is left).
    pub fn hiding_weight(&self, g: &PlannerGeometry, relaxed: bool) -> Vec<f64> {
        let r_min = g.jar_radius[0];
        let near = self.near_touched(g, 2.0 * r_min);
        let half_width = 0.5 * g.width - g.wall_gap - r_min;
        let deepest = g.depth - g.wall_gap - r_min;
        (0..self.swept.len())
            .map(|k| {
                let mut fits = g.xs[k].abs() <= half_width
                    && g.ys[k] <= deepest
                    && !self.swept[k]
                    && !near[k]
                    && self.from_seen[k] >= 0.5 * r_min;
                if !relaxed {
                    fits &= self.behind_wide[k] >= HIDDEN_DEPTH
                        && g.ys[k] >= g.target_min_depth - 0.5 * g.cell;
                }
                if fits {
                    self.std[k] + 0.01
                } else {
                    0.0
                }
            })
            .collect()
    }

    /// Cells that may hold jar material: seen or touched surfaces and insides, touched
    /// jars' footprints, and unswept shadows.
    pub fn blocked(&self, g: &PlannerGeometry) -> Vec<bool> {
        let near = self.near_touched(g, g.jar_radius[1]);
        let solid = self.solid(SOLID_MEAN);
        (0..self.swept.len())
            .map(|k| solid[k] || (self.behind[k] > 0.0 && !self.swept[k]) || near[k])
            .collect()
    }
}

fn solid_cells(mean: &[f64], std: &[f64], level: f64) -> Vec<bool> {
    mean.iter()
        .zip(std)
        .map(|(&m, &s)| m < level && s < SOLID_STD)
        .collect()
}

/// Per cell: range behind the nearest `solid` cell on its camera ray (−∞ if none), and the
/// least of that over the rays through the cell's centre and ±`SHADOW_HALF_WIDTH` beside
/// it (positive: a jar-wide shadow).
fn depth_behind_surfaces(g: &PlannerGeometry, solid: &[bool]) -> (Vec<f64>, Vec<f64>) {
    let (angles, ranges) = (&g.camera_bearings, &g.camera_ranges);
    let min = angles.iter().copied().fold(f64::INFINITY, f64::min);
    let max = angles.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let low = min - 0.5;
    let bins = ((max + 0.5 - low) / ANGLE_BIN) as usize + 1;
    let mut front = vec![f64::INFINITY; bins];
    for k in (0..solid.len()).filter(|&k| solid[k]) {
        let half = 0.5 * g.cell / ranges[k];
        let first = ((angles[k] - half - low) / ANGLE_BIN) as usize;
        let last = (((angles[k] + half - low) / ANGLE_BIN) as usize).min(bins - 1);
        for bin in &mut front[first.min(bins)..=last] {
            *bin = bin.min(ranges[k]);
        }
    }
    let behind_on = |k: usize, side: f64| {
        let index = (angles[k] + side * SHADOW_HALF_WIDTH / ranges[k] - low) / ANGLE_BIN;
        let index = (index as i64).clamp(0, bins as i64 - 1) as usize;
        ranges[k] - front[index]
    };
    let behind: Vec<f64> = (0..solid.len()).map(|k| behind_on(k, 0.0)).collect();
    let wide = (0..solid.len())
        .map(|k| behind[k].min(behind_on(k, -1.0)).min(behind_on(k, 1.0)))
        .collect();
    (behind, wide)
}
