//! Everything tunable about an episode: the scene, the map, the reward and the episode end.

use super::error::EpisodeError;
use crate::scene::SceneConfig;

/// Which map the agent sees.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MapMode {
    /// GPIS posterior mean and standard deviation.
    Gpis,
    /// A plain log-odds evidence grid from the same depth and touch points.
    Occupancy,
    /// No map: the agent sees only proprioception and touch.
    None,
}

impl MapMode {
    /// Parses `"gpis"`, `"occupancy"` or `"none"`.
    pub fn parse(text: &str) -> Option<Self> {
        match text {
            "gpis" => Some(Self::Gpis),
            "occupancy" => Some(Self::Occupancy),
            "none" => Some(Self::None),
            _ => None,
        }
    }

    /// The name [`Self::parse`] takes.
    pub fn name(self) -> &'static str {
        match self {
            Self::Gpis => "gpis",
            Self::Occupancy => "occupancy",
            Self::None => "none",
        }
    }
}

/// How the map is built from depth and touch, and how it is rendered as an image.
#[derive(Debug, Clone, PartialEq)]
pub struct MapConfig {
    /// Which map.
    pub mode: MapMode,
    /// (H, W) of the map grid over the cupboard's interior; cells must be square.
    pub grid_shape: (usize, usize),
    /// Constant prior mean of f, m (positive: unobserved space reads as free).
    pub prior_mean: f64,
    /// Diameter of the paper's circle prior placed behind each depth cluster, m; `None`
    /// for no circle prior.
    pub circle_prior_diameter: Option<f64>,
    /// GPIS noise standard deviation of a depth point, m.
    pub depth_noise_std: f64,
    /// The depth slice is thinned (evenly) to at most this many points before it enters the
    /// GPIS: the prior's cost grows as rows² · cells, and reset must stay fast.
    pub max_prior_depth_points: usize,
    /// Free-space evidence: a value observation f = +offset this far in front of each depth
    /// point along its camera ray, m; `None` to use surface points only.
    pub free_space_offset: Option<f64>,
    /// GPIS noise standard deviation of a contact's position, m.
    pub contact_noise_std: f64,
    /// GPIS noise standard deviation of each contact-normal component.
    pub normal_noise_std: f64,
    /// A contact is skipped when the map's variance at its point is already below this, m².
    pub skip_below_variance: f64,
    /// Most GP rows per episode; contacts beyond it are dropped and counted.
    pub max_rows: usize,
    /// |mean| that saturates the mean channel, m.
    pub mean_scale: f64,
    /// Standard deviation that saturates the std channel, m.
    pub std_scale: f64,
}

impl Default for MapConfig {
    fn default() -> Self {
        Self {
            mode: MapMode::Gpis,
            grid_shape: (40, 80),
            prior_mean: 0.01,
            circle_prior_diameter: None,
            depth_noise_std: 0.003,
            max_prior_depth_points: 96,
            free_space_offset: Some(0.01),
            contact_noise_std: 0.001,
            normal_noise_std: 0.1,
            skip_below_variance: 1e-5,
            max_rows: 1500,
            mean_scale: 0.05,
            std_scale: 0.1,
        }
    }
}

/// Reward weights. Each term is reported on its own in the step info.
#[derive(Debug, Clone, PartialEq)]
pub struct RewardConfig {
    /// Paid once when the finger touches the target.
    pub success: f64,
    /// Paid (negated) every step.
    pub step_cost: f64,
    /// Per metre of added jar displacement (summed over jars), negated.
    pub displacement: f64,
    /// Paid (negated) when a jar tips over. A tip ends the episode, so it must cost more
    /// than the step costs it saves (`max_steps · step_cost` = 2 at the defaults), or
    /// knocking a jar over early is the cheapest way out of a hard layout.
    pub tip: f64,
    /// Potential-based shaping, per metre the fingertip's path distance to the target
    /// shrinks (see [`super::approach`]); 0 (the default) leaves the task's reward alone.
    pub approach: f64,
}

