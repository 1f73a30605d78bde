//! The distance from every cell of a grid to the nearest cell of a mask, capped: what the
//! planner's clearance and hiding rules read.
//!
//! Exact and in the Python planner's values: the distance of offset `(di, dj)` cells is
//! `cell * hypot(di, dj)`, and the nearest masked cell is found by a separable exact
//! Euclidean distance transform (per row the nearest masked column, then per column the
//! lower envelope of the rows' parabolas, in integers), O(cells) instead of the brute
//! force's O(cells · (cap / cell)²).

/// The capped distance transform of one cell size and cap: the distance of every squared
/// offset within the cap's reach is found once, for every mask transformed.
#[derive(Debug, Clone)]
pub struct CappedDistance {
    cap: f64,
    /// `cell * hypot(di, dj)` per `di² + dj²` within reach ([`smallest_distance`]).
    table: Vec<f64>,
}

impl CappedDistance {
    /// The transform of cells of side `cell` capped at `cap` (m).
    pub fn new(cell: f64, cap: f64) -> Self {
        let reach = (cap / cell).ceil() as usize;
        let table = (0..=2 * reach * reach)
            .map(|squared| smallest_distance(squared, reach, cell))
            .collect();
        Self { cap, table }
    }

    /// Per cell of the `(rows, cols)` row-major `mask`: the distance from its centre to the
    /// nearest centre of a `mask` cell, `cell * hypot(di, dj)`, or the cap where none is
    /// nearer than it (m).
    pub fn of(&self, mask: &[bool], rows: usize, cols: usize) -> Vec<f64> {
        debug_assert_eq!(mask.len(), rows * cols);
        let (cap, table) = (self.cap, &self.table);
        // Per row, the column distance to the nearest masked cell in that row (none: -1).
        let mut along_row = vec![-1i64; rows * cols];
        for i in 0..rows {
            let row = &mask[i * cols..(i + 1) * cols];
            let out = &mut along_row[i * cols..(i + 1) * cols];
            let mut last = None;
            for j in 0..cols {
                if row[j] {
                    last = Some(j);
                }
                if let Some(k) = last {
                    out[j] = (j - k) as i64;
                }
            }
            let mut next = None;
            for j in (0..cols).rev() {
                if row[j] {
                    next = Some(j);
                }
                if let Some(k) = next {
                    let d = (k - j) as i64;
                    out[j] = if out[j] < 0 { d } else { out[j].min(d) };
                }
            }
        }
        let mut best = vec![cap; rows * cols];
        let mut envelope = LowerEnvelope::with_capacity(rows);
        for j in 0..cols {
            // Per column, the least over rows k of (i - k)² + along_row(k)²: the lower envelope
            // of one parabola per row that holds a masked cell.
            envelope.clear();
            for k in 0..rows {
                let dj = along_row[k * cols + j];
                if dj >= 0 {
                    envelope.add(k as i64, dj * dj);
                }
            }
            if envelope.is_empty() {
                continue;
            }
            let mut segment = 0;
            for i in 0..rows {
                let squared = envelope.least_at(i as i64, &mut segment) as usize;
                if let Some(&d) = table.get(squared) {
                    if d < cap {
                        best[i * cols + j] = d;
                    }
                }
            }
        }
        best
    }
}

/// The lower envelope of the parabolas `(x - vertex)² + height`, vertices added in rising
/// order (Felzenszwalb and Huttenlocher's distance transform), in exact integer arithmetic:
/// the crossings are kept as fractions.
struct LowerEnvelope {
    /// The parabolas on the envelope, (vertex, height), left to right.
    parabolas: Vec<(i64, i64)>,
    /// Where each parabola's stretch of the envelope starts: `numerator / denominator`
    /// (the first's is −∞, stored as `None`).
    starts: Vec<Option<(i64, i64)>>,
}

impl LowerEnvelope {
    fn with_capacity(capacity: usize) -> Self {
        Self {
            parabolas: Vec::with_capacity(capacity),
            starts: Vec::with_capacity(capacity),
        }
    }

    fn clear(&mut self) {
        self.parabolas.clear();
        self.starts.clear();
    }

