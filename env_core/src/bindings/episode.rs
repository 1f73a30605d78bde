//! `_core.EpisodeBatch`: N mechanical-search episodes stepped in parallel without the GIL.
//! The single environment uses a batch of one; the vector environment a batch of N.

use numpy::{PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use super::convert::seed_of;
use super::errors::{episode_error, episode_index_error, wrong_shape, wrong_type, wrong_value};
use super::settings::{config_dict, config_from, describe};
use crate::episode::{oracle_action, EpisodeBatch, EpisodeConfig, MapMode, StepInfo, PROPRIO_LEN};
use crate::scene::JarShape;
use crate::settings::Choice;

fn info_dict<'py>(py: Python<'py>, info: &StepInfo) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("reward_success", info.reward_success)?;
    d.set_item("reward_step", info.reward_step)?;
    d.set_item("reward_displacement", info.reward_displacement)?;
    d.set_item("reward_tip", info.reward_tip)?;
    d.set_item("reward_approach", info.reward_approach)?;
    d.set_item("target_distance", info.target_distance)?;
    d.set_item("success", info.success)?;
    d.set_item("tipped", info.tipped)?;
    d.set_item("steps", info.steps)?;
    d.set_item("jar_displacement", info.jar_displacement)?;
    d.set_item("max_jar_displacement", info.max_jar_displacement)?;
    d.set_item("max_tilt", info.max_tilt)?;
    d.set_item("tips", info.tips)?;
    d.set_item("contacts", info.contacts)?;
    d.set_item("rows_added", info.rows_added)?;
    d.set_item("contacts_skipped", info.contacts_skipped)?;
    d.set_item("contacts_dropped", info.contacts_dropped)?;
    d.set_item("gpis_rows", info.gpis_rows)?;
    d.set_item("iou", info.iou)?;
    d.set_item("clipped", info.clipped)?;
    d.set_item("blocked", info.blocked)?;
    Ok(d)
}

/// N episodes with one configuration (see `tactile_search.CupboardSearchEnv`).
#[pyclass(name = "EpisodeBatch", module = "tactile_search._core")]
pub struct PyEpisodeBatch {
    inner: EpisodeBatch,
    config: EpisodeConfig,
    maps: Vec<u8>,
    proprio: Vec<f32>,
}

impl PyEpisodeBatch {
    fn map_shape(&self) -> Option<[usize; 4]> {
        let (h, w) = self.config.map.grid_shape;
        (self.config.map.mode != MapMode::None).then_some([self.inner.len(), 2, h, w])
    }

