"""Fuzzing ``Gpis`` (hypothesis): constructor arguments and sequences of calls with points
exactly on and just outside the bounds, duplicates, empty and wrongly shaped arrays, odd
dtypes, huge and tiny noise, NaN and inf, and maps filled exactly to ``max_rows`` and one
beyond.

Every call either works, leaving finite mean and variance (variance never negative, never
above the prior's) and the rows it reports, or raises ``ValueError``/``TypeError`` naming
the argument and changes nothing. A pyo3 ``PanicException`` (a ``BaseException``) or any
other exception is a failure. test_gpis.py checks fixed bad inputs and
test_gpis_properties.py valid batches against a full recompute; this file draws the edges.
"""

from __future__ import annotations

import math
import subprocess
import sys
import warnings
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import array_shapes, arrays, scalar_dtypes

from tactile_search import Gpis, _core

MAX_PSI = 1e100  # the largest psi the map takes (env_core/src/gpis/config.rs, MAX_PSI)

DOCUMENTED = (ValueError, TypeError)
OK, BAD, EITHER = "ok", "bad", "either"
TINY = 5e-324


def examples(weight: float) -> int:
    """This test's share of the profile's ``max_examples`` (tests/conftest.py)."""
    return max(5, round(settings.default.max_examples * weight))


def call(function: Any, *args: Any, **kwargs: Any) -> tuple[Any, BaseException | None]:
    """The result, or the documented error; anything else (PanicException included) fails."""
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return function(*args, **kwargs), None
    except DOCUMENTED as error:
        return None, error
    except BaseException as error:  # PanicException derives from it
        pytest.fail(f"{type(error).__name__} from {function} with {args!r} {kwargs!r}: {error}")


def assert_sane(gpis: Gpis) -> None:
    mean, variance = gpis.mean, gpis.variance
    assert mean.shape == variance.shape == gpis.shape
    assert np.all(np.isfinite(mean)), "mean not finite"
    assert np.all(np.isfinite(variance)), "variance not finite"
    assert np.all(variance >= 0), variance.min()
    assert np.all(variance <= gpis.psi**3 * (1 + 1e-9)), "variance above the prior's"
    assert 0 <= gpis.n_rows <= gpis.max_rows
    assert gpis.free_rows == gpis.max_rows - gpis.n_rows


# --- the constructor ----------------------------------------------------------------------

# Extents and origins of any size: bounds whose default psi (1.5 x their diagonal) exceeds
# 1e100 are refused naming psi; the largest floats overflow the extent or the diagonal.
FLOAT_MAX = float(np.finfo(np.float64).max)
extents = st.one_of(
    st.sampled_from([TINY, 1e-300, 1e-9, 1e-3, 0.3, 1.0, 1e3, 1e100, 1e200, FLOAT_MAX]),
    st.floats(1e-6, 1e6),
    st.floats(0, FLOAT_MAX, exclude_min=True),
)
origins = st.one_of(
    st.sampled_from([0.0, -0.3, 1e6, -1e15, 1e300, -FLOAT_MAX]),
    st.floats(-1e3, 1e3),
    st.floats(allow_nan=False, allow_infinity=False),
)


def good_span(origin: float, extent: float) -> tuple[float, float]:
    """``(origin, origin + extent)``, or the closest finite span when the extent is lost to
    rounding or overflows."""
    if origin == FLOAT_MAX:
        return float(np.nextafter(origin, -math.inf)), origin
    high = origin + extent
    if not (origin < high and math.isfinite(high)):
        high = float(np.nextafter(origin, math.inf))
    return origin, high


@st.composite
def good_bounds(draw: st.DrawFn) -> tuple[tuple[float, float], tuple[float, float]]:
    return good_span(draw(origins), draw(extents)), good_span(draw(origins), draw(extents))


