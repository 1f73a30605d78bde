//! The registered environments: each id is a task and a tier, given as settings over the
//! defaults. The Python package registers exactly these ids with gymnasium, each with its
//! settings as the registration's keyword arguments (a user's own keyword arguments go over
//! them); the docs list them from here.

use super::task::Task;
use crate::settings::SettingValue;

/// A preset setting's value, as a constant (a [`SettingValue`] holds owned text).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Preset {
    /// A choice or other text.
    Text(&'static str),
    /// A real number.
    Float(f64),
    /// A whole number.
    Int(i64),
    /// A pair of whole numbers (a range such as `jar_count`).
    IntPair([i64; 2]),
}

impl Preset {
    /// The value as it crosses the boundary.
    pub fn value(&self) -> SettingValue {
        match *self {
            Self::Text(text) => SettingValue::Text(text.to_owned()),
            Self::Float(value) => SettingValue::Float(value),
            Self::Int(value) => SettingValue::Int(value),
            Self::IntPair(pair) => SettingValue::List(pair.map(SettingValue::Int).to_vec()),
        }
    }
}

/// One registered environment id.
#[derive(Debug, Clone, Copy)]
pub struct RegisteredEnv {
    /// The id, in the `tactile_search/` namespace, with its version.
    pub id: &'static str,
    /// The task it asks.
    pub task: Task,
    /// One line on what it is.
    pub summary: &'static str,
    /// Its settings over the defaults (the task included).
    pub settings: &'static [(&'static str, Preset)],
    /// What changed in each version of the id.
    pub history: &'static str,
}

/// The identify task's rule over the defaults: the target the only square jar among round
/// ones, and one decoy hidden as well as it (a decoy and its occluder need two more jars).
const IDENTIFY: [(&str, Preset); 4] = [
    ("task", Preset::Text("identify")),
    ("target_shape", Preset::Text("square")),
    ("round_fraction", Preset::Float(1.0)),
    ("hidden_decoys", Preset::Int(1)),
];

/// Dense shelves: 8 to 14 jars in the default cupboard (every seed of 0..2000 gets a layout
/// in a few attempts, with and without a decoy: `examples/layout_rates.rs`).
const DENSE: (&str, Preset) = ("jar_count", Preset::IntPair([8, 14]));

/// Every registered id. `CupboardSearch-v0` is the defaults, unchanged since v0.
pub const REGISTERED_ENVS: &[RegisteredEnv] = &[
    RegisteredEnv {
        id: "tactile_search/CupboardSearch-v0",
        task: Task::Search,
        summary: "find the hidden jar and touch it: a touch of the target succeeds",
        settings: &[],
        history: "v0: the search task at the defaults.",
    },
    RegisteredEnv {
        id: "tactile_search/IdentifyByTouch-v0",
        task: Task::Identify,
        summary: "the target is the only square jar among round ones, hidden like a decoy: \
                  touch to tell them apart and claim it",
        settings: &[
            IDENTIFY[0],
            IDENTIFY[1],
            IDENTIFY[2],
            IDENTIFY[3],
            ("jar_count", Preset::IntPair([4, 7])),
        ],
        history: "v0: the identify task, 4 to 7 jars, one hidden decoy.",
    },
    RegisteredEnv {
        id: "tactile_search/CupboardSearchDense-v0",
        task: Task::Search,
        summary: "search on dense shelves: 8 to 14 jars",
        settings: &[DENSE],
        history: "v0: the search task with 8 to 14 jars.",
    },
    RegisteredEnv {
        id: "tactile_search/IdentifyByTouchDense-v0",
        task: Task::Identify,
        summary: "identify on dense shelves: 8 to 14 jars, the target among round jars and a \
                  hidden decoy",
        settings: &[IDENTIFY[0], IDENTIFY[1], IDENTIFY[2], IDENTIFY[3], DENSE],
        history: "v0: the identify task with 8 to 14 jars, one hidden decoy.",
    },
    RegisteredEnv {
        id: "tactile_search/MapByTouch-v0",
        task: Task::Map,
        summary: "no target: touch so that the evidence reconstructs the cupboard within the \
                  time limit, scored the same whatever map the agent observes",
        settings: &[
            ("task", Preset::Text("map")),
            // The budget is fixed: a cost per motion would only shift every return.
            ("reward_step_cost", Preset::Float(0.0)),
        ],
        history: "v0: the map task at the default layouts, 200 motions.",
    },
];

#[cfg(test)]
mod tests {
    use super::*;
    use crate::episode::EpisodeConfig;
    use crate::settings::Settings;

    #[test]
    fn every_registered_env_has_valid_settings_and_its_task() {
        for env in REGISTERED_ENVS {
            let pairs = env
                .settings
                .iter()
                .map(|(key, preset)| (*key, preset.value()));
            let config =
                EpisodeConfig::from_pairs(pairs).unwrap_or_else(|e| panic!("{}: {e}", env.id));
            assert_eq!(config.task, env.task, "{}", env.id);
            assert!(env.id.starts_with("tactile_search/") && env.id.contains("-v"));
        }
    }

    #[test]
    fn registered_ids_are_unique() {
        let mut ids: Vec<_> = REGISTERED_ENVS.iter().map(|e| e.id).collect();
        ids.sort_unstable();
        ids.dedup();
        assert_eq!(ids.len(), REGISTERED_ENVS.len());
    }
}
