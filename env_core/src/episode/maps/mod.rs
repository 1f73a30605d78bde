//! The agent's map, one file per map mode behind one trait (modelled on parry's `Shape`:
//! one file per shape, the pipeline calls the trait). The episode builds its map from the
//! table below ([`MapMode::kind`]) and calls [`AgentMap`] for everything map-specific:
//! reset from the depth camera's first look, a step's touch and swept free space, the map
//! image, the rows held, the IoU against the true footprints and the grids a renderer
//! draws. Nothing outside this folder matches on the map mode.
//!
//! - [`gpis`]: the GPIS posterior (mean and std channels). Cost: the depth prior's rows at
//!   reset, O(k·n·G) for k rows added to n held on G cells, O(G) per image.
//! - [`occupancy`]: a log-odds evidence grid (probability channel). Cost: O(ray length /
//!   cell) per depth ray, O(1) per contact, O(G) per image.
//! - [`none`]: no map and no image. Free.
//! - [`MapConfig`]: the map's settings (one `settings!` table for every mode).
//! - [`MapChannel`]: one channel of a mode's image: its encoding and its decoder (one home
//!   for both, next to the mode's encoder); [`decode_image`] inverts an image.
//!
//! # Adding a map mode
//!
//! 1. Write `maps/<mode>.rs`: a type that implements [`AgentMap`], and
//!    `pub(super) const KIND: MapKind` with its image channels ([`MapChannel`], each with
//!    its encoding and decoder; none for a mode without an image) and its constructor
//!    `build(&MapConfig, &GridSpec)`. Settings of its own go into [`MapConfig`] below.
//! 2. Add one row to the `map_modes!` table below: its doc line, then
//!    `Variant = "name" => module`. The row declares the module, the [`MapMode`] variant,
//!    the name the `map` setting accepts (and the Python annotation and stub), and the
//!    constructor the episode calls.
//!
//! Nothing else changes: the episode, the batch, the bindings (observation arrays, layout,
//! decoders, render state) and the Python observation space read the mode through
//! [`MapMode::kind`] and the trait.

use std::any::Any;
use std::sync::Arc;

use super::error::EpisodeError;
use crate::gpis::{GridSpec, TileRunner};
use crate::scene::Contact;
use crate::settings;
use crate::settings::{Choice, Range};