    fn observation<'py>(
        &self,
        py: Python<'py>,
    ) -> PyResult<(Option<Bound<'py, PyAny>>, Bound<'py, PyAny>)> {
        let maps = match self.map_shape() {
            Some(shape) => Some(
                PyArray1::from_slice(py, &self.maps)
                    .reshape(shape)?
                    .into_any(),
            ),
            None => None,
        };
        let proprio = PyArray1::from_slice(py, &self.proprio)
            .reshape([self.inner.len(), PROPRIO_LEN])?
            .into_any();
        Ok((maps, proprio))
    }

    fn episode_index(&self, index: usize) -> PyResult<usize> {
        if index < self.inner.len() {
            Ok(index)
        } else {
            Err(episode_index_error(index, self.inner.len()))
        }
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
        let threads = match threads.filter(|t| !t.is_none()) {
            None => None,
            Some(t) => Some(
                t.extract::<usize>()
                    .ok()
                    .filter(|&n| n >= 1)
                    .ok_or_else(|| wrong_value("threads", "a positive int or None", t))?,
            ),
        };
        let config: EpisodeConfig = config_from(config, settings)?;
        let built = config.clone();
        let inner = py
            .detach(|| EpisodeBatch::new(built, &seeds, threads))
            .map_err(|e| episode_error(0, e))?;
        let n = inner.len();
        let map_len = inner.episodes()[0].map_len();
        let mut batch = Self {
            inner,
            config,
            maps: vec![0; n * map_len],
            proprio: vec![0.0; n * PROPRIO_LEN],
        };
        batch
            .inner
            .write_observations(&mut batch.maps, &mut batch.proprio)
            .map_err(|e| episode_error(0, e))?;
        Ok(batch)
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

    /// Resets episode `index` to `seed`; returns its (map or None, proprio) observation.
    fn reset<'py>(
        &mut self,
        py: Python<'py>,
        index: usize,
        seed: &Bound<'py, PyAny>,
    ) -> PyResult<(Option<Bound<'py, PyAny>>, Bound<'py, PyAny>)> {
        let index = self.episode_index(index)?;
        let seed = seed_of(seed)?;
        let inner = &mut self.inner;
        py.detach(|| inner.reset(index, seed))
            .map_err(|e| episode_error(index, e))?;
        self.inner
            .write_observations(&mut self.maps, &mut self.proprio)
            .map_err(|e| episode_error(index, e))?;
        self.observation(py)
    }

    /// The current observations: maps (N, 2, H, W) uint8 or None, proprio (N, 11) float32.
    fn observe<'py>(
        &self,
        py: Python<'py>,
    ) -> PyResult<(Option<Bound<'py, PyAny>>, Bound<'py, PyAny>)> {
        self.observation(py)
    }

    /// Steps every episode with its row of `actions` (N, 3) in [-1, 1] (clipped); returns
    /// (maps, proprio, rewards (N,), terminated (N,), infos). Where `active` (N,) bool is
    /// given and False, the episode is not stepped (the vector env's autoreset): its reward
    /// is 0, terminated False and its info that of its reset. Raises `ValueError` naming the
    /// episode if any step failed (a non-finite action, a step after termination).
    #[allow(clippy::type_complexity)]
    #[pyo3(signature = (actions, active = None))]
    fn step<'py>(
        &mut self,
        py: Python<'py>,
        actions: PyReadonlyArray2<'py, f64>,
        active: Option<PyReadonlyArray1<'py, bool>>,
    ) -> PyResult<(
        Option<Bound<'py, PyAny>>,
        Bound<'py, PyAny>,
        Bound<'py, PyArray1<f64>>,
        Bound<'py, PyArray1<bool>>,
        Bound<'py, PyList>,
    )> {
        let n = self.inner.len();
        let view = actions.as_array();
        if view.shape() != [n, 3] {
            return Err(wrong_shape("actions", &format!("({n}, 3)"), view.shape()));
        }
        let active: Vec<bool> = match &active {
            Some(mask) if mask.as_array().len() != n => {
                return Err(wrong_shape(
                    "active",
                    &format!("({n},)"),
                    mask.as_array().shape(),
                ))
            }
            Some(mask) => mask.as_array().to_vec(),
            None => vec![true; n],
        };
        let requested: Vec<Option<[f64; 3]>> = view
            .rows()
            .into_iter()
            .zip(&active)
            .map(|(r, &on)| on.then_some([r[0], r[1], r[2]]))
            .collect();
        let (inner, maps, proprio) = (&mut self.inner, &mut self.maps, &mut self.proprio);
        let results = py
            .detach(|| inner.step(&requested, maps, proprio))
            .map_err(|e| episode_error(0, e))?;
        let mut rewards = Vec::with_capacity(n);
        let mut terminated = Vec::with_capacity(n);
        let infos = PyList::empty(py);
        for (index, result) in results.into_iter().enumerate() {
            let (reward, ended, info) = match result {
                Some(outcome) => {
                    let info = outcome.map_err(|e| episode_error(index, e))?;
                    (info.reward, info.terminated, info)
                }
                None => (0.0, false, *self.inner.episodes()[index].last_info()),
            };
            rewards.push(reward);
            terminated.push(ended);
            infos.append(info_dict(py, &info)?)?;
        }
        let (maps, proprio) = self.observation(py)?;
        Ok((
            maps,
            proprio,
            PyArray1::from_vec(py, rewards),
            PyArray1::from_vec(py, terminated),
            infos,
        ))
    }

    /// The oracle's actions (N, 3): it knows the target (the upper-bound baseline).
    fn oracle_actions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let flat: Vec<f64> = self
            .inner
            .episodes()
            .iter()
            .flat_map(oracle_action)
            .collect();
        PyArray1::from_vec(py, flat).reshape([self.inner.len(), 3])
    }

    /// The metrics of episode `index`'s last reset or step, as the info dict.
    fn info<'py>(&self, py: Python<'py>, index: usize) -> PyResult<Bound<'py, PyDict>> {
        let index = self.episode_index(index)?;
        info_dict(py, self.inner.episodes()[index].last_info())
    }

    /// Ground truth and map of episode `index` for rendering: jars, hand, finger, contacts,
    /// target, the map's bounds, and its mean/std (gpis) or occupancy probability grids.
    fn render_state<'py>(&self, py: Python<'py>, index: usize) -> PyResult<Bound<'py, PyDict>> {
        let index = self.episode_index(index)?;
        let episode = &self.inner.episodes()[index];
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
        let contacts: Vec<[f64; 4]> = scene
            .contacts()
            .iter()
            .map(|c| [c.point[0], c.point[1], c.normal[0], c.normal[1]])
            .collect();
        d.set_item("contacts", contacts)?;
        d.set_item("bounds", episode.grid().bounds())?;
        let (h, w) = episode.grid().shape();
        if let Some(gpis) = episode.gpis() {
            let std: Vec<f64> = gpis.variance_grid().iter().map(|v| v.sqrt()).collect();
            d.set_item(
                "mean",
                PyArray1::from_slice(py, gpis.mean_grid()).reshape([h, w])?,
            )?;
            d.set_item("std", PyArray1::from_vec(py, std).reshape([h, w])?)?;
        }
        if let Some(occupancy) = episode.occupancy() {
            let p: Vec<f32> = (0..h * w).map(|i| occupancy.probability(i)).collect();
            d.set_item("occupancy", PyArray1::from_vec(py, p).reshape([h, w])?)?;
        }
        Ok(d)
    }

    /// Number of episodes.
    #[getter]
    fn num_envs(&self) -> usize {
        self.inner.len()
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
}
