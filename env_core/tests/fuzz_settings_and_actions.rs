//! Property tests of the episode's public entry points (proptest): settings and actions.
//!
//! - Any key (known or not) with any value (any type, nested lists, NaN, infinities) is
//!   accepted or refused with a `SettingError` naming the key; never a panic.
//! - Every numeric setting at the extremes of its valid range (its ends, one ulp inside an
//!   open end, ±1e300 where unbounded), one at a time, either builds an episode that steps
//!   with finite observations and infos, or is refused with an error; never a panic.
//! - Any action sequence (in range, huge, NaN, infinite) steps or is refused with
//!   `NonFiniteAction`, and a refused action leaves the episode as it was.
//! - In the `probe` action mode, any sequence of indices (valid, fractional, negative, too
//!   large, NaN) steps by at least one motion or is refused with `ProbeIndex` or
//!   `NonFiniteAction`, leaving the episode as it was.
//! - In every registered env (search, identify, their dense tiers) and either action mode,
//!   any action row with its claim entry (valid, NaN, out of range) steps, claims or is
//!   refused, leaving the episode as it was; a claim ends the episode, a success exactly
//!   when it names the target.
//!
//! `PROPTEST_CASES` sets the number of cases (the long run).

use env_core::episode::registry::REGISTERED_ENVS;
use env_core::episode::step_info::InfoValue;
use env_core::episode::{Action, ActionMode};
use env_core::episode::{
    Episode, EpisodeConfig, EpisodeError, MapMode, PROPRIO_LEN, STEP_INFO_FIELDS,
};
use env_core::settings::Checked;
use env_core::settings::{Limit, SettingError, SettingValue, Settings, MAX_SCENE_LENGTH};
use proptest::prelude::*;

