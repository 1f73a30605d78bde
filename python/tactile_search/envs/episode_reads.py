"""``EpisodeReads``: what an agent may read of one episode of a core batch beside its
observation: the oracle's action, the last step's motions, the core's decoders of the
observation, the static geometry and the ground truth.

Both faces of an episode have them from here: the single env (``CupboardSearchEnv``, episode
0 of its batch of one) and a slot of the vector env (``SubEnv``), so an agent written
against the one runs unchanged in the other.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from tactile_search import _core


class EpisodeReads:
    """Mixin: the read-only methods of episode ``_episode_index`` of ``_batch`` (a
    ``_core.EpisodeBatch``)."""

    _batch: _core.EpisodeBatch
    _episode_index: int

    def oracle_action(self) -> np.ndarray:
        """The action of a scripted searcher that knows the target (the upper bound); a
        wrist motion, so ``ValueError`` in the ``probe`` action mode."""
        return np.asarray(self._batch.oracle_actions()[self._episode_index], dtype=np.float32)

    def last_motions(self) -> np.ndarray:
        """The wrist motions the last step made, ``(k, 3)`` ``wrist``-mode actions (clipped to
        [-1, 1]): one in the ``wrist`` mode, every motion of the probe in the ``probe`` mode;
        none after a reset. Stepping a ``wrist``-mode env of the same settings, reset to the
        same layout, with them reproduces the episode motion by motion (to draw every motion
        of a probe)."""
        return self._batch.last_motions(self._episode_index)

    def decode_map(self, image: np.ndarray) -> dict[str, np.ndarray]:
        """The map image ``observation["map"]`` (``(C, H, W)`` uint8, the map mode's channels)
        decoded by the core, the inverse of its encoding up to the quantisation step:
        ``{"mean", "std"}`` for ``map="gpis"`` (the GPIS signed distance, negative inside a
        jar, and its standard deviation, m; saturated at ``mean_scale`` and ``std_scale``),
        ``{"occupied"}`` for ``map="occupancy"`` (the probability of occupancy), each
        ``(H, W)`` float64. ``TypeError`` for anything but a uint8 array, ``ValueError`` for
        another shape or with ``map="none"`` (no image)."""
        return self._batch.decode_map(image)

    def decode_proprio(self, proprio: np.ndarray) -> dict[str, float | bool | int]:
        """The proprio vector ``observation["proprio"]`` (float32, the core's proprio table)
        decoded by the core into physical quantities by name: ``x``, ``y`` (wrist, m),
        ``yaw`` (rad), ``deflection`` (the finger's, rad), ``in_contact`` (bool), ``contact_dx``,
        ``contact_dy`` (the first reading's offset from the wrist, m, clipped at the finger
        length), ``normal_x``, ``normal_y``, ``time_left`` (the share of ``max_steps`` left) and
        ``steps`` (int). ``TypeError`` for anything but a float32 array, ``ValueError`` for
        another shape."""
        return self._batch.decode_proprio(proprio)

    def geometry(self) -> dict[str, Any]:
        """The static geometry a planner may know, from the env's settings alone (no scene is
        built, no ground truth): ``width``, ``depth`` (the cupboard's interior, m),
        ``camera`` (x, y), ``start`` (the wrist's start pose x, y, yaw), ``workspace``
        ((x0, x1), (y0, y1)), ``max_step_translation``, ``max_step_yaw``, ``wrist_half_extent``,
        ``arm_length``, ``arm_half_width``, ``finger_length``, ``finger_half_thickness``,
        ``finger_limit``, ``joint_offset`` (wrist centre to finger joint), ``reach`` (to the
        fingertip), ``jar_radius`` (the smallest and largest bounding radius of a jar),
        ``target_min_depth``, ``wall_gap``, ``grid_shape`` (H, W), ``cell`` (a cell's side),
        ``mean_scale``, ``std_scale`` and the cells' centres ``xs``, ``ys`` ((H, W) float64
        each; row i along y, column j along x)."""
        return self._batch.geometry()

    def probe_motions(self, pose: Any, actions: Any) -> np.ndarray:
        """The wrist motions the ``probe`` action mode's controller makes from the wrist
        ``pose`` (x, y, yaw; m, m, rad) to finish each probe of ``actions`` (an ``(n, 3)``
        int64 array of lane, depth and sweep indices) when nothing touches or blocks the
        hand: an ``(n,)`` int64 array, from the env's settings alone (no ground truth). What
        a planner choosing probes weighs them by. ``TypeError`` for anything but an int64
        array, ``ValueError`` for another shape, an index outside the counts or a
        non-finite pose."""
        x, y, yaw = (float(v) for v in pose)
        return self._batch.probe_motions((x, y, yaw), actions)

    def render_state(self) -> dict[str, Any]:
        """Ground truth and map of the current state (jars, hand, contacts, map grids)."""
        return self._batch.render_state(self._episode_index)
