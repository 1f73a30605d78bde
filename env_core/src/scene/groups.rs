//! Collision groups: who touches whom. The finger and the wrist/arm never collide with each
//! other; the depth camera sees only the cupboard and the jars (it takes its picture before
//! the hand reaches in, as in the paper, so the hand never occludes it).

use rapier3d::prelude::{Group, InteractionGroups, InteractionTestMode};

/// Membership bit of the cupboard walls.
pub(crate) const CUPBOARD_BIT: Group = Group::GROUP_1;
/// Membership bit of the jars.
pub(crate) const JAR_BIT: Group = Group::GROUP_2;
/// Membership bit of the wrist and arm.
pub(crate) const HAND_BIT: Group = Group::GROUP_3;
/// Membership bit of the finger.
pub(crate) const FINGER_BIT: Group = Group::GROUP_4;

/// The walls meet jars, hand and finger.
pub(crate) const CUPBOARD: InteractionGroups = InteractionGroups::new(
    CUPBOARD_BIT,
    JAR_BIT.union(HAND_BIT).union(FINGER_BIT),
    InteractionTestMode::And,
);
/// Jars meet everything.
pub(crate) const JAR: InteractionGroups =
    InteractionGroups::new(JAR_BIT, Group::ALL, InteractionTestMode::And);
/// Wrist and arm meet walls and jars, not the finger.
pub(crate) const HAND: InteractionGroups = InteractionGroups::new(
    HAND_BIT,
    CUPBOARD_BIT.union(JAR_BIT),
    InteractionTestMode::And,
);
/// The finger meets walls and jars, not the wrist and arm.
pub(crate) const FINGER: InteractionGroups = InteractionGroups::new(
    FINGER_BIT,
    CUPBOARD_BIT.union(JAR_BIT),
    InteractionTestMode::And,
);
/// What the depth camera's rays see: walls and jars.
pub(crate) const CAMERA_VIEW: InteractionGroups = InteractionGroups::new(
    Group::ALL,
    CUPBOARD_BIT.union(JAR_BIT),
    InteractionTestMode::And,
);
