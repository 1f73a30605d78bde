//! The zero level set of a field sampled at a grid's cell centres, as line segments
//! (marching squares with linear interpolation along the edges between cell centres). It is
//! the map's estimated outline: the boundary of the interior `mean < 0` that the IoU counts.

use crate::gpis::GridSpec;

/// A straight piece of the zero level set, from one cell edge crossing to another.
pub type Segment = [[f64; 2]; 2];

/// Where the field crosses 0 on the edge from `a` (value `va`) to `b` (value `vb`); the two
/// values lie on opposite sides (one `< 0`, the other `>= 0`), so the division is safe.
fn crossing(a: [f64; 2], va: f64, b: [f64; 2], vb: f64) -> [f64; 2] {
    let t = va / (va - vb);
    [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]
}

/// The zero level set of `field` (H·W values in row-major cell order on `grid`). A cell
/// centre is inside when its value is `< 0` (as for the IoU), so a field that is 0
/// everywhere has no level set. Saddle squares are split by the mean of their corners.
/// Segments are returned in square order (row by row). Cost O(G); `field` must hold G values.
pub fn zero_level_segments(grid: &GridSpec, field: &[f64]) -> Vec<Segment> {
    let (h, w) = grid.shape();
    debug_assert_eq!(field.len(), h * w);
    let mut segments = Vec::new();
    for i in 0..h.saturating_sub(1) {
        for j in 0..w.saturating_sub(1) {
            // Corners counter-clockwise from the lower left; edges k join corner k to k + 1.
            let cells = [(i, j), (i, j + 1), (i + 1, j + 1), (i + 1, j)];
            let p = cells.map(|(a, b)| grid.cell_centre(a, b));
            let v = cells.map(|(a, b)| field[a * w + b]);
            let inside = v.map(|x| x < 0.0);
            let edge = |k: usize| {
                let n = (k + 1) % 4;
                crossing(p[k], v[k], p[n], v[n])
            };
            let cut: Vec<usize> = (0..4)
                .filter(|&k| inside[k] != inside[(k + 1) % 4])
                .collect();
            match cut.len() {
                2 => segments.push([edge(cut[0]), edge(cut[1])]),
                4 => {
                    // A saddle: corners 0 and 2 agree, 1 and 3 agree. If the square's centre
                    // sides with corner 0, corners 1 and 3 are cut off; else 0 and 2 are.
                    let centre_inside = v.iter().sum::<f64>() / 4.0 < 0.0;
                    if centre_inside == inside[0] {
                        segments.push([edge(0), edge(1)]);
                        segments.push([edge(2), edge(3)]);
                    } else {
                        segments.push([edge(3), edge(0)]);
                        segments.push([edge(1), edge(2)]);
                    }
                }
                _ => {}
            }
        }
    }
    segments
}

/// Distance from `p` to the nearest segment; infinite when there is none. Cost O(segments).
pub fn distance_to_segments(p: [f64; 2], segments: &[Segment]) -> f64 {
    segments
        .iter()
        .map(|[a, b]| {
            let ab = [b[0] - a[0], b[1] - a[1]];
            let ap = [p[0] - a[0], p[1] - a[1]];
            let length2 = (ab[0] * ab[0] + ab[1] * ab[1]).max(1e-30);
            let t = ((ap[0] * ab[0] + ap[1] * ab[1]) / length2).clamp(0.0, 1.0);
            (ap[0] - t * ab[0]).hypot(ap[1] - t * ab[1])
        })
        .fold(f64::INFINITY, f64::min)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn level_set_of_a_disc_field_lies_on_the_circle() {
        let grid = GridSpec::new([[-0.1, 0.1], [0.0, 0.2]], (50, 50)).unwrap();
        let field: Vec<f64> = grid
            .cell_centres()
            .iter()
            .map(|p| p[0].hypot(p[1] - 0.1) - 0.05)
            .collect();
        let segments = zero_level_segments(&grid, &field);
        assert!(segments.len() > 40);
        for s in &segments {
            for p in s {
                assert!((p[0].hypot(p[1] - 0.1) - 0.05).abs() < 5e-4, "{p:?}");
            }
        }
    }

    #[test]
    fn a_field_without_negative_values_has_no_level_set() {
        let grid = GridSpec::new([[0.0, 1.0], [0.0, 1.0]], (4, 4)).unwrap();
        assert!(zero_level_segments(&grid, &[0.0; 16]).is_empty());
        assert!(distance_to_segments([0.5, 0.5], &[]).is_infinite());
    }
}
