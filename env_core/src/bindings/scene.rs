//! `_core.Scene`: the cupboard scene for inspection from Python. Build from a seed and a flat
//! config (a dict and/or keyword arguments), command the hand, step (without the GIL), and read
//! the depth image, clouds, slice, contacts, jars and target as numpy arrays and dicts.

use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::scene::{
    CameraIntrinsics, Contact, DepthCapture, HandCommand, JarShape, Scene, SceneConfig, StepReport,
    TargetShape,
};

/// Every key the config accepts, as listed in error messages.
const KEYS: &[&str] = &[
    "slice_height",
    "cupboard_width",
    "cupboard_depth",
    "cupboard_height",
    "wall_thickness",
    "wall_friction",
    "jar_count",
    "round_fraction",
    "target_shape",
    "round_diameter",
    "square_side",
    "jar_height",
    "jar_mass",
    "jar_friction",
    "max_visible_fraction",
    "target_min_depth",
    "min_gap",
    "wall_gap",
    "corridor_width",
    "corridor_clearance",
    "max_attempts",
    "camera_width",
    "camera_height",
    "camera_hfov",
    "camera_fx",
    "camera_fy",
    "camera_cx",
    "camera_cy",
    "camera_position",
    "camera_look_at",
    "camera_max_range",
    "slice_band",
    "depth_noise_std",
    "max_slice_points",
    "hand_start",
    "max_step_translation",
    "max_step_yaw",
    "workspace",
    "wrist_half_extent",
    "arm_length",
    "arm_half_width",
    "finger_length",
    "finger_half_thickness",
    "finger_half_height",
    "finger_mass",
    "finger_friction",
    "finger_stiffness",
    "finger_damping",
    "finger_limit",
    "rigid_finger",
    "wall_margin",
    "touch_max_distance",
    "touch_merge_distance",
    "touch_point_noise_std",
    "touch_normal_noise_std",
    "dt",
    "substeps",
    "solver_iterations",
];

pub(super) fn type_name(value: &Bound<'_, PyAny>) -> String {
    value
        .get_type()
        .name()
        .map_or_else(|_| "?".to_owned(), |n| n.to_string())
}

pub(super) fn wrong_type(key: &str, expected: &str, value: &Bound<'_, PyAny>) -> PyErr {
    PyTypeError::new_err(format!(
        "config[{key:?}] must be {expected}, got {} {}",
        type_name(value),
        value
            .repr()
            .map_or_else(|_| "?".to_owned(), |r| r.to_string())
    ))
}

pub(super) fn float(key: &str, value: &Bound<'_, PyAny>) -> PyResult<f64> {
    if value.is_instance_of::<pyo3::types::PyBool>() {
        return Err(wrong_type(key, "a float", value));
    }
    value
        .extract::<f64>()
        .map_err(|_| wrong_type(key, "a float", value))
}

pub(super) fn int(key: &str, value: &Bound<'_, PyAny>) -> PyResult<usize> {
    if value.is_instance_of::<pyo3::types::PyBool>()
        || !value.is_instance_of::<pyo3::types::PyInt>()
    {
        return Err(wrong_type(key, "a non-negative int", value));
    }
    value.extract::<usize>().map_err(|_| {
        PyValueError::new_err(format!(
            "config[{key:?}] must be a non-negative int, got {value}"
        ))
    })
}

fn floats<const N: usize>(key: &str, value: &Bound<'_, PyAny>) -> PyResult<[f64; N]> {
    let expected = format!("a sequence of {N} floats");
    if value.is_instance_of::<pyo3::types::PyString>() {
        return Err(wrong_type(key, &expected, value));
    }
    let items: Vec<Bound<'_, PyAny>> = value
        .try_iter()
        .map_err(|_| wrong_type(key, &expected, value))?
        .collect::<PyResult<_>>()?;
    if items.len() != N {
        return Err(PyValueError::new_err(format!(
            "config[{key:?}] must have {N} entries, got {}",
            items.len()
        )));
    }
    let mut out = [0.0; N];
    for (slot, item) in out.iter_mut().zip(&items) {
        *slot = float(key, item)?;
    }
    Ok(out)
}

