//! Criterion benchmark of the `probe` action mode: random probes on the GPIS map with the
//! fast path of free motion (`fast_free_motion`) on and off, side by side, with the episode
//! resets excluded (a probe alone; an episode that ends is reset outside the timing) and
//! included (a reset whenever an episode ends, as a training loop runs it).
//!
//! Run: `cargo bench -p env_core --bench probe` (append `-- --quick` on a noisy machine).

use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::{criterion_group, criterion_main, Criterion};
use env_core::episode::ActionMode;
use env_core::episode::{Episode, EpisodeConfig, MapMode};
use env_core::settings::Checked;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Random probes on validation-range layouts, the same sequence for either setting.
struct Prober {
    episode: Episode,
    rng: ChaCha8Rng,
    seed: u64,
}

impl Prober {
    fn new(fast: bool) -> Self {
        let mut config = EpisodeConfig::default();
        config.map.mode = MapMode::Gpis;
        config.action_mode = ActionMode::Probe;
        config.scene.physics.fast_free_motion = fast;
        let seed = 1_000_000;
        Self {
            episode: Episode::started(Checked::new(config).unwrap(), seed).expect("episode starts"),
            rng: ChaCha8Rng::seed_from_u64(7),
            seed,
        }
    }

    /// One random probe; whether the episode ended.
    fn probe(&mut self) -> bool {
        let counts = self.episode.config().probe.counts();
        let action = counts.map(|n| self.rng.random_range(0..n) as i64);
        let info = self.episode.step(action).expect("probe");
        black_box(&info);
        info.terminated || info.truncated
    }

    fn reset(&mut self) {
        self.seed += 1;
        self.episode.reset(self.seed).expect("reset");
    }
}

fn bench_probes(c: &mut Criterion) {
    let mut group = c.benchmark_group("random_probe_gpis");
    for (name, fast) in [("fast_free_motion", true), ("stepped", false)] {
        let mut prober = Prober::new(fast);
        group.bench_function(format!("{name}/resets_excluded"), |b| {
            b.iter_custom(|iters| {
                let mut timed = Duration::ZERO;
                for _ in 0..iters {
                    let start = Instant::now();
                    let ended = prober.probe();
                    timed += start.elapsed();
                    if ended {
                        prober.reset();
                    }
                }
                timed
            })
        });
        let mut prober = Prober::new(fast);
        group.bench_function(format!("{name}/resets_included"), |b| {
            b.iter(|| {
                if prober.probe() {
                    prober.reset();
                }
            })
        });
    }
    group.finish();
}

criterion_group!(benches, bench_probes);
criterion_main!(benches);
