//! What every planner of the core is to its callers ([`Planner`]), and a batch of planners
//! acting at once on rayon's pool (every core).

use rayon::prelude::*;

use super::error::PlannerError;
use super::identify_planner::IdentifyPlanner;
use super::map_planner::MapPlanner;
use super::probe_planner::{PlannerObservation, ProbePlanner};

/// A planner of one episode at a time, reading observations only: started from an
/// episode's first observation, then asked for an action after each probe, and told of a
/// probe the env carries out instead of its own (DAgger).
pub trait Planner: Send {
    /// The env's action: the probe's `[lane, depth, sweep]`, and a claim entry where the
    /// task has one.
    type Action: AsRef<[i64]> + Send;

    /// Starts an episode from its first observation.
    fn reset(&mut self, observation: PlannerObservation<'_>) -> Result<(), PlannerError>;

    /// The next action after `observation`.
    fn act(&mut self, observation: PlannerObservation<'_>) -> Result<Self::Action, PlannerError>;

    /// Takes `probe` (`[lane, depth, sweep]`) as the probe the env carries out next.
    fn follow(&mut self, probe: [i64; 3]) -> Result<(), PlannerError>;
}

impl Planner for ProbePlanner {
    type Action = [i64; 3];

    fn reset(&mut self, observation: PlannerObservation<'_>) -> Result<(), PlannerError> {
        ProbePlanner::reset(self, observation)
    }

    fn act(&mut self, observation: PlannerObservation<'_>) -> Result<[i64; 3], PlannerError> {
        ProbePlanner::act(self, observation)
    }

    fn follow(&mut self, probe: [i64; 3]) -> Result<(), PlannerError> {
        ProbePlanner::follow(self, probe)
    }
}

impl Planner for IdentifyPlanner {
    type Action = [i64; 4];

    fn reset(&mut self, observation: PlannerObservation<'_>) -> Result<(), PlannerError> {
        IdentifyPlanner::reset(self, observation)
    }

    fn act(&mut self, observation: PlannerObservation<'_>) -> Result<[i64; 4], PlannerError> {
        IdentifyPlanner::act(self, observation)
    }

    fn follow(&mut self, probe: [i64; 3]) -> Result<(), PlannerError> {
        IdentifyPlanner::follow(self, probe)
    }
}

impl Planner for MapPlanner {
    type Action = [i64; 3];

    fn reset(&mut self, observation: PlannerObservation<'_>) -> Result<(), PlannerError> {
        MapPlanner::reset(self, observation)
    }

    fn act(&mut self, observation: PlannerObservation<'_>) -> Result<[i64; 3], PlannerError> {
        MapPlanner::act(self, observation)
    }

    fn follow(&mut self, probe: [i64; 3]) -> Result<(), PlannerError> {
        MapPlanner::follow(self, probe)
    }
}

/// Each planner's next action for its observation, the planners run in parallel on rayon's
/// pool (one planner per task: each is independent, so the actions do not depend on the
/// thread count).
pub fn act_batch<P: Planner>(
    planners: &mut [P],
    observations: &[PlannerObservation<'_>],
) -> Result<Vec<P::Action>, PlannerError> {
    planners
        .par_iter_mut()
        .zip(observations.par_iter())
        .map(|(planner, observation)| planner.act(*observation))
        .collect()
}
