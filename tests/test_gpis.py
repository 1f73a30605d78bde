"""The Python contract of ``tactile_search.Gpis``: names, shapes, conventions, bad input."""

from __future__ import annotations

import threading

import numpy as np
import pytest

from tactile_search import Gpis

BOUNDS = ((-0.3, 0.3), (0.0, 0.3))


@pytest.fixture
def gpis() -> Gpis:
    return Gpis(bounds=BOUNDS, shape=(24, 32))


def random_points(rng: np.random.Generator, count: int) -> np.ndarray:
    return rng.uniform([-0.3, 0.0], [0.3, 0.3], size=(count, 2))


def test_defaults_follow_the_contract(gpis: Gpis) -> None:
    assert gpis.psi == pytest.approx(1.5 * np.hypot(0.6, 0.3))
    assert gpis.n_rows == 0
    assert gpis.max_rows == 4096
    assert gpis.prior_mean == 0.0
    assert gpis.shape == (24, 32)
    assert gpis.bounds == BOUNDS
    assert gpis.mean.shape == (24, 32) and gpis.mean.dtype == np.float64
    assert gpis.variance.shape == (24, 32) and gpis.variance.dtype == np.float64
    np.testing.assert_allclose(gpis.variance, gpis.psi**3)


def test_cell_centres_follow_the_documented_convention(gpis: Gpis) -> None:
    (x0, x1), (y0, y1) = BOUNDS
    height, width = gpis.shape
    centres = gpis.cell_centres
    assert centres.shape == (height, width, 2)
    i, j = 5, 17
    expected = (x0 + (j + 0.5) * (x1 - x0) / width, y0 + (i + 0.5) * (y1 - y0) / height)
    np.testing.assert_allclose(centres[i, j], expected)


def test_add_returns_rows_added_and_grids_match_predict(gpis: Gpis) -> None:
    rng = np.random.default_rng(0)
    assert gpis.add_values(random_points(rng, 20)) == 20
    normals = rng.normal(size=(5, 2)) * 3.0  # not unit length: they are normalised
    assert gpis.add_contacts(random_points(rng, 5), normals) == 15
    assert gpis.n_rows == 35
    assert gpis.free_rows == 4096 - 35
    mean, variance = gpis.predict(gpis.cell_centres.reshape(-1, 2))
    assert mean.shape == variance.shape == (24 * 32,)
    np.testing.assert_allclose(mean.reshape(24, 32), gpis.mean, atol=1e-9)
    np.testing.assert_allclose(variance.reshape(24, 32), gpis.variance, atol=1e-9)


def test_incremental_grids_equal_the_full_recompute(gpis: Gpis) -> None:
    rng = np.random.default_rng(1)
    gpis.add_values(random_points(rng, 100), values=rng.uniform(-0.01, 0.05, 100))
    for _ in range(30):
        gpis.add_contacts(random_points(rng, 1), rng.normal(size=(1, 2)))
    mean, variance = gpis.recompute_from_scratch()
    np.testing.assert_allclose(gpis.mean, mean, atol=1e-9, rtol=0)
    np.testing.assert_allclose(gpis.variance, variance, atol=1e-9, rtol=0)


def test_contact_sets_value_and_gradient(gpis: Gpis) -> None:
    point = np.array([[0.05, 0.1]])
    gpis.add_contacts(point, [[0.0, -2.0]], noise_std=0.0, normal_noise_std=0.0)
    mean, variance, gradient = gpis.predict(point, return_gradient=True)
    assert abs(mean[0]) < 1e-8 and variance[0] < 1e-8
    np.testing.assert_allclose(gradient[0], [0.0, -1.0], atol=1e-6)


def test_positive_prior_mean_reads_unobserved_space_as_free() -> None:
    gpis = Gpis(bounds=BOUNDS, shape=(8, 8), prior_mean=0.05)
    assert np.all(gpis.mean == 0.05)


def test_skip_below_variance_reports_what_it_skipped(gpis: Gpis) -> None:
    points = np.array([[0.0, 0.1], [0.0, 0.1], [0.2, 0.2]])
    normals = np.array([[0.0, -1.0]] * 3)
    assert gpis.add_contacts(points, normals, skip_below_variance=1e-5) == 6
    assert gpis.last_report == {
        "added_rows": 6,
        "added_observations": 2,
        "skipped_uninformative": 1,
        "rejected_degenerate": 0,
    }


def test_duplicate_noise_free_point_is_rejected_without_nan(gpis: Gpis) -> None:
    gpis.add_values([[0.1, 0.1]], noise_std=0.0)
    assert gpis.add_values([[0.1, 0.1]], noise_std=0.0) == 0
    assert gpis.last_report["rejected_degenerate"] == 1
    assert np.all(np.isfinite(gpis.mean)) and np.all(np.isfinite(gpis.variance))


