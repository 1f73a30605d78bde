//! The fingertip's path distance to the target, for potential-based reward shaping.
//!
//! At reset, a Dijkstra search over the map grid (8-connected, cell centres) measures every
//! cell's shortest path to the target's footprint, where a step through another jar's
//! footprint (widened by `clearance`) costs `THROUGH_JAR_COST` times its length: the
//! distance follows the free corridor instead of pointing through the occluder, yet stays
//! finite everywhere, so a finger pressed into a jar still has a well-defined potential.
//! The search runs on the grid with a border of cells no step enters (no bounds to check)
//! and its queue is a ring of buckets (`BucketQueue`) rather than a binary heap: the same
//! distances bit for bit, with O(1) pushes and pops for a heap's O(log n) (it runs at every
//! reset).
//!
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

impl ApproachField {
    /// The field for `jars[target]` (cells within `clearance` of its footprint are the goal);
    /// other jars' footprints widened by `clearance` (m) are expensive to cross. Cost
    /// O(G) for G cells.
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
        let [[x0, x1], [y0, y1]] = grid.bounds();
        let (cell_w, cell_h) = ((x1 - x0) / w as f64, (y1 - y0) / h as f64);
        let lengths = NEIGHBOURS.map(|(di, dj)| (di as f64 * cell_h).hypot(dj as f64 * cell_w));
        let distance = path_distances((h, w), lengths, &step_factor, &goal);
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

/// Dijkstra over an `h × w` grid, 8-connected (`NEIGHBOURS`, whose lengths are `lengths`):
/// each cell's least path cost to a `goal` cell, a step costing its length times the mean
/// of its two cells' `step_factor`s (each at least 1 and at most `THROUGH_JAR_COST`);
/// infinite where no goal is reachable.
fn path_distances(
    (h, w): (usize, usize),
    lengths: [f64; 8],
    step_factor: &[f64],
    goal: &[bool],
) -> Vec<f64> {
    let mut queue = BucketQueue::new(lengths, THROUGH_JAR_COST);
    // The search runs on the grid with a border of one cell, so a neighbour is an offset
    // with no bounds to check: border cells hold distance 0, which no step (of positive
    // cost) improves, so they are never queued.
    let padded_w = w + 2;
    // Row i of the grid is `interior(i)` of the bordered one.
    let interior = |i: usize| (i + 1) * padded_w + 1..(i + 1) * padded_w + 1 + w;
    let mut distance = vec![0.0; (h + 2) * padded_w];
    let mut factor = vec![1.0; (h + 2) * padded_w];
    for i in 0..h {
        distance[interior(i)].fill(f64::INFINITY);
        factor[interior(i)].copy_from_slice(&step_factor[i * w..(i + 1) * w]);
        for (j, cell) in interior(i).enumerate() {
            if goal[i * w + j] {
                distance[cell] = 0.0;
                queue.push(cell, 0.0);
            }
        }
    }
    let offsets = NEIGHBOURS.map(|(di, dj)| di * padded_w as isize + dj);
    let mut settled = vec![false; distance.len()];
    while let Some(cell) = queue.pop() {
        if std::mem::replace(&mut settled[cell], true) {
            continue;
        }
        let (d, own) = (distance[cell], factor[cell]);
        for (offset, length) in offsets.into_iter().zip(lengths) {
            let next = cell.wrapping_add_signed(offset);
            let candidate = d + length * 0.5 * (own + factor[next]);
            if candidate < distance[next] {
                distance[next] = candidate;
                queue.push(next, candidate);
            }
        }
    }
    (0..h)
        .flat_map(|i| distance[interior(i)].iter().copied())
        .collect()
}

/// Dijkstra's queue as a ring of buckets (Dial's queue, with buckets narrower than a step):
/// bucket b holds the cells reached at a distance in [b·width, (b+1)·width), with the width
/// half the cheapest step. A cell settled from bucket b reaches its neighbours at least two
/// buckets later (the half width also covers the rounding of the sums), so no cell of a
/// bucket can improve another of the same bucket: its cells are settled in any order, and
/// every cell ends with the distance a binary heap gives, bit for bit (each is the least
/// rounded sum over its neighbours' final distances, whatever the order of settling). A
/// step spans fewer buckets than the ring holds, so the ring never laps itself. A cell
/// pushed again when its distance drops leaves a stale entry behind; the caller skips
/// cells it has settled. Push and pop cost O(1) (amortised over the empty buckets passed).
struct BucketQueue {
    width: f64,
    ring: Vec<Vec<usize>>,
    /// The absolute bucket being drained.
    current: usize,
    pending: usize,
}

impl BucketQueue {
    /// A queue for steps of these lengths (positive and finite) with step factors from 1 to
    /// `most_factor`.
    fn new(lengths: [f64; 8], most_factor: f64) -> Self {
        let shortest = lengths.iter().copied().fold(f64::INFINITY, f64::min);
        let longest = lengths.iter().copied().fold(0.0, f64::max) * most_factor;
        let width = 0.5 * shortest;
        let buckets = (longest / width).ceil() as usize + 2;
        Self {
            width,
            ring: vec![Vec::new(); buckets],
            current: 0,
            pending: 0,
        }
    }

