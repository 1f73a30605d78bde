//! The `occupancy` map mode: a plain occupancy evidence grid (log-odds) built from the same
//! depth and touch points as the GPIS, a baseline map without uncertainty. Its image is the
//! probability of occupancy as a byte, and an empty channel.
//!
//! Depth: every cell a camera ray crosses before its hit gains free evidence, the hit cell
//! gains occupied evidence. Touch: the cell just behind the contact (along −normal) gains
//! occupied evidence, the cell just in front of it free evidence. Cost: O(ray length / cell)
//! per ray, O(1) per contact, O(G) per image and per IoU.

use std::any::Any;

use super::{
    to_byte, AgentMap, ChannelDecoder, GridValues, MapChannel, MapConfig, MapKind, TouchReport,
};
use crate::episode::error::EpisodeError;
use crate::episode::metrics::iou;
use crate::gpis::GridSpec;
use crate::scene::Contact;

/// The `occupancy` row of the map-mode table.
pub(super) const KIND: MapKind = MapKind {
    channels: &CHANNELS,
    build: |_: &MapConfig, grid| Ok(Box::new(OccupancyGrid::new(grid.clone()))),
};

/// The image's channels: the probability of occupancy, and an empty one.
pub const CHANNELS: [MapChannel; 2] = [
    MapChannel {
        name: "occupied",
        encoding: "255 P(occupied): 128 where unknown",
        decoded: Some(ChannelDecoder {
            name: "occupied",
            meaning: "the probability that the cell is occupied: pixel / 255 (0.502 where \
                      unknown)",
            value: |pixel, _| f64::from(pixel) / 255.0,
        }),
    },
    MapChannel {
        name: "empty",
        encoding: "0 (this map has no uncertainty; the channel keeps the space the same \
                   across modes)",
        decoded: None,
    },
];

/// Log-odds added to a cell seen occupied.
const OCCUPIED: f32 = 0.85;
/// Log-odds added to a cell seen free.
const FREE: f32 = -0.4;
/// Log-odds are clamped to ±this, so one contradicting look can still flip a cell.
const CLAMP: f32 = 3.5;

/// Log-odds of occupancy per grid cell, row-major (H, W); 0 = unknown.
#[derive(Debug, Clone)]
pub struct OccupancyGrid {
    grid: GridSpec,
    log_odds: Vec<f32>,
}

impl OccupancyGrid {
    /// An all-unknown grid.
    pub fn new(grid: GridSpec) -> Self {
        let cells = grid.n_cells();
        Self {
            grid,
            log_odds: vec![0.0; cells],
        }
    }

    /// Forgets all evidence.
    pub fn clear(&mut self) {
        self.log_odds.fill(0.0);
    }

    /// The grid.
    pub fn grid(&self) -> &GridSpec {
        &self.grid
    }

    /// Log-odds per cell, row-major.
    pub fn log_odds(&self) -> &[f32] {
        &self.log_odds
    }

    /// Probability of occupancy of cell `index`.
    pub fn probability(&self, index: usize) -> f32 {
        1.0 / (1.0 + (-self.log_odds[index]).exp())
    }

    fn cell_of(&self, p: [f64; 2]) -> Option<usize> {
        if !self.grid.contains(p) {
            return None;
        }
        let [[x0, x1], [y0, y1]] = self.grid.bounds();
        let (h, w) = self.grid.shape();
        let j = (((p[0] - x0) / (x1 - x0) * w as f64) as usize).min(w - 1);
        let i = (((p[1] - y0) / (y1 - y0) * h as f64) as usize).min(h - 1);
        Some(i * w + j)
    }

    fn add(&mut self, p: [f64; 2], evidence: f32) {
        if let Some(cell) = self.cell_of(p) {
            let v = &mut self.log_odds[cell];
            *v = (*v + evidence).clamp(-CLAMP, CLAMP);
        }
    }

    fn cell_size(&self) -> f64 {
        let [[x0, x1], _] = self.grid.bounds();
        (x1 - x0) / self.grid.shape().1 as f64
    }

