//! The thin-plate kernel's derivative blocks are the derivatives of its value block.

use env_core::gpis::{RowKind, ThinPlateKernel};

const KINDS: [RowKind; 3] = [RowKind::Value, RowKind::GradX, RowKind::GradY];

fn shifted(p: [f64; 2], kind: RowKind, step: f64) -> [f64; 2] {
    let mut q = p;
    if let Some(axis) = kind.axis() {
        q[axis] += step;
    }
    q
}

/// cov(row a, row b) by central finite differences of k(x, x′) in the derivative slots.
fn finite_difference(
    kernel: &ThinPlateKernel,
    a: [f64; 2],
    ka: RowKind,
    b: [f64; 2],
    kb: RowKind,
) -> f64 {
    let h = 1e-5;
    let k = |x: [f64; 2], y: [f64; 2]| kernel.covariance(x, RowKind::Value, y, RowKind::Value);
    let steps = |kind: RowKind| -> Vec<(f64, f64)> {
        if kind.axis().is_some() {
            vec![(h, 1.0 / (2.0 * h)), (-h, -1.0 / (2.0 * h))]
        } else {
            vec![(0.0, 1.0)]
        }
    };
    let mut total = 0.0;
    for (sa, wa) in steps(ka) {
        for (sb, wb) in steps(kb) {
            total += wa * wb * k(shifted(a, ka, sa), shifted(b, kb, sb));
        }
    }
    total
}

#[test]
fn derivative_blocks_match_finite_differences_of_the_kernel() {
    let kernel = ThinPlateKernel::new(1.0);
    let pairs = [
        ([0.1, 0.2], [-0.15, 0.05]),
        ([0.0, 0.0], [0.3, 0.0]),
        ([0.25, -0.1], [0.2, 0.12]),
        ([0.01, 0.02], [0.015, 0.018]),
    ];
    for (a, b) in pairs {
        for ka in KINDS {
            for kb in KINDS {
                let exact = kernel.covariance(a, ka, b, kb);
                let numeric = finite_difference(&kernel, a, ka, b, kb);
                let tolerance = 1e-5 * (1.0 + exact.abs());
                assert!(
                    (exact - numeric).abs() < tolerance,
                    "{ka:?}/{kb:?} at {a:?},{b:?}: exact {exact}, finite difference {numeric}"
                );
            }
        }
    }
}

#[test]
fn gradient_block_tends_to_six_psi_identity_at_zero_distance() {
    let psi = 0.7;
    let kernel = ThinPlateKernel::new(psi);
    let p = [0.1, -0.2];
    assert_eq!(
        kernel.covariance(p, RowKind::GradX, p, RowKind::GradX),
        6.0 * psi
    );
    assert_eq!(
        kernel.covariance(p, RowKind::GradY, p, RowKind::GradY),
        6.0 * psi
    );
    assert_eq!(kernel.covariance(p, RowKind::GradX, p, RowKind::GradY), 0.0);
    let near = [p[0] + 1e-9, p[1] - 1e-9];
    let limit = kernel.covariance(p, RowKind::GradX, near, RowKind::GradY);
    assert!(limit.abs() < 1e-7, "off-diagonal near r = 0: {limit}");
    assert!((kernel.covariance(p, RowKind::GradX, near, RowKind::GradX) - 6.0 * psi).abs() < 1e-7);
}

#[test]
fn covariance_is_symmetric_under_swapping_rows() {
    let kernel = ThinPlateKernel::new(1.2);
    let (a, b) = ([0.05, 0.2], [-0.1, 0.07]);
    for ka in KINDS {
        for kb in KINDS {
            let ab = kernel.covariance(a, ka, b, kb);
            let ba = kernel.covariance(b, kb, a, ka);
            assert!((ab - ba).abs() < 1e-15, "{ka:?}/{kb:?}: {ab} vs {ba}");
        }
    }
}
