"""``SubEnv``: one sub-env of a ``CupboardSearchVectorEnv`` as an agent reads it.

A planner or a learned agent reads more than the observation: the env's settings and static
geometry, the core's decoders of the observation, an oracle's action, its episode's seed.
``vector.sub_env(i)`` gives episode ``i`` of the batch the single env's read-only methods
(``EpisodeReads``, the same code), so that an agent written against ``CupboardSearchEnv``
runs unchanged in a slot of the vector env (``tactile_search.benchmark`` runs agents that
way). It never steps or resets: the vector env does.
"""

from __future__ import annotations

from typing import Any

from tactile_search import _core
from tactile_search.envs.episode_reads import EpisodeReads


class SubEnv(EpisodeReads):
    """Episode ``index`` of ``vector`` (see the module docstring)."""

    # ``vector``: a ``CupboardSearchVectorEnv`` (not imported: it makes its SubEnvs).
    def __init__(self, vector: Any, index: int) -> None:
        if not 0 <= index < vector.num_envs:
            raise ValueError(f"index must be from 0 to {vector.num_envs - 1}, got {index}")
        self._vector = vector
        self.index = index

    @property
    def _batch(self) -> _core.EpisodeBatch:  # type: ignore[override]  # the vector's, read-only
        batch: _core.EpisodeBatch = self._vector._batch
        return batch

    @property
    def _episode_index(self) -> int:  # type: ignore[override]
        return self.index

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
        return int(self._vector.np_random_seed[self.index])
