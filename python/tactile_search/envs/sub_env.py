"""``SubEnv``: one sub-env of a ``CupboardSearchVectorEnv`` as an agent reads it.

A planner or a learned agent reads more than the observation: the env's settings and static
geometry, the core's decoders of the observation, an oracle's action, its episode's seed.
``vector.sub_env(i)`` gives episode ``i`` of the batch those read-only methods of
``CupboardSearchEnv``, so that an agent written against the single env runs unchanged in a
slot of the vector env (``tactile_search.benchmark`` runs agents that way). It never steps
or resets: the vector env does.
"""

from __future__ import annotations

from typing import Any

import numpy as np


class SubEnv:
    """Episode ``index`` of ``vector`` (see the module docstring)."""

    def __init__(self, vector: Any, index: int) -> None:
        if not 0 <= index < vector.num_envs:
            raise ValueError(f"index must be from 0 to {vector.num_envs - 1}, got {index}")
        self._vector = vector
        self.index = index

    @property
    def unwrapped(self) -> SubEnv:
        return self

    @property
    def config(self) -> Any:
        return self._vector.config

    @property
    def observation_space(self) -> Any:
        return self._vector.single_observation_space

    @property
    def action_space(self) -> Any:
        return self._vector.single_action_space

    @property
    def np_random_seed(self) -> int:
        """The seed of this episode's generator: its layout seed when reset with one."""
        return self._vector.np_random_seed[self.index]

    def oracle_action(self) -> np.ndarray:
        """As ``CupboardSearchEnv.oracle_action``, for this episode."""
        return self._vector._batch.oracle_actions()[self.index].astype(np.float32)

    def last_motions(self) -> np.ndarray:
        """As ``CupboardSearchEnv.last_motions``, for this episode."""
        return self._vector._batch.last_motions(self.index)

    def decode_map(self, image: np.ndarray) -> dict[str, np.ndarray]:
        """As ``CupboardSearchEnv.decode_map``."""
        return self._vector._batch.decode_map(image)

    def decode_proprio(self, proprio: np.ndarray) -> dict[str, Any]:
        """As ``CupboardSearchEnv.decode_proprio``."""
        return self._vector._batch.decode_proprio(proprio)

    def geometry(self) -> dict[str, Any]:
        """As ``CupboardSearchEnv.geometry``."""
        return self._vector._batch.geometry()

    def render_state(self) -> dict[str, Any]:
        """As ``CupboardSearchEnv.render_state``, for this episode (ground truth)."""
        return self._vector._batch.render_state(self.index)
