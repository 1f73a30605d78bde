//! Criterion benchmark of the GPIS contact append against a full recompute (`docs/DESIGN.md` §5).
//!
//! Map: x in [-0.3, 0.3], y in [0, 0.3] (metres), 64 x 64 grid, default psi. For each n the
//! map holds exactly n rows: value rows at distinct random points (noise_std 0.002) plus
//! about 10 % of the rows as contacts, from a fixed seed.
//!
//! Groups:
//! - `append_one_contact/n=N`: one contact (3 rows) appended to a clone of the n-row map
//!   (`iter_batched`, the clone is made in the untimed setup; `Gpis::clone` keeps the
//!   original's spare capacity, so the append does not reallocate).
//! - `append_one_contact_in_place/n=N`: the same append on a map built directly, whose
//!   storage already has room for the new rows (no reallocation). The map is built with
//!   `max_rows = n + 3 R`, so that its capacity is exactly that, and receives R contacts
//!   (about 2 % of n) before it is rebuilt (untimed); every timed append therefore starts
//!   from n..n + 3 (R - 1) rows.
//! - `full_recompute/n=N`: `recompute_from_scratch()` on the n-row map.

use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::{criterion_group, criterion_main, BatchSize, Criterion, SamplingMode};
use env_core::gpis::{AddReport, Gpis, GpisConfig};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

const SIZES: [usize; 5] = [100, 250, 500, 1000, 2000];
const BOUNDS: [[f64; 2]; 2] = [[-0.3, 0.3], [0.0, 0.3]];
const SHAPE: (usize, usize) = (64, 64);
const SEED: u64 = 0x6770_6973;
const VALUE_NOISE_STD: f64 = 0.002;
const CONTACT_NOISE_STD: f64 = 0.0005;
const NORMAL_NOISE_STD: f64 = 0.05;
/// The contact appended in the timed region (inside the bounds, unit normal).
const CONTACT_POINT: [f64; 2] = [0.031, 0.137];
const CONTACT_NORMAL: [f64; 2] = [0.6, -0.8];

fn config(max_rows: usize) -> GpisConfig {
    GpisConfig {
        bounds: BOUNDS,
        shape: SHAPE,
        psi: None,
        prior_mean: 0.0,
        max_rows,
    }
}

fn random_point(rng: &mut ChaCha8Rng) -> [f64; 2] {
    [
        rng.random_range(BOUNDS[0][0]..BOUNDS[0][1]),
        rng.random_range(BOUNDS[1][0]..BOUNDS[1][1]),
    ]
}

fn random_normal(rng: &mut ChaCha8Rng) -> [f64; 2] {
    let angle = rng.random_range(0.0..std::f64::consts::TAU);
    [angle.cos(), angle.sin()]
}

/// A map holding exactly `n` rows (same rows for the same `n`, whatever `max_rows`).
fn build_map(n: usize, max_rows: usize) -> Gpis {
    let mut rng = ChaCha8Rng::seed_from_u64(SEED ^ n as u64);
    let mut map = Gpis::new(config(max_rows)).expect("valid config");
    let n_contacts = n / 30;
    let values: Vec<[f64; 2]> = (0..n - 3 * n_contacts)
        .map(|_| random_point(&mut rng))
        .collect();
    map.add_values(&values, None, VALUE_NOISE_STD)
        .expect("values fit");
    let points: Vec<[f64; 2]> = (0..n_contacts).map(|_| random_point(&mut rng)).collect();
    let normals: Vec<[f64; 2]> = (0..n_contacts).map(|_| random_normal(&mut rng)).collect();
    map.add_contacts(&points, &normals, CONTACT_NOISE_STD, NORMAL_NOISE_STD, None)
        .expect("contacts fit");
    // Any rejected (degenerate) row is replaced by a fresh value point.
    while map.n_rows() < n {
        let fill: Vec<[f64; 2]> = (map.n_rows()..n).map(|_| random_point(&mut rng)).collect();
        map.add_values(&fill, None, VALUE_NOISE_STD)
            .expect("fill fits");
    }
    assert_eq!(map.n_rows(), n, "the map must hold exactly n rows");
    map
}

fn append_contact(map: &mut Gpis) -> AddReport {
    map.add_contacts(
        &[CONTACT_POINT],
        &[CONTACT_NORMAL],
        CONTACT_NOISE_STD,
        NORMAL_NOISE_STD,
        None,
    )
    .expect("contact fits")
}

/// Contacts appended to one in-place map before it is rebuilt: about 2 % of n in rows.
fn contacts_per_build(n: usize) -> usize {
    (n / 150).max(1)
}

fn bench_append_clone(c: &mut Criterion) {
    let mut group = c.benchmark_group("append_one_contact");
    group
        .sample_size(50)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2));
    for n in SIZES {
        let base = build_map(n, 4096);
        group.bench_function(format!("n={n}"), |b| {
            b.iter_batched(
                || base.clone(),
                |mut map| {
                    let report = append_contact(&mut map);
                    (map, report)
                },
                BatchSize::LargeInput,
            );
        });
        let mut check = base.clone();
        assert_eq!(append_contact(&mut check).added_rows, 3);
    }
    group.finish();
}

fn bench_append_in_place(c: &mut Criterion) {
    let mut group = c.benchmark_group("append_one_contact_in_place");
    group
        .sampling_mode(SamplingMode::Flat)
        .sample_size(10)
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_secs(1));
    for n in SIZES {
        let per_build = contacts_per_build(n);
        let max_rows = n + 3 * per_build;
        let mut map = build_map(n, max_rows);
        group.bench_function(format!("n={n}"), |b| {
            b.iter_custom(|iters| {
                let mut total = Duration::ZERO;
                for _ in 0..iters {
                    if map.free_rows() < 3 {
                        map = build_map(n, max_rows);
                    }
                    let start = Instant::now();
                    let report = append_contact(&mut map);
                    total += start.elapsed();
                    assert_eq!(report.added_rows, 3);
                    black_box(&map);
                }
                total
            });
        });
    }
    group.finish();
}

fn bench_full_recompute(c: &mut Criterion) {
    let mut group = c.benchmark_group("full_recompute");
    group
        .sampling_mode(SamplingMode::Flat)
        .sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(3));
    for n in SIZES {
        let map = build_map(n, 4096);
        group.bench_function(format!("n={n}"), |b| {
            b.iter(|| black_box(map.recompute_from_scratch()));
        });
    }
    group.finish();
}

criterion_group!(
    benches,
    bench_append_clone,
    bench_append_in_place,
    bench_full_recompute
);
criterion_main!(benches);
