"""``CupboardSearchSb3VecEnv``: the Rust episode batch as a stable-baselines3 ``VecEnv``.

stable-baselines3 does not take a gymnasium ``VectorEnv``; its ``VecEnv`` resets an episode
in the same step that ends it, returns the new episode's first observation, and keeps the
last one in ``infos[i]["terminal_observation"]`` (with ``"TimeLimit.truncated"`` set when
the time limit ended it, and ``"is_success"``, which SB3 logs as ``rollout/success_rate``).
This adapter gives the batch exactly those semantics, so SB3 trains on all cores:
``PPO("MultiInputPolicy", CupboardSearchSb3VecEnv(num_envs=8))``.
The time limit is the core's (``max_steps``). The core writes each step's results into
arrays allocated once per batch; this adapter copies the observation once per step (SB3
keeps the previous step's observation while it takes the next) and builds SB3's per-env
info dicts in Rust. Needs the ``agents`` extra (stable-baselines3).
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import Any

import numpy as np
from stable_baselines3.common.vec_env.base_vec_env import VecEnv

from tactile_search.envs.config import (
    CupboardSearchConfig,
    checked_layout_seeds,
    with_settings_signature,
)
from tactile_search.envs.cupboard_search import action_space, observation_space
from tactile_search.envs.vector import observation_dict


class CupboardSearchSb3VecEnv(VecEnv):
    """``num_envs`` cupboard-search episodes for stable-baselines3 (see ``CupboardSearchEnv``).

    Args:
        num_envs: number of episodes.
        seed: seed of the generator that draws each new episode's layout seed.
        layout_seeds: ``[low, high)``, the range layout seeds are drawn from (keep training
            out of the ranges evaluation holds out: ``tactile_search.seed_ranges.TRAINING``,
            as ``agents.train`` does).
        threads: worker threads (default: every core).
        **kwargs: the fields of ``CupboardSearchConfig`` (``max_steps`` is the time limit).
    """

    def __init__(
        self,
        num_envs: int = 2,
        seed: int | None = None,
        layout_seeds: tuple[int, int] = (0, 2**63),
        threads: int | None = None,
        **kwargs: Any,
    ) -> None:
        if not isinstance(num_envs, int) or num_envs < 1:
            raise ValueError(f"num_envs must be a positive int, got {num_envs!r}")
        self.layout_seeds = checked_layout_seeds(layout_seeds)
        self.config = CupboardSearchConfig(**kwargs)
        self._rng = np.random.default_rng(seed)
        self._batch = self.config.make_batch(self._new_seeds(num_envs), threads=threads)
        self.render_mode = None
        super().__init__(
            num_envs,
            observation_space(self.config, self._batch.proprio_len),
            action_space(self._batch),
        )
        self._actions: Any = np.zeros((num_envs, 3))

    def _new_seeds(self, count: int) -> list[int]:
        low, high = self.layout_seeds
        return [int(s) for s in self._rng.integers(low, high, size=count, dtype=np.uint64)]

    def seed(self, seed: int | None = None) -> Sequence[int | None]:
        self._rng = np.random.default_rng(seed)
        return [seed] * self.num_envs

    def reset(self) -> dict[str, np.ndarray]:
        self._batch.reset_many(list(enumerate(self._new_seeds(self.num_envs))))
        return self._observation()

    def _observation(self) -> dict[str, np.ndarray]:
        """A copy of the batch's observation arrays (the batch overwrites its own)."""
        return {k: v.copy() for k, v in observation_dict(*self._batch.observe()).items()}

    def step_async(self, actions: np.ndarray) -> None:
        self._actions = actions  # checked once, by the core, in step_wait

    def step_wait(self) -> tuple[dict[str, np.ndarray], np.ndarray, np.ndarray, list[dict]]:
        maps, proprio, rewards, terminated, truncated, _ = self._batch.step(self._actions)
        dones = terminated | truncated
        rewards = rewards.astype(np.float32)
        infos = self._batch.infos()
        ended = np.flatnonzero(dones).tolist()
        if ended:
            # The terminal rows first: the resets below overwrite them in the batch's arrays.
            for index in ended:
                terminal = {"proprio": proprio[index].copy()}
                if maps is not None:
                    terminal["map"] = maps[index].copy()
                info = infos[index]
                info["terminal_observation"] = terminal
                info["TimeLimit.truncated"] = info["truncated"]
                info["is_success"] = info["success"]
            self._batch.reset_many([(index, self._new_seeds(1)[0]) for index in ended])
        return self._observation(), rewards, dones, infos

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


with_settings_signature(CupboardSearchSb3VecEnv.__init__)
