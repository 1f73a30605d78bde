//! One call at a time per object. `Scene`, `EpisodeBatch` and `GpisCore` release the GIL
//! while they compute, so another Python thread can call the same object meanwhile. Each
//! keeps its state in an [`Exclusive`]: a call that finds the state in use by another call
//! gets a `RuntimeError` saying so at once, instead of pyo3's bare "Already borrowed".
//!
//! The call fails rather than waits: two threads stepping one environment interleave their
//! steps in whatever order the scheduler picks, so even a waiting call would give
//! rollouts that change from run to run. Each thread needs its own object (its own env, or
//! one vector env stepped from one thread).

use std::sync::{Mutex, MutexGuard, TryLockError};

use pyo3::exceptions::PyRuntimeError;
use pyo3::PyResult;

/// State that one call at a time may use; `class` names the Python class in errors.
pub(crate) struct Exclusive<T> {
    state: Mutex<T>,
    class: &'static str,
}

impl<T> Exclusive<T> {
    pub(crate) fn new(class: &'static str, state: T) -> Self {
        Self {
            state: Mutex::new(state),
            class,
        }
    }

    /// The state for this call, or a `RuntimeError` if another call is using it (or an
    /// earlier call panicked half-way and left it unusable).
    pub(crate) fn lock(&self) -> PyResult<MutexGuard<'_, T>> {
        self.state.try_lock().map_err(|error| {
            let class = self.class;
            PyRuntimeError::new_err(match error {
                TryLockError::WouldBlock => format!(
                    "this {class} is in use by another thread (one of its calls has not \
                     returned); it serves one thread at a time: give each thread its own"
                ),
                TryLockError::Poisoned(_) => format!(
                    "this {class} is unusable: an earlier call on it failed half-way \
                     (a PanicException); make a new one"
                ),
            })
        })
    }
}