ANY = st.one_of(
    st.none(),
    st.booleans(),
    st.integers(-(2**70), 2**70),
    st.floats(),
    st.text(max_size=3),
    st.lists(st.floats(), max_size=3),
    st.just(object()),
)
BOUND_FLOATS = st.one_of(st.floats(), st.sampled_from([math.nan, math.inf, 1e100, FLOAT_MAX]))
bounds_values = st.one_of(
    good_bounds(),
    good_bounds().map(lambda b: (b[0][::-1], b[1])),
    st.lists(st.lists(BOUND_FLOATS, min_size=2, max_size=2), min_size=2, max_size=2),
    ANY,
)
# Grids up to 24 x 24, a limit for run time and memory only: a grid too large to allocate is
# refused (the subprocess test below, under an address-space limit, as an abort would take
# the test process with it). Shapes whose cell count overflows 64 bits cost nothing.
shape_values = st.one_of(
    st.tuples(st.integers(1, 24), st.integers(1, 24)),
    st.tuples(st.integers(2**32, 2**64 - 1), st.integers(2**32, 2**64 - 1)),
    st.tuples(st.integers(-2, 2), st.integers(-2, 2)),
    st.tuples(st.sampled_from([np.int64(3), 3.0, True, "3"]), st.just(4)),
    ANY,
)
psi_values = st.one_of(
    st.none(),
    st.floats(),
    st.sampled_from([1e100, np.nextafter(1e100, math.inf), FLOAT_MAX]),
    st.sampled_from(["diagonal", "below", "1.5"]),
)
max_rows_values = st.one_of(
    st.sampled_from([1, 3, 4096, 2**63, 2**64 - 1, 2**64, 2**70, 0, -1, 2.5, True]),
    st.integers(1, 10_000),
    ANY,
)


@settings(max_examples=examples(5))
@given(
    bounds=bounds_values,
    shape=shape_values,
    psi=psi_values,
    prior_mean=st.one_of(st.floats(), st.sampled_from([0.0, 0.02, 1e300]), ANY),
    max_rows=max_rows_values,
)
def test_any_constructor_arguments_build_a_sane_map_or_name_the_argument(
    bounds: Any, shape: Any, psi: Any, prior_mean: Any, max_rows: Any
) -> None:
    if isinstance(psi, str) and psi in ("diagonal", "below", "1.5"):
        try:
            (x0, x1), (y0, y1) = bounds
            diagonal = math.hypot(x1 - x0, y1 - y0)
        except (TypeError, ValueError):
            diagonal = 1.0
        factor = {"diagonal": 1.0, "below": 1.0 - 1e-12, "1.5": 1.5}[psi]
        psi = diagonal * factor
    kwargs = {"bounds": bounds, "shape": shape, "psi": psi, "prior_mean": prior_mean}
    gpis, error = call(Gpis, max_rows=max_rows, **kwargs)
    if error is not None:
        assert any(name in str(error) for name in [*kwargs, "max_rows"]), error
        return
    assert gpis.psi <= MAX_PSI, gpis.psi
    assert_sane(gpis)
    assert gpis.n_rows == 0 and gpis.max_rows == max_rows
    # The map works at its corners and centre.
    (x0, x1), (y0, y1) = gpis.bounds
    corners = [[x0, y0], [x1, y1], [x0, y1], [(x0 + x1) / 2, (y0 + y1) / 2]]
    mean, variance = gpis.predict(corners)
    assert np.all(np.isfinite(mean)) and np.all(np.isfinite(variance))


# --- sequences of calls ---------------------------------------------------------------


def just_outside(value: float, direction: float) -> float:
    return float(np.nextafter(value, direction))


@st.composite
def points_for(draw: st.DrawFn, gpis: Gpis, history: list[np.ndarray]) -> Any:
    """Points: inside, exactly on the bounds, a float step outside, earlier points again,
    non-finite, empty, wrongly shaped, odd dtypes."""
    (x0, x1), (y0, y1) = gpis.bounds
    xs = st.one_of(
        st.floats(x0, x1),
        st.sampled_from([x0, x1, just_outside(x0, -math.inf), just_outside(x1, math.inf)]),
    )
    ys = st.one_of(
        st.floats(y0, y1),
        st.sampled_from([y0, y1, just_outside(y0, -math.inf), just_outside(y1, math.inf)]),
    )
    count = draw(st.integers(0, 5))
    points = np.array([[draw(xs), draw(ys)] for _ in range(count)]).reshape(count, 2)
    kind = draw(st.integers(0, 9))
    if kind == 0 and history:
        return np.concatenate([draw(st.sampled_from(history)), points])  # duplicates
    if kind == 1 and count:
        points[draw(st.integers(0, count - 1)), draw(st.integers(0, 1))] = draw(
            st.sampled_from([math.nan, math.inf, -math.inf])
        )
    if kind == 2:
        return draw(arrays(scalar_dtypes(), array_shapes(min_dims=0, max_dims=3, max_side=3)))
    if kind == 3:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # inf and NaN cast to int64
            return points.astype(draw(st.sampled_from([np.float32, np.int64, np.float16, object])))
    if kind == 4:
        return points.tolist()
    if kind == 5:
        return draw(st.sampled_from([None, "points", [1.0, 2.0], [[]], np.zeros((0, 2))]))
    return points


