//! Cholesky factorisation of a Schur complement that rejects whole observations.
//!
//! faer's LLᵀ stops at the first non-positive pivot; the GPIS instead needs to drop the
//! observation that owns a bad pivot (a duplicated noise-free point, say) or one that is no
//! longer informative, and carry on with the rest. This up-looking factorisation processes
//! the rows group by group (one group per observation), so each pivot is exactly the
//! variance of that row given all rows accepted before it. Cost: O(k³/3) for k rows; the
//! GPIS feeds it chunks of at most a few dozen rows, so it is never the bottleneck.

use faer::{Mat, MatRef};
use std::ops::Range;

/// A pivot at or below this fraction of its row's prior variance means the row is (nearly)
/// a linear combination of rows already in the map: accepting it would wreck conditioning.
/// For a value row with ψ ≈ 1 m this rejects a noise-free point whose remaining standard
/// deviation is below ~0.1 mm (one within ~40 µm of another noise-free point). Noisy rows
/// never come near it: their pivot includes their noise variance.
pub(crate) const DEGENERATE_RELATIVE_TOLERANCE: f64 = 1e-8;

/// The rows of one observation and the test that may skip it.
pub(crate) struct RowGroup {
    /// Its rows in the Schur complement; the first is the value row.
    pub rows: Range<usize>,
    /// Skip the observation when the posterior variance of f at its point is below this.
    pub skip_below_variance: Option<f64>,
    /// Noise variance of its value row (subtracted from the pivot for the skip test).
    pub value_noise_var: f64,
}

/// What became of one observation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum GroupOutcome {
    Accepted,
    Uninformative,
    Degenerate,
}

/// The factor of the accepted rows' Schur complement.
pub(crate) struct RejectingFactor {
    /// Indices (into the Schur complement) of the accepted rows, in order.
    pub accepted: Vec<usize>,
    /// Lower-triangular factor of the accepted rows, `accepted.len()` square.
    pub factor: Mat<f64>,
    /// One outcome per group.
    pub outcomes: Vec<GroupOutcome>,
}

/// Factors `schur` (symmetric, k × k) group by group. `prior_scale[i]` is row i's prior
/// variance (kernel diagonal plus noise), against which degeneracy is judged.
pub(crate) fn factor_rejecting(
    schur: MatRef<'_, f64>,
    prior_scale: &[f64],
    groups: &[RowGroup],
) -> RejectingFactor {
    let k = schur.nrows();
    let mut factor = Mat::<f64>::zeros(k, k);
    let mut accepted: Vec<usize> = Vec::with_capacity(k);
    let mut outcomes = Vec::with_capacity(groups.len());
    for group in groups {
        let first_position = accepted.len();
        let mut outcome = GroupOutcome::Accepted;
        for (offset, row) in group.rows.clone().enumerate() {
            let p = first_position + offset;
            for q in 0..p {
                let mut entry = schur[(row, accepted[q])];
                for l in 0..q {
                    entry -= factor[(p, l)] * factor[(q, l)];
                }
                factor[(p, q)] = entry / factor[(q, q)];
            }
            let mut pivot = schur[(row, row)];
            for l in 0..p {
                pivot -= factor[(p, l)] * factor[(p, l)];
            }
            if offset == 0 {
                if let Some(threshold) = group.skip_below_variance {
                    if pivot - group.value_noise_var < threshold {
                        outcome = GroupOutcome::Uninformative;
                        break;
                    }
                }
            }
            let floor = DEGENERATE_RELATIVE_TOLERANCE * prior_scale[row];
            if pivot.is_nan() || pivot <= floor {
                outcome = GroupOutcome::Degenerate;
                break;
            }
            factor[(p, p)] = pivot.sqrt();
            accepted.push(row);
        }
        if outcome != GroupOutcome::Accepted {
            accepted.truncate(first_position);
        }
        outcomes.push(outcome);
    }
    let kept = accepted.len();
    let factor = Mat::from_fn(kept, kept, |i, j| if j <= i { factor[(i, j)] } else { 0.0 });
    RejectingFactor {
        accepted,
        factor,
        outcomes,
    }
}
