//! Geometry and metrics of the core as functions (`_core.jar_signed_distance`,
//! `_core.footprint_mask`, `_core.outline_distance`, `_core.hand_geometry`, ...): the
//! experiments, the rendering and the planners call these instead of keeping their own
//! copies, so they measure and draw what the environment computes.
//!
//! Jars come as the dict `Scene.jars` returns (or any dict with the same keys):
//! `shapes` (sequence of `"round"`/`"square"`), `positions` (J, 2) or (J, 3) (x, y first),
//! `half_widths` (J,) (radius or half side, m) and `yaws` (J,) (rad).

use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use super::arrays::{count, grid, grid_values, mask, matrix, points, vector};
use super::errors::{wrong_type, wrong_value};
use super::settings::{config_dict, config_from};
use crate::episode::level_set::zero_level_segments as level_set_segments;
use crate::episode::metrics::{footprints_mask, interior_iou as map_iou};
use crate::episode::outline;
use crate::gpis::GridSpec;
use crate::scene::hand::{joint_offset, reach};
use crate::scene::{Footprint, JarShape, SceneConfig};

/// Outline samples per jar when the caller gives none.
const OUTLINE_SAMPLES: usize = 64;

const JARS: &str =
    "a dict with shapes, positions (J, 2 or 3), half_widths (J,) and yaws (J,) (see Scene.jars)";

/// The footprints of a jars dict (see the module docs).
pub(super) fn footprints(jars: &Bound<'_, PyAny>) -> PyResult<Vec<Footprint>> {
    let dict = jars
        .cast::<PyDict>()
        .map_err(|_| wrong_type("jars", JARS, jars))?;
    let item = |key: &str| -> PyResult<Bound<'_, PyAny>> {
        dict.get_item(key)?
            .ok_or_else(|| wrong_value("jars", JARS, format!("no key {key:?}")))
    };
    let shapes_value = item("shapes")?;
    let shapes: Vec<String> = shapes_value
        .extract()
        .map_err(|_| wrong_type("jars[\"shapes\"]", "a sequence of str", &shapes_value))?;
    let n = shapes.len();
    if n == 0 {
        return Ok(Vec::new());
    }
    let positions = item("positions")?;
    let columns = match positions
        .getattr("shape")
        .and_then(|s| s.extract::<Vec<usize>>())
    {
        Ok(shape) if shape.len() == 2 && shape[1] == 3 => 3,
        _ => 2,
    };
    let (rows, flat) = matrix("jars[\"positions\"]", &positions, columns)?;
    if rows != n {
        return Err(wrong_value(
            "jars[\"positions\"]",
            &format!("one row per shape ({n})"),
            format!("{rows} rows"),
        ));
    }
    let half_widths = vector("jars[\"half_widths\"]", &item("half_widths")?, n)?;
    let yaws = vector("jars[\"yaws\"]", &item("yaws")?, n)?;
    (0..n)
        .map(|k| {
            let half = half_widths[k];
            if half <= 0.0 {
                return Err(wrong_value("jars[\"half_widths\"]", "> 0 everywhere", half));
            }
            let shape = JarShape::from_name(&shapes[k], half).ok_or_else(|| {
                wrong_value(
                    "jars[\"shapes\"]",
                    &format!(
                        "{:?} or {:?}",
                        JarShape::Round { radius: half }.name(),
                        JarShape::Square { half_side: half }.name()
                    ),
                    format!("{:?}", shapes[k]),
                )
            })?;
            Ok(Footprint {
                shape,
                centre: [flat[k * columns], flat[k * columns + 1]],
                yaw: yaws[k],
            })
        })
        .collect()
}

/// A map's mean grid and the grid it lives on (the bounds and the mean's shape).
fn mean_on(mean: &Bound<'_, PyAny>, bounds: &Bound<'_, PyAny>) -> PyResult<(Vec<f64>, GridSpec)> {
    let (values, (h, w)) = grid_values("mean", mean)?;
    let shape = (h, w).into_pyobject(mean.py())?;
    Ok((values, grid(bounds, shape.as_any())?))
}

