//! A batch of episodes stepped in parallel: the core of the vector environments.
//!
//! One call to [`EpisodeBatch::run`] gives each episode a [`Command`] (step with an action,
//! reset to a seed, or hold) and carries them out on the calling thread and the batch's own
//! helper threads (a rayon pool of `threads - 1`, kept alive: spawning threads every call
//! would cost as much as a step). The calling thread works too, from the first task. A
//! thread that sleeps costs a wake-up to start again: 70-200 µs on a virtual machine, whose
//! idle core halts (`cargo run --release -p env_core --example batch_scaling` measures it),
//! against about 60 µs of work per episode in a wrist-mode step. So threads spin before
//! they sleep, the wait policy of OpenMP runtimes: the calling thread spins (then yields)
//! for the helpers' last tasks, for at most [`CALLER_SPIN`], and after a run each helper
//! stays awake for [`HELPER_WARM`] (a spinning job in its pool) to take the next run's tasks
//! at once; past that it sleeps, so an idle batch costs no CPU. The tasks, one per episode
//! that steps or resets, are taken one at a time from a shared queue, resets first (then
//! the calling thread takes steps from its front and the helpers from its back, so that an
//! episode tends to stay on one thread and in its core's cache): a reset costs as much as
//! about 150 wrist steps, so one started last would leave the other threads idle while it
//! runs alone. Even first, a reset outlasts the other threads' share
//! of a wrist-mode step; so the episodes share one job board ([`SharedTiles`]), and a
//! thread with no task left helps with the tiles of cells of a grid update still running
//! on another (the bulk of a GPIS reset) before it waits. Each task writes its episode's
//! observation straight into that episode's rows of the caller's buffers (in the bindings:
//! numpy arrays allocated once per batch), so nothing is staged or copied and results do
//! not depend on the thread count or on which thread ran what.
//! [`EpisodeBatch::write_result`] then writes rewards, flags and infos as columns
//! (O(info fields) per episode, on the calling thread).

use std::collections::VecDeque;
use std::num::NonZeroUsize;
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, PoisonError};
use std::thread;
use std::time::{Duration, Instant};

use crossbeam_utils::Backoff;
use rayon::{ThreadPool, ThreadPoolBuilder};

use super::action_mode::Action;
use super::config::EpisodeConfig;
use super::episode::Episode;
use super::error::EpisodeError;
use super::observation::PROPRIO_LEN;
use super::shared_tiles::SharedTiles;
use super::step_info::InfoColumns;
use crate::settings::Checked;

/// What [`EpisodeBatch::run`] does with one episode.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Command {
    /// Step with this action (see [`Episode::step`]).
    Step(Action),
    /// Start the episode of this seed (the vector environment's autoreset).
    Reset(u64),
    /// Leave the episode and its observation rows untouched.
    Hold,
}

/// How long a helper thread stays awake after a run for the next one: longer than the gap
/// between two steps of a vector environment stepped in a loop (its serial part, ~0.1 ms),
/// short enough that a batch waiting on a learner burns little of its core.
pub const HELPER_WARM: Duration = Duration::from_millis(1);

/// How long a thread with no task left spins (then yields) for the others' last tasks, and
/// for a grid update of theirs to help with, before it sleeps until they are done: longer
/// than a wrist-mode task (~60 µs), far shorter than a scheduler's time slice. Unbounded, a
/// caller spinning on a loaded machine kept its core busy while the helper it waited for
/// queued for the other one (the soak saw wrist steps 20-80x slower while two trainings
/// ran); a sleeping caller's core takes the helper instead.
pub const CALLER_SPIN: Duration = Duration::from_micros(200);

/// N episodes with the same configuration.
pub struct EpisodeBatch {
    episodes: Vec<Episode>,
    threads: usize,
    /// `threads - 1` helper threads (none for one thread): the calling thread is the other.
    helpers: Option<Helpers>,
}

/// The helper threads and the count of runs they have been handed (a helper kept warm
/// after run k stops spinning when it changes).
struct Helpers {
    pool: ThreadPool,
    runs: Arc<AtomicU64>,
    /// The job board every episode's grid updates go through.
    tiles: Arc<SharedTiles>,
    /// The process whose threads `pool` holds (see [`EpisodeBatch::restart_helpers_after_fork`]).
    process: u32,
}

