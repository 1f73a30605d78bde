//! With ψ fixed at 1.5 × the domain's diagonal, the joint value + gradient covariance is
//! positive definite on random point sets; with ψ below the largest distance it is not.

mod gpis_fixtures;

use env_core::gpis::{Gpis, GpisConfig, GpisError, Observation, RowKind, ThinPlateKernel};
use faer::{Mat, Side};

/// The joint covariance (no noise) of the rows of `observations`.
fn joint_covariance(kernel: &ThinPlateKernel, observations: &[Observation]) -> Mat<f64> {
    let rows: Vec<_> = observations
        .iter()
        .flat_map(|o| o.rows().map(|(row, _, _)| row).collect::<Vec<_>>())
        .collect();
    Mat::from_fn(rows.len(), rows.len(), |i, j| {
        kernel.covariance(rows[i].point, rows[i].kind, rows[j].point, rows[j].kind)
    })
}

fn smallest_eigenvalue(matrix: &Mat<f64>) -> f64 {
    let eigenvalues = matrix
        .self_adjoint_eigenvalues(Side::Lower)
        .expect("eigenvalues");
    eigenvalues.into_iter().fold(f64::INFINITY, f64::min)
}

/// Random contacts and values at points at least 2 cm apart.
fn spread_observations(seed: u64, count: usize) -> Vec<Observation> {
    let mut rng = gpis_fixtures::rng(seed);
    let mut points: Vec<[f64; 2]> = Vec::new();
    while points.len() < count {
        let p = gpis_fixtures::random_point(&mut rng);
        if points
            .iter()
            .all(|q| (p[0] - q[0]).hypot(p[1] - q[1]) > 0.02)
        {
            points.push(p);
        }
    }
    points
        .iter()
        .enumerate()
        .map(|(i, &p)| {
            if i % 2 == 0 {
                Observation::contact(i, p, gpis_fixtures::random_normal(&mut rng), 0.0, 0.0)
                    .unwrap()
            } else {
                Observation::value(i, p, 0.0, 0.0).unwrap()
            }
        })
        .collect()
}

#[test]
fn joint_covariance_is_positive_definite_with_the_default_psi() {
    let map = gpis_fixtures::shelf_map((8, 8), 0.0, 16);
    let kernel = map.kernel();
    for seed in 0..20 {
        let observations = spread_observations(seed, 12);
        let covariance = joint_covariance(&kernel, &observations);
        let smallest = smallest_eigenvalue(&covariance);
        assert!(
            smallest > 0.0,
            "seed {seed}: smallest eigenvalue {smallest}"
        );
    }
}

#[test]
fn joint_covariance_can_be_indefinite_when_psi_is_below_the_largest_distance() {
    // The reason ψ is fixed and checked: beyond r = ψ the kernel is not a covariance.
    let kernel = ThinPlateKernel::new(0.1);
    let found_indefinite = (0..20).any(|seed| {
        let covariance = joint_covariance(&kernel, &spread_observations(seed, 12));
        smallest_eigenvalue(&covariance) < 0.0
    });
    assert!(found_indefinite);
}

#[test]
fn psi_below_the_diagonal_is_refused() {
    let result = Gpis::new(GpisConfig {
        bounds: gpis_fixtures::BOUNDS,
        shape: (8, 8),
        psi: Some(0.5),
        prior_mean: 0.0,
        max_rows: 10,
    });
    let diagonal = 0.6f64.hypot(0.3);
    assert_eq!(
        result.unwrap_err(),
        GpisError::PsiTooSmall { psi: 0.5, diagonal }
    );
}

#[test]
fn default_psi_is_one_and_a_half_diagonals() {
    let map = gpis_fixtures::shelf_map((8, 8), 0.0, 16);
    assert!((map.psi() - 1.5 * 0.6f64.hypot(0.3)).abs() < 1e-15);
    assert_eq!(
        map.kernel().prior_variance(RowKind::Value),
        map.psi().powi(3)
    );
}
