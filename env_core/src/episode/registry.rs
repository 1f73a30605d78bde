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
}

impl Preset {
    /// The value as it crosses the boundary.
    pub fn value(&self) -> SettingValue {
        match *self {
            Self::Text(text) => SettingValue::Text(text.to_owned()),
            Self::Float(value) => SettingValue::Float(value),
            Self::Int(value) => SettingValue::Int(value),
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
            ("task", Preset::Text("identify")),
            ("target_shape", Preset::Text("square")),
            ("round_fraction", Preset::Float(1.0)),
        ],
        history: "v0: the identify task; one hidden decoy.",
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
