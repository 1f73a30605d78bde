"""The batched ``CupboardSearch-v0``: N episodes stepped in parallel in Rust.

``gymnasium.make_vec("tactile_search/CupboardSearch-v0", num_envs=N,
vectorization_mode="vector_entry_point")``. Autoreset follows gymnasium 1.x's default
``NEXT_STEP`` mode: the step after an episode ends (terminated or truncated) resets that
episode and returns its first observation with reward 0 and both flags False; the action
given for it is ignored. Truncation comes from ``max_episode_steps`` (the registered time
limit), counted here per episode.
"""

from __future__ import annotations

from typing import Any, ClassVar

import numpy as np
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space

from tactile_search.envs.config import CupboardSearchConfig
from tactile_search.envs.cupboard_search import (
    ACTION_SPACE,
    as_observation,
    checked_actions,
    observation_space,
)


class CupboardSearchVectorEnv(VectorEnv):
    """``num_envs`` cupboard-search episodes stepped on all cores (see ``CupboardSearchEnv``).

    Args:
        num_envs: number of episodes.
        max_episode_steps: the time limit per episode (truncation).
        threads: worker threads (default: every core).
        **kwargs: the fields of ``CupboardSearchConfig``.
    """

    metadata: ClassVar[dict[str, Any]] = {
        "autoreset_mode": AutoresetMode.NEXT_STEP,
        "render_modes": [],
    }

    def __init__(
        self,
        num_envs: int = 2,
        max_episode_steps: int | None = 200,
        threads: int | None = None,
        **kwargs: Any,
    ) -> None:
        if not isinstance(num_envs, int) or num_envs < 1:
            raise ValueError(f"num_envs must be a positive int, got {num_envs!r}")
        self.num_envs = num_envs
        self.max_episode_steps = max_episode_steps
        self.config = CupboardSearchConfig(**kwargs)
        self._batch = self.config.make_batch(list(range(num_envs)), threads=threads)
        self.single_observation_space = observation_space(self.config, self._batch.proprio_len)
        self.single_action_space = ACTION_SPACE
        self.observation_space = batch_space(self.single_observation_space, num_envs)
        self.action_space = batch_space(self.single_action_space, num_envs)
        self._elapsed = np.zeros(num_envs, dtype=np.int64)
        self._needs_reset = np.zeros(num_envs, dtype=bool)

    def _seeds(self, count: int) -> list[int]:
        return [int(s) for s in self.np_random.integers(0, 2**63, size=count)]

    def reset(
        self, *, seed: int | list[int] | None = None, options: dict[str, Any] | None = None
    ) -> tuple[dict, dict]:
        if isinstance(seed, list):
            if len(seed) != self.num_envs:
                raise ValueError(f"seed must be a list of {self.num_envs} ints, got {seed!r}")
            super().reset(seed=seed[0])
            seeds = [int(s) for s in seed]
        else:
            super().reset(seed=seed)
            seeds = self._seeds(self.num_envs)
        for index, episode_seed in enumerate(seeds):
            self._batch.reset(index, episode_seed)
        self._elapsed[:] = 0
        self._needs_reset[:] = False
        maps, proprio = self._batch.observe()
        return as_observation(maps, proprio), self._infos()

    def _infos(self) -> dict:
        infos: dict = {}
        for index in range(self.num_envs):
            infos = self._add_info(infos, dict(self._batch.info(index)), index)
        return infos

    def step(self, actions: Any) -> tuple[dict, np.ndarray, np.ndarray, np.ndarray, dict]:
        actions = checked_actions(actions, self.num_envs)
        resetting = np.flatnonzero(self._needs_reset)
        for index, episode_seed in zip(resetting, self._seeds(len(resetting)), strict=True):
            self._batch.reset(int(index), episode_seed)
            self._elapsed[index] = 0
        # Episodes reset just now are not stepped: they return their first observation.
        stepping = ~self._needs_reset
        maps, proprio, rewards, terminated, step_infos = self._batch.step(actions, stepping)
        self._elapsed[stepping] += 1
        truncated = np.zeros(self.num_envs, dtype=bool)
        if self.max_episode_steps is not None:
            truncated = stepping & (self._elapsed >= self.max_episode_steps) & ~terminated
        infos: dict = {}
        for index in range(self.num_envs):
            infos = self._add_info(infos, dict(step_infos[index]), index)
        self._needs_reset = stepping & (terminated | truncated)
        return as_observation(maps, proprio), rewards, terminated, truncated, infos

    def oracle_actions(self) -> np.ndarray:
        """Actions ``(num_envs, 3)`` of a scripted searcher that knows each target."""
        return self._batch.oracle_actions().astype(np.float32)
