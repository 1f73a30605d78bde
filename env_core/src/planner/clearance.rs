//! Where the hand can go without coming near a jar: the planner's clearance queries on its
//! belief.
//!
//! A [`ClearanceField`] is the distance to the nearest blocked cell of the map, padded
//! beyond the cupboard (the side walls block; the space outside the opening is free).
//! [`deepest_clear`] is how deep the wrist can go straight in along a lane, and
//! [`safe_angle`] how far the finger can turn at a wrist position, the wrist's corners and
//! the arm kept clear and the turn stopped where the finger would meet a seen jar.

use super::belief::DISTANCE_CAP;
use super::distance::distance_to;
use super::geometry::PlannerGeometry;
use super::numeric::{arange, linspace};

/// Clearance kept between the wrist or arm and a cell that may hold a jar, m.
const MARGIN: f64 = 0.004;
/// Extra rows and columns of the clearance field beyond the map (outside the cupboard).
const PAD_CELLS: usize = 10;

/// Distance to the nearest blocked cell on the map padded beyond the cupboard, by
/// nearest-cell lookup.
pub struct ClearanceField {
    cell: f64,
    inverse_cell: f64,
    x0: f64,
    y0: f64,
    rows: usize,
    cols: usize,
    distance: Vec<f64>,
}

impl ClearanceField {
    /// The field of `blocked` (the map's cells, row-major).
    pub fn new(g: &PlannerGeometry, blocked: &[bool]) -> Self {
        let (h, w) = g.grid_shape;
        let pad = PAD_CELLS as f64;
        let x0 = -0.5 * g.width - pad * g.cell;
        let y0 = -pad * g.cell;
        let (rows, cols) = (h + PAD_CELLS, w + 2 * PAD_CELLS);
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
        Self {
            cell: g.cell,
            inverse_cell: 1.0 / g.cell,
            x0,
            y0,
            rows,
            cols,
            distance: distance_to(&padded, rows, cols, g.cell, DISTANCE_CAP),
        }
    }

    /// The distance at the cell holding `(x, y)`; infinite outside the padded grid.
    pub fn at(&self, x: f64, y: f64) -> f64 {
        match (self.cell_index(x - self.x0), self.cell_index(y - self.y0)) {
            (Some(j), Some(i)) if i < self.rows && j < self.cols => {
                self.distance[i * self.cols + j]
            }
            _ => f64::INFINITY,
        }
    }

    /// Whether `y` lies before the padded grid (every point there is outside it).
    pub fn is_before(&self, y: f64) -> bool {
        y < self.y0
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

/// The deepest wrist depth along lane `x` the wrist reaches without coming near a cell
/// that may hold a jar (`field`), the fingertip ahead clear of seen jars (`solid`); `None`
/// if the lane is blocked at the opening.
pub fn deepest_clear(
    g: &PlannerGeometry,
    field: &ClearanceField,
    solid: &ClearanceField,
    x: f64,
) -> Option<f64> {
    let wrist_room = g.wrist_half_extent + MARGIN + 0.5 * g.cell;
    let mut deepest = None;
    for y in arange(-g.wrist_half_extent, g.depth, 0.5 * g.cell) {
        let clear = field.at(x, y + g.wrist_half_extent) >= wrist_room
            && field.at(x, y) >= wrist_room
            && solid.at(x, y + g.reach) >= 0.5 * g.cell;
        if !clear {
            break;
        }
        deepest = Some(y);
    }
    deepest
}

/// The turns [`safe_angle`] tries and the points of the hand it checks, fixed per geometry:
/// per turn towards −x and towards +x, the offsets from the wrist of the points along the
/// arm behind it and along the finger ahead.
#[derive(Debug, Clone)]
pub struct TurnProbe {
    angles: Vec<f64>,
    /// Per side (−x, +x), per angle: the points' offsets from the wrist.
    offsets: [Vec<TurnedHand>; 2],
}

/// The offsets (forward · along) of the points checked along the arm and the finger, at
/// one turn.
#[derive(Debug, Clone)]
struct TurnedHand {
    arm: Vec<[f64; 2]>,
    finger: Vec<[f64; 2]>,
}

impl TurnProbe {
    /// The probe controller's turns, steps of its sweep rate up to the largest sweep angle;
    /// points along the arm every cell, and 8 along the finger.
    pub fn new(g: &PlannerGeometry) -> Self {
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
        let offsets = [-1.0, 1.0].map(|side: f64| {
            angles
                .iter()
                .map(|&angle| {
                    let [fx, fy] = PlannerGeometry::forward(-side * angle);
                    let points = |along: &[f64]| along.iter().map(|&a| [fx * a, fy * a]).collect();
                    TurnedHand {
                        arm: points(&along_arm),
                        finger: points(&along_finger),
                    }
                })
                .collect()
        });
        Self { angles, offsets }
    }
}

/// Largest turn towards `side` (+1: +x) at wrist `(x, y)` keeping the wrist's corners and
/// the arm clear (`field`), and stopping where the finger would meet a seen jar (`solid`).
pub fn safe_angle(
    g: &PlannerGeometry,
    turns: &TurnProbe,
    field: &ClearanceField,
    solid: &ClearanceField,
    [x, y]: [f64; 2],
    side: f64,
) -> f64 {
    let wrist_radius = 2f64.sqrt() * g.wrist_half_extent + MARGIN + 0.5 * g.cell;
    let arm_room = g.arm_half_width + MARGIN + 0.5 * g.cell;
    if field.at(x, y) < wrist_radius {
        return 0.0;
    }
    let mut safe = 0.0;
    // The turn stops at the first angle the arm cannot take, or just after the finger
    // meets a seen jar.
    let offsets = &turns.offsets[usize::from(side > 0.0)];
    for (&angle, TurnedHand { arm, finger }) in turns.angles.iter().zip(offsets) {
        // The arm's points go back out of the cupboard (a turn is under a right angle):
        // once one is before the field, so are the rest, and all of them are clear.
        let arm_ok = arm
            .iter()
            .map(|&[ox, oy]| (x - ox, y - oy))
            .take_while(|&(_, ay)| !field.is_before(ay))
            .all(|(ax, ay)| field.at(ax, ay) >= arm_room || ay <= -g.arm_half_width - g.cell);
        if !arm_ok {
            break;
        }
        safe = angle;
        let finger_free = finger
            .iter()
            .all(|&[ox, oy]| solid.at(x + ox, y + oy) >= 0.5 * g.cell);
        if !finger_free {
            break;
        }
    }
    safe
}
