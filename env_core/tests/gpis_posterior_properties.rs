//! Properties of the posterior a map user relies on: interpolation of noise-free data,
//! variance that only shrinks, no NaN ever, and clear behaviour at the edges (duplicates,
//! uninformative contacts, a full map, bad input).

mod gpis_fixtures;

use env_core::gpis::{GpisError, Observation};
use rand::Rng;

#[test]
fn noise_free_values_and_normals_are_interpolated() {
    let mut map = gpis_fixtures::shelf_map((16, 16), 0.05, 100);
    let points = [[-0.1, 0.1], [0.05, 0.2], [0.2, 0.05]];
    let values = [0.0, -0.01, 0.03];
    map.add_values(&points, Some(&values), 0.0).unwrap();
    let contact = [0.0, 0.05];
    let normal = [0.6, -0.8];
    map.add_contacts(&[contact], &[normal], 0.0, 0.0, None)
        .unwrap();

    let prediction = map.predict(&points).unwrap();
    for (i, &v) in values.iter().enumerate() {
        assert!(
            (prediction.mean[i] - v).abs() < 1e-8,
            "value {i}: {}",
            prediction.mean[i]
        );
        assert!(
            prediction.variance[i] < 1e-8,
            "variance {i}: {}",
            prediction.variance[i]
        );
    }
    let at_contact = map.predict(&[contact]).unwrap();
    assert!(at_contact.mean[0].abs() < 1e-8);
    for axis in 0..2 {
        let g = at_contact.gradient[0][axis];
        assert!((g - normal[axis]).abs() < 1e-6, "gradient {axis}: {g}");
    }
}

#[test]
fn mean_gradient_matches_finite_differences_of_the_mean() {
    let mut rng = gpis_fixtures::rng(5);
    let mut map = gpis_fixtures::shelf_map((8, 8), 0.02, 500);
    let observations: Vec<_> = (0..40)
        .map(|i| gpis_fixtures::random_observation(&mut rng, i))
        .collect();
    map.add(&observations, None).unwrap();
    let h = 1e-6;
    for _ in 0..10 {
        let p = [rng.random_range(-0.25..0.25), rng.random_range(0.05..0.25)];
        let analytic = map.predict(&[p]).unwrap().gradient[0];
        for axis in 0..2 {
            let (mut plus, mut minus) = (p, p);
            plus[axis] += h;
            minus[axis] -= h;
            let means = map.predict(&[plus, minus]).unwrap().mean;
            let numeric = (means[0] - means[1]) / (2.0 * h);
            assert!(
                (analytic[axis] - numeric).abs() < 1e-4 * (1.0 + numeric.abs()),
                "axis {axis} at {p:?}: {} vs {numeric}",
                analytic[axis]
            );
        }
    }
}

#[test]
fn variance_never_increases_as_rows_are_added() {
    let mut rng = gpis_fixtures::rng(1);
    let mut map = gpis_fixtures::shelf_map((20, 20), 0.0, 3000);
    let mut previous = map.variance_grid().to_vec();
    for i in 0..300 {
        map.add(&[gpis_fixtures::random_observation(&mut rng, i)], None)
            .unwrap();
        for (cell, (&now, &before)) in map.variance_grid().iter().zip(&previous).enumerate() {
            assert!(
                now <= before + 1e-12,
                "step {i}, cell {cell}: {before} -> {now}"
            );
        }
        previous = map.variance_grid().to_vec();
    }
}

#[test]
fn duplicated_noise_free_points_are_rejected_not_nan() {
    let mut map = gpis_fixtures::shelf_map((16, 16), 0.0, 100);
    let p = [0.1, 0.1];
    let first = map.add_values(&[p], None, 0.0).unwrap();
    assert_eq!(first.added_rows, 1);
    let again = map.add_values(&[p, p], None, 0.0).unwrap();
    assert_eq!(again.added_rows, 0);
    assert_eq!(again.rejected_degenerate, 2);
    let contact = map
        .add_contacts(&[p], &[[1.0, 0.0]], 0.0, 0.0, None)
        .unwrap();
    assert_eq!(
        contact.rejected_degenerate, 1,
        "its value row duplicates the point"
    );
    assert_eq!(map.n_rows(), 1);
    assert!(map
        .mean_grid()
        .iter()
        .chain(map.variance_grid())
        .all(|v| v.is_finite()));
}

#[test]
fn no_nan_over_adversarial_random_sequences() {
    let mut rng = gpis_fixtures::rng(2);
    let mut map = gpis_fixtures::shelf_map((16, 16), 0.01, 4000);
    let mut index = 0;
    for _ in 0..200 {
        index += 1;
        let p = gpis_fixtures::random_point(&mut rng);
        // Clusters of nearly coincident points, zero noise, mixed with ordinary data.
        let jitter = [p[0] + 1e-9, p[1]];
        let batch = [
            Observation::value(index, p, 0.0, 0.0).unwrap(),
            Observation::value(index, jitter, 0.0, 0.0).unwrap(),
            Observation::contact(index, p, gpis_fixtures::random_normal(&mut rng), 0.0, 0.0)
                .unwrap(),
            gpis_fixtures::random_observation(&mut rng, index),
        ];
        map.add(&batch, None).unwrap();
        let grids = map.mean_grid().iter().chain(map.variance_grid());
        assert!(grids.into_iter().all(|v| v.is_finite()));
    }
    let prediction = map.predict(&map.grid().cell_centres()).unwrap();
    assert!(prediction
        .mean
        .iter()
        .chain(&prediction.variance)
        .all(|v| v.is_finite()));
}

