//! The identify task: a touch of the target ends nothing and pays nothing; a claim names the
//! jar the finger touches and ends the episode, a success if it is the target and a failure
//! otherwise (another jar, or none), in both action modes; the info keeps the target secret
//! until the claim; settings that cannot tell the target apart (a shape shared, no hidden
//! decoy) are refused; and a claim is refused in the search task.

use env_core::episode::{
    oracle_motion, Action, ActionMode, Episode, EpisodeConfig, EpisodeError, StepInfo, Task,
};
use env_core::scene::TargetShape;
use env_core::settings::{Checked, SettingError};

fn identify(action_mode: ActionMode) -> EpisodeConfig {
    let mut config = EpisodeConfig {
        task: Task::Identify,
        action_mode,
        ..EpisodeConfig::default()
    };
    let layout = &mut config.scene.layout;
    layout.target_shape = TargetShape::Square;
    layout.round_fraction = 1.0;
    layout.hidden_decoys = 1;
    layout.jar_count = [4, 7];
    config
}

fn started(config: EpisodeConfig, seed: u64) -> Episode {
    Episode::started(Checked::new(config).unwrap(), seed).unwrap()
}

/// Follows the oracle's wrist motions until the finger touches the target; the infos of the
/// steps taken. Panics if it never does.
fn touch_target(episode: &mut Episode) -> Vec<StepInfo> {
    let target = episode.scene().target();
    let mut infos = Vec::new();
    for _ in 0..episode.config().max_steps {
        infos.push(episode.step(oracle_motion(episode)).unwrap());
        if episode.touched_jar() == Some(target) {
            return infos;
        }
    }
    panic!("the oracle never touched the target");
}

#[test]
fn a_touch_of_the_target_alone_does_not_end_or_pay() {
    for seed in 0..4 {
        let mut episode = started(identify(ActionMode::Wrist), seed);
        let mut infos = touch_target(&mut episode);
        // Pressing on while touching it changes nothing either.
        for _ in 0..3 {
            infos.push(episode.step(oracle_motion(&episode)).unwrap());
        }
        for info in &infos {
            assert!(!info.terminated && !info.success, "seed {seed}: {info:?}");
            assert_eq!(info.reward_success, 0.0);
            assert_eq!(info.claimed_jar, None);
            // The info keeps the target secret.
            assert_eq!(info.target_distance, 0.0);
        }
    }
}

#[test]
fn a_claim_on_the_target_succeeds_and_ends_the_episode() {
    for seed in 0..4 {
        let mut episode = started(identify(ActionMode::Wrist), seed);
        touch_target(&mut episode);
        let steps = episode.last_info().steps;
        let info = episode.step(Action::Claim).unwrap();
        assert!(
            info.success && info.terminated && !info.wrong_claim,
            "seed {seed}"
        );
        assert_eq!(info.claimed_jar, Some(episode.scene().target()));
        assert_eq!(info.reward, episode.config().reward.success);
        // A claim is no motion and no step of the time limit.
        assert_eq!((info.motions, info.steps), (0, steps));
        assert_eq!(
            episode.step(Action::Claim).unwrap_err(),
            EpisodeError::Ended
        );
    }
}

#[test]
fn a_claim_with_nothing_touched_fails_and_ends_the_episode() {
    for mode in [ActionMode::Wrist, ActionMode::Probe] {
        let mut episode = started(identify(mode), 7);
        let info = episode.step(Action::Claim).unwrap();
        assert!(info.wrong_claim && info.terminated && !info.success);
        assert_eq!(info.claimed_jar, None);
        assert_eq!(info.reward, -episode.config().reward.wrong_claim);
        assert_eq!(info.reward_wrong_claim, info.reward);
    }
}

/// Every probe (at a middle sweep) of the first seeds, each from a fresh episode, until
/// one ends touching a jar for which `wanted(touched, target)` holds; the episode then.
fn probe_until(wanted: impl Fn(usize, usize) -> bool) -> Episode {
    let config = identify(ActionMode::Probe);
    let [lanes, depths, sweeps] = config.probe.counts();
    for seed in 0..4 {
        for lane in 0..lanes {
            for depth in (0..depths).rev() {
                let mut episode = started(config.clone(), seed);
                let probe = [lane as i64, depth as i64, (sweeps / 2) as i64];
                let info = episode.step(probe).unwrap();
                assert!(!info.terminated || info.tipped);
                if let Some(touched) = episode.touched_jar() {
                    if wanted(touched, episode.scene().target()) && !info.terminated {
                        return episode;
                    }
                }
            }
        }
    }
    panic!("no probe of the first seeds touched such a jar");
}

#[test]
fn in_the_probe_mode_a_claim_names_the_touched_jar() {
    let mut on_target = probe_until(|touched, target| touched == target);
    let info = on_target.step(Action::Claim).unwrap();
    assert!(info.success && info.terminated);

    let mut on_decoy = probe_until(|touched, target| touched != target);
    let touched = on_decoy.touched_jar();
    let info = on_decoy.step(Action::Claim).unwrap();
    assert!(info.wrong_claim && info.terminated && !info.success);
    assert_eq!(info.claimed_jar, touched);
    assert_eq!(info.reward, -on_decoy.config().reward.wrong_claim);
}

#[test]
fn a_claim_in_the_search_task_is_refused() {
    let mut episode = started(EpisodeConfig::default(), 0);
    assert_eq!(
        episode.step(Action::Claim).unwrap_err(),
        EpisodeError::ClaimOutsideIdentify { task: "search" }
    );
}

#[test]
fn identify_settings_that_cannot_name_the_target_are_refused() {
    let mut any_shape = identify(ActionMode::Wrist);
    any_shape.scene.layout.target_shape = TargetShape::Any;
    let error = Checked::new(any_shape).unwrap_err();
    assert!(matches!(
        &error,
        SettingError::OutOfRange {
            key: "target_shape",
            ..
        }
    ));

    let mut no_decoy = identify(ActionMode::Wrist);
    no_decoy.scene.layout.hidden_decoys = 0;
    let error = Checked::new(no_decoy).unwrap_err();
    assert!(matches!(
        &error,
        SettingError::OutOfRange {
            key: "hidden_decoys",
            ..
        }
    ));

    let mut mixed = identify(ActionMode::Wrist);
    mixed.scene.layout.round_fraction = 0.5;
    let error = Checked::new(mixed).unwrap_err();
    assert!(matches!(
        &error,
        SettingError::OutOfRange {
            key: "round_fraction",
            ..
        }
    ));
    assert!(error.to_string().contains("identify"), "{error}");
}
