"""Closed after use: the vector env and the SB3 VecEnv refuse ``reset`` and stepping after
``close()`` (gymnasium's ``ClosedEnvironmentError``, as its ``AsyncVectorEnv`` raises),
and ``close()`` itself may be called again."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.error import ClosedEnvironmentError

from tactile_search import ENV_ID, CupboardSearchVectorEnv


def test_a_closed_vector_env_refuses_reset_and_step() -> None:
    vector = CupboardSearchVectorEnv(num_envs=2, map="none")
    vector.reset(seed=0)
    actions = vector.action_space.sample()
    vector.step(actions)
    assert not vector.closed
    vector.close()
    assert vector.closed
    with pytest.raises(ClosedEnvironmentError, match="CupboardSearchVectorEnv is closed"):
        vector.step(actions)
    with pytest.raises(ClosedEnvironmentError, match="make a new one"):
        vector.reset(seed=0)
    vector.close()  # idempotent
    assert vector.closed


def test_a_closed_vector_env_made_by_gymnasium_refuses_step_through_its_wrappers() -> None:
    vector = gym.make_vec(ENV_ID, num_envs=2, vectorization_mode="vector_entry_point", map="none")
    vector.reset(seed=0)
    vector.close()
    assert vector.closed and vector.unwrapped.closed
    with pytest.raises(ClosedEnvironmentError):
        vector.step(vector.action_space.sample())
    vector.close()


def test_a_new_vector_env_steps_after_another_was_closed() -> None:
    CupboardSearchVectorEnv(num_envs=2, map="none").close()
    vector = CupboardSearchVectorEnv(num_envs=2, map="none")
    vector.reset(seed=0)
    vector.step(vector.action_space.sample())
    vector.close()


def test_a_closed_sb3_vec_env_refuses_reset_and_stepping() -> None:
    pytest.importorskip("stable_baselines3")
    from tactile_search.envs.sb3_vec_env import CupboardSearchSb3VecEnv

    env = CupboardSearchSb3VecEnv(num_envs=2, seed=0, map="none")
    env.reset()
    actions = np.stack([env.action_space.sample() for _ in range(env.num_envs)])
    env.step(actions)
    assert not env.closed
    env.close()
    assert env.closed
    message = "CupboardSearchSb3VecEnv is closed"
    with pytest.raises(ClosedEnvironmentError, match=message):
        env.step(actions)
    with pytest.raises(ClosedEnvironmentError, match=message):
        env.step_async(actions)
    with pytest.raises(ClosedEnvironmentError, match=message):
        env.step_wait()
    with pytest.raises(ClosedEnvironmentError, match=message):
        env.reset()
    with pytest.raises(ClosedEnvironmentError, match=message):
        env.env_method("reset", indices=[1])  # one episode's reset, as SB3 reaches it
    env.close()  # idempotent
    assert env.closed


def test_an_sb3_vec_env_closed_between_step_async_and_step_wait_refuses_the_wait() -> None:
    pytest.importorskip("stable_baselines3")
    from tactile_search.envs.sb3_vec_env import CupboardSearchSb3VecEnv

    env = CupboardSearchSb3VecEnv(num_envs=2, seed=0, map="none")
    env.reset()
    env.step_async(np.stack([env.action_space.sample() for _ in range(env.num_envs)]))
    env.close()
    with pytest.raises(ClosedEnvironmentError):
        env.step_wait()
