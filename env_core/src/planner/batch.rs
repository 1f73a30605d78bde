//! A batch of planners acting at once, on rayon's pool (every core).

use rayon::prelude::*;

use super::error::PlannerError;
use super::probe_planner::{PlannerObservation, ProbePlanner};

/// Each planner's next probe for its observation, the planners run in parallel on rayon's
/// pool (one planner per task: each is independent, so the probes do not depend on the
/// thread count).
pub fn act_batch(
    planners: &mut [ProbePlanner],
    observations: &[PlannerObservation<'_>],
) -> Result<Vec<[i64; 3]>, PlannerError> {
    planners
        .par_iter_mut()
        .zip(observations.par_iter())
        .map(|(planner, observation)| planner.act(*observation))
        .collect()
}
