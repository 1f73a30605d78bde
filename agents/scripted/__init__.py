"""Scripted baselines: random, the oracle (knows the target) and the GPIS planner."""

from __future__ import annotations

from collections.abc import Callable

from agents.rollout import Agent
from agents.scripted.gpis_planner import GpisPlanner
from agents.scripted.oracle_agent import OracleAgent
from agents.scripted.random_agent import RandomAgent

SCRIPTED_AGENTS: dict[str, Callable[[], Agent]] = {
    "random": RandomAgent,
    "oracle": OracleAgent,
    "gpis_planner": GpisPlanner,
}

__all__ = ["SCRIPTED_AGENTS", "Agent", "GpisPlanner", "OracleAgent", "RandomAgent"]