fn positive_cap(cap: f64) -> PyResult<f64> {
    if cap.is_finite() && cap > 0.0 {
        Ok(cap)
    } else {
        Err(wrong_value("cap", "finite and > 0", cap))
    }
}

/// Signed distance (negative inside) from each of the (N, 2) `points` to each jar's
/// footprint, (J, N). Cost O(J·N).
#[pyfunction]
pub(super) fn jar_signed_distance<'py>(
    py: Python<'py>,
    jars: &Bound<'py, PyAny>,
    points: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let footprints = footprints(jars)?;
    let points = self::points("points", points)?;
    let flat: Vec<f64> = footprints
        .iter()
        .flat_map(|f| points.iter().map(|&p| f.signed_distance(p)))
        .collect();
    PyArray1::from_vec(py, flat).reshape([footprints.len(), points.len()])
}

/// `samples` points on each jar's outline (evenly in angle for a round jar, along the
/// perimeter for a square one), (J, samples, 2), not closed.
#[pyfunction]
#[pyo3(signature = (jars, samples = None))]
pub(super) fn jar_outlines<'py>(
    py: Python<'py>,
    jars: &Bound<'py, PyAny>,
    samples: Option<&Bound<'_, PyAny>>,
) -> PyResult<Bound<'py, PyAny>> {
    let footprints = footprints(jars)?;
    let samples = samples.map_or(Ok(OUTLINE_SAMPLES), |s| count("samples", s))?;
    let flat: Vec<f64> = footprints
        .iter()
        .flat_map(|f| f.outline(samples))
        .flatten()
        .collect();
    Ok(PyArray1::from_vec(py, flat)
        .reshape([footprints.len(), samples, 2])?
        .into_any())
}

/// Each jar's support distance along `normal` (normalised; non-zero): how far its
/// footprint reaches from its centre in that direction, (J,).
#[pyfunction]
pub(super) fn jar_support<'py>(
    py: Python<'py>,
    jars: &Bound<'py, PyAny>,
    normal: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let footprints = footprints(jars)?;
    let n = vector("normal", normal, 2)?;
    let length = n[0].hypot(n[1]);
    if length == 0.0 {
        return Err(wrong_value("normal", "a non-zero (x, y)", "(0, 0)"));
    }
    let unit = [n[0] / length, n[1] / length];
    Ok(PyArray1::from_vec(
        py,
        footprints.iter().map(|f| f.support(unit)).collect(),
    ))
}

/// Which cell centres of the grid `(bounds, shape)` lie closer than `margin` to a jar's
/// footprint (inside it at `margin = 0`): the truth of the environment's IoU, (H, W) bool.
#[pyfunction]
#[pyo3(signature = (jars, bounds, shape, margin = 0.0))]
pub(super) fn footprint_mask<'py>(
    py: Python<'py>,
    jars: &Bound<'py, PyAny>,
    bounds: &Bound<'py, PyAny>,
    shape: &Bound<'py, PyAny>,
    margin: f64,
) -> PyResult<Bound<'py, PyAny>> {
    let footprints = footprints(jars)?;
    let grid = grid(bounds, shape)?;
    if !(margin.is_finite() && margin >= 0.0) {
        return Err(wrong_value("margin", "finite and >= 0", margin));
    }
    let mut out = Vec::new();
    footprints_mask(&grid, footprints, margin, &mut out);
    let (h, w) = grid.shape();
    Ok(PyArray1::from_vec(py, out).reshape([h, w])?.into_any())
}

/// IoU of a map's interior (`mean < 0`) against the (H, W) bool `truth`, as the
/// environment's `info["iou"]`; 1 when both are empty.
#[pyfunction]
pub(super) fn interior_iou(mean: &Bound<'_, PyAny>, truth: &Bound<'_, PyAny>) -> PyResult<f64> {
    let (values, shape) = grid_values("mean", mean)?;
    let truth = mask("truth", truth, shape)?;
    Ok(map_iou(&values, &truth))
}

