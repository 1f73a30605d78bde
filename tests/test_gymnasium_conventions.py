"""Gymnasium's conventions for the time limit hold for every registered id, with one limit,
the episode's ``max_steps`` (``tactile_search/envs/time_limit.py``):

- ``gymnasium.make`` wraps a ``TimeLimit`` exactly when the spec it makes from declares a
  limit, and at the env's own ``max_steps``;
- ``gymnasium.make_vec`` re-makes a vector env from its own spec and from a single env's;
- ``make(id, max_episode_steps=N)`` and ``make(id, max_steps=N)`` make the same env and the
  same episodes, in every vectorization mode too; given both, they must agree.
"""

from __future__ import annotations

from typing import Any

import gymnasium as gym
import numpy as np
import pytest

import tactile_search
from tactile_search import CupboardSearchVectorEnv

#: Cheap settings over each id's own (the time limit does not depend on the map).
CHEAP: dict[str, Any] = {"map": "none", "threads": 1}


def time_limits(env: gym.Env) -> list[int]:
    """The limits of the ``TimeLimit`` wrappers around ``env``, outermost first."""
    limits = []
    while isinstance(env, gym.Wrapper):
        if isinstance(env, gym.wrappers.TimeLimit):
            limits.append(env._max_episode_steps)
        env = env.env
    return limits


def still_action(space: gym.Space) -> np.ndarray:
    """An action that moves nothing and claims nothing (zeros): only the time limit can end
    the episode."""
    return np.zeros(space.shape, dtype=space.dtype)


def episode(env: gym.Env, steps: int) -> tuple[list[np.ndarray], list[bool]]:
    """The proprio vectors (with ``time_left``, which reads ``max_steps``) and truncation
    flags of ``steps`` still steps from ``reset(seed=5)``."""
    observation, _ = env.reset(seed=5)
    proprio, truncations = [observation["proprio"]], []
    for _ in range(steps):
        observation, _, terminated, truncated, _ = env.step(still_action(env.action_space))
        assert not terminated
        proprio.append(observation["proprio"])
        truncations.append(bool(truncated))
    return proprio, truncations


@pytest.mark.parametrize("env_id", tactile_search.ENV_IDS)
@pytest.mark.parametrize("max_steps", [None, 7])
def test_make_wraps_a_time_limit_exactly_when_the_spec_declares_one_at_the_envs_own_limit(
    env_id: str, max_steps: int | None
) -> None:
    settings = {} if max_steps is None else {"max_steps": max_steps}
    made = gym.make(env_id, **CHEAP, **settings)
    remade = gym.make(made.spec)  # the made env's spec declares its limit
    for spec, env in ((gym.spec(env_id), made), (made.spec, remade)):
        declared = [] if spec.max_episode_steps is None else [spec.max_episode_steps]
        assert time_limits(env) == declared
        assert env.spec.max_episode_steps == env.unwrapped.config.max_steps
    limit = made.unwrapped.config.max_steps
    assert remade.unwrapped.config.max_steps == limit == (max_steps or limit)
    assert time_limits(remade) == [limit]
    _, truncations = episode(remade, limit)
    assert truncations.index(True) == limit - 1
    made.close()
    remade.close()


@pytest.mark.parametrize("env_id", tactile_search.ENV_IDS)
def test_make_vec_remakes_a_vector_env_from_its_own_spec(env_id: str) -> None:
    vector = gym.make_vec(
        env_id, num_envs=2, vectorization_mode="vector_entry_point", **CHEAP, max_steps=7
    )
    again = gym.make_vec(vector.spec)
    # Its spec now carries the limit in its kwargs as max_episode_steps, too.
    third = gym.make_vec(again.spec)
    first, _ = vector.reset(seed=3)
    for remade in (again, third):
        assert isinstance(remade.unwrapped, CupboardSearchVectorEnv)
        assert remade.num_envs == 2
        assert remade.unwrapped.config == vector.unwrapped.config
        assert remade.spec.max_episode_steps == vector.spec.max_episode_steps == 7
        second, _ = remade.reset(seed=3)
        for key in first:
            np.testing.assert_array_equal(first[key], second[key])
        remade.close()
    vector.close()


