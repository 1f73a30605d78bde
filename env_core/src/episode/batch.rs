//! A batch of episodes stepped in parallel: the core of the vector environments.
//!
//! One call to [`EpisodeBatch::run`] gives each episode a [`Command`] (step with an action,
//! reset to a seed, or hold) and carries them out on the batch's own rayon pool of
//! `threads` workers, kept alive (spawning threads every call would cost as much as a
//! step); the calling thread waits meanwhile. The tasks, one per episode that steps or
//! resets, are a parallel iterator, resets first: a reset costs as much as about 150 wrist
//! steps, so one started last would leave the other threads idle while it runs alone.
//! Even first, a reset outlasts the other threads' share of a wrist-mode step; so each
//! episode's grid updates and a reset's two pieces are parallel iterators too
//! ([`PoolTiles`]), which a worker with no episode left steals from the one resetting.
//! Each task writes its episode's observation straight into that episode's rows of the
//! caller's buffers (in the bindings: numpy arrays allocated once per batch), so nothing is
//! staged or copied and results do not depend on the thread count or on which thread ran
//! what. [`EpisodeBatch::write_result`] then writes rewards, flags and infos as columns
//! (O(info fields) per episode, on the calling thread).

use std::num::NonZeroUsize;
use std::sync::Arc;
use std::thread;

use rayon::prelude::*;
use rayon::{ThreadPool, ThreadPoolBuilder};

use super::action_mode::Action;
use super::config::EpisodeConfig;
use super::episode::Episode;
use super::error::EpisodeError;
use super::observation::PROPRIO_LEN;
use super::step_info::InfoColumns;
use crate::gpis::PoolTiles;
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

/// N episodes with the same configuration.
pub struct EpisodeBatch {
    episodes: Vec<Episode>,
    threads: usize,
    /// The pool of `threads` workers (none for one thread).
    pool: Option<Pool>,
}

/// The batch's rayon pool and the process that started its threads.
struct Pool {
    threads: ThreadPool,
    /// See [`EpisodeBatch::restart_pool_after_fork`].
    process: u32,
}

impl Pool {
    /// A pool of `count` workers; every episode's grid updates and reset pieces go to the
    /// pool of the thread that runs them.
    fn start(count: usize, episodes: &mut [Episode]) -> Self {
        for episode in episodes {
            episode.share_tiles(Arc::new(PoolTiles));
        }
        Self {
            threads: ThreadPoolBuilder::new()
                .num_threads(count)
                .build()
                .expect("the OS can start the batch's threads"),
            process: std::process::id(),
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
        let pool = (threads > 1).then(|| Pool::start(threads, &mut episodes));
        Ok(Self {
            episodes,
            threads,
            pool,
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

    /// Threads that carry out a run: the pool's workers (the calling thread with one).
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
    /// A panic in a task reaches the caller once the other threads' tasks have returned.
    /// Cost: the work divided over the threads by work stealing (resets first), plus a
    /// wake-up of the pool's workers; a single step, or one thread, runs on the calling
    /// thread alone.
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
        self.restart_pool_after_fork();
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
        // Resets first (a stable sort: otherwise in episode order).
        tasks.sort_by_key(|task| !matches!(task.command, Command::Reset(_)));
        let resets = tasks
            .first()
            .is_some_and(|task| matches!(task.command, Command::Reset(_)));
        let failure = match &self.pool {
            // A reset's pieces and grid tiles are worth the pool even alone.
            Some(pool) if tasks.len() > 1 || resets => pool.threads.install(|| {
                tasks
                    .into_par_iter()
                    .with_max_len(1)
                    .filter_map(|task| carry_out(task).err())
                    .min_by_key(|(index, _)| *index)
            }),
            _ => tasks
                .into_iter()
                .filter_map(|task| carry_out(task).err())
                .min_by_key(|(index, _)| *index),
        };
        match failure {
            Some((index, error)) => Err(error.in_episode(index)),
            None => Ok(()),
        }
    }

    /// Starts the pool's threads again in a process forked from the one that started them.
    /// A `fork` copies only the forking thread: the child's pool would queue the run's
    /// jobs for threads that are not there, and the run would wait for them for ever
    /// (Python's `multiprocessing` forks a process holding an env). The child's batch
    /// starts a pool of its own instead; the old one is left alone, not dropped: its
    /// threads and whatever locks they held belong to the parent. Cost: a `getpid` per run.
    fn restart_pool_after_fork(&mut self) {
        let Some(pool) = &self.pool else {
            return;
        };
        if pool.process != std::process::id() {
            let count = pool.threads.current_num_threads();
            std::mem::forget(self.pool.take());
            self.pool = Some(Pool::start(count, &mut self.episodes));
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

/// One episode's share of a run: its index, the episode, its command, its map rows, its
/// proprio row.
struct Task<'a> {
    index: usize,
    episode: &'a mut Episode,
    command: Command,
    map: &'a mut [u8],
    proprio: &'a mut [f32],
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
                    false => Command::Step(oracle_action(e)),
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
