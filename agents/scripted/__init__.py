"""Scripted baselines: random, the oracle (knows the target) and the GPIS probe planner
(reads only the observation, chooses the core's probes); for the identify task random probes
with random claims while touching and the identify planner (finds the hidden jars, judges a
touched jar's shape and claims the square one); for the map task random probes, the greedy
mappers on the GPIS standard deviation and the occupancy grid's unknown cells, and a map
oracle (reads the true jars). The oracle runs in the search and identify tasks."""

from __future__ import annotations

from collections.abc import Callable

from agents.rollout import Agent
from agents.scripted.belief_identify import BeliefIdentifyPlanner
from agents.scripted.belief_planner import BeliefProbePlanner
from agents.scripted.core_mappers import OccupancyMapper, VarianceMapper
from agents.scripted.gpis_probe_planner import GpisProbePlanner
from agents.scripted.identify_planner import IdentifyPlanner
from agents.scripted.map_probe import (
    BeliefOccupancyMapper,
    BeliefVarianceMapper,
    MapOracle,
    RandomMapAgent,
)
from agents.scripted.oracle_agent import OracleAgent
from agents.scripted.random_agent import RandomAgent
from agents.scripted.random_identify import RandomIdentifyAgent

SCRIPTED_AGENTS: dict[str, Callable[[], Agent]] = {
    "random": RandomAgent,
    "oracle": OracleAgent,
    "gpis_probe_planner": GpisProbePlanner,
    "random_identify": RandomIdentifyAgent,
    "identify_planner": IdentifyPlanner,
    # The map task's baselines (tactile_search/MapByTouch-v0, probe action mode).
    "random_map": RandomMapAgent,
    "variance_mapper": VarianceMapper,
    "occupancy_mapper": OccupancyMapper,
    "map_oracle": MapOracle,
}

#: The scripted planners that are faces of the core's (the teachers), each beside the
#: Python reference of its rules (``benchmarks.planner_agreement``,
#: ``benchmarks.teacher_speed``).
CORE_PLANNERS: dict[str, tuple[type, type]] = {
    "gpis_probe_planner": (GpisProbePlanner, BeliefProbePlanner),
    "identify_planner": (IdentifyPlanner, BeliefIdentifyPlanner),
    "variance_mapper": (VarianceMapper, BeliefVarianceMapper),
    "occupancy_mapper": (OccupancyMapper, BeliefOccupancyMapper),
}

#: The name of the upper-bound baseline (it knows the target).
ORACLE = "oracle"

#: The tasks (the ``task`` setting) each scripted agent plays: the search agents' actions
#: carry no claim entry, the identify agents' do; the oracle's come from the core's.
SCRIPTED_TASKS: dict[str, tuple[str, ...]] = {
    "random": ("search",),
    "oracle": ("search", "identify"),
    "gpis_probe_planner": ("search",),
    "random_identify": ("identify",),
    "identify_planner": ("identify",),
    "random_map": ("map",),
    "variance_mapper": ("map",),
    "occupancy_mapper": ("map",),
    "map_oracle": ("map",),
}


def scripted_agents_for(task: str) -> list[str]:
    """The scripted agents that play ``task``, in the order of ``SCRIPTED_AGENTS``."""
    return [name for name in SCRIPTED_AGENTS if task in SCRIPTED_TASKS[name]]


__all__ = [
    "CORE_PLANNERS",
    "ORACLE",
    "SCRIPTED_AGENTS",
    "SCRIPTED_TASKS",
    "Agent",
    "BeliefIdentifyPlanner",
    "BeliefOccupancyMapper",
    "BeliefProbePlanner",
    "BeliefVarianceMapper",
    "GpisProbePlanner",
    "IdentifyPlanner",
    "MapOracle",
    "OccupancyMapper",
    "OracleAgent",
    "RandomAgent",
    "RandomIdentifyAgent",
    "RandomMapAgent",
    "VarianceMapper",
    "scripted_agents_for",
]
