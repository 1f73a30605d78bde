//! A map cleared and reused (as each episode reset does) gives the posterior of a fresh map,
//! and holds the storage its last use needed, not the most any use ever needed: memory stays
//! flat over many episodes of different sizes.

use env_core::gpis::{Gpis, GpisConfig};

fn map() -> Gpis {
    Gpis::new(GpisConfig {
        bounds: [[-0.3, 0.3], [0.0, 0.3]],
        shape: (20, 40),
        psi: None,
        prior_mean: 0.01,
        max_rows: 2000,
    })
    .expect("a valid map")
}

/// `count` distinct points spread over the bounds.
fn points(count: usize) -> Vec<[f64; 2]> {
    (0..count)
        .map(|i| {
            let t = i as f64 / count as f64;
            [-0.29 + 0.58 * (t * 37.0).fract(), 0.01 + 0.28 * t]
        })
        .collect()
}

#[test]
fn a_cleared_map_gives_the_posterior_of_a_fresh_one() {
    let mut reused = map();
    reused.add_values(&points(700), None, 1e-3).unwrap();
    reused.clear();
    reused.add_values(&points(90), None, 1e-3).unwrap();
    let mut fresh = map();
    fresh.add_values(&points(90), None, 1e-3).unwrap();
    assert_eq!(reused.mean_grid(), fresh.mean_grid());
    assert_eq!(reused.variance_grid(), fresh.variance_grid());
}

#[test]
fn clearing_releases_storage_a_large_map_grew_and_keeps_what_the_last_one_used() {
    let mut reused = map();
    let mut fresh = map();
    fresh.add_values(&points(100), None, 1e-3).unwrap();
    let small = fresh.memory_bytes();

    reused.add_values(&points(900), None, 1e-3).unwrap();
    let large = reused.memory_bytes();
    assert!(large > 4 * small, "{large} vs {small}");
    reused.clear(); // held 900 rows: keeps storage for 1350 (2048, capped at max_rows)
    reused.add_values(&points(100), None, 1e-3).unwrap();
    assert_eq!(
        reused.memory_bytes(),
        large,
        "storage the last use needed is kept"
    );
    reused.clear(); // held 100 rows: keeps storage for 150 (256), releases the rest
    assert!(
        4 * reused.memory_bytes() < large,
        "{} vs {large}",
        reused.memory_bytes()
    );
    // What it keeps is what a fresh map of that use grows to, no more.
    reused.add_values(&points(100), None, 1e-3).unwrap();
    assert_eq!(reused.memory_bytes(), small);
    reused.clear();
    // Reuse at the same size keeps the same storage (no reallocation every episode).
    reused.add_values(&points(100), None, 1e-3).unwrap();
    reused.clear();
    let steady = reused.memory_bytes();
    reused.add_values(&points(100), None, 1e-3).unwrap();
    reused.clear();
    assert_eq!(reused.memory_bytes(), steady);
}

/// An episode's map holds its prior (128 rows at the defaults) and then a few touches, or
/// none: uses alternating between just under and just over a power of two keep one storage
/// instead of growing it in one episode and giving it back at the next clear.
#[test]
fn uses_alternating_around_a_power_of_two_keep_one_storage() {
    let mut reused = map();
    reused.add_values(&points(128), None, 1e-3).unwrap();
    let prior_only = reused.memory_bytes();
    reused.add_values(&points(140)[128..], None, 1e-3).unwrap();
    assert_eq!(
        reused.memory_bytes(),
        prior_only,
        "a few touches need no growth"
    );
    for rows in [128, 135, 120, 140, 128] {
        reused.clear();
        reused.add_values(&points(rows), None, 1e-3).unwrap();
        assert_eq!(reused.memory_bytes(), prior_only, "{rows} rows");
    }
}
