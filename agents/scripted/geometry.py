"""The static geometry a planner may know: cupboard, hand, camera, map grid, layout priors.

No ground truth of an episode: the numbers come from the env's config and from a scene
built with the same ``scene_config`` (``Scene.config``: the core's defaults plus the
overrides; the cupboard, the camera and the hand's start pose), and derived sizes from the
core's own functions (``_core.hand_geometry``: the finger joint's offset from the wrist).
"""

from __future__ import annotations

import dataclasses
import functools
from typing import Any

import numpy as np

from tactile_search import CupboardSearchEnv, _core


@functools.lru_cache(maxsize=8)
def _probe_scene(scene_items: tuple) -> tuple:
    scene = _core.Scene(0, config=dict(scene_items))
    camera = scene.camera["position"]
    return (
        scene.cupboard["width"],
        scene.cupboard["depth"],
        (float(camera[0]), float(camera[1])),
        tuple(scene.hand_pose),
        scene.config,
        _core.hand_geometry(scene.config)["joint_offset"],
    )


@dataclasses.dataclass(frozen=True)
class Geometry:
    """Static sizes in metres (and radians); see the module docstring for the sources."""

    width: float
    depth: float
    camera: tuple[float, float]
    start: tuple[float, float, float]
    workspace: tuple[tuple[float, float], tuple[float, float]]
    max_step_translation: float
    max_step_yaw: float
    wrist_half_extent: float
    arm_length: float
    arm_half_width: float
    finger_length: float
    finger_half_thickness: float
    finger_limit: float
    joint_offset: float
    jar_radius: tuple[float, float]
    target_min_depth: float
    wall_gap: float
    grid_shape: tuple[int, int]
    mean_scale: float
    std_scale: float

    @classmethod
    def from_env(cls, env: CupboardSearchEnv) -> Geometry:
        scene_config = env.config.scene_dict()
        items = tuple(sorted((k, _hashable(v)) for k, v in scene_config.items()))
        width, depth, camera, start, value, joint_offset = _probe_scene(items)
        radii = (
            0.5 * min(value["round_diameter"][0], value["square_side"][0]),
            0.5 * max(value["round_diameter"][1], np.sqrt(2.0) * value["square_side"][1]),
        )
        x0, x1, y0, y1 = value["workspace"]
        return cls(
            width=width,
            depth=depth,
            camera=camera,
            start=start,
            workspace=((float(x0), float(x1)), (float(y0), float(y1))),
            max_step_translation=float(value["max_step_translation"]),
            max_step_yaw=float(value["max_step_yaw"]),
            wrist_half_extent=float(value["wrist_half_extent"]),
            arm_length=float(value["arm_length"]),
            arm_half_width=float(value["arm_half_width"]),
            finger_length=float(value["finger_length"]),
            finger_half_thickness=float(value["finger_half_thickness"]),
            finger_limit=float(value["finger_limit"]),
            joint_offset=float(joint_offset),
            jar_radius=radii,
            target_min_depth=float(value["target_min_depth"]),
            wall_gap=float(value["wall_gap"]),
            grid_shape=tuple(env.config.grid_shape),
            mean_scale=float(env.config.mean_scale),
            std_scale=float(env.config.std_scale),
        )

    @property
    def reach(self) -> float:
        """Distance from the wrist's centre to the fingertip, m."""
        return self.joint_offset + self.finger_length

    @property
    def cell(self) -> float:
        """Side of a (square) map cell, m."""
        return self.depth / self.grid_shape[0]

    def cell_centres(self) -> tuple[np.ndarray, np.ndarray]:
        """``(xs, ys)``, each ``(H, W)``: the map cells' centres (row i along y, column j
        along x)."""
        height, width = self.grid_shape
        xs = -0.5 * self.width + (np.arange(width) + 0.5) * self.width / width
        ys = (np.arange(height) + 0.5) * self.depth / height
        return np.meshgrid(xs, ys)


def _hashable(value: Any) -> Any:
    if isinstance(value, list | tuple):
        return tuple(_hashable(v) for v in value)
    return value
