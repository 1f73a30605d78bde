//! Touch is non-intrusive: pressing the finger's edge 12 mm past first contact and sweeping it
//! 2 cm each way along a jar at the default stiffness moves the jar less than 2 mm (the finger deflects and
//! the deflection is sensed), while the same sweep with a rigid finger moves it more than 1 cm.

mod common;

use env_core::scene::{HandCommand, JarShape, Layout, Scene, SceneConfig};
use env_core::settings::Checked;

/// Runs the sweep; returns the jar's largest displacement, its largest tilt and the finger's
/// largest deflection, and the number of steps with a reading.
fn sweep(shape: JarShape, rigid: bool) -> (f64, f64, f64, usize) {
    let jar = common::test_jar(shape, 0.0, 0.15, 0.0);
    let mut config = SceneConfig::default();
    config.hand.rigid_finger = rigid;
    common::start_beside(&mut config, &jar, 0.006);
    let layout = Layout::lone_jar(jar);
    let mut scene =
        Scene::from_layout(&Checked::new(config).unwrap(), layout, 0).expect("scene builds");
    let script = (0..9)
        .map(|_| HandCommand {
            dx: 0.002,
            ..Default::default()
        })
        .chain((0..10).map(|_| HandCommand {
            dy: 0.002,
            ..Default::default()
        }))
        .chain((0..20).map(|_| HandCommand {
            dy: -0.002,
            ..Default::default()
        }))
        .chain((0..10).map(|_| HandCommand {
            dy: 0.002,
            ..Default::default()
        }));
    let (mut moved, mut tilt, mut deflection, mut touching) = (0.0f64, 0.0f64, 0.0f64, 0);
    for command in script {
        scene.step(command).expect("finite command");
        let d = scene.jar_states()[0].disturbance;
        moved = moved.max(d.displacement);
        tilt = tilt.max(d.tilt);
        deflection = deflection.max(scene.finger_angle().abs());
        touching += usize::from(!scene.true_contacts().is_empty());
    }
    (moved, tilt, deflection, touching)
}

#[test]
fn compliant_finger_slides_along_jars_without_moving_them() {
    for shape in [
        JarShape::Round { radius: 0.025 },
        JarShape::Square { half_side: 0.024 },
    ] {
        let (moved, tilt, deflection, touching) = sweep(shape, false);
        println!("compliant {shape:?}: moved {moved} m, tilt {tilt}, deflection {deflection}");
        assert!(moved < 2e-3, "{shape:?}: jar moved {moved} m");
        assert!(tilt < 0.05, "{shape:?}: jar tilted {tilt} rad");
        assert!(
            deflection > 0.1,
            "{shape:?}: finger deflected only {deflection} rad"
        );
        assert!(touching > 35, "{shape:?}: touched in only {touching} steps");
    }
}

#[test]
fn rigid_finger_shoves_the_same_jar_more_than_a_centimetre() {
    for shape in [
        JarShape::Round { radius: 0.025 },
        JarShape::Square { half_side: 0.024 },
    ] {
        let (moved, _, deflection, touching) = sweep(shape, true);
        println!("rigid {shape:?}: moved {moved} m");
        assert!(
            moved > 1e-2,
            "{shape:?}: rigid finger moved the jar only {moved} m"
        );
        assert_eq!(deflection, 0.0);
        assert!(touching > 0);
    }
}
