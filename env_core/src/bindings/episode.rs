//! `_core.EpisodeBatch`: N mechanical-search episodes stepped in parallel without the GIL.
//! The single environment uses a batch of one; the vector environments a batch of N.
//!
//! A step converts the actions once, releases the GIL while every episode steps (or
//! resets) and writes its observation straight into the batch's numpy arrays
//! ([`BatchArrays`], allocated once), then writes rewards, flags and the info columns in
//! place: no staging buffer, no per-step array or per-env dict.

use std::time::Instant;

use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use super::actions::actions_of;
use super::batch_arrays::BatchArrays;
use super::convert::{count_of, seed_of, threads_of};
use super::decode::{geometry_dict, map_dict, probe_motions, proprio_dict};
use super::episode_config::{episode_config_of, PyEpisodeConfig};
use super::errors::{episode_index_error, wrong_type, wrong_value};
use super::exclusive::Exclusive;
use super::step_info::info_dict;
use crate::episode::action_mode::action_len;
use crate::episode::maps::GridValues;
use crate::episode::metrics::{footprint_of, footprints_mask};
use crate::episode::{
    oracle_action, ActionMode, Claim, Command, EpisodeBatch, EpisodeConfig, EpisodeError,
    PROPRIO_LEN,
};
use crate::gpis::GridSpec;
use crate::scene::JarState;
use crate::settings::{Checked, Choice};

/// N episodes with one configuration (see `tactile_search.CupboardSearchEnv`).
#[pyclass(name = "EpisodeBatch", module = "tactile_search._core", frozen)]
pub struct PyEpisodeBatch {
    /// The settings, fixed at construction (readable while another call runs).
    config: Checked<EpisodeConfig>,
    num_envs: usize,
    state: Exclusive<BatchState>,
}

/// What a call on the batch uses: the episodes and the arrays they write.
struct BatchState {
    inner: EpisodeBatch,
    arrays: BatchArrays,
    /// Wall-clock seconds spent with the GIL released in the episodes' work (benchmarks
    /// read it to split a step into its parallel and serial parts).
    parallel_seconds: f64,
}

impl BatchState {
    fn episode_index(&self, index: usize) -> PyResult<usize> {
        if index < self.inner.len() {
            Ok(index)
        } else {
            Err(episode_index_error(index, self.inner.len()))
        }
    }

    /// Runs `commands` with the GIL released, writing observations in place, then the
    /// results (all episodes', or only episode `only`'s).
    fn run(&mut self, py: Python<'_>, commands: &[Command], only: Option<usize>) -> PyResult<()> {
        let inner = &mut self.inner;
        let started = Instant::now();
        let ran = self.arrays.with_observation(py, |maps, proprio| {
            py.detach(|| inner.run(commands, maps, proprio))
        });
        self.parallel_seconds += started.elapsed().as_secs_f64();
        ran??;
        self.arrays.write_results(py, &self.inner, commands, only)
    }

    /// Turns the commands of `resets`, a list of (index, seed), into resets.
    fn set_resets(&self, commands: &mut [Command], resets: &Bound<'_, PyAny>) -> PyResult<()> {
        const EXPECTED: &str = "a list of (index, seed) pairs";
        for pair in resets
            .try_iter()
            .map_err(|_| wrong_type("resets", EXPECTED, resets))?
        {
            let (index, seed): (usize, Bound<'_, PyAny>) = pair?
                .extract()
                .map_err(|_| wrong_type("resets", EXPECTED, resets))?;
            commands[self.episode_index(index)?] = Command::Reset(seed_of(&seed)?);
        }
        Ok(())
    }

    /// Episode `index`'s observation as a dict of fresh arrays (a copy of its rows).
    fn observation_of<'py>(&self, py: Python<'py>, index: usize) -> PyResult<Bound<'py, PyDict>> {
        let (maps, proprio) = self.arrays.observation(py);
        let d = PyDict::new(py);
        if let Some(maps) = maps {
            d.set_item("map", maps.get_item(index)?.call_method0("copy")?)?;
        }
        d.set_item("proprio", proprio.get_item(index)?.call_method0("copy")?)?;
        Ok(d)
    }
}

