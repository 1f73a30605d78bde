//! Episodes are deterministic, finite, solvable, and the batch equals single episodes.

mod common;
use common::observe;

use env_core::episode::{
    oracle_action, oracle_motion, Command, Episode, EpisodeBatch, EpisodeConfig, EpisodeError,
    MapMode, StepInfo, PROPRIO_LEN,
};
use env_core::settings::Checked;
use env_core::settings::SettingError;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn config(mode: MapMode) -> EpisodeConfig {
    let mut config = EpisodeConfig::default();
    config.map.mode = mode;
    config
}

fn random_actions(seed: u64, count: usize) -> Vec<[f64; 3]> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..count)
        .map(|_| [0; 3].map(|_| rng.random_range(-1.0..1.0)))
        .collect()
}

fn assert_finite(info: &StepInfo) {
    let values = [
        info.reward,
        info.reward_success,
        info.reward_step,
        info.reward_displacement,
        info.reward_tip,
        info.reward_approach,
        info.target_distance,
        info.jar_displacement,
        info.max_jar_displacement,
        info.max_tilt,
        info.iou,
    ];
    assert!(values.iter().all(|v| v.is_finite()), "{info:?}");
    let sum = info.reward_success
        + info.reward_step
        + info.reward_displacement
        + info.reward_tip
        + info.reward_approach;
    assert!((info.reward - sum).abs() < 1e-12);
}

#[test]
fn same_seed_and_actions_give_identical_observations_in_every_mode() {
    for mode in [MapMode::Gpis, MapMode::Occupancy, MapMode::None] {
        let actions = random_actions(1, 40);
        let run = || {
            let mut episode = Episode::started(Checked::new(config(mode)).unwrap(), 5).unwrap();
            let mut trace = vec![observe(&episode)];
            for &a in &actions {
                match episode.step(a) {
                    Ok(info) if !info.terminated => trace.push(observe(&episode)),
                    _ => break,
                }
            }
            trace
        };
        assert_eq!(run(), run(), "mode {mode:?}");
    }
}

#[test]
fn random_play_keeps_observations_and_rewards_finite() {
    for seed in 0..6 {
        let mut episode =
            Episode::started(Checked::new(config(MapMode::Gpis)).unwrap(), seed).unwrap();
        for (k, action) in random_actions(seed, 60).into_iter().enumerate() {
            let info = episode.step(action.map(|v| 3.0 * v)).unwrap();
            assert_finite(&info);
            assert!(info.clipped || action.iter().all(|v| v.abs() <= 1.0 / 3.0));
            let (_, proprio) = observe(&episode);
            assert!(
                proprio.iter().all(|v| v.is_finite() && v.abs() <= 1.0),
                "{k}: {proprio:?}"
            );
            if info.terminated {
                assert!(matches!(episode.step([0.0; 3]), Err(EpisodeError::Ended)));
                break;
            }
        }
    }
}

#[test]
fn the_oracle_touches_the_target_without_tipping_in_nearly_every_episode() {
    let mut successes = 0;
    let seeds: usize = 40;
    for seed in 0..seeds as u64 {
        let mut episode =
            Episode::started(Checked::new(config(MapMode::Gpis)).unwrap(), seed).unwrap();
        for _ in 0..200 {
            let info = episode.step(oracle_action(&episode)).unwrap();
            assert_finite(&info);
            if info.terminated {
                successes += usize::from(info.success && !info.tipped);
                assert!(info.reward_success > 0.0 || !info.success);
                break;
            }
        }
    }
    assert!(
        successes * 100 >= 95 * seeds,
        "{successes} of {seeds} episodes succeeded"
    );
}

#[test]
fn touch_adds_rows_to_the_map_and_the_map_tracks_the_jars() {
    let mut episode = Episode::started(Checked::new(config(MapMode::Gpis)).unwrap(), 3).unwrap();
    let prior_rows = episode.last_info().gpis_rows;
    let prior_iou = episode.last_info().iou;
    assert!(prior_rows > 0);
    let mut last = *episode.last_info();
    for _ in 0..200 {
        last = episode.step(oracle_action(&episode)).unwrap();
        if last.terminated {
            break;
        }
    }
    assert!(last.success);
    assert!(
        last.gpis_rows > prior_rows,
        "touch added rows: {prior_rows} -> {}",
        last.gpis_rows
    );
    assert!((0.0..=1.0).contains(&prior_iou) && (0.0..=1.0).contains(&last.iou));
}

