//! Property tests of the GPIS map's public entry points (proptest): whatever points, values,
//! normals, noise levels and capacities come (on the bounds and just outside, duplicates,
//! NaN and infinities, huge and tiny noise, one row short of the capacity and one over),
//! each call either works or returns a `GpisError`, never panics, and the map stays finite
//! with a non-negative variance. `PROPTEST_CASES` sets the number of cases (the long run).

use env_core::gpis::{Gpis, GpisConfig, GpisError};
use proptest::prelude::*;

const BOUNDS: [[f64; 2]; 2] = [[-0.3, 0.3], [0.0, 0.3]];

/// A coordinate along one axis: inside, exactly on an end, one ulp outside, far outside,
/// or not finite.
fn coordinate(low: f64, high: f64) -> impl Strategy<Value = f64> {
    prop_oneof![
        4 => low..=high,
        1 => Just(low),
        1 => Just(high),
        1 => Just(low.next_down()),
        1 => Just(high.next_up()),
        1 => prop_oneof![
            Just(f64::NAN),
            Just(f64::INFINITY),
            Just(f64::NEG_INFINITY),
            Just(1e300),
            Just(-1e300),
        ],
    ]
}

fn point() -> impl Strategy<Value = [f64; 2]> {
    (
        coordinate(BOUNDS[0][0], BOUNDS[0][1]),
        coordinate(BOUNDS[1][0], BOUNDS[1][1]),
    )
        .prop_map(|(x, y)| [x, y])
}

/// Points, with some exact duplicates of earlier ones.
fn points(max: usize) -> impl Strategy<Value = Vec<[f64; 2]>> {
    (
        prop::collection::vec(point(), 0..max),
        prop::collection::vec(any::<prop::sample::Index>(), 0..3),
    )
        .prop_map(|(mut points, repeats)| {
            if !points.is_empty() {
                for index in repeats {
                    points.push(points[index.index(points.len())]);
                }
            }
            points
        })
}

/// A noise standard deviation: zero, tiny, ordinary, huge, negative or not finite.
fn noise() -> impl Strategy<Value = f64> {
    prop_oneof![
        3 => 1e-4..0.05f64,
        1 => Just(0.0),
        1 => Just(f64::MIN_POSITIVE),
        1 => Just(1e-300),
        1 => Just(1e150),
        1 => Just(-1e-3),
        1 => Just(f64::NAN),
        1 => Just(f64::INFINITY),
    ]
}

fn value() -> impl Strategy<Value = f64> {
    prop_oneof![
        4 => -0.5..0.5f64,
        1 => Just(1e300),
        1 => Just(f64::NAN),
        1 => Just(f64::NEG_INFINITY),
    ]
}

fn normal() -> impl Strategy<Value = [f64; 2]> {
    prop_oneof![
        4 => (-1.0..1.0f64, -1.0..1.0f64).prop_map(|(x, y)| [x, y]),
        1 => Just([0.0, 0.0]),
        1 => Just([1e-320, 0.0]),
        1 => Just([1e300, 1e300]),
        1 => Just([f64::NAN, 1.0]),
    ]
}

/// One call on the map.
#[derive(Debug, Clone)]
enum Call {
    Values(Vec<[f64; 2]>, Option<Vec<f64>>, f64),
    Contacts(Vec<[f64; 2]>, Vec<[f64; 2]>, f64, f64, Option<f64>),
    Circle([f64; 2], f64, f64, f64),
    Predict(Vec<[f64; 2]>),
    Clear,
}

fn call() -> impl Strategy<Value = Call> {
    prop_oneof![
        4 => (points(12), prop::option::of(prop::collection::vec(value(), 0..14)), noise())
            .prop_map(|(p, v, n)| Call::Values(p, v, n)),
        4 => (points(6), prop::collection::vec(normal(), 0..8), noise(), noise(),
              prop::option::of(prop_oneof![Just(0.0), Just(1e-5), Just(-1.0), Just(f64::NAN)]))
            .prop_map(|(p, n, a, b, s)| Call::Contacts(p, n, a, b, s)),
        1 => (point(), prop_oneof![0.01..0.2f64, Just(0.0), Just(-0.1), Just(1e300)], noise(), noise())
            .prop_map(|(c, d, a, b)| Call::Circle(c, d, a, b)),
        2 => points(6).prop_map(Call::Predict),
        1 => Just(Call::Clear),
    ]
}

fn assert_map_finite(map: &Gpis) {
    assert!(
        map.mean_grid().iter().all(|m| m.is_finite()),
        "mean not finite"
    );
    assert!(
        map.variance_grid()
            .iter()
            .all(|v| v.is_finite() && *v >= -1e-9),
        "variance not finite or negative"
    );
    assert!(map.n_rows() <= map.max_rows());
}

