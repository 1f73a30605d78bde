//! Scripted teachers that read only the observation: what a recipe's agent clones, run
//! where they are cheap (here, beside the probe controller) instead of in Python.
//!
//! - [`probe_planner`]: the GPIS probe planner ([`ProbePlanner`]), the teacher of every
//!   search recipe, built on its [`belief`], the [`clearance`] queries and [`reachable`]
//!   (which probes the hand can make, asked probe by probe).
//! - [`identify_planner`]: the identify task's planner ([`IdentifyPlanner`]): the search
//!   planner's probes, its touched jars' shapes told from their contacts, and the claim.
//! - [`map_planner`]: the map task's greedy mappers ([`MapPlanner`]): the probe whose
//!   finger passes the most of the map's own uncertainty (GPIS std, unknown occupancy).
//! - [`distance`], [`numeric`]: the capped distance transform and numpy's float order the
//!   rules were chosen with.
//! - [`Planner`], [`act_batch`]: what a planner is to its callers, and one action per
//!   episode of a batch, the planners run on every core.
//!
//! A planner is given the episode configuration (the static geometry it may know) and then
//! observations alone: the map image and the proprio vector. It has no way to read the
//! scene, the target or anything else of an episode's ground truth.

mod batch;
mod belief;
mod clearance;
mod distance;
mod error;
mod geometry;
pub mod identify_planner;
pub mod map_planner;
mod numeric;
pub mod probe_planner;
mod reachable;

pub use batch::{act_batch, Planner};
pub use error::PlannerError;
pub use identify_planner::IdentifyPlanner;
pub use map_planner::MapPlanner;
pub use probe_planner::{PlannerObservation, ProbePlanner};
