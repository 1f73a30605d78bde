//! A setting's value as it crosses the boundary: the few shapes a user can type (a bool, an
//! int, a float, a string, None, or a list of these), independent of Python.

use std::fmt;

/// A value given for, or read from, a setting.
#[derive(Debug, Clone, PartialEq)]
pub enum SettingValue {
    /// `True` / `False`.
    Bool(bool),
    /// A whole number.
    Int(i64),
    /// A real number.
    Float(f64),
    /// A string (a choice such as `"gpis"`).
    Text(String),
    /// `None`: an optional setting switched off.
    Null,
    /// A sequence (a pair, a position).
    List(Vec<SettingValue>),
}

impl fmt::Display for SettingValue {
    /// Python's spelling, so that error messages quote what the user typed.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Bool(true) => write!(f, "True"),
            Self::Bool(false) => write!(f, "False"),
            Self::Int(v) => write!(f, "{v}"),
            Self::Float(v) => write!(f, "{v:?}"),
            Self::Text(v) => write!(f, "{v:?}"),
            Self::Null => write!(f, "None"),
            Self::List(items) => {
                write!(f, "(")?;
                for (i, item) in items.iter().enumerate() {
                    if i > 0 {
                        write!(f, ", ")?;
                    }
                    write!(f, "{item}")?;
                }
                write!(f, ")")
            }
        }
    }
}
