"""The seam between Python and the core runs one way: settings are checked once, into a
config the core keeps; making an env starts no episode; a bad setting raises the same
exception on every path; the SB3 adapter steps and starts ended episodes over in one call;
rendering draws what the core hands it."""

from __future__ import annotations

import pickle
from typing import Any

import gymnasium as gym
import numpy as np
import pytest

from tactile_search import ENV_ID, CupboardSearchEnv, CupboardSearchVectorEnv, _core
from tactile_search.envs.config import CupboardSearchConfig, config_for


def test_a_new_batch_starts_no_episode_and_a_reset_starts_one() -> None:
    batch = _core.EpisodeBatch(_core.EpisodeConfig(map="none"), 2)
    _, proprio = batch.observe()
    assert not proprio.any()
    with pytest.raises(ValueError, match="episode 0: the episode has not started"):
        batch.step(np.zeros((2, 3)))
    with pytest.raises(RuntimeError, match="call reset"):
        batch.render_state(1)
    batch.reset(1, 7)
    assert batch.render_state(1)["jars"]
    with pytest.raises(RuntimeError, match="episode 0 has not started"):
        batch.render_state(0)


def test_making_an_env_or_a_vector_env_starts_no_episode() -> None:
    for env in (CupboardSearchEnv(map="none"), CupboardSearchVectorEnv(num_envs=3, map="none")):
        with pytest.raises(RuntimeError, match="has not started"):
            env._batch.render_state(0)


def test_the_batch_keeps_the_checked_config_it_was_given() -> None:
    config = _core.EpisodeConfig(map="occupancy", jar_count=4)
    assert _core.EpisodeBatch(config, 1).config == config
    assert hash(config) == hash(_core.EpisodeConfig({"map": "occupancy", "jar_count": (4, 4)}))
    assert pickle.loads(pickle.dumps(config)) == config
    assert config != _core.EpisodeConfig()
    env_config = config_for("CupboardSearchEnv", {"map": "occupancy", "jar_count": 4})
    assert env_config == CupboardSearchConfig(map="occupancy", jar_count=4)
    assert env_config.core == config
    with pytest.raises(TypeError, match="an EpisodeConfig"):
        _core.EpisodeBatch({"map": "none"}, 1)
    with pytest.raises(ValueError, match="num_envs must be a positive int, got 0"):
        _core.EpisodeBatch(config, 0)


def _sb3_vec_env(**settings: Any) -> Any:
    pytest.importorskip("stable_baselines3")
    from tactile_search.envs.sb3_vec_env import CupboardSearchSb3VecEnv

    return CupboardSearchSb3VecEnv(num_envs=2, **settings)


MAKERS = {
    "EpisodeConfig": lambda **kw: _core.EpisodeConfig(**kw),
    "CupboardSearchConfig": lambda **kw: CupboardSearchConfig(**kw),
    "CupboardSearchEnv": lambda **kw: CupboardSearchEnv(**kw),
    "CupboardSearchVectorEnv": lambda **kw: CupboardSearchVectorEnv(num_envs=2, **kw),
    "gym.make": lambda **kw: gym.make(ENV_ID, **kw),
    "gym.make_vec": lambda **kw: gym.make_vec(
        ENV_ID, num_envs=2, vectorization_mode="vector_entry_point", **kw
    ),
    "CupboardSearchSb3VecEnv": _sb3_vec_env,
}


@pytest.mark.parametrize("make", MAKERS.values(), ids=MAKERS.keys())
@pytest.mark.parametrize(
    ("settings", "error", "words"),
    [
        ({"max_step": 5}, TypeError, "unexpected keyword argument 'max_step'"),
        ({"max_steps": 2.5}, TypeError, "max_steps must be"),
        ({"max_steps": 0}, ValueError, "max_steps must be"),
        ({"map": "sonar"}, ValueError, "map must be one of"),
    ],
)
def test_a_bad_setting_raises_the_same_exception_on_every_path(
    make: Any, settings: dict, error: type, words: str
) -> None:
    with pytest.raises(error) as raised:
        make(**settings)
    assert type(raised.value) is error
    assert words in str(raised.value)


