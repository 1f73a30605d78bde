//! The sensed deflection is a contact signal: starting and stopping a free-space motion at the
//! largest command deflects the finger only transiently (inertia; a reversal, twice the speed
//! jump, twice as much) and it settles back to zero, while a finger held pressed on a jar stays
//! deflected, with its reading, at rest.

mod common;

use env_core::scene::{HandCommand, JarShape, Layout, Scene, SceneConfig};
use env_core::settings::Checked;

fn one_jar(config: SceneConfig) -> Scene {
    let jar = common::test_jar(JarShape::Round { radius: 0.025 }, 0.0, 0.15, 0.0);
    let layout = Layout::lone_jar(jar);
    Scene::from_layout(&Checked::new(config).unwrap(), layout, 0).expect("scene builds")
}

#[test]
fn free_motion_deflects_the_finger_only_transiently() {
    let mut scene = one_jar(SceneConfig::default());
    let max = scene.config().hand.max_step_translation;
    let mut peak = 0.0f64;
    for k in 0..20 {
        let dx = if k < 10 { max } else { 0.0 };
        scene
            .step(HandCommand {
                dx,
                ..Default::default()
            })
            .expect("finite");
        assert!(scene.true_contacts().is_empty());
        peak = peak.max(scene.finger_angle().abs());
    }
    assert!(peak < 0.15, "free-space deflection peaked at {peak} rad");
    assert!(peak > 1e-3, "the finger has no inertia at all? peak {peak}");
    scene.idle(120);
    assert!(
        scene.finger_angle().abs() < 2e-3,
        "still deflected: {}",
        scene.finger_angle()
    );
}

#[test]
fn a_pressed_finger_stays_deflected_with_its_reading_at_rest() {
    let mut config = SceneConfig::default();
    config.hand.start = [-0.034, 0.063, 0.0];
    let mut scene = one_jar(config);
    for _ in 0..8 {
        scene
            .step(HandCommand {
                dx: 0.002,
                ..Default::default()
            })
            .expect("finite");
    }
    scene.idle(120);
    scene.step(HandCommand::default()).expect("finite");
    let angle = scene.finger_angle();
    assert!(angle > 0.1, "pressed finger deflection {angle}");
    assert_eq!(
        scene.true_contacts().len(),
        1,
        "{:?}",
        scene.true_contacts()
    );
    assert!(scene.jar_states()[0].disturbance.displacement < 1e-3);
}
