//! The fingertip's path distance to the target, for potential-based reward shaping.
//!
//! At reset, a Dijkstra search over the map grid (8-connected, cell centres) measures every
//! cell's shortest path to the target's footprint, where a step through another jar's
//! footprint (widened by `clearance`) costs `THROUGH_JAR_COST` times its length: the
//! distance follows the free corridor instead of pointing through the occluder, yet stays
//! finite everywhere, so a finger pressed into a jar still has a well-defined potential.
//! Points between cell centres are interpolated bilinearly; points outside the grid (the
//! fingertip before it enters the opening) add their straight distance to the nearest point
//! of the grid.
//!
//! The shaping term `w · (d_{t−1} − d_t)` is a difference of potentials `Φ = −w·d` (Ng,
//! Harada and Russell, 1999), without their two conditions for leaving the optimal
//! policies unchanged:
//! - the final potential is not zero: undiscounted, the terms of an episode sum to
//!   `w · (d_0 − d_T)`, so the shaped return is the task's return plus a bonus for how much
//!   nearer the finger ended, and a policy that ends nearer the target (a time-out beside
//!   it, rather than at the opening) is preferred over one with the same task return;
//! - it is not discounted with the learner's γ (`γ·Φ(s') − Φ(s)`): under discounting
//!   (γ = 0.99 in the recipes) approach made early is worth more than the same approach late.
//!
//! What holds: `d_0` is fixed by the layout, and a touch ends the episode with the fingertip
//! at the target (`d_T` ≈ 0), so among successful episodes the undiscounted bonus is the
//! same whatever the path; the shaping tells a learner early which way is closer.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use super::metrics::footprint_mask_within;
use crate::gpis::GridSpec;
use crate::scene::JarState;

/// Cost factor of a path through another jar's footprint.
const THROUGH_JAR_COST: f64 = 4.0;

/// Path distances to the target over the map grid.
#[derive(Debug, Clone, Default)]
pub struct ApproachField {
    shape: (usize, usize),
    bounds: [[f64; 2]; 2],
    /// Per cell (row-major, row along y), m.
    distance: Vec<f64>,
}

#[derive(PartialEq)]
struct Frontier {
    distance: f64,
    cell: usize,
}

impl Eq for Frontier {}

impl Ord for Frontier {
    fn cmp(&self, other: &Self) -> Ordering {
        // Reversed: BinaryHeap is a max-heap and Dijkstra pops the nearest cell first.
        other.distance.total_cmp(&self.distance)
    }
}

impl PartialOrd for Frontier {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl ApproachField {
    /// The field for `jars[target]` (cells within `clearance` of its footprint are the goal);
    /// other jars' footprints widened by `clearance` (m) are expensive to cross. Cost
    /// O(G log G).
    pub fn new(grid: &GridSpec, jars: &[JarState], target: usize, clearance: f64) -> Self {
        let (h, w) = grid.shape();
        let (mut goal, mut blocked) = (Vec::new(), Vec::new());
        let target_jar = jars.get(target..=target).unwrap_or(&[]);
        footprint_mask_within(grid, target_jar, clearance, &mut goal);
        let others: Vec<JarState> = (jars.iter().enumerate())
            .filter(|&(k, _)| k != target)
            .map(|(_, &jar)| jar)
            .collect();
        footprint_mask_within(grid, &others, clearance, &mut blocked);
        let step_factor: Vec<f64> = (goal.iter().zip(&blocked))
            .map(|(&g, &b)| if b && !g { THROUGH_JAR_COST } else { 1.0 })
            .collect();
        let mut distance = vec![f64::INFINITY; h * w];
        let mut heap = BinaryHeap::new();
        for cell in (0..h * w).filter(|&cell| goal[cell]) {
            distance[cell] = 0.0;
            heap.push(Frontier {
                distance: 0.0,
                cell,
            });
        }
        let [[x0, x1], [y0, y1]] = grid.bounds();
        let (cell_w, cell_h) = ((x1 - x0) / w as f64, (y1 - y0) / h as f64);
        let lengths = NEIGHBOURS.map(|(di, dj)| (di as f64 * cell_h).hypot(dj as f64 * cell_w));
        while let Some(Frontier { distance: d, cell }) = heap.pop() {
            if d > distance[cell] {
                continue;
            }
            let (i, j) = (cell / w, cell % w);
            for ((di, dj), length) in NEIGHBOURS.into_iter().zip(lengths) {
                let (Some(ni), Some(nj)) = (i.checked_add_signed(di), j.checked_add_signed(dj))
                else {
                    continue;
                };
                if ni >= h || nj >= w {
                    continue;
                }
                let next = ni * w + nj;
                let candidate = d + length * 0.5 * (step_factor[cell] + step_factor[next]);
                if candidate < distance[next] {
                    distance[next] = candidate;
                    heap.push(Frontier {
                        distance: candidate,
                        cell: next,
                    });
                }
            }
        }
        Self {
            shape: (h, w),
            bounds: grid.bounds(),
            distance,
        }
    }

    /// Path distance from `point` to the target, m (0 before the first reset, or when the
    /// target covers no cell).
    pub fn distance(&self, point: [f64; 2]) -> f64 {
        let (h, w) = self.shape;
        if h < 2 || w < 2 {
            return 0.0;
        }
        let [[x0, x1], [y0, y1]] = self.bounds;
        let (cell_w, cell_h) = ((x1 - x0) / w as f64, (y1 - y0) / h as f64);
        // Clamp onto the rectangle of cell centres and add the straight distance to it.
        let inside = [
            point[0].clamp(x0 + 0.5 * cell_w, x1 - 0.5 * cell_w),
            point[1].clamp(y0 + 0.5 * cell_h, y1 - 0.5 * cell_h),
        ];
        let outside = (point[0] - inside[0]).hypot(point[1] - inside[1]);
        let u = (inside[0] - x0) / cell_w - 0.5;
        let v = (inside[1] - y0) / cell_h - 0.5;
        let (j, i) = (
            (u.floor() as usize).min(w - 2),
            (v.floor() as usize).min(h - 2),
        );
        let (fu, fv) = (u - j as f64, v - i as f64);
        let at = |i: usize, j: usize| self.distance[i * w + j];
        let near = at(i, j) * (1.0 - fu) + at(i, j + 1) * fu;
        let far = at(i + 1, j) * (1.0 - fu) + at(i + 1, j + 1) * fu;
        let d = outside + near * (1.0 - fv) + far * fv;
        if d.is_finite() {
            d
        } else {
            0.0
        }
    }
}

const NEIGHBOURS: [(isize, isize); 8] = [
    (-1, -1),
    (-1, 0),
    (-1, 1),
    (0, -1),
    (0, 1),
    (1, -1),
    (1, 0),
    (1, 1),
];

/// The fingertip of a finger whose joint is at `(x, y)` with yaw `yaw` (yaw 0 points along
/// +y).
pub fn fingertip(x: f64, y: f64, yaw: f64, finger_length: f64) -> [f64; 2] {
    let (s, c) = yaw.sin_cos();
    [x - s * finger_length, y + c * finger_length]
}
