//! A config whose settings have all been checked: what the core's constructors take, so a
//! config is checked once, where it is made, and never again on the way down. Made only by
//! [`Checked::new`] and [`Checked::section`] (beside the [`super::Settings`] trait they
//! need).

use std::ops::Deref;
use std::sync::Arc;

/// A config `C` that passed its every check: each setting within its range and every
/// relation between settings kept. Shared, not copied: cloning is a reference count, so a
/// batch's episodes and each reset's scene hold the same config.
#[derive(Debug, PartialEq)]
pub struct Checked<C>(Arc<C>);

impl<C> Checked<C> {
    /// Wraps `config`, which the caller has checked.
    pub(super) fn wrap(config: C) -> Self {
        Self(Arc::new(config))
    }
}

impl<C> Clone for Checked<C> {
    fn clone(&self) -> Self {
        Self(Arc::clone(&self.0))
    }
}

impl<C> Deref for Checked<C> {
    type Target = C;

    fn deref(&self) -> &C {
        &self.0
    }
}
