//! The settings tables are the one description of every setting: each round-trips through
//! its value, each refuses a value of the wrong type and one out of its range with an error
//! that names the key as the user types it, and keys are unique across the scene and the
//! episode. A choice's annotation and error words are made from its names.

use std::collections::HashSet;

use env_core::episode::{ActionMode, EpisodeConfig, MapMode};
use env_core::scene::{JarShape, SceneConfig, TargetShape};
use env_core::settings::{Choice, Limit, Range, SettingError, SettingValue, Settings};

/// A number outside `range`, if the range has an end.
fn outside(range: &Range) -> Option<f64> {
    match (range.low, range.high) {
        (Limit::Closed(low), _) => Some(low - 1.0),
        (Limit::Open(low), _) => Some(low),
        (_, Limit::Closed(high)) => Some(high + 1.0),
        (_, Limit::Open(high)) => Some(high),
        _ => None,
    }
}

/// `value` with every number replaced by `number` (keeping ints as ints where whole).
fn with_numbers(value: &SettingValue, number: f64) -> SettingValue {
    match value {
        SettingValue::Int(_) if number.fract() == 0.0 => SettingValue::Int(number as i64),
        SettingValue::Int(_) | SettingValue::Float(_) | SettingValue::Null => {
            SettingValue::Float(number)
        }
        SettingValue::List(items) => {
            SettingValue::List(items.iter().map(|v| with_numbers(v, number)).collect())
        }
        other => other.clone(),
    }
}

fn every_setting_round_trips<C: Settings + Clone + std::fmt::Debug + PartialEq>() {
    let defaults = C::default();
    let rebuilt = C::from_pairs(defaults.to_pairs()).expect("the defaults are valid");
    let rebuilt = (*rebuilt).clone();
    assert_eq!(rebuilt, defaults);
    for setting in C::table() {
        let mut config = C::default();
        let value = setting.get(&config);
        config
            .set_value(setting.key, &value)
            .expect("a value read back is accepted");
        assert_eq!(config, defaults, "{} did not round-trip", setting.key);
    }
}

fn every_bad_value_names_its_key<C: Settings>() {
    for setting in C::table() {
        let mut config = C::default();
        let wrong = SettingValue::List(vec![SettingValue::Bool(true); 5]);
        match config.set_value(setting.key, &wrong) {
            Err(SettingError::WrongType { key, .. }) => assert_eq!(key, setting.key),
            other => panic!("{}: a wrong type gave {other:?}", setting.key),
        }
        let Some(bad) = outside(&setting.range) else {
            continue;
        };
        if !setting.choices.is_empty() || setting.annotation == "bool" {
            continue;
        }
        let value = with_numbers(&setting.get(&C::default()), bad);
        // An int setting whose range starts at 0 refuses a negative value as it reads it;
        // every other value of the right type is refused by the check.
        let error = match config.set_value(setting.key, &value) {
            Err(error) => error,
            Ok(()) => config
                .check_settings()
                .expect_err(&format!("{} accepted {value}", setting.key)),
        };
        assert!(
            error.to_string().starts_with(setting.key),
            "{}: {error}",
            setting.key
        );
        // The rule in Python's words: ">= 1", "from 0 to 1", "> 0 and <= 100".
        assert!(
            error.to_string().contains(&setting.range.words())
                || error.to_string().contains("pair"),
            "{}: {error}",
            setting.key
        );
    }
}

#[test]
fn every_scene_setting_round_trips_through_its_value() {
    every_setting_round_trips::<SceneConfig>();
}

#[test]
fn every_episode_setting_round_trips_through_its_value() {
    every_setting_round_trips::<EpisodeConfig>();
}

#[test]
fn every_scene_setting_refuses_bad_values_by_its_key() {
    every_bad_value_names_its_key::<SceneConfig>();
}

#[test]
fn every_episode_setting_refuses_bad_values_by_its_key() {
    every_bad_value_names_its_key::<EpisodeConfig>();
}

#[test]
fn keys_are_unique_and_the_episode_table_holds_the_scene_table() {
    let episode: Vec<&str> = EpisodeConfig::keys();
    let unique: HashSet<&str> = episode.iter().copied().collect();
    assert_eq!(unique.len(), episode.len(), "duplicate keys");
    for key in SceneConfig::keys() {
        assert!(unique.contains(key), "{key} missing from the episode table");
    }
    for setting in EpisodeConfig::table() {
        assert!(!setting.doc.is_empty(), "{} has no doc", setting.key);
    }
}

#[test]
fn unknown_keys_list_the_known_ones() {
    let error = SceneConfig::default()
        .set_value("finger_stifness", &SettingValue::Float(1.0))
        .unwrap_err();
    assert!(matches!(error, SettingError::UnknownKey { .. }));
    assert!(error.to_string().contains("finger_stiffness"));
}

#[test]
fn a_count_given_as_one_int_means_that_many_and_optional_settings_take_none() {
    let mut config = EpisodeConfig::default();
    config
        .set_value("jar_count", &SettingValue::Int(5))
        .unwrap();
    assert_eq!(config.scene.layout.jar_count, [5, 5]);
    config
        .set_value("free_space_offset", &SettingValue::Null)
        .unwrap();
    assert_eq!(config.map.free_space_offset, None);
    config
        .set_value("camera_fx", &SettingValue::Int(100))
        .unwrap();
    assert_eq!(config.scene.camera.intrinsics().fx, 100.0);
    assert!(config.check_settings().is_ok());
}

/// Every variant of a choice, by its index, round-trips through its index and its name.
fn check_choice<T: Choice + PartialEq + std::fmt::Debug>() {
    for (index, name) in T::NAMES.iter().enumerate() {
        let variant = T::from_index(index);
        assert_eq!(variant.index(), index);
        assert_eq!(variant.name(), *name);
        assert_eq!(T::parse(name), Some(variant));
    }
}

#[test]
fn a_choices_annotation_and_words_are_made_from_its_names() {
    assert_eq!(TargetShape::NAMES, ["round", "square", "any"]);
    assert_eq!(
        <TargetShape as Choice>::ANNOTATION,
        "Literal['round', 'square', 'any']"
    );
    assert_eq!(
        <TargetShape as Choice>::EXPECTED,
        "'round', 'square' or 'any'"
    );
    assert_eq!(
        <ActionMode as Choice>::ANNOTATION,
        "Literal['wrist', 'probe']"
    );
    assert_eq!(<ActionMode as Choice>::EXPECTED, "'wrist' or 'probe'");
    assert_eq!(
        <MapMode as Choice>::EXPECTED,
        "'gpis', 'occupancy' or 'none'"
    );
    check_choice::<TargetShape>();
    check_choice::<ActionMode>();
    check_choice::<MapMode>();
    // A jar's shape is named as `target_shape` names it.
    assert_eq!(
        JarShape::Round { radius: 0.02 }.name(),
        TargetShape::Round.name()
    );
    assert_eq!(
        JarShape::Square { half_side: 0.02 }.name(),
        TargetShape::Square.name()
    );
}
