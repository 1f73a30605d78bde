//! The approach field (reward shaping): path distances go around other jars, vanish at the
//! target, and the shaping term telescopes to the distance covered.

use env_core::episode::approach::ApproachField;
use env_core::episode::{oracle_action, Episode, EpisodeConfig};
use env_core::gpis::GridSpec;
use env_core::scene::{Disturbance, JarShape, JarSpec, JarState};
use env_core::settings::Checked;

fn round_jar(x: f64, y: f64, radius: f64) -> JarState {
    JarState {
        spec: JarSpec {
            shape: JarShape::Round { radius },
            height: 0.1,
            mass: 0.1,
            x,
            y,
            yaw: 0.0,
        },
        position: [x, y, 0.05],
        rotation: [0.0, 0.0, 0.0, 1.0],
        disturbance: Disturbance::default(),
        asleep: false,
    }
}

fn grid() -> GridSpec {
    GridSpec::new([[-0.3, 0.3], [0.0, 0.3]], (40, 80)).unwrap()
}

#[test]
fn the_distance_vanishes_at_the_target_and_grows_with_the_straight_distance() {
    let field = ApproachField::new(&grid(), &[round_jar(0.0, 0.2, 0.03)], 0, 0.01);
    assert!(field.distance([0.0, 0.165]) < 1e-9);
    let near = field.distance([0.1, 0.2]);
    let far = field.distance([0.25, 0.2]);
    assert!((near - 0.06).abs() < 0.01, "near {near}");
    assert!((far - 0.21).abs() < 0.01, "far {far}");
    // Outside the opening the straight distance to the grid is added.
    let inside = field.distance([0.0, 0.01]);
    let outside = field.distance([0.0, -0.09]);
    assert!((outside - inside - 0.1).abs() < 0.01, "{inside} {outside}");
}

#[test]
fn the_distance_goes_around_an_occluder_but_stays_finite_inside_it() {
    let target = round_jar(0.0, 0.25, 0.03);
    let occluder = round_jar(0.0, 0.12, 0.05);
    let alone = ApproachField::new(&grid(), &[target], 0, 0.01);
    let hidden = ApproachField::new(&grid(), &[target, occluder], 0, 0.01);
    let start = [0.0, 0.0];
    assert!(
        hidden.distance(start) > alone.distance(start) + 0.02,
        "detour {} vs straight {}",
        hidden.distance(start),
        alone.distance(start)
    );
    let in_occluder = hidden.distance([0.0, 0.12]);
    assert!(in_occluder.is_finite() && in_occluder > alone.distance([0.0, 0.12]));
}

#[test]
fn the_shaping_term_telescopes_and_is_off_by_default() {
    let mut shaped = EpisodeConfig::default();
    shaped.reward.approach = 1.0;
    for seed in 0..5 {
        let mut episode = Episode::started(Checked::new(shaped.clone()).unwrap(), seed).unwrap();
        let mut plain =
            Episode::started(Checked::new(EpisodeConfig::default()).unwrap(), seed).unwrap();
        let start = episode.last_info().target_distance;
        assert!(start > 0.1, "seed {seed}: start distance {start}");
        let mut total = 0.0;
        for _ in 0..200 {
            let action = oracle_action(&episode);
            let info = episode.step(action).unwrap();
            let plain_info = plain.step(action).unwrap();
            assert_eq!(plain_info.reward_approach, 0.0);
            assert!((info.reward - info.reward_approach - plain_info.reward).abs() < 1e-12);
            total += info.reward_approach;
            if info.terminated {
                assert!(info.success, "seed {seed}");
                assert!(
                    info.target_distance < 0.03,
                    "seed {seed}: touching at {}",
                    info.target_distance
                );
                assert!((total - (start - info.target_distance)).abs() < 1e-9);
                break;
            }
        }
    }
}
