//! Where the hand can go without coming near a jar: the planner's clearance queries on its
//! belief.
//!
//! A [`ClearanceField`] is the distance to the nearest blocked cell of the map, padded
//! beyond the cupboard (the side walls block; the space outside the opening is free).
//! [`deepest_clear`] is how deep the wrist can go straight in along a lane, and
//! [`safe_angle`] how far the finger can turn at a wrist position, the wrist's corners and
//! the arm kept clear and the turn stopped where the finger would meet a seen jar.

use super::geometry::PlannerGeometry;
use super::numeric::{arange, linspace};

/// Clearance kept between the wrist or arm and a cell that may hold a jar, m.
const MARGIN: f64 = 0.004;
/// Extra rows and columns of the clearance field beyond the map (outside the cupboard).
const PAD_CELLS: usize = 10;

/// The padded grid a [`ClearanceField`] is sampled on: fixed per geometry, so the cells a
/// point falls in can be found once and read from every field.
#[derive(Debug, Clone)]
pub struct FieldLayout {
    cell: f64,
    inverse_cell: f64,
    x0: f64,
    y0: f64,
    rows: usize,
    cols: usize,
}

impl FieldLayout {
    /// The map's grid padded by `PAD_CELLS` beyond the sides and the opening.
    pub fn new(g: &PlannerGeometry) -> Self {
        let (h, w) = g.grid_shape;
        let pad = PAD_CELLS as f64;
        Self {
            cell: g.cell,
            inverse_cell: 1.0 / g.cell,
            x0: -0.5 * g.width - pad * g.cell,
            y0: -pad * g.cell,
            rows: h + PAD_CELLS,
            cols: w + 2 * PAD_CELLS,
        }
    }

    /// The column holding `x`, if inside the grid.
    #[inline]
    fn column(&self, x: f64) -> Option<usize> {
        self.cell_index(x - self.x0).filter(|&j| j < self.cols)
    }

    /// The row holding `y`, if inside the grid.
    #[inline]
    fn row(&self, y: f64) -> Option<usize> {
        self.cell_index(y - self.y0).filter(|&i| i < self.rows)
    }

    /// The floor of `offset / cell`, `None` below 0. By the reciprocal (a multiplication,
    /// not a division), and by the division itself where the two could part: within a
    /// millionth of a cell of a cell's edge (they differ by a few units in the last place).
    #[inline]
    fn cell_index(&self, offset: f64) -> Option<usize> {
        let quick = offset * self.inverse_cell;
        if quick >= 1e-6 {
            let whole = quick as usize;
            let part = quick - whole as f64;
            if (1e-6..=1.0 - 1e-6).contains(&part) {
                return Some(whole);
            }
        }
        let exact = offset / self.cell;
        (exact >= 0.0).then_some(exact as usize)
    }
}

/// Distance to the nearest blocked cell on the map padded beyond the cupboard, by
/// nearest-cell lookup.
pub struct ClearanceField {
    layout: FieldLayout,
    distance: Vec<f64>,
}

impl ClearanceField {
    /// The field of `blocked` (the map's cells, row-major) on `layout`.
    pub fn new(g: &PlannerGeometry, layout: &FieldLayout, blocked: &[bool]) -> Self {
        let padded = padded_mask(g, layout, blocked);
        Self {
            layout: layout.clone(),
            distance: g.distance.of(&padded, layout.rows, layout.cols),
        }
    }

    /// The distance at the cell holding `(x, y)`; infinite outside the padded grid.
    pub fn at(&self, x: f64, y: f64) -> f64 {
        self.at_cell(self.layout.row(y), self.layout.column(x))
    }

    /// The distance at cell (`row`, `column`); infinite if either is outside.
    #[inline]
    fn at_cell(&self, row: Option<usize>, column: Option<usize>) -> f64 {
        match (row, column) {
            (Some(i), Some(j)) => self.distance[i * self.layout.cols + j],
            _ => f64::INFINITY,
        }
    }
}

/// `blocked` (the map's cells, row-major) on `layout`'s padded grid: beyond the side walls
/// blocked, outside the opening free.
fn padded_mask(g: &PlannerGeometry, layout: &FieldLayout, blocked: &[bool]) -> Vec<bool> {
    let (h, w) = g.grid_shape;
    let FieldLayout {
        x0, y0, rows, cols, ..
    } = *layout;
    debug_assert_eq!(rows, h + PAD_CELLS);
    let mut padded = vec![false; rows * cols];
    for i in 0..rows {
        let y = y0 + (i as f64 + 0.5) * g.cell;
        for j in 0..cols {
            let x = x0 + (j as f64 + 0.5) * g.cell;
            let inside = i >= PAD_CELLS && (PAD_CELLS..PAD_CELLS + w).contains(&j);
            padded[i * cols + j] = (inside && blocked[(i - PAD_CELLS) * w + (j - PAD_CELLS)])
                || (x.abs() > 0.5 * g.width && y > 0.0);
        }
    }
    padded
}

