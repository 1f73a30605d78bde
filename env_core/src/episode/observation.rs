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
    /// The entry's factor in the scene's mirror image (x -> -x about the cupboard's centre
    /// plane, yaw -> -yaw): 1 where the entry is kept, -1 where it is negated. Exact while the
    /// hand's workspace is symmetric in x, as it is by default; learners augment their data
    /// with mirrored observations.
    pub mirror: f64,
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
        mirror: -1.0,
        value: |p| {
            let [x0, x1] = p.config.scene.hand.workspace[0];
            scaled(p.pose.x, x0, x1)
        },
    },
    ProprioField {
        name: "y",
        scale: "2 (y - y_min) / (y_max - y_min) - 1, clamped",
        meaning: "wrist y (into the cupboard) over the hand's workspace",
        mirror: 1.0,
        value: |p| {
            let [y0, y1] = p.config.scene.hand.workspace[1];
            scaled(p.pose.y, y0, y1)
        },
    },
    ProprioField {
        name: "cos_yaw",
        scale: "cos(yaw)",
        meaning: "cosine of the wrist yaw (0 points the finger into the cupboard)",
        mirror: 1.0,
        value: |p| p.pose.yaw.cos(),
    },
    ProprioField {
        name: "sin_yaw",
        scale: "sin(yaw)",
        meaning: "sine of the wrist yaw",
        mirror: -1.0,
        value: |p| p.pose.yaw.sin(),
    },
    ProprioField {
        name: "deflection",
        scale: "angle / finger_limit, clamped",
        meaning: "the compliant finger's deflection from the wrist",
        mirror: -1.0,
        value: |p| (p.finger_angle / p.config.scene.hand.finger_limit).clamp(-1.0, 1.0),
    },
    ProprioField {
        name: "in_contact",
        scale: "0 or 1",
        meaning: "1 when the finger made at least one tactile reading this step",
        mirror: 1.0,
        value: |p| if p.contact.is_some() { 1.0 } else { 0.0 },
    },
    ProprioField {
        name: "contact_dx",
        scale: "dx / finger_length, clamped",
        meaning: "the first reading's x offset from the wrist (0 without contact)",
        mirror: -1.0,
        value: |p| contact_offset(p, 0),
    },
    ProprioField {
        name: "contact_dy",
        scale: "dy / finger_length, clamped",
        meaning: "the first reading's y offset from the wrist (0 without contact)",
        mirror: 1.0,
        value: |p| contact_offset(p, 1),
    },
    ProprioField {
        name: "normal_x",
        scale: "unit vector",
        meaning: "x of the touched jar's outward normal at the first reading (0 without)",
        mirror: -1.0,
        value: |p| p.contact.map_or(0.0, |c| c.normal[0]),
    },
    ProprioField {
        name: "normal_y",
        scale: "unit vector",
        meaning: "y of the touched jar's outward normal at the first reading (0 without)",
        mirror: 1.0,
        value: |p| p.contact.map_or(0.0, |c| c.normal[1]),
    },
    ProprioField {
        name: "time_left",
        scale: "1 - steps / max_steps, floored at -1",
        meaning: "the share of the episode's time limit (max_steps) still left",
        mirror: 1.0,
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

/// A physical quantity decoded from the proprio vector.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Quantity {
    /// A real number (m, rad or a share).
    Real(f64),
    /// A flag.
    Flag(bool),
    /// A count.
    Count(i64),
}

/// A proprio vector read by entry name, with the configuration its scales came from.
pub struct ProprioReading<'a> {
    /// The vector, as the observation holds it.
    pub proprio: &'a [f32; PROPRIO_LEN],
    /// The episode's configuration (hand geometry, workspace, `max_steps`).
    pub config: &'a EpisodeConfig,
}

impl ProprioReading<'_> {
    /// The entry `name` as stored (float32).
    fn entry(&self, name: &str) -> f32 {
        self.proprio[proprio_index(name).expect("a name of PROPRIO_FIELDS")]
    }

    /// The entry `name` widened to f64.
    fn real(&self, name: &str) -> f64 {
        f64::from(self.entry(name))
    }
}