impl PyEpisodeBatch {
    /// A step for every episode, with its row of `actions` (N, 3) read in the batch's
    /// action mode.
    fn step_commands(&self, actions: &Bound<'_, PyAny>) -> PyResult<Vec<Command>> {
        let actions = actions_of(
            "actions",
            actions,
            Some(self.num_envs),
            self.config.action_mode,
            self.config.task.claims(),
        )?;
        Ok(actions.into_iter().map(Command::Step).collect())
    }
}

#[pymethods]
impl PyEpisodeBatch {
    /// `num_envs` episodes of `config` (an `EpisodeConfig`, checked when it was made), none
    /// started: `reset` or `reset_many` starts each (until then a step raises and the
    /// observation is zeros). `threads`: see the `threads` getter; None uses every core.
    #[new]
    #[pyo3(signature = (config, num_envs, threads = None))]
    fn new(
        py: Python<'_>,
        config: &Bound<'_, PyAny>,
        num_envs: &Bound<'_, PyAny>,
        threads: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let config = episode_config_of(config)?;
        let num_envs = count_of("num_envs", num_envs)?;
        let threads = threads_of(threads)?;
        let built = config.clone();
        let inner = py
            .detach(|| EpisodeBatch::new(built, num_envs, threads))
            .map_err(PyErr::from)?;
        let n = inner.len();
        let channels = config.map.mode.kind().channels.len();
        let (h, w) = config.map.grid_shape;
        let map = (channels > 0).then_some([channels, h, w]);
        let state = BatchState {
            inner,
            arrays: BatchArrays::new(py, n, map)?,
            parallel_seconds: 0.0,
        };
        state.arrays.with_observation(py, |maps, proprio| {
            state.inner.write_observations(maps, proprio)
        })??;
        let holds = vec![Command::Hold; n];
        state.arrays.write_results(py, &state.inner, &holds, None)?;
        Ok(Self {
            config,
            num_envs: n,
            state: Exclusive::new("EpisodeBatch (the core of an environment)", state),
        })
    }

    /// The batch's settings, the `EpisodeConfig` it was made with.
    #[getter]
    fn config(&self) -> PyEpisodeConfig {
        PyEpisodeConfig {
            checked: self.config.clone(),
        }
    }

    /// Resets episode `index` to `seed` (the GIL released) and writes only its entries of
    /// the batch's arrays (observation, reward 0, flags False, the reset's info).
    fn reset(&self, py: Python<'_>, index: usize, seed: &Bound<'_, PyAny>) -> PyResult<()> {
        let seed = seed_of(seed)?;
        let mut state = self.state.lock()?;
        let index = state.episode_index(index)?;
        let mut commands = vec![Command::Hold; self.num_envs];
        commands[index] = Command::Reset(seed);
        state.run(py, &commands, Some(index))
    }

    /// Resets the episodes of `resets`, a list of (index, seed), in parallel (the GIL
    /// released) and writes their entries of the batch's arrays.
    fn reset_many(&self, py: Python<'_>, resets: &Bound<'_, PyAny>) -> PyResult<()> {
        let mut state = self.state.lock()?;
        let mut commands = vec![Command::Hold; self.num_envs];
        state.set_resets(&mut commands, resets)?;
        state.run(py, &commands, None)
    }

