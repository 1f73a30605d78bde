//! How much a second core speeds up [`EpisodeBatch::run`], with no Python in the loop, and
//! what a sleeping rayon worker costs to wake (each run hands its tasks to the batch's
//! pool, whose workers sleep between runs, `env_core/src/episode/batch.rs`):
//!
//! `cargo run --release -p env_core --example batch_scaling [rounds]`
//!
//! Per map mode and action mode, a batch of 16 episodes on 1 thread and on 2, stepped with
//! random actions (episodes that end are reset to new seeds), in alternating rounds of 200
//! runs (probe mode: 20); prints the median time per run on each and their ratio, and the
//! means (which, unlike the medians, count the few runs that hold a reset). Then the
//! wake-up of a sleeping rayon helper: the time from handing it a task to its start, after
//! a pause long enough for it to sleep. The machine is shared and noisy: compare ratios
//! from one run.

use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

use env_core::episode::{
    Action, ActionMode, Command, EpisodeBatch, EpisodeConfig, MapMode, PROPRIO_LEN,
};
use env_core::settings::Checked;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

const EPISODES: usize = 16;

/// A batch and its buffers, stepped with random actions from its own generator.
struct Stepper {
    batch: EpisodeBatch,
    maps: Vec<u8>,
    proprio: Vec<f32>,
    rng: ChaCha8Rng,
    next_seed: u64,
    counts: [usize; 3],
    action_mode: ActionMode,
}

impl Stepper {
    fn new(config: EpisodeConfig, threads: usize) -> Self {
        let seeds: Vec<u64> = (1_000_000..1_000_000 + EPISODES as u64).collect();
        let counts = config.probe.counts();
        let action_mode = config.action_mode;
        let batch = EpisodeBatch::started(Checked::new(config).unwrap(), &seeds, Some(threads))
            .expect("batch starts");
        let (maps, proprio) = (
            vec![0; EPISODES * batch.map_len()],
            vec![0.0; EPISODES * PROPRIO_LEN],
        );
        Self {
            batch,
            maps,
            proprio,
            rng: ChaCha8Rng::seed_from_u64(threads as u64),
            next_seed: 1_100_000,
            counts,
            action_mode,
        }
    }

    /// One run; returns its wall time.
    fn run(&mut self) -> Duration {
        let commands: Vec<Command> = (0..EPISODES)
            .map(|i| {
                let info = self.batch.episodes()[i].last_info();
                if info.terminated || info.truncated {
                    self.next_seed += 1;
                    return Command::Reset(self.next_seed);
                }
                Command::Step(match self.action_mode {
                    ActionMode::Wrist => {
                        Action::Wrist([0; 3].map(|_| self.rng.random_range(-1.0..1.0)))
                    }
                    ActionMode::Probe => Action::Probe(
                        [0, 1, 2].map(|k| self.rng.random_range(0..self.counts[k]) as i64),
                    ),
                })
            })
            .collect();
        let start = Instant::now();
        self.batch
            .run(&commands, &mut self.maps, &mut self.proprio)
            .expect("run");
        start.elapsed()
    }
}

fn median(times: &[Duration]) -> Duration {
    let mut times = times.to_vec();
    times.sort();
    times[times.len() / 2]
}

/// The mean: unlike the median, it counts the few runs that hold a reset.
fn mean(times: &[Duration]) -> Duration {
    times.iter().sum::<Duration>() / times.len() as u32
}

fn main() {
    // The options the Python module sets when it is imported.
    env_core::allocator::configure();
    let rounds: usize = std::env::args()
        .nth(1)
        .map(|a| a.parse().expect("the number of rounds"))
        .unwrap_or(5);
    for action_mode in [ActionMode::Wrist, ActionMode::Probe] {
        let runs = if action_mode == ActionMode::Wrist {
            200
        } else {
            20
        };
        for map in [MapMode::Gpis, MapMode::Occupancy, MapMode::None] {
            let mut config = EpisodeConfig::default();
            config.map.mode = map;
            config.action_mode = action_mode;
            let mut steppers = [1, 2].map(|threads| Stepper::new(config.clone(), threads));
            let mut times = [Vec::new(), Vec::new()];
            for _ in 0..rounds {
                for (stepper, times) in steppers.iter_mut().zip(&mut times) {
                    times.extend((0..runs).map(|_| stepper.run()));
                }
            }
            let [one, two] = times.each_ref().map(|t| median(t));
            let [one_mean, two_mean] = times.each_ref().map(|t| mean(t));
            println!(
                "{action_mode:?} {map:?}, {EPISODES} episodes: {:.3} ms per run on 1 thread, \
                 {:.3} on 2, speed-up {:.2}x (medians); means, resets included: {:.3} and \
                 {:.3} ms, {:.2}x",
                one.as_secs_f64() * 1e3,
                two.as_secs_f64() * 1e3,
                one.as_secs_f64() / two.as_secs_f64(),
                one_mean.as_secs_f64() * 1e3,
                two_mean.as_secs_f64() * 1e3,
                one_mean.as_secs_f64() / two_mean.as_secs_f64()
            );
        }
    }
    wake_latency();
}

/// Median time from handing a sleeping rayon helper a task to the task's start.
fn wake_latency() {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("a helper thread");
    let epoch = Instant::now();
    let latencies: Vec<Duration> = (0..200)
        .map(|_| {
            // The calling thread works meanwhile, as it does between two steps.
            let pause = Instant::now();
            while pause.elapsed() < Duration::from_millis(2) {
                std::hint::spin_loop();
            }
            let started = AtomicU64::new(0);
            let handed = epoch.elapsed();
            pool.in_place_scope(|scope| {
                scope
                    .spawn(|_| started.store(epoch.elapsed().as_nanos() as u64, Ordering::Release));
            });
            Duration::from_nanos(started.load(Ordering::Acquire)) - handed
        })
        .collect();
    println!(
        "a sleeping helper thread starts a task {:.0} µs after it is handed one (median)",
        median(&latencies).as_secs_f64() * 1e6
    );
}