/// The zero level set of an (H, W) `mean` on `bounds` (marching squares between cell
/// centres, linear interpolation; `mean < 0` is inside), (S, 2, 2) segments.
#[pyfunction]
pub(super) fn zero_level_segments<'py>(
    py: Python<'py>,
    mean: &Bound<'py, PyAny>,
    bounds: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyAny>> {
    let (values, grid) = mean_on(mean, bounds)?;
    let segments = level_set_segments(&grid, &values);
    let n = segments.len();
    let flat: Vec<f64> = segments.into_iter().flatten().flatten().collect();
    Ok(PyArray1::from_vec(py, flat).reshape([n, 2, 2])?.into_any())
}

/// Mean over `samples` points on each true outline of the distance to the zero level set
/// of `mean` (H, W) on `bounds`, each capped at `cap` (m); `cap` without a level set.
#[pyfunction]
#[pyo3(signature = (mean, bounds, jars, samples = None, cap = 0.05))]
pub(super) fn outline_distance(
    py: Python<'_>,
    mean: &Bound<'_, PyAny>,
    bounds: &Bound<'_, PyAny>,
    jars: &Bound<'_, PyAny>,
    samples: Option<&Bound<'_, PyAny>>,
    cap: f64,
) -> PyResult<f64> {
    let (values, grid) = mean_on(mean, bounds)?;
    let footprints = footprints(jars)?;
    let samples = samples.map_or(Ok(OUTLINE_SAMPLES), |s| count("samples", s))?;
    let cap = positive_cap(cap)?;
    Ok(py.detach(|| outline::outline_distance(&grid, &values, &footprints, samples, cap)))
}

/// The reverse of `outline_distance`: mean over the zero level set's segment midpoints of
/// the distance to the nearest true outline, each capped at `cap`; `cap` without a level
/// set.
#[pyfunction]
#[pyo3(signature = (mean, bounds, jars, cap = 0.05))]
pub(super) fn spurious_distance(
    py: Python<'_>,
    mean: &Bound<'_, PyAny>,
    bounds: &Bound<'_, PyAny>,
    jars: &Bound<'_, PyAny>,
    cap: f64,
) -> PyResult<f64> {
    let (values, grid) = mean_on(mean, bounds)?;
    let footprints = footprints(jars)?;
    let cap = positive_cap(cap)?;
    Ok(py.detach(|| outline::spurious_distance(&grid, &values, &footprints, cap)))
}

/// The hand's sizes for a scene configuration (a dict of scene keys and/or keyword
/// arguments, as `Scene` takes): every hand setting by its key (`wrist_half_extent`,
/// `finger_length`, `hand_start`, ...), and the derived `joint_offset` (wrist centre to
/// finger joint) and `reach` (wrist centre to fingertip).
#[pyfunction]
#[pyo3(signature = (config = None, **kwargs))]
pub(super) fn hand_geometry<'py>(
    py: Python<'py>,
    config: Option<&Bound<'py, PyAny>>,
    kwargs: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyDict>> {
    let scene = config_from::<SceneConfig>(config, kwargs, None)?;
    let hand = &scene.hand;
    let d = config_dict(py, hand)?;
    d.set_item("joint_offset", joint_offset(hand))?;
    d.set_item("reach", reach(hand))?;
    Ok(d)
}

/// Registers the functions of this file on the module.
pub(super) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(jar_signed_distance, m)?)?;
    m.add_function(wrap_pyfunction!(jar_outlines, m)?)?;
    m.add_function(wrap_pyfunction!(jar_support, m)?)?;
    m.add_function(wrap_pyfunction!(footprint_mask, m)?)?;
    m.add_function(wrap_pyfunction!(interior_iou, m)?)?;
    m.add_function(wrap_pyfunction!(zero_level_segments, m)?)?;
    m.add_function(wrap_pyfunction!(outline_distance, m)?)?;
    m.add_function(wrap_pyfunction!(spurious_distance, m)?)?;
    m.add_function(wrap_pyfunction!(hand_geometry, m)?)?;
    Ok(())
}
