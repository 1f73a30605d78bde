//! Criterion benchmarks of the cupboard scene and the episode's reset: a scene step in free
//! motion and with the finger pressed on a jar (the default physics substeps), a single
//! physics step in contact, one whole depth capture (render + cloud + slice), layout
//! generation, a scene reset (layout + world + the first look's slice), and an episode reset
//! (scene, prior, map, metrics) with the GPIS map and with none.
//!
//! Run: `cargo bench -p env_core --bench scene` (append `-- --quick` on a noisy machine).

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use env_core::episode::{ActionMode, Episode, EpisodeConfig, MapMode};
use env_core::scene::{
    Cupboard, DepthCamera, HandCommand, JarShape, JarSpec, Layout, Scene, SceneConfig,
};
use env_core::settings::Checked;

/// A scene whose finger is pressed 8 mm into a round jar's side (deflected, in contact).
fn pressed_scene() -> Scene {
    let jar = JarSpec {
        shape: JarShape::Round { radius: 0.025 },
        height: 0.11,
        mass: 0.15,
        x: 0.0,
        y: 0.15,
        yaw: 0.0,
    };
    let mut config = SceneConfig::default();
    config.hand.start = [-0.034, 0.063, 0.0];
    let layout = Layout::lone_jar(jar);
    let mut scene =
        Scene::from_layout(&Checked::new(config).unwrap(), layout, 0).expect("scene builds");
    for _ in 0..7 {
        scene
            .step(HandCommand {
                dx: 0.002,
                ..Default::default()
            })
            .expect("finite");
    }
    assert!(!scene.true_contacts().is_empty(), "finger not in contact");
    scene
}

fn bench_physics(c: &mut Criterion) {
    let mut scene =
        Scene::new(&Checked::new(SceneConfig::default()).unwrap(), 1).expect("scene builds");
    let mut k = 0u64;
    c.bench_function("scene_step_free_motion", |b| {
        b.iter(|| {
            // Sideways in front of the opening, touching nothing.
            k += 1;
            let dx = if (k / 5) % 2 == 0 { 0.01 } else { -0.01 };
            black_box(
                scene
                    .step(HandCommand {
                        dx,
                        ..Default::default()
                    })
                    .expect("finite"),
            );
        })
    });
    assert!(
        scene.true_contacts().is_empty(),
        "free motion touched a jar"
    );
    let mut scene = pressed_scene();
    let mut k = 0u64;
    c.bench_function("scene_step_finger_in_contact", |b| {
        b.iter(|| {
            // Slide back and forth along the jar so the contact stays live.
            k += 1;
            let dy = if (k / 10) % 2 == 0 { 0.0005 } else { -0.0005 };
            black_box(
                scene
                    .step(HandCommand {
                        dy,
                        ..Default::default()
                    })
                    .expect("finite"),
            );
        })
    });
    assert!(
        !scene.true_contacts().is_empty(),
        "contact lost during the benchmark"
    );
    let mut scene = pressed_scene();
    c.bench_function("physics_step_finger_in_contact (1 step)", |b| {
        b.iter(|| scene.idle(black_box(1)))
    });
}

fn bench_depth(c: &mut Criterion) {
    let mut scene =
        Scene::new(&Checked::new(SceneConfig::default()).unwrap(), 3).expect("scene builds");
    c.bench_function("depth_capture_160x120", |b| {
        b.iter(|| black_box(scene.capture()))
    });
}

fn bench_layout(c: &mut Criterion) {
    let config = SceneConfig::default();
    let cupboard = Cupboard::new(&config.cupboard);
    let camera = DepthCamera::new(&config.camera).expect("camera");
    let mut seed = 0u64;
    c.bench_function("layout_generation", |b| {
        b.iter(|| {
            seed += 1;
            black_box(Layout::generate(&config.layout, &cupboard, &camera, seed).expect("layout"))
        })
    });
    let mut seed = 0u64;
    c.bench_function("scene_reset (layout + world + first look's slice)", |b| {
        b.iter(|| {
            seed += 1;
            black_box(Scene::new(&Checked::new(config.clone()).unwrap(), seed).expect("scene"))
        })
    });
}

/// The reset of a probe-mode episode (the learned agents' mode; a reset does the same work in
/// either action mode) from validation seeds: with the GPIS map, whose depth prior is most of
/// it, and with none, the scene and metrics alone.
fn bench_episode_reset(c: &mut Criterion) {
    for (name, mode) in [
        ("episode_reset_gpis (probe mode)", MapMode::Gpis),
        ("episode_reset_none (probe mode)", MapMode::None),
    ] {
        let mut config = EpisodeConfig::default();
        config.map.mode = mode;
        config.action_mode = ActionMode::Probe;
        let mut episode =
            Episode::started(Checked::new(config).unwrap(), 0).expect("episode starts");
        let mut seed = 1_000_000u64;
        c.bench_function(name, |b| {
            b.iter(|| {
                seed += 1;
                episode.reset(seed).expect("reset");
            })
        });
    }
}

criterion_group!(
    benches,
    bench_physics,
    bench_depth,
    bench_layout,
    bench_episode_reset
);
criterion_main!(benches);
