//! The fast path of free motion (`fast_free_motion`): hand commands that provably touch
//! nothing are made without stepping the physics. It is deterministic, it is taken (most
//! free motions of random probes), and where neither episode's probe touched anything or
//! moved a jar, the fast episode's probe reports the same: motions, readings (none),
//! rewards, success and tips, the wrist pose bit for bit, the map image bit for bit (when no
//! wall stopped the hand: the stop depends on the finger's deflection).
//!
//! Not bit-exact, by design: the stepped wrist starts and stops with a jump in velocity,
//! which swings the compliant finger in free space (up to ~0.17 rad measured); the fast path
//! carries it undeflected. So the proprio's deflection entry may differ, by at most
//! `MAX_DEFLECTION_GAP` here, and so may the fingertip (`target_distance`), while the probes
//! agree; once a probe of either episode touches or moves a jar, the two may part (the
//! swinging or the still finger meets a jar the other misses, near jars both are stepped)
//! and the comparison of that episode stops.

mod common;
use common::observe;

use env_core::episode::ActionMode;
use env_core::episode::{Episode, EpisodeConfig, MapMode, StepInfo};
use env_core::scene::HandPose;
use env_core::settings::Checked;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Largest difference of the finger's deflection (rad) between the two episodes while their
/// probes agree: the stepped finger's free swing (measured up to ~0.17 rad) plus slack.
const MAX_DEFLECTION_GAP: f64 = 0.25;

fn config(map: MapMode, fast: bool) -> EpisodeConfig {
    let mut config = EpisodeConfig::default();
    config.map.mode = map;
    config.action_mode = ActionMode::Probe;
    config.scene.physics.fast_free_motion = fast;
    config
}

fn random_probe(rng: &mut ChaCha8Rng, counts: [usize; 3]) -> [i64; 3] {
    counts.map(|n| rng.random_range(0..n) as i64)
}

fn pose_bits(pose: HandPose) -> [u64; 3] {
    [pose.x.to_bits(), pose.y.to_bits(), pose.yaw.to_bits()]
}

/// What a probe reports that must not depend on the fast path where the path was clear.
fn outcome(info: &StepInfo) -> (usize, usize, bool, bool, usize, bool, usize) {
    (
        info.motions,
        info.contacts,
        info.success,
        info.tipped,
        info.steps,
        info.blocked,
        info.rows_added,
    )
}

#[test]
fn the_fast_path_is_deterministic() {
    for seed in [1_000_000u64, 1_000_001] {
        let run = || {
            let mut episode =
                Episode::started(Checked::new(config(MapMode::Gpis, true)).unwrap(), seed).unwrap();
            let counts = episode.config().probe.counts();
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            let mut trace = Vec::new();
            for _ in 0..12 {
                let info = episode.step(random_probe(&mut rng, counts)).unwrap();
                trace.push((
                    observe(&episode),
                    episode.scene().state_vector(),
                    info.reward,
                ));
                if info.terminated || info.truncated {
                    break;
                }
            }
            (trace, episode.scene().free_motions())
        };
        let (first, fast) = run();
        assert!(fast > 0, "seed {seed}: no motion took the fast path");
        assert!(first == run().0, "seed {seed}: two runs differ");
    }
}

#[test]
fn probes_that_touch_nothing_report_the_same_with_and_without_the_fast_path() {
    let (mut compared, mut agreed, mut fast_motions, mut motions) = (0, 0, 0u64, 0u64);
    let mut deflection_differs = false;
    for map in [MapMode::Gpis, MapMode::Occupancy] {
        for seed in 1_000_000..1_000_012u64 {
            let mut fast =
                Episode::started(Checked::new(config(map, true)).unwrap(), seed).unwrap();
            let mut stepped =
                Episode::started(Checked::new(config(map, false)).unwrap(), seed).unwrap();
            let counts = fast.config().probe.counts();
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            loop {
                let action = random_probe(&mut rng, counts);
                let before = stepped.last_info().jar_displacement;
                let a = fast.step(action).unwrap();
                let b = stepped.step(action).unwrap();
                compared += 1;
                // Both episodes start the probe in the same state but the finger's swing;
                // a probe is clear when neither touched nor moved a jar.
                let clear = [(&a, before), (&b, before)]
                    .iter()
                    .all(|(i, d)| i.contacts == 0 && i.jar_displacement == *d && !i.tipped)
                    // A wall stops the hand where the finger, at its deflection, meets it.
                    && !a.blocked
                    && !b.blocked;
                let same = outcome(&a) == outcome(&b)
                    && a.reward == b.reward
                    && pose_bits(fast.scene().hand_pose())
                        == pose_bits(stepped.scene().hand_pose())
                    && observe(&fast).0 == observe(&stepped).0;
                assert!(
                    same || !clear,
                    "map {map:?} seed {seed}: a probe both episodes made without touching \
                     differs with the fast path: {a:?} vs {b:?}"
                );
                if !same {
                    break; // the episodes parted where one of them touched
                }
                agreed += 1;
                let gap = (fast.scene().finger_angle() - stepped.scene().finger_angle()).abs();
                assert!(
                    gap <= MAX_DEFLECTION_GAP,
                    "map {map:?} seed {seed}: deflection gap {gap}"
                );
                deflection_differs |= gap > 0.0;
                if a.terminated || a.truncated {
                    break;
                }
            }
            fast_motions += fast.scene().free_motions();
            motions += fast.scene().steps();
            assert_eq!(
                stepped.scene().free_motions(),
                0,
                "the stepped episode took the fast path"
            );
        }
    }
    println!("{agreed} of {compared} probes agreed; {fast_motions} of {motions} motions fast");
    assert!(
        deflection_differs,
        "the finger never differed: was the fast path taken?"
    );
    assert!(
        fast_motions * 3 >= motions,
        "only {fast_motions} of {motions} motions took the fast path"
    );
    // Episodes part at the first probe that touches or hits a wall, so most comparisons are
    // short; the clear probes compared must not be a handful.
    assert!(
        agreed >= 8,
        "only {agreed} of {compared} probes compared agreed"
    );
}
