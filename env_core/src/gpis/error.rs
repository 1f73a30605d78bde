//! Typed errors of the GPIS engine. Each says what was expected and what came; the Python
//! bindings map them to `ValueError` in one place (`bindings/errors.rs`).

use thiserror::Error;

/// Everything that can go wrong when building or feeding a [`crate::gpis::Gpis`].
#[derive(Debug, Clone, PartialEq, Error)]
pub enum GpisError {
    /// The grid needs at least one cell along each axis.
    #[error("grid shape must be positive (H >= 1, W >= 1, H * W < 2^64), got ({height}, {width})")]
    InvalidShape {
        /// Rows of the grid (along y).
        height: usize,
        /// Columns of the grid (along x).
        width: usize,
    },
    /// Bounds must be finite with lower < upper.
    #[error("bounds along {axis} must be finite with lower < upper, got ({lower}, {upper})")]
    InvalidBounds {
        /// `"x"` or `"y"`.
        axis: &'static str,
        /// Lower bound given.
        lower: f64,
        /// Upper bound given.
        upper: f64,
    },
    /// ψ must exceed every distance in the domain, or the kernel is not a covariance.
    #[error(
        "psi must be finite and at least the diagonal of the bounds ({diagonal}) so that the \
         thin-plate kernel stays a covariance, got {psi}"
    )]
    PsiTooSmall {
        /// ψ given.
        psi: f64,
        /// Diagonal of the map's bounds.
        diagonal: f64,
    },
    /// ψ so large that the kernel's values (ψ³) could overflow.
    #[error(
        "psi must be at most {max:e} (the kernel grows as psi^3), got {psi:e}: bounds this \
         large need smaller units"
    )]
    PsiTooLarge {
        /// ψ given (or the default from the bounds).
        psi: f64,
        /// The largest ψ allowed.
        max: f64,
    },
    /// Storage the map needs could not be allocated.
    #[error(
        "the map's {what} needs {gigabytes:.1} GB, more than this machine could allocate (use \
         a coarser grid or a smaller max_rows)"
    )]
    OutOfMemory {
        /// What the storage is for.
        what: &'static str,
        /// Gigabytes (1e9 bytes) it needed.
        gigabytes: f64,
    },
    /// A scalar parameter that must be finite was not.
    #[error("{what} must be finite, got {value}")]
    NonFiniteParameter {
        /// Which parameter.
        what: &'static str,
        /// Value given.
        value: f64,
    },
    /// A noise level, threshold or size that must be non-negative (a diameter: positive)
    /// was not.
    #[error("{what} must be finite and non-negative (a diameter: positive), got {value}")]
    NegativeParameter {
        /// Which parameter.
        what: &'static str,
        /// Value given.
        value: f64,
    },
    /// A row capacity of zero can hold nothing.
    #[error("max_rows must be at least 1, got {max_rows}")]
    InvalidCapacity {
        /// Capacity given.
        max_rows: usize,
    },
    /// An input array entry was NaN or infinite.
    #[error("{what}[{index}] must be finite, got {value:?}")]
    NonFiniteInput {
        /// Which input (`"points"`, `"values"`, `"normals"`).
        what: &'static str,
        /// Index of the offending entry.
        index: usize,
        /// The entry.
        value: Vec<f64>,
    },
    /// A point lies outside the map's bounds, where the kernel is not a covariance.
    #[error(
        "points[{index}] = ({x}, {y}) lies outside the map bounds: x from {x0} to {x1}, y from {y0} to {y1}"
    )]
    PointOutsideBounds {
        /// Index of the offending point.
        index: usize,
        /// Its x.
        x: f64,
        /// Its y.
        y: f64,
        /// Bounds.
        x0: f64,
        /// Bounds.
        x1: f64,
        /// Bounds.
        y0: f64,
        /// Bounds.
        y1: f64,
    },
    /// A contact normal of zero length has no direction.
    #[error("normals[{index}] must be non-zero (it is normalised), got ({nx}, {ny})")]
    ZeroNormal {
        /// Index of the offending normal.
        index: usize,
        /// Its x component.
        nx: f64,
        /// Its y component.
        ny: f64,
    },
    /// Parallel inputs differ in length.
    #[error("{what} must have one entry per point ({expected}), got {got}")]
    LengthMismatch {
        /// Which input.
        what: &'static str,
        /// Number of points.
        expected: usize,
        /// Entries given.
        got: usize,
    },
    /// Adding the observations could exceed the row capacity; nothing was added.
    #[error(
        "adding up to {requested} rows to a map holding {current} of max_rows={capacity} could \
         exceed its capacity; nothing was added (raise max_rows or thin the observations)"
    )]
    CapacityExceeded {
        /// `max_rows`.
        capacity: usize,
        /// Rows held now.
        current: usize,
        /// Rows the call could add.
        requested: usize,
    },
}
