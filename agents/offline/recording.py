"""An agent's episodes on training layouts as Minari's episode buffers.

Each episode is played in a ``gymnasium.make``'d env of the registered id (so the dataset
records the id's spec, with the agent's map and action mode over it), from a layout seed of
the training range only (``tactile_search.seed_ranges.TRAINING``: a dataset to learn from must
not hold validation or test layouts). The buffer keeps the seed: reset a fresh env with it
and step the recorded actions, and the observations come again bit for bit.
"""

from __future__ import annotations

import numbers
from collections.abc import Mapping, Sequence
from typing import Any

import gymnasium
import numpy as np
from minari.data_collector import EpisodeBuffer

from agents.rollout import Agent
from tactile_search._validation import as_count
from tactile_search.seed_ranges import TRAINING


def training_seeds(episodes: int, first: int = TRAINING[0]) -> list[int]:
    """``episodes`` consecutive layout seeds of the training range from ``first``."""
    seeds = list(range(first, first + as_count("episodes", episodes)))
    check_training_seeds(seeds)
    return seeds


def check_training_seeds(seeds: Sequence[int]) -> None:
    """``ValueError`` unless every seed is an int of the training range."""
    low, high = TRAINING
    outside = [seed for seed in seeds if not _is_training_seed(seed)]
    if outside:
        raise ValueError(
            f"a dataset's layout seeds must be ints of the training range [{low}, {high}) "
            f"(tactile_search.seed_ranges.TRAINING), got {outside[:5]}"
        )


def _is_training_seed(seed: object) -> bool:
    return (
        isinstance(seed, numbers.Integral)
        and not isinstance(seed, bool)
        and TRAINING[0] <= int(seed) < TRAINING[1]
    )


def agent_settings(env_id: str, agent_kwargs: Mapping[str, Any]) -> dict[str, Any]:
    """The settings an agent's env takes over registered id ``env_id``'s: the agent's own
    (its map, its action mode) but none the id sets (the id's task and tier win, as in the
    evaluation, ``agents.evaluation.evaluation.prepare_evaluation``)."""
    registered = gymnasium.spec(env_id).kwargs
    return {key: value for key, value in agent_kwargs.items() if key not in registered}


def make_env(env_id: str, agent_kwargs: Mapping[str, Any]) -> gymnasium.Env:
    """``gymnasium.make(env_id)`` with the agent's settings over the id's (``agent_settings``)."""
    return gymnasium.make(env_id, **agent_settings(env_id, agent_kwargs))


def record_episode(env: gymnasium.Env, agent: Agent, seed: int) -> EpisodeBuffer:
    """One episode of ``agent`` in ``env`` from layout ``seed``: its observations (the reset's
    and every step's, stacked per key of the Dict space), actions, rewards, terminations,
    truncations and infos (the reset's and every step's), and the seed. The agent is handed
    the unwrapped env at reset (``agents.rollout.Agent``)."""
    check_training_seeds([seed])
    observation, info = env.reset(seed=int(seed))
    agent.reset(env.unwrapped, observation, info)  # type: ignore[arg-type]
    observations, infos = [observation], [info]
    actions, rewards, terminations, truncations = [], [], [], []
    terminated = truncated = False
    # The env ends every episode itself: a success, a tip, a claim, or its own time limit.
    while not (terminated or truncated):
        action = agent.act(observation)
        observation, reward, terminated, truncated, info = env.step(action)
        observations.append(observation)
        infos.append(info)
        actions.append(np.asarray(action))
        rewards.append(float(reward))
        terminations.append(bool(terminated))
        truncations.append(bool(truncated))
    return EpisodeBuffer(
        seed=int(seed),
        observations=_stacked(observations),
        actions=np.stack(actions),
        rewards=rewards,
        terminations=terminations,
        truncations=truncations,
        infos=_stacked(infos),
    )


def record_episodes(env: gymnasium.Env, agent: Agent, seeds: Sequence[int]) -> list[EpisodeBuffer]:
    """``record_episode`` for each seed, in order."""
    check_training_seeds(seeds)
    return [record_episode(env, agent, seed) for seed in seeds]


def _stacked(items: list[dict[str, Any]]) -> dict[str, np.ndarray]:
    """A list of dicts (observations, infos) as a dict of arrays, one row per item."""
    return {key: np.stack([np.asarray(item[key]) for item in items]) for key in items[0]}