def classify_points(gpis: Gpis, points: Any) -> tuple[str, np.ndarray | None]:
    """OK with the (N, 2) float64 array when the points are valid, else BAD (or EITHER
    for numpy's lenient readings, e.g. numeric strings or complex numbers)."""
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            raw = np.asarray(points)
            array = np.asarray(points, dtype=np.float64)
    except (TypeError, ValueError, OverflowError):
        return BAD, None
    lenient = raw.dtype.kind in "cSUVmMO"
    if array.ndim != 2 or array.shape[1] != 2 or not np.all(np.isfinite(array)):
        return BAD, None
    (x0, x1), (y0, y1) = gpis.bounds
    inside = (array[:, 0] >= x0) & (array[:, 0] <= x1) & (array[:, 1] >= y0) & (array[:, 1] <= y1)
    if not inside.all():
        return BAD, None
    return (EITHER if lenient else OK), array


NOISE = st.one_of(
    st.sampled_from([0.0, TINY, 1e-300, 1e-12, 1e-3, 1.0, 1e150, 1e300, -0.0]),
    st.sampled_from([math.nan, math.inf, -1e-3, "0.1", None]),
    st.floats(0, 1),
)


def noise_ok(value: Any) -> bool:
    return (
        isinstance(value, int | float)
        and not isinstance(value, bool)
        and math.isfinite(value)
        and value >= 0
    )


def snapshot(gpis: Gpis) -> tuple[int, bytes, bytes]:
    return gpis.n_rows, gpis.mean.tobytes(), gpis.variance.tobytes()


