//! The core's planners ([`crate::planner`]) over a batch of episodes, one planner per
//! episode, acting on every core with the GIL released: `ProbePlanner` (the GPIS probe
//! planner), `IdentifyPlanner` (the identify task's) and `MapPlanner` (the map task's
//! greedy mappers).

use numpy::{Element, PyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;

use super::decode::{exact_array, typed_array, values_of};
use super::episode_config::episode_config_of;
use super::errors::{episode_index_error, wrong_shape, wrong_value};
use super::exclusive::Exclusive;
use crate::episode::{EpisodeConfig, PROPRIO_LEN};
use crate::planner::{
    act_batch, IdentifyPlanner, MapPlanner, Planner, PlannerError, PlannerObservation, ProbePlanner,
};
use crate::settings::Checked;

impl From<PlannerError> for PyErr {
    fn from(error: PlannerError) -> Self {
        match error {
            PlannerError::Episode(episode) => episode.into(),
            // Every other planner error is a bad value (settings, image, call order), and
            // its message says what was expected and what came.
            other => pyo3::exceptions::PyValueError::new_err(other.to_string()),
        }
    }
}

/// `num_envs` planners of episodes of one configuration, behind a lock (what both Python
/// classes hold).
struct PlannerBatch<P> {
    config: Checked<EpisodeConfig>,
    planners: Exclusive<Vec<P>>,
}

/// The rows of `value`, an array of dtype `T` and shape `(n, *row)`: `n` and the values in
/// row-major order.
fn rows_of<T: Element + Copy>(
    what: &str,
    value: &Bound<'_, PyAny>,
    dtype: &str,
    row: &[usize],
) -> PyResult<(usize, Vec<T>)> {
    let dims: Vec<String> = row.iter().map(usize::to_string).collect();
    let shape_wanted = format!("(n, {})", dims.join(", "));
    let expected = format!("a {dtype} numpy array of shape {shape_wanted}");
    let array = typed_array::<T>(what, value, &expected)?;
    let shape = array.shape();
    if shape.len() != row.len() + 1 || shape[1..] != *row {
        return Err(wrong_shape(what, &shape_wanted, shape));
    }
    Ok((shape[0], values_of(what, array)?))
}

impl<P: Planner + Clone> PlannerBatch<P> {
    fn new(
        name: &'static str,
        config: &Bound<'_, PyAny>,
        num_envs: usize,
        make: impl FnOnce(&EpisodeConfig) -> Result<P, PlannerError>,
    ) -> PyResult<Self> {
        let config = episode_config_of(config)?;
        if num_envs == 0 {
            return Err(wrong_value("num_envs", "at least 1", num_envs));
        }
        let planner = make(&config)?;
        Ok(Self {
            config,
            planners: Exclusive::new(name, vec![planner; num_envs]),
        })
    }

    fn map_shape(&self) -> [usize; 3] {
        let channels = self.config.map.mode.kind().channels.len();
        let (h, w) = self.config.map.grid_shape;
        [channels, h, w]
    }

    fn len(&self) -> PyResult<usize> {
        Ok(self.planners.lock()?.len())
    }

    fn reset(
        &self,
        py: Python<'_>,
        index: usize,
        map: &Bound<'_, PyAny>,
        proprio: &Bound<'_, PyAny>,
    ) -> PyResult<()> {
        let map: Vec<u8> = exact_array("map", map, "uint8", &self.map_shape())?;
        let proprio: Vec<f32> = exact_array("proprio", proprio, "float32", &[PROPRIO_LEN])?;
        let proprio: [f32; PROPRIO_LEN] = proprio.try_into().expect("checked length");
        let mut planners = self.planners.lock()?;
        let len = planners.len();
        let planner = planners
            .get_mut(index)
            .ok_or_else(|| episode_index_error(index, len))?;
        py.detach(|| {
            planner.reset(PlannerObservation {
                map: &map,
                proprio: &proprio,
            })
        })?;
        Ok(())
    }

    fn act<'py>(
        &self,
        py: Python<'py>,
        maps: &Bound<'py, PyAny>,
        proprio: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray2<i64>>> {
        let [c, h, w] = self.map_shape();
        let (n, maps) = rows_of::<u8>("maps", maps, "uint8", &[c, h, w])?;
        let (m, proprio) = rows_of::<f32>("proprio", proprio, "float32", &[PROPRIO_LEN])?;
        let mut planners = self.planners.lock()?;
        if n != planners.len() || m != planners.len() {
            return Err(wrong_value(
                "maps and proprio",
                &format!("one row per episode ({})", planners.len()),
                format!("{n} maps and {m} proprio rows"),
            ));
        }
        let observations: Vec<PlannerObservation<'_>> = maps
            .chunks_exact(c * h * w)
            .zip(proprio.chunks_exact(PROPRIO_LEN))
            .map(|(map, row)| PlannerObservation {
                map,
                proprio: row.try_into().expect("rows of PROPRIO_LEN"),
            })
            .collect();
        let batch: &mut [P] = &mut planners;
        let actions = py.detach(|| act_batch(batch, &observations))?;
        Ok(PyArray2::from_vec2(
            py,
            &actions
                .iter()
                .map(|a| a.as_ref().to_vec())
                .collect::<Vec<_>>(),
        )?)
    }

    fn follow(&self, index: usize, probe: [i64; 3]) -> PyResult<()> {
        let mut planners = self.planners.lock()?;
        let len = planners.len();
        let planner = planners
            .get_mut(index)
            .ok_or_else(|| episode_index_error(index, len))?;
        planner.follow(probe)?;
        Ok(())
    }
}

/// A Python class over a [`PlannerBatch`] of one planner type: `new(config, num_envs)`,
/// `__len__`, `reset(index, map, proprio)`, `act(maps, proprio)` and `follow(index, probe)`.
macro_rules! planner_class {
    ($(#[$doc:meta])* $class:ident, $name:literal, $planner:ty, acts: $actions:literal) => {
        $(#[$doc])*
        #[pyclass(name = $name, module = "tactile_search._core", frozen)]
        pub struct $class(PlannerBatch<$planner>);

        #[pymethods]
        impl $class {
            #[new]
            fn new(config: &Bound<'_, PyAny>, num_envs: usize) -> PyResult<Self> {
                PlannerBatch::new($name, config, num_envs, <$planner>::new).map(Self)
            }

            /// How many episodes it plans for.
            fn __len__(&self) -> PyResult<usize> {
                self.0.len()
            }

            /// Starts episode `index` from its first observation: `map` `(C, H, W)` uint8
            /// and `proprio` `(11,)` float32.
            fn reset(
                &self,
                py: Python<'_>,
                index: usize,
                map: &Bound<'_, PyAny>,
                proprio: &Bound<'_, PyAny>,
            ) -> PyResult<()> {
                self.0.reset(py, index, map, proprio)
            }

            #[doc = concat!(
                "Every episode's next action for its observation after the last probe: `maps` ",
                "`(n, C, H, W)` uint8 and `proprio` `(n, 11)` float32, one row per episode; ",
                "an int64 array of ", $actions, ". The planners run in parallel."
            )]
            fn act<'py>(
                &self,
                py: Python<'py>,
                maps: &Bound<'py, PyAny>,
                proprio: &Bound<'py, PyAny>,
            ) -> PyResult<Bound<'py, PyArray2<i64>>> {
                self.0.act(py, maps, proprio)
            }

            /// Tells episode `index`'s planner that the env carries out `probe` (lane,
            /// depth, sweep), not the action it chose: its belief then learns from that
            /// probe.
            fn follow(&self, index: usize, probe: [i64; 3]) -> PyResult<()> {
                self.0.follow(index, probe)
            }
        }
    };
}

