//! Every generated layout leaves the target reachable: a simple scripted reach (into the
//! corridor, straight in to the target's depth, then a yaw towards the target) touches the
//! target with the finger without moving any other jar by 2 mm or tipping it.

mod common;

use env_core::scene::{Scene, SceneConfig};
use env_core::settings::Checked;

#[test]
fn a_scripted_reach_through_the_corridor_touches_the_target_without_disturbing_others() {
    let config = Checked::new(SceneConfig::default()).unwrap();
    for seed in 0..60 {
        let mut scene = Scene::new(&config, seed).expect("scene builds");
        let layout = scene.layout().clone();
        let corridor = layout.corridor.expect("generated layouts have a corridor");
        common::reach_through(&mut scene, &corridor, layout.target, seed);
    }
}