/// One physical quantity the proprio vector decodes to: the inverse of the scales of
/// [`PROPRIO_FIELDS`], exact up to the float32 rounding of the entries (and their clamps).
pub struct ProprioQuantity {
    /// The quantity's name (the key of the decoded dict).
    pub name: &'static str,
    /// What it is, with its unit and how it is computed from the entries.
    pub meaning: &'static str,
    /// Computes it from the entries, in f64 in the order `meaning` states.
    pub value: fn(&ProprioReading<'_>) -> Quantity,
}

/// `lo + (v + 1) · 0.5 · (hi − lo)`: the inverse of [`scaled`] inside its clamp.
fn unscaled(v: f64, [lo, hi]: [f64; 2]) -> f64 {
    lo + (v + 1.0) * 0.5 * (hi - lo)
}

/// Every quantity the proprio vector decodes to, entry by entry (`yaw` from the cosine and
/// sine entries, `steps` from `time_left`).
pub const PROPRIO_QUANTITIES: [ProprioQuantity; 11] = [
    ProprioQuantity {
        name: "x",
        meaning: "wrist x, m: x_min + (x + 1) * 0.5 * (x_max - x_min)",
        value: |r| Quantity::Real(unscaled(r.real("x"), r.config.scene.hand.workspace[0])),
    },
    ProprioQuantity {
        name: "y",
        meaning: "wrist y, m: y_min + (y + 1) * 0.5 * (y_max - y_min)",
        value: |r| Quantity::Real(unscaled(r.real("y"), r.config.scene.hand.workspace[1])),
    },
    ProprioQuantity {
        name: "yaw",
        meaning: "wrist yaw, rad in [-pi, pi]: atan2(sin_yaw, cos_yaw), in f64",
        value: |r| Quantity::Real(r.real("sin_yaw").atan2(r.real("cos_yaw"))),
    },
    ProprioQuantity {
        name: "deflection",
        meaning: "the finger's deflection from the wrist, rad: deflection * finger_limit",
        value: |r| Quantity::Real(r.real("deflection") * r.config.scene.hand.finger_limit),
    },
    ProprioQuantity {
        name: "in_contact",
        meaning: "whether the finger made a tactile reading this step: in_contact > 0.5",
        value: |r| Quantity::Flag(r.entry("in_contact") > 0.5),
    },
    ProprioQuantity {
        name: "contact_dx",
        meaning: "the first reading's x offset from the wrist, m: finger_length * contact_dx \
                  (clipped at +-finger_length; 0 without contact)",
        value: |r| Quantity::Real(r.config.scene.hand.finger_length * r.real("contact_dx")),
    },
    ProprioQuantity {
        name: "contact_dy",
        meaning: "the first reading's y offset from the wrist, m: finger_length * contact_dy \
                  (clipped at +-finger_length; 0 without contact)",
        value: |r| Quantity::Real(r.config.scene.hand.finger_length * r.real("contact_dy")),
    },
    ProprioQuantity {
        name: "normal_x",
        meaning: "x of the touched jar's outward unit normal at the first reading (0 without)",
        value: |r| Quantity::Real(r.real("normal_x")),
    },
    ProprioQuantity {
        name: "normal_y",
        meaning: "y of the touched jar's outward unit normal at the first reading (0 without)",
        value: |r| Quantity::Real(r.real("normal_y")),
    },
    ProprioQuantity {
        name: "time_left",
        meaning: "the share of the time limit still left: time_left (floored at -1)",
        value: |r| Quantity::Real(r.real("time_left")),
    },
    ProprioQuantity {
        name: "steps",
        meaning: "steps since reset: round((1 - time_left) * max_steps) (exact below \
                  2 max_steps, where time_left is floored)",
        value: |r| {
            let steps = (1.0 - r.real("time_left")) * r.config.max_steps as f64;
            Quantity::Count(steps.round() as i64)
        },
    },
];

/// The physical quantities of `proprio` (a vector of this `config`), by name in the order
/// of [`PROPRIO_QUANTITIES`]. Cost O(1).
pub fn decode_proprio(
    proprio: &[f32; PROPRIO_LEN],
    config: &EpisodeConfig,
) -> [(&'static str, Quantity); PROPRIO_QUANTITIES.len()] {
    let reading = ProprioReading { proprio, config };
    PROPRIO_QUANTITIES.map(|q| (q.name, (q.value)(&reading)))
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

    fn real(decoded: &[(&str, Quantity)], name: &str) -> f64 {
        match decoded.iter().find(|(n, _)| *n == name).unwrap().1 {
            Quantity::Real(v) => v,
            other => panic!("{name}: {other:?}"),
        }
    }

    /// Encode then decode gives the quantities back within the entries' float32 rounding.
    #[test]
    fn decode_inverts_the_proprio_scales() {
        let config = EpisodeConfig::default();
        let hand = &config.scene.hand;
        for (k, yaw) in [-3.0, -1.2, 0.0, 0.4, 2.9].into_iter().enumerate() {
            let pose = HandPose {
                x: -0.2 + 0.1 * k as f64,
                y: -0.1 + 0.07 * k as f64,
                yaw,
            };
            let contact = Contact {
                point: [pose.x + 0.031, pose.y - 0.052],
                normal: [0.6, -0.8],
                jar: 0,
            };
            let touching = k % 2 == 0;
            let inputs = ProprioInputs {
                pose,
                finger_angle: 0.3 - 0.1 * k as f64,
                contact: touching.then_some(&contact),
                steps: 17 * k,
                config: &config,
            };
            let proprio = PROPRIO_FIELDS.map(|field| (field.value)(&inputs) as f32);
            let decoded = decode_proprio(&proprio, &config);
            let close = |name: &str, want: f64, scale: f64| {
                let got = real(&decoded, name);
                assert!(
                    (got - want).abs() <= 1e-6 * scale,
                    "{name}: {got} vs {want}"
                );
            };
            close("x", pose.x, 1.0);
            close("y", pose.y, 1.0);
            close("yaw", yaw, 1.0);
            close("deflection", inputs.finger_angle, 1.0);
            let in_contact = decoded.iter().find(|(n, _)| *n == "in_contact").unwrap().1;
            assert_eq!(in_contact, Quantity::Flag(touching));
            if touching {
                close("contact_dx", contact.point[0] - pose.x, hand.finger_length);
                close("contact_dy", contact.point[1] - pose.y, hand.finger_length);
                close("normal_x", 0.6, 1.0);
                close("normal_y", -0.8, 1.0);
            }
            let steps = decoded.iter().find(|(n, _)| *n == "steps").unwrap().1;
            assert_eq!(steps, Quantity::Count(17 * k as i64));
        }
    }

    /// The mirror image of the hand's state (x, yaw, the finger's deflection, the contact's
    /// x offset and normal negated) gives each entry times its `mirror` factor.
    #[test]
    fn mirrored_inputs_negate_the_entries_marked_so() {
        let config = EpisodeConfig::default();
        let [x0, x1] = config.scene.hand.workspace[0];
        assert_eq!(x0, -x1, "the default workspace is symmetric in x");
        for (k, yaw) in [-1.1, -0.3, 0.0, 0.7].into_iter().enumerate() {
            let pose = HandPose {
                x: -0.21 + 0.13 * k as f64,
                y: 0.02 * k as f64,
                yaw,
            };
            let contact = Contact {
                point: [pose.x - 0.04, pose.y + 0.05],
                normal: [0.8, -0.6],
                jar: 1,
            };
            let mirrored_pose = HandPose {
                x: -pose.x,
                y: pose.y,
                yaw: -yaw,
            };
            let mirrored_contact = Contact {
                point: [-contact.point[0], contact.point[1]],
                normal: [-contact.normal[0], contact.normal[1]],
                jar: 1,
            };
            let inputs = |pose, finger_angle, contact| ProprioInputs {
                pose,
                finger_angle,
                contact,
                steps: 9 * k,
                config: &config,
            };
            let angle = 0.2 - 0.15 * k as f64;
            let original = inputs(pose, angle, Some(&contact));
            let mirrored = inputs(mirrored_pose, -angle, Some(&mirrored_contact));
            for field in &PROPRIO_FIELDS {
                let (a, b) = ((field.value)(&original), (field.value)(&mirrored));
                assert!(
                    (b - field.mirror * a).abs() < 1e-12,
                    "{}: {a} mirrored to {b}",
                    field.name
                );
            }
        }
        assert!(PROPRIO_FIELDS
            .iter()
            .all(|f| f.mirror == 1.0 || f.mirror == -1.0));
    }

    #[test]
    fn every_entry_is_decoded_by_its_name() {
        for q in &PROPRIO_QUANTITIES {
            assert!(
                proprio_index(q.name).is_some() || ["yaw", "steps"].contains(&q.name),
                "{}",
                q.name
            );
        }
    }
}