impl Default for RewardConfig {
    fn default() -> Self {
        Self {
            success: 1.0,
            step_cost: 0.01,
            displacement: 10.0,
            tip: 3.0,
            approach: 0.0,
        }
    }
}

/// One episode's configuration.
#[derive(Debug, Clone, PartialEq)]
pub struct EpisodeConfig {
    /// The physical scene.
    pub scene: SceneConfig,
    /// The map.
    pub map: MapConfig,
    /// The reward.
    pub reward: RewardConfig,
    /// Episode length used for the "time left" entry of the proprioception (the time limit
    /// itself is the registered `max_episode_steps`).
    pub max_steps: usize,
    /// A jar whose axis leans more than this from vertical has tipped over, rad.
    pub tip_angle: f64,
}

impl Default for EpisodeConfig {
    fn default() -> Self {
        Self {
            scene: SceneConfig::default(),
            map: MapConfig::default(),
            reward: RewardConfig::default(),
            max_steps: 200,
            tip_angle: 0.5,
        }
    }
}

fn in_range(
    what: &'static str,
    value: f64,
    ok: bool,
    expected: &'static str,
) -> Result<(), EpisodeError> {
    if value.is_finite() && ok {
        Ok(())
    } else {
        Err(EpisodeError::OutOfRange {
            what,
            expected,
            value,
        })
    }
}

impl EpisodeConfig {
    /// The map's bounds `[[x0, x1], [y0, y1]]`: the cupboard's interior in the slice plane.
    pub fn map_bounds(&self) -> [[f64; 2]; 2] {
        let half_width = self.scene.cupboard.width / 2.0;
        [[-half_width, half_width], [0.0, self.scene.cupboard.depth]]
    }

    /// Checks every field (the scene's own checks included).
    pub fn validate(&self) -> Result<(), EpisodeError> {
        self.scene.validate()?;
        let map = &self.map;
        let (h, w) = map.grid_shape;
        let (width, depth) = (self.scene.cupboard.width, self.scene.cupboard.depth);
        let aspect = width / depth;
        let square = (w as f64 / h as f64 - aspect).abs() < 1e-9 * aspect;
        if h < 36 || w < 36 || !square {
            return Err(EpisodeError::GridShape {
                height_cells: h,
                width_cells: w,
                width,
                depth,
                aspect,
            });
        }
        let m = map.prior_mean;
        in_range("prior_mean", m, true, "finite")?;
        if let Some(d) = map.circle_prior_diameter {
            in_range("circle_prior_diameter", d, d > 0.0, "> 0")?;
        }
        if let Some(d) = map.free_space_offset {
            in_range("free_space_offset", d, d > 0.0, "> 0")?;
        }
        for (what, v) in [
            ("depth_noise_std", map.depth_noise_std),
            ("contact_noise_std", map.contact_noise_std),
            ("normal_noise_std", map.normal_noise_std),
            ("skip_below_variance", map.skip_below_variance),
            ("reward_success", self.reward.success),
            ("reward_step_cost", self.reward.step_cost),
            ("reward_displacement", self.reward.displacement),
            ("reward_tip", self.reward.tip),
            ("reward_approach", self.reward.approach),
        ] {
            in_range(what, v, v >= 0.0, ">= 0")?;
        }
        for (what, v) in [("mean_scale", map.mean_scale), ("std_scale", map.std_scale)] {
            in_range(what, v, v > 0.0, "> 0")?;
        }
        let points = map.max_prior_depth_points as f64;
        in_range("max_prior_depth_points", points, points >= 1.0, ">= 1")?;
        let rows = map.max_rows as f64;
        in_range("max_rows", rows, map.max_rows >= 1, ">= 1")?;
        let steps = self.max_steps as f64;
        in_range("max_steps", steps, self.max_steps >= 1, ">= 1")?;
        let tip = self.tip_angle;
        in_range("tip_angle", tip, tip > 0.0 && tip < 1.6, "in (0, pi/2]")?;
        Ok(())
    }
}