#[test]
fn the_batch_equals_single_episodes_whatever_the_thread_count() {
    for mode in [MapMode::Gpis, MapMode::None] {
        let seeds = [0, 1, 2];
        for threads in [1, 2] {
            let mut singles: Vec<Episode> = seeds
                .iter()
                .map(|&s| Episode::started(Checked::new(config(mode)).unwrap(), s).unwrap())
                .collect();
            let mut batch =
                EpisodeBatch::started(Checked::new(config(mode)).unwrap(), &seeds, Some(threads))
                    .unwrap();
            let map_len = singles[0].map_len();
            let mut maps = vec![0u8; seeds.len() * map_len];
            let mut proprio = vec![0f32; seeds.len() * PROPRIO_LEN];
            for step in 0..15 {
                let actions: Vec<[f64; 3]> = singles
                    .iter()
                    .map(|e| oracle_motion(e).map(|v| 0.7 * v))
                    .collect();
                let commands: Vec<_> = actions
                    .iter()
                    .copied()
                    .map(|action| Command::Step(action.into()))
                    .collect();
                let outcome = batch.run(&commands, &mut maps, &mut proprio);
                let mut failed = false;
                for (i, episode) in singles.iter_mut().enumerate() {
                    let Ok(single) = episode.step(actions[i]) else {
                        failed = true;
                        continue;
                    };
                    let context = format!("mode {mode:?}, threads {threads}, step {step}, {i}");
                    assert_eq!(&single, batch.episodes()[i].last_info(), "{context}");
                    let (map, own) = observe(episode);
                    assert_eq!(map, maps[i * map_len..(i + 1) * map_len], "{context}");
                    assert_eq!(own, proprio[i * PROPRIO_LEN..(i + 1) * PROPRIO_LEN]);
                }
                assert_eq!(outcome.is_err(), failed);
                if failed {
                    break;
                }
            }
        }
    }
}

#[test]
fn a_batch_leaves_held_episodes_untouched_and_resets_only_those_it_is_told_to() {
    let seeds = [4, 5, 6];
    let mut batch = EpisodeBatch::started(
        Checked::new(config(MapMode::Gpis)).unwrap(),
        &seeds,
        Some(2),
    )
    .unwrap();
    let map_len = batch.map_len();
    let mut maps = vec![0u8; 3 * map_len];
    let mut proprio = vec![0f32; 3 * PROPRIO_LEN];
    batch.write_observations(&mut maps, &mut proprio).unwrap();
    let held = maps[map_len..2 * map_len].to_vec();
    let commands = [
        Command::Step([1.0, 1.0, 0.0].into()),
        Command::Hold,
        Command::Reset(9),
    ];
    batch.run(&commands, &mut maps, &mut proprio).unwrap();
    assert_eq!(batch.episodes()[0].last_info().steps, 1);
    assert_eq!(batch.episodes()[1].last_info().steps, 0);
    assert_eq!(maps[map_len..2 * map_len], held[..]);
    let fresh = Episode::started(Checked::new(config(MapMode::Gpis)).unwrap(), 9).unwrap();
    let (map, own) = observe(&fresh);
    assert_eq!(map, maps[2 * map_len..]);
    assert_eq!(own, proprio[2 * PROPRIO_LEN..]);
}

#[test]
fn a_non_finite_action_in_a_batch_moves_no_episode() {
    let mut batch = EpisodeBatch::started(
        Checked::new(config(MapMode::None)).unwrap(),
        &[1, 2],
        Some(2),
    )
    .unwrap();
    let mut proprio = vec![0f32; 2 * PROPRIO_LEN];
    let commands = [
        Command::Step([0.5, 0.5, 0.0].into()),
        Command::Step([0.0, f64::NAN, 0.0].into()),
    ];
    let error = batch.run(&commands, &mut [], &mut proprio).unwrap_err();
    assert!(
        matches!(error, EpisodeError::InEpisode { index: 1, .. }),
        "{error}"
    );
    assert!(error
        .to_string()
        .contains("episode 1: action[1] must be finite"));
    assert!(batch.episodes().iter().all(|e| e.last_info().steps == 0));
}

