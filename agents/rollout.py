"""The ``Agent`` protocol every agent implements (scripted and learned), and the loop that runs
agents through episodes of ``CupboardSearchEnv`` (``run_episodes``)."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, Protocol

import numpy as np

from tactile_search import CupboardSearchEnv
from tactile_search.benchmark import episode_row


class Agent(Protocol):
    """Acts in one episode at a time; ``reset`` starts an episode.

    ``env`` is the unwrapped environment, for static geometry (hand sizes, map bounds) and the
    oracle; agents that claim not to use ground truth must not call ``render_state``.
    """

    name: str

    def reset(self, env: CupboardSearchEnv, observation: dict, info: dict) -> None: ...

    def act(self, observation: dict) -> np.ndarray:
        """A float32 ``(3,)`` action in [-1, 1]."""
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
        agent.reset(env, observation, info)
        if on_step is not None:
            on_step(env, 0, False)
        total = 0.0
        for step in range(1, limit + 1):
            observation, reward, terminated, truncated, info = env.step(agent.act(observation))
            total += reward
            # The env's own time limit counts wrist motions: in the probe action mode a
            # step is many of them, so its truncation, not this loop's count, ends the run.
            ended = terminated or truncated or step == limit
            if on_step is not None:
                on_step(env, step, ended)
            if ended:
                break
        result = episode_row(seed, info, actions=step, reward=total)
        results.append(result)
        if on_episode is not None:
            on_episode(result)
    env.close()
    return results
