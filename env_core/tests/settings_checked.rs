//! A checked config: refused by the key of its first bad setting, shared when cloned, and
//! its sections checked with it.

use env_core::episode::EpisodeConfig;
use env_core::scene::SceneConfig;
use env_core::settings::{Checked, SettingError};

#[test]
fn a_config_out_of_range_is_refused_by_its_key() {
    let config = SceneConfig {
        slice_height: -1.0,
        ..SceneConfig::default()
    };
    let error = Checked::new(config).unwrap_err();
    assert!(
        matches!(
            error,
            SettingError::OutOfRange {
                key: "slice_height",
                ..
            }
        ),
        "{error}"
    );
}

#[test]
fn a_clone_shares_the_checked_config() {
    let checked = Checked::new(SceneConfig::default()).unwrap();
    let clone = checked.clone();
    assert!(std::ptr::eq(&*checked, &*clone));
}

#[test]
fn a_section_of_a_checked_config_is_the_section_it_holds() {
    let mut config = EpisodeConfig::default();
    config.scene.slice_height = 0.04;
    let checked = Checked::new(config).unwrap();
    let scene = checked.section(|c| &c.scene);
    assert_eq!(*scene, checked.scene);
}
