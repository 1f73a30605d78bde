"""The copy-free step path: the batch writes into arrays allocated once; each face returns
what its semantics need (fresh arrays, or documented views); bad input is refused once,
before any episode moves, with an error naming what was expected and what came."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

from tactile_search import CupboardSearchEnv, CupboardSearchVectorEnv, _core


def started_batch(seeds: list[int], **settings: Any) -> _core.EpisodeBatch:
    """A core batch of ``settings`` with episode ``i`` reset to ``seeds[i]``."""
    batch = _core.EpisodeBatch(_core.EpisodeConfig(**settings), len(seeds))
    batch.reset_many(list(enumerate(seeds)))
    return batch


def test_the_batch_hands_out_its_own_arrays_written_in_place() -> None:
    batch = started_batch([1, 2], map="gpis")
    first = batch.step(np.zeros((2, 3)))
    second = batch.step(np.full((2, 3), 0.5))
    for a, b in zip(first[:5], second[:5], strict=True):
        assert a is b  # the same arrays, overwritten by the next step
    assert first[5] is second[5] and all(v is second[5][k] for k, v in first[5].items())
    assert (second[5]["steps"] == 2).all()


def test_the_vector_env_copies_by_default_and_aliases_on_request() -> None:
    copying = CupboardSearchVectorEnv(num_envs=2, map="none")
    copying.reset(seed=0)
    obs, rewards, _, _, info = copying.step(np.zeros((2, 3)))
    kept = (obs["proprio"].copy(), rewards.copy(), info["steps"].copy())
    copying.step(np.ones((2, 3)))
    np.testing.assert_array_equal(obs["proprio"], kept[0])
    np.testing.assert_array_equal(rewards, kept[1])
    np.testing.assert_array_equal(info["steps"], kept[2])
    aliasing = CupboardSearchVectorEnv(num_envs=2, map="none", copy=False)
    aliasing.reset(seed=0)
    obs, *_ = aliasing.step(np.zeros((2, 3)))
    again, *_ = aliasing.step(np.zeros((2, 3)))
    assert obs["proprio"] is again["proprio"]


def test_the_sb3_vec_env_keeps_the_previous_observation_intact() -> None:
    pytest.importorskip("stable_baselines3")
    from tactile_search.envs.sb3_vec_env import CupboardSearchSb3VecEnv

    env = CupboardSearchSb3VecEnv(num_envs=2, seed=0)
    previous = env.reset()
    kept = {k: v.copy() for k, v in previous.items()}
    env.step(np.ones((2, 3), dtype=np.float32))
    for key in kept:
        np.testing.assert_array_equal(previous[key], kept[key])


def test_reset_of_one_episode_rewrites_only_its_rows() -> None:
    batch = started_batch([1, 2, 3], map="gpis")
    batch.step(np.full((3, 3), 0.5))
    maps, proprio = batch.observe()
    before = (maps.copy(), proprio.copy())
    batch.reset(1, 42)
    np.testing.assert_array_equal(maps[[0, 2]], before[0][[0, 2]])
    np.testing.assert_array_equal(proprio[[0, 2]], before[1][[0, 2]])
    fresh = started_batch([42], map="gpis")
    np.testing.assert_array_equal(maps[1], fresh.observe()[0][0])
    assert batch.info(1)["steps"] == 0 and batch.info(0)["steps"] == 1


@pytest.mark.parametrize(
    ("actions", "message"),
    [
        (np.zeros((3,)), r"actions must have shape \(2, 3\), got shape \(3,\)"),
        (np.zeros((2, 4), dtype=np.float32), r"shape \(2, 3\), got shape \(2, 4\)"),
        ([[0, 0, 0], [0, np.nan, 0]], r"episode 1: action\[1\] must be finite, got NaN"),
        (np.array([[0, 0, 0], [np.inf, 0, 0]], np.float32), r"episode 1: action\[0\]"),
        ([[0, 0, 0], "abc"], "numeric"),
        ("left", TypeError),
        (0.5, TypeError),
        ({"dx": 0}, TypeError),
    ],
)
def test_bad_vector_actions_raise_before_any_episode_moves(actions: object, message: Any) -> None:
    vector = CupboardSearchVectorEnv(num_envs=2, map="none")
    vector.reset(seed=0)
    error, message = (
        (message, "actions must be an array") if message is TypeError else (ValueError, message)
    )
    with pytest.raises(error, match=message):
        vector.step(actions)
    _, _, _, _, info = vector.step(np.zeros((2, 3)))
    assert (info["steps"] == 1).all()  # the refused step moved nothing


def test_bad_resets_raise_type_errors_naming_what_came() -> None:
    batch = started_batch([1, 2], map="none")
    with pytest.raises(TypeError, match="resets must be a list of"):
        batch.step(np.zeros((2, 3)), resets=5)
    with pytest.raises(IndexError, match=r"episode index must be from 0 to 1, got 7"):
        batch.reset_many([(7, 1)])


def test_float32_and_float64_actions_step_alike() -> None:
    a = CupboardSearchEnv(map="none")
    b = CupboardSearchEnv(map="none")
    a.reset(seed=4)
    b.reset(seed=4)
    action = np.array([0.3, -0.7, 0.1], dtype=np.float32)
    obs_a, *_ = a.step(action)
    obs_b, *_ = b.step(action.astype(np.float64))
    np.testing.assert_array_equal(obs_a["proprio"], obs_b["proprio"])
