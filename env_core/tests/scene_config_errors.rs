//! Bad configuration and bad layouts are refused with typed errors that say what was expected
//! and what came, never a panic.

use env_core::scene::{
    JarShape, JarSpec, Layout, Scene, SceneConfig, SceneError, TargetShape, Visibility,
};
use env_core::settings::Checked;
use env_core::settings::{Choice, SettingError, SettingValue, Settings};

/// What refuses `config`: its check, else the scene built from it.
fn error_of(config: SceneConfig) -> SceneError {
    let checked = match Checked::new(config) {
        Ok(checked) => checked,
        Err(e) => return SceneError::from(e),
    };
    match Scene::new(&checked, 0) {
        Ok(_) => panic!("accepted a bad config"),
        Err(e) => e,
    }
}

#[test]
fn bad_configs_are_refused_with_the_users_key_in_the_message() {
    let mut c = SceneConfig::default();
    c.layout.jar_count = [5, 3];
    assert!(error_of(c)
        .to_string()
        .contains("jar_count must be a pair (low, high)"));
    let mut c = SceneConfig::default();
    c.layout.jar_count = [3, 17];
    assert!(error_of(c)
        .to_string()
        .contains("jar_count must be an int from 1 to 16"));
    let mut c = SceneConfig::default();
    c.camera.noise_std = -1.0;
    assert!(error_of(c)
        .to_string()
        .starts_with("depth_noise_std must be from 0 to 100"));
    let mut c = SceneConfig::default();
    c.hand.finger_stiffness = f64::NAN;
    assert!(matches!(
        error_of(c),
        SceneError::Setting(SettingError::OutOfRange {
            key: "finger_stiffness",
            ..
        })
    ));
    let mut c = SceneConfig::default();
    c.camera.look_at = c.camera.position;
    assert!(matches!(
        error_of(c),
        SceneError::DegenerateCameraPose { .. }
    ));
    let mut c = SceneConfig::default();
    c.camera.image_width = 0;
    assert!(error_of(c)
        .to_string()
        .starts_with("camera_width must be an int from 1 to 4096"));
    let mut c = SceneConfig::default();
    c.hand.start = [0.29, 0.1, 0.0];
    assert!(matches!(error_of(c), SceneError::HandStartBlocked { .. }));
    let c = SceneConfig {
        slice_height: 0.2,
        ..Default::default()
    };
    assert!(error_of(c)
        .to_string()
        .starts_with("slice_height must be below the shortest jar"));
    assert_eq!(TargetShape::parse("triangle"), None);
    let mut c = SceneConfig::default();
    let error = c
        .set_value("target_shape", &SettingValue::Text("triangle".into()))
        .unwrap_err();
    assert!(error.to_string().contains("'round'"), "{error}");
}

#[test]
fn an_impossible_layout_request_fails_after_its_attempts() {
    let mut c = SceneConfig::default();
    c.layout.jar_count = [7, 7];
    c.layout.corridor_width = 0.5;
    c.layout.max_attempts = 20;
    assert!(matches!(
        error_of(c),
        SceneError::LayoutNotFound { attempts: 20, .. }
    ));
}

#[test]
fn bad_explicit_layouts_are_refused() {
    let jar = |x: f64, y: f64| JarSpec {
        shape: JarShape::Round { radius: 0.025 },
        height: 0.11,
        mass: 0.15,
        x,
        y,
        yaw: 0.0,
    };
    let layout = |jars: Vec<JarSpec>, target: usize| Layout {
        jars,
        target,
        corridor: None,
        visibility: Visibility::default(),
        decoys: Vec::new(),
        decoy_corridors: Vec::new(),
    };
    let with_decoys = |target: usize, decoys: Vec<usize>| Layout {
        decoys,
        ..layout(vec![jar(-0.1, 0.1), jar(0.0, 0.1), jar(0.1, 0.1)], target)
    };
    for (bad, needle) in [
        (layout(vec![jar(0.0, 0.1), jar(0.01, 0.1)], 0), "overlap"),
        (layout(vec![jar(0.0, 0.1)], 1), "target index"),
        (layout(vec![jar(0.29, 0.1)], 0), "inside the interior"),
        (layout(vec![], 0), "1 to 16 jars"),
        (layout(vec![jar(f64::NAN, 0.1)], 0), "non-finite"),
        (with_decoys(0, vec![3]), "decoy indices must be < 3"),
        (with_decoys(1, vec![1]), "not the target's (1)"),
        (
            with_decoys(0, vec![2, 1]),
            "decoy indices must be increasing",
        ),
    ] {
        match Scene::from_layout(&Checked::new(SceneConfig::default()).unwrap(), bad, 0) {
            Ok(_) => panic!("accepted a bad layout ({needle})"),
            Err(e) => assert!(e.to_string().contains(needle), "{e}"),
        }
    }
}
