"""The time limit has one source: the episode's ``max_steps``, reported by the core as
``truncated``; what ``gymnasium.make(..., max_steps=N)`` says is what truncates, and the made
env's ``spec.max_episode_steps`` declares it, with no second, different limit: ``make`` of an
id adds no ``TimeLimit``. (Gymnasium's conventions for every id, ``make`` of a made env's
spec, ``make_vec`` of a spec and ``max_episode_steps``: ``test_gymnasium_conventions.py``.)"""

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
        assert truncated == (step == max_steps), step
        assert "truncated" not in info  # the step's own flag, not repeated in the info
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
        == _core.EpisodeConfig().as_dict()["max_steps"]
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
        assert (truncated == (step == max_steps)).all() and "truncated" not in info
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


@pytest.mark.parametrize("max_steps", [None, 7])
def test_the_made_envs_spec_declares_the_episodes_limit_and_adds_no_second_one(
    max_steps: int | None,
) -> None:
    settings = {} if max_steps is None else {"max_steps": max_steps}
    expected = max_steps or _core.EpisodeConfig().as_dict()["max_steps"]
    env = gym.make(ENV_ID, map="none", **settings)
    assert env.spec.max_episode_steps == env.unwrapped.spec.max_episode_steps == expected
    assert gym.spec(ENV_ID).max_episode_steps is None  # so make adds no TimeLimit
    wrapper = env
    while isinstance(wrapper, gym.Wrapper):
        assert not isinstance(wrapper, gym.wrappers.TimeLimit)
        wrapper = wrapper.env
    vector = gym.make_vec(
        ENV_ID, num_envs=2, vectorization_mode="vector_entry_point", map="none", **settings
    )
    assert vector.spec.max_episode_steps == expected


def test_time_aware_observation_reads_the_declared_limit() -> None:
    env = gym.wrappers.TimeAwareObservation(
        gym.make(ENV_ID, map="none", max_steps=4), flatten=False, normalize_time=True
    )
    obs, _ = env.reset(seed=0)
    assert env.max_timesteps == 4 and float(np.asarray(obs["time"]).item()) == 0.0
    for _ in range(4):
        obs, _, _, truncated, _ = env.step(np.zeros(3))
    assert truncated and float(np.asarray(obs["time"]).item()) == 1.0


def test_max_episode_steps_names_max_steps_and_must_agree_with_it() -> None:
    vector = CupboardSearchVectorEnv(num_envs=1, threads=1, map="none", max_episode_steps=5)
    assert vector.config.max_steps == 5
    vector.close()
    same = CupboardSearchVectorEnv(
        num_envs=1, threads=1, map="none", max_episode_steps=5, max_steps=5
    )
    assert same.config.max_steps == 5
    same.close()
    with pytest.raises(ValueError, match=r"max_episode_steps \(5\) and max_steps \(6\)"):
        CupboardSearchVectorEnv(num_envs=1, map="none", max_episode_steps=5, max_steps=6)
    with pytest.raises(TypeError, match="max_episode_steps must be an integer"):
        CupboardSearchVectorEnv(num_envs=1, map="none", max_episode_steps="5")
    with pytest.raises(ValueError, match="max_episode_steps must be at least 1"):
        CupboardSearchVectorEnv(num_envs=1, map="none", max_episode_steps=0)