impl Helpers {
    /// `count` helper threads and a job board that every episode's grid updates go through.
    fn start(count: usize, episodes: &mut [Episode]) -> Self {
        let tiles = Arc::new(SharedTiles::default());
        for episode in episodes {
            episode.share_tiles(tiles.clone());
        }
        Self {
            pool: ThreadPoolBuilder::new()
                .num_threads(count)
                .build()
                .expect("the OS can start the batch's helper threads"),
            runs: Arc::new(AtomicU64::new(0)),
            tiles,
            process: std::process::id(),
        }
    }

    /// Starts a run: wakes the helpers kept warm after the last one. Returns its number.
    fn begin_run(&self) -> u64 {
        self.runs.fetch_add(1, Ordering::AcqRel) + 1
    }

    /// Keeps every helper awake for [`HELPER_WARM`] after run `run`, or until the next run.
    fn keep_warm(&self, run: u64) {
        for _ in 0..self.pool.current_num_threads() {
            let runs = Arc::clone(&self.runs);
            self.pool.spawn(move || {
                let start = Instant::now();
                let backoff = Backoff::new();
                while runs.load(Ordering::Acquire) == run && start.elapsed() < HELPER_WARM {
                    backoff.snooze();
                }
            });
        }
    }
}

impl EpisodeBatch {
    /// `len` episodes of `config`, none started: a [`Command::Reset`] starts each.
    /// `threads = None` uses every available core.
    ///
    /// # Errors
    /// A map that cannot be built on the config's grid ([`EpisodeError::Gpis`]).
    pub fn new(
        config: Checked<EpisodeConfig>,
        len: usize,
        threads: Option<usize>,
    ) -> Result<Self, EpisodeError> {
        let mut episodes = (0..len)
            .map(|_| Episode::new(config.clone()))
            .collect::<Result<Vec<_>, _>>()?;
        let cores = thread::available_parallelism().map_or(1, NonZeroUsize::get);
        // More threads than episodes only help with resets' grid tiles: up to the cores.
        let threads = threads
            .unwrap_or(cores)
            .clamp(1, episodes.len().max(cores).max(1));
        let helpers = (threads > 1).then(|| Helpers::start(threads - 1, &mut episodes));
        Ok(Self {
            episodes,
            threads,
            helpers,
        })
    }

    /// [`EpisodeBatch::new`] with an episode for each of `seeds`, then a run that resets
    /// each to its seed: a batch ready to step.
    ///
    /// # Errors
    /// As [`EpisodeBatch::new`] and [`Episode::reset`].
    pub fn started(
        config: Checked<EpisodeConfig>,
        seeds: &[u64],
        threads: Option<usize>,
    ) -> Result<Self, EpisodeError> {
        let mut batch = Self::new(config, seeds.len(), threads)?;
        let resets: Vec<Command> = seeds.iter().map(|&seed| Command::Reset(seed)).collect();
        let mut maps = vec![0u8; seeds.len() * batch.map_len()];
        let mut proprio = vec![0f32; seeds.len() * PROPRIO_LEN];
        batch.run(&resets, &mut maps, &mut proprio)?;
        Ok(batch)
    }

    /// Number of episodes.
    pub fn len(&self) -> usize {
        self.episodes.len()
    }

    /// Whether the batch holds no episode.
    pub fn is_empty(&self) -> bool {
        self.episodes.is_empty()
    }

    /// The episodes.
    pub fn episodes(&self) -> &[Episode] {
        &self.episodes
    }

    /// Threads that carry out a run: the calling thread and `threads - 1` helpers.
    pub fn threads(&self) -> usize {
        self.threads
    }

    /// Bytes of one episode's map image (0 in the `none` mode).
    pub fn map_len(&self) -> usize {
        self.episodes.first().map_or(0, Episode::map_len)
    }

    /// Writes every episode's observation (maps: N × map_len, proprio: N × PROPRIO_LEN).
    pub fn write_observations(
        &self,
        maps: &mut [u8],
        proprio: &mut [f32],
    ) -> Result<(), EpisodeError> {
        self.check_buffers(maps, proprio)?;
        for index in 0..self.episodes.len() {
            self.write_observation(index, maps, proprio)?;
        }
        Ok(())
    }

