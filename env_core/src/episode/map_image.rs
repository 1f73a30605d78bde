//! The map as a 2-channel uint8 image (2 × H × W, channel first), the form in which
//! stable-baselines3 gives a Box observation its CNN.
//!
//! - `gpis`: channel 0 = 128 + 127 · clamp(mean / mean_scale, −1, 1) (below 128: inside an
//!   object, 128: a surface, above: free); channel 1 = 255 · clamp(std / std_scale, 0, 1).
//! - `occupancy`: channel 0 = 255 · P(occupied) (128: unknown); channel 1 = 0 (this map has
//!   no uncertainty; the channel keeps the observation space the same across modes).

use super::occupancy::OccupancyGrid;
use crate::gpis::Gpis;

/// Writes the GPIS image into `out` (length 2·G). Cost O(G).
pub fn encode_gpis(gpis: &Gpis, mean_scale: f64, std_scale: f64, out: &mut [u8]) {
    let cells = gpis.mean_grid().len();
    let (mean_channel, std_channel) = out.split_at_mut(cells);
    for (pixel, &mean) in mean_channel.iter_mut().zip(gpis.mean_grid()) {
        *pixel = (128.0 + 127.0 * (mean / mean_scale).clamp(-1.0, 1.0)).round() as u8;
    }
    for (pixel, &variance) in std_channel.iter_mut().zip(gpis.variance_grid()) {
        *pixel = (255.0 * (variance.max(0.0).sqrt() / std_scale).clamp(0.0, 1.0)).round() as u8;
    }
}

/// Writes the occupancy image into `out` (length 2·G). Cost O(G).
pub fn encode_occupancy(grid: &OccupancyGrid, out: &mut [u8]) {
    let cells = grid.log_odds().len();
    let (probability_channel, empty_channel) = out.split_at_mut(cells);
    for (index, pixel) in probability_channel.iter_mut().enumerate() {
        *pixel = (255.0 * grid.probability(index)).round() as u8;
    }
    empty_channel.fill(0);
}