@pytest.mark.parametrize("env_id", tactile_search.ENV_IDS)
@pytest.mark.parametrize("mode", ["vector_entry_point", "sync"])
def test_make_vec_makes_the_vector_env_of_a_single_envs_spec(env_id: str, mode: str) -> None:
    env = gym.make(env_id, **CHEAP, max_steps=7)
    vector = gym.make_vec(env.spec, num_envs=2, vectorization_mode=mode)
    assert vector.num_envs == 2 and vector.spec.max_episode_steps == 7
    if mode == "vector_entry_point":
        assert isinstance(vector.unwrapped, CupboardSearchVectorEnv)
        assert vector.unwrapped.config == env.unwrapped.config
    else:
        for sub_env in vector.unwrapped.envs:
            assert sub_env.unwrapped.config == env.unwrapped.config
            assert time_limits(sub_env) == [7]
    env.close()
    vector.close()


@pytest.mark.parametrize("env_id", tactile_search.ENV_IDS)
@pytest.mark.parametrize("limit", [3, 9])
def test_max_episode_steps_and_max_steps_make_the_same_env_and_episodes(
    env_id: str, limit: int
) -> None:
    by_gymnasium = gym.make(env_id, **CHEAP, max_episode_steps=limit)
    by_setting = gym.make(env_id, **CHEAP, max_steps=limit)
    assert time_limits(by_gymnasium) == [limit]  # gymnasium's wrapper, at the env's limit
    episodes = []
    for env in (by_gymnasium, by_setting):
        assert env.unwrapped.config.max_steps == limit
        assert env.spec.max_episode_steps == env.unwrapped.spec.max_episode_steps == limit
        proprio, truncations = episode(env, limit + 2)
        assert truncations.index(True) == limit - 1
        episodes.append((proprio, truncations))
        env.close()
    (proprio, truncations), (proprio_again, truncations_again) = episodes
    assert truncations == truncations_again
    np.testing.assert_array_equal(np.stack(proprio), np.stack(proprio_again))


@pytest.mark.parametrize("env_id", tactile_search.ENV_IDS)
@pytest.mark.parametrize("mode", ["vector_entry_point", "sync"])
def test_every_vectorization_mode_takes_max_episode_steps_as_max_steps(
    env_id: str, mode: str
) -> None:
    vector = gym.make_vec(env_id, num_envs=2, vectorization_mode=mode, **CHEAP, max_episode_steps=4)
    if mode == "vector_entry_point":
        configs = [vector.unwrapped.config]
    else:
        configs = [sub_env.unwrapped.config for sub_env in vector.unwrapped.envs]
    assert [config.max_steps for config in configs] == [4] * len(configs)
    vector.reset(seed=0)
    actions = np.stack([still_action(vector.single_action_space)] * 2)
    for step in range(1, 5):
        _, _, terminated, truncated, _ = vector.step(actions)
        assert not terminated.any()
        assert (truncated == (step == 4)).all(), step
    vector.close()


@pytest.mark.parametrize("env_id", tactile_search.ENV_IDS)
def test_max_episode_steps_beside_a_different_max_steps_is_a_value_error(env_id: str) -> None:
    conflict = r"max_episode_steps \(5\) and max_steps \(6\)"
    with pytest.raises(ValueError, match=conflict):
        gym.make(env_id, **CHEAP, max_episode_steps=5, max_steps=6)
    for mode in ("vector_entry_point", "sync"):
        with pytest.raises(ValueError, match=conflict):
            gym.make_vec(
                env_id, num_envs=2, vectorization_mode=mode, **CHEAP,
                max_episode_steps=5, max_steps=6,
            )  # fmt: skip
    agreeing = gym.make(env_id, **CHEAP, max_episode_steps=5, max_steps=5)
    assert agreeing.unwrapped.config.max_steps == 5 and time_limits(agreeing) == [5]
    agreeing.close()


def test_a_bad_max_episode_steps_is_refused_naming_it() -> None:
    with pytest.raises(TypeError, match="max_episode_steps must be an integer, got str"):
        gym.make(tactile_search.ENV_ID, **CHEAP, max_episode_steps="5")
    with pytest.raises(ValueError, match="max_episode_steps must be at least 1, got 0"):
        gym.make(tactile_search.ENV_ID, **CHEAP, max_episode_steps=0)


def test_make_without_the_wrapper_keeps_the_episodes_own_limit() -> None:
    """``max_episode_steps=-1`` is gymnasium's "no ``TimeLimit``": the env keeps its own."""
    env = gym.make(tactile_search.ENV_ID, **CHEAP, max_episode_steps=-1, max_steps=6)
    assert time_limits(env) == [] and env.unwrapped.config.max_steps == 6
    assert env.spec.max_episode_steps == 6
    _, truncations = episode(env, 6)
    assert truncations.index(True) == 5
    env.close()
