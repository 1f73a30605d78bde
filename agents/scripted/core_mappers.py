"""The map task's greedy mappers the agents run: thin faces (``agents.scripted.core_planner``)
over the core's mapper (``tactile_search._core.MapPlanner``; its rules are documented in
``env_core/src/planner/map_planner.rs``), which picks the probe whose finger passes the most
of the map's own uncertainty, each probe once.

- ``VarianceMapper`` (``map="gpis"``): the GPIS standard deviation, the paper's suggestion.
- ``OccupancyMapper`` (``map="occupancy"``): how unknown each cell of the occupancy grid is
  (1 at P(occupied) = 0.5, 0 at 0 or 1).

Their Python reference is ``agents.scripted.map_probe`` (``BeliefVarianceMapper``,
``BeliefOccupancyMapper``).
"""

from __future__ import annotations

from typing import Any, ClassVar

from agents.scripted.core_planner import CorePlannerFace
from tactile_search import _core


class VarianceMapper(CorePlannerFace):
    """Probes where the GPIS standard deviation along the finger's path sums largest."""

    name = "variance_mapper"
    core_class: ClassVar[Any] = _core.MapPlanner


class OccupancyMapper(CorePlannerFace):
    """Probes where the occupancy grid's unknown cells along the finger's path sum largest."""

    name = "occupancy_mapper"
    env_kwargs: ClassVar[dict[str, str]] = {"map": "occupancy", "action_mode": "probe"}
    core_class: ClassVar[Any] = _core.MapPlanner
