//! The `probe` action mode: a probe is exactly its controller's wrist motions, it stops
//! where it says it does, bad indices move nothing, and the `wrist` mode (v0) is the
//! default.

mod common;
use common::observe;

use env_core::episode::metrics::{footprint_mask, interior_iou};
use env_core::episode::probe::{Phase, ProbeController};
use env_core::episode::ActionMode;
use env_core::episode::{Command, Episode, EpisodeBatch, EpisodeConfig, EpisodeError, MapMode};
use env_core::episode::{StepInfo, PROPRIO_LEN};
use env_core::settings::Checked;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn config(map: MapMode, action_mode: ActionMode) -> EpisodeConfig {
    let mut config = EpisodeConfig::default();
    config.map.mode = map;
    config.action_mode = action_mode;
    config
}

fn controller(config: &EpisodeConfig) -> ProbeController {
    let cupboard = &config.scene.cupboard;
    ProbeController::new(
        &config.probe,
        &config.scene.hand,
        cupboard.width,
        cupboard.depth,
    )
}

fn random_probe(rng: &mut ChaCha8Rng, counts: [usize; 3]) -> [i64; 3] {
    counts.map(|n| rng.random_range(0..n) as i64)
}

#[test]
fn a_probe_is_exactly_its_controllers_wrist_motions_and_stops_by_its_rules() {
    for map in [MapMode::Gpis, MapMode::None] {
        for seed in 0..4u64 {
            let probe_config = config(map, ActionMode::Probe);
            let control = controller(&probe_config);
            let counts = probe_config.probe.counts();
            let mut probing = Episode::started(Checked::new(probe_config).unwrap(), seed).unwrap();
            let mut moving =
                Episode::started(Checked::new(config(map, ActionMode::Wrist)).unwrap(), seed)
                    .unwrap();
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            loop {
                let action = random_probe(&mut rng, counts);
                let info = probing.step(action).unwrap();
                assert!(info.motions >= 1);
                // The same motions, one wrist step each, from the controller.
                let probe = control.probe(&action);
                let mut summed = StepInfo::default();
                let mut phases = Vec::new();
                let mut touching = !moving.scene().contacts().is_empty();
                let mut stop_reason = None;
                let mut motions = Vec::new();
                for _ in 0..info.motions {
                    let (phase, motion) = control.next_motion(moving.scene().hand_pose(), &probe);
                    phases.push(phase);
                    // Never a motion that presses on while the finger touches (a wait instead).
                    let waits = phase == Phase::Done || (touching && phase.presses(&motion));
                    let motion = if waits { [0.0; 3] } else { motion };
                    motions.push(motion.map(|v| v.clamp(-1.0, 1.0)));
                    let step = moving.step(motion).unwrap();
                    touching = step.contacts > 0;
                    // A reason to stop holds only at the probe's last motion.
                    assert_eq!(stop_reason, None, "map {map:?} seed {seed}: {phases:?}");
                    if waits {
                        stop_reason = Some("waited");
                    } else if touching && phase.presses(&motion) {
                        stop_reason = Some("pressed on a touch");
                    }
                    summed.reward += step.reward;
                    summed.reward_step += step.reward_step;
                    summed.contacts += step.contacts;
                }
                assert!(
                    stop_reason != Some("waited") || info.motions == 1,
                    "map {map:?} seed {seed}: a wait is a probe's only motion"
                );
                assert_eq!(
                    observe(&probing),
                    observe(&moving),
                    "map {map:?} seed {seed}"
                );
                // The probe reports the motions it made: a wrist-mode replay of them.
                assert_eq!(
                    probing.last_motions(),
                    &motions[..],
                    "map {map:?} seed {seed}"
                );
                assert_eq!(moving.last_motions(), &motions[motions.len() - 1..]);
                assert!((info.reward - summed.reward).abs() < 1e-9);
                assert!((info.reward_step - summed.reward_step).abs() < 1e-12);
                assert_eq!(info.contacts, summed.contacts);
                assert_eq!(info.steps, moving.last_info().steps);
                // The rest is the last motion's: the IoU too, which a probe computes once,
                // after its last motion, and the wrist replay after every motion.
                let last = moving.last_info();
                assert_eq!(
                    info.iou.to_bits(),
                    last.iou.to_bits(),
                    "map {map:?} seed {seed}"
                );
                assert_eq!(info.target_distance, last.target_distance);
                assert_eq!(info.jar_displacement, last.jar_displacement);
                assert_eq!(info.gpis_rows, last.gpis_rows);
                assert_eq!(probing.last_info().iou.to_bits(), info.iou.to_bits());
                // And it is the map's IoU with where the jars are now, from scratch.
                if let Some(gpis) = probing.gpis() {
                    let mut truth = Vec::new();
                    footprint_mask(probing.grid(), &probing.scene().jar_states(), &mut truth);
                    let now = interior_iou(gpis.mean_grid(), &truth);
                    assert_eq!(info.iou.to_bits(), now.to_bits(), "map {map:?} seed {seed}");
                }
                // Why it stopped: arrived, ended, blocked, a touch after pressing on, or the
                // next motion would press on a touch.
                let (now, next) = control.next_motion(moving.scene().hand_pose(), &probe);
                assert!(
                    now == Phase::Done
                        || info.terminated
                        || info.truncated
                        || info.blocked
                        || stop_reason.is_some()
                        || (touching && now.presses(&next)),
                    "map {map:?} seed {seed}: stopped in {phases:?} with {info:?}"
                );
                if info.terminated || info.truncated {
                    break;
                }
            }
        }
    }
}