/// Cases per property: `PROPTEST_CASES` if set (the long run), else `default`.
fn cases(default: u32) -> u32 {
    std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

fn number() -> impl Strategy<Value = f64> {
    prop_oneof![
        3 => -10.0..10.0f64,
        1 => Just(0.0),
        1 => Just(f64::NAN),
        1 => Just(f64::INFINITY),
        1 => Just(-1e300),
        1 => Just(1e-300),
    ]
}

fn setting_value() -> impl Strategy<Value = SettingValue> {
    let leaf = prop_oneof![
        any::<bool>().prop_map(SettingValue::Bool),
        prop_oneof![any::<i64>(), -5i64..5000].prop_map(SettingValue::Int),
        number().prop_map(SettingValue::Float),
        prop::collection::vec(any::<char>(), 0..8)
            .prop_map(|c| SettingValue::Text(c.into_iter().collect())),
        prop::sample::select(vec![
            "gpis",
            "occupancy",
            "none",
            "round",
            "square",
            "any",
            "identify",
            "search",
        ])
        .prop_map(|s| SettingValue::Text(s.to_owned())),
        Just(SettingValue::Null),
    ];
    leaf.prop_recursive(2, 8, 5, |inner| {
        prop::collection::vec(inner, 0..5).prop_map(SettingValue::List)
    })
}

fn key() -> impl Strategy<Value = String> {
    let keys: Vec<String> = EpisodeConfig::keys()
        .into_iter()
        .map(str::to_owned)
        .collect();
    prop_oneof![
        8 => prop::sample::select(keys),
        1 => prop::collection::vec(any::<char>(), 0..10).prop_map(|c| c.into_iter().collect()),
    ]
}

/// The value of `value` with every number replaced by `number` (ints kept whole if it is).
fn with_number(value: &SettingValue, number: f64) -> SettingValue {
    match value {
        SettingValue::Int(_) if number.fract() == 0.0 && number.abs() < 9e18 => {
            SettingValue::Int(number as i64)
        }
        SettingValue::Int(_) => SettingValue::Int(if number > 0.0 { i64::MAX } else { i64::MIN }),
        SettingValue::Float(_) | SettingValue::Null => SettingValue::Float(number),
        SettingValue::List(items) => {
            SettingValue::List(items.iter().map(|v| with_number(v, number)).collect())
        }
        other => other.clone(),
    }
}

/// The extremes of a range that are still inside it.
fn extremes(low: Limit, high: Limit) -> Vec<f64> {
    let mut out = Vec::new();
    match low {
        Limit::Unbounded => out.push(-1e300),
        Limit::Closed(v) => out.push(v),
        Limit::Open(v) => out.push(v.next_up()),
    }
    match high {
        Limit::Unbounded => out.push(1e300),
        Limit::Closed(v) => out.push(v),
        Limit::Open(v) => out.push(v.next_down()),
    }
    out
}

fn assert_outputs_finite(episode: &Episode) -> Result<(), TestCaseError> {
    let mut proprio = vec![0f32; PROPRIO_LEN];
    episode.write_proprio(&mut proprio).expect("right length");
    prop_assert!(
        proprio.iter().all(|v| v.is_finite() && v.abs() <= 1.0),
        "{proprio:?}"
    );
    let mut map = vec![0u8; episode.map_len()];
    episode.write_map(&mut map).expect("right length");
    let info = episode.last_info();
    for field in STEP_INFO_FIELDS {
        if let InfoValue::Float(get) = field.value {
            prop_assert!(get(info).is_finite(), "info {} = {}", field.name, get(info));
        }
    }
    Ok(())
}

fn action() -> impl Strategy<Value = [f64; 3]> {
    let component = prop_oneof![
        6 => -1.0..1.0f64,
        1 => -1e6..1e6f64,
        1 => Just(f64::NAN),
        1 => Just(f64::NEG_INFINITY),
        1 => Just(f64::MAX),
    ];
    [component.clone(), component.clone(), component]
}

fn probe_action() -> impl Strategy<Value = [i64; 3]> {
    let component = prop_oneof![
        8 => 0i64..12,
        1 => -3i64..40,
        1 => Just(i64::MIN),
        1 => Just(i64::MAX),
    ];
    [component.clone(), component.clone(), component]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(cases(256)))]

    #[test]
    fn any_key_and_value_is_accepted_or_refused_naming_the_key(
        pairs in prop::collection::vec((key(), setting_value()), 1..4),
    ) {
        let given: Vec<(&str, SettingValue)> =
            pairs.iter().map(|(k, v)| (k.as_str(), v.clone())).collect();
        match EpisodeConfig::from_pairs(given) {
            Ok(config) => prop_assert!(config.check_settings().is_ok()),
            Err(error) => {
                let key: String = match &error {
                    SettingError::WrongType { key, .. } | SettingError::OutOfRange { key, .. } => {
                        (*key).to_owned()
                    }
                    SettingError::UnknownKey { key, .. } => key.clone(),
                };
                prop_assert!(!key.is_empty() || pairs.iter().any(|(k, _)| k.is_empty()));
                // The key as typed, or escaped when it holds control characters.
                let message = error.to_string();
                prop_assert!(
                    message.contains(&key) || message.contains(&format!("{key:?}")),
                    "{message}"
                );
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(cases(48)))]

    #[test]
    fn every_setting_at_an_extreme_of_its_range_builds_and_steps_or_is_refused(
        index in any::<prop::sample::Index>(),
        upper in any::<bool>(),
        mode in prop::sample::select(vec![MapMode::Gpis, MapMode::Occupancy, MapMode::None]),
        seed in 0u64..1000,
        actions in prop::collection::vec(action(), 1..4),
    ) {
        let table = EpisodeConfig::table();
        let setting = &table[index.index(table.len())];
        let mut config = EpisodeConfig::default();
        config.map.mode = mode;
        let default = setting.get(&config);
        let [low, high] = extremes(setting.range.low, setting.range.high)[..] else {
            unreachable!()
        };
        let value = with_number(&default, if upper { high } else { low });
        if config.set_value(setting.key, &value).is_err() || config.check_settings().is_err() {
            return Ok(()); // refused with an error: the first property checks its message
        }
        let Ok(mut episode) = Episode::started(Checked::new(config).unwrap(), seed) else {
            return Ok(()); // e.g. no layout fits: an error, not a panic
        };
        assert_outputs_finite(&episode)?;
        for action in actions {
            match episode.step(action) {
                Ok(_) => assert_outputs_finite(&episode)?,
                Err(EpisodeError::NonFiniteAction { .. }) => {
                    prop_assert!(action.iter().any(|a| !a.is_finite()));
                }
                Err(other) => prop_assert!(!other.to_string().is_empty()),
            }
            if episode.last_info().terminated {
                break;
            }
        }
    }

    #[test]
    fn any_action_sequence_steps_or_is_refused_leaving_the_episode_as_it_was(
        mode in prop::sample::select(vec![MapMode::Gpis, MapMode::Occupancy, MapMode::None]),
        seed in any::<u64>(),
        actions in prop::collection::vec(action(), 1..30),
    ) {
        let mut config = EpisodeConfig::default();
        config.map.mode = mode;
        let mut episode = Episode::started(Checked::new(config).unwrap(), seed).expect("default settings build");
        for action in actions {
            let before = *episode.last_info();
            match episode.step(action) {
                Ok(info) => {
                    prop_assert!(action.iter().all(|a| a.is_finite()));
                    prop_assert_eq!(info.steps, before.steps + 1);
                    assert_outputs_finite(&episode)?;
                }
                Err(EpisodeError::NonFiniteAction { .. }) => {
                    prop_assert!(action.iter().any(|a| !a.is_finite()));
                    prop_assert_eq!(*episode.last_info(), before);
                }
                Err(other) => {
                    prop_assert!(before.terminated, "{other}");
                    break;
                }
            }
        }
    }
}

