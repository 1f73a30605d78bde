//! The incremental posterior equals a full recompute over the same rows, however the rows
//! arrive (one by one, in chunks, in large batches), and predictions agree with the grid.

mod gpis_fixtures;

use env_core::gpis::Gpis;
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
