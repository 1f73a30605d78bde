"""The agent protocol every evaluated agent (learned or scripted) follows."""

from __future__ import annotations

from typing import Protocol

import numpy as np

from tactile_search import CupboardSearchEnv


class Agent(Protocol):
    """Acts in one episode at a time; ``reset`` starts an episode.

    ``env`` is the unwrapped environment, for static geometry (hand sizes, map bounds) and the
    oracle; agents that claim not to use ground truth must not call ``render_state``.
    """

    name: str

    def reset(self, env: CupboardSearchEnv, observation: dict, info: dict) -> None: ...

    def act(self, observation: dict) -> np.ndarray:
        """A float32 ``(3,)`` action in [-1, 1]."""
        ...