/// The cells the finger must not sweep into, padded as a [`ClearanceField`] is: the finger
/// asks only whether a point is in such a cell (a field's distance under half a cell is
/// exactly that), so no distance is computed.
pub struct SweepMask {
    layout: FieldLayout,
    blocked: Vec<bool>,
}

impl SweepMask {
    /// The mask of `blocked` (the map's cells, row-major) on `layout`.
    pub fn new(g: &PlannerGeometry, layout: &FieldLayout, blocked: &[bool]) -> Self {
        Self {
            layout: layout.clone(),
            blocked: padded_mask(g, layout, blocked),
        }
    }

    /// Whether the cell holding `(x, y)` is free (outside the padded grid: free).
    pub fn is_free_at(&self, x: f64, y: f64) -> bool {
        self.is_free_cell(self.layout.row(y), self.layout.column(x))
    }

    /// Whether cell (`row`, `column`) is free (either outside: free).
    #[inline]
    fn is_free_cell(&self, row: Option<usize>, column: Option<usize>) -> bool {
        match (row, column) {
            (Some(i), Some(j)) => !self.blocked[i * self.layout.cols + j],
            _ => true,
        }
    }
}

/// The deepest wrist depth along lane `x` the wrist reaches without coming near a cell
/// that may hold a jar (`field`), the fingertip ahead clear of seen jars (`solid`); `None`
/// if the lane is blocked at the opening.
pub fn deepest_clear(
    g: &PlannerGeometry,
    field: &ClearanceField,
    solid: &SweepMask,
    x: f64,
) -> Option<f64> {
    let wrist_room = g.wrist_half_extent + MARGIN + 0.5 * g.cell;
    let mut deepest = None;
    for y in arange(-g.wrist_half_extent, g.depth, 0.5 * g.cell) {
        let clear = field.at(x, y + g.wrist_half_extent) >= wrist_room
            && field.at(x, y) >= wrist_room
            && solid.is_free_at(x, y + g.reach);
        if !clear {
            break;
        }
        deepest = Some(y);
    }
    deepest
}

/// The turns [`safe_angle`] tries and the cells of the padded grid it reads, fixed per
/// geometry: for every lane, depth, side and turn, the cells of the points along the arm
/// behind the wrist and along the finger ahead (found once: a field changes every probe,
/// its grid never).
#[derive(Debug, Clone)]
pub struct TurnProbe {
    angles: Vec<f64>,
    /// Per (side, angle): the points along the arm, their cells' columns per lane and rows
    /// per depth.
    arm: Vec<TurnedPoints>,
    /// Per (side, angle): the points along the finger, their cells as for the arm.
    finger: Vec<TurnedPoints>,
}

/// A turn's points (arm or finger) as cells of the padded grid, per lane and per depth.
#[derive(Debug, Clone)]
struct TurnedPoints {
    /// `[lane][point]`: the column holding the point's x.
    columns: Vec<Vec<Option<usize>>>,
    /// `[depth][point]`: the row holding the point's y.
    rows: Vec<Vec<Option<usize>>>,
    /// `[depth]`: how many of the points come before the first that is clear whatever the
    /// field: one at or before y = −(arm half width + cell), or before the grid. The arm
    /// goes back out of the cupboard (a turn is under a right angle), so every point after
    /// that one is clear too, and only these need reading.
    needed: Vec<usize>,
}

