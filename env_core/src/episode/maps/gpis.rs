//! The `gpis` map mode: the GPIS posterior over the grid, started from the depth prior
//! ([`prior`]) and refined by every touch; its image is the posterior mean and standard
//! deviation, each scaled to a byte.
//!
//! Cost: the prior's rows at reset and O(k·n·G) for k rows added to n held on G cells (the
//! GPIS's incremental update); O(G) per image; O(G) per IoU.

pub mod prior;

use std::any::Any;
use std::sync::Arc;

use super::{
    to_byte, AgentMap, ChannelDecoder, GridValues, MapChannel, MapConfig, MapKind, TouchReport,
};
use crate::episode::error::EpisodeError;
use crate::episode::metrics::iou;
use crate::gpis::observation::noise_variance;
use crate::gpis::{Gpis, GpisConfig, GridSpec, Observation, TileRunner};
use crate::scene::Contact;
use prior::depth_prior;

/// The `gpis` row of the map-mode table.
pub(super) const KIND: MapKind = MapKind {
    channels: &CHANNELS,
    build: |config, grid| Ok(Box::new(GpisMap::new(config, grid)?)),
};

/// The image's channels: the mean and the standard deviation.
pub const CHANNELS: [MapChannel; 2] = [
    MapChannel {
        name: "mean",
        encoding: "128 + 127 clip(mean / mean_scale, -1, 1): below 128 inside a jar, 128 on \
                   a surface, above in free space",
        decoded: Some(ChannelDecoder {
            name: "mean",
            meaning: "the GPIS posterior mean, a signed distance (negative inside a jar), m: \
                      (pixel - 128) / 127 * mean_scale, saturated at +-mean_scale",
            value: |pixel, config| (f64::from(pixel) - 128.0) / 127.0 * config.mean_scale,
        }),
    },
    MapChannel {
        name: "std",
        encoding: "255 clip(std / std_scale, 0, 1): the GPIS posterior standard deviation",
        decoded: Some(ChannelDecoder {
            name: "std",
            meaning: "the GPIS posterior standard deviation, m: pixel / 255 * std_scale, \
                      saturated at std_scale",
            value: |pixel, config| f64::from(pixel) / 255.0 * config.std_scale,
        }),
    },
];

/// The GPIS map of an episode and the settings it adds rows with.
pub struct GpisMap {
    gpis: Gpis,
    grid: GridSpec,
    config: MapConfig,
}

impl GpisMap {
    /// An empty GPIS over `grid` (ψ from the bounds, the prior mean and row capacity of
    /// `config`).
    pub fn new(config: &MapConfig, grid: &GridSpec) -> Result<Self, EpisodeError> {
        let gpis = Gpis::new(GpisConfig {
            bounds: grid.bounds(),
            shape: grid.shape(),
            psi: None,
            prior_mean: config.prior_mean,
            max_rows: config.max_rows,
        })?;
        Ok(Self {
            gpis,
            grid: grid.clone(),
            config: config.clone(),
        })
    }

    /// The GPIS.
    pub fn gpis(&self) -> &Gpis {
        &self.gpis
    }
}

impl AgentMap for GpisMap {
    fn reset(&mut self, slice: &[[f64; 2]], camera: [f64; 2]) -> Result<(), EpisodeError> {
        self.gpis.clear();
        let prior = depth_prior(slice, camera, &self.grid, &self.config)?;
        self.gpis.add(&prior, None)?;
        Ok(())
    }

