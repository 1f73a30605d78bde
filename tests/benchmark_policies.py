"""Policies for the benchmark API's tests: a seeded random one and a scripted one, both
reading only the observation."""

from __future__ import annotations

import numpy as np


def forward(observation: dict) -> np.ndarray:
    """Straight into the cupboard (stateless)."""
    return np.array([0.0, 1.0, 0.0], dtype=np.float32)


class Weaving:
    """Scripted: into the cupboard, weaving from side to side; its phase restarts with each
    episode (``reset``), so a copy per slot is what keeps episodes independent."""

    name = "weaving"

    def __init__(self) -> None:
        self.step = 0

    def reset(self, observation: dict, info: dict) -> None:
        self.step = 0

    def __call__(self, observation: dict) -> np.ndarray:
        self.step += 1
        return np.array([0.6 * np.sin(self.step / 4), 1.0, 0.0], dtype=np.float32)


class RandomProbes:
    """Random probes, seeded per episode from the observation (so order-independent)."""

    def reset(self, observation: dict, info: dict) -> None:
        seed = int(np.asarray(observation["proprio"]).view(np.uint32).sum())
        self.rng = np.random.default_rng(seed)

    def __call__(self, observation: dict) -> np.ndarray:
        return self.rng.integers(0, [29, 10, 9])


class ProbeThenClaim:
    """Identify: one probe straight in along the middle lane, then a claim of whatever the
    finger touches (a probe-mode action with its claim entry)."""

    name = "probe_then_claim"

    def reset(self, observation: dict, info: dict) -> None:
        self.probed = False

    def __call__(self, observation: dict) -> np.ndarray:
        claim = int(self.probed)
        self.probed = True
        return np.array([14, 9, 4, claim])
