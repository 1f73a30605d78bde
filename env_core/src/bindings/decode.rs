//! The inverses of the core's encodings and the static geometry, for Python planners
//! (`EpisodeBatch.decode_map`, `.decode_proprio`, `.geometry`, `.probe_motions`): what the core knows of the
//! observation's meaning, so no planner re-types a scale or a size. The core does the work
//! ([`crate::episode::maps::decode_image`], [`crate::episode::decode_proprio`],
//! [`crate::episode::StaticGeometry`]); this file checks the arrays and builds the dicts.
//! Cost: O(G) per map image, O(1) per proprio vector, O(G) for the geometry's cell
//! centres.

use numpy::{Element, PyArray1, PyArrayDyn, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use super::errors::{shape_text, type_name, wrong_shape, wrong_type, wrong_value};
use crate::episode::maps::decode_image;
use crate::episode::{
    decode_proprio, EpisodeConfig, ProbeController, Quantity, StaticGeometry, PROPRIO_LEN,
};
use crate::scene::HandPose;
use crate::settings::Choice;

/// `value` as a numpy array of dtype `T`: `TypeError` naming `expected`, and what came
/// (its type and dtype), for anything else.
pub(super) fn typed_array<'a, 'py, T: Element>(
    what: &str,
    value: &'a Bound<'py, PyAny>,
    expected: &str,
) -> PyResult<&'a Bound<'py, PyArrayDyn<T>>> {
    value.cast::<PyArrayDyn<T>>().or_else(|_| {
        Err(match value.getattr("dtype") {
            Ok(got) => PyTypeError::new_err(format!(
                "{what} must be {expected}, got {} of dtype {}",
                type_name(value),
                got.str()?
            )),
            Err(_) => wrong_type(what, expected, value),
        })
    })
}

/// The values of `value`, a numpy array of dtype `T` (named `dtype`) and exactly `shape`,
/// in row-major order: `TypeError` for anything else (naming its type and dtype),
/// `ValueError` for another shape.
pub(super) fn exact_array<T: Element + Copy>(
    what: &str,
    value: &Bound<'_, PyAny>,
    dtype: &str,
    shape: &[usize],
) -> PyResult<Vec<T>> {
    let expected = format!("a {dtype} numpy array of shape {}", shape_text(shape));
    let array = typed_array::<T>(what, value, &expected)?;
    if array.shape() != shape {
        return Err(wrong_shape(what, &shape_text(shape), array.shape()));
    }
    values_of(what, array)
}

/// The values of `array` in row-major order (`ValueError` while another borrow writes it).
pub(super) fn values_of<T: Element + Copy>(
    what: &str,
    array: &Bound<'_, PyArrayDyn<T>>,
) -> PyResult<Vec<T>> {
    let readonly = array.try_readonly().map_err(|e| {
        wrong_value(
            what,
            "an array that is not being written elsewhere",
            e.to_string(),
        )
    })?;
    Ok(readonly.as_array().iter().copied().collect())
}

/// A map image `(C, H, W)` uint8 of `config`'s map mode decoded: one (H, W) float64
/// array per channel that carries a quantity, by its decoded name.
pub(super) fn map_dict<'py>(
    py: Python<'py>,
    config: &EpisodeConfig,
    image: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyDict>> {
    let channels = config.map.mode.kind().channels.len();
    if channels == 0 {
        return Err(wrong_value(
            "map",
            "the image of a map mode that has one",
            format!(
                "an image for map='{}', which has no map image",
                config.map.mode.name()
            ),
        ));
    }
    let (h, w) = config.map.grid_shape;
    let pixels: Vec<u8> = exact_array("map", image, "uint8", &[channels, h, w])?;
    let decoded = decode_image(&config.map, h * w, &pixels)
        .map_err(|e| wrong_value("map", &e.expected, e.got))?;
    let d = PyDict::new(py);
    for (name, values) in decoded {
        d.set_item(name, PyArray1::from_vec(py, values).reshape([h, w])?)?;
    }
    Ok(d)
}

/// A proprio vector `(PROPRIO_LEN,)` float32 of `config` decoded: every quantity by name
/// (floats, `in_contact` a bool, `steps` an int).
pub(super) fn proprio_dict<'py>(
    py: Python<'py>,
    config: &EpisodeConfig,
    proprio: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyDict>> {
    let values: Vec<f32> = exact_array("proprio", proprio, "float32", &[PROPRIO_LEN])?;
    let values: [f32; PROPRIO_LEN] = values.try_into().expect("exact_array checked the length");
    let d = PyDict::new(py);
    for (name, quantity) in decode_proprio(&values, config) {
        match quantity {
            Quantity::Real(v) => d.set_item(name, v)?,
            Quantity::Flag(v) => d.set_item(name, v)?,
            Quantity::Count(v) => d.set_item(name, v)?,
        }
    }
    Ok(d)
}

/// The static geometry of `config` ([`StaticGeometry`]) as a dict; `xs` and `ys` are the
/// cells' centres, (H, W) float64 each.
pub(super) fn geometry_dict<'py>(
    py: Python<'py>,
    config: &EpisodeConfig,
) -> PyResult<Bound<'py, PyDict>> {
    let g = StaticGeometry::of(config)?;
    let d = PyDict::new(py);
    d.set_item("width", g.width)?;
    d.set_item("depth", g.depth)?;
    d.set_item("camera", (g.camera[0], g.camera[1]))?;
    d.set_item("start", (g.start[0], g.start[1], g.start[2]))?;
    let [[x0, x1], [y0, y1]] = g.workspace;
    d.set_item("workspace", ((x0, x1), (y0, y1)))?;
    d.set_item("max_step_translation", g.max_step_translation)?;
    d.set_item("max_step_yaw", g.max_step_yaw)?;
    d.set_item("wrist_half_extent", g.wrist_half_extent)?;
    d.set_item("arm_length", g.arm_length)?;
    d.set_item("arm_half_width", g.arm_half_width)?;
    d.set_item("finger_length", g.finger_length)?;
    d.set_item("finger_half_thickness", g.finger_half_thickness)?;
    d.set_item("finger_limit", g.finger_limit)?;
    d.set_item("joint_offset", g.joint_offset)?;
    d.set_item("reach", g.reach)?;
    d.set_item("jar_radius", (g.jar_radius[0], g.jar_radius[1]))?;
    d.set_item("target_min_depth", g.target_min_depth)?;
    d.set_item("wall_gap", g.wall_gap)?;
    d.set_item("grid_shape", g.grid.shape())?;
    d.set_item("cell", g.cell)?;
    d.set_item("mean_scale", g.mean_scale)?;
    d.set_item("std_scale", g.std_scale)?;
    let (h, w) = g.grid.shape();
    let (xs, ys) = g.cell_centres();
    d.set_item("xs", PyArray1::from_vec(py, xs).reshape([h, w])?)?;
    d.set_item("ys", PyArray1::from_vec(py, ys).reshape([h, w])?)?;
    let probes = &g.probes;
    d.set_item("probe_lanes", PyArray1::from_slice(py, &probes.lanes))?;
    d.set_item("probe_depths", PyArray1::from_slice(py, &probes.depths))?;
    d.set_item("probe_yaws", PyArray1::from_slice(py, &probes.yaws))?;
    d.set_item("probe_outside", probes.outside)?;
    d.set_item("probe_sweep_rate", probes.sweep_rate)?;
    Ok(d)
}

