"""The static geometry a planner may know: cupboard, hand, camera, map grid, layout priors.

No ground truth of an episode: every number comes from the core, from the env's settings
alone (``CupboardSearchEnv.geometry()``: the cupboard, the camera, the hand's sizes, start
pose and per-step bounds, the jar radius range, the map grid and its cells' centres, the
probe action mode's probes; and the env's ``config``: the largest sweep angle); this
module only gives them typed names.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from tactile_search import CupboardSearchEnv


@dataclasses.dataclass(frozen=True)
class Geometry:
    """Static sizes in metres (and radians), as the core's ``geometry()`` names them."""

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
    #: Distance from the wrist's centre to the fingertip, m.
    reach: float
    #: The smallest and the largest bounding radius of a jar, m.
    jar_radius: tuple[float, float]
    target_min_depth: float
    wall_gap: float
    grid_shape: tuple[int, int]
    #: Side of a (square) map cell, m.
    cell: float
    mean_scale: float
    std_scale: float
    #: The map cells' centres, each (H, W): row i along y, column j along x.
    xs: np.ndarray = dataclasses.field(repr=False, compare=False)
    ys: np.ndarray = dataclasses.field(repr=False, compare=False)
    #: The ``probe`` action mode's probes per action index: the wrist's x per lane, y per
    #: depth and yaw at the end of each sweep (a turn towards +x is a negative yaw).
    probe_lanes: np.ndarray = dataclasses.field(repr=False, compare=False)
    probe_depths: np.ndarray = dataclasses.field(repr=False, compare=False)
    probe_yaws: np.ndarray = dataclasses.field(repr=False, compare=False)
    #: The wrist's y the probe controller backs out to before changing lanes, m.
    probe_outside: float = dataclasses.field(compare=False)
    #: The probe controller's turn per motion while sweeping, rad.
    probe_sweep_rate: float = dataclasses.field(compare=False)
    #: The largest sweep angle either way, rad (the env's ``probe_max_angle``).
    probe_max_angle: float = dataclasses.field(compare=False)

    @classmethod
    def from_env(cls, env: CupboardSearchEnv) -> Geometry:
        return cls(**env.geometry(), probe_max_angle=env.config.probe_max_angle)

    def cell_centres(self) -> tuple[np.ndarray, np.ndarray]:
        """``(xs, ys)``, each ``(H, W)``: the map cells' centres."""
        return self.xs, self.ys
