"""The GPIS probe planner: the scripted searcher that plans on the GPIS map without ground
truth, choosing the probes of the core's probe action mode, and the teacher every recipe
clones.

A thin face (``agents.scripted.core_planner``) over the core's planner
(``tactile_search._core.ProbePlanner``; its rules are documented in
``env_core/src/planner/probe_planner.rs``).
"""

from __future__ import annotations

from typing import Any, ClassVar

from agents.scripted.core_planner import CorePlannerFace
from tactile_search import _core


class GpisProbePlanner(CorePlannerFace):
    """The GPIS-map searcher choosing the core's probes; see the module docstring. Its
    actions are ``(lane, depth, sweep)``."""

    name = "gpis_probe_planner"
    core_class: ClassVar[Any] = _core.ProbePlanner