def test_an_unknown_scene_setting_is_a_type_error_in_the_scene_too() -> None:
    with pytest.raises(TypeError, match="unexpected keyword argument 'cupboard_wdth'"):
        _core.Scene(0, cupboard_wdth=0.5)


def test_the_sb3_step_in_one_call_equals_a_step_then_the_resets() -> None:
    """``step_autoreset`` against the same batch driven by ``step`` and ``reset_many``: the
    same observations, rewards, dones, infos and terminal observations."""
    config = _core.EpisodeConfig(map="gpis", max_steps=6)
    one_call, reference = _core.EpisodeBatch(config, 3), _core.EpisodeBatch(config, 3)
    for batch in (one_call, reference):
        batch.reset_many([(0, 1), (1, 2), (2, 3)])
    rng = np.random.default_rng(0)
    next_seed = iter(range(100, 10_000))
    ended_count = 0
    for step in range(14):
        actions = rng.uniform(-1, 1, (3, 3))
        seeds = [next(next_seed) for _ in range(3)]
        observation, rewards, dones, infos = one_call.step_autoreset(actions, seeds)
        maps, proprio, ref_rewards, terminated, truncated, _ = reference.step(actions)
        ref_infos = reference.infos()
        np.testing.assert_array_equal(rewards, ref_rewards.astype(np.float32))
        np.testing.assert_array_equal(dones, terminated | truncated)
        ended = np.flatnonzero(dones).tolist()
        for index, info in enumerate(infos):
            terminal = info.pop("terminal_observation", None)
            if index in ended:
                np.testing.assert_array_equal(terminal["map"], maps[index])
                np.testing.assert_array_equal(terminal["proprio"], proprio[index])
                assert info.pop("TimeLimit.truncated") == truncated[index]
                assert info.pop("is_success") == ref_infos[index]["success"]
            assert info == ref_infos[index], (step, index)
        if ended:
            reference.reset_many(list(zip(ended, seeds, strict=False)))
            ended_count += len(ended)
        ref_maps, ref_proprio = reference.observe()
        np.testing.assert_array_equal(observation["map"], ref_maps)
        np.testing.assert_array_equal(observation["proprio"], ref_proprio)
    assert ended_count >= 3, "the time limit ends every episode at least once"


def test_the_sb3_step_refuses_a_wrong_count_of_seeds() -> None:
    batch = _core.EpisodeBatch(_core.EpisodeConfig(map="none"), 2)
    batch.reset_many([(0, 1), (1, 2)])
    with pytest.raises(ValueError, match=r"seeds must be 2 seeds \(one per episode\), got 1"):
        batch.step_autoreset(np.zeros((2, 3)), [5])
    with pytest.raises(TypeError, match="seeds must be a sequence of ints"):
        batch.step_autoreset(np.zeros((2, 3)), 5)


@pytest.mark.parametrize("mode", ["gpis", "occupancy", "none"])
def test_render_state_hands_jars_by_shape_the_map_by_name_and_the_jars_pixels(mode) -> None:
    env = CupboardSearchEnv(map=mode)
    env.reset(seed=1_000_001)
    state = env._batch.render_state(0, 500.0, 0.15)
    assert {jar["shape"] for jar in state["jars"]} <= {"round", "square"}
    channels = {"gpis": ["mean", "std"], "occupancy": ["occupancy"], "none": []}[mode]
    assert list(state["map"]) == channels
    (x0, x1), (y0, y1) = state["bounds"]
    pixels = state["jar_pixels"]
    assert pixels.shape == (round((y1 - y0 + 0.15) * 500), round((x1 - x0) * 500))
    jars = {
        "shapes": [jar["shape"] for jar in state["jars"]],
        "positions": [[jar["x"], jar["y"]] for jar in state["jars"]],
        "half_widths": [jar["half_width"] for jar in state["jars"]],
        "yaws": [jar["yaw"] for jar in state["jars"]],
    }
    scene_bounds = ((x0, x1), (y0 - 0.15, y1))
    truth = np.flipud(_core.footprint_mask(jars, scene_bounds, pixels.shape))
    np.testing.assert_array_equal(pixels >= 0, truth)
    assert set(np.unique(pixels)) <= {-1, *range(len(state["jars"]))}
