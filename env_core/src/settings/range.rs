//! The valid range of a numeric setting: one interval that every number of the setting (each
//! entry of a pair or a position) must lie in. Checked by [`super::validate`].

use std::fmt;

/// The largest length or coordinate of the scene's settings, m. The physics (rapier) runs in
/// f32, which keeps sub-millimetre resolution only over a bounded scene, and turns lengths
/// beyond f32::MAX into infinities; 100 m is far beyond any cupboard and well inside both.
pub const MAX_SCENE_LENGTH: f64 = 100.0;

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
    /// `(0, MAX_SCENE_LENGTH]` m: a length in the scene ([`MAX_SCENE_LENGTH`] says why it
    /// is bounded).
    pub const LENGTH: Self = Self::left_open(0.0, MAX_SCENE_LENGTH);
    /// `[0, MAX_SCENE_LENGTH]` m: a length in the scene that may be zero (a gap, a margin, a noise).
    pub const NON_NEGATIVE_LENGTH: Self = Self::closed(0.0, MAX_SCENE_LENGTH);
    /// `[-MAX_SCENE_LENGTH, MAX_SCENE_LENGTH]` m: a coordinate in the scene.
    pub const COORDINATE: Self = Self::closed(-MAX_SCENE_LENGTH, MAX_SCENE_LENGTH);
    /// `[1e-6, 1e6]`: a mass (kg), stiffness or damping the f32 physics represents (the
    /// smallest f32 rounds 1e-300 to 0, which the physics reads as infinite mass).
    pub const PHYSICAL: Self = Self::closed(1e-6, 1e6);

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

    /// The rule in Python's words, for error messages: `>= 1`, `> 0`, `from 0 to 1`,
    /// `> 0 and <= 100`, `finite`.
    pub fn words(&self) -> String {
        let low = match self.low {
            Limit::Unbounded => None,
            Limit::Closed(v) => Some((">=", v)),
            Limit::Open(v) => Some((">", v)),
        };
        let high = match self.high {
            Limit::Unbounded => None,
            Limit::Closed(v) => Some(("<=", v)),
            Limit::Open(v) => Some(("<", v)),
        };
        match (low, high) {
            (None, None) => "finite".to_string(),
            (Some((op, v)), None) | (None, Some((op, v))) => format!("{op} {v}"),
            (Some((">=", a)), Some(("<=", b))) => format!("from {a} to {b}"),
            (Some((lo, a)), Some((hi, b))) => format!("{lo} {a} and {hi} {b}"),
        }
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
