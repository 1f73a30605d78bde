//! A config whose settings have all been checked: what the core's constructors take, so a
//! config is checked once, where it is made, and never again on the way down.

use std::ops::Deref;
use std::sync::Arc;

use super::{SettingError, Settings};

/// A config `C` that passed [`Settings::check_settings`]: every setting within its range and
/// every relation between settings kept. Only [`Checked::new`] (and a section of a checked
/// config, [`Checked::section`]) makes one. Shared, not copied: cloning is a reference
/// count, so a batch's episodes and each reset's scene hold the same config.
#[derive(Debug, PartialEq)]
pub struct Checked<C>(Arc<C>);

impl<C> Clone for Checked<C> {
    fn clone(&self) -> Self {
        Self(Arc::clone(&self.0))
    }
}

impl<C: Settings> Checked<C> {
    /// Checks `config`.
    ///
    /// # Cost
    /// O(settings).
    ///
    /// # Errors
    /// The first setting out of its range, or the first relation between settings broken,
    /// named by its key ([`SettingError`]).
    pub fn new(config: C) -> Result<Self, SettingError> {
        config.check_settings()?;
        Ok(Self(Arc::new(config)))
    }

    /// The section `part` of this config, checked: a config's check covers its sections
    /// (the `settings!` table lifts every section's settings and runs its relations), so
    /// the section needs no check of its own.
    ///
    /// # Cost
    /// One clone of the section.
    pub fn section<S: Settings + Clone>(&self, part: impl FnOnce(&C) -> &S) -> Checked<S> {
        Checked(Arc::new(part(&self.0).clone()))
    }
}

impl<C> Deref for Checked<C> {
    type Target = C;

    fn deref(&self) -> &C {
        &self.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::settings::Range;

    crate::settings! {
        /// A config of one setting, for the tests.
        pub struct Probe {
            /// A length, m.
            length: f64 = 1.0 => "length" in Range::POSITIVE,
        }
        sections {}
        check_across = |_config| Ok(());
    }

    #[test]
    fn a_config_out_of_range_is_refused_by_its_key() {
        let error = Checked::new(Probe { length: -1.0 }).unwrap_err();
        assert!(error.to_string().starts_with("length must be"), "{error}");
    }

    #[test]
    fn a_clone_shares_the_checked_config() {
        let checked = Checked::new(Probe::default()).unwrap();
        let clone = checked.clone();
        assert!(std::ptr::eq(&*checked, &*clone));
    }
}