def test_full_map_raises_and_keeps_its_rows() -> None:
    gpis = Gpis(bounds=BOUNDS, shape=(8, 8), max_rows=4)
    gpis.add_values([[0.0, 0.1], [0.1, 0.1]])
    before = gpis.mean
    with pytest.raises(ValueError, match="max_rows=4"):
        gpis.add_contacts([[0.2, 0.2]], [[1.0, 0.0]])
    assert gpis.n_rows == 2
    np.testing.assert_array_equal(gpis.mean, before)


def test_clear_restores_the_prior(gpis: Gpis) -> None:
    gpis.add_values([[0.0, 0.1]])
    gpis.clear()
    assert gpis.n_rows == 0
    np.testing.assert_allclose(gpis.variance, gpis.psi**3)


def test_lists_and_integer_arrays_are_accepted(gpis: Gpis) -> None:
    assert gpis.add_values([[0, 0]]) == 1
    assert gpis.add_values(np.array([[0, 1]], dtype=np.int32) / 10) == 1


def test_empty_input_adds_nothing(gpis: Gpis) -> None:
    assert gpis.add_values(np.zeros((0, 2))) == 0
    mean, variance = gpis.predict(np.zeros((0, 2)))
    assert mean.shape == variance.shape == (0,)


def test_grids_are_copies(gpis: Gpis) -> None:
    grid = gpis.mean
    grid[:] = 99.0
    assert not np.any(gpis.mean == 99.0)


