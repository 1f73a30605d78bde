//! `_core.Scene`: the cupboard scene for inspection from Python. Build from a seed and a flat
//! config (a dict and/or keyword arguments), command the hand, step (without the GIL), and read
//! the depth image, clouds, slice, contacts, jars and target as numpy arrays and dicts.

use numpy::{PyArray1, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use super::convert::{array2, rows_array, seed_of};
use super::errors::wrong_value;
use super::exclusive::Exclusive;
use super::settings::{config_dict, config_from, describe};
use crate::scene::{Contact, DepthCapture, HandCommand, Scene, SceneConfig, StepReport};
use crate::settings::Settings;

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
#[pyclass(name = "Scene", module = "tactile_search._core", frozen)]
pub struct PyScene {
    scene: Exclusive<Scene>,
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
        let config = config_from::<SceneConfig>(config, kwargs, None)?;
        let inner = py.detach(|| Scene::new(&config, seed))?;
        Ok(Self {
            scene: Exclusive::new("Scene", inner),
        })
    }

    /// Every setting key, in the table's order.
    #[staticmethod]
    fn config_keys() -> Vec<&'static str> {
        SceneConfig::keys()
    }

    /// The scene's settings table: one dict per setting with key, type, default, range,
    /// choices and doc.
    #[staticmethod]
    fn settings(py: Python<'_>) -> PyResult<Bound<'_, PyList>> {
        describe::<SceneConfig>(py)
    }

    /// Moves the wrist by (dx, dy, dyaw) (clipped to the step bounds, stopped at walls) over
    /// the configured physics substeps; returns a report dict.
    #[pyo3(signature = (dx = 0.0, dy = 0.0, dyaw = 0.0))]
    fn step<'py>(
        &self,
        py: Python<'py>,
        dx: f64,
        dy: f64,
        dyaw: f64,
    ) -> PyResult<Bound<'py, PyDict>> {
        let mut scene = self.scene.lock()?;
        let inner = &mut *scene;
        let report = py.detach(|| inner.step(HandCommand { dx, dy, dyaw }))?;
        report_dict(py, &report)
    }

    /// Runs `n` physics steps with the hand held still.
    fn idle(&self, py: Python<'_>, n: i64) -> PyResult<()> {
        let n =
            usize::try_from(n).map_err(|_| wrong_value("idle(n): n", "a non-negative int", n))?;
        let mut scene = self.scene.lock()?;
        let inner = &mut *scene;
        py.detach(|| inner.idle(n));
        Ok(())
    }

    /// A new depth look at the current state (fresh noise), as a dict of arrays.
    fn capture<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let mut scene = self.scene.lock()?;
        let inner = &mut *scene;
        let look = py.detach(|| inner.capture());
        capture_dict(py, &look)
    }

    /// Every setting of this scene by its config key (the defaults plus what was given): a
    /// dict that `Scene(seed, config=...)` accepts back.
    #[getter]
    fn config<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let scene = self.scene.lock()?;
        config_dict(py, scene.config())
    }

    /// The first look taken at reset, as a dict of arrays: depth (H, W), labels (H, W),
    /// cloud (N, 3), cloud_labels (N,), slice (M, 2), slice_clean (M, 2), slice_labels (M,).
    /// The whole image is rendered on each read (a few ms).
    #[getter]
    fn first_look<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let scene = self.scene.lock()?;
        let inner = &*scene;
        let look = py.detach(|| inner.first_look());
        capture_dict(py, &look)
    }

    /// Depth image of the first look, (H, W) float64, NaN where nothing was hit (rendered on
    /// each read).
    #[getter]
    fn depth_image<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let scene = self.scene.lock()?;
        let inner = &*scene;
        let image = py.detach(|| inner.first_look().image);
        array2(py, image.height, image.width, image.depth)
    }

    /// Back-projected 3D cloud of the first look, (N, 3) float64 (rendered on each read).
    #[getter]
    fn cloud<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let scene = self.scene.lock()?;
        let inner = &*scene;
        let look = py.detach(|| inner.first_look());
        rows_array(py, &look.cloud)
    }

    /// The noisy, thinned 2D slice of the first look, (M, 2) float64 (kept from reset).
    #[getter]
    fn slice_points<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let scene = self.scene.lock()?;
        rows_array(py, scene.first_slice())
    }

    /// Tactile readings after the last step (with noise): points (K, 2), normals (K, 2),
    /// jars (K,) int64 (ground truth).
    #[getter]
    fn contacts<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let scene = self.scene.lock()?;
        contacts_dict(py, scene.contacts())
    }

    /// The same readings without noise.
    #[getter]
    fn true_contacts<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let scene = self.scene.lock()?;
        contacts_dict(py, scene.true_contacts())
    }

    /// Jars: shapes (list of str), half_widths, heights, masses, yaws at reset (n,),
    /// positions (n, 3), rotations (n, 4) as (x, y, z, w), displacement, vertical, tilt (n,),
    /// is_target (n,) bool.
    #[getter]
    fn jars<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let scene = self.scene.lock()?;
        let states = scene.jar_states();
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
        let target = scene.target();
        let is_target: Vec<bool> = (0..n).map(|i| i == target).collect();
        d.set_item("is_target", PyArray1::from_vec(py, is_target))?;
        Ok(d)
    }

    /// Index of the target jar.
    #[getter]
    fn target(&self) -> PyResult<usize> {
        let scene = self.scene.lock()?;
        Ok(scene.target())
    }

    /// The target's shape, `"round"` or `"square"`.
    #[getter]
    fn target_shape(&self) -> PyResult<&'static str> {
        let scene = self.scene.lock()?;
        let layout = scene.layout();
        Ok(layout.jars[layout.target].shape.name())
    }

    /// Visible fraction of the target (visible / silhouette pixels, by ray casting).
    #[getter]
    fn visible_fraction(&self) -> PyResult<f64> {
        let scene = self.scene.lock()?;
        Ok(scene.layout().visibility.fraction())
    }

    /// (silhouette pixels, visible pixels) of the target.
    #[getter]
    fn target_pixels(&self) -> PyResult<(usize, usize)> {
        let scene = self.scene.lock()?;
        let v = scene.layout().visibility;
        Ok((v.silhouette_pixels, v.visible_pixels))
    }

    /// The clear corridor to the target: dict with x (lo, hi), y (lo, hi), side; or None.
    #[getter]
    fn corridor<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let scene = self.scene.lock()?;
        scene
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
    fn hand_pose(&self) -> PyResult<(f64, f64, f64)> {
        let scene = self.scene.lock()?;
        let p = scene.hand_pose();
        Ok((p.x, p.y, p.yaw))
    }

    /// The finger joint's position and the finger's yaw (x, y, yaw).
    #[getter]
    fn finger_pose(&self) -> PyResult<(f64, f64, f64)> {
        let scene = self.scene.lock()?;
        let p = scene.finger_pose();
        Ok((p.x, p.y, p.yaw))
    }

    /// Sensed finger deflection (joint angle), rad.
    #[getter]
    fn finger_angle(&self) -> PyResult<f64> {
        let scene = self.scene.lock()?;
        Ok(scene.finger_angle())
    }

    /// Camera intrinsics and extrinsics: width, height, fx, fy, cx, cy, position (3,),
    /// rotation (3, 3) camera→world (columns right, down, forward).
    #[getter]
    fn camera<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let scene = self.scene.lock()?;
        let camera = scene.camera();
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
        let scene = self.scene.lock()?;
        let c = scene.cupboard();
        let d = PyDict::new(py);
        d.set_item("width", c.width())?;
        d.set_item("depth", c.depth())?;
        d.set_item("height", c.height())?;
        Ok(d)
    }

    /// Height of the map plane, m.
    #[getter]
    fn slice_height(&self) -> PyResult<f64> {
        let scene = self.scene.lock()?;
        Ok(scene.config().slice_height)
    }

    /// The seed.
    #[getter]
    fn seed(&self) -> PyResult<u64> {
        let scene = self.scene.lock()?;
        Ok(scene.seed())
    }

    /// Scene steps since reset.
    #[getter]
    fn steps(&self) -> PyResult<u64> {
        let scene = self.scene.lock()?;
        Ok(scene.steps())
    }

    /// All body poses and velocities, the hand and the readings, flattened (for determinism
    /// checks), (N,) float64.
    #[getter]
    fn state_vector<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let scene = self.scene.lock()?;
        Ok(PyArray1::from_vec(py, scene.state_vector()))
    }

    fn __repr__(&self) -> PyResult<String> {
        let scene = self.scene.lock()?;
        Ok(format!(
            "Scene(seed={}, jars={}, target={}, steps={})",
            scene.seed(),
            scene.layout().jars.len(),
            scene.target(),
            scene.steps()
        ))
    }
}
