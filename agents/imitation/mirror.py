"""Demonstrations in the scene's mirror image: twice the data for nothing.

The cupboard, the camera, the hand's workspace and the probe grid are symmetric about the
plane x = 0 (checked from the env's static geometry, not assumed), and the jars are drawn
without a side. So the mirror image of a demonstrated state is a state of the mirrored
layout, and the mirror image of the teacher's probe is the probe it would choose there (up
to its tie-breaking): the map's columns reversed, each proprio entry times its ``mirror``
factor (the core's observation layout says which entries x -> -x negates), the lane and the
sweep indices counted from the other end.
"""

from __future__ import annotations

import numpy as np

from agents.imitation.demonstrations import Demonstrations
from agents.scripted.geometry import Geometry
from tactile_search.envs.observation import LAYOUT

# Geometry equal to its mirror image within this, m or rad.
SYMMETRY_TOL = 1e-9


def check_symmetric(geometry: Geometry) -> None:
    """Raises ``ValueError`` naming what is not symmetric about x = 0 (then a mirrored state
    is not a state of the env)."""
    camera_x = geometry.camera[0]
    (x_low, x_high), _ = geometry.workspace
    lanes, yaws = np.asarray(geometry.probe_lanes), np.asarray(geometry.probe_yaws)
    columns = np.asarray(geometry.xs)[0]
    checks = {
        "the camera's x": abs(camera_x) <= SYMMETRY_TOL,
        "the hand's workspace in x": abs(x_low + x_high) <= SYMMETRY_TOL,
        "the probe lanes": np.allclose(lanes, -lanes[::-1], atol=SYMMETRY_TOL),
        "the probe sweeps' yaws": np.allclose(yaws, -yaws[::-1], atol=SYMMETRY_TOL),
        "the map's columns": np.allclose(columns, -columns[::-1], atol=SYMMETRY_TOL),
    }
    broken = [name for name, symmetric in checks.items() if not symmetric]
    if broken:
        raise ValueError(
            f"mirrored demonstrations need a scene symmetric about x = 0; not symmetric: "
            f"{', '.join(broken)}"
        )


def mirror_signs() -> np.ndarray:
    """Each proprio entry's factor in the mirror image, from the core's layout."""
    fields = sorted(LAYOUT["proprio"], key=lambda field: field["index"])
    return np.array([field["mirror"] for field in fields], dtype=np.float32)


def mirrored(demonstrations: Demonstrations, geometry: Geometry) -> Demonstrations:
    """``demonstrations`` in the mirror image of the scene ``geometry`` describes."""
    check_symmetric(geometry)
    observations = dict(demonstrations.observations)
    if "map" in observations:  # the no-map agent sees the proprioception alone
        observations["map"] = np.ascontiguousarray(observations["map"][..., ::-1])
    observations["proprio"] = observations["proprio"] * mirror_signs()
    actions = demonstrations.actions.copy()
    actions[:, 0] = len(geometry.probe_lanes) - 1 - actions[:, 0]
    actions[:, 2] = len(geometry.probe_yaws) - 1 - actions[:, 2]
    return Demonstrations(
        observations,
        actions,
        demonstrations.returns,
        demonstrations.layout_seeds,
        demonstrations.episode_success,
        demonstrations.episode_tips,
        demonstrations.episode_steps,
    )