def test_gil_is_released_while_rust_computes() -> None:
    """Two maps fed from two threads finish, and each equals its own full recompute."""
    maps = [Gpis(bounds=BOUNDS, shape=(32, 32)) for _ in range(2)]

    def feed(gpis: Gpis, seed: int) -> None:
        rng = np.random.default_rng(seed)
        gpis.add_values(random_points(rng, 300))

    threads = [threading.Thread(target=feed, args=(g, s)) for s, g in enumerate(maps)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    for gpis in maps:
        assert gpis.n_rows == 300
        np.testing.assert_allclose(gpis.mean, gpis.recompute_from_scratch()[0], atol=1e-9)


BAD_CONSTRUCTORS = [
    ({"bounds": ((0.3, -0.3), (0.0, 0.3))}, ValueError, "lower < upper"),
    ({"bounds": ((0.0, 1.0),)}, ValueError, r"\(\(x0, x1\), \(y0, y1\)\)"),
    ({"bounds": ((0.0, np.nan), (0.0, 1.0))}, ValueError, "finite"),
    ({"bounds": "shelf"}, TypeError, "real numbers"),
    ({"shape": (0, 5)}, ValueError, r"shape\[0\] must be at least 1"),
    ({"shape": (-3, 5)}, ValueError, "at least 1"),
    ({"shape": (4.5, 5)}, TypeError, "integer"),
    ({"shape": (4, 5, 6)}, ValueError, "two positive integers"),
    ({"shape": 7}, TypeError, "two positive integers"),
    ({"psi": 0.5}, ValueError, "psi must be finite and at least the diagonal"),
    ({"psi": np.inf}, ValueError, "psi must be finite"),
    ({"psi": "big"}, TypeError, "psi must be a real number"),
    ({"prior_mean": np.nan}, ValueError, "prior_mean must be finite"),
    ({"max_rows": 0}, ValueError, "max_rows must be at least 1"),
    ({"max_rows": 2.5}, TypeError, "max_rows must be an integer"),
]


@pytest.mark.parametrize(("override", "error", "message"), BAD_CONSTRUCTORS)
def test_bad_constructor_arguments_raise_clear_errors(
    override: dict, error: type[Exception], message: str
) -> None:
    kwargs = {"bounds": BOUNDS, "shape": (8, 8)} | override
    with pytest.raises(error, match=message):
        Gpis(**kwargs)


BAD_VALUES = [
    ({"points": [[0.0, 0.5]]}, ValueError, r"outside the map bounds"),
    ({"points": [0.0, 0.1]}, ValueError, r"shape \(N, 2\), got shape \(2,\)"),
    ({"points": [[0.0, 0.1, 0.2]]}, ValueError, r"shape \(N, 2\)"),
    ({"points": [[np.nan, 0.1]]}, ValueError, "points must be finite"),
    ({"points": [[np.inf, 0.1]]}, ValueError, "points must be finite"),
    ({"points": [["a", "b"]]}, TypeError, "real numbers"),
    ({"points": [[0.0, 0.1]], "values": [0.0, 1.0]}, ValueError, r"shape \(1,\)"),
    ({"points": [[0.0, 0.1]], "values": [np.nan]}, ValueError, "values must be finite"),
    ({"points": [[0.0, 0.1]], "noise_std": -0.1}, ValueError, "noise_std must be at least 0"),
    ({"points": [[0.0, 0.1]], "noise_std": np.nan}, ValueError, "noise_std must be finite"),
]


@pytest.mark.parametrize(("kwargs", "error", "message"), BAD_VALUES)
def test_bad_value_observations_raise_clear_errors(
    gpis: Gpis, kwargs: dict, error: type[Exception], message: str
) -> None:
    with pytest.raises(error, match=message):
        gpis.add_values(**kwargs)
    assert gpis.n_rows == 0


BAD_CONTACTS = [
    ({"points": [[0.0, -0.1]]}, ValueError, "outside the map bounds"),
    ({"normals": [[0.0, 0.0]]}, ValueError, r"normals\[0\] must be non-zero"),
    ({"normals": [[1.0, 0.0], [0.0, 1.0]]}, ValueError, "one row per point"),
    ({"normals": [[np.nan, 1.0]]}, ValueError, "normals must be finite"),
    ({"normals": [1.0, 0.0]}, ValueError, r"normals must have shape \(N, 2\)"),
    ({"noise_std": -1.0}, ValueError, "noise_std must be at least 0"),
    ({"normal_noise_std": -1.0}, ValueError, "normal_noise_std must be at least 0"),
    ({"skip_below_variance": -1.0}, ValueError, "skip_below_variance must be at least 0"),
    ({"skip_below_variance": "x"}, TypeError, "skip_below_variance must be a real number"),
]


@pytest.mark.parametrize(("override", "error", "message"), BAD_CONTACTS)
def test_bad_contacts_raise_clear_errors(
    gpis: Gpis, override: dict, error: type[Exception], message: str
) -> None:
    kwargs = {"points": [[0.0, 0.1]], "normals": [[1.0, 0.0]]} | override
    with pytest.raises(error, match=message):
        gpis.add_contacts(**kwargs)
    assert gpis.n_rows == 0


@pytest.mark.parametrize(
    ("points", "message"),
    [([[0.0, 0.31]], "outside the map bounds"), ([[np.nan, 0.0]], "finite"), ([1, 2], "(N, 2)")],
)
def test_bad_prediction_points_raise_value_error(gpis: Gpis, points: list, message: str) -> None:
    with pytest.raises(ValueError, match=message.replace("(", r"\(").replace(")", r"\)")):
        gpis.predict(points)


def test_circle_prior_adds_four_contacts_with_radial_normals(gpis: Gpis) -> None:
    assert gpis.add_circle_prior((0.0, 0.15), diameter=0.03) == 12
    mean, _, gradient = gpis.predict([[0.0, 0.15], [0.015, 0.15]], return_gradient=True)
    assert mean[0] < 0.0
    np.testing.assert_allclose(gradient[1], [1.0, 0.0], atol=0.05)


@pytest.mark.parametrize(
    ("kwargs", "error", "message"),
    [
        ({"centre": (0.0, 0.15), "diameter": -0.03}, ValueError, "diameter must be at least 0"),
        ({"centre": (0.0, 0.15), "diameter": 0.0}, ValueError, "diameter must be finite and"),
        ({"centre": (0.0,)}, ValueError, r"centre must have shape \(2,\)"),
        ({"centre": (0.29, 0.15), "diameter": 0.1}, ValueError, "outside the map bounds"),
    ],
)
def test_bad_circle_prior_raises(
    gpis: Gpis, kwargs: dict, error: type[Exception], message: str
) -> None:
    with pytest.raises(error, match=message):
        gpis.add_circle_prior(**kwargs)
    assert gpis.n_rows == 0


def test_defaults_and_checks_come_from_the_core() -> None:
    """The signatures show the core's defaults (``_core.gpis_defaults()``), and the default
    psi is the core's factor times the bounds' diagonal."""
    import inspect

    from tactile_search import _core

    defaults = _core.gpis_defaults()
    params = inspect.signature(Gpis).parameters
    assert params["prior_mean"].default == defaults["prior_mean"]
    assert params["max_rows"].default == defaults["max_rows"]
    add_values = inspect.signature(Gpis.add_values).parameters
    assert add_values["noise_std"].default == defaults["value_noise_std"]
    add_contacts = inspect.signature(Gpis.add_contacts).parameters
    assert add_contacts["noise_std"].default == defaults["contact_noise_std"]
    assert add_contacts["normal_noise_std"].default == defaults["normal_noise_std"]
    circle = inspect.signature(Gpis.add_circle_prior).parameters
    assert circle["diameter"].default == defaults["circle_diameter"]
    gpis = Gpis(bounds=BOUNDS, shape=(8, 8))
    diagonal = np.hypot(*np.ptp(np.asarray(BOUNDS), axis=1))
    assert gpis.psi == pytest.approx(defaults["psi_factor"] * diagonal, rel=1e-12)
    assert (gpis.prior_mean, gpis.max_rows) == (defaults["prior_mean"], defaults["max_rows"])
    with pytest.raises(ValueError, match="max_rows must fit in 64 bits"):
        _core.GpisCore(BOUNDS, (8, 8), None, 0.0, max_rows=2**64)
    with pytest.raises(TypeError, match="max_rows must be an integer, got bool: True"):
        _core.GpisCore(BOUNDS, (8, 8), None, 0.0, max_rows=True)
    # None is not a default for a given argument, as for Gpis before the core checked them.
    for name in ("prior_mean", "max_rows"):
        with pytest.raises(TypeError, match=f"^{name} must be "):
            Gpis(bounds=BOUNDS, shape=(8, 8), **{name: None})
