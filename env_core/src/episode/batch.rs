//! A batch of episodes stepped in parallel: the core of the vector environment.
//!
//! Episodes are split into one contiguous chunk per worker thread of the batch's own rayon
//! pool (kept alive: spawning threads every step would cost as much as a step); each worker
//! steps its episodes and writes their observations into its own slices of the caller's
//! buffers, so results do not depend on the thread count.

use std::num::NonZeroUsize;
use std::thread;

use rayon::prelude::*;
use rayon::{ThreadPool, ThreadPoolBuilder};

use super::config::EpisodeConfig;
use super::episode::{Episode, StepInfo, PROPRIO_LEN};
use super::error::EpisodeError;

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

    /// Resets episode `index` to `seed`.
    pub fn reset(&mut self, index: usize, seed: u64) -> Result<(), EpisodeError> {
        self.episodes[index].reset(seed)
    }

    fn map_len(&self) -> usize {
        self.episodes.first().map_or(0, Episode::map_len)
    }

    /// Writes every episode's observation (maps: N × map_len, proprio: N × PROPRIO_LEN).
    pub fn write_observations(
        &self,
        maps: &mut [u8],
        proprio: &mut [f32],
    ) -> Result<(), EpisodeError> {
        self.check_buffers(maps, proprio)?;
        let map_len = self.map_len();
        for (i, episode) in self.episodes.iter().enumerate() {
            episode.write_map(&mut maps[i * map_len..(i + 1) * map_len])?;
            episode.write_proprio(&mut proprio[i * PROPRIO_LEN..(i + 1) * PROPRIO_LEN])?;
        }
        Ok(())
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

    /// Steps episode i with `actions[i]` on all worker threads and writes every episode's
    /// observation. An episode whose action is `None` is not stepped (the vector
    /// environment's autoreset: it was just reset) and gets `None`. Returns one result per
    /// episode (an episode's error does not stop the others). Cost: the slowest chunk.
    #[allow(clippy::type_complexity)]
    pub fn step(
        &mut self,
        actions: &[Option<[f64; 3]>],
        maps: &mut [u8],
        proprio: &mut [f32],
    ) -> Result<Vec<Option<Result<StepInfo, EpisodeError>>>, EpisodeError> {
        let n = self.episodes.len();
        if actions.len() != n {
            return Err(EpisodeError::BufferLength {
                what: "actions",
                expected: n,
                got: actions.len(),
            });
        }
        self.check_buffers(maps, proprio)?;
        let map_len = self.map_len();
        let chunk = n.div_ceil(self.threads).max(1);
        let n_chunks = n.div_ceil(chunk);
        // Without a map (`none` mode) every episode writes into an empty slice.
        let map_chunks: Vec<&mut [u8]> = if map_len == 0 {
            (0..n_chunks).map(|_| &mut [][..]).collect()
        } else {
            maps.chunks_mut(chunk * map_len).collect()
        };
        let mut results: Vec<Option<Result<StepInfo, EpisodeError>>> = Vec::with_capacity(n);
        if n_chunks == 1 {
            // One chunk: step on the calling thread (a spawn costs more than a small step).
            let maps = map_chunks.into_iter().next().expect("one chunk");
            results.extend(step_chunk(
                &mut self.episodes,
                actions,
                maps,
                proprio,
                map_len,
            ));
            return Ok(results);
        }
        let episodes = &mut self.episodes;
        let chunks: Vec<_> = self.pool.install(|| {
            episodes
                .par_chunks_mut(chunk)
                .zip(actions.par_chunks(chunk))
                .zip(map_chunks.into_par_iter())
                .zip(proprio.par_chunks_mut(chunk * PROPRIO_LEN))
                .map(|(((episodes, actions), maps), proprio)| {
                    step_chunk(episodes, actions, maps, proprio, map_len)
                })
                .collect()
        });
        results.extend(chunks.into_iter().flatten());
        Ok(results)
    }
}

/// Steps one chunk of episodes and writes their observations into the chunk's slices.
fn step_chunk(
    episodes: &mut [Episode],
    actions: &[Option<[f64; 3]>],
    maps: &mut [u8],
    proprio: &mut [f32],
    map_len: usize,
) -> Vec<Option<Result<StepInfo, EpisodeError>>> {
    let mut out = Vec::with_capacity(episodes.len());
    for (i, (episode, &action)) in episodes.iter_mut().zip(actions).enumerate() {
        let result = action.map(|a| episode.step(a));
        let written = episode
            .write_map(&mut maps[i * map_len..(i + 1) * map_len])
            .and_then(|()| {
                episode.write_proprio(&mut proprio[i * PROPRIO_LEN..(i + 1) * PROPRIO_LEN])
            });
        out.push(match (result, written) {
            (Some(Ok(info)), Ok(())) => Some(Ok(info)),
            (Some(Err(error)), _) | (_, Err(error)) => Some(Err(error)),
            (None, Ok(())) => None,
        });
    }
    out
}
