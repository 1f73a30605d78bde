//! The depth camera sees true surfaces: back-projected points lie on the jars and walls they
//! hit within 1 mm before noise, the slice is the band at the map height, thinning is
//! deterministic and bounded, and the added noise has the configured standard deviation.

mod common;

use common::{box_sdf, JarGeom};
use env_core::scene::{Scene, SceneConfig, LABEL_CUPBOARD, LABEL_NONE};
use env_core::settings::Checked;

#[test]
fn camera_points_lie_on_true_surfaces_within_1_mm_before_noise() {
    for seed in 0..6 {
        let scene =
            Scene::new(&Checked::new(SceneConfig::default()).unwrap(), seed).expect("scene builds");
        let jars: Vec<JarGeom> = scene.jar_states().iter().map(JarGeom::of).collect();
        let walls = scene.cupboard().walls();
        let look = scene.first_look();
        assert!(
            look.cloud.len() > 1000,
            "too few points: {}",
            look.cloud.len()
        );
        let mut on_jars = 0;
        for (p, &label) in look.cloud.iter().zip(&look.cloud_labels) {
            let distance = if label >= 0 {
                on_jars += 1;
                jars[label as usize].sdf(*p).abs()
            } else {
                assert_eq!(label, LABEL_CUPBOARD);
                walls
                    .iter()
                    .map(|w| box_sdf(w, *p).abs())
                    .fold(f64::INFINITY, f64::min)
            };
            assert!(
                distance < 1e-3,
                "seed {seed}: point {p:?} (label {label}) is {distance} m off its surface"
            );
        }
        assert!(on_jars > 50, "seed {seed}: only {on_jars} points on jars");
        // The clean slice: each point is on the side of the jar (or wall) it came from.
        let h = scene.config().slice_height;
        for (q, &label) in look.slice_clean.iter().zip(&look.slice_labels) {
            if label >= 0 {
                let d = jars[label as usize].sdf([q[0], q[1], h]).abs();
                assert!(
                    d < 1e-3,
                    "seed {seed}: slice point {q:?} is {d} m off jar {label}"
                );
            }
        }
    }
}

#[test]
fn depth_image_has_the_configured_shape_and_nan_exactly_where_nothing_was_hit() {
    let mut config = SceneConfig::default();
    config.camera.image_width = 64;
    config.camera.image_height = 48;
    config.camera.hfov = 2.4;
    let scene = Scene::new(&Checked::new(config).unwrap(), 5).expect("scene builds");
    let image = &scene.first_look().image;
    assert_eq!((image.width, image.height), (64, 48));
    assert_eq!(image.depth.len(), 64 * 48);
    let mut misses = 0;
    for (d, &l) in image.depth.iter().zip(&image.labels) {
        assert_eq!(d.is_nan(), l == LABEL_NONE);
        misses += usize::from(l == LABEL_NONE);
    }
    // A 137° view from outside the cupboard sees past its sides.
    assert!(misses > 0);
    assert_eq!(scene.first_look().cloud.len(), 64 * 48 - misses);
}

#[test]
fn slice_is_the_band_at_the_map_height_thinned_evenly_and_deterministically() {
    let mut config = SceneConfig::default();
    config.camera.max_slice_points = 1_000_000;
    let full = Scene::new(&Checked::new(config.clone()).unwrap(), 11).expect("scene builds");
    let look = full.first_look();
    let h = config.slice_height;
    let band: Vec<[f64; 2]> = look
        .cloud
        .iter()
        .filter(|p| (p[2] - h).abs() <= 0.5 * config.camera.slice_band)
        .map(|p| [p[0], p[1]])
        .collect();
    assert!(band.len() > 100);
    assert_eq!(look.slice_clean, band);

    config.camera.max_slice_points = 40;
    let thin = Scene::new(&Checked::new(config.clone()).unwrap(), 11).expect("scene builds");
    let again = Scene::new(&Checked::new(config).unwrap(), 11).expect("scene builds");
    let thinned = &thin.first_look().slice_clean;
    assert_eq!(thinned.len(), 40);
    assert!(thinned.iter().all(|p| band.contains(p)));
    assert_eq!(thinned, &again.first_look().slice_clean);
    assert_eq!(thin.first_look().slice, again.first_look().slice);
}

