"""The identify task's planner (``tactile_search/IdentifyByTouch-v0`` and its dense tier): it
finds the hidden jars with the GPIS probe planner's search, tells a touched jar's shape from
the contacts it collects on it, and claims the square one.

A thin face (``agents.scripted.core_planner``) over the core's planner
(``tactile_search._core.IdentifyPlanner``; its strategy and rules are documented in
``env_core/src/planner/identify_planner.rs``). It reads only the observation and the
settings, never the ground truth.
"""

from __future__ import annotations

from typing import Any, ClassVar

import numpy as np

from agents.scripted.core_planner import CorePlannerFace
from tactile_search import _core


class IdentifyPlanner(CorePlannerFace):
    """The identify task's planner; see the module docstring. Its actions are ``(lane,
    depth, sweep, claim)``."""

    name = "identify_planner"
    core_class: ClassVar[Any] = _core.IdentifyPlanner

    def _probe_of(self, action: np.ndarray) -> np.ndarray:
        """The probe of an identify action ``(lane, depth, sweep, claim)``; a probe alone
        is taken as it is."""
        indices = np.asarray(action).reshape(-1)
        return indices[:3] if indices.shape == (4,) else indices
