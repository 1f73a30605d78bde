//! The core's GPIS probe planner on episodes of the core: it finds the target reading only
//! the observations (the map image and the proprio vector) without tipping a jar, a batch
//! of planners acting in parallel chooses what each would alone, and it refuses settings it
//! cannot plan in and calls out of order.

use env_core::episode::{ActionMode, Episode, EpisodeConfig, MapMode, PROPRIO_LEN};
use env_core::planner::{act_batch, PlannerError, PlannerObservation, ProbePlanner};
use env_core::settings::Checked;

fn probe_config() -> EpisodeConfig {
    EpisodeConfig {
        action_mode: ActionMode::Probe,
        ..EpisodeConfig::default()
    }
}

/// The episode's observation, as the bindings hand it over.
fn observe(episode: &Episode) -> (Vec<u8>, [f32; PROPRIO_LEN]) {
    let mut map = vec![0u8; episode.map_len()];
    episode.write_map(&mut map).unwrap();
    let mut proprio = [0f32; PROPRIO_LEN];
    episode.write_proprio(&mut proprio).unwrap();
    (map, proprio)
}

/// Runs the planner on the episode of `seed`; the probes and whether it ended in success.
fn run(seed: u64) -> (Vec<[i64; 3]>, bool, usize) {
    let config = probe_config();
    let mut episode = Episode::started(Checked::new(config.clone()).unwrap(), seed).unwrap();
    let mut planner = ProbePlanner::new(&config).unwrap();
    let (map, proprio) = observe(&episode);
    planner
        .reset(PlannerObservation {
            map: &map,
            proprio: &proprio,
        })
        .unwrap();
    let mut probes = Vec::new();
    loop {
        let (map, proprio) = observe(&episode);
        let probe = planner
            .act(PlannerObservation {
                map: &map,
                proprio: &proprio,
            })
            .unwrap();
        probes.push(probe);
        let info = episode
            .step(env_core::episode::Action::Probe(probe))
            .unwrap();
        if info.terminated || info.truncated {
            return (probes, info.success, info.tips);
        }
    }
}

#[test]
fn the_planner_finds_the_target_from_observations_alone_without_tipping() {
    for seed in [1, 2, 3, 4, 5] {
        let (_, success, tips) = run(seed);
        assert!(
            success && tips == 0,
            "seed {seed}: success {success}, tips {tips}"
        );
    }
}

#[test]
fn a_batch_of_planners_chooses_what_each_chooses_alone() {
    let config = probe_config();
    let seeds = [1u64, 2, 3, 6, 7, 8];
    let alone: Vec<[i64; 3]> = seeds.iter().map(|&seed| run(seed).0[0]).collect();
    let episodes: Vec<Episode> = seeds
        .iter()
        .map(|&seed| Episode::started(Checked::new(config.clone()).unwrap(), seed).unwrap())
        .collect();
    let observed: Vec<_> = episodes.iter().map(observe).collect();
    let observations: Vec<PlannerObservation<'_>> = observed
        .iter()
        .map(|(map, proprio)| PlannerObservation { map, proprio })
        .collect();
    let mut planners = vec![ProbePlanner::new(&config).unwrap(); seeds.len()];
    for (planner, observation) in planners.iter_mut().zip(&observations) {
        planner.reset(*observation).unwrap();
    }
    assert_eq!(act_batch(&mut planners, &observations).unwrap(), alone);
}

#[test]
fn the_planner_refuses_other_maps_action_modes_and_calls_out_of_order() {
    let occupancy = EpisodeConfig {
        action_mode: ActionMode::Probe,
        ..EpisodeConfig::default()
    };
    let mut occupancy = occupancy;
    occupancy.map.mode = MapMode::Occupancy;
    assert_eq!(
        ProbePlanner::new(&occupancy).unwrap_err(),
        PlannerError::NeedsMap {
            wanted: "gpis",
            got: "occupancy"
        }
    );
    assert_eq!(
        ProbePlanner::new(&EpisodeConfig::default()).unwrap_err(),
        PlannerError::NeedsProbeActions("wrist")
    );
    let config = probe_config();
    let mut planner = ProbePlanner::new(&config).unwrap();
    let episode = Episode::started(Checked::new(config.clone()).unwrap(), 1).unwrap();
    let (map, proprio) = observe(&episode);
    let observation = PlannerObservation {
        map: &map,
        proprio: &proprio,
    };
    assert_eq!(
        planner.act(observation).unwrap_err(),
        PlannerError::NotReset
    );
    assert_eq!(
        planner.follow([0, 0, 0]).unwrap_err(),
        PlannerError::NotReset
    );
    planner.reset(observation).unwrap();
    assert!(matches!(
        planner.follow([0, 99, 0]),
        Err(PlannerError::Episode(_))
    ));
    let short = PlannerObservation {
        map: &map[1..],
        proprio: &proprio,
    };
    assert!(matches!(
        planner.act(short),
        Err(PlannerError::Image { .. })
    ));
}