/// Cases per property: `PROPTEST_CASES` if set (the long run), else `default`.
fn cases(default: u32) -> u32 {
    std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(cases(64)))]

    #[test]
    fn any_sequence_of_calls_works_or_errs_and_leaves_the_map_finite(
        max_rows in prop_oneof![1usize..8, 8usize..64, Just(200usize)],
        calls in prop::collection::vec(call(), 1..12),
    ) {
        let mut map = Gpis::new(GpisConfig {
            bounds: BOUNDS,
            shape: (12, 24),
            psi: None,
            prior_mean: 0.01,
            max_rows,
        })
        .expect("a valid map");
        for call in calls {
            let rows_before = map.n_rows();
            let added = match call {
                Call::Values(p, v, n) => map.add_values(&p, v.as_deref(), n).map(|r| r.added_rows),
                Call::Contacts(p, n, a, b, s) => {
                    map.add_contacts(&p, &n, a, b, s).map(|r| r.added_rows)
                }
                Call::Circle(c, d, a, b) => map.add_circle_prior(c, d, a, b).map(|r| r.added_rows),
                Call::Predict(p) => {
                    if let Ok(prediction) = map.predict(&p) {
                        prop_assert!(prediction.mean.iter().all(|m| m.is_finite()));
                        prop_assert!(prediction.variance.iter().all(|v| v.is_finite()));
                    }
                    Ok(0)
                }
                Call::Clear => {
                    map.clear();
                    prop_assert_eq!(map.n_rows(), 0);
                    continue;
                }
            };
            match added {
                Ok(rows) => prop_assert_eq!(map.n_rows(), rows_before + rows),
                // A refused call adds nothing, and says why.
                Err(error) => {
                    prop_assert_eq!(map.n_rows(), rows_before);
                    prop_assert!(!error.to_string().is_empty());
                }
            }
            assert_map_finite(&map);
        }
    }

    #[test]
    fn a_map_fills_exactly_to_its_capacity_and_refuses_one_row_more(
        capacity in 1usize..40,
        seed in any::<u64>(),
    ) {
        let mut map = Gpis::new(GpisConfig {
            bounds: BOUNDS,
            shape: (10, 20),
            psi: None,
            prior_mean: 0.0,
            max_rows: capacity,
        })
        .expect("a valid map");
        // Distinct points on a lattice: every value row is informative and none degenerate.
        let lattice: Vec<[f64; 2]> = (0..capacity)
            .map(|i| {
                let k = (i as u64).wrapping_mul(seed | 1) as usize % (capacity * 7 + 1);
                [-0.29 + 0.58 * (k % 29) as f64 / 28.0, 0.01 + 0.28 * (k / 29 % 29) as f64 / 28.0]
            })
            .collect();
        let mut seen = std::collections::HashSet::new();
        let distinct: Vec<[f64; 2]> = lattice
            .into_iter()
            .filter(|p| seen.insert((p[0].to_bits(), p[1].to_bits())))
            .collect();
        map.add_values(&distinct, None, 1e-3).expect("fits");
        let free = map.free_rows();
        let more: Vec<[f64; 2]> = (0..=free).map(|i| [0.0, 0.01 + 0.2 * i as f64 / (free as f64 + 1.0)]).collect();
        if free > 0 {
            prop_assert!(map.add_values(&more[..free], None, 1e-3).is_ok());
        }
        prop_assert_eq!(map.n_rows(), capacity);
        let rows = map.n_rows();
        prop_assert!(map.add_values(&more[..1], None, 1e-3).is_err());
        prop_assert_eq!(map.n_rows(), rows);
        assert_map_finite(&map);
    }
}

/// Bounds with a diagonal near 1e102 would give a prior variance ψ³ of inf: a ψ above
/// 1e100 (given, or the default from the bounds) is refused.
#[test]
fn bounds_too_large_for_the_kernel_are_refused() {
    let config = |bounds, psi| GpisConfig {
        bounds,
        shape: (4, 4),
        psi,
        prior_mean: 0.0,
        max_rows: 8,
    };
    let huge = [[-1e200, 1e200], [-1e200, 1e200]];
    let error = Gpis::new(config(huge, None)).expect_err("refused");
    assert!(matches!(error, GpisError::PsiTooLarge { .. }), "{error}");
    assert!(Gpis::new(config([[0.0, 1.0], [0.0, 1.0]], Some(1e101))).is_err());
    let largest = Gpis::new(config([[0.0, 1.0], [0.0, 1.0]], Some(1e100))).expect("in range");
    assert!(largest.variance_grid().iter().all(|v| v.is_finite()));
}

/// A grid too large to allocate is an error that says how much it needs, not an abort of
/// the process: its storage is allocated fallibly.
#[test]
fn a_grid_too_large_to_allocate_is_an_error_not_an_abort() {
    let error = Gpis::new(GpisConfig {
        bounds: [[0.0, 1.0], [0.0, 1.0]],
        shape: (1 << 31, 1 << 31),
        psi: None,
        prior_mean: 0.0,
        max_rows: 8,
    })
    .expect_err("refused");
    assert!(
        matches!(error, GpisError::OutOfMemory { what: "grid", .. }),
        "{error}"
    );
    assert!(error.to_string().contains("GB"), "{error}");
    let uncountable = Gpis::new(GpisConfig {
        bounds: [[0.0, 1.0], [0.0, 1.0]],
        shape: (usize::MAX, 2),
        psi: None,
        prior_mean: 0.0,
        max_rows: 8,
    });
    assert!(matches!(uncountable, Err(GpisError::InvalidShape { .. })));
}
