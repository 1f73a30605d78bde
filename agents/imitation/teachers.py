"""Who labels the states a student clones: one of the core's scripted planners, or an
ensemble of trained probe-mode runs (distillation).

A teacher is named by a spec, the ``teacher`` key of a recipe's ``imitation`` section:

- ``gpis_probe_planner`` (the default): the scripted planner
  (``agents.scripted.gpis_probe_planner``), which keeps a belief of the probes made; or
  another of the core's planners (``agents.scripted.CORE_PLANNERS``: the identify task's
  ``identify_planner``, whose labels carry its claim, the map task's mappers);
- ``ensemble:RUN,RUN,...``: training seeds of one learned agent acting as one
  (``agents.evaluation.ensemble``), the mode of their averaged probe probabilities. They
  read only the observation, so they label any state a student visits; distilling them into
  one policy keeps what averaging the seeds gains (``docs/RESULTS.md``, "Distilling the
  seeds' ensemble").

Both act through the probe interface: ``reset(env, observation, info)``, ``act(observation)``,
``follow(action)`` (the probe the env carries out instead, in DAgger), and ``env_kwargs``: the
settings of the env the teacher reads (its map), a twin of the student's when they differ.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from agents.evaluation.ensemble import EnsembleAgent, ensemble_members
from agents.scripted import CORE_PLANNERS
from agents.scripted.gpis_probe_planner import GpisProbePlanner

PLANNER = GpisProbePlanner.name


def check_teacher(spec: Any) -> str:
    """``spec`` if it names a teacher (one of the core's planners or an ``ensemble:`` of two
    runs or more); ``TypeError`` / ``ValueError`` naming what was expected otherwise. The
    ensemble's runs are read when the teacher is made (``make_teacher``)."""
    if not isinstance(spec, str):
        raise TypeError(f"teacher must be a string, got {type(spec).__name__}")
    if spec not in CORE_PLANNERS and ensemble_members(spec) is None:
        raise ValueError(
            f"teacher must be one of the core's planners {sorted(CORE_PLANNERS)} or "
            f"'ensemble:RUN,RUN,...', got {spec!r}"
        )
    return spec


class EnsembleTeacher(EnsembleAgent):
    """An ``EnsembleAgent`` as a teacher: it reads nothing but the observation, so following
    another agent's probe changes nothing it keeps; its labels are probe indices."""

    def act(self, observation: dict) -> np.ndarray:
        return np.asarray(super().act(observation), dtype=np.int64)

    def follow(self, action: np.ndarray) -> None:
        del action  # observation-only: nothing to update


def make_teacher(spec: str) -> Any:
    """The teacher ``spec`` names (``check_teacher``)."""
    if check_teacher(spec) in CORE_PLANNERS:
        return CORE_PLANNERS[spec][0]()
    return EnsembleTeacher.from_spec(spec)
