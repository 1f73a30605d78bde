//! The map task's greedy mappers: the GPIS probe planner's belief of the finger's swept
//! cells and touched jars, and its candidate probes (those of the core's grid the wrist and
//! arm can make without coming near a cell that may hold a jar); what differs is the weight
//! a probe is chosen by. The teachers of the map recipes.
//!
//! A probe's weight is the sum of a per-cell weight over the cells within `PATH_HALF_WIDTH`
//! of the finger's path (straight in along the lane, then the turn), cells the finger
//! already swept without touching counted as nothing (a probe that touched nothing is not
//! chosen again for the same cells), and a probe once chosen is never chosen again (its
//! touch, if any, is already evidence). The per-cell weight is the map's own uncertainty:
//!
//! - on the GPIS map, the GPIS standard deviation (the paper's suggestion: the variance says
//!   where to explore next);
//! - on the occupancy grid, how unknown each cell is (1 at P(occupied) = 0.5, 0 at 0 or 1);
//!   its belief reads the grid as a map of signed distance ([`MapReading::Occupancy`]).
//!
//! It reads only the observation (the map image and the proprio vector) and the settings.
//! The rules are the Python mappers' (`agents/scripted/map_probe.py`), in their float order.

use super::error::PlannerError;
use std::sync::Arc;

use super::probe_planner::{
    ContactRule, MapChannel, MapReading, PlannerObservation, ProbePaths, ProbePlanner,
};
use crate::episode::maps::MapMode;
use crate::episode::EpisodeConfig;

/// Half width of the band around the finger's path whose cells a probe's weight sums, m.
const PATH_HALF_WIDTH: f64 = 0.01;

/// A greedy mapper of one episode at a time (see the module docs).
#[derive(Debug, Clone)]
pub struct MapPlanner {
    search: ProbePlanner,
    /// The cells each grid probe's finger passes within `PATH_HALF_WIDTH` (clones share it).
    paths: Arc<ProbePaths>,
    /// The probes chosen this episode (each is chosen once).
    tried: Vec<[i64; 3]>,
}

impl MapPlanner {
    /// The mapper of episodes of `config`, which must have the GPIS map (the variance
    /// mapper) or the occupancy grid (the occupancy mapper), and the `probe` action mode.
    pub fn new(config: &EpisodeConfig) -> Result<Self, PlannerError> {
        let reading = match config.map.mode {
            MapMode::Occupancy => MapReading::Occupancy,
            _ => MapReading::Gpis,
        };
        let search = ProbePlanner::with_rules(config, ContactRule::FingerAxis, reading)?;
        Ok(Self {
            paths: Arc::new(ProbePaths::new(search.geometry(), PATH_HALF_WIDTH)),
            search,
            tried: Vec::new(),
        })
    }

    /// Starts an episode from its first observation.
    pub fn reset(&mut self, observation: PlannerObservation<'_>) -> Result<(), PlannerError> {
        self.tried.clear();
        self.search.reset(observation)
    }

    /// Takes `observation` (the one after the last probe) into the belief and chooses the
    /// next probe, `[lane, depth, sweep]`: of the candidates not chosen yet, the one whose
    /// finger passes the most weight; with no weight left, the first candidate not chosen
    /// yet, else straight in at the middle lane's opening.
    pub fn act(&mut self, observation: PlannerObservation<'_>) -> Result<[i64; 3], PlannerError> {
        let reading = self.search.reading();
        let (pose, weight) = self
            .search
            .observe_reading(observation, |channels| cell_weight(reading, channels))?;
        // Nothing where the finger already swept (the belief has taken this observation).
        let swept = self.search.belief().swept();
        let weight: Vec<f64> = weight
            .into_iter()
            .zip(swept)
            .map(|(w, &swept)| if swept { 0.0 } else { w })
            .collect();
        let candidates = self.search.candidates(&pose);
        let mut best: Option<[i64; 3]> = None;
        let mut best_score = 0.0;
        let tried = &self.tried;
        let untried: Vec<_> = candidates
            .into_iter()
            .filter(|c| !tried.contains(&c.action))
            .collect();
        self.search
            .path_weights(&untried, &weight, &self.paths, |candidate, score| {
                if score > best_score {
                    best = Some(candidate.action);
                    best_score = score;
                }
            });
        let chosen = best
            .or_else(|| untried.first().map(|c| c.action))
            .unwrap_or_else(|| self.search.geometry().opening_probe());
        self.tried.push(chosen);
        self.search.set_chosen(chosen);
        Ok(chosen)
    }

    /// Takes `probe`, not the probe [`MapPlanner::act`] just chose, as the probe the env
    /// carries out next.
    pub fn follow(&mut self, probe: [i64; 3]) -> Result<(), PlannerError> {
        self.search.follow(probe)
    }
}

/// Per map cell, what a finger passing it is worth (≥ 0), from the map's decoded
/// `channels` read by `reading`: the GPIS std, or how unknown an occupancy is.
fn cell_weight(reading: MapReading, channels: &[MapChannel]) -> Vec<f64> {
    let channel = |name: &str| {
        channels
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(_, values)| values)
            .expect("the settings' map has the channel")
    };
    match reading {
        MapReading::Gpis => channel("std").clone(),
        MapReading::Occupancy => channel("occupied")
            .iter()
            .map(|&p| 1.0 - 2.0 * (p - 0.5).abs())
            .collect(),
    }
}
