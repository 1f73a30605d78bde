//! How much a jar was disturbed since reset: planar displacement of its centre, vertical
//! displacement, and tilt of its axis from the vertical. Intrusive contact is measured here,
//! never hidden.

use rapier3d::prelude::*;

/// Disturbance of one jar since reset.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Disturbance {
    /// Distance its centre moved in the slice plane, m.
    pub displacement: f64,
    /// Change of its centre's height, m.
    pub vertical: f64,
    /// Angle between its axis and the world's z axis, rad.
    pub tilt: f64,
}

impl Disturbance {
    /// Compares the jar's body pose now with its pose at reset. Cost: O(1).
    pub fn between(at_reset: &Pose, now: &Pose) -> Self {
        let d = now.translation - at_reset.translation;
        let axis = now.rotation * Vector::Z;
        Self {
            displacement: f64::from(d.x).hypot(f64::from(d.y)),
            vertical: f64::from(d.z),
            // atan2 keeps small tilts accurate where acos(z) would lose them in f32.
            tilt: f64::from(axis.x)
                .hypot(f64::from(axis.y))
                .atan2(f64::from(axis.z)),
        }
    }
}
