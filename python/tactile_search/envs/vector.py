"""The batched ``CupboardSearch-v0``: N episodes stepped in parallel in Rust.

``gymnasium.make_vec("tactile_search/CupboardSearch-v0", num_envs=N,
vectorization_mode="vector_entry_point")``. Autoreset follows gymnasium 1.x's default
``NEXT_STEP`` mode: the step after an episode ends (terminated or truncated) resets that
episode and returns its first observation with reward 0 and both flags False; the action
given for it is ignored. The reset runs in the same parallel call as the other episodes'
steps. Truncation is the core's: an episode truncates when its steps reach ``max_steps``.

The step path: the core writes observations, rewards, flags and the info (one array per
key, never per-env dicts) into arrays allocated once per batch. With ``copy=True`` (the
default, like gymnasium's own vector envs) each step returns fresh copies of them; with
``copy=False`` it returns the batch's own arrays, which the next step overwrites.
"""

from __future__ import annotations

from typing import Any, ClassVar

import numpy as np
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space

from tactile_search.envs.config import (
    CupboardSearchConfig,
    checked_layout_seeds,
    with_settings_signature,
)
from tactile_search.envs.cupboard_search import action_space, observation_space


def observation_dict(maps: np.ndarray | None, proprio: np.ndarray) -> dict[str, np.ndarray]:
    """The observation dict of the batch's arrays (no ``map`` in the ``none`` mode)."""
    return {"proprio": proprio} if maps is None else {"proprio": proprio, "map": maps}


class CupboardSearchVectorEnv(VectorEnv):
    """``num_envs`` cupboard-search episodes stepped on all cores (see ``CupboardSearchEnv``).

    Args:
        num_envs: number of episodes.
        threads: worker threads (default: every core).
        layout_seeds: ``[low, high)``, the range the episodes' layout seeds are drawn from
            by the env's generator (``np_random``, seeded by ``reset(seed=...)``); keep
            training out of the validation and test ranges with
            ``tactile_search.seed_ranges.TRAINING``.
        copy: return fresh arrays each step (True) or the batch's own arrays, overwritten
            by the next step (False; saves a copy of every output per step).
        **kwargs: the fields of ``CupboardSearchConfig`` (``max_steps`` is the time limit).
    """

    metadata: ClassVar[dict[str, Any]] = {
        "autoreset_mode": AutoresetMode.NEXT_STEP,
        "render_modes": [],
    }

    def __init__(
        self,
        num_envs: int = 2,
        threads: int | None = None,
        copy: bool = True,
        layout_seeds: tuple[int, int] = (0, 2**63),
        **kwargs: Any,
    ) -> None:
        if not isinstance(num_envs, int) or num_envs < 1:
            raise ValueError(f"num_envs must be a positive int, got {num_envs!r}")
        self.layout_seeds = checked_layout_seeds(layout_seeds)
        self.num_envs = num_envs
        self.copy = bool(copy)
        self.config = CupboardSearchConfig(**kwargs)
        self._batch = self.config.make_batch(list(range(num_envs)), threads=threads)
        self.single_observation_space = observation_space(self.config, self._batch.proprio_len)
        self.single_action_space = action_space(self._batch)
        self.observation_space = batch_space(self.single_observation_space, num_envs)
        self.action_space = batch_space(self.single_action_space, num_envs)
        self._needs_reset = np.zeros(num_envs, dtype=bool)

    def _seeds(self, count: int) -> list[int]:
        low, high = self.layout_seeds
        # int64 draws while the range fits them (the default range draws what it always did).
        dtype = np.int64 if high <= 2**63 else np.uint64
        return [int(s) for s in self.np_random.integers(low, high, size=count, dtype=dtype)]

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
        self._batch.reset_many(list(enumerate(seeds)))
        self._needs_reset[:] = False
        observation = observation_dict(*self._batch.observe())
        info = self._batch.info_arrays()
        return self._out(observation), self._out(info)

    def step(self, actions: Any) -> tuple[dict, np.ndarray, np.ndarray, np.ndarray, dict]:
        # Episodes that ended last step start over in the same parallel call (their action
        # is ignored): they return their first observation, reward 0, flags False. (Most
        # steps reset nothing: skip the numpy calls then, a draw of no seeds changes no state.)
        # A step the core refuses (bad actions) changes nothing: the generator's state is put
        # back, so the seeds drawn for these resets are drawn again by the next step.
        resets = None
        generator_state = None
        if self._needs_reset.any():
            generator_state = self.np_random.bit_generator.state
            resetting = np.flatnonzero(self._needs_reset).tolist()
            resets = list(zip(resetting, self._seeds(len(resetting)), strict=True))
        try:
            maps, proprio, rewards, terminated, truncated, info = self._batch.step(actions, resets)
        except Exception:
            if generator_state is not None:
                self.np_random.bit_generator.state = generator_state
            raise
        self._needs_reset = terminated | truncated
        observation = observation_dict(maps, proprio)
        if self.copy:
            return (
                self._out(observation),
                rewards.copy(),
                terminated.copy(),
                truncated.copy(),
                self._out(info),
            )
        return observation, rewards, terminated, truncated, info

    def _out(self, arrays: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        """``arrays`` as returned: copies unless ``copy=False``."""
        if self.copy:
            return {key: value.copy() for key, value in arrays.items()}
        return dict(arrays)

    def oracle_actions(self) -> np.ndarray:
        """Actions ``(num_envs, 3)`` of a scripted searcher that knows each target."""
        return self._batch.oracle_actions().astype(np.float32)


with_settings_signature(CupboardSearchVectorEnv.__init__)