    /// Writes episode `index`'s observation into its rows of the batch buffers. Cost: one
    /// map image, O(G).
    pub fn write_observation(
        &self,
        index: usize,
        maps: &mut [u8],
        proprio: &mut [f32],
    ) -> Result<(), EpisodeError> {
        self.check_buffers(maps, proprio)?;
        let (m, p) = (self.map_len(), PROPRIO_LEN);
        let episode = &self.episodes[index];
        episode.write_map(&mut maps[index * m..(index + 1) * m])?;
        episode.write_proprio(&mut proprio[index * p..(index + 1) * p])
    }

    /// Resets episode `index` to `seed` and writes its observation rows only. Cost: one
    /// reset on the calling thread.
    pub fn reset(
        &mut self,
        index: usize,
        seed: u64,
        maps: &mut [u8],
        proprio: &mut [f32],
    ) -> Result<(), EpisodeError> {
        self.check_buffers(maps, proprio)?;
        self.episodes[index]
            .reset(seed)
            .map_err(|e| e.in_episode(index))?;
        self.write_observation(index, maps, proprio)
    }

    fn check_buffers(&self, maps: &[u8], proprio: &[f32]) -> Result<(), EpisodeError> {
        let n = self.episodes.len();
        for (what, expected, got) in [
            ("maps", n * self.map_len(), maps.len()),
            ("proprio", n * PROPRIO_LEN, proprio.len()),
        ] {
            if expected != got {
                return Err(EpisodeError::BufferLength {
                    what,
                    expected,
                    got,
                });
            }
        }
        Ok(())
    }

    /// Carries out `commands[i]` on episode i, on all worker threads, and writes the
    /// observation of every episode stepped or reset into its rows of `maps` (N × map_len)
    /// and `proprio` (N × PROPRIO_LEN). Every action is checked (finite; in the `probe`
    /// mode, indices within their counts) before any episode moves, so a bad action
    /// changes nothing. Otherwise the first failing episode (a step
    /// after termination) is reported as [`EpisodeError::InEpisode`]; the others have run.
    /// Cost: the work divided over the threads, each taking the next task when it is free
    /// (resets first), plus one task's length at most; one task or one thread runs on the
    /// calling thread alone.
    pub fn run(
        &mut self,
        commands: &[Command],
        maps: &mut [u8],
        proprio: &mut [f32],
    ) -> Result<(), EpisodeError> {
        let n = self.episodes.len();
        if commands.len() != n {
            return Err(EpisodeError::BufferLength {
                what: "commands",
                expected: n,
                got: commands.len(),
            });
        }
        self.check_buffers(maps, proprio)?;
        self.restart_helpers_after_fork();
        for (index, command) in commands.iter().enumerate() {
            if let Command::Step(action) = command {
                self.episodes[index]
                    .check_action(action)
                    .map_err(|e| e.in_episode(index))?;
            }
        }
        let map_len = self.map_len();
        // Without a map (`none` mode) every episode writes into an empty slice.
        let map_rows: Vec<&mut [u8]> = if map_len == 0 {
            (0..n).map(|_| &mut [][..]).collect()
        } else {
            maps.chunks_mut(map_len).collect()
        };
        let mut tasks: Vec<Task<'_>> = self
            .episodes
            .iter_mut()
            .zip(commands)
            .zip(map_rows)
            .zip(proprio.chunks_mut(PROPRIO_LEN))
            .enumerate()
            .filter(|(_, (((_, command), _), _))| **command != Command::Hold)
            .map(|(index, (((episode, &command), map), proprio))| Task {
                index,
                episode,
                command,
                map,
                proprio,
            })
            .collect();
        let helpers = self.helpers.as_ref();
        // Resets first (a stable sort: otherwise in episode order).
        tasks.sort_by_key(|task| !matches!(task.command, Command::Reset(_)));
        let resets = tasks
            .first()
            .is_some_and(|task| matches!(task.command, Command::Reset(_)));
        let failures = match helpers {
            Some(helpers) if tasks.len() > 1 || resets => {
                let run = helpers.begin_run();
                // A helper with no episode to take still takes tiles of a reset's grid.
                let helpful = if resets { usize::MAX } else { tasks.len() - 1 };
                let working = helpers.pool.current_num_threads().min(helpful);
                let work = Work {
                    remaining: AtomicUsize::new(tasks.len()),
                    queue: Mutex::new(tasks.into()),
                    failures: Mutex::new(Vec::new()),
                    tiles: &helpers.tiles,
                    // A reset posts its grid job after its scene (~0.5 ms): a helper
                    // asleep by then would cost a wake-up (70-150 µs) of the job.
                    spin: if resets { HELPER_WARM } else { CALLER_SPIN },
                };
                let unfinished = AtomicUsize::new(working);
                helpers.pool.in_place_scope(|scope| {
                    for _ in 0..working {
                        scope.spawn(|_| {
                            // Counted off even if a task panics (rayon then re-raises it
                            // here), so the wait below ends.
                            let _finished = CountOff(&unfinished);
                            work.take_part(End::Back);
                        });
                    }
                    work.take_part(End::Front);
                    // Spin (then yield) rather than sleep on the scope's latch, for at
                    // most CALLER_SPIN: past that the helper has likely lost its core to
                    // another process, and only a sleeping caller frees one for it.
                    let (backoff, spinning) = (Backoff::new(), Instant::now());
                    while unfinished.load(Ordering::Acquire) > 0 && spinning.elapsed() < CALLER_SPIN
                    {
                        backoff.snooze();
                    }
                });
                // A batch of one never has a step for a helper to take next.
                if n > 1 {
                    helpers.keep_warm(run);
                }
                work.failures
                    .into_inner()
                    .unwrap_or_else(PoisonError::into_inner)
            }
            // One task or one thread: on the calling thread alone.
            _ => tasks
                .into_iter()
                .filter_map(|task| carry_out(task).err())
                .collect(),
        };
        match failures.into_iter().min_by_key(|(index, _)| *index) {
            Some((index, error)) => Err(error.in_episode(index)),
            None => Ok(()),
        }
    }

