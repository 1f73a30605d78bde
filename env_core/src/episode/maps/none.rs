//! The `none` map mode: no map. The agent sees only proprioception and touch; the image has
//! no channels, the IoU is 0 and nothing is held. Cost: nothing.

use std::any::Any;

use super::{AgentMap, GridValues, MapKind, TouchReport};
use crate::episode::error::EpisodeError;
use crate::scene::Contact;

/// The `none` row of the map-mode table.
pub(super) const KIND: MapKind = MapKind {
    channels: &[],
    build: |_, _| Ok(Box::new(NoMap)),
};

/// No map.
pub struct NoMap;

impl AgentMap for NoMap {
    fn reset(&mut self, _slice: &[[f64; 2]], _camera: [f64; 2]) -> Result<(), EpisodeError> {
        Ok(())
    }

    fn add_touch(&mut self, _readings: &[Contact], _swept: Option<[f64; 2]>) -> TouchReport {
        TouchReport::default()
    }

    fn rows(&self) -> usize {
        0
    }

    fn iou(&self, _truth: &[bool]) -> f64 {
        0.0
    }

    fn encode(&self, _out: &mut [u8]) {}

    fn render_grids(&self) -> Vec<(&'static str, GridValues)> {
        Vec::new()
    }

    fn as_any(&self) -> &dyn Any {
        self
    }
}