/// Under depth noise of 1e300 the occupancy map's first look would walk each ray cell by
/// cell out to its reading, 1e300 m away, and never return: the largest noise allowed
/// ([`MAX_SCENE_LENGTH`]) puts readings 100 m away, and every map mode builds and steps.
#[test]
fn huge_depth_noise_builds_and_steps_in_every_map_mode() {
    for mode in [MapMode::Gpis, MapMode::Occupancy, MapMode::None] {
        let mut config = EpisodeConfig::default();
        config.map.mode = mode;
        config
            .set_value("depth_noise_std", &SettingValue::Float(MAX_SCENE_LENGTH))
            .expect("in range");
        let mut episode = Episode::started(Checked::new(config).unwrap(), 0).expect("builds");
        episode.step([0.5, 0.5, 0.0]).expect("steps");
        assert_outputs_finite(&episode).expect("finite");
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(cases(24)))]

    #[test]
    fn any_probe_sequence_steps_or_is_refused_leaving_the_episode_as_it_was(
        mode in prop::sample::select(vec![MapMode::Gpis, MapMode::Occupancy, MapMode::None]),
        seed in any::<u64>(),
        actions in prop::collection::vec(probe_action(), 1..8),
    ) {
        let mut config = EpisodeConfig::default();
        config.map.mode = mode;
        config.action_mode = ActionMode::Probe;
        let counts = config.probe.counts();
        let mut episode = Episode::started(Checked::new(config).unwrap(), seed).expect("default settings build");
        for action in actions {
            let before = *episode.last_info();
            let valid = action
                .iter()
                .zip(counts)
                .all(|(&a, n)| usize::try_from(a).is_ok_and(|a| a < n));
            match episode.step(action) {
                Ok(info) => {
                    prop_assert!(valid, "{action:?} was taken");
                    prop_assert!(info.motions >= 1);
                    prop_assert_eq!(info.steps, before.steps + info.motions);
                    assert_outputs_finite(&episode)?;
                }
                Err(EpisodeError::ProbeIndex { .. }) => {
                    prop_assert!(!valid, "{action:?} was refused");
                    prop_assert_eq!(*episode.last_info(), before);
                }
                Err(other) => {
                    prop_assert!(before.terminated, "{other}");
                    break;
                }
            }
        }
    }
}

/// An action row of `mode` as the env's action space holds it, with a claim entry: a wrist
/// row's numbers or a probe row's indices (as f64: `claim_row` casts them), each valid or
/// not.
fn claim_row() -> impl Strategy<Value = (Vec<f64>, Vec<i64>)> {
    let claim = prop_oneof![3 => -1.0..1.0f64, 1 => Just(f64::NAN), 1 => Just(f64::INFINITY)];
    let index = prop_oneof![8 => 0i64..2, 1 => -2i64..4];
    (
        (action(), claim).prop_map(|(m, c)| vec![m[0], m[1], m[2], c]),
        (probe_action(), index).prop_map(|(p, c)| vec![p[0], p[1], p[2], c]),
    )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(cases(24)))]

    #[test]
    fn any_row_of_any_registered_env_steps_claims_or_is_refused(
        env in prop::sample::select(REGISTERED_ENVS.to_vec()),
        probe in any::<bool>(),
        seed in 0u64..100_000,
        rows in prop::collection::vec(claim_row(), 1..8),
    ) {
        let pairs = env.settings.iter().map(|(key, preset)| (*key, preset.value()));
        let mut config = (*EpisodeConfig::from_pairs(pairs).expect("a registered env")).clone();
        config.action_mode = if probe { ActionMode::Probe } else { ActionMode::Wrist };
        let claims = config.task.claims();
        let mut episode = Episode::started(Checked::new(config).unwrap(), seed)
            .expect("a registered env's layouts are found");
        for (wrist, indices) in rows {
            let parsed = if probe {
                Action::from_probe_row(&indices[..if claims { 4 } else { 3 }], claims)
            } else {
                Action::from_wrist_row(&wrist[..if claims { 4 } else { 3 }], claims)
            };
            let Ok(action) = parsed else {
                prop_assert!(claims, "a row without a claim entry parses");
                continue;
            };
            let before = *episode.last_info();
            match episode.step(action) {
                Ok(info) => {
                    assert_outputs_finite(&episode)?;
                    if action == Action::Claim {
                        prop_assert!(info.terminated);
                        let target = episode.scene().target();
                        prop_assert_eq!(info.success, info.claimed_jar == Some(target));
                        prop_assert_eq!(info.wrong_claim, !info.success);
                    } else {
                        prop_assert!(!info.success || !claims, "a touch succeeded in identify");
                    }
                }
                Err(EpisodeError::NonFiniteAction { .. } | EpisodeError::ProbeIndex { .. }) => {
                    prop_assert_eq!(*episode.last_info(), before);
                }
                Err(other) => {
                    prop_assert!(before.terminated, "{other}");
                    break;
                }
            }
        }
    }
}