#[test]
fn uninformative_contacts_are_skipped_and_counted() {
    let mut map = gpis_fixtures::shelf_map((16, 16), 0.0, 100);
    let point = [0.0, 0.1];
    let normal = [0.0, -1.0];
    let report = map
        .add_contacts(&[point, point], &[normal, normal], 0.0005, 0.05, Some(1e-5))
        .unwrap();
    assert_eq!(report.added_rows, 3);
    assert_eq!(report.skipped_uninformative, 1);
    let far = map
        .add_contacts(&[[0.25, 0.25]], &[normal], 0.0005, 0.05, Some(1e-5))
        .unwrap();
    assert_eq!(far.added_rows, 3, "a contact far from data is informative");
}

#[test]
fn a_call_that_could_exceed_capacity_adds_nothing() {
    let mut map = gpis_fixtures::shelf_map((8, 8), 0.0, 5);
    map.add_values(&[[0.0, 0.1], [0.1, 0.1]], None, 0.002)
        .unwrap();
    let before = map.mean_grid().to_vec();
    let error = map
        .add_contacts(
            &[[0.2, 0.2], [-0.2, 0.2]],
            &[[1.0, 0.0], [0.0, 1.0]],
            0.0,
            0.0,
            None,
        )
        .unwrap_err();
    assert_eq!(
        error,
        GpisError::CapacityExceeded {
            capacity: 5,
            current: 2,
            requested: 6
        }
    );
    assert_eq!(map.n_rows(), 2);
    assert_eq!(map.mean_grid(), &before[..]);
    assert_eq!(
        map.add_contacts(&[[0.2, 0.2]], &[[1.0, 0.0]], 0.0, 0.0, None)
            .unwrap()
            .added_rows,
        3
    );
    assert_eq!(map.free_rows(), 0);
}

#[test]
fn bad_observations_are_refused_with_what_came() {
    let mut map = gpis_fixtures::shelf_map((8, 8), 0.0, 100);
    assert!(matches!(
        map.add_values(&[[0.0, 0.5]], None, 0.0),
        Err(GpisError::PointOutsideBounds { index: 0, y, .. }) if y == 0.5
    ));
    assert!(matches!(
        map.add_values(&[[0.0, 0.1], [f64::NAN, 0.1]], None, 0.0),
        Err(GpisError::NonFiniteInput {
            what: "points",
            index: 1,
            ..
        })
    ));
    assert!(matches!(
        map.add_values(&[[0.0, 0.1]], None, -1.0),
        Err(GpisError::NegativeParameter {
            what: "noise_std",
            ..
        })
    ));
    assert!(matches!(
        map.add_contacts(&[[0.0, 0.1]], &[[0.0, 0.0]], 0.0, 0.0, None),
        Err(GpisError::ZeroNormal { index: 0, .. })
    ));
    assert!(matches!(
        map.add_values(&[[0.0, 0.1]], Some(&[0.0, 1.0]), 0.0),
        Err(GpisError::LengthMismatch {
            what: "values",
            expected: 1,
            got: 2
        })
    ));
    assert_eq!(map.n_rows(), 0, "nothing was added by a refused call");
}

#[test]
fn clear_returns_the_map_to_its_prior() {
    let mut rng = gpis_fixtures::rng(4);
    let mut map = gpis_fixtures::shelf_map((8, 8), 0.03, 500);
    let fresh = map.clone();
    let observations: Vec<_> = (0..50)
        .map(|i| gpis_fixtures::random_observation(&mut rng, i))
        .collect();
    map.add(&observations, None).unwrap();
    map.clear();
    assert_eq!(map.n_rows(), 0);
    assert_eq!(map.mean_grid(), fresh.mean_grid());
    assert_eq!(map.variance_grid(), fresh.variance_grid());
    map.add(&observations, None).unwrap();
    let full = map.recompute_from_scratch();
    assert!(gpis_fixtures::max_abs_difference(map.mean_grid(), &full.mean) <= 1e-9);
}

#[test]
fn circle_prior_makes_its_centre_inside_and_its_rim_a_surface() {
    let mut map = gpis_fixtures::shelf_map((16, 16), 0.02, 100);
    let centre = [0.05, 0.15];
    let report = map.add_circle_prior(centre, 0.03, 0.0, 0.0).unwrap();
    assert_eq!(report.added_rows, 12);
    let rim = [centre[0], centre[1] + 0.015];
    let far = [0.25, 0.02];
    let prediction = map.predict(&[centre, rim, far]).unwrap();
    assert!(
        prediction.mean[0] < 0.0,
        "centre reads inside: {}",
        prediction.mean[0]
    );
    assert!(
        prediction.mean[1].abs() < 1e-8,
        "rim is a surface: {}",
        prediction.mean[1]
    );
    assert!(
        prediction.mean[2] > 0.0,
        "far away reads free: {}",
        prediction.mean[2]
    );
    assert!(
        prediction.gradient[1][1] > 0.99,
        "normal at the top of the rim points up"
    );
    assert!(matches!(
        map.add_circle_prior(centre, 0.0, 0.0, 0.0),
        Err(GpisError::NegativeParameter {
            what: "diameter",
            ..
        })
    ));
}
