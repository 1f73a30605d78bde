"""Scripted baselines: random, the oracle (knows the target) and the GPIS probe planner
(reads only the observation, chooses the core's probes)."""

from __future__ import annotations

from collections.abc import Callable

from agents.rollout import Agent
from agents.scripted.gpis_probe_planner import GpisProbePlanner
from agents.scripted.map_probe import MapOracle, OccupancyMapper, RandomMapAgent, VarianceMapper
from agents.scripted.oracle_agent import OracleAgent
from agents.scripted.random_agent import RandomAgent

SCRIPTED_AGENTS: dict[str, Callable[[], Agent]] = {
    "random": RandomAgent,
    "oracle": OracleAgent,
    "gpis_probe_planner": GpisProbePlanner,
    # The map task's baselines (tactile_search/MapByTouch-v0, probe action mode).
    "random_map": RandomMapAgent,
    "variance_mapper": VarianceMapper,
    "occupancy_mapper": OccupancyMapper,
    "map_oracle": MapOracle,
}

__all__ = [
    "SCRIPTED_AGENTS",
    "Agent",
    "GpisProbePlanner",
    "OracleAgent",
    "RandomAgent",
]