#[test]
fn an_episode_truncates_when_its_steps_reach_max_steps() {
    let mut short = config(MapMode::None);
    short.max_steps = 4;
    let mut episode = Episode::started(Checked::new(short).unwrap(), 2).unwrap();
    let mut flags = Vec::new();
    for _ in 0..6 {
        let info = episode.step([0.0; 3]).unwrap();
        flags.push(info.truncated);
    }
    // Stepping on after the limit is allowed (time_left floors at -1) and stays truncated.
    assert_eq!(flags, [false, false, false, true, true, true]);
    assert!(!episode.last_info().terminated);
}

#[test]
fn bad_actions_and_configs_are_refused_and_a_config_is_checked_when_made() {
    let mut episode = Episode::started(Checked::new(config(MapMode::Gpis)).unwrap(), 0).unwrap();
    assert!(matches!(
        episode.step([0.0, f64::NAN, 0.0]),
        Err(EpisodeError::NonFiniteAction { index: 1, .. })
    ));
    let mut bad = config(MapMode::Gpis);
    bad.map.grid_shape = (40, 60);
    assert!(matches!(
        Checked::new(bad),
        Err(SettingError::OutOfRange {
            key: "grid_shape",
            ..
        })
    ));
    let mut small = config(MapMode::Gpis);
    small.map.grid_shape = (20, 40);
    assert!(matches!(
        Checked::new(small),
        Err(SettingError::OutOfRange {
            key: "grid_shape",
            ..
        })
    ));
    let mut negative = config(MapMode::Gpis);
    negative.reward.step_cost = -1.0;
    assert!(matches!(
        Checked::new(negative),
        Err(SettingError::OutOfRange {
            key: "reward_step_cost",
            ..
        })
    ));
    let mut map = vec![0u8; 3];
    assert!(matches!(
        episode.write_map(&mut map),
        Err(EpisodeError::BufferLength { .. })
    ));
}

#[test]
fn an_episode_starts_at_its_first_reset_and_refuses_steps_before() {
    let checked = Checked::new(config(MapMode::Gpis)).unwrap();
    let mut episode = Episode::new(checked.clone()).unwrap();
    assert!(!episode.is_started());
    assert!(matches!(
        episode.step([0.0; 3]),
        Err(EpisodeError::NotReset)
    ));
    let mut map = vec![1u8; episode.map_len()];
    let mut proprio = vec![1f32; PROPRIO_LEN];
    episode.write_map(&mut map).unwrap();
    episode.write_proprio(&mut proprio).unwrap();
    assert!(map.iter().all(|&v| v == 0) && proprio.iter().all(|&v| v == 0.0));
    episode.reset(3).unwrap();
    let started = Episode::started(checked, 3).unwrap();
    assert_eq!(observe(&episode), observe(&started));
    episode.step([0.5, 0.5, 0.0]).unwrap();
}

#[test]
fn a_new_batch_starts_no_episode() {
    let checked = Checked::new(config(MapMode::None)).unwrap();
    let mut batch = EpisodeBatch::new(checked, 2, Some(1)).unwrap();
    assert!(batch.episodes().iter().all(|e| !e.is_started()));
    let mut proprio = vec![0f32; 2 * PROPRIO_LEN];
    let error = batch
        .run(
            &[Command::Step([0.0; 3].into()), Command::Hold],
            &mut [],
            &mut proprio,
        )
        .unwrap_err();
    assert!(error.to_string().contains("episode 0"), "{error}");
    batch
        .run(&[Command::Reset(1), Command::Hold], &mut [], &mut proprio)
        .unwrap();
    assert!(batch.episodes()[0].is_started() && !batch.episodes()[1].is_started());
}