    /// A depth ray from `origin` to its `hit`: free along the way, occupied at the hit.
    /// Samples every half cell, only over the part of the ray inside the grid (a reading
    /// far away, e.g. under huge depth noise, costs no more than one across the grid); a
    /// ray with a non-finite end adds nothing.
    pub fn add_ray(&mut self, origin: [f64; 2], hit: [f64; 2]) {
        if !origin.iter().chain(&hit).all(|v| v.is_finite()) {
            return;
        }
        let hit_cell = self.cell_of(hit);
        let (dx, dy) = (hit[0] - origin[0], hit[1] - origin[1]);
        let length = dx.hypot(dy);
        let step = 0.5 * self.cell_size();
        let samples = (length / step) as usize;
        // Samples outside the grid add nothing and leave `last` as it was: skip those
        // before the ray enters and after it leaves (one sample of slack on each side).
        let Some((enter, leave)) = self.inside_span(origin, [dx, dy]) else {
            self.add(hit, OCCUPIED);
            return;
        };
        let first = ((enter * length / step).floor() as usize).saturating_sub(1);
        let end = ((leave * length / step).ceil() as usize)
            .saturating_add(2)
            .min(samples);
        let mut last = None;
        for s in first..end {
            let t = s as f64 * step / length;
            let p = [origin[0] + t * dx, origin[1] + t * dy];
            let cell = self.cell_of(p);
            if cell.is_some() && cell != last && cell != hit_cell {
                self.add(p, FREE);
            }
            last = cell.or(last);
        }
        self.add(hit, OCCUPIED);
    }

    /// The span [enter, leave] of t in [0, 1] where `origin + t·delta` lies inside the
    /// grid's bounds (the slab method), or None if it never does.
    fn inside_span(&self, origin: [f64; 2], delta: [f64; 2]) -> Option<(f64, f64)> {
        let (mut enter, mut leave) = (0.0f64, 1.0f64);
        for (axis, [low, high]) in self.grid.bounds().into_iter().enumerate() {
            if delta[axis] == 0.0 {
                if origin[axis] < low || origin[axis] > high {
                    return None;
                }
                continue;
            }
            let a = (low - origin[axis]) / delta[axis];
            let b = (high - origin[axis]) / delta[axis];
            enter = enter.max(a.min(b));
            leave = leave.min(a.max(b));
        }
        (enter <= leave).then_some((enter, leave))
    }

    /// Free-space evidence at `point` (a place the finger passed without touching).
    pub fn add_free(&mut self, point: [f64; 2]) {
        self.add(point, FREE);
    }

    /// A contact at `point` with outward `normal` (unit): occupied behind, free in front.
    pub fn add_contact(&mut self, point: [f64; 2], normal: [f64; 2]) {
        let d = 0.5 * self.cell_size();
        self.add(
            [point[0] - d * normal[0], point[1] - d * normal[1]],
            OCCUPIED,
        );
        self.add(
            [
                point[0] + 2.0 * d * normal[0],
                point[1] + 2.0 * d * normal[1],
            ],
            FREE,
        );
    }
}

impl AgentMap for OccupancyGrid {
    /// Every depth ray of the slice, from the camera to its hit.
    fn reset(&mut self, slice: &[[f64; 2]], camera: [f64; 2]) -> Result<(), EpisodeError> {
        self.clear();
        for &hit in slice {
            self.add_ray(camera, hit);
        }
        Ok(())
    }

    /// Every reading, then the swept point as free evidence.
    fn add_touch(&mut self, readings: &[Contact], swept: Option<[f64; 2]>) -> TouchReport {
        for c in readings {
            self.add_contact(c.point, c.normal);
        }
        if let Some(point) = swept {
            self.add_free(point);
        }
        TouchReport {
            changed: !readings.is_empty() || swept.is_some(),
            ..TouchReport::default()
        }
    }

    fn rows(&self) -> usize {
        0
    }

    /// The interior is P(occupied) > 0.5.
    fn iou(&self, truth: &[bool]) -> f64 {
        iou((0..truth.len()).map(|i| self.probability(i) > 0.5), truth)
    }

    /// The [`CHANNELS`]. Cost O(G).
    fn encode(&self, out: &mut [u8]) {
        let cells = self.log_odds().len();
        let (probability_channel, empty_channel) = out.split_at_mut(cells);
        for (index, pixel) in probability_channel.iter_mut().enumerate() {
            *pixel = to_byte(f64::from(255.0 * self.probability(index)));
        }
        empty_channel.fill(0);
    }

    /// `occupancy`: P(occupied), float32.
    fn render_grids(&self) -> Vec<(&'static str, GridValues)> {
        let p = (0..self.log_odds.len()).map(|i| self.probability(i)).collect();
        vec![("occupancy", GridValues::F32(p))]
    }

    fn as_any(&self) -> &dyn Any {
        self
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every probability decodes within half a quantisation step of itself.
    #[test]
    fn decode_inverts_encode_within_a_step() {
        let decode = CHANNELS[0].decoded.as_ref().unwrap().value;
        let config = MapConfig::default();
        for k in 0..=1000 {
            let p = f64::from(k) / 1000.0;
            let pixel = to_byte(255.0 * p);
            assert!((decode(pixel, &config) - p).abs() <= 0.5 / 255.0 + 1e-15);
        }
    }
}
