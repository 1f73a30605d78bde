"""Scripted baselines: random, the oracle (knows the target) and the GPIS probe planner
(reads only the observation, chooses the core's probes); for the identify task random probes
with random claims while touching and the identify planner (finds the hidden jars, judges a
touched jar's shape and claims the square one). The oracle runs in either task."""

from __future__ import annotations

from collections.abc import Callable

from agents.rollout import Agent
from agents.scripted.gpis_probe_planner import GpisProbePlanner
from agents.scripted.identify_planner import IdentifyPlanner
from agents.scripted.oracle_agent import OracleAgent
from agents.scripted.random_agent import RandomAgent
from agents.scripted.random_identify import RandomIdentifyAgent

SCRIPTED_AGENTS: dict[str, Callable[[], Agent]] = {
    "random": RandomAgent,
    "oracle": OracleAgent,
    "gpis_probe_planner": GpisProbePlanner,
    "random_identify": RandomIdentifyAgent,
    "identify_planner": IdentifyPlanner,
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
}


def scripted_agents_for(task: str) -> list[str]:
    """The scripted agents that play ``task``, in the order of ``SCRIPTED_AGENTS``."""
    return [name for name in SCRIPTED_AGENTS if task in SCRIPTED_TASKS[name]]


__all__ = [
    "ORACLE",
    "SCRIPTED_AGENTS",
    "SCRIPTED_TASKS",
    "Agent",
    "GpisProbePlanner",
    "IdentifyPlanner",
    "OracleAgent",
    "RandomAgent",
    "RandomIdentifyAgent",
    "scripted_agents_for",
]
