//! Touch is geometrically right: while the finger's long edge presses on and slides along a
//! jar, every reading lies on the jar's surface within 1 mm, with the jar's outward normal
//! within 3° (radial on round jars, a face normal on square ones); no reading appears before
//! the finger touches, and readings on one jar are at least the merge distance apart.

mod common;

use common::{angle_deg, JarGeom};
use env_core::scene::{Contact, HandCommand, JarShape, Layout, Scene, SceneConfig};
use env_core::settings::Checked;

/// Presses the finger's +x side onto a jar centred at (0, 0.15) from a gap of 6 mm, then
/// slides along it and back; returns the readings of every step with the jar's pose at that
/// step, and the scene.
fn press_and_slide(shape: JarShape, yaw: f64) -> (Vec<(Vec<Contact>, JarGeom)>, Scene) {
    let jar = common::test_jar(shape, 0.0, 0.15, yaw);
    let mut config = SceneConfig::default();
    config.touch.point_noise_std = 0.0;
    config.touch.normal_noise_std = 0.0;
    common::start_beside(&mut config, &jar, 0.006);
    let layout = Layout::lone_jar(jar);
    let mut scene =
        Scene::from_layout(&Checked::new(config).unwrap(), layout, 0).expect("scene builds");
    let mut readings = Vec::new();
    let script = (0..10)
        .map(|_| HandCommand {
            dx: 0.002,
            ..Default::default()
        })
        .chain((0..12).map(|_| HandCommand {
            dy: 0.002,
            ..Default::default()
        }))
        .chain((0..24).map(|_| HandCommand {
            dy: -0.002,
            ..Default::default()
        }));
    for (k, command) in script.enumerate() {
        scene.step(command).expect("finite command");
        if k < 2 {
            // The finger is still at least 2 mm away: predicted contacts must not leak.
            assert!(
                scene.true_contacts().is_empty(),
                "step {k}: {:?}",
                scene.true_contacts()
            );
        }
        let geom = JarGeom::of(&scene.jar_states()[0]);
        readings.push((scene.true_contacts().to_vec(), geom));
    }
    (readings, scene)
}

fn check_distinct(contacts: &[Contact], merge: f64) {
    for (i, a) in contacts.iter().enumerate() {
        for b in &contacts[..i] {
            if a.jar == b.jar {
                let d = (a.point[0] - b.point[0]).hypot(a.point[1] - b.point[1]);
                assert!(d > merge, "duplicate readings {a:?} {b:?}");
            }
        }
    }
}

#[test]
fn on_round_jars_contacts_are_on_the_surface_with_radial_normals() {
    let (readings, scene) = press_and_slide(JarShape::Round { radius: 0.026 }, 0.0);
    let h = scene.config().slice_height;
    let mut n = 0;
    for (contacts, geom) in &readings {
        check_distinct(contacts, scene.config().touch.merge_distance);
        for c in contacts {
            n += 1;
            assert_eq!(c.jar, 0);
            let off = geom.sdf([c.point[0], c.point[1], h]).abs();
            assert!(off < 1e-3, "{c:?} is {off} m off the surface");
            let radial = [c.point[0] - geom.x, c.point[1] - geom.y];
            let err = angle_deg(c.normal, radial);
            assert!(err < 3.0, "{c:?}: normal {err}° from radial");
            assert!((c.normal[0].hypot(c.normal[1]) - 1.0).abs() < 1e-9);
            // The finger comes from -x: the normal faces it.
            assert!(c.normal[0] < 0.0);
        }
    }
    assert!(n >= 30, "only {n} readings");
}

#[test]
fn on_square_jars_contacts_are_on_a_face_with_its_normal() {
    for yaw in [0.0, 0.35] {
        let (readings, scene) = press_and_slide(JarShape::Square { half_side: 0.024 }, yaw);
        let h = scene.config().slice_height;
        let mut n = 0;
        for (contacts, geom) in &readings {
            check_distinct(contacts, scene.config().touch.merge_distance);
            for c in contacts {
                n += 1;
                let off = geom.sdf([c.point[0], c.point[1], h]).abs();
                assert!(off < 1e-3, "yaw {yaw}: {c:?} is {off} m off the surface");
                // The face normal nearest the reading, and the reading on that face.
                let (s, co) = geom.yaw.sin_cos();
                let faces = [[co, s], [-s, co], [-co, -s], [s, -co]];
                let (face, err) = faces
                    .iter()
                    .map(|f| (*f, angle_deg(c.normal, *f)))
                    .min_by(|a, b| a.1.total_cmp(&b.1))
                    .expect("four faces");
                assert!(
                    err < 3.0,
                    "yaw {yaw}: {c:?}: normal {err}° from the nearest face normal"
                );
                let along = (c.point[0] - geom.x) * face[0] + (c.point[1] - geom.y) * face[1];
                assert!(
                    (along - 0.024).abs() < 1e-3,
                    "yaw {yaw}: {c:?} not on the face {face:?}"
                );
            }
        }
        assert!(n >= 30, "yaw {yaw}: only {n} readings");
    }
}