    /// The batch's observation arrays: maps (N, 2, H, W) uint8 or None, proprio (N, 11)
    /// float32. The same arrays every call, overwritten by every step and reset.
    #[allow(clippy::type_complexity)]
    fn observe<'py>(
        &self,
        py: Python<'py>,
    ) -> PyResult<(Option<Bound<'py, PyAny>>, Bound<'py, PyAny>)> {
        Ok(self.state.lock()?.arrays.observation(py))
    }

    /// Episode `index`'s observation as a dict of fresh arrays (`"map"`, `"proprio"`).
    fn observation<'py>(&self, py: Python<'py>, index: usize) -> PyResult<Bound<'py, PyDict>> {
        let state = self.state.lock()?;
        let index = state.episode_index(index)?;
        state.observation_of(py, index)
    }

    /// Steps every episode with its row of `actions` (N, 3) in [-1, 1] (clipped), except
    /// the episodes of `resets` (a list of (index, seed)), which start over instead (the
    /// vector env's autoreset: reward 0, flags False, the reset's info). Returns (maps,
    /// proprio, rewards (N,), terminated (N,), truncated (N,), info): the batch's own arrays,
    /// written in place and overwritten by the next step or reset; info is a dict of one
    /// array (N,) per key of `step_info_fields()`. The episodes of `holds` (a list of
    /// indices) are left untouched, their action ignored (a pickled vector env replaying
    /// its episodes). Raises `ValueError` for actions of the wrong shape or not finite
    /// (before any episode moves) and names the episode of a failed step (a step after
    /// termination).
    #[allow(clippy::type_complexity)]
    #[pyo3(signature = (actions, resets = None, holds = None))]
    fn step<'py>(
        &self,
        py: Python<'py>,
        actions: &Bound<'py, PyAny>,
        resets: Option<&Bound<'py, PyAny>>,
        holds: Option<Vec<usize>>,
    ) -> PyResult<(
        Option<Bound<'py, PyAny>>,
        Bound<'py, PyAny>,
        Bound<'py, PyArray1<f64>>,
        Bound<'py, PyArray1<bool>>,
        Bound<'py, PyArray1<bool>>,
        Bound<'py, PyDict>,
    )> {
        let mut commands = self.step_commands(actions)?;
        let mut state = self.state.lock()?;
        if let Some(resets) = resets {
            state.set_resets(&mut commands, resets)?;
        }
        for index in holds.unwrap_or_default() {
            commands[state.episode_index(index)?] = Command::Hold;
        }
        state.run(py, &commands, None)?;
        let (maps, proprio) = state.arrays.observation(py);
        let (rewards, terminated, truncated, info) = state.arrays.results(py);
        Ok((maps, proprio, rewards, terminated, truncated, info))
    }

    /// stable-baselines3's step, in one call: steps every episode with its row of `actions`
    /// (N, 3); each episode that ended (terminated or truncated) starts over at once on the
    /// next unused seed of `seeds` (N ints; the k-th ended episode, in index order, takes
    /// `seeds[k]`). Returns (observation dict of fresh arrays: the new episodes' first
    /// observations, rewards (N,) float32, dones (N,) bool, infos): one dict of Python
    /// scalars per episode, its step's info; an ended episode's also holds
    /// `terminal_observation` (its last observation), `TimeLimit.truncated` and
    /// `is_success`. The steps run in parallel, then the resets. Raises as `step` does,
    /// before any episode moves.
    #[allow(clippy::type_complexity)]
    fn step_autoreset<'py>(
        &self,
        py: Python<'py>,
        actions: &Bound<'py, PyAny>,
        seeds: &Bound<'py, PyAny>,
    ) -> PyResult<(
        Bound<'py, PyDict>,
        Bound<'py, PyArray1<f32>>,
        Bound<'py, PyArray1<bool>>,
        Bound<'py, PyList>,
    )> {
        let n = self.num_envs;
        let commands = self.step_commands(actions)?;
        let seeds: Vec<u64> = seeds
            .try_iter()
            .map_err(|_| wrong_type("seeds", "a sequence of ints", seeds))?
            .map(|seed| seed_of(&seed?))
            .collect::<PyResult<_>>()?;
        if seeds.len() != n {
            return Err(wrong_value(
                "seeds",
                &format!("{n} seeds (one per episode)"),
                seeds.len(),
            ));
        }
        let mut state = self.state.lock()?;
        state.run(py, &commands, None)?;
        let mut rewards = Vec::with_capacity(n);
        let mut dones = Vec::with_capacity(n);
        let infos = PyList::empty(py);
        let mut resets = vec![Command::Hold; n];
        let mut unused_seeds = seeds.into_iter();
        for (index, episode) in state.inner.episodes().iter().enumerate() {
            let info = episode.last_info();
            let done = info.terminated || info.truncated;
            rewards.push(info.reward as f32);
            dones.push(done);
            let dict = info_dict(py, info)?;
            if done {
                dict.set_item("terminal_observation", state.observation_of(py, index)?)?;
                dict.set_item("TimeLimit.truncated", info.truncated)?;
                dict.set_item("is_success", info.success)?;
                if let Some(seed) = unused_seeds.next() {
                    resets[index] = Command::Reset(seed);
                }
            }
            infos.append(dict)?;
        }
        if resets.iter().any(|c| matches!(c, Command::Reset(_))) {
            state.run(py, &resets, None)?;
        }
        let (maps, proprio) = state.arrays.observation(py);
        let observation = PyDict::new(py);
        if let Some(maps) = maps {
            observation.set_item("map", maps.call_method0("copy")?)?;
        }
        observation.set_item("proprio", proprio.call_method0("copy")?)?;
        Ok((
            observation,
            PyArray1::from_vec(py, rewards),
            PyArray1::from_vec(py, dones),
            infos,
        ))
    }

    /// Steps a batch of one with `action` (3,) and returns gymnasium's step tuple for it:
    /// (observation dict of fresh arrays, reward, terminated, truncated, info dict of
    /// Python scalars).
    #[allow(clippy::type_complexity)]
    fn step_single<'py>(
        &self,
        py: Python<'py>,
        action: &Bound<'py, PyAny>,
    ) -> PyResult<(Bound<'py, PyDict>, f64, bool, bool, Bound<'py, PyDict>)> {
        if self.num_envs != 1 {
            return Err(wrong_value(
                "step_single's batch",
                "one episode",
                format!("{} episodes", self.num_envs),
            ));
        }
        let rows = actions_of(
            "action",
            action,
            None,
            self.config.action_mode,
            self.config.task.claims(),
        )?;
        let commands = [Command::Step(rows[0])];
        let mut state = self.state.lock()?;
        let state = &mut *state;
        let inner = &mut state.inner;
        let started = Instant::now();
        let stepped = state.arrays.with_observation(py, |maps, proprio| {
            py.detach(|| inner.run(&commands, maps, proprio))
        });
        state.parallel_seconds += started.elapsed().as_secs_f64();
        let stepped = stepped?;
        // A batch of one: report the episode's own error, without "episode 0: ".
        stepped.map_err(|e| match e {
            EpisodeError::InEpisode { source, .. } => PyErr::from(*source),
            other => PyErr::from(other),
        })?;
        state
            .arrays
            .write_results(py, &state.inner, &commands, None)?;
        let info = state.inner.episodes()[0].last_info();
        Ok((
            state.observation_of(py, 0)?,
            info.reward,
            info.terminated,
            info.truncated,
            info_dict(py, info)?,
        ))
    }

    /// The oracle's actions (N, action_len): it knows the target (the upper-bound
    /// baseline). Wrist motions, and a claim once it touches the target where the task
    /// claims: `ValueError` in the `probe` action mode.
    fn oracle_actions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        if self.config.action_mode != ActionMode::Wrist {
            return Err(wrong_value(
                "action_mode",
                "'wrist' for the oracle's actions (wrist motions)",
                self.config.action_mode.name(),
            ));
        }
        let claims = self.config.task.claims();
        let flat: Vec<f64> = self
            .state
            .lock()?
            .inner
            .episodes()
            .iter()
            .flat_map(|episode| {
                oracle_action(episode)
                    .to_wrist_row(claims)
                    .expect("the oracle acts in the wrist mode")
            })
            .collect();
        PyArray1::from_vec(py, flat).reshape([self.num_envs, action_len(claims)])
    }

    /// The metrics of episode `index`'s last reset or step, as a dict of Python scalars.
    fn info<'py>(&self, py: Python<'py>, index: usize) -> PyResult<Bound<'py, PyDict>> {
        let state = self.state.lock()?;
        let index = state.episode_index(index)?;
        info_dict(py, state.inner.episodes()[index].last_info())
    }

    /// The wrist motions episode `index`'s last step made, (k, 3) `wrist`-mode actions
    /// (`Episode::last_motions`): replayed in a `wrist`-mode env of the same settings and
    /// layout, they draw a probe motion by motion.
    fn last_motions<'py>(
        &self,
        py: Python<'py>,
        index: usize,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let state = self.state.lock()?;
        let index = state.episode_index(index)?;
        let motions = state.inner.episodes()[index].last_motions();
        let flat: Vec<f64> = motions.iter().flatten().copied().collect();
        PyArray1::from_vec(py, flat).reshape([motions.len(), 3])
    }

    /// The batch's info arrays: a dict of one array (N,) per key of `step_info_fields()`,
    /// the same arrays every call, overwritten by every step and reset.
    fn info_arrays<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        Ok(self.state.lock()?.arrays.results(py).3)
    }

    /// Every episode's info, as a list of dicts of Python scalars (stable-baselines3's
    /// per-env `infos`).
    fn infos<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let infos = PyList::empty(py);
        for episode in self.state.lock()?.inner.episodes() {
            infos.append(info_dict(py, episode.last_info())?)?;
        }
        Ok(infos)
    }

    /// Ground truth and map of episode `index` for rendering: jars (shape name, centre,
    /// yaw, half width, tilt, whether the target, whether a hidden decoy), the last step's
    /// `claim` (`{"jar", "correct"}`, None without one), `touched_jar` (the jar a claim
    /// would name now, `Episode::touched_jar`: None when the finger touches none), the map task's reconstruction
    /// `score_mean` (its GPIS mean grid, None in other tasks), hand, finger, contacts, the hand's
    /// sizes, the map's bounds, its grids by name under `map` (`mean` and `std` for gpis,
    /// `occupancy`; none in the `none` mode, in the order of the mode's channels), and,
    /// given `pixels_per_metre`, `jar_pixels`: which jar covers each pixel (its index, -1
    /// for none) of an image at that resolution over the map's bounds widened by
    /// `in_front` metres before the opening, row 0 at the back of the cupboard.
    /// `RuntimeError` before the first reset.
    #[pyo3(signature = (index, pixels_per_metre = None, in_front = 0.0))]
    fn render_state<'py>(
        &self,
        py: Python<'py>,
        index: usize,
        pixels_per_metre: Option<f64>,
        in_front: f64,
    ) -> PyResult<Bound<'py, PyDict>> {
        if let Some(ppm) = pixels_per_metre.filter(|p| !(p.is_finite() && *p > 0.0)) {
            return Err(wrong_value("pixels_per_metre", "finite and > 0", ppm));
        }
        if !(in_front.is_finite() && in_front >= 0.0) {
            return Err(wrong_value("in_front", "finite and >= 0", in_front));
        }
        let state = self.state.lock()?;
        let index = state.episode_index(index)?;
        let episode = &state.inner.episodes()[index];
        if !episode.is_started() {
            return Err(PyRuntimeError::new_err(format!(
                "episode {index} has not started: call reset() before rendering it"
            )));
        }
        let scene = episode.scene();
        let d = PyDict::new(py);
        let jars = PyList::empty(py);
        let jar_states = scene.jar_states();
        for (i, jar) in jar_states.iter().enumerate() {
            let j = PyDict::new(py);
            j.set_item("shape", jar.spec.shape.name())?;
            j.set_item("x", jar.position[0])?;
            j.set_item("y", jar.position[1])?;
            j.set_item("yaw", crate::episode::metrics::yaw_of(jar.rotation))?;
            j.set_item("half_width", jar.spec.shape.half_width())?;
            j.set_item("tilt", jar.disturbance.tilt)?;
            let target = self.config.task.has_target() && i == scene.target();
            j.set_item("is_target", target)?;
            j.set_item("is_decoy", scene.layout().decoys.contains(&i))?;
            jars.append(j)?;
        }
        d.set_item("jars", jars)?;
        // The last step's claim: the jar it named (None with none touched) and whether it was
        // the target; None when the last step made no claim.
        let info = episode.last_info();
        if self.config.task.claims() && (info.success || info.wrong_claim) {
            let claim = PyDict::new(py);
            claim.set_item("jar", info.claimed_jar)?;
            claim.set_item("correct", info.success)?;
            d.set_item("claim", claim)?;
        } else {
            d.set_item("claim", py.None())?;
        }
        d.set_item("touched_jar", episode.touched_jar())?;
        let hand = scene.hand_pose();
        d.set_item("hand", (hand.x, hand.y, hand.yaw))?;
        let finger = scene.finger_pose();
        d.set_item("finger", (finger.x, finger.y, finger.yaw))?;
        let hand_config = &self.config.scene.hand;
        d.set_item("finger_length", hand_config.finger_length)?;
        d.set_item("wrist_half_extent", hand_config.wrist_half_extent)?;
        d.set_item("arm_length", hand_config.arm_length)?;
        d.set_item("arm_half_width", hand_config.arm_half_width)?;
        let contacts: Vec<[f64; 4]> = scene
            .contacts()
            .iter()
            .map(|c| [c.point[0], c.point[1], c.normal[0], c.normal[1]])
            .collect();
        d.set_item("contacts", contacts)?;
        let bounds = episode.grid().bounds();
        d.set_item("bounds", bounds)?;
        let (h, w) = episode.grid().shape();
        let map = PyDict::new(py);
        for (name, values) in episode.map().render_grids() {
            let grid = match values {
                GridValues::F64(v) => PyArray1::from_vec(py, v).reshape([h, w])?.into_any(),
                GridValues::F32(v) => PyArray1::from_vec(py, v).reshape([h, w])?.into_any(),
            };
            map.set_item(name, grid)?;
        }
        d.set_item("map", map)?;
        // The map task's reconstruction, which its score is measured on (None elsewhere).
        match episode.map_score() {
            Some(score) => {
                let mean = PyArray1::from_vec(py, score.mean_grid().to_vec()).reshape([h, w])?;
                d.set_item("score_mean", mean)?;
            }
            None => d.set_item("score_mean", py.None())?,
        }
        let Some(pixels_per_metre) = pixels_per_metre else {
            return Ok(d);
        };
        let [[x0, x1], [y0, y1]] = bounds;
        let pixels = GridSpec::new(
            [[x0, x1], [y0 - in_front, y1]],
            (
                ((y1 - y0 + in_front) * pixels_per_metre).round().max(1.0) as usize,
                ((x1 - x0) * pixels_per_metre).round().max(1.0) as usize,
            ),
        )?;
        let (rows, columns) = pixels.shape();
        let labels = jar_labels(&pixels, &jar_states);
        // Row 0 of the image at the back (y1): the grid's rows run from y0 up.
        let flipped: Vec<i8> = labels.chunks(columns).rev().flatten().copied().collect();
        d.set_item(
            "jar_pixels",
            PyArray1::from_vec(py, flipped).reshape([rows, columns])?,
        )?;
        Ok(d)
    }

    /// Wall-clock seconds this batch has spent in its episodes' work with the GIL
    /// released (steps, resets and their observations); the rest of a call is serial.
    #[getter]
    fn parallel_seconds(&self) -> PyResult<f64> {
        Ok(self.state.lock()?.parallel_seconds)
    }

    /// The threads the batch runs its episodes on: its pool's workers, or the calling thread
    /// alone (more than the episodes only to share resets' grid updates, up to the cores).
    #[getter]
    fn threads(&self) -> PyResult<usize> {
        Ok(self.state.lock()?.inner.threads())
    }

    /// Number of episodes.
    #[getter]
    fn num_envs(&self) -> usize {
        self.num_envs
    }

    /// (H, W) of the map grid.
    #[getter]
    fn grid_shape(&self) -> (usize, usize) {
        self.config.map.grid_shape
    }

    /// `"gpis"`, `"occupancy"` or `"none"`.
    #[getter]
    fn map_mode(&self) -> &'static str {
        self.config.map.mode.name()
    }

    /// Length of the proprioception vector.
    #[getter]
    fn proprio_len(&self) -> usize {
        PROPRIO_LEN
    }

    /// `"wrist"` or `"probe"`: what an action is.
    #[getter]
    fn action_mode(&self) -> &'static str {
        self.config.action_mode.name()
    }

    /// The `probe` action mode's index counts `(lanes, depths, sweeps)` (None in the
    /// `wrist` mode).
    #[getter]
    fn probe_counts(&self) -> Option<[usize; 3]> {
        (self.config.action_mode == ActionMode::Probe).then(|| self.config.probe.counts())
    }

    /// `"search"` or `"identify"`: what the episode asks.
    #[getter]
    fn task(&self) -> &'static str {
        self.config.task.name()
    }

    /// Entries of one action: 3, and the claim entry (4) where the task claims. In the
    /// `probe` mode the claim entry's count is `Claim.PROBE_CHOICES` (2: probe or claim);
    /// in the `wrist` mode it claims above `claim_threshold`.
    #[getter]
    fn action_len(&self) -> usize {
        action_len(self.config.task.claims())
    }

    /// The `MultiDiscrete` space's `nvec` in the `probe` mode: the probe counts, and the
    /// claim entry's where the task claims (None in the `wrist` mode).
    #[getter]
    fn probe_nvec(&self) -> Option<Vec<usize>> {
        let counts = self.probe_counts()?;
        let claim = self.config.task.claims().then_some(Claim::PROBE_CHOICES);
        Some(counts.into_iter().chain(claim).collect())
    }

    /// The wrist mode's claim entry claims above this value (where the task claims).
    #[getter]
    fn claim_threshold(&self) -> f64 {
        Claim::WRIST_THRESHOLD
    }

    /// The hand's largest translation (m) and yaw (rad) per step: the action scale.
    #[getter]
    fn action_scale(&self) -> (f64, f64) {
        let hand = &self.config.scene.hand;
        (hand.max_step_translation, hand.max_step_yaw)
    }

    /// The map's bounds ((x0, x1), (y0, y1)).
    #[getter]
    fn map_bounds(&self) -> [[f64; 2]; 2] {
        self.config.map_bounds()
    }

    /// One map image `(C, H, W)` uint8 of this batch's map mode decoded to float64 `(H, W)`
    /// arrays by name: `mean` and `std` (m) for `gpis`, `occupied` (a probability) for
    /// `occupancy`. `TypeError` for anything but a uint8 array, `ValueError` for another
    /// shape or in the `none` mode (no image).
    fn decode_map<'py>(
        &self,
        py: Python<'py>,
        image: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyDict>> {
        map_dict(py, &self.config, image)
    }

    /// One proprio vector `(11,)` float32 decoded to its physical quantities by name (x, y,
    /// yaw, deflection, in_contact, contact_dx, contact_dy, normal_x, normal_y, time_left,
    /// steps). `TypeError` for anything but a float32 array, `ValueError` for another shape.
    fn decode_proprio<'py>(
        &self,
        py: Python<'py>,
        proprio: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyDict>> {
        proprio_dict(py, &self.config, proprio)
    }

    /// The static geometry a planner may know, from the settings alone (no scene): the
    /// cupboard, camera, hand sizes and bounds, jar radius range, map grid and its cells'
    /// centres `xs`, `ys` (H, W), and the `probe` action mode's probes per action index
    /// (`probe_lanes` x, `probe_depths` y, `probe_yaws`; `probe_outside`, the y the
    /// controller backs out to before changing lanes; `probe_sweep_rate`).
    fn geometry<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        geometry_dict(py, &self.config)
    }

    /// The wrist motions the `probe` mode's controller makes from the wrist `pose` (x, y,
    /// yaw; m, m, rad) to finish each probe of `actions` (an `(n, 3)` int64 array of lane,
    /// depth and sweep indices) when nothing touches or blocks the hand: an `(n,)` int64
    /// array, from the settings alone (no scene). What a planner choosing probes weighs
    /// them by. `TypeError` for anything but an int64 array, `ValueError` for another
    /// shape, an index outside the counts or a non-finite pose.
    fn probe_motions<'py>(
        &self,
        py: Python<'py>,
        pose: [f64; 3],
        actions: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray1<i64>>> {
        probe_motions(py, &self.config, pose, actions)
    }
}

/// Which jar covers each cell of `grid` (row-major, row 0 at the grid's y0): the jar's
/// index, or -1.
fn jar_labels(grid: &GridSpec, jars: &[JarState]) -> Vec<i8> {
    let mut labels = vec![-1i8; grid.n_cells()];
    let mut mask = Vec::new();
    for (index, jar) in jars.iter().enumerate() {
        footprints_mask(grid, [footprint_of(jar)], 0.0, &mut mask);
        let label = i8::try_from(index).expect("a layout holds at most MAX_JARS (16) jars");
        for (cell, &covered) in labels.iter_mut().zip(&mask) {
            if covered {
                *cell = label;
            }
        }
    }
    labels
}