    /// Starts the helper threads again in a process forked from the one that started them.
    /// A `fork` copies only the forking thread: the child's pool would queue the run's
    /// jobs for threads that are not there, and the run would wait for them for ever
    /// (Python's `multiprocessing` forks a process holding an env). The child's batch
    /// starts its own helpers instead; the old pool is left alone, not dropped: its threads
    /// and whatever locks they held belong to the parent. Cost: a `getpid` per run.
    fn restart_helpers_after_fork(&mut self) {
        let Some(helpers) = &self.helpers else {
            return;
        };
        if helpers.process != std::process::id() {
            let count = helpers.pool.current_num_threads();
            std::mem::forget(self.helpers.take());
            self.helpers = Some(Helpers::start(count, &mut self.episodes));
        }
    }

    /// Writes, after [`EpisodeBatch::run`], episode `index`'s reward and
    /// terminated/truncated flags (0 and false unless it was `stepped`: a reset or hold is
    /// not a transition) and its info (that of its last step or reset) into the columns.
    /// Cost O(info fields).
    pub fn write_result(
        &self,
        index: usize,
        stepped: bool,
        rewards: &mut [f64],
        terminated: &mut [bool],
        truncated: &mut [bool],
        infos: &mut InfoColumns<'_>,
    ) {
        let info = self.episodes[index].last_info();
        rewards[index] = if stepped { info.reward } else { 0.0 };
        terminated[index] = stepped && info.terminated;
        truncated[index] = stepped && info.truncated;
        infos.write(index, info);
    }
}

/// Takes one off a count of unfinished helpers when dropped.
struct CountOff<'a>(&'a AtomicUsize);

impl Drop for CountOff<'_> {
    fn drop(&mut self) {
        self.0.fetch_sub(1, Ordering::Release);
    }
}

/// One episode's share of a run: its index, the episode, its command, its map rows, its
/// proprio row.
struct Task<'a> {
    index: usize,
    episode: &'a mut Episode,
    command: Command,
    map: &'a mut [u8],
    proprio: &'a mut [f32],
}

/// A run's tasks shared by its threads: the queue (resets first, then the steps in episode
/// order; see [`take_next`]), how many tasks are not yet done, the failures with their
/// episode's index, and the job board of grid tiles.
struct Work<'a> {
    remaining: AtomicUsize,
    queue: Mutex<VecDeque<Task<'a>>>,
    failures: Mutex<Vec<(usize, EpisodeError)>>,
    tiles: &'a SharedTiles,
    /// How long a thread with no task left spins for a grid job before it sleeps.
    spin: Duration,
}

