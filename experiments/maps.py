"""Maps started the way the environment starts its map, for the experiments.

``env_settings()`` is the environment's default settings (from the core), and
``start_map`` builds a ``Gpis`` on any grid holding exactly the rows the environment's
depth prior adds at reset (``_core.depth_prior``, one call, the same order), so an experiment
that overrides nothing measures the environment's own map.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from tactile_search import Gpis, _core


def env_settings() -> dict[str, Any]:
    """The environment's default episode settings, read from the core."""
    return dict(_core.EpisodeConfig().as_dict())


def start_map(
    slice_points: ArrayLike,
    camera_xy: ArrayLike,
    bounds: tuple[tuple[float, float], tuple[float, float]],
    shape: tuple[int, int],
    settings: Mapping[str, Any] | None = None,
) -> Gpis:
    """The depth-only map: a ``Gpis`` with the settings' prior mean and row capacity (the
    environment's defaults for what ``settings`` leaves out) holding the depth prior's rows."""
    merged = env_settings() | dict(settings or {})
    rows = _core.depth_prior(
        np.asarray(slice_points, dtype=float).reshape(-1, 2),
        np.asarray(camera_xy, dtype=float)[:2],
        bounds,
        shape,
        **merged,
    )
    gpis = Gpis(bounds, shape, prior_mean=merged["prior_mean"], max_rows=merged["max_rows"])
    gpis.add_observations(rows)
    return gpis


def add_touch(gpis: Gpis, points: ArrayLike, normals: ArrayLike, settings=None) -> int:
    """Adds contacts inside the map's bounds with the environment's contact noise and
    skipping rule (``settings`` override them); returns the rows added."""
    merged = env_settings() | dict(settings or {})
    points = np.asarray(points, dtype=float).reshape(-1, 2)
    normals = np.asarray(normals, dtype=float).reshape(-1, 2)
    (x0, x1), (y0, y1) = gpis.bounds
    keep = (points[:, 0] >= x0) & (points[:, 0] <= x1) & (points[:, 1] >= y0) & (points[:, 1] <= y1)
    if not keep.any():
        return 0
    return gpis.add_contacts(
        points[keep],
        normals[keep],
        noise_std=merged["contact_noise_std"],
        normal_noise_std=merged["normal_noise_std"],
        skip_below_variance=merged["skip_below_variance"],
    )
