//! The target is hidden and reachable: over 200 seeds the camera sees at most
//! `max_visible_fraction` (10 %) of its silhouette, measured independently of the generator
//! (silhouette by exact f64 ray–jar intersection, visibility from the rendered depth labels),
//! and every layout keeps its jars apart, inside the cupboard and out of the corridor.

mod common;

use common::JarGeom;
use env_core::scene::{JarShape, Scene, SceneConfig};
use env_core::settings::Checked;

#[test]
fn over_200_seeds_the_camera_sees_at_most_the_bound_of_the_target() {
    let config = SceneConfig::default();
    let bound = config.layout.max_visible_fraction;
    assert!(bound <= 0.10);
    let mut worst = 0.0f64;
    let mut shapes = [0usize; 2];
    let mut counts = [0usize; 8];
    for seed in 0..200 {
        let scene = Scene::new(&Checked::new(config.clone()).unwrap(), seed).expect("scene builds");
        let states = scene.jar_states();
        let target = scene.target();
        let geom = JarGeom::of(&states[target]);
        let camera = scene.camera();
        let image = &scene.first_look().image;
        let origin = camera.position();
        let (mut silhouette, mut visible) = (0usize, 0usize);
        for v in 0..image.height {
            for u in 0..image.width {
                if geom.ray_hit(origin, camera.pixel_direction(u, v)).is_some() {
                    silhouette += 1;
                    if image.labels[v * image.width + u] == target as i32 {
                        visible += 1;
                    }
                }
            }
        }
        assert!(
            silhouette > 20,
            "seed {seed}: target barely in view ({silhouette} px)"
        );
        let fraction = visible as f64 / silhouette as f64;
        assert!(
            fraction <= bound,
            "seed {seed}: {visible}/{silhouette} = {fraction} of the target is visible (bound {bound})"
        );
        worst = worst.max(fraction);
        shapes[usize::from(matches!(states[target].spec.shape, JarShape::Round { .. }))] += 1;
        counts[states.len()] += 1;

        // Layout invariants: apart, inside, corridor clear.
        let layout = scene.layout();
        let corridor = layout.corridor.expect("generated layouts have a corridor");
        let half_w = 0.5 * scene.cupboard().width();
        assert!(corridor.x[0] >= -half_w && corridor.x[1] <= half_w);
        for (i, a) in layout.jars.iter().enumerate() {
            let r = a.shape.bounding_radius();
            assert!(a.x - r >= -half_w && a.x + r <= half_w && a.y - r >= 0.0);
            assert!(a.y + r <= scene.cupboard().depth());
            if i != target {
                assert!(
                    corridor.distance([a.x, a.y]) >= r,
                    "seed {seed}: jar {i} in the corridor"
                );
            }
            for b in &layout.jars[..i] {
                assert!((a.x - b.x).hypot(a.y - b.y) >= r + b.shape.bounding_radius());
            }
        }
        let t = &layout.jars[target];
        let gap = if corridor.side > 0.0 {
            corridor.x[0] - (t.x + t.half_extent_x())
        } else {
            t.x - t.half_extent_x() - corridor.x[1]
        };
        assert!(
            (0.0..=0.01).contains(&gap),
            "seed {seed}: corridor {gap} m from the target's side"
        );
    }
    println!("worst visible fraction {worst}, target shapes [square, round] {shapes:?}, jar counts {counts:?}");
    assert!(shapes[0] > 40 && shapes[1] > 40, "target shapes {shapes:?}");
    assert!((3..=7).all(|n| counts[n] > 10), "jar counts {counts:?}");
}
