//! The agent's observation, described once: the map image and the proprio vector.
//!
//! Each proprio entry is one row of [`PROPRIO_FIELDS`] (name, scale, meaning, and the
//! function that computes it), so the vector, its length, the Python docstring's table and
//! the planner's decoder all follow from this table; adding an entry is one edit here.
//! The map image's channels are described by each map mode, beside the encoder and the
//! decoder (`super::maps`).
//!
//! Cost: the proprio vector is O(1) per step.

use super::config::EpisodeConfig;
use crate::scene::{Contact, HandPose, Scene};

/// What the proprio entries are computed from: the hand's state after a step.
pub struct ProprioInputs<'a> {
    /// The wrist's pose.
    pub pose: HandPose,
    /// The finger's deflection from the wrist, rad.
    pub finger_angle: f64,
    /// The first tactile reading of the step, if any.
    pub contact: Option<&'a Contact>,
    /// Steps since reset.
    pub steps: usize,
    /// The episode's configuration (hand geometry, workspace, `max_steps`).
    pub config: &'a EpisodeConfig,
}

/// One entry of the proprio vector: its index is its position in [`PROPRIO_FIELDS`].
pub struct ProprioField {
    /// The entry's name (what decoders index by).
    pub name: &'static str,
    /// How the raw quantity maps to [−1, 1].
    pub scale: &'static str,
    /// What the entry means.
    pub meaning: &'static str,
    /// Computes the entry (before the cast to f32).
    pub value: fn(&ProprioInputs<'_>) -> f64,
}

/// `v` in `[lo, hi]` mapped linearly to [−1, 1], clamped.
fn scaled(v: f64, lo: f64, hi: f64) -> f64 {
    (2.0 * (v - lo) / (hi - lo) - 1.0).clamp(-1.0, 1.0)
}

/// The contact's offset from the wrist along axis `axis`, over the finger length; 0 without.
fn contact_offset(p: &ProprioInputs<'_>, axis: usize) -> f64 {
    let wrist = [p.pose.x, p.pose.y];
    p.contact.map_or(0.0, |c| {
        ((c.point[axis] - wrist[axis]) / p.config.scene.hand.finger_length).clamp(-1.0, 1.0)
    })
}

/// The proprioception and touch vector, entry by entry; every entry lies in [−1, 1].
pub const PROPRIO_FIELDS: [ProprioField; 11] = [
    ProprioField {
        name: "x",
        scale: "2 (x - x_min) / (x_max - x_min) - 1, clamped",
        meaning: "wrist x (along the opening) over the hand's workspace",
        value: |p| {
            let [x0, x1] = p.config.scene.hand.workspace[0];
            scaled(p.pose.x, x0, x1)
        },
    },
    ProprioField {
        name: "y",
        scale: "2 (y - y_min) / (y_max - y_min) - 1, clamped",
        meaning: "wrist y (into the cupboard) over the hand's workspace",
        value: |p| {
            let [y0, y1] = p.config.scene.hand.workspace[1];
            scaled(p.pose.y, y0, y1)
        },
    },
    ProprioField {
        name: "cos_yaw",
        scale: "cos(yaw)",
        meaning: "cosine of the wrist yaw (0 points the finger into the cupboard)",
        value: |p| p.pose.yaw.cos(),
    },
    ProprioField {
        name: "sin_yaw",
        scale: "sin(yaw)",
        meaning: "sine of the wrist yaw",
        value: |p| p.pose.yaw.sin(),
    },
    ProprioField {
        name: "deflection",
        scale: "angle / finger_limit, clamped",
        meaning: "the compliant finger's deflection from the wrist",
        value: |p| (p.finger_angle / p.config.scene.hand.finger_limit).clamp(-1.0, 1.0),
    },
    ProprioField {
        name: "in_contact",
        scale: "0 or 1",
        meaning: "1 when the finger made at least one tactile reading this step",
        value: |p| if p.contact.is_some() { 1.0 } else { 0.0 },
    },
    ProprioField {
        name: "contact_dx",
        scale: "dx / finger_length, clamped",
        meaning: "the first reading's x offset from the wrist (0 without contact)",
        value: |p| contact_offset(p, 0),
    },
    ProprioField {
        name: "contact_dy",
        scale: "dy / finger_length, clamped",
        meaning: "the first reading's y offset from the wrist (0 without contact)",
        value: |p| contact_offset(p, 1),
    },
    ProprioField {
        name: "normal_x",
        scale: "unit vector",
        meaning: "x of the touched jar's outward normal at the first reading (0 without)",
        value: |p| p.contact.map_or(0.0, |c| c.normal[0]),
    },
    ProprioField {
        name: "normal_y",
        scale: "unit vector",
        meaning: "y of the touched jar's outward normal at the first reading (0 without)",
        value: |p| p.contact.map_or(0.0, |c| c.normal[1]),
    },
    ProprioField {
        name: "time_left",
        scale: "1 - steps / max_steps, floored at -1",
        meaning: "the share of the episode's time limit (max_steps) still left",
        value: |p| (1.0 - p.steps as f64 / p.config.max_steps as f64).max(-1.0),
    },
];

/// Length of the proprio vector.
pub const PROPRIO_LEN: usize = PROPRIO_FIELDS.len();

/// The index of the proprio entry `name`, if there is one.
pub fn proprio_index(name: &str) -> Option<usize> {
    PROPRIO_FIELDS.iter().position(|f| f.name == name)
}

/// The proprio vector of `scene` after `steps` steps. Cost O(1).
pub fn proprio(config: &EpisodeConfig, scene: &Scene, steps: usize) -> [f32; PROPRIO_LEN] {
    let inputs = ProprioInputs {
        pose: scene.hand_pose(),
        finger_angle: scene.finger_angle(),
        contact: scene.contacts().first(),
        steps,
        config,
    };
    PROPRIO_FIELDS.map(|field| (field.value)(&inputs) as f32)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn proprio_names_are_unique_and_found_by_index() {
        for (index, field) in PROPRIO_FIELDS.iter().enumerate() {
            assert_eq!(proprio_index(field.name), Some(index));
        }
        assert_eq!(proprio_index("no such entry"), None);
    }
}
