"""The planner's belief: the decoded GPIS map plus its own memory of touch.

From the observation alone: the GPIS mean and std (the uint8 map decoded by the core,
``CupboardSearchEnv.decode_map``), the camera's
shadows (cells behind surfaces the first look saw, by angular sweeps from the camera), the
cells the finger has swept without contact (no jar can stand there) and the jars it touched
(not the target: touching the target ends the episode). From these it gives

- ``hiding_weight``: where the target's centre may be (in a shadow wide enough for a jar,
  deep enough, not swept, not a touched jar), weighted by the GPIS std;
- ``blocked``: cells that may hold jar material, which the wrist and arm must keep clear of.

A negative mean counts as a jar only where the std is low: far from the data the GPIS
extrapolates (behind the jars it often dips below zero). Where the target may hide is judged
on the camera's map (``seen``): a touch pulls the mean below zero well beyond the touched
jar, so touched jars are excluded by their estimated centres instead.
"""

from __future__ import annotations

import numpy as np

from agents.scripted.geometry import Geometry

# Angular resolution of the shadow sweep, rad.
ANGLE_BIN = 0.004
# A target's centre is at least this far behind the surface that hides it, m.
HIDDEN_DEPTH = 0.035
# Half width (m) of the shadow needed on each side of a hidden jar's centre.
SHADOW_HALF_WIDTH = 0.015
# The mean below which a cell counts as (touched or seen) jar, m...
SOLID_MEAN = 0.002
# ...where the std is below this (elsewhere a negative mean is the GPIS extrapolating), m.
SOLID_STD = 0.02


def distance_to(mask: np.ndarray, cell: float, cap: float = 0.08) -> np.ndarray:
    """Distance from every cell centre to the nearest centre of a ``mask`` cell, capped at
    ``cap`` (m), on a grid of square cells of side ``cell``."""
    reach = int(np.ceil(cap / cell))
    height, width = mask.shape
    padded = np.zeros((height + 2 * reach, width + 2 * reach), dtype=bool)
    padded[reach : reach + height, reach : reach + width] = mask
    best = np.full(mask.shape, cap)
    for di in range(-reach, reach + 1):
        for dj in range(-reach, reach + 1):
            d = cell * np.hypot(di, dj)
            if d >= cap:
                continue
            shifted = padded[reach + di : reach + di + height, reach + dj : reach + dj + width]
            best[shifted] = np.minimum(best[shifted], d)
    return best