/// Applies one flat config entry.
fn apply(config: &mut SceneConfig, key: &str, value: &Bound<'_, PyAny>) -> PyResult<()> {
    let c = config;
    match key {
        "slice_height" => c.slice_height = float(key, value)?,
        "cupboard_width" => c.cupboard.width = float(key, value)?,
        "cupboard_depth" => c.cupboard.depth = float(key, value)?,
        "cupboard_height" => c.cupboard.height = float(key, value)?,
        "wall_thickness" => c.cupboard.wall_thickness = float(key, value)?,
        "wall_friction" => c.cupboard.friction = float(key, value)?,
        "jar_count" => {
            c.layout.jar_count = if value.is_instance_of::<pyo3::types::PyInt>() {
                let n = int(key, value)?;
                [n, n]
            } else {
                let [lo, hi] = floats::<2>(key, value)?;
                let whole = |v: f64| v >= 0.0 && v.fract() == 0.0 && v <= 1e6;
                if !(whole(lo) && whole(hi)) {
                    return Err(PyValueError::new_err(format!(
                        "config[\"jar_count\"] must be an int or two ints (low, high), got {lo}, {hi}"
                    )));
                }
                [lo as usize, hi as usize]
            }
        }
        "round_fraction" => c.layout.round_fraction = float(key, value)?,
        "target_shape" => {
            let text: String = value
                .extract()
                .map_err(|_| wrong_type(key, "'round', 'square' or 'any'", value))?;
            c.layout.target_shape = TargetShape::parse(&text)?;
        }
        "round_diameter" => c.layout.round_diameter = floats(key, value)?,
        "square_side" => c.layout.square_side = floats(key, value)?,
        "jar_height" => c.layout.jar_height = floats(key, value)?,
        "jar_mass" => c.layout.jar_mass = floats(key, value)?,
        "jar_friction" => c.layout.jar_friction = float(key, value)?,
        "max_visible_fraction" => c.layout.max_visible_fraction = float(key, value)?,
        "target_min_depth" => c.layout.target_min_depth = float(key, value)?,
        "min_gap" => c.layout.min_gap = float(key, value)?,
        "wall_gap" => c.layout.wall_gap = float(key, value)?,
        "corridor_width" => c.layout.corridor_width = float(key, value)?,
        "corridor_clearance" => c.layout.corridor_clearance = float(key, value)?,
        "max_attempts" => c.layout.max_attempts = int(key, value)?,
        // Intrinsics keys are applied in `config_from` in a fixed order.
        "camera_width" | "camera_height" | "camera_hfov" | "camera_fx" | "camera_fy"
        | "camera_cx" | "camera_cy" => {}
        "camera_position" => c.camera.position = floats(key, value)?,
        "camera_look_at" => c.camera.look_at = floats(key, value)?,
        "camera_max_range" => c.camera.max_range = float(key, value)?,
        "slice_band" => c.camera.slice_band = float(key, value)?,
        "depth_noise_std" => c.camera.noise_std = float(key, value)?,
        "max_slice_points" => c.camera.max_slice_points = int(key, value)?,
        "hand_start" => c.hand.start = floats(key, value)?,
        "max_step_translation" => c.hand.max_step_translation = float(key, value)?,
        "max_step_yaw" => c.hand.max_step_yaw = float(key, value)?,
        "workspace" => {
            let [x0, x1, y0, y1] = floats::<4>(key, value)?;
            c.hand.workspace = [[x0, x1], [y0, y1]];
        }
        "wrist_half_extent" => c.hand.wrist_half_extent = float(key, value)?,
        "arm_length" => c.hand.arm_length = float(key, value)?,
        "arm_half_width" => c.hand.arm_half_width = float(key, value)?,
        "finger_length" => c.hand.finger_length = float(key, value)?,
        "finger_half_thickness" => c.hand.finger_half_thickness = float(key, value)?,
        "finger_half_height" => c.hand.finger_half_height = float(key, value)?,
        "finger_mass" => c.hand.finger_mass = float(key, value)?,
        "finger_friction" => c.hand.finger_friction = float(key, value)?,
        "finger_stiffness" => c.hand.finger_stiffness = float(key, value)?,
        "finger_damping" => c.hand.finger_damping = float(key, value)?,
        "finger_limit" => c.hand.finger_limit = float(key, value)?,
        "rigid_finger" => {
            c.hand.rigid_finger = if value.is_instance_of::<pyo3::types::PyBool>() {
                value.extract::<bool>()?
            } else {
                return Err(wrong_type(key, "a bool", value));
            }
        }
        "wall_margin" => c.hand.wall_margin = float(key, value)?,
        "touch_max_distance" => c.touch.max_distance = float(key, value)?,
        "touch_merge_distance" => c.touch.merge_distance = float(key, value)?,
        "touch_point_noise_std" => c.touch.point_noise_std = float(key, value)?,
        "touch_normal_noise_std" => c.touch.normal_noise_std = float(key, value)?,
        "dt" => c.physics.dt = float(key, value)?,
        "substeps" => c.physics.substeps = int(key, value)?,
        "solver_iterations" => c.physics.solver_iterations = int(key, value)?,
        _ => {
            return Err(PyValueError::new_err(format!(
                "unknown config key {key:?}; expected one of: {}",
                KEYS.join(", ")
            )))
        }
    }
    Ok(())
}

