//! Shared fixtures of the GPIS integration tests: a shelf-sized map and random observations.
#![allow(dead_code)]

use env_core::gpis::{Gpis, GpisConfig, Observation};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// The shelf slice: 0.6 m wide, 0.3 m deep.
pub const BOUNDS: [[f64; 2]; 2] = [[-0.3, 0.3], [0.0, 0.3]];

/// A map over [`BOUNDS`] with the default ψ.
pub fn shelf_map(shape: (usize, usize), prior_mean: f64, max_rows: usize) -> Gpis {
    Gpis::new(GpisConfig {
        bounds: BOUNDS,
        shape,
        psi: None,
        prior_mean,
        max_rows,
    })
    .expect("valid config")
}

/// A seeded generator.
pub fn rng(seed: u64) -> ChaCha8Rng {
    ChaCha8Rng::seed_from_u64(seed)
}

/// A uniformly random point inside [`BOUNDS`].
pub fn random_point(rng: &mut ChaCha8Rng) -> [f64; 2] {
    [
        rng.random_range(BOUNDS[0][0]..BOUNDS[0][1]),
        rng.random_range(BOUNDS[1][0]..BOUNDS[1][1]),
    ]
}

/// A random unit vector.
pub fn random_normal(rng: &mut ChaCha8Rng) -> [f64; 2] {
    let angle: f64 = rng.random_range(0.0..std::f64::consts::TAU);
    [angle.cos(), angle.sin()]
}

/// A random observation: a noisy value (f in [-0.02, 0.05]) or a noisy contact.
pub fn random_observation(rng: &mut ChaCha8Rng, index: usize) -> Observation {
    let point = random_point(rng);
    if rng.random_bool(0.5) {
        let value = rng.random_range(-0.02..0.05);
        Observation::value(index, point, value, 0.002f64.powi(2)).unwrap()
    } else {
        let normal = random_normal(rng);
        Observation::contact(index, point, normal, 0.0005f64.powi(2), 0.05f64.powi(2)).unwrap()
    }
}

/// Largest absolute difference between two equally long slices.
pub fn max_abs_difference(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}