/// Which end of a run's queue a thread takes its steps from: the calling thread the front,
/// the helpers the back.
#[derive(Debug, Clone, Copy)]
enum End {
    Front,
    Back,
}

/// The next task from a queue that holds its resets first: a reset while there is one,
/// then a step from `end`. With the steps in episode order, the calling thread steps the
/// first episodes and a helper the last ones, run after run, as long as the load is even:
/// an episode keeps its thread, and its physics world and map stay in that core's cache
/// (taken in one order by both, they went to either thread at random).
fn take_next<T>(queue: &mut VecDeque<T>, end: End, is_reset: impl Fn(&T) -> bool) -> Option<T> {
    match end {
        _ if queue.front().is_some_and(is_reset) => queue.pop_front(),
        End::Front => queue.pop_front(),
        End::Back => queue.pop_back(),
    }
}

impl Work<'_> {
    /// One thread's part: takes tasks one at a time until the queue is empty (the lock is
    /// held only to take a task, never while one runs), then helps with the grid tiles of
    /// the tasks still running until every task is done.
    fn take_part(&self, end: End) {
        loop {
            let next = take_next(
                &mut self.queue.lock().unwrap_or_else(PoisonError::into_inner),
                end,
                |task| matches!(task.command, Command::Reset(_)),
            );
            let Some(task) = next else { break };
            // Counted as done even if the task panics, so no thread helps forever.
            let _done = TaskDone(self);
            if let Err(failure) = carry_out(task) {
                self.failures
                    .lock()
                    .unwrap_or_else(PoisonError::into_inner)
                    .push(failure);
            }
        }
        self.tiles
            .help_until(|| self.remaining.load(Ordering::Acquire) == 0, self.spin);
    }
}

/// Counts one task of a [`Work`] as done when dropped; the last one wakes the helpers.
struct TaskDone<'w, 'a>(&'w Work<'a>);

impl Drop for TaskDone<'_, '_> {
    fn drop(&mut self) {
        if self.0.remaining.fetch_sub(1, Ordering::AcqRel) == 1 {
            self.0.tiles.wake_all();
        }
    }
}

/// Carries out one episode's command and writes its observation rows; a failure comes
/// back with the episode's index.
fn carry_out(task: Task<'_>) -> Result<(), (usize, EpisodeError)> {
    let Task {
        index,
        episode,
        command,
        map,
        proprio,
    } = task;
    let done = match command {
        Command::Step(action) => episode.advance(action).map(|_| ()),
        Command::Reset(seed) => episode.reset(seed),
        Command::Hold => return Ok(()),
    };
    done.and_then(|()| episode.write_map(map))
        .and_then(|()| episode.write_proprio(proprio))
        .map_err(|error| (index, error))
}

#[cfg(test)]
mod tests {
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    use super::*;
    use crate::episode::{oracle_action, ActionMode, MapMode, StepInfo};

    /// Resets are taken first, from either end; then the calling thread takes steps from
    /// the front and a helper from the back, so each keeps its own episodes.
    #[test]
    fn resets_go_first_then_each_thread_steps_its_own_end_of_the_queue() {
        let is_reset = |task: &&str| task.starts_with('r');
        let mut queue = VecDeque::from(["r1", "r2", "s1", "s2", "s3", "s4"]);
        let mut take = |end| take_next(&mut queue, end, is_reset);
        assert_eq!(take(End::Back), Some("r1"));
        assert_eq!(take(End::Back), Some("r2"));
        assert_eq!(take(End::Back), Some("s4"));
        assert_eq!(take(End::Front), Some("s1"));
        assert_eq!(take(End::Back), Some("s3"));
        assert_eq!(take(End::Front), Some("s2"));
        assert_eq!(take(End::Front), None);
        assert_eq!(take(End::Back), None);
    }

    /// A batch of `config` on `threads` threads, its episodes reset to `seeds`.
    fn started(config: EpisodeConfig, seeds: &[u64], threads: usize) -> EpisodeBatch {
        let checked = Checked::new(config).unwrap();
        EpisodeBatch::started(checked, seeds, Some(threads)).unwrap()
    }