/// Every key of [`KEYS`] with its value in `c` (the inverse of [`config_from`]).
fn config_dict<'py>(py: Python<'py>, c: &SceneConfig) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let (l, k, h) = (&c.layout, &c.camera.intrinsics, &c.hand);
    let [[x0, x1], [y0, y1]] = h.workspace;
    d.set_item("slice_height", c.slice_height)?;
    d.set_item("cupboard_width", c.cupboard.width)?;
    d.set_item("cupboard_depth", c.cupboard.depth)?;
    d.set_item("cupboard_height", c.cupboard.height)?;
    d.set_item("wall_thickness", c.cupboard.wall_thickness)?;
    d.set_item("wall_friction", c.cupboard.friction)?;
    d.set_item("jar_count", l.jar_count.to_vec())?;
    d.set_item("round_fraction", l.round_fraction)?;
    d.set_item("target_shape", l.target_shape.name())?;
    d.set_item("round_diameter", l.round_diameter.to_vec())?;
    d.set_item("square_side", l.square_side.to_vec())?;
    d.set_item("jar_height", l.jar_height.to_vec())?;
    d.set_item("jar_mass", l.jar_mass.to_vec())?;
    d.set_item("jar_friction", l.jar_friction)?;
    d.set_item("max_visible_fraction", l.max_visible_fraction)?;
    d.set_item("target_min_depth", l.target_min_depth)?;
    d.set_item("min_gap", l.min_gap)?;
    d.set_item("wall_gap", l.wall_gap)?;
    d.set_item("corridor_width", l.corridor_width)?;
    d.set_item("corridor_clearance", l.corridor_clearance)?;
    d.set_item("max_attempts", l.max_attempts)?;
    d.set_item("camera_width", k.width)?;
    d.set_item("camera_height", k.height)?;
    d.set_item("camera_hfov", 2.0 * (0.5 * k.width as f64 / k.fx).atan())?;
    d.set_item("camera_fx", k.fx)?;
    d.set_item("camera_fy", k.fy)?;
    d.set_item("camera_cx", k.cx)?;
    d.set_item("camera_cy", k.cy)?;
    d.set_item("camera_position", c.camera.position.to_vec())?;
    d.set_item("camera_look_at", c.camera.look_at.to_vec())?;
    d.set_item("camera_max_range", c.camera.max_range)?;
    d.set_item("slice_band", c.camera.slice_band)?;
    d.set_item("depth_noise_std", c.camera.noise_std)?;
    d.set_item("max_slice_points", c.camera.max_slice_points)?;
    d.set_item("hand_start", h.start.to_vec())?;
    d.set_item("max_step_translation", h.max_step_translation)?;
    d.set_item("max_step_yaw", h.max_step_yaw)?;
    d.set_item("workspace", vec![x0, x1, y0, y1])?;
    d.set_item("wrist_half_extent", h.wrist_half_extent)?;
    d.set_item("arm_length", h.arm_length)?;
    d.set_item("arm_half_width", h.arm_half_width)?;
    d.set_item("finger_length", h.finger_length)?;
    d.set_item("finger_half_thickness", h.finger_half_thickness)?;
    d.set_item("finger_half_height", h.finger_half_height)?;
    d.set_item("finger_mass", h.finger_mass)?;
    d.set_item("finger_friction", h.finger_friction)?;
    d.set_item("finger_stiffness", h.finger_stiffness)?;
    d.set_item("finger_damping", h.finger_damping)?;
    d.set_item("finger_limit", h.finger_limit)?;
    d.set_item("rigid_finger", h.rigid_finger)?;
    d.set_item("wall_margin", h.wall_margin)?;
    d.set_item("touch_max_distance", c.touch.max_distance)?;
    d.set_item("touch_merge_distance", c.touch.merge_distance)?;
    d.set_item("touch_point_noise_std", c.touch.point_noise_std)?;
    d.set_item("touch_normal_noise_std", c.touch.normal_noise_std)?;
    d.set_item("dt", c.physics.dt)?;
    d.set_item("substeps", c.physics.substeps)?;
    d.set_item("solver_iterations", c.physics.solver_iterations)?;
    Ok(d)
}