impl TurnProbe {
    /// The probe controller's turns, steps of its sweep rate up to the largest sweep angle;
    /// points along the arm every cell, and 8 along the finger; their cells for every lane
    /// and depth of the probe grid.
    pub fn new(g: &PlannerGeometry, layout: &FieldLayout) -> Self {
        let angles = arange(
            g.probe_sweep_rate,
            g.probe_max_angle + 1e-9,
            g.probe_sweep_rate,
        );
        let along_arm = arange(
            g.wrist_half_extent,
            g.wrist_half_extent + g.arm_length,
            g.cell,
        );
        let along_finger = linspace(g.joint_offset + 0.02, g.reach, 8);
        let escape = -g.arm_half_width - g.cell;
        let mut arm = Vec::new();
        let mut finger = Vec::new();
        for side in [-1.0f64, 1.0] {
            for &angle in &angles {
                let [fx, fy] = PlannerGeometry::forward(-side * angle);
                let points = |along: &[f64], sign: f64| -> TurnedPoints {
                    let offsets: Vec<[f64; 2]> = along.iter().map(|&a| [fx * a, fy * a]).collect();
                    // The arm's points are behind the wrist (x − offset), the finger's ahead.
                    let at = |base: f64, offset: f64| {
                        if sign < 0.0 {
                            base - offset
                        } else {
                            base + offset
                        }
                    };
                    let ys: Vec<Vec<f64>> = g
                        .probe_depths
                        .iter()
                        .map(|&y| offsets.iter().map(|o| at(y, o[1])).collect())
                        .collect();
                    TurnedPoints {
                        columns: g
                            .probe_lanes
                            .iter()
                            .map(|&x| offsets.iter().map(|o| layout.column(at(x, o[0]))).collect())
                            .collect(),
                        rows: ys
                            .iter()
                            .map(|row| row.iter().map(|&y| layout.row(y)).collect())
                            .collect(),
                        needed: ys
                            .iter()
                            .map(|row| {
                                row.iter()
                                    .take_while(|&&y| y >= layout.y0 && y > escape)
                                    .count()
                            })
                            .collect(),
                    }
                };
                arm.push(points(&along_arm, -1.0));
                finger.push(points(&along_finger, 1.0));
            }
        }
        Self {
            angles,
            arm,
            finger,
        }
    }
}

/// Largest turn towards `side` (+1: +x) at the wrist position of probe lane `lane` and
/// depth `depth` keeping the wrist's corners and the arm clear (`field`), and stopping
/// where the finger would meet a seen jar (`solid`).
pub fn safe_angle(
    g: &PlannerGeometry,
    turns: &TurnProbe,
    field: &ClearanceField,
    solid: &SweepMask,
    [lane, depth]: [usize; 2],
    side: f64,
) -> f64 {
    let wrist_radius = 2f64.sqrt() * g.wrist_half_extent + MARGIN + 0.5 * g.cell;
    let arm_room = g.arm_half_width + MARGIN + 0.5 * g.cell;
    if field.at(g.probe_lanes[lane], g.probe_depths[depth]) < wrist_radius {
        return 0.0;
    }
    let first = if side > 0.0 { turns.angles.len() } else { 0 };
    let mut safe = 0.0;
    // The turn stops at the first angle the arm cannot take, or just after the finger
    // meets a seen jar.
    for (a, &angle) in turns.angles.iter().enumerate() {
        let (arm, finger) = (&turns.arm[first + a], &turns.finger[first + a]);
        let (columns, rows) = (&arm.columns[lane], &arm.rows[depth]);
        let arm_ok = (0..arm.needed[depth]).all(|k| field.at_cell(rows[k], columns[k]) >= arm_room);
        if !arm_ok {
            break;
        }
        safe = angle;
        let (columns, rows) = (&finger.columns[lane], &finger.rows[depth]);
        let finger_free = (0..columns.len()).all(|k| solid.is_free_cell(rows[k], columns[k]));
        if !finger_free {
            break;
        }
    }
    safe
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::episode::EpisodeConfig;

    #[test]
    fn the_sweep_mask_is_free_exactly_where_the_field_is_half_a_cell_clear() {
        let g = PlannerGeometry::of(&EpisodeConfig::default()).expect("the default geometry");
        let layout = FieldLayout::new(&g);
        let mut state = 3u64;
        let blocked: Vec<bool> = (0..g.xs.len())
            .map(|_| {
                state = state
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                (state >> 60) == 0
            })
            .collect();
        let (field, mask) = (
            ClearanceField::new(&g, &layout, &blocked),
            SweepMask::new(&g, &layout, &blocked),
        );
        let half = 0.5 * g.cell;
        let mut points = 0;
        for i in -20..(2 * layout.rows as i64 + 20) {
            for j in -20..(2 * layout.cols as i64 + 20) {
                // Points on a half-cell lattice, beyond the padded grid too.
                let (x, y) = (layout.x0 + j as f64 * half, layout.y0 + i as f64 * half);
                assert_eq!(mask.is_free_at(x, y), field.at(x, y) >= half, "({x}, {y})");
                points += 1;
            }
        }
        assert!(points > 10_000);
    }
}