@settings(max_examples=examples(5))
@given(
    data=st.data(),
    bounds=st.one_of(st.just(((-0.3, 0.3), (0.0, 0.3))), good_bounds()),
    shape=st.tuples(st.integers(1, 9), st.integers(1, 9)),
    max_rows=st.sampled_from([1, 3, 4, 12, 40, 4096]),
    prior_mean=st.sampled_from([0.0, 0.01, -1e3]),
    steps=st.integers(1, 10),
)
def test_any_call_sequence_keeps_the_map_sane_or_refuses_changing_nothing(
    data: st.DataObject, bounds: Any, shape: Any, max_rows: int, prior_mean: float, steps: int
) -> None:
    gpis, error = call(Gpis, bounds=bounds, shape=shape, max_rows=max_rows, prior_mean=prior_mean)
    if error is not None:  # bounds too large for the default psi (1.5 x their diagonal)
        assert "psi" in str(error) and 1.5 * math.hypot(*np.ptp(bounds, axis=1)) > MAX_PSI, error
        return
    history: list[np.ndarray] = []
    for _ in range(steps):
        operation = data.draw(
            st.sampled_from(["values", "contacts", "circle", "predict", "fill", "clear"])
        )
        before = snapshot(gpis)
        if operation == "clear":
            gpis.clear()
            assert gpis.n_rows == 0
            assert_sane(gpis)
            continue
        if operation == "fill":
            # Exactly to max_rows with distinct noisy values, then one row beyond.
            free = gpis.free_rows
            if free > 200:  # a limit for run time only
                continue
            (x0, x1), (y0, y1) = gpis.bounds
            xs = np.linspace(x0, x1, free + 2)[1:-1]
            points = np.column_stack([xs, np.full(free, (y0 + y1) / 2)])
            added, error = call(gpis.add_values, points, noise_std=1e-2)
            assert error is None, error
            assert gpis.n_rows == before[0] + added
            # (Fewer rows than asked when near-duplicates are rejected as degenerate.)
            full = gpis.free_rows == 0
            _, error = call(gpis.add_values, [[x0, y0]], noise_std=1e-2)
            if full:
                assert isinstance(error, ValueError) and "max_rows" in str(error), error
            assert_sane(gpis)
            continue
        points = data.draw(points_for(gpis, history))
        verdict, array = classify_points(gpis, points)
        if operation == "predict":
            gradient = data.draw(st.booleans())
            result, error = call(gpis.predict, points, return_gradient=gradient)
            if verdict == OK:
                assert error is None, (points, error)
                for part in result:
                    assert np.all(np.isfinite(part)), (points, result)
                assert np.all(result[1] >= 0)
            elif verdict == BAD:
                assert error is not None and "points" in str(error), (points, error)
            assert snapshot(gpis) == before
            continue
        noise = data.draw(NOISE)
        if operation == "values":
            values = data.draw(
                st.one_of(
                    st.none(),
                    st.sampled_from([[math.nan], [1e300], "v"]),
                    st.lists(st.floats(-1, 1), min_size=0, max_size=6),
                )
            )
            arguments = {"values": values, "noise_std": noise}
            n = 0 if array is None else len(array)
            values_ok = values is None or (
                isinstance(values, list) and len(values) == n and np.isfinite(values).all()
            )
            rows, valid = n, verdict != BAD and values_ok and noise_ok(noise)
            result, error = call(gpis.add_values, points, **arguments)
        elif operation == "contacts":
            normals = data.draw(
                st.one_of(
                    st.lists(
                        st.tuples(
                            st.sampled_from([0.0, TINY, 1.0, -1.0, 1e300, math.nan]),
                            st.floats(-1, 1),
                        ),
                        min_size=0,
                        max_size=6,
                    ),
                    st.sampled_from([None, [[1.0, 0.0, 0.0]], "up"]),
                )
            )
            normal_noise = data.draw(NOISE)
            skip = data.draw(st.one_of(st.none(), NOISE))
            arguments = {
                "normals": normals,
                "noise_std": noise,
                "normal_noise_std": normal_noise,
                "skip_below_variance": skip,
            }
            n = 0 if array is None else len(array)
            normals_array = np.asarray(normals if isinstance(normals, list) else [], dtype=float)
            normals_ok = (
                isinstance(normals, list)
                and normals_array.shape == (n, 2)
                and np.isfinite(normals_array).all()
                and (np.hypot(*normals_array.T) > 0).all()
            )
            rows = 3 * n
            valid = (
                verdict != BAD
                and normals_ok
                and noise_ok(noise)
                and noise_ok(normal_noise)
                and (skip is None or noise_ok(skip))
            )
            result, error = call(gpis.add_contacts, points, **arguments)
        else:  # circle
            (x0, x1), (y0, y1) = gpis.bounds
            centre = data.draw(
                st.one_of(
                    st.tuples(st.floats(x0, x1), st.floats(y0, y1)),
                    st.sampled_from([(math.nan, 0.0), (0.0,), "c"]),
                )
            )
            diameter = data.draw(st.one_of(NOISE, st.floats(0, 2 * max(x1 - x0, y1 - y0))))
            arguments = {"diameter": diameter, "noise_std": noise}
            result, error = call(gpis.add_circle_prior, centre, **arguments)
            # Whether the four points fit the bounds is the core's call at the edges.
            rows, valid = 12, None
        if error is not None:
            assert snapshot(gpis) == before, "a refused call changed the map"
            names = ["points", "values", "normals", "centre", "diameter", "noise", "max_rows"]
            names += ["variance", "bounds"]
            assert any(name in str(error) for name in names), error
            if valid:  # valid input is refused only when it could overflow max_rows
                assert rows > gpis.free_rows, (points, arguments, error)
        else:
            assert valid is not False, f"accepted {points!r} {arguments!r}"
            report = gpis.last_report
            assert result == report["added_rows"] == gpis.n_rows - before[0]
            assert rows >= result
            if array is not None and verdict == OK:
                history.append(array)
        assert_sane(gpis)


# --- _core.GpisCore: the class behind Gpis, called with raw arguments ------------------


