"""The agents an evaluation is given by name: a scripted agent's name or a training run's
directory, made into an agent with the settings of the env it is evaluated in, with unique
names (training seeds of one agent told apart)."""

from __future__ import annotations

import inspect
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from agents.evaluation.ensemble import EnsembleAgent, ensemble_members
from agents.evaluation.map_ablation import blanked_agent
from agents.evaluation.unstuck_mode import UnstuckMode
from agents.run_dir import run_label
from agents.scripted import SCRIPTED_AGENTS

# How a learned agent picks its actions: as its recipe says (deterministic_evaluation), the
# policy's mode, a sample from it (seeded per episode), or the mode but a sample whenever the
# last probe left the observation unchanged (agents.evaluation.unstuck_mode).
ACTIONS = ("recipe", "mode", "sample", "mode_unstuck")


def _deterministic(actions: str) -> bool | None:
    if actions not in ACTIONS:
        raise ValueError(f"actions must be one of {ACTIONS}, got {actions!r}")
    return {"recipe": None, "mode": True, "sample": False, "mode_unstuck": True}[actions]


def make_agent(
    spec: str, actions: str = "recipe", blanked: Sequence[str] = ()
) -> tuple[Any, dict[str, Any]]:
    """An agent and the settings of the env it is evaluated in (with its ``map``) from a
    scripted name (the GPIS map, and the agent's own ``env_kwargs`` where it has them, such as
    the probe action mode) or a run directory (its recipe's env settings without the
    reward terms: ``agents.sb3.learned.evaluation_env_kwargs``), its actions chosen as
    ``actions`` says (``ACTIONS``), reading its map with the ``blanked`` channels (``NAME=VALUE``
    each) held at their values (``agents.evaluation.map_ablation``).

    A scripted agent that takes a ``seed`` (the random agent) is made afresh for every
    episode, seeded with the episode's layout seed (``SeededPerEpisode``)."""
    agent, env_kwargs = _make_unblanked(spec, actions)
    return blanked_agent(agent, env_kwargs["map"], blanked), env_kwargs


def _make_unblanked(spec: str, actions: str) -> tuple[Any, dict[str, Any]]:
    if ensemble_members(spec) is not None:
        if actions not in ("recipe", "mode"):
            raise ValueError(f"an ensemble acts by the mode of its mean, got actions {actions!r}")
        ensemble = EnsembleAgent.from_spec(spec)
        return ensemble, ensemble.env_kwargs
    if spec in SCRIPTED_AGENTS:
        factory = SCRIPTED_AGENTS[spec]
        # The GPIS map unless the agent names its own (random_map plays any map).
        env_kwargs = {"map": "gpis", **getattr(factory, "env_kwargs", {})}
        if "seed" in inspect.signature(factory).parameters:
            return SeededPerEpisode(factory), env_kwargs
        return factory(), env_kwargs
    from agents.sb3.learned import LearnedAgent

    agent = LearnedAgent(Path(spec), deterministic=_deterministic(actions))
    if actions == "mode_unstuck":
        return UnstuckMode(agent), agent.env_kwargs
    return agent, agent.env_kwargs


class SeededPerEpisode:
    """An agent with its own random generator, made afresh at every reset and seeded with
    the episode's layout seed: an episode's actions then do not depend on the episodes run
    before it, so an evaluation resumed part-way gives the rows of an uninterrupted one."""

    def __init__(self, factory: Any) -> None:
        self._factory = factory
        self._agent = factory(seed=0)
        self.name: str = self._agent.name

    def reset(self, env: Any, observation: dict, info: dict) -> None:
        self._agent = self._factory(seed=env.np_random_seed)
        self._agent.reset(env, observation, info)

    def act(self, observation: dict) -> np.ndarray:
        return self._agent.act(observation)


def seeded_name(algo: str, map_mode: str, seed: int) -> str:
    """The evaluated name of one training seed's run when an agent has several
    (``agents.evaluation.comparison.agent_and_seed`` reads it back)."""
    return f"{algo} ({map_mode} map, seed {seed})"


def unique_names(agents: Sequence[Any], specs: Sequence[str]) -> list[str]:
    """The agents' names, made unique: learned agents of the same algorithm and map (several
    training seeds) get their run's seed in the name."""
    given = [agent.name for agent in agents]
    names = list(given)
    for i, (agent, spec) in enumerate(zip(agents, specs, strict=True)):
        if given.count(agent.name) > 1 and spec not in SCRIPTED_AGENTS:
            config = agent.config
            suffix = getattr(agent, "name_suffix", "")  # a blanked map's (map_ablation)
            names[i] = seeded_name(run_label(config), config["map"], config["seed"]) + suffix
    repeated = sorted({name for name in names if names.count(name) > 1})
    if repeated:
        raise ValueError(f"each agent may be evaluated once, got {repeated} more than once")
    return names
