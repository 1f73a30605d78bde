"""The time limit has one source: the episode's ``max_steps``, reported by the core as
``truncated``; what ``gymnasium.make(..., max_steps=N)`` says is what truncates."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

import tactile_search  # noqa: F401  (registers the environment)
from tactile_search import CupboardSearchVectorEnv, _core

ENV_ID = "tactile_search/CupboardSearch-v0"


@pytest.mark.parametrize("max_steps", [3, 50])
def test_gym_make_max_steps_is_what_truncates_the_single_env(max_steps: int) -> None:
    env = gym.make(ENV_ID, map="none", max_steps=max_steps)
    env.reset(seed=0)
    for step in range(1, max_steps + 1):
        # A still hand touches nothing, so only the time limit can end the episode.
        _, _, terminated, truncated, info = env.step(np.zeros(3))
        assert not terminated
        assert truncated == (step == max_steps) == info["truncated"], step
    env.close()


def test_the_default_time_limit_is_the_cores() -> None:
    env = gym.make(ENV_ID, map="none")
    env.reset(seed=1)
    steps = 0
    truncated = False
    while not truncated:
        _, _, _, truncated, info = env.step(np.zeros(3))
        steps += 1
    assert (
        steps
        == info["steps"]
        == _core.EpisodeBatch.resolve_settings()["max_steps"]
        == env.unwrapped.config.max_steps
    )


@pytest.mark.parametrize("max_steps", [2, 7])
def test_make_vec_max_steps_is_what_truncates_the_vector_env(max_steps: int) -> None:
    vector = gym.make_vec(
        ENV_ID, num_envs=3, vectorization_mode="vector_entry_point", map="none", max_steps=max_steps
    )
    assert isinstance(vector.unwrapped, CupboardSearchVectorEnv)
    vector.reset(seed=0)
    for step in range(1, max_steps + 1):
        _, _, terminated, truncated, info = vector.step(np.zeros((3, 3)))
        assert not terminated.any()
        assert (truncated == (step == max_steps)).all() and (info["truncated"] == truncated).all()
    _, rewards, _, truncated, info = vector.step(np.zeros((3, 3)))  # the autoreset step
    assert not truncated.any() and (info["steps"] == 0).all() and (rewards == 0).all()


def test_the_sb3_vec_env_truncates_at_max_steps() -> None:
    pytest.importorskip("stable_baselines3")
    from tactile_search.envs.sb3_vec_env import CupboardSearchSb3VecEnv

    env = CupboardSearchSb3VecEnv(num_envs=2, seed=0, map="none", max_steps=4)
    env.reset()
    for step in range(1, 5):
        _, _, dones, infos = env.step(np.zeros((2, 3)))
        assert dones.all() == (step == 4) and dones.any() == (step == 4)
    assert all(info["TimeLimit.truncated"] and info["steps"] == 4 for info in infos)
