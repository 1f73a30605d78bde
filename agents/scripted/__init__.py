"""Scripted baselines: random, the oracle (knows the target) and the GPIS planner (driving the
wrist itself, or choosing the core's probes)."""

from __future__ import annotations

from collections.abc import Callable

from agents.rollout import Agent
from agents.scripted.gpis_planner import GpisPlanner
from agents.scripted.gpis_probe_planner import GpisProbePlanner
from agents.scripted.oracle_agent import OracleAgent
from agents.scripted.random_agent import RandomAgent

SCRIPTED_AGENTS: dict[str, Callable[[], Agent]] = {
    "random": RandomAgent,
    "oracle": OracleAgent,
    "gpis_planner": GpisPlanner,
    "gpis_probe_planner": GpisProbePlanner,
}

__all__ = [
    "SCRIPTED_AGENTS",
    "Agent",
    "GpisPlanner",
    "GpisProbePlanner",
    "OracleAgent",
    "RandomAgent",
]