/// The wrist motions the `probe` mode's controller of `config` makes from the wrist `pose`
/// (x, y, yaw) to finish each probe of `actions`, an `(n, 3)` int64 array of indices, when
/// nothing touches or blocks the hand ([`ProbeController::motions`]): `TypeError` for
/// anything but an int64 array, `ValueError` for another shape, an index outside the counts
/// or a non-finite pose.
pub(super) fn probe_motions<'py>(
    py: Python<'py>,
    config: &EpisodeConfig,
    pose: [f64; 3],
    actions: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyArray1<i64>>> {
    const WHAT: &str = "actions";
    let expected = "an int64 numpy array of shape (n, 3)";
    let array = typed_array::<i64>(WHAT, actions, expected)?;
    let shape = array.shape().to_vec();
    if shape.len() != 2 || shape[1] != 3 {
        return Err(wrong_shape(WHAT, "(n, 3)", &shape));
    }
    if pose.iter().any(|v| !v.is_finite()) {
        return Err(wrong_value(
            "pose",
            "finite (x, y, yaw)",
            format!("{pose:?}"),
        ));
    }
    let values: Vec<i64> = array.try_readonly()?.as_array().iter().copied().collect();
    let controller = ProbeController::for_episode(config);
    let [x, y, yaw] = pose;
    let from = HandPose { x, y, yaw };
    let mut motions = Vec::with_capacity(shape[0]);
    for row in values.chunks_exact(3) {
        let action = [row[0], row[1], row[2]];
        controller.check(&action)?;
        motions.push(controller.motions(from, &controller.probe(&action)) as i64);
    }
    Ok(PyArray1::from_vec(py, motions))
}