    /// Every observation and info after each run of mixed commands (resets, holds, steps in
    /// random order) on a batch of `n` episodes and `threads` threads.
    fn trace(
        action_mode: ActionMode,
        n: usize,
        threads: usize,
    ) -> Vec<(Vec<u8>, Vec<f32>, Vec<StepInfo>)> {
        let config = EpisodeConfig {
            action_mode,
            ..EpisodeConfig::default()
        };
        assert_eq!(config.map.mode, MapMode::Gpis, "the grid tiles are shared");
        let counts = config.probe.counts();
        let seeds: Vec<u64> = (0..n as u64).collect();
        let mut batch = started(config, &seeds, threads);
        if threads <= n {
            assert_eq!(batch.threads(), threads);
        }
        let mut maps = vec![0u8; n * batch.map_len()];
        let mut proprio = vec![0f32; n * PROPRIO_LEN];
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let mut out = Vec::new();
        for round in 0..8u64 {
            let commands: Vec<Command> = (0..n)
                .map(|i| match rng.random_range(0..6) {
                    _ if batch.episodes()[i].last_info().terminated => Command::Reset(100 + round),
                    0 => Command::Reset(10 * round + i as u64),
                    1 => Command::Hold,
                    _ => Command::Step(match action_mode {
                        ActionMode::Wrist => {
                            Action::Wrist([0; 3].map(|_| rng.random_range(-1.0..1.0)))
                        }
                        ActionMode::Probe => {
                            Action::Probe([0, 1, 2].map(|k| rng.random_range(0..counts[k]) as i64))
                        }
                    }),
                })
                .collect();
            batch.run(&commands, &mut maps, &mut proprio).unwrap();
            let infos = batch.episodes().iter().map(|e| *e.last_info()).collect();
            out.push((maps.clone(), proprio.clone(), infos));
        }
        out
    }

    #[test]
    fn mixed_resets_holds_and_steps_give_the_same_results_on_any_thread_count() {
        for action_mode in [ActionMode::Wrist, ActionMode::Probe] {
            let one = trace(action_mode, 6, 1);
            for threads in [2, 3, 6] {
                assert!(
                    one == trace(action_mode, 6, threads),
                    "{action_mode:?}: {threads} threads differ from one"
                );
            }
        }
    }

    /// A batch of one episode (the single env) with a helper thread, which takes tiles of
    /// its resets' grid updates, gives what one thread gives.
    #[test]
    fn a_batch_of_one_with_a_helper_gives_the_same_results_as_one_thread() {
        for action_mode in [ActionMode::Wrist, ActionMode::Probe] {
            assert!(
                trace(action_mode, 1, 1) == trace(action_mode, 1, 2),
                "{action_mode:?}: a helper changes a batch of one"
            );
        }
    }

    #[test]
    fn the_first_failing_episode_is_reported_though_resets_run_first() {
        let mut config = EpisodeConfig::default();
        config.map.mode = MapMode::None;
        let n = 4;
        let mut batch = started(config, &[0, 1, 2, 3], 2);
        let mut proprio = vec![0f32; n * PROPRIO_LEN];
        let ended = |batch: &EpisodeBatch| -> Vec<usize> {
            (0..n)
                .filter(|&i| batch.episodes()[i].last_info().terminated)
                .collect()
        };
        // The oracle ends episodes (success); ended ones hold until two have ended.
        for _ in 0..400 {
            if ended(&batch).len() >= 2 {
                break;
            }
            let commands: Vec<Command> = batch
                .episodes()
                .iter()
                .map(|e| match e.last_info().terminated {
                    true => Command::Hold,
                    false => Command::Step(oracle_action(e).into()),
                })
                .collect();
            batch.run(&commands, &mut [], &mut proprio).unwrap();
        }
        let ended = ended(&batch);
        assert!(ended.len() >= 2, "the oracle ended only {ended:?}");
        // Step every ended episode (each fails) and reset the last episode (queued first).
        let commands: Vec<Command> = (0..n)
            .map(|i| match i {
                _ if ended.contains(&i) => Command::Step([0.0; 3].into()),
                _ if i == n - 1 => Command::Reset(77),
                _ => Command::Hold,
            })
            .collect();
        let error = batch.run(&commands, &mut [], &mut proprio).unwrap_err();
        assert!(
            matches!(error, EpisodeError::InEpisode { index, .. } if index == ended[0]),
            "{error} (ended: {ended:?})"
        );
        if !ended.contains(&(n - 1)) {
            assert_eq!(
                batch.episodes()[n - 1].last_info().steps,
                0,
                "the reset ran"
            );
        }
    }
}