/// Builds a config from the defaults, a dict, then keyword arguments (a key given in both is
/// an error).
pub(super) fn config_from(
    config: Option<&Bound<'_, PyAny>>,
    kwargs: Option<&Bound<'_, PyDict>>,
) -> PyResult<SceneConfig> {
    let merged = PyDict::new(
        config
            .map(|c| c.py())
            .or_else(|| kwargs.map(|k| k.py()))
            .ok_or_else(|| PyValueError::new_err("no Python context"))?,
    );
    if let Some(config) = config.filter(|c| !c.is_none()) {
        let dict = config.cast::<PyDict>().map_err(|_| {
            PyTypeError::new_err(format!(
                "config must be a dict or None, got {}",
                type_name(config)
            ))
        })?;
        merged.update(dict.as_mapping())?;
    }
    if let Some(kwargs) = kwargs {
        for (key, value) in kwargs.iter() {
            if merged.contains(&key)? {
                return Err(PyValueError::new_err(format!(
                    "config key {key} was given both in the config dict and as a keyword argument"
                )));
            }
            merged.set_item(key, value)?;
        }
    }
    let mut out = SceneConfig::default();
    let mut intrinsics: [Option<Bound<'_, PyAny>>; 7] = std::array::from_fn(|_| None);
    let names = [
        "camera_width",
        "camera_height",
        "camera_hfov",
        "camera_fx",
        "camera_fy",
        "camera_cx",
        "camera_cy",
    ];
    for (key, value) in merged.iter() {
        let key: String = key.extract().map_err(|_| {
            PyTypeError::new_err(format!("config keys must be str, got {}", type_name(&key)))
        })?;
        apply(&mut out, &key, &value)?;
        if let Some(i) = names.iter().position(|n| *n == key) {
            intrinsics[i] = Some(value);
        }
    }
    // Size and field of view first, then explicit focal lengths / principal point.
    if intrinsics[..3].iter().any(Option::is_some) {
        let k = out.camera.intrinsics;
        let width = intrinsics[0]
            .as_ref()
            .map_or(Ok(k.width), |v| int(names[0], v))?;
        let height = intrinsics[1]
            .as_ref()
            .map_or(Ok(k.height), |v| int(names[1], v))?;
        let hfov = match &intrinsics[2] {
            Some(v) => float(names[2], v)?,
            None => 2.0 * (0.5 * k.width as f64 / k.fx).atan(),
        };
        if !(hfov.is_finite() && hfov > 0.0 && hfov < std::f64::consts::PI) {
            return Err(PyValueError::new_err(format!(
                "config[\"camera_hfov\"] must be in (0, pi) radians, got {hfov}"
            )));
        }
        out.camera.intrinsics = CameraIntrinsics::from_hfov(width, height, hfov);
    }
    let k = &mut out.camera.intrinsics;
    for (i, slot) in [&mut k.fx, &mut k.fy, &mut k.cx, &mut k.cy]
        .into_iter()
        .enumerate()
    {
        if let Some(v) = &intrinsics[3 + i] {
            *slot = float(names[3 + i], v)?;
        }
    }
    Ok(out)
}

/// A seed: an int in [0, 2**64).
pub(super) fn seed_of(seed: &Bound<'_, PyAny>) -> PyResult<u64> {
    if seed.is_instance_of::<pyo3::types::PyBool>() || !seed.is_instance_of::<pyo3::types::PyInt>()
    {
        return Err(PyTypeError::new_err(format!(
            "seed must be an int, got {}",
            type_name(seed)
        )));
    }
    seed.extract::<u64>().map_err(|_| {
        PyValueError::new_err(format!("seed must be an int in [0, 2**64), got {seed}"))
    })
}

fn array2<'py>(
    py: Python<'py>,
    rows: usize,
    cols: usize,
    flat: Vec<f64>,
) -> PyResult<Bound<'py, PyAny>> {
    Ok(PyArray1::from_vec(py, flat)
        .reshape([rows, cols])?
        .into_any())
}

