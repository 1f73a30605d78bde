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

/// `impl Planner` for a planner type whose inherent `reset`, `act` and `follow` are the
/// trait's.
macro_rules! planner_impl {
    ($planner:ty, $action:ty) => {
        impl Planner for $planner {
            type Action = $action;

            fn reset(&mut self, observation: PlannerObservation<'_>) -> Result<(), PlannerError> {
                <$planner>::reset(self, observation)
            }

            fn act(
                &mut self,
                observation: PlannerObservation<'_>,
            ) -> Result<$action, PlannerError> {
                <$planner>::act(self, observation)
            }

            fn follow(&mut self, probe: [i64; 3]) -> Result<(), PlannerError> {
                <$planner>::follow(self, probe)
            }
        }
    };
}

planner_impl!(ProbePlanner, [i64; 3]);
planner_impl!(IdentifyPlanner, [i64; 4]);
planner_impl!(MapPlanner, [i64; 3]);

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
