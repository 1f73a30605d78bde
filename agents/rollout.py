"""The ``Agent`` protocol every agent implements (scripted and learned), and the loops that run
agents through episodes: ``evaluate_agent`` (the evaluation: the package's benchmark runner,
``tactile_search.benchmark``, on the vector env) and ``run_episodes`` (one
``CupboardSearchEnv`` episode after another, with a hook after every step, for drawing
GIFs and tracing probes)."""

from __future__ import annotations

import copy
from collections.abc import Callable
from typing import Any, Protocol

import numpy as np

from tactile_search import CupboardSearchEnv
from tactile_search.benchmark import episode_row
from tactile_search.benchmark.map_curve import MapScoreTrace
from tactile_search.benchmark.runner import run_on_seeds


class Agent(Protocol):
    """Acts in one episode at a time; ``reset`` starts an episode.

    ``env`` is the unwrapped environment, for static geometry (hand sizes, map bounds) and the
    oracle; agents that claim not to use ground truth must not call ``render_state``.
    """

    name: str

    def reset(self, env: CupboardSearchEnv, observation: dict, info: dict) -> None: ...

    def act(self, observation: dict) -> np.ndarray:
        """The env's action: a float32 ``(3,)`` wrist motion in [-1, 1], or in the
        ``probe`` action mode int64 ``(3,)`` probe indices."""
        ...


def run_episodes(
    agent: Agent,
    seeds: list[int],
    max_steps: int | None = None,
    on_step: Callable[[CupboardSearchEnv, int, bool], None] | None = None,
    on_episode: Callable[[dict[str, Any]], None] | None = None,
    **env_kwargs: Any,
) -> list[dict[str, Any]]:
    """One ``CupboardSearchEnv`` episode per seed with ``agent``; per-episode summaries.

    ``max_steps`` (at most this many agent steps) defaults to the env's ``max_steps`` (the
    registered time limit, which the env enforces itself). Each dict: seed, success, steps
    (wrist motions), actions (the agent's steps: a probe each in the probe action mode, a
    wrist motion in the wrist mode), tips, jar_displacement, max_jar_displacement, iou
    (final), reward.
    ``on_step(env, step, done)``, if given, is called after the reset (step 0) and after
    every step (``done``: the episode's last), e.g. to render frames. ``on_episode(result)``,
    if given, is called with each episode's summary as soon as the episode ends (e.g. to write
    it to disk, so that an interrupted evaluation keeps what it finished).
    """
    env = CupboardSearchEnv(**env_kwargs)
    limit = env.config.max_steps if max_steps is None else max_steps
    results = []
    for seed in seeds:
        observation, info = env.reset(seed=seed)
        trace = MapScoreTrace(info) if env.config.task == "map" else None
        agent.reset(env, observation, info)
        if on_step is not None:
            on_step(env, 0, False)
        total = 0.0
        for step in range(1, limit + 1):
            observation, reward, terminated, truncated, info = env.step(agent.act(observation))
            total += reward
            if trace is not None:
                trace.step(info)
            # The env's own time limit counts wrist motions: in the probe action mode a
            # step is many of them, so its truncation, not this loop's count, ends the run.
            ended = terminated or truncated or step == limit
            if on_step is not None:
                on_step(env, step, ended)
            if ended:
                break
        curve = "" if trace is None else trace.curve(env.config.max_steps)
        result = episode_row(seed, info, actions=step, reward=total, map_score_curve=curve)
        results.append(result)
        if on_episode is not None:
            on_episode(result)
    env.close()
    return results


class AgentPolicy:
    """An ``Agent`` as a benchmark policy for one slot of the vector env: ``reset`` hands the
    agent the slot's ``SubEnv`` (what it reads of the env: geometry, decoders, oracle, the
    episode's seed)."""

    def __init__(self, agent: Agent, env: Any) -> None:
        self.agent = agent
        self.env = env

    def reset(self, observation: dict, info: dict) -> None:
        self.agent.reset(self.env, observation, info)

    def __call__(self, observation: dict) -> np.ndarray:
        return self.agent.act(observation)


def evaluate_agent(
    agent: Agent,
    seeds: list[int],
    on_episode: Callable[[dict[str, Any]], None] | None = None,
    num_envs: int | None = None,
    **env_kwargs: Any,
) -> list[dict[str, Any]]:
    """One episode per seed with ``agent`` on the vector env, through the package's
    benchmark runner (``tactile_search.benchmark.runner.run_on_seeds``): the rows
    ``run_episodes`` gives, one per seed in order (``on_episode`` as each ends). Slot 0 plays
    ``agent`` itself, the others copies of it; each episode starts with the agent's
    ``reset``, so an agent's episodes do not depend on which slot or what came before."""

    def make_policy(sub_env: Any) -> AgentPolicy:
        return AgentPolicy(agent if sub_env.index == 0 else copy.deepcopy(agent), sub_env)

    return run_on_seeds(make_policy, seeds, num_envs=num_envs, on_episode=on_episode, **env_kwargs)