planner_class!(
    /// The GPIS probe planner of `num_envs` episodes of `config` (the GPIS map, the `probe`
    /// action mode): per episode, `reset` with its first observation, then `act` on the
    /// observations after each probe (and `follow` when the env carries out another probe
    /// than the one chosen). It reads the observations and the settings, nothing else.
    PyProbePlanner,
    "ProbePlanner",
    ProbePlanner,
    acts: "`(n, 3)`: (lane, depth, sweep)"
);

planner_class!(
    /// The identify task's planner of `num_envs` episodes of `config` (the identify task
    /// with a square target, the GPIS map, the `probe` action mode): the GPIS probe
    /// planner's search, the touched jars' shapes told from their contacts, and the claim.
    /// Used as `ProbePlanner` is; its actions are (lane, depth, sweep, claim).
    PyIdentifyPlanner,
    "IdentifyPlanner",
    IdentifyPlanner,
    acts: "`(n, 4)`: (lane, depth, sweep, claim)"
);

planner_class!(
    /// The map task's greedy mapper of `num_envs` episodes of `config` (the GPIS map: the
    /// variance mapper; the occupancy grid: the occupancy mapper; the `probe` action mode):
    /// the probe whose finger passes the most of the map's own uncertainty, each probe
    /// chosen once. Used as `ProbePlanner` is.
    PyMapPlanner,
    "MapPlanner",
    MapPlanner,
    acts: "`(n, 3)`: (lane, depth, sweep)"
);