/// An (N, K) float64 array from N rows of K values.
fn rows_array<'py, const K: usize>(
    py: Python<'py>,
    rows: &[[f64; K]],
) -> PyResult<Bound<'py, PyAny>> {
    array2(py, rows.len(), K, rows.iter().flatten().copied().collect())
}

fn capture_dict<'py>(py: Python<'py>, look: &DepthCapture) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let (w, h) = (look.image.width, look.image.height);
    d.set_item("depth", array2(py, h, w, look.image.depth.clone())?)?;
    d.set_item(
        "labels",
        PyArray1::from_slice(py, &look.image.labels).reshape([h, w])?,
    )?;
    d.set_item("cloud", rows_array(py, &look.cloud)?)?;
    d.set_item("cloud_labels", PyArray1::from_slice(py, &look.cloud_labels))?;
    d.set_item("slice", rows_array(py, &look.slice)?)?;
    d.set_item("slice_clean", rows_array(py, &look.slice_clean)?)?;
    d.set_item("slice_labels", PyArray1::from_slice(py, &look.slice_labels))?;
    Ok(d)
}

fn contacts_dict<'py>(py: Python<'py>, contacts: &[Contact]) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let n = contacts.len();
    let points: Vec<f64> = contacts.iter().flat_map(|c| c.point).collect();
    let normals: Vec<f64> = contacts.iter().flat_map(|c| c.normal).collect();
    let jars: Vec<i64> = contacts.iter().map(|c| c.jar as i64).collect();
    d.set_item("points", array2(py, n, 2, points)?)?;
    d.set_item("normals", array2(py, n, 2, normals)?)?;
    d.set_item("jars", PyArray1::from_vec(py, jars))?;
    Ok(d)
}

fn report_dict<'py>(py: Python<'py>, report: &StepReport) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let c = report.commanded;
    let m = report.moved;
    d.set_item("commanded", (c.dx, c.dy, c.dyaw))?;
    d.set_item("clipped", report.clipped)?;
    d.set_item("moved", (m.dx, m.dy, m.dyaw))?;
    d.set_item("blocked", report.blocked.map(|b| b.name()))?;
    Ok(d)
}

/// The cupboard scene (see the module docs of `env_core::scene`).
#[pyclass(name = "Scene", module = "tactile_search._core")]
pub struct PyScene {
    inner: Scene,
}

#[pymethods]
impl PyScene {
    /// Builds the scene of `seed` (default 0) from the default config updated by `config` (a dict) and
    /// keyword arguments.
    #[new]
    #[pyo3(signature = (seed = None, config = None, **kwargs))]
    fn new(
        py: Python<'_>,
        seed: Option<&Bound<'_, PyAny>>,
        config: Option<&Bound<'_, PyAny>>,
        kwargs: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        let seed = seed.map_or(Ok(0), seed_of)?;
        let config = match (config, kwargs) {
            (None, None) => SceneConfig::default(),
            _ => config_from(config, kwargs)?,
        };
        let inner = py.detach(|| Scene::new(config, seed))?;
        Ok(Self { inner })
    }

