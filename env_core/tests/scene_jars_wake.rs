//! Jars start asleep where the layout put them (a jar nothing touches costs the physics
//! nothing), and whatever touches one wakes it: a rigid
//! finger (a collider of the kinematic wrist) shoving a jar moves it, and the shoved jar
//! moves the sleeping jar it is pushed into. With `jars_start_asleep` off, the same push
//! gives the same outcome within a millimetre.

mod common;

use env_core::scene::{HandCommand, JarShape, Layout, Scene, SceneConfig};
use env_core::settings::Checked;

#[test]
fn resting_jars_are_asleep_from_the_first_step_and_only_then() {
    for asleep in [true, false] {
        let mut config = SceneConfig::default();
        config.physics.jars_start_asleep = asleep;
        let mut scene = Scene::new(&Checked::new(config).unwrap(), 7).expect("scene builds");
        // The hand moves in front of the opening, touching nothing.
        for dx in [0.01, -0.01, -0.01, 0.01] {
            scene
                .step(HandCommand {
                    dx,
                    ..Default::default()
                })
                .expect("finite command");
            for (i, jar) in scene.jar_states().iter().enumerate() {
                assert_eq!(jar.asleep, asleep, "jar {i}");
                assert!(!asleep || jar.disturbance.displacement == 0.0);
            }
        }
    }
}

/// Shoves the first of two round jars in a row along +x with a rigid finger; returns how far
/// each jar moved.
fn shove_into_neighbour(asleep: bool) -> (f64, f64) {
    let pushed = common::test_jar(JarShape::Round { radius: 0.025 }, -0.05, 0.15, 0.0);
    let neighbour = common::test_jar(JarShape::Round { radius: 0.025 }, 0.01, 0.15, 0.0);
    let mut config = SceneConfig::default();
    config.hand.rigid_finger = true;
    config.physics.jars_start_asleep = asleep;
    common::start_beside(&mut config, &pushed, 0.006);
    let layout = Layout {
        jars: vec![pushed, neighbour],
        ..Layout::lone_jar(pushed)
    };
    let mut scene =
        Scene::from_layout(&Checked::new(config).unwrap(), layout, 0).expect("scene builds");
    for _ in 0..25 {
        scene
            .step(HandCommand {
                dx: 0.002,
                ..Default::default()
            })
            .expect("finite command");
    }
    let moved = scene.jar_states();
    assert!(
        moved.iter().all(|jar| !jar.asleep),
        "a pushed jar still asleep"
    );
    (
        moved[0].disturbance.displacement,
        moved[1].disturbance.displacement,
    )
}

#[test]
fn a_shoved_jar_wakes_and_wakes_the_sleeping_jar_it_is_pushed_into() {
    let (pushed, neighbour) = shove_into_neighbour(true);
    println!("asleep at start: pushed {pushed} m, neighbour {neighbour} m");
    assert!(pushed > 0.02, "the shoved jar moved only {pushed} m");
    assert!(neighbour > 0.01, "the neighbour moved only {neighbour} m");
    let (pushed_awake, neighbour_awake) = shove_into_neighbour(false);
    println!("awake at start: pushed {pushed_awake} m, neighbour {neighbour_awake} m");
    assert!((pushed - pushed_awake).abs() < 1e-3);
    assert!((neighbour - neighbour_awake).abs() < 1e-3);
}
