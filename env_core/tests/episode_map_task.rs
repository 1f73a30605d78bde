//! The map task: its score matches an independent reference on a hand-made scene, it is
//! the same whatever map the agent observes, its reward is the outline distance's shrink,
//! touches shrink it, and the episode ends only by a tip or the time limit.

use env_core::episode::map_score::{score_iou, score_outline};
use env_core::episode::{oracle_motion, Episode, EpisodeConfig, MapMode, StepInfo, Task};
use env_core::gpis::GridSpec;
use env_core::scene::{Footprint, JarShape};
use env_core::settings::Checked;

fn map_task(map: MapMode) -> EpisodeConfig {
    let mut config = EpisodeConfig {
        task: Task::Map,
        max_steps: 60,
        ..EpisodeConfig::default()
    };
    config.map.mode = map;
    config
}

/// Signed distance to a circle: a reconstruction's mean field made by hand.
fn circle_field(grid: &GridSpec, centre: [f64; 2], radius: f64) -> Vec<f64> {
    grid.cell_centres()
        .iter()
        .map(|p| (p[0] - centre[0]).hypot(p[1] - centre[1]) - radius)
        .collect()
}

#[test]
fn the_score_of_a_hand_made_scene_matches_an_independent_reference() {
    // A round jar of radius 25 mm; the reconstruction a circle of 31 mm around its centre.
    let grid = GridSpec::new([[-0.3, 0.3], [0.0, 0.3]], (150, 300)).unwrap();
    let centre = [0.05, 0.12];
    let jar = Footprint {
        shape: JarShape::Round { radius: 0.025 },
        centre,
        yaw: 0.0,
    };
    let mean = circle_field(&grid, centre, 0.031);
    // The reference IoU counts cells by hand: inside the jar over inside the estimate.
    let cells = grid.cell_centres();
    let inside = |p: &[f64; 2], r: f64| (p[0] - centre[0]).hypot(p[1] - centre[1]) < r;
    let truth: Vec<bool> = cells.iter().map(|p| inside(p, 0.025)).collect();
    let both = cells.iter().filter(|p| inside(p, 0.025)).count() as f64;
    let either = cells.iter().filter(|p| inside(p, 0.031)).count() as f64;
    assert!((score_iou(&mean, &truth) - both / either).abs() < 1e-12);
    // Its area ratio is (25 / 31)^2, up to the grid's 2 mm cells.
    assert!((score_iou(&mean, &truth) - (25.0f64 / 31.0).powi(2)).abs() < 0.03);
    // Both outlines are 6 mm apart everywhere, in both directions.
    let distance = score_outline(&grid, &mean, &[jar]);
    assert!((distance - 0.006).abs() < 3e-4, "{distance}");
}

/// The map task's scores along an episode of `map`'s agent making the oracle's motions
/// (the motions do not depend on the map).
fn scores(map: MapMode, seed: u64) -> Vec<StepInfo> {
    let mut episode = Episode::started(Checked::new(map_task(map)).unwrap(), seed).unwrap();
    let mut infos = vec![*episode.last_info()];
    while !(infos.last().unwrap().terminated || infos.last().unwrap().truncated) {
        infos.push(episode.step(oracle_motion(&episode)).unwrap());
    }
    infos
}

#[test]
fn the_score_is_the_same_whatever_map_the_agent_observes() {
    let gpis = scores(MapMode::Gpis, 3);
    for map in [MapMode::Occupancy, MapMode::None] {
        let other = scores(map, 3);
        assert_eq!(gpis.len(), other.len());
        for (a, b) in gpis.iter().zip(&other) {
            assert_eq!(
                (
                    a.map_score_iou,
                    a.map_score_mm,
                    a.map_score_area,
                    a.reward_map
                ),
                (
                    b.map_score_iou,
                    b.map_score_mm,
                    b.map_score_area,
                    b.reward_map
                ),
                "{map:?}"
            );
        }
    }
}

#[test]
fn the_reward_is_the_outline_distances_shrink_and_touches_shrink_it() {
    let (mut before, mut after) = (0.0, 0.0);
    for seed in 0..8 {
        let infos = scores(MapMode::None, seed);
        let (first, last) = (infos[0], *infos.last().unwrap());
        let paid: f64 = infos[1..].iter().map(|i| i.reward_map).sum();
        assert!((paid - 0.1 * (first.map_score_mm - last.map_score_mm)).abs() < 1e-9);
        assert!(infos.iter().any(|i| i.contacts > 0), "seed {seed}");
        assert!(first.map_score_mm > 0.0 && first.map_score_iou > 0.0);
        (before, after) = (before + first.map_score_mm, after + last.map_score_mm);
        // At the end the area is the mean distance over the budget's motions.
        let motions: usize = infos[1..].iter().map(|i| i.motions).sum();
        let sum: f64 = infos[1..]
            .iter()
            .map(|i| i.map_score_mm * i.motions as f64)
            .sum();
        let rest = (60 - motions) as f64 * last.map_score_mm;
        assert!((last.map_score_area - (sum + rest) / 60.0).abs() < 1e-9);
        // No success, no claim: the budget ends it (or a tip).
        assert!(infos.iter().all(|i| !i.success && !i.wrong_claim));
        assert!(last.truncated || last.tipped);
        assert_eq!(last.target_distance, 0.0);
    }
    // The oracle's path touches jars near the target, and on the whole the reconstruction's
    // outlines come nearer the true ones.
    assert!(
        after < before,
        "{before} mm -> {after} mm (summed over seeds)"
    );
}

#[test]
fn other_tasks_report_no_map_score() {
    let config = EpisodeConfig {
        max_steps: 5,
        ..EpisodeConfig::default()
    };
    let mut episode = Episode::started(Checked::new(config).unwrap(), 1).unwrap();
    let info = episode.step([0.0, 1.0, 0.0]).unwrap();
    assert_eq!(
        (
            info.map_score_iou,
            info.map_score_mm,
            info.map_score_area,
            info.reward_map
        ),
        (0.0, 0.0, 0.0, 0.0)
    );
}
