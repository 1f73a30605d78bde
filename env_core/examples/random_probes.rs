//! Random probes on GPIS episodes (probe mode, default settings), resets included as a
//! training loop runs them, for `valgrind --tool=callgrind` instruction counts of the probe
//! mode's environment (`docs/DESIGN.md` §9.1):
//!
//! `cargo build --release -p env_core --example random_probes &&
//!  valgrind --tool=callgrind target/release/examples/random_probes 200`
//!
//! The first argument is the number of probes (layouts 1,000,000.., a new one whenever an
//! episode ends; the probes drawn from a fixed seed); `stepped` as the second turns off the
//! fast path of free motion (`fast_free_motion`, on by default) and steps every command.
//! Its first line gives the episodes, the contacts, the GPIS rows the touches added and the
//! summed reward, so two builds can be checked to do the same work.

use env_core::episode::{ActionMode, Episode, EpisodeConfig, MapMode};
use env_core::settings::Checked;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn main() {
    let mut args = std::env::args().skip(1);
    let probes: u64 = args
        .next()
        .map(|a| a.parse().expect("the number of probes"))
        .unwrap_or(200);
    let stepped = args.next().is_some_and(|a| a == "stepped");
    let mut config = EpisodeConfig::default();
    config.map.mode = MapMode::Gpis;
    config.action_mode = ActionMode::Probe;
    if stepped {
        config.scene.physics.fast_free_motion = false;
    }
    let mut seed = 1_000_000;
    let mut episode =
        Episode::started(Checked::new(config).unwrap(), seed).expect("episode starts");
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let (mut episodes, mut contacts, mut rows, mut reward) = (1u64, 0usize, 0usize, 0.0f64);
    let (mut commands, mut carried) = (0u64, 0u64);
    for _ in 0..probes {
        let counts = episode.config().probe.counts();
        let action = counts.map(|n| rng.random_range(0..n) as i64);
        let info = episode.step(action).expect("probe");
        contacts += info.contacts;
        rows += info.rows_added;
        reward += info.reward;
        if info.terminated || info.truncated {
            commands += episode.scene().steps();
            carried += episode.scene().free_motions();
            seed += 1;
            episode.reset(seed).expect("reset");
            episodes += 1;
        }
    }
    println!(
        "episodes {episodes}, contacts {contacts}, GPIS rows added {rows}, summed reward {reward:.6}"
    );
    println!(
        "wrist commands of the ended episodes {commands}, {carried} of them by the fast path of \
         free motion ({:.1} %)",
        100.0 * carried as f64 / commands.max(1) as f64
    );
}
