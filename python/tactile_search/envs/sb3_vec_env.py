"""``CupboardSearchSb3VecEnv``: the Rust episode batch as a stable-baselines3 ``VecEnv``.

stable-baselines3 does not take a gymnasium ``VectorEnv``; its ``VecEnv`` resets an episode
in the same step that ends it, returns the new episode's first observation, and keeps the
last one in ``infos[i]["terminal_observation"]`` (with ``"TimeLimit.truncated"`` set when
the time limit ended it, and ``"is_success"``, which SB3 logs as ``rollout/success_rate``).
This adapter gives the batch exactly those semantics, so SB3 trains on all cores:
``PPO("MultiInputPolicy", CupboardSearchSb3VecEnv(num_envs=8))``.
Needs the ``agents`` extra (stable-baselines3).
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import Any

import numpy as np
from stable_baselines3.common.vec_env.base_vec_env import VecEnv

from tactile_search.envs.config import CupboardSearchConfig
from tactile_search.envs.cupboard_search import (
    ACTION_SPACE,
    as_observation,
    checked_actions,
    observation_space,
)


class CupboardSearchSb3VecEnv(VecEnv):
    """``num_envs`` cupboard-search episodes for stable-baselines3 (see ``CupboardSearchEnv``).

    Args:
        num_envs: number of episodes.
        max_episode_steps: the time limit per episode (truncation).
        seed: seed of the generator that draws each new episode's layout seed.
        layout_seeds: ``[low, high)``, the range layout seeds are drawn from (keep training
            out of the range evaluation holds out; ``agents/train.py`` uses ``[2**32, 2**63)``).
        threads: worker threads (default: every core).
        **kwargs: the fields of ``CupboardSearchConfig``.
    """

    def __init__(
        self,
        num_envs: int = 2,
        max_episode_steps: int = 200,
        seed: int | None = None,
        layout_seeds: tuple[int, int] = (0, 2**63),
        threads: int | None = None,
        **kwargs: Any,
    ) -> None:
        if not isinstance(num_envs, int) or num_envs < 1:
            raise ValueError(f"num_envs must be a positive int, got {num_envs!r}")
        low, high = layout_seeds
        if not 0 <= low < high <= 2**64:
            raise ValueError(
                f"layout_seeds must be [low, high) within [0, 2**64), got {layout_seeds}"
            )
        self.layout_seeds = (int(low), int(high))
        self.config = CupboardSearchConfig(**kwargs)
        self._rng = np.random.default_rng(seed)
        self._batch = self.config.make_batch(self._new_seeds(num_envs), threads=threads)
        self.render_mode = None
        super().__init__(
            num_envs, observation_space(self.config, self._batch.proprio_len), ACTION_SPACE
        )
        self.max_episode_steps = max_episode_steps
        self._elapsed = np.zeros(num_envs, dtype=np.int64)
        self._actions = np.zeros((num_envs, 3))

    def _new_seeds(self, count: int) -> list[int]:
        low, high = self.layout_seeds
        return [int(s) for s in self._rng.integers(low, high, size=count, dtype=np.uint64)]

    def seed(self, seed: int | None = None) -> Sequence[int | None]:
        self._rng = np.random.default_rng(seed)
        return [seed] * self.num_envs

    def reset(self) -> dict[str, np.ndarray]:
        for index, episode_seed in enumerate(self._new_seeds(self.num_envs)):
            self._batch.reset(index, episode_seed)
        self._elapsed[:] = 0
        return as_observation(*self._batch.observe())

    def step_async(self, actions: np.ndarray) -> None:
        self._actions = checked_actions(actions, self.num_envs)

    def step_wait(self) -> tuple[dict[str, np.ndarray], np.ndarray, np.ndarray, list[dict]]:
        maps, proprio, rewards, terminated, step_infos = self._batch.step(self._actions)
        self._elapsed += 1
        truncated = (self._elapsed >= self.max_episode_steps) & ~terminated
        dones = terminated | truncated
        observation = as_observation(maps, proprio)
        infos = [dict(info) for info in step_infos]
        for index in np.flatnonzero(dones):
            infos[index]["terminal_observation"] = {
                k: v[index].copy() for k, v in observation.items()
            }
            infos[index]["TimeLimit.truncated"] = bool(truncated[index])
            infos[index]["is_success"] = bool(infos[index]["success"])
            first = as_observation(*self._batch.reset(int(index), self._new_seeds(1)[0]), index)
            for key, value in first.items():
                observation[key][index] = value
            self._elapsed[index] = 0
        return observation, rewards.astype(np.float32), dones, infos

    def close(self) -> None:
        pass

    def get_attr(self, attr_name: str, indices: Any = None) -> list[Any]:
        return [getattr(self, attr_name) for _ in self._indices(indices)]

    def set_attr(self, attr_name: str, value: Any, indices: Any = None) -> None:
        setattr(self, attr_name, value)

    def env_method(self, method_name: str, *args: Any, indices: Any = None, **kw: Any) -> list:
        return [getattr(self, method_name)(*args, **kw) for _ in self._indices(indices)]

    def env_is_wrapped(self, wrapper_class: type, indices: Any = None) -> list[bool]:
        return [False for _ in self._indices(indices)]

    def _indices(self, indices: Any) -> Iterable[int]:
        if indices is None:
            return range(self.num_envs)
        if isinstance(indices, int):
            return [indices]
        return indices
