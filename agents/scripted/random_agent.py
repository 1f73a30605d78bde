"""Uniformly random actions: the lower-bound baseline."""

from __future__ import annotations

import numpy as np

from tactile_search import CupboardSearchEnv


class RandomAgent:
    """Uniform actions in [-1, 1]^3 from its own seeded generator."""

    name = "random"

    def __init__(self, seed: int | None = 0) -> None:
        self._rng = np.random.default_rng(seed)

    def reset(self, env: CupboardSearchEnv, observation: dict, info: dict) -> None:
        pass

    def act(self, observation: dict) -> np.ndarray:
        return self._rng.uniform(-1.0, 1.0, 3).astype(np.float32)