/// The table of map modes: one row per mode declares its module, its [`MapMode`] variant
/// and name, and dispatches to the module's [`MapKind`].
macro_rules! map_modes {
    ($( $(#[doc = $doc:literal])+ $variant:ident = $name:literal => $module:ident ),+ $(,)?) => {
        $( pub mod $module; )+

        /// Which map the agent sees: one row of the table in [`crate::episode::maps`].
        #[derive(Debug, Clone, Copy, PartialEq, Eq)]
        pub enum MapMode {
            $( $(#[doc = $doc])+ $variant, )+
        }

        crate::choice! {
            MapMode {
                $( $variant => $name, )+
            }
        }

        impl MapMode {
            /// What this mode's map is: its image channels and its constructor.
            pub fn kind(self) -> &'static MapKind {
                match self {
                    $( Self::$variant => &$module::KIND, )+
                }
            }
        }
    };
}

map_modes! {
    /// GPIS posterior mean and standard deviation.
    Gpis = "gpis" => gpis,
    /// A plain log-odds evidence grid from the same depth and touch points.
    Occupancy = "occupancy" => occupancy,
    /// No map: the agent sees only proprioception and touch.
    None = "none" => none,
}

settings! {
    /// How the map is built from depth and touch, and how it is rendered as an image.
    pub struct MapConfig {
        /// Which map the agent sees: the GPIS mean and std, a plain occupancy grid, or none.
        mode: MapMode = MapMode::Gpis => "map" in Range::FINITE,
        /// (H, W) of the map grid over the cupboard's interior; square cells, H >= 36.
        grid_shape: (usize, usize) = (40, 80) => "grid_shape" in Range::closed(36.0, 4096.0),
        /// Constant prior mean of the GPIS, m (positive: unobserved space reads as free).
        prior_mean: f64 = 0.01 => "prior_mean" in Range::FINITE,
        /// Diameter of the paper's circle prior placed behind each depth cluster, m; None
        /// for no circle prior.
        circle_prior_diameter: Option<f64> = None => "circle_prior_diameter" in Range::POSITIVE,
        /// GPIS noise standard deviation of a depth point, m.
        depth_noise_std: f64 = 0.003 => "map_depth_noise_std" in Range::NON_NEGATIVE,
        /// The depth slice is thinned (evenly) to at most this many points before it enters
        /// the GPIS (the prior's cost grows as rows squared times cells; 64 keeps the prior's
        /// IoU within the interval of 96's on validation layouts, benchmarks/prior_rows.py).
        max_prior_depth_points: usize = 64 => "max_prior_depth_points" in Range::AT_LEAST_ONE,
        /// Free-space evidence: a value observation f = +offset this far in front of each
        /// depth point along its camera ray, m; None for surface points only.
        free_space_offset: Option<f64> = Some(0.01) => "free_space_offset" in Range::POSITIVE,
        /// Depth points closer than this to the side or back walls are left out of the prior
        /// before thinning, m (they are the cupboard, not a jar); 0 keeps every point.
        wall_clearance: f64 = 0.0 => "prior_wall_clearance" in Range::NON_NEGATIVE,
        /// The finger's swept free space as map evidence (not in the paper): after every
        /// wrist motion without a tactile reading, the fingertip's point becomes a value
        /// observation f = +this (m) in the GPIS map (skipped, as contacts are, where the
        /// map is already certain: skip_below_variance) and free evidence in the occupancy
        /// map, so the map keeps where the finger has been. None adds nothing (v0).
        swept_free_space: Option<f64> = None => "swept_free_space" in Range::POSITIVE,
        /// GPIS noise standard deviation of a contact's position, m.
        contact_noise_std: f64 = 0.001 => "contact_noise_std" in Range::NON_NEGATIVE,
        /// GPIS noise standard deviation of each contact-normal component.
        normal_noise_std: f64 = 0.1 => "normal_noise_std" in Range::NON_NEGATIVE,
        /// A contact is skipped when the map's variance at its point is already below
        /// this, m^2.
        skip_below_variance: f64 = 1e-5 => "skip_below_variance" in Range::NON_NEGATIVE,
        /// Most GPIS rows per episode; contacts beyond it are dropped and counted.
        max_rows: usize = 1500 => "max_rows" in Range::AT_LEAST_ONE,
        /// |mean| that saturates the map's mean channel, m.
        mean_scale: f64 = 0.05 => "mean_scale" in Range::POSITIVE,
        /// Standard deviation that saturates the map's std channel, m.
        std_scale: f64 = 0.1 => "std_scale" in Range::POSITIVE,
    }
    sections {}
    check_across = |_| Ok(());
}

/// A map mode's constructor: a new map over `grid` with these settings (`config` valid),
/// before its first reset.
pub type BuildMap = fn(&MapConfig, &GridSpec) -> Result<Box<dyn AgentMap>, EpisodeError>;

/// What a map mode is, apart from its state: the row of the table a [`MapMode`] reaches.
pub struct MapKind {
    /// The channels of its image, in order (channel first, each H × W); empty for a mode
    /// without an image.
    pub channels: &'static [MapChannel],
    /// Its constructor.
    pub build: BuildMap,
}

/// One channel of a mode's map image.
pub struct MapChannel {
    /// The channel's name.
    pub name: &'static str,
    /// How the pixel value is computed from the map.
    pub encoding: &'static str,
    /// What a pixel decodes to; None for a channel that carries nothing.
    pub decoded: Option<ChannelDecoder>,
}

/// The inverse of a channel's encoding, up to its quantisation step.
pub struct ChannelDecoder {
    /// The decoded quantity's name (the key of the decoded arrays).
    pub name: &'static str,
    /// What it means, with its unit.
    pub meaning: &'static str,
    /// The quantity of one pixel (in f64, in the order the docs state).
    pub value: fn(u8, &MapConfig) -> f64,
}

/// What a map did with one step's touch.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct TouchReport {
    /// Rows the map gained (GPIS rows; 0 for maps without rows).
    pub rows_added: usize,
    /// Readings (and the swept point) left out as uninformative or degenerate.
    pub skipped: usize,
    /// Readings dropped for want of capacity.
    pub dropped: usize,
    /// Whether the map changed (its IoU must be recomputed).
    pub changed: bool,
}

/// The values of one grid a renderer draws, row-major (H, W), in the map's own type.
#[derive(Debug, Clone, PartialEq)]
pub enum GridValues {
    /// Float64 values.
    F64(Vec<f64>),
    /// Float32 values.
    F32(Vec<f32>),
}

/// A map mode's map: what the episode calls for everything map-specific.
pub trait AgentMap: Send + Sync {
    /// Forgets everything and starts from the depth camera's first look: the noisy slice
    /// `slice` seen from `camera` (x, y). Fails only on what the prior refuses (a
    /// non-finite camera).
    fn reset(&mut self, slice: &[[f64; 2]], camera: [f64; 2]) -> Result<(), EpisodeError>;

    /// Adds one step's tactile `readings` (already inside the grid) and, when the finger
    /// read nothing and `swept_free_space` is set, the fingertip point `swept`.
    fn add_touch(&mut self, readings: &[Contact], swept: Option<[f64; 2]>) -> TouchReport;

    /// Rows held (GPIS rows; 0 for maps without rows): `info["gpis_rows"]`.
    fn rows(&self) -> usize;

    /// IoU of the map's interior against the `truth` mask (row-major cells); 0 without a
    /// map.
    fn iou(&self, truth: &[bool]) -> f64;

    /// Writes the image into `out` (channels × G, channel first, as [`MapKind::channels`]
    /// describes).
    fn encode(&self, out: &mut [u8]);

    /// The grids a renderer draws, by name (`mean`/`std`, `occupancy`, none).
    fn render_grids(&self) -> Vec<(&'static str, GridValues)>;

    /// The map as `Any`, for typed access (tests, benchmarks).
    fn as_any(&self) -> &dyn Any;

    /// Lets `runner` compute the map's grid updates in tiles (the episode batch's threads
    /// help each other); maps without tiled updates ignore it. Results do not change.
    fn share_tiles(&mut self, _runner: Arc<dyn TileRunner>) {}
}

/// The nearest byte to `value` in [0, 255], halves rounded up: `value + 0.5` truncated,
/// which (unlike `f64::round`, a libm call) the compiler vectorises.
#[inline]
pub(super) fn to_byte(value: f64) -> u8 {
    (value + 0.5) as u8
}

/// Why an image cannot be decoded.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DecodeError {
    /// What was expected.
    pub expected: String,
    /// What came.
    pub got: String,
}

/// The decoded channels of a `mode` image over `cells` cells (channel first, each `cells`
/// long): one (name, values) per channel that carries a quantity, in channel order; none
/// for a mode without an image. Fails when `image` is not `channels × cells` long. Cost
/// O(channels · (cells + 256)).
pub fn decode_image(
    config: &MapConfig,
    cells: usize,
    image: &[u8],
) -> Result<Vec<(&'static str, Vec<f64>)>, DecodeError> {
    let channels = config.mode.kind().channels;
    let expected = channels.len() * cells;
    if image.len() != expected {
        return Err(DecodeError {
            expected: format!(
                "{expected} pixels ({} channels of {cells} cells) for map '{}'",
                channels.len(),
                config.mode.name()
            ),
            got: format!("{} pixels", image.len()),
        });
    }
    Ok(channels
        .iter()
        .zip(image.chunks_exact(cells.max(1)))
        .filter_map(|(channel, pixels)| {
            let decoder = channel.decoded.as_ref()?;
            // A pixel has 256 values: decode each once, then look the cells up.
            let table: Vec<f64> = (0..=u8::MAX).map(|p| (decoder.value)(p, config)).collect();
            let values = pixels.iter().map(|&p| table[usize::from(p)]).collect();
            Some((decoder.name, values))
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_table_names_every_mode_in_order() {
        assert_eq!(MapMode::NAMES, ["gpis", "occupancy", "none"]);
        assert_eq!(MapMode::ANNOTATION, "Literal['gpis', 'occupancy', 'none']");
        assert_eq!(MapMode::EXPECTED, "'gpis', 'occupancy' or 'none'");
        for (index, name) in MapMode::NAMES.iter().enumerate() {
            let mode = MapMode::from_index(index);
            assert_eq!(mode.index(), index);
            assert_eq!(mode.name(), *name);
        }
    }

    #[test]
    fn every_mode_builds_and_writes_its_channels() {
        let grid = GridSpec::new([[-0.3, 0.3], [0.0, 0.3]], (40, 80)).unwrap();
        for index in 0..MapMode::NAMES.len() {
            let config = MapConfig {
                mode: MapMode::from_index(index),
                ..MapConfig::default()
            };
            let kind = config.mode.kind();
            let mut map = (kind.build)(&config, &grid).unwrap();
            map.reset(&[[0.0, 0.15], [0.05, 0.2]], [0.0, -0.25])
                .unwrap();
            let mut image = vec![0u8; kind.channels.len() * grid.n_cells()];
            map.encode(&mut image);
            let decoded = decode_image(&config, grid.n_cells(), &image).unwrap();
            let carrying = kind.channels.iter().filter(|c| c.decoded.is_some()).count();
            assert_eq!(decoded.len(), carrying);
            assert!(
                decode_image(&config, grid.n_cells(), &image[..image.len() / 2]).is_err()
                    || image.is_empty()
            );
        }
    }
}
