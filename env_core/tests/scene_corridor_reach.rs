//! Every generated layout leaves the target reachable: a simple scripted reach (into the
//! corridor, straight in to the target's depth, then a yaw towards the target) touches the
//! target with the finger without moving any other jar by 2 mm or tipping it.

use env_core::scene::{HandCommand, Scene, SceneConfig};
use env_core::settings::Checked;

/// Steps the wrist towards `(x, y)` in moves of at most 1 cm; returns false if blocked.
fn go_to(scene: &mut Scene, x: f64, y: f64) -> bool {
    for _ in 0..200 {
        let pose = scene.hand_pose();
        let (dx, dy) = (x - pose.x, y - pose.y);
        if dx.abs() < 1e-9 && dy.abs() < 1e-9 {
            return true;
        }
        let report = scene
            .step(HandCommand {
                dx: dx.clamp(-0.01, 0.01),
                dy: dy.clamp(-0.01, 0.01),
                dyaw: 0.0,
            })
            .expect("finite command");
        if report.blocked.is_some() {
            return false;
        }
    }
    false
}

#[test]
fn a_scripted_reach_through_the_corridor_touches_the_target_without_disturbing_others() {
    let config = SceneConfig::default();
    let reach = config.hand.wrist_half_extent + 0.002 + config.hand.finger_length;
    for seed in 0..60 {
        let mut scene =
            Scene::new(&Checked::new(config.clone()).unwrap(), seed).expect("scene builds");
        let layout = scene.layout().clone();
        let corridor = layout.corridor.expect("generated layouts have a corridor");
        let target = layout.jars[layout.target];
        // The wrist runs 2 mm inside the corridor's edge next to the target.
        let inner = if corridor.side > 0.0 {
            corridor.x[0]
        } else {
            corridor.x[1]
        };
        let x = inner + corridor.side * (config.hand.wrist_half_extent + 0.002);
        let start_y = scene.hand_pose().y;
        assert!(
            go_to(&mut scene, x, start_y),
            "seed {seed}: blocked outside the cupboard"
        );
        assert!(
            go_to(&mut scene, x, target.y - reach),
            "seed {seed}: blocked going in"
        );
        let mut touched = false;
        for _ in 0..30 {
            scene
                .step(HandCommand {
                    dyaw: 0.02 * corridor.side,
                    ..Default::default()
                })
                .expect("finite command");
            if scene.true_contacts().iter().any(|c| c.jar == layout.target) {
                touched = true;
                break;
            }
        }
        assert!(touched, "seed {seed}: the finger never touched the target");
        for (i, jar) in scene.jar_states().iter().enumerate() {
            if i != layout.target {
                assert!(
                    jar.disturbance.displacement < 2e-3 && jar.disturbance.tilt < 0.05,
                    "seed {seed}: jar {i} disturbed {:?}",
                    jar.disturbance
                );
            }
        }
    }
}
