//! The incremental posterior equals a full recompute over the same rows, however the rows
//! arrive (one by one, in chunks, in large batches), and predictions agree with the grid.

mod gpis_fixtures;

use env_core::gpis::{Gpis, Observation};
use rand::Rng;

fn assert_matches_full_recompute(map: &Gpis, context: &str) {
    let full = map.recompute_from_scratch();
    let mean_error = gpis_fixtures::max_abs_difference(map.mean_grid(), &full.mean);
    let variance_error = gpis_fixtures::max_abs_difference(map.variance_grid(), &full.variance);
    assert!(
        mean_error <= 1e-9,
        "{context}: mean differs by {mean_error}"
    );
    assert!(
        variance_error <= 1e-9,
        "{context}: variance differs by {variance_error}"
    );
}

#[test]
fn incremental_equals_full_recompute_over_long_random_sequences() {
    for seed in 0..4 {
        let mut rng = gpis_fixtures::rng(seed);
        let mut map = gpis_fixtures::shelf_map((24, 32), 0.01, 2000);
        let mut index = 0;
        for step in 0..60 {
            // Mix single observations and batches of up to 70 (more than one chunk).
            let batch = if rng.random_bool(0.7) {
                1
            } else {
                rng.random_range(2..70)
            };
            let observations: Vec<_> = (0..batch)
                .map(|_| {
                    index += 1;
                    gpis_fixtures::random_observation(&mut rng, index)
                })
                .collect();
            map.add(&observations, None).unwrap();
            if step % 15 == 14 {
                assert_matches_full_recompute(&map, &format!("seed {seed}, step {step}"));
            }
        }
        assert!(
            map.n_rows() > 300,
            "the sequence should grow the map: {}",
            map.n_rows()
        );
        assert_matches_full_recompute(&map, &format!("seed {seed}, end"));
    }
}

#[test]
fn batch_and_one_by_one_additions_give_the_same_posterior() {
    let mut rng = gpis_fixtures::rng(7);
    let observations: Vec<_> = (0..150)
        .map(|i| gpis_fixtures::random_observation(&mut rng, i))
        .collect();
    let mut batched = gpis_fixtures::shelf_map((16, 16), 0.0, 1000);
    let mut one_by_one = batched.clone();
    batched.add(&observations, None).unwrap();
    for obs in &observations {
        one_by_one.add(std::slice::from_ref(obs), None).unwrap();
    }
    assert_eq!(batched.n_rows(), one_by_one.n_rows());
    assert!(gpis_fixtures::max_abs_difference(batched.mean_grid(), one_by_one.mean_grid()) <= 1e-9);
    assert!(
        gpis_fixtures::max_abs_difference(batched.variance_grid(), one_by_one.variance_grid())
            <= 1e-9
    );
}

#[test]
fn predict_at_cell_centres_agrees_with_the_grid() {
    let mut rng = gpis_fixtures::rng(3);
    let mut map = gpis_fixtures::shelf_map((12, 20), 0.02, 1000);
    let observations: Vec<_> = (0..80)
        .map(|i| gpis_fixtures::random_observation(&mut rng, i))
        .collect();
    map.add(&observations, None).unwrap();
    let centres = map.grid().cell_centres();
    let prediction = map.predict(&centres).unwrap();
    assert!(gpis_fixtures::max_abs_difference(&prediction.mean, map.mean_grid()) <= 1e-9);
    assert!(gpis_fixtures::max_abs_difference(&prediction.variance, map.variance_grid()) <= 1e-9);
}

#[test]
fn same_inputs_give_bitwise_identical_maps() {
    let build = || {
        let mut rng = gpis_fixtures::rng(11);
        let mut map = gpis_fixtures::shelf_map((16, 16), 0.0, 1000);
        for i in 0..100 {
            map.add(&[gpis_fixtures::random_observation(&mut rng, i)], None)
                .unwrap();
        }
        map
    };
    let (a, b) = (build(), build());
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(a.mean_grid()), bits(b.mean_grid()));
    assert_eq!(bits(a.variance_grid()), bits(b.variance_grid()));
}

#[test]
fn a_clone_grows_like_its_original_and_independently_of_it() {
    let mut rng = gpis_fixtures::rng(13);
    let mut original = gpis_fixtures::shelf_map((16, 16), 0.0, 1000);
    let first: Vec<_> = (0..70)
        .map(|i| gpis_fixtures::random_observation(&mut rng, i))
        .collect();
    original.add(&first, None).unwrap();
    let mut copy = original.clone();
    let before = original.mean_grid().to_vec();
    let more: Vec<_> = (0..40)
        .map(|i| gpis_fixtures::random_observation(&mut rng, i))
        .collect();
    copy.add(&more, None).unwrap();
    assert_eq!(
        original.mean_grid(),
        &before[..],
        "the original is untouched"
    );
    original.add(&more, None).unwrap();
    assert_eq!(original.n_rows(), copy.n_rows());
    assert_eq!(original.mean_grid(), copy.mean_grid());
    assert_eq!(original.variance_grid(), copy.variance_grid());
}

/// A depth prior like the episode's (`docs/DESIGN.md` §3, §9.1): 96 noisy points on the
/// visible fronts of five jars, each with a free-space row 1 cm towards the camera, on the
/// environment's 40 × 80 grid, in one `add` (192 rows: four factorisation chunks, one grid
/// update), then touches one at a time with skipping. The grid stays within 1e-9 of a full
/// recompute throughout.
#[test]
fn an_episode_sized_prior_in_one_add_matches_full_recompute() {
    let mut rng = gpis_fixtures::rng(17);
    let camera = [0.0, -0.25];
    let mut observations = Vec::new();
    let mut front = Vec::new();
    for (jar, &x) in [-0.2, -0.09, 0.0, 0.1, 0.21].iter().enumerate() {
        let centre = [x, 0.08 + 0.04 * jar as f64];
        for k in 0..19 + usize::from(jar == 0) {
            let angle = -2.6 + 2.2 * k as f64 / 19.0;
            let noise = [
                rng.random_range(-0.002..0.002),
                rng.random_range(-0.002..0.002),
            ];
            front.push([
                centre[0] + 0.025 * f64::cos(angle) + noise[0],
                centre[1] + 0.025 * f64::sin(angle) + noise[1],
            ]);
        }
    }
    assert_eq!(front.len(), 96);
    let noise_var = 0.003f64.powi(2);
    for (i, &p) in front.iter().enumerate() {
        observations.push(Observation::value(i, p, 0.0, noise_var).unwrap());
    }
    for (i, &p) in front.iter().enumerate() {
        let towards = [camera[0] - p[0], camera[1] - p[1]];
        let length = towards[0].hypot(towards[1]);
        let q = [
            p[0] + 0.01 * towards[0] / length,
            p[1] + 0.01 * towards[1] / length,
        ];
        observations.push(Observation::value(i, q, 0.01, noise_var).unwrap());
    }
    let mut map = gpis_fixtures::shelf_map((40, 80), 0.01, 1500);
    let report = map.add(&observations, None).unwrap();
    assert_eq!(report.added_rows, 192);
    assert_matches_full_recompute(&map, "prior");
    for i in 0..30 {
        let contact = gpis_fixtures::random_observation(&mut rng, i);
        map.add(&[contact], Some(1e-5)).unwrap();
    }
    assert!(
        map.n_rows() > 192,
        "touches should add rows: {}",
        map.n_rows()
    );
    assert_matches_full_recompute(&map, "prior and touches");
}
