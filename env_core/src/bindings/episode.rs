//! `_core.EpisodeBatch`: N mechanical-search episodes stepped in parallel without the GIL.
//! The single environment uses a batch of one; the vector environments a batch of N.
//!
//! A step converts the actions once, releases the GIL while every episode steps (or
//! resets) and writes its observation straight into the batch's numpy arrays
//! ([`BatchArrays`], allocated once), then writes rewards, flags and the info columns in
//! place: no staging buffer, no per-step array or per-env dict.

use std::time::Instant;

use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use super::actions::action_rows;
use super::batch_arrays::BatchArrays;
use super::convert::{seed_of, threads_of};
use super::decode::{geometry_dict, map_dict, probe_motions, proprio_dict};
use super::errors::{episode_error, episode_index_error, wrong_type, wrong_value};
use super::exclusive::Exclusive;
use super::settings::{config_dict, config_from, describe};
use super::step_info::info_dict;
use crate::episode::maps::GridValues;
use crate::episode::{
    oracle_action, ActionMode, Command, EpisodeBatch, EpisodeConfig, EpisodeError, PROPRIO_LEN,
};
use crate::scene::JarShape;
use crate::settings::Choice;

/// N episodes with one configuration (see `tactile_search.CupboardSearchEnv`).
#[pyclass(name = "EpisodeBatch", module = "tactile_search._core", frozen)]
pub struct PyEpisodeBatch {
    /// The settings, fixed at construction (readable while another call runs).
    config: EpisodeConfig,
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

#[pymethods]
impl PyEpisodeBatch {
    /// Episodes seeded `seeds[i]`, with the default settings updated by `config` (a dict)
    /// and keyword arguments: every key of `EpisodeBatch.settings()` (the episode's, the
    /// map's, the reward's and the scene's).
    #[new]
    #[pyo3(signature = (seeds, threads = None, config = None, **settings))]
    fn new(
        py: Python<'_>,
        seeds: &Bound<'_, PyAny>,
        threads: Option<&Bound<'_, PyAny>>,
        config: Option<&Bound<'_, PyAny>>,
        settings: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        let seeds: Vec<u64> = seeds
            .try_iter()
            .map_err(|_| wrong_type("seeds", "a sequence of ints", seeds))?
            .map(|s| seed_of(&s?))
            .collect::<PyResult<_>>()?;
        if seeds.is_empty() {
            return Err(wrong_value("seeds", "at least one seed", "none"));
        }
        let threads = threads_of(threads)?;
        let config: EpisodeConfig = config_from(config, settings)?;
        let built = config.clone();
        let inner = py
            .detach(|| EpisodeBatch::new(built, &seeds, threads))
            .map_err(|e| episode_error(0, e))?;
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

    /// The episode's settings table (the scene's included): one dict per setting with key,
    /// type, default, range, choices and doc.
    #[staticmethod]
    fn settings(py: Python<'_>) -> PyResult<Bound<'_, PyList>> {
        describe::<EpisodeConfig>(py)
    }

    /// Checks settings given as keyword arguments (TypeError / ValueError naming the key)
    /// and returns every setting by key: the defaults with the given ones over them.
    #[staticmethod]
    #[pyo3(signature = (**settings))]
    fn resolve_settings<'py>(
        py: Python<'py>,
        settings: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let config: EpisodeConfig = config_from(None, settings)?;
        config_dict(py, &config)
    }

    /// Every setting of this batch by key.
    #[getter]
    fn config<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        config_dict(py, &self.config)
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
        let n = self.num_envs;
        let mut commands: Vec<Command> = action_rows("actions", actions, &[n, 3])?
            .into_iter()
            .map(Command::Step)
            .collect();
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
        let rows = action_rows("action", action, &[3])?;
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

    /// The oracle's actions (N, 3): it knows the target (the upper-bound baseline). Wrist
    /// motions: `ValueError` in the `probe` action mode.
    fn oracle_actions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        if self.config.action_mode != ActionMode::Wrist {
            return Err(wrong_value(
                "action_mode",
                "'wrist' for the oracle's actions (wrist motions)",
                self.config.action_mode.name(),
            ));
        }
        let flat: Vec<f64> = self
            .state
            .lock()?
            .inner
            .episodes()
            .iter()
            .flat_map(oracle_action)
            .collect();
        PyArray1::from_vec(py, flat).reshape([self.num_envs, 3])
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

    /// Ground truth and map of episode `index` for rendering: jars, hand, finger, contacts,
    /// target, the map's bounds, and its mean/std (gpis) or occupancy probability grids.
    fn render_state<'py>(&self, py: Python<'py>, index: usize) -> PyResult<Bound<'py, PyDict>> {
        let state = self.state.lock()?;
        let index = state.episode_index(index)?;
        let episode = &state.inner.episodes()[index];
        let scene = episode.scene();
        let d = PyDict::new(py);
        let jars = PyList::empty(py);
        for (i, jar) in scene.jar_states().iter().enumerate() {
            let j = PyDict::new(py);
            j.set_item("x", jar.position[0])?;
            j.set_item("y", jar.position[1])?;
            j.set_item("yaw", crate::episode::metrics::yaw_of(jar.rotation))?;
            let (shape, size) = match jar.spec.shape {
                JarShape::Round { radius } => ("round", 2.0 * radius),
                JarShape::Square { half_side } => ("square", 2.0 * half_side),
            };
            j.set_item("shape", shape)?;
            j.set_item("size", size)?;
            j.set_item("tilt", jar.disturbance.tilt)?;
            j.set_item("is_target", i == scene.target())?;
            jars.append(j)?;
        }
        d.set_item("jars", jars)?;
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
        d.set_item("bounds", episode.grid().bounds())?;
        let (h, w) = episode.grid().shape();
        for (name, values) in episode.map().render_grids() {
            let grid = match values {
                GridValues::F64(v) => PyArray1::from_vec(py, v).reshape([h, w])?.into_any(),
                GridValues::F32(v) => PyArray1::from_vec(py, v).reshape([h, w])?.into_any(),
            };
            d.set_item(name, grid)?;
        }
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

    /// The `probe` action mode's index counts `(lanes, depths, sweeps)`: its
    /// `MultiDiscrete` space's `nvec` (None in the `wrist` mode).
    #[getter]
    fn probe_counts(&self) -> Option<[usize; 3]> {
        (self.config.action_mode == ActionMode::Probe).then(|| self.config.probe.counts())
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
