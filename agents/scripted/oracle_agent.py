"""The scripted oracle that knows the target: the upper-bound baseline."""

from __future__ import annotations

import numpy as np

from tactile_search import CupboardSearchEnv


class OracleAgent:
    """Follows ``CupboardSearchEnv.oracle_action`` (ground truth: the target and corridor)."""

    name = "oracle"

    def __init__(self) -> None:
        self._env: CupboardSearchEnv | None = None

    def reset(self, env: CupboardSearchEnv, observation: dict, info: dict) -> None:
        self._env = env

    def act(self, observation: dict) -> np.ndarray:
        if self._env is None:
            raise RuntimeError("call reset before act")
        return self._env.oracle_action()
