//! The valid range of a numeric setting: one interval that every number of the setting (each
//! entry of a pair or a position) must lie in. Checked by [`super::validate`].

use std::fmt;

/// One end of a [`Range`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Limit {
    /// No bound on this side (the value must still be finite).
    Unbounded,
    /// The end is allowed.
    Closed(f64),
    /// The end itself is not allowed.
    Open(f64),
}

/// An interval of allowed values. Every setting's numbers must also be finite.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Range {
    /// Lower end.
    pub low: Limit,
    /// Upper end.
    pub high: Limit,
}

impl Range {
    /// Any finite value.
    pub const FINITE: Self = Self::new(Limit::Unbounded, Limit::Unbounded);
    /// `(0, inf)`.
    pub const POSITIVE: Self = Self::new(Limit::Open(0.0), Limit::Unbounded);
    /// `[0, inf)`.
    pub const NON_NEGATIVE: Self = Self::new(Limit::Closed(0.0), Limit::Unbounded);
    /// `[0, 1]`.
    pub const UNIT: Self = Self::closed(0.0, 1.0);
    /// `[1, inf)`: counts of at least one.
    pub const AT_LEAST_ONE: Self = Self::new(Limit::Closed(1.0), Limit::Unbounded);

    /// From two ends.
    pub const fn new(low: Limit, high: Limit) -> Self {
        Self { low, high }
    }

    /// `[low, high]`.
    pub const fn closed(low: f64, high: f64) -> Self {
        Self::new(Limit::Closed(low), Limit::Closed(high))
    }

    /// `(low, high)`.
    pub const fn open(low: f64, high: f64) -> Self {
        Self::new(Limit::Open(low), Limit::Open(high))
    }

    /// `(low, high]`.
    pub const fn left_open(low: f64, high: f64) -> Self {
        Self::new(Limit::Open(low), Limit::Closed(high))
    }

    /// Whether `value` is finite and inside.
    pub fn contains(&self, value: f64) -> bool {
        let above = match self.low {
            Limit::Unbounded => true,
            Limit::Closed(low) => value >= low,
            Limit::Open(low) => value > low,
        };
        let below = match self.high {
            Limit::Unbounded => true,
            Limit::Closed(high) => value <= high,
            Limit::Open(high) => value < high,
        };
        value.is_finite() && above && below
    }
}

impl fmt::Display for Range {
    /// Interval notation, e.g. `(0, inf)` or `[0, 1]`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.low {
            Limit::Unbounded => write!(f, "(-inf, ")?,
            Limit::Closed(v) => write!(f, "[{v}, ")?,
            Limit::Open(v) => write!(f, "({v}, ")?,
        }
        match self.high {
            Limit::Unbounded => write!(f, "inf)"),
            Limit::Closed(v) => write!(f, "{v}]"),
            Limit::Open(v) => write!(f, "{v})"),
        }
    }
}
