//! How far a map's estimated outline (the zero level set of its mean) lies from the true
//! jar outlines, in both directions (the paper's table). Truth to estimate misses parts of
//! the outline the map did not find; estimate to truth sees spurious surfaces in free space.

use super::level_set::{distance_to_segments, zero_level_segments};
use crate::gpis::GridSpec;
use crate::scene::Footprint;

/// Mean over `samples` points on each footprint's outline of the distance to the zero
/// level set of `mean` (H·W values on `grid`), each point's distance capped at `cap`; `cap`
/// when the map has no zero level set (or there are no footprints). Cost O(G + J·samples·S)
/// for J footprints and S level-set segments.
pub fn outline_distance(
    grid: &GridSpec,
    mean: &[f64],
    footprints: &[Footprint],
    samples: usize,
    cap: f64,
) -> f64 {
    let segments = zero_level_segments(grid, mean);
    let outline: Vec<[f64; 2]> = footprints.iter().flat_map(|f| f.outline(samples)).collect();
    if segments.is_empty() || outline.is_empty() {
        return cap;
    }
    let total: f64 = outline
        .iter()
        .map(|&p| distance_to_segments(p, &segments).min(cap))
        .sum();
    total / outline.len() as f64
}

/// The reverse of [`outline_distance`]: mean over the zero level set's segment midpoints of
/// the distance to the nearest true outline, each capped at `cap`; `cap` when there is no
/// zero level set (or no footprint). Cost O(G + S·J).
pub fn spurious_distance(grid: &GridSpec, mean: &[f64], footprints: &[Footprint], cap: f64) -> f64 {
    let segments = zero_level_segments(grid, mean);
    if segments.is_empty() || footprints.is_empty() {
        return cap;
    }
    let total: f64 = segments
        .iter()
        .map(|[a, b]| {
            let mid = [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])];
            footprints
                .iter()
                .map(|f| f.signed_distance(mid).abs())
                .fold(f64::INFINITY, f64::min)
                .min(cap)
        })
        .sum();
    total / segments.len() as f64
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::JarShape;

    fn disc_field(grid: &GridSpec, centre: [f64; 2], radius: f64) -> Vec<f64> {
        let cells = grid.cell_centres();
        cells
            .iter()
            .map(|p| (p[0] - centre[0]).hypot(p[1] - centre[1]) - radius)
            .collect()
    }

    #[test]
    fn a_concentric_larger_circle_is_off_by_the_difference_of_radii() {
        let grid = GridSpec::new([[-0.3, 0.3], [0.0, 0.3]], (150, 300)).unwrap();
        let jar = Footprint {
            shape: JarShape::Round { radius: 0.025 },
            centre: [0.05, 0.12],
            yaw: 0.0,
        };
        let exact = disc_field(&grid, jar.centre, 0.025);
        assert!(outline_distance(&grid, &exact, &[jar], 64, 0.05) < 3e-4);
        assert!(spurious_distance(&grid, &exact, &[jar], 0.05) < 3e-4);
        let bigger = disc_field(&grid, jar.centre, 0.031);
        assert!((outline_distance(&grid, &bigger, &[jar], 64, 0.05) - 0.006).abs() < 3e-4);
        assert!((spurious_distance(&grid, &bigger, &[jar], 0.05) - 0.006).abs() < 3e-4);
        let flat = vec![1.0; grid.n_cells()];
        assert_eq!(outline_distance(&grid, &flat, &[jar], 64, 0.05), 0.05);
        assert_eq!(spurious_distance(&grid, &flat, &[jar], 0.05), 0.05);
    }
}
