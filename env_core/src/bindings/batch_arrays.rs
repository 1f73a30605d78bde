//! The numpy arrays a batch writes its results into, allocated once per batch and written
//! in place every step (the GIL released while the episodes write their rows): observations,
//! rewards, terminated/truncated flags, and the info as one array per key (views into three
//! field-major blocks, one per dtype, so the info dict itself is built once too).
//!
//! The same array objects are handed out every step: what a step returns is overwritten by
//! the next step or reset. The gymnasium and SB3 faces copy once at their edge where their
//! semantics need a fresh array. Cost per step: no allocation; O(N × info fields) writes.

use numpy::ndarray::Dimension;
use numpy::{Element, PyArray, PyArray1, PyArray2, PyArray4, PyArrayMethods, PyReadwriteArray};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::episode::step_info::{info_counts, InfoColumns, InfoValue, STEP_INFO_FIELDS};
use crate::episode::{Command, EpisodeBatch, PROPRIO_LEN};

/// The batch's output arrays.
pub(crate) struct BatchArrays {
    /// (N, C, H, W) uint8 (C = 2 for the `gpis` and `occupancy` modes); none for a map mode
    /// without an image.
    maps: Option<Py<PyArray4<u8>>>,
    /// (N, PROPRIO_LEN) float32.
    proprio: Py<PyArray2<f32>>,
    /// (N,) float64.
    rewards: Py<PyArray1<f64>>,
    /// (N,) bool.
    terminated: Py<PyArray1<bool>>,
    /// (N,) bool.
    truncated: Py<PyArray1<bool>>,
    /// Float info fields (K_f, N).
    floats: Py<PyArray2<f64>>,
    /// Flag info fields (K_b, N).
    flags: Py<PyArray2<bool>>,
    /// Count info fields (K_c, N).
    counts: Py<PyArray2<i64>>,
    /// Info key → its row of the block of its dtype, shape (N,).
    info: Py<PyDict>,
}

fn not_writeable(what: &str, error: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(format!(
        "the batch's {what} array must be writeable and not borrowed elsewhere: {error}"
    ))
}

impl BatchArrays {
    /// Zeroed arrays for `n` episodes with a `[channels, h, w]` map image (`None`: no
    /// image).
    pub(crate) fn new(py: Python<'_>, n: usize, map: Option<[usize; 3]>) -> PyResult<Self> {
        let (nf, nb, nc) = info_counts();
        let floats = PyArray2::<f64>::zeros(py, [nf, n], false);
        let flags = PyArray2::<bool>::zeros(py, [nb, n], false);
        let counts = PyArray2::<i64>::zeros(py, [nc, n], false);
        let info = PyDict::new(py);
        // Row k of a block is the k-th field of its dtype (the order `InfoColumns` writes).
        let mut next = [0usize; 3];
        for field in STEP_INFO_FIELDS {
            let (block, kind) = match field.value {
                InfoValue::Float(_) => (floats.as_any(), 0),
                InfoValue::Flag(_) => (flags.as_any(), 1),
                InfoValue::Count(_) | InfoValue::Index(_) => (counts.as_any(), 2),
            };
            info.set_item(field.name, block.get_item(next[kind])?)?;
            next[kind] += 1;
        }
        Ok(Self {
            maps: map.map(|[c, h, w]| PyArray4::<u8>::zeros(py, [n, c, h, w], false).unbind()),
            proprio: PyArray2::<f32>::zeros(py, [n, PROPRIO_LEN], false).unbind(),
            rewards: PyArray1::<f64>::zeros(py, n, false).unbind(),
            terminated: PyArray1::<bool>::zeros(py, n, false).unbind(),
            truncated: PyArray1::<bool>::zeros(py, n, false).unbind(),
            floats: floats.unbind(),
            flags: flags.unbind(),
            counts: counts.unbind(),
            info: info.unbind(),
        })
    }

    /// The observation arrays: (maps or None, proprio).
    pub(crate) fn observation<'py>(
        &self,
        py: Python<'py>,
    ) -> (Option<Bound<'py, PyAny>>, Bound<'py, PyAny>) {
        (
            self.maps.as_ref().map(|m| m.bind(py).clone().into_any()),
            self.proprio.bind(py).clone().into_any(),
        )
    }

    /// The result arrays: (rewards, terminated, truncated, info dict of arrays).
    #[allow(clippy::type_complexity)]
    pub(crate) fn results<'py>(
        &self,
        py: Python<'py>,
    ) -> (
        Bound<'py, PyArray1<f64>>,
        Bound<'py, PyArray1<bool>>,
        Bound<'py, PyArray1<bool>>,
        Bound<'py, PyDict>,
    ) {
        (
            self.rewards.bind(py).clone(),
            self.terminated.bind(py).clone(),
            self.truncated.bind(py).clone(),
            self.info.bind(py).clone(),
        )
    }

    /// Calls `f` with the maps and proprio arrays as mutable slices (maps empty without a
    /// map); `f` may release the GIL while it writes.
    pub(crate) fn with_observation<R>(
        &self,
        py: Python<'_>,
        f: impl FnOnce(&mut [u8], &mut [f32]) -> R,
    ) -> PyResult<R> {
        let mut proprio = writeable(self.proprio.bind(py), "proprio")?;
        let proprio = slice(&mut proprio, "proprio")?;
        match &self.maps {
            Some(maps) => {
                let mut maps = writeable(maps.bind(py), "maps")?;
                Ok(f(slice(&mut maps, "maps")?, proprio))
            }
            None => Ok(f(&mut [], proprio)),
        }
    }

    /// Writes rewards, flags and infos after `batch.run(commands)` (see
    /// [`EpisodeBatch::write_result`]): every episode's entries, or only episode `only`'s.
    pub(crate) fn write_results(
        &self,
        py: Python<'_>,
        batch: &EpisodeBatch,
        commands: &[Command],
        only: Option<usize>,
    ) -> PyResult<()> {
        let mut rewards = writeable(self.rewards.bind(py), "rewards")?;
        let mut terminated = writeable(self.terminated.bind(py), "terminated")?;
        let mut truncated = writeable(self.truncated.bind(py), "truncated")?;
        let mut floats = writeable(self.floats.bind(py), "info")?;
        let mut flags = writeable(self.flags.bind(py), "info")?;
        let mut counts = writeable(self.counts.bind(py), "info")?;
        let (rewards, terminated, truncated) = (
            slice(&mut rewards, "rewards")?,
            slice(&mut terminated, "terminated")?,
            slice(&mut truncated, "truncated")?,
        );
        let mut infos = InfoColumns {
            n: batch.len(),
            floats: slice(&mut floats, "info")?,
            flags: slice(&mut flags, "info")?,
            counts: slice(&mut counts, "info")?,
        };
        let indices = match only {
            Some(index) => index..index + 1,
            None => 0..batch.len(),
        };
        for index in indices {
            let stepped = matches!(commands[index], Command::Step(_));
            batch.write_result(index, stepped, rewards, terminated, truncated, &mut infos);
        }
        Ok(())
    }
}

fn writeable<'py, T: Element, D: Dimension>(
    array: &Bound<'py, PyArray<T, D>>,
    what: &str,
) -> PyResult<PyReadwriteArray<'py, T, D>> {
    array.try_readwrite().map_err(|e| not_writeable(what, e))
}

fn slice<'a, T: Element, D: Dimension>(
    array: &'a mut PyReadwriteArray<'_, T, D>,
    what: &str,
) -> PyResult<&'a mut [T]> {
    array.as_slice_mut().map_err(|e| not_writeable(what, e))
}