#[test]
fn a_probe_into_a_jar_stops_at_the_touch_and_a_deeper_one_does_not_push_it() {
    let probe_config = config(MapMode::Gpis, ActionMode::Probe);
    let control = controller(&probe_config);
    let [lanes, depths, sweeps] = probe_config.probe.counts();
    let mut stopped_early = 0;
    for seed in 0..6u64 {
        let mut episode =
            Episode::started(Checked::new(probe_config.clone()).unwrap(), seed).unwrap();
        // The lane nearest the jar closest to the opening, straight in to the deepest depth.
        let front = episode
            .scene()
            .jar_states()
            .into_iter()
            .min_by(|a, b| a.position[1].total_cmp(&b.position[1]))
            .unwrap();
        let lane = (0..lanes)
            .min_by(|&a, &b| {
                let x = |i: usize| (control.probe(&[i as i64, 0, 0]).x - front.position[0]).abs();
                x(a).total_cmp(&x(b))
            })
            .unwrap();
        let action = [lane as i64, (depths - 1) as i64, (sweeps / 2) as i64];
        let info = episode.step(action).unwrap();
        let goal = control.probe(&action);
        if info.contacts > 0 && episode.scene().hand_pose().y < goal.y - 1e-6 {
            stopped_early += 1;
        }
        assert!(
            !info.tipped,
            "seed {seed}: a probe stopped at the touch tipped a jar"
        );
    }
    assert!(
        stopped_early >= 5,
        "only {stopped_early} of 6 probes stopped at the touch"
    );
}

#[test]
fn probe_indices_out_of_their_counts_move_no_episode_of_a_batch() {
    let mut batch = EpisodeBatch::started(
        Checked::new(config(MapMode::None, ActionMode::Probe)).unwrap(),
        &[1, 2],
        Some(2),
    )
    .unwrap();
    let mut proprio = vec![0f32; 2 * PROPRIO_LEN];
    for (bad, message) in [
        ([3, 29, 0], "action[1] must be an integer from 0 to 9"),
        ([3, 1, 9], "action[2] must be an integer from 0 to 8"),
        ([-1, 1, 0], "action[0] must be an integer from 0 to 28"),
    ] {
        let commands = [
            Command::Step([14i64, 5, 4].into()),
            Command::Step(bad.into()),
        ];
        let error = batch.run(&commands, &mut [], &mut proprio).unwrap_err();
        assert!(
            matches!(error, EpisodeError::InEpisode { index: 1, .. }),
            "{error}"
        );
        assert!(error.to_string().contains(message), "{error}");
        assert!(batch.episodes().iter().all(|e| e.last_info().steps == 0));
    }
}

#[test]
fn the_wrist_mode_is_the_default_and_a_step_is_one_motion() {
    let default = EpisodeConfig::default();
    assert_eq!(default.action_mode, ActionMode::Wrist);
    let mut episode = Episode::started(Checked::new(default).unwrap(), 3).unwrap();
    assert_eq!(episode.last_info().motions, 0);
    assert!(episode.last_motions().is_empty());
    // Fractional wrist actions stay valid: the probe indices' check is the probe mode's.
    let info = episode.step([0.25, 0.5, -0.125]).unwrap();
    assert_eq!((info.motions, info.steps), (1, 1));
    // The one motion, clipped as it was applied; a reset forgets it.
    episode.step([2.0, -0.5, 0.0]).unwrap();
    assert_eq!(episode.last_motions(), &[[1.0, -0.5, 0.0]]);
    episode.reset(4).unwrap();
    assert!(episode.last_motions().is_empty());
}
