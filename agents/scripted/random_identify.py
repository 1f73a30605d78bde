"""Random probes that claim at random while touching: the identify task's lower-bound
baseline."""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from tactile_search import CupboardSearchEnv
from tactile_search.envs.observation import PROPRIO


class RandomIdentifyAgent:
    """Random probes of the ``probe`` action mode's grid, with a coin flip for a claim.

    The rule: every action is a probe (lane, depth, sweep) drawn uniformly from the grid.
    When the observation says the last step ended touching something (the proprio entry
    ``in_contact`` is 1), the agent claims with probability 0.5 instead (the claim entry
    1; the probe indices drawn all the same, though a claim makes no motion); it never claims
    otherwise, so it never claims with nothing touched. Its generator is its own, seeded
    with ``seed``; an evaluation makes it afresh for every episode with the episode's layout
    seed (``agents.evaluation.agent_specs.SeededPerEpisode``), as the random agent.
    """

    name = "random_identify"
    #: The settings of the env it runs on (an evaluation builds it with these).
    env_kwargs: ClassVar[dict[str, str]] = {"map": "gpis", "action_mode": "probe"}

    def __init__(self, seed: int | None = 0) -> None:
        self._rng = np.random.default_rng(seed)
        self._counts: np.ndarray | None = None

    def reset(self, env: CupboardSearchEnv, observation: dict, info: dict) -> None:
        config = env.config
        if config.action_mode != "probe" or config.task != "identify":
            raise ValueError(
                "RandomIdentifyAgent needs task='identify' and action_mode='probe', got "
                f"task={config.task!r}, action_mode={config.action_mode!r}"
            )
        g = env.geometry()
        self._counts = np.array(
            [len(g["probe_lanes"]), len(g["probe_depths"]), len(g["probe_yaws"])]
        )

    def act(self, observation: dict) -> np.ndarray:
        if self._counts is None:
            raise RuntimeError("call reset before act")
        probe = self._rng.integers(0, self._counts)
        touching = observation["proprio"][PROPRIO["in_contact"]] > 0.5
        claim = int(touching and self._rng.random() < 0.5)
        return np.array([*probe, claim], dtype=np.int64)