#[test]
fn slice_noise_has_the_configured_standard_deviation() {
    let sigma = 0.004;
    let mut config = SceneConfig::default();
    config.camera.noise_std = sigma;
    config.camera.max_slice_points = 1_000_000;
    config.camera.slice_band = 0.04;
    let mut errors = Vec::new();
    for seed in 0..3 {
        let scene = Scene::new(&Checked::new(config.clone()).unwrap(), seed).expect("scene builds");
        let look = scene.first_look();
        for (noisy, clean) in look.slice.iter().zip(&look.slice_clean) {
            errors.push(noisy[0] - clean[0]);
            errors.push(noisy[1] - clean[1]);
        }
    }
    let n = errors.len() as f64;
    assert!(n > 4000.0, "too few samples: {n}");
    let mean = errors.iter().sum::<f64>() / n;
    let std = (errors.iter().map(|e| (e - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
    // Standard errors: sigma/sqrt(n) for the mean, about sigma/sqrt(2n) for the std; allow 5.
    assert!(mean.abs() < 5.0 * sigma / n.sqrt(), "mean {mean}");
    assert!(
        (std - sigma).abs() < 5.0 * sigma / (2.0 * n).sqrt(),
        "std {std} vs {sigma}"
    );

    config.camera.noise_std = 0.0;
    let clean = Scene::new(&Checked::new(config).unwrap(), 0).expect("scene builds");
    assert_eq!(clean.first_look().slice, clean.first_look().slice_clean);
}

#[test]
fn the_hand_never_occludes_the_camera() {
    // The camera's look is taken before the hand reaches in; a later capture with the hand
    // deep in the cupboard still sees only walls and jars.
    let mut scene =
        Scene::new(&Checked::new(SceneConfig::default()).unwrap(), 2).expect("scene builds");
    let corridor = scene.layout().corridor.expect("corridor");
    let x = 0.5 * (corridor.x[0] + corridor.x[1]);
    for k in 0..70 {
        // Line up with the corridor outside the cupboard, then go straight in.
        let pose = scene.hand_pose();
        let command = env_core::scene::HandCommand {
            dx: (x - pose.x).clamp(-0.01, 0.01),
            dy: if k < 30 { 0.0 } else { 0.005 },
            dyaw: 0.0,
        };
        scene.step(command).expect("finite");
    }
    assert!(
        scene.hand_pose().y > 0.05,
        "hand not inside: {:?}",
        scene.hand_pose()
    );
    let look = scene.capture();
    let jars: Vec<JarGeom> = scene.jar_states().iter().map(JarGeom::of).collect();
    let walls = scene.cupboard().walls();
    for (p, &label) in look.cloud.iter().zip(&look.cloud_labels) {
        let distance = if label >= 0 {
            jars[label as usize].sdf(*p).abs()
        } else {
            walls
                .iter()
                .map(|w| box_sdf(w, *p).abs())
                .fold(f64::INFINITY, f64::min)
        };
        assert!(
            distance < 1e-3,
            "point {p:?} (label {label}) is {distance} m off any surface"
        );
    }
}

#[test]
fn the_reset_slice_from_the_band_rows_equals_the_whole_first_looks_slice() {
    // Reset casts only the rows that can reach the slice band; the whole image, rendered on
    // demand, must give the same slice, noise included, for any camera pose and band.
    let mut tilted = SceneConfig::default();
    tilted.camera.position = [0.05, -0.3, 0.2];
    tilted.camera.look_at = [0.0, 0.3, 0.0];
    let mut wide_band = SceneConfig::default();
    wide_band.camera.slice_band = 0.04;
    let mut noiseless = SceneConfig::default();
    noiseless.camera.noise_std = 0.0;
    for (name, config) in [
        ("default", SceneConfig::default()),
        ("tilted", tilted),
        ("wide band", wide_band),
        ("noiseless", noiseless),
    ] {
        for seed in 0..8 {
            let scene =
                Scene::new(&Checked::new(config.clone()).unwrap(), seed).expect("scene builds");
            let look = scene.first_look();
            assert!(!look.slice.is_empty(), "{name} seed {seed}: empty slice");
            assert_eq!(
                scene.first_slice(),
                look.slice.as_slice(),
                "{name} seed {seed}"
            );
        }
    }
}

#[test]
fn a_look_at_reset_sees_what_the_first_look_saw() {
    // capture() renders the world's current poses; first_look() the layout at rest. Before
    // anything moves the two images are the same, pixel for pixel.
    for seed in 0..4 {
        let mut scene =
            Scene::new(&Checked::new(SceneConfig::default()).unwrap(), seed).expect("scene builds");
        let first = scene.first_look().image;
        let now = scene.capture().image;
        assert_eq!(first.labels, now.labels, "seed {seed}");
        for (a, b) in first.depth.iter().zip(&now.depth) {
            assert!(
                a == b || (a.is_nan() && b.is_nan()),
                "seed {seed}: {a} vs {b}"
            );
        }
    }
}
