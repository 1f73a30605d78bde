//! Walls stop the hand: commands that would drive the wrist, arm or finger into a cupboard wall
//! (or the wrist out of its workspace) stop at the last clear pose, are reported, and do not
//! leave the hand stuck; oversize commands are clipped; non-finite ones are refused.

mod common;

use env_core::scene::{
    Blocker, HandCommand, JarShape, Layout, Scene, SceneConfig, SceneError, Wall,
};
use env_core::settings::Checked;

/// One jar tucked in the back-left corner, out of the way.
fn open_scene() -> Scene {
    let jar = common::test_jar(JarShape::Round { radius: 0.025 }, -0.26, 0.26, 0.0);
    let layout = Layout::lone_jar(jar);
    Scene::from_layout(&Checked::new(SceneConfig::default()).unwrap(), layout, 0)
        .expect("scene builds")
}

fn push(scene: &mut Scene, command: HandCommand, steps: usize) -> Option<Blocker> {
    let mut last = None;
    for _ in 0..steps {
        last = scene
            .step(command)
            .expect("finite command")
            .blocked
            .or(last);
    }
    last
}

#[test]
fn the_side_wall_stops_the_wrist_at_its_margin_and_lets_it_back_out() {
    let mut scene = open_scene();
    let config = scene.config().hand.clone();
    assert_eq!(
        push(
            &mut scene,
            HandCommand {
                dy: 0.01,
                ..Default::default()
            },
            16
        ),
        None
    );
    assert!(
        scene.hand_pose().y > config.wrist_half_extent,
        "wrist inside the cupboard"
    );
    let blocked = push(
        &mut scene,
        HandCommand {
            dx: 0.01,
            ..Default::default()
        },
        40,
    );
    assert_eq!(blocked, Some(Blocker::Wall(Wall::Right)));
    let face = scene.hand_pose().x + config.wrist_half_extent;
    let wall = 0.5 * scene.cupboard().width();
    assert!(
        face <= wall - config.wall_margin + 1e-9,
        "wrist face at {face}"
    );
    assert!(
        face >= wall - config.wall_margin - 1e-4,
        "stopped early, at {face}"
    );
    // Pushing again does not move it; backing out does.
    let x = scene.hand_pose().x;
    let report = scene
        .step(HandCommand {
            dx: 0.01,
            ..Default::default()
        })
        .expect("finite");
    assert_eq!(report.blocked, Some(Blocker::Wall(Wall::Right)));
    assert_eq!(scene.hand_pose().x, x);
    let report = scene
        .step(HandCommand {
            dx: -0.01,
            ..Default::default()
        })
        .expect("finite");
    assert_eq!(report.blocked, None);
    assert!((report.moved.dx + 0.01).abs() < 1e-12);
}

#[test]
fn the_back_wall_stops_the_finger_before_it_jams() {
    let mut scene = open_scene();
    let config = scene.config().hand.clone();
    let blocked = push(
        &mut scene,
        HandCommand {
            dy: 0.01,
            ..Default::default()
        },
        60,
    );
    assert_eq!(blocked, Some(Blocker::Wall(Wall::Back)));
    let tip = scene.hand_pose().y + config.wrist_half_extent + 0.002 + config.finger_length;
    let back = scene.cupboard().depth();
    assert!(
        tip <= back - config.wall_margin + 1e-4,
        "finger tip at {tip}"
    );
    assert!(
        tip >= back - config.wall_margin - 2e-3,
        "stopped early, tip at {tip}"
    );
}

#[test]
fn turning_stops_when_the_arm_meets_the_side_wall() {
    let mut scene = open_scene();
    push(
        &mut scene,
        HandCommand {
            dy: 0.01,
            ..Default::default()
        },
        22,
    );
    let y = scene.hand_pose().y;
    assert!((y - 0.095).abs() < 1e-9, "wrist y {y}");
    let blocked = push(
        &mut scene,
        HandCommand {
            dyaw: 0.1,
            ..Default::default()
        },
        20,
    );
    assert_eq!(blocked, Some(Blocker::Wall(Wall::Right)));
    // The arm leaves through the opening: its edge reaches the right wall where it crosses
    // y = 0, at a yaw just short of atan((W/2) / y).
    let yaw = scene.hand_pose().yaw;
    let limit = (0.5 * scene.cupboard().width() / y).atan();
    assert!(yaw < limit && yaw > limit - 0.2, "yaw {yaw}, limit {limit}");
}

#[test]
fn the_workspace_bounds_the_wrist_and_commands_are_clipped() {
    let mut scene = open_scene();
    let config = scene.config().hand.clone();
    let report = scene
        .step(HandCommand {
            dx: 1.0,
            dy: -1.0,
            dyaw: 5.0,
        })
        .expect("finite");
    assert!(report.clipped);
    assert_eq!(report.commanded.dx, config.max_step_translation);
    assert_eq!(report.commanded.dy, -config.max_step_translation);
    assert_eq!(report.commanded.dyaw, config.max_step_yaw);
    let blocked = push(
        &mut scene,
        HandCommand {
            dy: -0.01,
            ..Default::default()
        },
        40,
    );
    assert_eq!(blocked, Some(Blocker::Workspace));
    assert!(scene.hand_pose().y >= config.workspace[1][0]);
    for (dx, dy, dyaw) in [
        (f64::NAN, 0.0, 0.0),
        (0.0, f64::INFINITY, 0.0),
        (0.0, 0.0, f64::NAN),
    ] {
        let error = scene
            .step(HandCommand { dx, dy, dyaw })
            .expect_err("refused");
        assert!(
            matches!(error, SceneError::NonFiniteCommand { .. }),
            "{error}"
        );
    }
}
