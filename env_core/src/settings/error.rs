//! What can be wrong with a setting. Every message names the key as the user types it, the
//! value that came and what was expected; the bindings map [`SettingError::WrongType`] to
//! `TypeError` and the rest to `ValueError`.

use thiserror::Error;

/// A setting that was unknown, of the wrong type, or out of its range.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum SettingError {
    /// No setting has this key: worded as Python words an unexpected keyword argument,
    /// since a setting is one.
    #[error("got an unexpected keyword argument '{key}'; {hint}")]
    UnknownKey {
        /// The key given.
        key: String,
        /// The closest keys (`did you mean 'a' or 'b'?`), or every key when none is close.
        hint: String,
    },
    /// The value has the wrong type or shape (a string for a float, three numbers for a pair).
    #[error("{key} must be {expected}, got {got}")]
    WrongType {
        /// The setting.
        key: &'static str,
        /// The type expected, in Python's terms.
        expected: String,
        /// The value given.
        got: String,
    },
    /// The value has the right type but lies outside the setting's range, or contradicts
    /// another setting.
    #[error("{key} must be {expected}, got {got}")]
    OutOfRange {
        /// The setting.
        key: &'static str,
        /// What was expected, e.g. `in (0, inf)` or `below cupboard_height (0.3)`.
        expected: String,
        /// The value given.
        got: String,
    },
}

/// How similar (normalised Damerau-Levenshtein, 0 to 1) a key must be to a typed one to be
/// suggested; the cut-off Python's `difflib.get_close_matches` uses for its own ratio.
const CLOSE_KEY: f64 = 0.6;

impl SettingError {
    /// An [`SettingError::UnknownKey`] for `key`, suggesting up to three of `known` closest
    /// to it, or listing every key when none is close.
    pub fn unknown_key(key: &str, known: &[&str]) -> Self {
        let mut close: Vec<(f64, &str)> = known
            .iter()
            .map(|k| (strsim::normalized_damerau_levenshtein(key, k), *k))
            .filter(|(similarity, _)| *similarity >= CLOSE_KEY)
            .collect();
        close.sort_by(|a, b| b.0.total_cmp(&a.0));
        let hint = if close.is_empty() {
            format!("the settings are {}", known.join(", "))
        } else {
            let names: Vec<String> = close
                .iter()
                .take(3)
                .map(|(_, k)| format!("'{k}'"))
                .collect();
            format!("did you mean {}?", names.join(" or "))
        };
        Self::UnknownKey {
            key: key.to_owned(),
            hint,
        }
    }

    /// This error with `rule` as what was expected (a type's rule that includes its range,
    /// see `SettingType::rule`); unchanged when `rule` is None or the key is unknown.
    pub fn with_rule(self, rule: Option<String>) -> Self {
        match (self, rule) {
            (Self::WrongType { key, got, .. }, Some(rule)) => Self::WrongType {
                key,
                expected: rule,
                got,
            },
            (Self::OutOfRange { key, got, .. }, Some(rule)) => Self::OutOfRange {
                key,
                expected: rule,
                got,
            },
            (error, _) => error,
        }
    }

    /// An [`SettingError::OutOfRange`] for `key`.
    pub fn out_of_range(
        key: &'static str,
        expected: impl Into<String>,
        got: impl ToString,
    ) -> Self {
        Self::OutOfRange {
            key,
            expected: expected.into(),
            got: got.to_string(),
        }
    }
}
