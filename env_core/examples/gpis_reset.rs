//! Resets GPIS episodes (probe mode, default settings) of fixed validation seeds, for
//! `valgrind --tool=callgrind` instruction counts of the reset (`docs/DESIGN.md` §3, §9.1):
//!
//! `cargo build --release -p env_core --example gpis_reset &&
//!  valgrind --tool=callgrind target/release/examples/gpis_reset 20`
//!
//! The argument is the number of resets (seeds 1,000,001..). It prints the rows the map
//! holds after each reset, so two builds can be checked to do the same work.

use env_core::episode::{ActionMode, Episode, EpisodeConfig, MapMode};
use env_core::settings::Checked;

fn main() {
    let resets: u64 = std::env::args()
        .nth(1)
        .map(|a| a.parse().expect("the number of resets"))
        .unwrap_or(20);
    let mut config = EpisodeConfig::default();
    config.map.mode = MapMode::Gpis;
    config.action_mode = ActionMode::Probe;
    let mut episode = Episode::started(Checked::new(config).unwrap(), 0).expect("episode starts");
    let mut rows = Vec::new();
    for seed in 1_000_001..=1_000_000 + resets {
        episode.reset(seed).expect("reset");
        rows.push(episode.last_info().gpis_rows);
    }
    println!("gpis rows after each reset: {rows:?}");
}
