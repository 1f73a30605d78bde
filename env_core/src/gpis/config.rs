//! How a GPIS map is built ([`GpisConfig`]), and the defaults of the map and of its `add_*`
//! calls as the Python API takes them ([`GPIS_DEFAULTS`]), each typed once here.

/// Default ψ as a multiple of the bounds' diagonal (`docs/DESIGN.md` §3).
pub const DEFAULT_PSI_FACTOR: f64 = 1.5;

/// Largest ψ: the kernel's values grow as ψ³, and sums of many of them must stay far from
/// f64's overflow (ψ³ = 1e300 leaves eight orders of magnitude).
pub const MAX_PSI: f64 = 1e100;

/// The defaults of a map and of its `add_*` calls as the Python API takes them
/// (`tactile_search.Gpis`, through `_core.gpis_defaults()`): the one place they are typed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GpisDefaults {
    /// ψ without one given: this times the bounds' diagonal ([`DEFAULT_PSI_FACTOR`]).
    pub psi_factor: f64,
    /// Constant prior mean of f.
    pub prior_mean: f64,
    /// Most rows the map will hold.
    pub max_rows: usize,
    /// Standard deviation of a value observation's noise, m (depth is noisier than touch).
    pub value_noise_std: f64,
    /// Standard deviation of a contact position's value noise, m.
    pub contact_noise_std: f64,
    /// Standard deviation of each contact-normal component's noise.
    pub normal_noise_std: f64,
    /// Diameter of the paper's circle prior, m (the paper's 0.03 m).
    pub circle_diameter: f64,
}

/// The GPIS API's defaults (see [`GpisDefaults`]).
pub const GPIS_DEFAULTS: GpisDefaults = GpisDefaults {
    psi_factor: DEFAULT_PSI_FACTOR,
    prior_mean: 0.0,
    max_rows: 4096,
    value_noise_std: 0.002,
    contact_noise_std: 0.0005,
    normal_noise_std: 0.05,
    circle_diameter: 0.03,
};

/// How a map is built ([`crate::gpis::Gpis::new`] checks it). `psi: None` means
/// [`DEFAULT_PSI_FACTOR`] × the bounds' diagonal.
#[derive(Debug, Clone, PartialEq)]
pub struct GpisConfig {
    /// `[[x0, x1], [y0, y1]]` in metres.
    pub bounds: [[f64; 2]; 2],
    /// Grid shape (H, W).
    pub shape: (usize, usize),
    /// The kernel's ψ; must be at least the bounds' diagonal and at most [`MAX_PSI`].
    pub psi: Option<f64>,
    /// Constant prior mean of f (positive = free space).
    pub prior_mean: f64,
    /// Most rows the map will ever hold.
    pub max_rows: usize,
}