    /// Every accepted config key.
    #[staticmethod]
    fn config_keys() -> Vec<&'static str> {
        KEYS.to_vec()
    }

    /// Moves the wrist by (dx, dy, dyaw) (clipped to the step bounds, stopped at walls) over
    /// the configured physics substeps; returns a report dict.
    #[pyo3(signature = (dx = 0.0, dy = 0.0, dyaw = 0.0))]
    fn step<'py>(
        &mut self,
        py: Python<'py>,
        dx: f64,
        dy: f64,
        dyaw: f64,
    ) -> PyResult<Bound<'py, PyDict>> {
        let inner = &mut self.inner;
        let report = py.detach(|| inner.step(HandCommand { dx, dy, dyaw }))?;
        report_dict(py, &report)
    }

    /// Runs `n` physics steps with the hand held still.
    fn idle(&mut self, py: Python<'_>, n: i64) -> PyResult<()> {
        let n = usize::try_from(n).map_err(|_| {
            PyValueError::new_err(format!("idle(n): n must be a non-negative int, got {n}"))
        })?;
        let inner = &mut self.inner;
        py.detach(|| inner.idle(n));
        Ok(())
    }

    /// A new depth look at the current state (fresh noise), as a dict of arrays.
    fn capture<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let inner = &mut self.inner;
        let look = py.detach(|| inner.capture());
        capture_dict(py, &look)
    }

    /// Every setting of this scene by its config key (the defaults plus what was given): a
    /// dict that `Scene(seed, config=...)` accepts back.
    #[getter]
    fn config<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        config_dict(py, self.inner.config())
    }

    /// The first look taken at reset, as a dict of arrays: depth (H, W), labels (H, W),
    /// cloud (N, 3), cloud_labels (N,), slice (M, 2), slice_clean (M, 2), slice_labels (M,).
    #[getter]
    fn first_look<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        capture_dict(py, self.inner.first_look())
    }

    /// Depth image of the first look, (H, W) float64, NaN where nothing was hit.
    #[getter]
    fn depth_image<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let image = &self.inner.first_look().image;
        array2(py, image.height, image.width, image.depth.clone())
    }

    /// Back-projected 3D cloud of the first look, (N, 3) float64.
    #[getter]
    fn cloud<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        rows_array(py, &self.inner.first_look().cloud)
    }

    /// The noisy, thinned 2D slice of the first look, (M, 2) float64.
    #[getter]
    fn slice_points<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        rows_array(py, &self.inner.first_look().slice)
    }

    /// Tactile readings after the last step (with noise): points (K, 2), normals (K, 2),
    /// jars (K,) int64 (ground truth).
    #[getter]
    fn contacts<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        contacts_dict(py, self.inner.contacts())
    }

    /// The same readings without noise.
    #[getter]
    fn true_contacts<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        contacts_dict(py, self.inner.true_contacts())
    }

    /// Jars: shapes (list of str), half_widths, heights, masses, yaws at reset (n,),
    /// positions (n, 3), rotations (n, 4) as (x, y, z, w), displacement, vertical, tilt (n,),
    /// is_target (n,) bool.
    #[getter]
    fn jars<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let states = self.inner.jar_states();
        let n = states.len();
        let d = PyDict::new(py);
        let shapes: Vec<&str> = states.iter().map(|s| s.spec.shape.name()).collect();
        d.set_item("shapes", PyList::new(py, shapes)?)?;
        let column = |f: &dyn Fn(&crate::scene::JarState) -> f64| -> Vec<f64> {
            states.iter().map(f).collect()
        };
        d.set_item(
            "half_widths",
            PyArray1::from_vec(py, column(&|s| s.spec.shape.half_width())),
        )?;
        d.set_item(
            "heights",
            PyArray1::from_vec(py, column(&|s| s.spec.height)),
        )?;
        d.set_item("masses", PyArray1::from_vec(py, column(&|s| s.spec.mass)))?;
        d.set_item("yaws", PyArray1::from_vec(py, column(&|s| s.spec.yaw)))?;
        let positions: Vec<f64> = states.iter().flat_map(|s| s.position).collect();
        d.set_item("positions", array2(py, n, 3, positions)?)?;
        let rotations: Vec<f64> = states.iter().flat_map(|s| s.rotation).collect();
        d.set_item("rotations", array2(py, n, 4, rotations)?)?;
        d.set_item(
            "displacement",
            PyArray1::from_vec(py, column(&|s| s.disturbance.displacement)),
        )?;
        d.set_item(
            "vertical",
            PyArray1::from_vec(py, column(&|s| s.disturbance.vertical)),
        )?;
        d.set_item(
            "tilt",
            PyArray1::from_vec(py, column(&|s| s.disturbance.tilt)),
        )?;
        let target = self.inner.target();
        let is_target: Vec<bool> = (0..n).map(|i| i == target).collect();
        d.set_item("is_target", PyArray1::from_vec(py, is_target))?;
        Ok(d)
    }

    /// Index of the target jar.
    #[getter]
    fn target(&self) -> usize {
        self.inner.target()
    }

    /// The target's shape, `"round"` or `"square"`.
    #[getter]
    fn target_shape(&self) -> &'static str {
        let layout = self.inner.layout();
        match layout.jars[layout.target].shape {
            JarShape::Round { .. } => "round",
            JarShape::Square { .. } => "square",
        }
    }

    /// Visible fraction of the target (visible / silhouette pixels, by ray casting).
    #[getter]
    fn visible_fraction(&self) -> f64 {
        self.inner.layout().visibility.fraction()
    }

    /// (silhouette pixels, visible pixels) of the target.
    #[getter]
    fn target_pixels(&self) -> (usize, usize) {
        let v = self.inner.layout().visibility;
        (v.silhouette_pixels, v.visible_pixels)
    }

    /// The clear corridor to the target: dict with x (lo, hi), y (lo, hi), side; or None.
    #[getter]
    fn corridor<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        self.inner
            .layout()
            .corridor
            .map(|c| {
                let d = PyDict::new(py);
                d.set_item("x", (c.x[0], c.x[1]))?;
                d.set_item("y", (c.y[0], c.y[1]))?;
                d.set_item("side", c.side)?;
                Ok(d)
            })
            .transpose()
    }

    /// The wrist pose (x, y, yaw).
    #[getter]
    fn hand_pose(&self) -> (f64, f64, f64) {
        let p = self.inner.hand_pose();
        (p.x, p.y, p.yaw)
    }

    /// The finger joint's position and the finger's yaw (x, y, yaw).
    #[getter]
    fn finger_pose(&self) -> (f64, f64, f64) {
        let p = self.inner.finger_pose();
        (p.x, p.y, p.yaw)
    }

    /// Sensed finger deflection (joint angle), rad.
    #[getter]
    fn finger_angle(&self) -> f64 {
        self.inner.finger_angle()
    }

    /// Camera intrinsics and extrinsics: width, height, fx, fy, cx, cy, position (3,),
    /// rotation (3, 3) camera→world (columns right, down, forward).
    #[getter]
    fn camera<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let camera = self.inner.camera();
        let k = camera.intrinsics();
        let d = PyDict::new(py);
        d.set_item("width", k.width)?;
        d.set_item("height", k.height)?;
        d.set_item("fx", k.fx)?;
        d.set_item("fy", k.fy)?;
        d.set_item("cx", k.cx)?;
        d.set_item("cy", k.cy)?;
        d.set_item("position", PyArray1::from_slice(py, &camera.position()))?;
        let rotation: Vec<f64> = camera.rotation().iter().flatten().copied().collect();
        d.set_item("rotation", array2(py, 3, 3, rotation)?)?;
        Ok(d)
    }

    /// Interior size: dict with width, depth, height (m).
    #[getter]
    fn cupboard<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let c = self.inner.cupboard();
        let d = PyDict::new(py);
        d.set_item("width", c.width())?;
        d.set_item("depth", c.depth())?;
        d.set_item("height", c.height())?;
        Ok(d)
    }

    /// Height of the map plane, m.
    #[getter]
    fn slice_height(&self) -> f64 {
        self.inner.config().slice_height
    }

    /// The seed.
    #[getter]
    fn seed(&self) -> u64 {
        self.inner.seed()
    }

    /// Scene steps since reset.
    #[getter]
    fn steps(&self) -> u64 {
        self.inner.steps()
    }

    /// All body poses and velocities, the hand and the readings, flattened (for determinism
    /// checks), (N,) float64.
    #[getter]
    fn state_vector<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_vec(py, self.inner.state_vector())
    }

    fn __repr__(&self) -> String {
        format!(
            "Scene(seed={}, jars={}, target={}, steps={})",
            self.inner.seed(),
            self.inner.layout().jars.len(),
            self.inner.target(),
            self.inner.steps()
        )
    }
}