@settings(max_examples=examples(3))
@given(
    points=arrays(
        st.sampled_from([np.float64, np.float32, np.float16]),
        array_shapes(min_dims=1, max_dims=3, min_side=0, max_side=4),
        elements=st.floats(-1, 2, width=16) | st.sampled_from([math.nan, math.inf]),
    ),
    noise=st.one_of(st.floats(), st.sampled_from([TINY, 1e300, -0.0])),
    psi=st.one_of(st.none(), st.floats(0, 10), st.floats()),
)
def test_the_raw_core_refuses_bad_input_without_panicking(
    points: np.ndarray, noise: float, psi: float | None
) -> None:
    core, error = call(_core.GpisCore, ((0.0, 1.0), (0.0, 1.0)), (4, 4), psi, 0.0, 64)
    if error is not None:
        return
    call(core.add_values, points, None, noise)
    call(core.predict, points)
    if points.ndim == 2 and points.shape[1] == 2:
        call(core.add_contacts, points, points, noise, noise, None)
    assert np.all(np.isfinite(core.mean)) and np.all(np.isfinite(core.variance))


# --- found by this fuzzer: bugs in the Rust core (env_core) --------------------------------


def test_huge_bounds_or_psi_are_refused_naming_psi() -> None:
    """Found by this fuzzer, fixed in env_core/src/gpis/config.rs (``MAX_PSI``): bounds whose
    diagonal exceeded about 3.8e102 (or a psi above about 5.6e102) were accepted, and the
    prior variance psi**3 overflowed to inf. A psi above 1e100, given or the default 1.5 x
    the bounds' diagonal, is refused; 1e100 itself gives a finite map."""
    for kwargs in [
        {"bounds": ((-1e200, 1e200), (-1e200, 1e200))},
        {"bounds": ((0.0, 1e100), (0.0, 1e100))},  # default psi 2.1e100
        {"bounds": ((0.0, 1.0), (0.0, 1.0)), "psi": float(np.nextafter(MAX_PSI, math.inf))},
        {"bounds": ((0.0, 1.0), (0.0, 1.0)), "psi": 1e300},
    ]:
        _, error = call(Gpis, shape=(4, 4), **kwargs)
        assert isinstance(error, ValueError), kwargs
        assert "psi must be at most 1e100" in str(error), error
        _, error = call(_core.GpisCore, kwargs["bounds"], (4, 4), kwargs.get("psi"), 0.0, 64)
        assert isinstance(error, ValueError) and "psi" in str(error), error
    gpis, error = call(Gpis, bounds=((0.0, 1.0), (0.0, 1.0)), shape=(4, 4), psi=MAX_PSI)
    assert error is None, error
    assert_sane(gpis)
    gpis.add_values([[0.5, 0.5], [0.25, 0.75]], noise_std=1e-3)
    assert_sane(gpis)


def refusal_of_a_grid_shape(shape: tuple[int, int]) -> str:
    """The ValueError message of ``Gpis`` with ``shape``, built in a fresh interpreter
    limited to 2 GiB of address space, so that an allocation the map cannot make fails fast
    (and an abort takes only that process). Fails the test if the map is accepted or the
    process dies."""
    script = (
        "import resource; resource.setrlimit(resource.RLIMIT_AS, (2**31, 2**31))\n"
        "from tactile_search import Gpis\n"
        "try:\n"
        f"    Gpis(bounds=((0, 1), (0, 1)), shape={shape!r})\n"
        "except ValueError as error:\n"
        "    print(error)\n"
        "else:\n"
        "    raise SystemExit('accepted')\n"
    )
    result = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, timeout=120
    )
    assert result.returncode == 0, result.stderr[-300:]
    return result.stdout


def test_a_grid_too_large_to_allocate_raises_instead_of_aborting() -> None:
    """Found by this fuzzer, fixed in env_core/src/gpis/map/ (fallible reservations): a
    grid too large to allocate aborted the process (Rust's "memory allocation of N bytes
    failed") instead of raising. Now a ValueError says how much the grid needs."""
    message = refusal_of_a_grid_shape((100_000, 100_000))
    assert "the map's grid needs" in message and "GB" in message, message


@pytest.mark.parametrize("shape", [(2**32, 2**32), (2**63, 2)])
def test_a_grid_whose_cell_count_overflows_raises_instead_of_aborting(
    shape: tuple[int, int],
) -> None:
    """Found by this fuzzer (checking the fix above), fixed in env_core/src/gpis/grid.rs
    (``GridSpec::new``): a shape whose cell count overflows 64 bits (H * W >= 2**64)
    wrapped around, so the fallible reservation asked for too little and filling the cell
    centres aborted the process ("memory allocation of N bytes failed")."""
    message = refusal_of_a_grid_shape(shape)
    assert "grid shape must be positive" in message, message
