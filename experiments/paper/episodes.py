"""One scene per layout seed and jar shape: its depth slices at each noise level, the
scripted finger's contacts, and the maps and metrics of each prior option.

Seeds are the validation range of ``docs/DESIGN.md`` §7
(``tactile_search.seed_ranges.VALIDATION``): the default prior is chosen on them, so they are
not test layouts.

- Depth: the first look's noisy 2D slice; the map starts from the environment's depth prior
  (``experiments.maps.start_map``, i.e. ``_core.depth_prior``) at the environment's default
  settings, with the prior option's settings on top.
- Touch: the scripted finger's contacts (thinned to one per 3 mm per jar), added as the
  environment adds touch (its contact noise and skipping rule).
- Metrics (on a grid of square cells over the cupboard interior in the slice plane, the
  core's functions): IoU of the interior (mean < 0) against the footprints at reset, as
  ``info["iou"]``; the mean distance from the true outlines (64 samples per jar, every jar,
  hidden ones included) to the zero level set of the mean, each sample capped at
  ``MISS_DISTANCE`` (a map with no zero level set scores the cap); and the reverse, the mean
  distance from the zero level set to the nearest true outline.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from experiments.maps import add_touch, start_map
from experiments.paper.priors import PRIOR_OPTIONS, PriorOption
from experiments.paper.scripted_touch import TouchLog, follow_surfaces
from tactile_search import Gpis, _core
from tactile_search._core import Scene

MISS_DISTANCE = 0.05  # cap of one outline sample's distance (m)
OUTLINE_SAMPLES = 64
DEPTH_NOISE_LEVELS = (0.001, 0.002, 0.005)
DEFAULT_DEPTH_NOISE = 0.002
SHAPES = ("round", "square")


def scene_config(shape: str, depth_noise: float) -> dict[str, object]:
    """All-round or all-square jars (the target too), with the given depth noise."""
    return {
        "round_fraction": 1.0 if shape == "round" else 0.0,
        "target_shape": shape,
        "depth_noise_std": depth_noise,
    }


def map_bounds(scene: Scene) -> tuple[tuple[float, float], tuple[float, float]]:
    """The cupboard interior in the slice plane (the environment's map bounds)."""
    c = scene.cupboard
    return (-0.5 * c["width"], 0.5 * c["width"]), (0.0, c["depth"])


def grid_shape(
    bounds: tuple[tuple[float, float], tuple[float, float]], cell: float
) -> tuple[int, int]:
    """(H, W) of a grid of square cells of side ``cell`` over ``bounds``."""
    (x0, x1), (y0, y1) = bounds
    return round((y1 - y0) / cell), round((x1 - x0) / cell)


@dataclass
class Episode:
    """One seed and jar shape: the scene after touching, its touch data and depth slices."""

    seed: int
    shape: str
    scene: Scene
    jars: dict[str, Any]
    touch: dict[str, NDArray]
    raw_touch_count: int
    log: TouchLog
    slices: dict[float, NDArray[np.float64]]
    camera_xy: NDArray[np.float64]


def run_episode(
    seed: int, shape: str, noise_levels: Sequence[float], jar_limit: int | None = None
) -> Episode:
    """Builds the scene at each depth-noise level (same layout) and touches it once."""
    scene = Scene(seed=seed, **scene_config(shape, DEFAULT_DEPTH_NOISE))
    jars = {key: np.copy(value) for key, value in scene.jars.items()}
    slices = {}
    for noise in noise_levels:
        other = scene if noise == DEFAULT_DEPTH_NOISE else Scene(seed, **scene_config(shape, noise))
        if not np.array_equal(other.jars["positions"], jars["positions"]):
            raise RuntimeError(f"seed {seed}: the layout changed with the depth noise")
        slices[noise] = other.slice_points
    count = len(jars["shapes"])
    indices = None if jar_limit is None else range(min(jar_limit, count))
    touch, log = follow_surfaces(scene, jars, indices)
    return Episode(
        seed=seed,
        shape=shape,
        scene=scene,
        jars=jars,
        touch=touch,
        raw_touch_count=sum(len(p) for p in log.points),
        log=log,
        slices=slices,
        camera_xy=np.asarray(scene.camera["position"][:2], dtype=float),
    )


def maps_for(episode: Episode, option: PriorOption, noise: float, cell: float) -> tuple[Gpis, Gpis]:
    """(depth only, depth + touch) maps of ``episode`` under ``option``."""
    bounds = map_bounds(episode.scene)
    shape = grid_shape(bounds, cell)
    depth = episode.slices[noise]
    settings = option.settings()
    prior = start_map(depth, episode.camera_xy, bounds, shape, settings)
    touched = start_map(depth, episode.camera_xy, bounds, shape, settings)
    add_touch(touched, episode.touch["points"], episode.touch["normals"], settings)
    return prior, touched


def map_metrics(gpis: Gpis, jars: dict[str, Any]) -> dict[str, float]:
    """IoU (as ``info["iou"]``), outline distance and its reverse (m) of a map."""
    truth = _core.footprint_mask(jars, gpis.bounds, gpis.shape)
    mean = gpis.mean
    return {
        "iou": _core.interior_iou(mean, truth),
        "outline_distance": _core.outline_distance(
            mean, gpis.bounds, jars, OUTLINE_SAMPLES, MISS_DISTANCE
        ),
        "spurious_distance": _core.spurious_distance(mean, gpis.bounds, jars, MISS_DISTANCE),
    }


def evaluate(
    episodes: Sequence[Episode],
    noise_levels: Sequence[float],
    cell: float,
    options: Sequence[PriorOption] = PRIOR_OPTIONS,
) -> list[dict[str, object]]:
    """One row per (episode, noise, prior option, data): IoU and outline distances."""
    rows = []
    for episode in episodes:
        for noise in noise_levels:
            for option in options:
                for data, gpis in zip(
                    ("depth only", "depth + touch"),
                    maps_for(episode, option, noise, cell),
                    strict=True,
                ):
                    rows.append(
                        {
                            "seed": episode.seed,
                            "shape": episode.shape,
                            "depth_noise": noise,
                            "prior": option.name,
                            "data": data,
                            **map_metrics(gpis, episode.jars),
                            "rows": gpis.n_rows,
                            "contacts": len(episode.touch["points"]),
                            "jar_displacement": float(np.mean(episode.scene.jars["displacement"])),
                        }
                    )
    return rows
