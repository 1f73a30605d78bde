"""A scripted agent that is a thin face over one of the core's planners
(``tactile_search._core.ProbePlanner``, ``IdentifyPlanner``, ``MapPlanner``): the core keeps
the episode's belief and chooses the actions, from the env's settings and the observations
alone. The face
runs it as an agent of one episode (``reset``, ``act``, ``follow``, as every scripted agent
and teacher does); the core's class plans for a batch of ``n`` episodes at once, on every
core (``agents.imitation.batched`` and ``benchmarks.teacher_speed`` run it over a vector
env).
"""

from __future__ import annotations

from typing import Any, ClassVar

import numpy as np

from tactile_search import CupboardSearchEnv


class CorePlannerFace:
    """An agent over the core's planner class ``core_class`` (set by each subclass)."""

    name = "core_planner"
    #: The settings of the env it runs on (an evaluation builds it with these).
    env_kwargs: ClassVar[dict[str, str]] = {"map": "gpis", "action_mode": "probe"}
    #: The core's planner class, made as ``core_class(config, num_envs)``.
    core_class: ClassVar[Any]

    def __init__(self) -> None:
        self._core: Any = None
        self._core_config: Any = None
        self._sizes: tuple[int, ...] = ()

    def __getstate__(self) -> dict:
        """A copy (pickled, or deep-copied by a runner giving each slot its own agent)
        plans from its next ``reset``: the core's planner, which holds the episode's belief,
        is not copied."""
        return {**self.__dict__, "_core": None, "_core_config": None}

    def reset(self, env: CupboardSearchEnv, observation: dict, info: dict) -> None:
        """Starts an episode of ``env`` (settings the core's planner plans for, else
        ``ValueError`` naming them) from its first ``observation``."""
        del info  # the planner reads the observation only
        wanted = self.env_kwargs["map"]
        if "map" not in observation or env.config.map != wanted:
            raise ValueError(
                f"{type(self).__name__} needs the map observation of map={wanted!r}, got "
                f"map={env.config.map!r}"
            )
        # The core's planner holds the settings' static geometry: made once per settings.
        if self._core is None or self._core_config != env.config.core:
            self._core = self.core_class(env.config.core, 1)
            self._core_config = env.config.core
        self._core.reset(0, observation["map"], observation["proprio"])
        config = env.config
        self._sizes = (config.probe_lanes, config.probe_depths, config.probe_sweeps)

    def act(self, observation: dict) -> np.ndarray:
        """The next action after ``observation``."""
        if self._core is None:
            raise RuntimeError("call reset before act")
        return self._core.act(observation["map"][None], observation["proprio"][None])[0]

    def follow(self, action: np.ndarray) -> None:
        """Takes ``action``'s probe, not the one ``act`` just chose, as the probe the env
        carries out next: the planner then labels states another agent visits (DAgger), its
        belief learning from the probes that agent made. Raises ``ValueError`` for an action
        that is not a probe of the grid."""
        if self._core is None:
            raise RuntimeError("call reset before follow")
        self._core.follow(0, list(probe_indices(self._probe_of(action), self._sizes)))

    def _probe_of(self, action: np.ndarray) -> np.ndarray:
        """The probe part of ``action``."""
        return action


def probe_indices(action: np.ndarray, sizes: tuple[int, ...]) -> tuple[int, int, int]:
    """``action`` as a probe's ``(lane, depth, sweep)`` indices below ``sizes``;
    ``ValueError`` naming the grid for anything else (a float index, one out of range, a
    shape other than three)."""
    indices = np.asarray(action).reshape(-1)
    if indices.shape != (3,) or any(
        not float(i).is_integer() or not 0 <= i < n for i, n in zip(indices, sizes, strict=True)
    ):
        raise ValueError(f"follow needs a probe (lane, depth, sweep) below {sizes}, got {action!r}")
    lane, depth, sweep = (int(i) for i in indices)
    return lane, depth, sweep
