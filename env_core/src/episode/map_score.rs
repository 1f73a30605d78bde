//! The map task's score (`docs/DESIGN.md` §4.4): how well the episode's evidence, the depth
//! camera's first look and every touch, reconstructs the cupboard's contents. The same for
//! every agent whatever map it observes, so that maps are compared as observations only:
//! the reconstruction is the core's exact GPIS with the episode's GPIS settings, fed what
//! the agent's map is fed, and scored against the jars' true footprints by
//!
//! - the IoU of its interior (mean < 0) with the footprints on the map's grid, and
//! - the outline distance: the mean of the two directed mean distances between its zero
//!   level set and the true outlines ([`super::outline`]: truth to estimate finds what the
//!   map missed, estimate to truth what it made up), each point's distance capped.
//!
//! The reward is the outline distance's shrink. Cost per step (measured once per step, not
//! per motion): the GPIS's own update, O(G) for the IoU, O(G + J·samples·S) for the
//! outline distance.

use super::maps::gpis::GpisMap;
use super::maps::{AgentMap, MapConfig};
use super::metrics::iou;
use super::outline::{outline_distance, spurious_distance};
use super::EpisodeError;
use crate::gpis::GridSpec;
use crate::scene::{Contact, Footprint};

/// Points sampled on each true outline for the outline distance.
pub const OUTLINE_SAMPLES: usize = 64;
/// Each point's distance is capped here, m (a jar the map never found counts this much).
pub const OUTLINE_CAP: f64 = 0.05;

/// The map task's reconstruction and its latest scores.
pub struct MapScore {
    map: GpisMap,
    grid: GridSpec,
}

impl MapScore {
    /// An empty reconstruction over `grid` with the GPIS settings of `config`.
    ///
    /// # Errors
    /// A GPIS that cannot be built on the grid.
    pub fn new(config: &MapConfig, grid: &GridSpec) -> Result<Self, EpisodeError> {
        Ok(Self {
            map: GpisMap::new(config, grid)?,
            grid: grid.clone(),
        })
    }

    /// Starts from the depth camera's first look (`slice`, seen from `camera`).
    ///
    /// # Errors
    /// As the GPIS map's reset.
    pub fn reset(&mut self, slice: &[[f64; 2]], camera: [f64; 2]) -> Result<(), EpisodeError> {
        self.map.reset(slice, camera)
    }

    /// Adds a step's readings (and the swept fingertip, where the episode sweeps free
    /// space), as the agent's map gets them.
    pub fn add_touch(&mut self, readings: &[Contact], swept: Option<[f64; 2]>) {
        self.map.add_touch(readings, swept);
    }

    /// The reconstruction's mean on the grid (H·W values, row-major), m.
    pub fn mean_grid(&self) -> &[f64] {
        self.map.gpis().mean_grid()
    }

    /// The IoU of the reconstruction's interior with `truth` (the footprints' grid mask).
    pub fn iou(&self, truth: &[bool]) -> f64 {
        score_iou(self.map.gpis().mean_grid(), truth)
    }

    /// The outline distance to `footprints`, m ([`score_outline`]).
    pub fn outline_distance(&self, footprints: &[Footprint]) -> f64 {
        score_outline(&self.grid, self.map.gpis().mean_grid(), footprints)
    }
}

/// The IoU of a reconstruction's interior (`mean` < 0, H·W values) with `truth`.
pub fn score_iou(mean: &[f64], truth: &[bool]) -> f64 {
    iou(mean.iter().map(|&m| m < 0.0), truth)
}

/// The outline distance of a reconstruction (`mean`, H·W values on `grid`) to `footprints`,
/// m: the mean of the two directed mean distances between its zero level set and the true
/// outlines, each point's distance capped at [`OUTLINE_CAP`].
pub fn score_outline(grid: &GridSpec, mean: &[f64], footprints: &[Footprint]) -> f64 {
    let missed = outline_distance(grid, mean, footprints, OUTLINE_SAMPLES, OUTLINE_CAP);
    let made_up = spurious_distance(grid, mean, footprints, OUTLINE_CAP);
    0.5 * (missed + made_up)
}
