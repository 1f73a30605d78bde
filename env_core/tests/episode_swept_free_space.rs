//! `swept_free_space`: where the finger passed without touching becomes free evidence in the
//! map (GPIS value rows, occupancy free cells); off (v0), the map does not change.

use env_core::episode::{Episode, EpisodeConfig, MapMode};
use env_core::settings::Checked;

fn config(mode: MapMode, swept: Option<f64>) -> EpisodeConfig {
    let mut config = EpisodeConfig::default();
    config.map.mode = mode;
    config.map.swept_free_space = swept;
    config
}

/// The lane (x) farthest from every jar's centre, over lanes the wrist fits in.
fn clear_lane(episode: &Episode) -> f64 {
    let jars = episode.scene().jar_states();
    (-25..=25)
        .map(|k| f64::from(k) * 0.01)
        .max_by(|&a, &b| {
            let gap = |x: f64| {
                jars.iter()
                    .map(|j| (j.position[0] - x).abs())
                    .fold(f64::INFINITY, f64::min)
            };
            gap(a).total_cmp(&gap(b))
        })
        .unwrap()
}

/// Moves to `lane` outside the cupboard, then straight in `depth_steps` steps.
fn go_in(episode: &mut Episode, lane: f64, depth_steps: usize) -> usize {
    let step = episode.config().scene.hand.max_step_translation;
    let mut rows = 0;
    while (episode.scene().hand_pose().x - lane).abs() > 1e-9 {
        let dx = ((lane - episode.scene().hand_pose().x) / step).clamp(-1.0, 1.0);
        rows += episode.step([dx, 0.0, 0.0]).unwrap().rows_added;
    }
    for _ in 0..depth_steps {
        let info = episode.step([0.0, 1.0, 0.0]).unwrap();
        assert_eq!(info.contacts, 0, "the lane was meant to be clear");
        rows += info.rows_added;
    }
    rows
}

fn cell_of(episode: &Episode, p: [f64; 2]) -> usize {
    let grid = episode.grid();
    let [[x0, x1], [y0, y1]] = grid.bounds();
    let (h, w) = grid.shape();
    let j = ((p[0] - x0) / (x1 - x0) * w as f64) as usize;
    let i = ((p[1] - y0) / (y1 - y0) * h as f64) as usize;
    i * w + j
}

#[test]
fn a_clear_pass_of_the_finger_lowers_the_gpis_variance_where_it_went() {
    for seed in 0..3u64 {
        let mut with = Episode::started(
            Checked::new(config(MapMode::Gpis, Some(0.01))).unwrap(),
            seed,
        )
        .unwrap();
        let mut without =
            Episode::started(Checked::new(config(MapMode::Gpis, None)).unwrap(), seed).unwrap();
        let lane = clear_lane(&with);
        let added = go_in(&mut with, lane, 16);
        assert_eq!(
            go_in(&mut without, lane, 16),
            0,
            "seed {seed}: v0 added rows"
        );
        assert!(added > 0, "seed {seed}: no swept rows");
        // Halfway along the pass (well inside the cupboard, 6 cm deep).
        let cell = cell_of(&with, [lane, 0.06]);
        let (v_with, v_without) = (
            with.gpis().unwrap().variance_grid()[cell],
            without.gpis().unwrap().variance_grid()[cell],
        );
        assert!(
            v_with < 0.5 * v_without,
            "seed {seed}: {v_with} vs {v_without}"
        );
        assert!(
            with.gpis().unwrap().mean_grid()[cell] > 0.0,
            "seed {seed}: not free"
        );
    }
}

#[test]
fn a_clear_pass_marks_the_occupancy_cells_free() {
    let mut with = Episode::started(
        Checked::new(config(MapMode::Occupancy, Some(0.01))).unwrap(),
        1,
    )
    .unwrap();
    let mut without =
        Episode::started(Checked::new(config(MapMode::Occupancy, None)).unwrap(), 1).unwrap();
    let lane = clear_lane(&with);
    go_in(&mut with, lane, 16);
    go_in(&mut without, lane, 16);
    let cell = cell_of(&with, [lane, 0.06]);
    let (p_with, p_without) = (
        with.occupancy().unwrap().probability(cell),
        without.occupancy().unwrap().probability(cell),
    );
    assert!(p_with < p_without, "{p_with} vs {p_without}");
}

#[test]
fn going_over_the_same_free_space_again_adds_few_rows() {
    let mut episode =
        Episode::started(Checked::new(config(MapMode::Gpis, Some(0.01))).unwrap(), 2).unwrap();
    let lane = clear_lane(&episode);
    let first = go_in(&mut episode, lane, 12);
    assert!(first > 0);
    let mut again = 0;
    for _ in 0..12 {
        again += episode.step([0.0, -1.0, 0.0]).unwrap().rows_added;
    }
    // Skipped where the map is already certain (the finger's tip sways a little, so not
    // every point lands on an earlier one).
    assert!(
        4 * again <= first,
        "{again} rows on the way back, {first} on the way in"
    );
}
