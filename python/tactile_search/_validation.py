"""Turning user input into the arrays and scalars the Rust core takes, with clear errors.

Each helper names the argument, what was expected and what came, and raises ``TypeError``
for the wrong kind of thing and ``ValueError`` for the right kind with a wrong value. (The
``Gpis`` constructor's arguments, bounds, shape and counts, are checked by the core.)
"""

from __future__ import annotations

import numbers
from typing import Any

import numpy as np
from numpy.typing import NDArray


def as_float_array(name: str, value: Any) -> NDArray[np.float64]:
    """``value`` as a C-contiguous float64 array, or ``TypeError`` if it is not numeric."""
    try:
        array = np.ascontiguousarray(value, dtype=np.float64)
    except (TypeError, ValueError) as error:
        raise TypeError(
            f"{name} must be an array of real numbers, got {type(value).__name__}: {error}"
        ) from None
    return array


def as_points(name: str, value: Any) -> NDArray[np.float64]:
    """An (N, 2) float64 array of finite (x, y) points."""
    array = as_float_array(name, value)
    if array.ndim != 2 or array.shape[1] != 2:
        raise ValueError(f"{name} must have shape (N, 2), got shape {array.shape}")
    require_finite(name, array)
    return array


def as_vector(name: str, value: Any, length: int) -> NDArray[np.float64]:
    """A (length,) float64 array of finite numbers."""
    array = as_float_array(name, value)
    if array.shape != (length,):
        raise ValueError(f"{name} must have shape ({length},), got shape {array.shape}")
    require_finite(name, array)
    return array


def require_finite(name: str, array: NDArray[np.float64]) -> None:
    """``ValueError`` naming the first non-finite entry of ``array``."""
    bad = np.argwhere(~np.isfinite(array))
    if bad.size:
        index = tuple(int(i) for i in bad[0])
        raise ValueError(f"{name} must be finite, got {array[index]} at index {index}")


def as_bool(name: str, value: Any) -> bool:
    """``value`` if it is a ``bool`` (numpy's included), else ``TypeError``: the one check of
    a flag in the project (``resume``, ``mirror``, ``bfloat16_updates``...), so that 0, 1 or
    "false" from a YAML recipe or a command line never pass as one."""
    if not isinstance(value, bool | np.bool_):
        raise TypeError(f"{name} must be a bool, got {type(value).__name__}: {value!r}")
    return bool(value)


def as_real(name: str, value: Any, *, minimum: float | None = None) -> float:
    """A finite real scalar, optionally at least ``minimum``."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise TypeError(f"{name} must be a real number, got {type(value).__name__}: {value!r}")
    result = float(value)
    if not np.isfinite(result):
        raise ValueError(f"{name} must be finite, got {result}")
    if minimum is not None and result < minimum:
        raise ValueError(f"{name} must be at least {minimum}, got {result}")
    return result


#: The largest count the core takes (a u64): beyond it pyo3 would raise OverflowError.
MAX_COUNT = 2**64 - 1


def as_count(name: str, value: Any, *, minimum: int = 1) -> int:
    """An integer of at least ``minimum`` that fits in 64 bits: the one check of a count in
    the project (the agents' thread counts, checkpoint intervals, encoder widths...)."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise TypeError(f"{name} must be an integer, got {type(value).__name__}: {value!r}")
    count = int(value)
    if count < minimum:
        raise ValueError(f"{name} must be at least {minimum}, got {value}")
    if count > MAX_COUNT:
        raise ValueError(f"{name} must fit in 64 bits (at most 2**64 - 1), got {value}")
    return count
