//! A batch of episodes stepped in parallel: the core of the vector environments.
//!
//! One call to [`EpisodeBatch::run`] gives each episode a [`Command`] (step with an action,
//! reset to a seed, or hold) and carries them out on the batch's own rayon pool (kept
//! alive: spawning threads every call would cost as much as a step), one task per episode so
//! that a slow reset does not hold up a whole chunk of steps. Each task writes its episode's
//! observation straight into that episode's rows of the caller's buffers (in the bindings:
//! numpy arrays allocated once per batch), so nothing is staged or copied and results do
//! not depend on the thread count. [`EpisodeBatch::write_result`] then writes rewards,
//! flags and infos as columns (O(info fields) per episode, on the calling thread).

use std::num::NonZeroUsize;
use std::thread;

use rayon::prelude::*;
use rayon::{ThreadPool, ThreadPoolBuilder};

use super::config::EpisodeConfig;
use super::episode::Episode;
use super::error::EpisodeError;
use super::observation::PROPRIO_LEN;
use super::step_info::InfoColumns;

/// What [`EpisodeBatch::run`] does with one episode.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Command {
    /// Step with this action (see [`Episode::step`]).
    Step([f64; 3]),
    /// Start the episode of this seed (the vector environment's autoreset).
    Reset(u64),
    /// Leave the episode and its observation rows untouched.
    Hold,
}

/// N episodes with the same configuration.
pub struct EpisodeBatch {
    episodes: Vec<Episode>,
    threads: usize,
    pool: ThreadPool,
}

impl EpisodeBatch {
    /// Episodes seeded `seeds[i]`; `threads = None` uses every available core.
    pub fn new(
        config: EpisodeConfig,
        seeds: &[u64],
        threads: Option<usize>,
    ) -> Result<Self, EpisodeError> {
        let episodes = seeds
            .iter()
            .map(|&seed| Episode::new(config.clone(), seed))
            .collect::<Result<Vec<_>, _>>()?;
        let cores = thread::available_parallelism().map_or(1, NonZeroUsize::get);
        let threads = threads.unwrap_or(cores).clamp(1, episodes.len().max(1));
        let pool = ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("the OS can start the batch's worker threads");
        Ok(Self {
            episodes,
            threads,
            pool,
        })
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

    /// Worker threads.
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
    /// Cost: the slowest worker's share, tasks balanced by work stealing.
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
        let outcomes: Vec<Result<(), EpisodeError>> = if self.threads == 1 || n == 1 {
            // One worker: run on the calling thread (a hand-off costs more than a step).
            self.episodes
                .iter_mut()
                .zip(commands)
                .zip(map_rows)
                .zip(proprio.chunks_mut(PROPRIO_LEN))
                .map(carry_out)
                .collect()
        } else {
            let episodes = &mut self.episodes;
            self.pool.install(|| {
                episodes
                    .par_iter_mut()
                    .zip(commands.par_iter())
                    .zip(map_rows.into_par_iter())
                    .zip(proprio.par_chunks_mut(PROPRIO_LEN))
                    .map(carry_out)
                    .collect()
            })
        };
        match outcomes.into_iter().enumerate().find(|(_, o)| o.is_err()) {
            Some((index, Err(error))) => Err(error.in_episode(index)),
            _ => Ok(()),
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

/// One episode's share of a run: the episode, its command, its map rows, its proprio row.
type Task<'a> = (
    ((&'a mut Episode, &'a Command), &'a mut [u8]),
    &'a mut [f32],
);

/// Carries out one episode's command and writes its observation rows.
fn carry_out((((episode, &command), map), proprio): Task<'_>) -> Result<(), EpisodeError> {
    match command {
        Command::Step(action) => {
            episode.advance(action)?;
        }
        Command::Reset(seed) => episode.reset(seed)?,
        Command::Hold => return Ok(()),
    }
    episode.write_map(map)?;
    episode.write_proprio(proprio)
}