    /// Queues `cell` at `distance` (finite, at least the distance of the cell last popped).
    fn push(&mut self, cell: usize, distance: f64) {
        let bucket = (distance / self.width) as usize;
        debug_assert!(bucket >= self.current && bucket < self.current + self.ring.len());
        let slot = bucket % self.ring.len();
        self.ring[slot].push(cell);
        self.pending += 1;
    }

    /// A cell of the nearest non-empty bucket, or `None` once every bucket is empty.
    fn pop(&mut self) -> Option<usize> {
        if self.pending == 0 {
            return None;
        }
        loop {
            let slot = self.current % self.ring.len();
            if let Some(cell) = self.ring[slot].pop() {
                self.pending -= 1;
                return Some(cell);
            }
            self.current += 1;
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

#[cfg(test)]
mod tests {
    use super::*;
    use std::cmp::Reverse;
    use std::collections::BinaryHeap;

    /// The textbook search the field's replaced: a binary heap (non-negative floats order
    /// as their bits do), neighbours checked against the grid's bounds.
    fn heap_distances(
        (h, w): (usize, usize),
        lengths: [f64; 8],
        step_factor: &[f64],
        goal: &[bool],
    ) -> Vec<f64> {
        let mut distance = vec![f64::INFINITY; h * w];
        let mut heap = BinaryHeap::new();
        for cell in (0..h * w).filter(|&cell| goal[cell]) {
            distance[cell] = 0.0;
            heap.push(Reverse((0u64, cell)));
        }
        while let Some(Reverse((bits, cell))) = heap.pop() {
            let d = f64::from_bits(bits);
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
                    heap.push(Reverse((candidate.to_bits(), next)));
                }
            }
        }
        distance
    }

    /// The field's search (a ring of buckets, a bordered grid) settles every cell at the
    /// textbook search's distance, bit for bit: random
    /// blocked cells and goals on grids of several shapes and cell aspect ratios (the
    /// rounding of long sums included: the largest grid's paths run to hundreds of steps).
    #[test]
    fn the_fields_search_gives_the_textbook_searchs_distances_bit_for_bit() {
        let mut state = 0x9e37_79b9_7f4a_7c15_u64;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        for (h, w, cell_h, cell_w) in [
            (40, 80, 0.01, 0.01),
            (40, 80, 0.0075, 0.01),
            (7, 3, 0.3, 0.011),
            (1, 9, 0.02, 0.02),
            (120, 90, 0.004, 0.0051),
        ] {
            let lengths = NEIGHBOURS.map(|(di, dj)| (di as f64 * cell_h).hypot(dj as f64 * cell_w));
            for trial in 0..20 {
                let goal: Vec<bool> = (0..h * w).map(|_| next() % 97 == 0).collect();
                let blocked_share = trial % 5;
                let step_factor: Vec<f64> = (0..h * w)
                    .map(|_| {
                        if next() % 5 < blocked_share {
                            THROUGH_JAR_COST
                        } else {
                            1.0
                        }
                    })
                    .collect();
                let buckets = path_distances((h, w), lengths, &step_factor, &goal);
                let heap = heap_distances((h, w), lengths, &step_factor, &goal);
                for (cell, (b, e)) in buckets.iter().zip(&heap).enumerate() {
                    assert_eq!(
                        b.to_bits(),
                        e.to_bits(),
                        "{h}x{w}, trial {trial}, cell {cell}"
                    );
                }
            }
        }
    }
}