class SearchMap:
    """Belief over the cupboard for one episode; see the module docstring."""

    def __init__(self, geometry: Geometry, decoded: dict[str, np.ndarray]) -> None:
        """``decoded``: the first observation's GPIS map as the core decodes it (``mean`` and
        ``std``, (H, W), m)."""
        self.geometry = geometry
        self.xs, self.ys = geometry.cell_centres()
        self.mean, self.std = decoded["mean"], decoded["std"]
        self.seen = self.solid(0.0)
        self.behind, self.behind_wide = self._depth_behind_surfaces(self.seen)
        self.swept = np.zeros(self.xs.shape, dtype=bool)
        self.touched: list[np.ndarray] = []

    def update(self, decoded: dict[str, np.ndarray]) -> None:
        """The GPIS map of a new observation, as the core decodes it."""
        self.mean, self.std = decoded["mean"], decoded["std"]

    def solid(self, level: float = SOLID_MEAN) -> np.ndarray:
        """Cells the map is confident are inside or on a jar (mean below ``level``)."""
        return (self.mean < level) & (self.std < SOLID_STD)

    def _depth_behind_surfaces(self, solid: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Per cell: range behind the nearest solid cell on its camera ray (-inf if none),
        and the minimum of that over the rays through the cell's centre and
        ±SHADOW_HALF_WIDTH beside it (positive: a jar-wide shadow)."""
        cx, cy = self.geometry.camera
        angles = np.arctan2(self.xs - cx, self.ys - cy)
        ranges = np.hypot(self.xs - cx, self.ys - cy)
        low = angles.min() - 0.5
        bins = int((angles.max() + 0.5 - low) / ANGLE_BIN) + 1
        front = np.full(bins, np.inf)
        half = 0.5 * self.geometry.cell / ranges[solid]
        first = ((angles[solid] - half - low) / ANGLE_BIN).astype(int)
        last = ((angles[solid] + half - low) / ANGLE_BIN).astype(int)
        for a, b, r in zip(first, last, ranges[solid], strict=True):
            front[a : b + 1] = np.minimum(front[a : b + 1], r)
        behind = []
        for side in (0.0, -1.0, 1.0):
            index = ((angles + side * SHADOW_HALF_WIDTH / ranges - low) / ANGLE_BIN).astype(int)
            behind.append(ranges - front[np.clip(index, 0, bins - 1)])
        return behind[0], np.minimum.reduce(behind)

    def sweep_radius(self) -> float:
        """How near a finger that touched nothing rules out a jar centre: the smallest jar
        radius, less a quarter cell (cell centres stand for their whole cell)."""
        return self.geometry.jar_radius[0] - 0.25 * self.geometry.cell

    def sweep_finger(self, joint: np.ndarray, tip: np.ndarray) -> None:
        """Remembers that the finger segment ``joint`` to ``tip`` touched nothing: no jar centre
        lies within ``sweep_radius()`` of it."""
        self.swept |= _segment_distance(self.xs, self.ys, joint, tip) <= self.sweep_radius()

    def mark_swept(self, cells: np.ndarray) -> None:
        """Remembers that no jar centre lies in ``cells`` (a boolean (H, W) mask)."""
        self.swept |= cells

    def add_touch(self, point: np.ndarray, normal: np.ndarray) -> None:
        """Remembers a touched jar (not the target) by its estimated centre."""
        centre = point - normal * np.mean(self.geometry.jar_radius)
        if all(np.hypot(*(centre - c)) > 0.02 for c in self.touched):
            self.touched.append(centre)

    def _near_touched(self, radius: float) -> np.ndarray:
        near = np.zeros(self.xs.shape, dtype=bool)
        for cx, cy in self.touched:
            near |= np.hypot(self.xs - cx, self.ys - cy) <= radius
        return near

    def hiding_weight(self, relaxed: bool = False) -> np.ndarray:
        """Where the target's centre may be, weighted by the GPIS std (0 elsewhere).
        ``relaxed`` drops the shadow and depth conditions (when nothing else is left)."""
        g = self.geometry
        r_min = g.jar_radius[0]
        fits = (
            (np.abs(self.xs) <= 0.5 * g.width - g.wall_gap - r_min)
            & (self.ys <= g.depth - g.wall_gap - r_min)
            & ~self.swept
            & ~self._near_touched(2.0 * r_min)
            & (distance_to(self.seen, g.cell) >= 0.5 * r_min)
        )
        if not relaxed:
            fits &= (self.behind_wide >= HIDDEN_DEPTH) & (
                self.ys >= g.target_min_depth - 0.5 * g.cell
            )
        return np.where(fits, self.std + 0.01, 0.0)

    def blocked(self) -> np.ndarray:
        """Cells that may hold jar material: seen or touched surfaces and insides, touched
        jars' footprints, and unswept shadows."""
        unknown = (self.behind > 0.0) & ~self.swept
        return self.solid() | unknown | self._near_touched(self.geometry.jar_radius[1])


def _segment_distance(xs: np.ndarray, ys: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Distance from every cell centre to the segment from ``a`` to ``b``."""
    d = b - a
    length2 = float(d @ d)
    t = np.zeros(xs.shape) if length2 == 0 else ((xs - a[0]) * d[0] + (ys - a[1]) * d[1]) / length2
    t = np.clip(t, 0.0, 1.0)
    return np.hypot(xs - a[0] - t * d[0], ys - a[1] - t * d[1])
