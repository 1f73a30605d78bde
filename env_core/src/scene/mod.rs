//! The cupboard scene in rapier3d (`docs/DESIGN.md` §2; paper §IV.A): one shelf compartment,
//! 3–7 (up to 16) dynamic spice jars with a hidden target (and optionally hidden decoys), a
//! pinhole depth camera for the first look, and the Exploratory Hand whose compliant finger
//! senses contacts.
//!
//! SI units, z up; the interior is `x ∈ [−W/2, W/2]`, `y ∈ [0, D]` (open front at y = 0, the
//! robot at y < 0), `z ∈ [0, H]`. The map plane is the horizontal slice at
//! [`SceneConfig::slice_height`].
//!
//! - [`config`]: every setting of the scene, declared once in its settings table.
//! - [`camera_intrinsics`]: the pinhole intrinsics derived from the camera settings.
//! - [`cupboard`], [`jar`]: the fixed walls and the dynamic jars; [`footprint`]: a jar's
//!   cross-section at a pose (signed distance, outline, support).
//! - [`layout`]: the seeded generator hiding the target (and any decoys) and keeping a
//!   corridor to each.
//! - [`visibility`]: the target's visible fraction, by ray casting.
//! - [`ray_cast`]: exact ray casts against the walls and jars the camera sees.
//! - [`depth_camera`], [`point_cloud`]: depth image, 3D cloud, 2D slice, noise, thinning.
//! - [`hand`], [`touch`]: the kinematic wrist and arm, the compliant finger, its readings.
//! - [`disturbance`]: per-jar displacement and tilt since reset.
//! - [`Scene`]: all of it in one rapier world, stepped by hand commands.

pub mod camera_intrinsics;
pub mod config;
pub mod cupboard;
pub mod depth_camera;
pub mod disturbance;
pub mod error;
pub mod footprint;
mod free_motion;
mod groups;
pub mod hand;
pub mod jar;
pub mod layout;
pub mod point_cloud;
pub mod ray_cast;
// The file is named for the concept it holds, like its siblings.
#[allow(clippy::module_inception)]
mod scene;
pub mod touch;
pub mod visibility;

pub use camera_intrinsics::CameraIntrinsics;
pub use config::{
    CameraConfig, CupboardConfig, HandConfig, LayoutConfig, PhysicsConfig, SceneConfig,
    TargetShape, TouchConfig,
};
pub use cupboard::{Cupboard, Wall, WallBox};
pub use depth_camera::{DepthCamera, DepthImage, LABEL_NONE};
pub use disturbance::Disturbance;
pub use error::SceneError;
pub use footprint::{Footprint, JarShape};
pub use hand::{Blocker, HandPose};
pub use jar::JarSpec;
pub use layout::{Corridor, Layout};
pub use point_cloud::{DepthCapture, SliceSpec};
pub use ray_cast::LABEL_CUPBOARD;
pub use scene::{HandCommand, JarState, Scene, StepReport};
pub use touch::Contact;
pub use visibility::{target_visibility, Visibility};