    fn is_empty(&self) -> bool {
        self.parabolas.is_empty()
    }

    /// Where parabolas `a` and `b` (`a`'s vertex left of `b`'s) cross, as a fraction.
    fn crossing((p, fp): (i64, i64), (q, fq): (i64, i64)) -> (i64, i64) {
        ((fq + q * q) - (fp + p * p), 2 * (q - p))
    }

    fn add(&mut self, vertex: i64, height: i64) {
        let new = (vertex, height);
        while let Some(&last) = self.parabolas.last() {
            let (num, den) = Self::crossing(last, new);
            match self.starts.last().copied().flatten() {
                // The new parabola is below the last all along the last's stretch.
                Some((start_num, start_den)) if num * start_den <= start_num * den => {
                    self.parabolas.pop();
                    self.starts.pop();
                }
                _ => {
                    self.parabolas.push(new);
                    self.starts.push(Some((num, den)));
                    return;
                }
            }
        }
        self.parabolas.push(new);
        self.starts.push(None);
    }

    /// The envelope's value at `x`, for `x` rising from call to call (`segment` keeps the
    /// stretch reached).
    fn least_at(&self, x: i64, segment: &mut usize) -> i64 {
        while let Some(&Some((num, den))) = self.starts.get(*segment + 1) {
            if num <= x * den {
                *segment += 1;
            } else {
                break;
            }
        }
        let (vertex, height) = self.parabolas[*segment];
        (x - vertex) * (x - vertex) + height
    }
}

/// `cell * hypot(di, dj)` for an offset with `di² + dj² = squared` (the smallest such
/// value, should rounding part offsets of one length; infinite if none within `reach`).
fn smallest_distance(squared: usize, reach: usize, cell: f64) -> f64 {
    let mut best = f64::INFINITY;
    for di in 0..=reach {
        let rest = match squared.checked_sub(di * di) {
            Some(rest) => rest,
            None => break,
        };
        let dj = (rest as f64).sqrt().round() as usize;
        if dj <= reach && dj * dj == rest {
            best = best.min(cell * (di as f64).hypot(dj as f64));
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The brute force the transform stands for: every masked cell within reach.
    fn brute_force(mask: &[bool], rows: usize, cols: usize, cell: f64, cap: f64) -> Vec<f64> {
        let reach = (cap / cell).ceil() as i64;
        let mut best = vec![cap; rows * cols];
        for i in 0..rows as i64 {
            for j in 0..cols as i64 {
                for di in -reach..=reach {
                    for dj in -reach..=reach {
                        let (k, l) = (i + di, j + dj);
                        if k < 0 || l < 0 || k >= rows as i64 || l >= cols as i64 {
                            continue;
                        }
                        let d = cell * (di as f64).hypot(dj as f64);
                        if d < cap && mask[(k * cols as i64 + l) as usize] {
                            let cell_best = &mut best[(i * cols as i64 + j) as usize];
                            *cell_best = cell_best.min(d);
                        }
                    }
                }
            }
        }
        best
    }

    #[test]
    fn the_transform_equals_the_brute_force_bit_for_bit() {
        let (rows, cols) = (23, 37);
        let mut state = 12345u64;
        for density in [0.0, 0.01, 0.05, 0.3, 0.9] {
            let mask: Vec<bool> = (0..rows * cols)
                .map(|_| {
                    state = state
                        .wrapping_mul(6364136223846793005)
                        .wrapping_add(1442695040888963407);
                    ((state >> 33) as f64 / (1u64 << 31) as f64) < density
                })
                .collect();
            let fast = CappedDistance::new(0.0075, 0.08).of(&mask, rows, cols);
            assert_eq!(
                fast,
                brute_force(&mask, rows, cols, 0.0075, 0.08),
                "density {density}"
            );
        }
    }

    #[test]
    fn an_empty_mask_is_at_the_cap_everywhere() {
        assert!(CappedDistance::new(0.01, 0.05)
            .of(&[false; 12], 3, 4)
            .iter()
            .all(|&d| d == 0.05));
    }
}
