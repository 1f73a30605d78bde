//! Jars left alone stay put: 1000 physics steps without the hand moving move no jar more than
//! 0.1 mm (3D, from its pose at reset) and tilt none, whether they start asleep (the
//! default) or are simulated from the first step.

use env_core::scene::{Scene, SceneConfig};
use env_core::settings::Checked;

#[test]
fn jars_left_alone_move_less_than_a_tenth_of_a_millimetre_in_1000_steps() {
    for (seed, jars, asleep) in [
        (0, [3, 7], true),
        (1, [7, 7], true),
        (0, [3, 7], false),
        (1, [7, 7], false),
        (2, [7, 7], false),
        (3, [3, 3], false),
    ] {
        let mut config = SceneConfig::default();
        config.layout.jar_count = jars;
        config.physics.jars_start_asleep = asleep;
        let mut scene = Scene::new(&Checked::new(config).unwrap(), seed).expect("scene builds");
        let before = scene.jar_states();
        scene.idle(1000);
        let after = scene.jar_states();
        assert_eq!(before.len(), after.len());
        for (i, (a, b)) in before.iter().zip(&after).enumerate() {
            let moved = (0..3)
                .map(|k| (a.position[k] - b.position[k]).powi(2))
                .sum::<f64>()
                .sqrt();
            assert!(
                moved < 1e-4,
                "seed {seed}: jar {i} moved {moved} m in 1000 steps (from {:?} to {:?})",
                a.position,
                b.position
            );
            assert!(
                b.disturbance.displacement < 1e-4,
                "seed {seed} jar {i}: {:?}",
                b.disturbance
            );
            assert!(
                b.disturbance.tilt < 1e-3,
                "seed {seed} jar {i} tilted: {:?}",
                b.disturbance
            );
        }
    }
}
