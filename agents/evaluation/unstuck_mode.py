"""A learned agent that takes its policy's mode until it is stuck, then samples.

A probe-mode policy evaluated by its mode can loop: a probe that makes no wrist motion (a
"wait", ``agents.evaluation.probe_trace``) leaves the observation as it was but for the time
left, so the mode chooses the same probe again until the time limit. ``UnstuckMode`` reads
only the observation: when everything but ``time_left`` is what it was before its last
probe, that probe changed nothing, and it samples its next probe from the policy instead
(seeded per episode, as ``agents.sb3.learned.LearnedAgent`` samples); otherwise it takes the
mode. It measures how much of a mode-evaluated agent's failure is this loop; it is a
decoding rule of the same policy, not what third-party tools do (they take the mode).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from agents.evaluation.wrapped_agent import WrappedAgent
from tactile_search.envs.observation import PROPRIO

# Proprio entries that change with time alone: not a sign that the last probe did anything.
_CLOCK = PROPRIO["time_left"]


def unchanged_but_the_clock(before: dict, now: dict) -> bool:
    """Whether ``now`` equals ``before`` in every entry but the proprio's ``time_left``."""
    if before.keys() != now.keys():
        return False
    for key in now:
        a, b = np.asarray(before[key]), np.asarray(now[key])
        if key == "proprio":
            a, b = np.delete(a, _CLOCK, axis=-1), np.delete(b, _CLOCK, axis=-1)
        if not np.array_equal(a, b):
            return False
    return True


class UnstuckMode(WrappedAgent):
    """``agent`` (a ``LearnedAgent``) by its mode, sampling a probe whenever its last probe
    left the observation unchanged but for the clock. Named as ``agent``: an evaluation that
    uses it says so by its ``actions`` (``mode_unstuck``) and keeps its rows apart by their
    fingerprint."""

    def __init__(self, agent: Any) -> None:
        super().__init__(agent)
        self._previous: dict | None = None

    def reset(self, env: Any, observation: dict, info: dict) -> None:
        self._agent.deterministic = False  # seeds the episode's sampling stream
        self._agent.reset(env, observation, info)
        self._previous = None

    def act(self, observation: dict) -> np.ndarray:
        stuck = self._previous is not None and unchanged_but_the_clock(self._previous, observation)
        self._agent.deterministic = not stuck
        self._previous = {key: np.array(value, copy=True) for key, value in observation.items()}
        return self._agent.act(observation)