    /// The swept point first (a value observation f = +swept_free_space, if a row is free),
    /// then as many contacts as fit (3 rows each); the rest are dropped.
    fn add_touch(&mut self, readings: &[Contact], swept: Option<[f64; 2]>) -> TouchReport {
        let gpis = &mut self.gpis;
        let map = &self.config;
        let mut swept_rows = 0;
        let mut swept_skipped = 0;
        if let (Some(point), Some(value)) = (swept, map.swept_free_space) {
            if gpis.free_rows() >= 1 {
                let free = noise_variance("depth_noise_std", map.depth_noise_std)
                    .and_then(|noise| Observation::value(0, point, value, noise))
                    .expect("the fingertip is finite and the noise non-negative");
                let report = gpis
                    .add(&[free], Some(map.skip_below_variance))
                    .expect("a finite point inside the bounds that fits the capacity");
                swept_rows = report.added_rows;
                swept_skipped = report.skipped_uninformative + report.rejected_degenerate;
            }
        }
        let fit = readings.len().min(gpis.free_rows() / 3);
        let points: Vec<[f64; 2]> = readings[..fit].iter().map(|c| c.point).collect();
        let normals: Vec<[f64; 2]> = readings[..fit].iter().map(|c| c.normal).collect();
        let report = gpis
            .add_contacts(
                &points,
                &normals,
                map.contact_noise_std,
                map.normal_noise_std,
                Some(map.skip_below_variance),
            )
            .expect("contacts are finite, inside the bounds and fit the capacity");
        TouchReport {
            rows_added: report.added_rows + swept_rows,
            skipped: report.skipped_uninformative + report.rejected_degenerate + swept_skipped,
            dropped: readings.len() - fit,
            changed: swept_rows > 0 || report.added_rows > 0,
        }
    }

    fn rows(&self) -> usize {
        self.gpis.n_rows()
    }

    /// The interior is `mean < 0`.
    fn iou(&self, truth: &[bool]) -> f64 {
        iou(self.gpis.mean_grid().iter().map(|&m| m < 0.0), truth)
    }

    /// The [`CHANNELS`]. Cost O(G).
    fn encode(&self, out: &mut [u8]) {
        let (mean_scale, std_scale) = (self.config.mean_scale, self.config.std_scale);
        let cells = self.gpis.mean_grid().len();
        let (mean_channel, std_channel) = out.split_at_mut(cells);
        for (pixel, &mean) in mean_channel.iter_mut().zip(self.gpis.mean_grid()) {
            *pixel = to_byte(128.0 + 127.0 * (mean / mean_scale).clamp(-1.0, 1.0));
        }
        for (pixel, &variance) in std_channel.iter_mut().zip(self.gpis.variance_grid()) {
            *pixel = to_byte(255.0 * (variance.max(0.0).sqrt() / std_scale).clamp(0.0, 1.0));
        }
    }

    /// `mean` and `std` (the square root of the variance), float64.
    fn render_grids(&self) -> Vec<(&'static str, GridValues)> {
        let std = self.gpis.variance_grid().iter().map(|v| v.sqrt()).collect();
        vec![
            ("mean", GridValues::F64(self.gpis.mean_grid().to_vec())),
            ("std", GridValues::F64(std)),
        ]
    }

    fn as_any(&self) -> &dyn Any {
        self
    }

    fn share_tiles(&mut self, runner: Arc<dyn TileRunner>) {
        self.gpis.share_tiles(runner);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every byte decodes within half a quantisation step of what encodes to it.
    #[test]
    fn decode_inverts_encode_within_a_step() {
        let config = MapConfig::default();
        let [mean, std] = &CHANNELS;
        let (mean, std) = (
            mean.decoded.as_ref().unwrap().value,
            std.decoded.as_ref().unwrap().value,
        );
        for k in -2000..=2000 {
            let m = f64::from(k) * 1e-3 * config.mean_scale;
            let pixel = to_byte(128.0 + 127.0 * (m / config.mean_scale).clamp(-1.0, 1.0));
            let step = config.mean_scale / 127.0;
            assert!((mean(pixel, &config) - m.clamp(-config.mean_scale, config.mean_scale)).abs()
                <= 0.5 * step + 1e-15);
        }
        for k in 0..=2000 {
            let s = f64::from(k) * 1e-3 * config.std_scale;
            let pixel = to_byte(255.0 * (s / config.std_scale).clamp(0.0, 1.0));
            let step = config.std_scale / 255.0;
            assert!((std(pixel, &config) - s.min(config.std_scale)).abs() <= 0.5 * step + 1e-15);
        }
        assert_eq!(mean(128, &config), 0.0);
        assert_eq!(mean(255, &config), config.mean_scale);
        assert_eq!(std(255, &config), config.std_scale);
    }
}
