"""The gymnasium face: checkers, determinism, pickling, finiteness, solvability, bad input."""

from __future__ import annotations

import pickle

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import tactile_search  # registers the environments
from tactile_search import CupboardSearchEnv, CupboardSearchVectorEnv
from tactile_search.envs.config import MAP_MODES

ENV_ID = "tactile_search/CupboardSearch-v0"
MODES = list(MAP_MODES)


@pytest.mark.parametrize("mode", MODES)
def test_gymnasium_env_checker_passes(mode: str) -> None:
    env = gym.make(ENV_ID, map=mode)
    check_env(env.unwrapped, skip_render_check=True)
    env.close()


@pytest.mark.parametrize("env_id", tactile_search.ENV_IDS)
@pytest.mark.parametrize("action_mode", ["wrist", "probe"])
def test_every_registered_id_passes_the_env_checker(env_id: str, action_mode: str) -> None:
    env = gym.make(env_id, action_mode=action_mode)
    check_env(env.unwrapped, skip_render_check=True)
    env.close()


@pytest.mark.parametrize("mode", MODES)
def test_stable_baselines3_env_checker_passes(mode: str) -> None:
    sb3_checker = pytest.importorskip("stable_baselines3.common.env_checker")
    sb3_checker.check_env(CupboardSearchEnv(map=mode), warn=True)


def test_registered_without_a_second_time_limit() -> None:
    env = gym.make(ENV_ID)
    assert gym.spec(ENV_ID).max_episode_steps is None  # make adds no TimeLimit wrapper
    assert env.spec.max_episode_steps == env.unwrapped.config.max_steps  # the one limit
    obs, _ = env.reset(seed=0)
    assert obs["map"].shape == (2, 40, 80) and obs["map"].dtype == np.uint8
    assert obs["proprio"].shape == (11,) and obs["proprio"].dtype == np.float32


def rollout(env: gym.Env, seed: int, steps: int) -> list:
    obs, _ = env.reset(seed=seed)
    rng = np.random.default_rng(seed)
    trace = [obs]
    for _ in range(steps):
        obs, reward, terminated, truncated, info = env.step(rng.uniform(-1, 1, 3))
        trace.append((obs, reward, info))
        if terminated or truncated:
            break
    return trace


def assert_same(a: object, b: object) -> None:
    if isinstance(a, dict):
        assert a.keys() == b.keys()
        for key in a:
            assert_same(a[key], b[key])
    elif isinstance(a, list | tuple):
        assert len(a) == len(b)
        for x, y in zip(a, b, strict=True):
            assert_same(x, y)
    elif isinstance(a, np.ndarray):
        np.testing.assert_array_equal(a, b)
    else:
        assert a == b


@pytest.mark.parametrize("mode", MODES)
def test_same_seed_same_actions_give_identical_rollouts(mode: str) -> None:
    first = rollout(gym.make(ENV_ID, map=mode), seed=3, steps=30)
    second = rollout(gym.make(ENV_ID, map=mode), seed=3, steps=30)
    assert_same(first, second)


def test_vector_env_matches_single_envs() -> None:
    vector = gym.make_vec(ENV_ID, num_envs=2, vectorization_mode="vector_entry_point")
    singles = [gym.make(ENV_ID) for _ in range(2)]
    obs, _ = vector.reset(seed=[11, 12])
    for index, env in enumerate(singles):
        single_obs, _ = env.reset(seed=[11, 12][index])
        np.testing.assert_array_equal(single_obs["map"], obs["map"][index])
    rng = np.random.default_rng(0)
    for _ in range(20):
        actions = rng.uniform(-1, 1, (2, 3))
        obs, rewards, terminated, _, infos = vector.step(actions)
        for index, env in enumerate(singles):
            single_obs, reward, done, _, info = env.step(actions[index])
            np.testing.assert_array_equal(single_obs["map"], obs["map"][index])
            np.testing.assert_array_equal(single_obs["proprio"], obs["proprio"][index])
            assert reward == rewards[index] and done == terminated[index]
            assert info["iou"] == infos["iou"][index]
        if terminated.any():
            break


def test_vector_env_autoresets_on_the_next_step() -> None:
    vector = CupboardSearchVectorEnv(num_envs=2, max_steps=5)
    vector.reset(seed=0)
    for _ in range(5):
        _, _, terminated, truncated, _ = vector.step(np.zeros((2, 3)))
    assert truncated.all() and not terminated.any()
    _, rewards, terminated, truncated, infos = vector.step(np.ones((2, 3)))
    assert (rewards == 0).all() and not terminated.any() and not truncated.any()
    assert (infos["steps"] == 0).all()
    _, _, _, _, infos = vector.step(np.zeros((2, 3)))
    assert (infos["steps"] == 1).all()


def test_pickle_round_trip_builds_an_equal_env() -> None:
    env = CupboardSearchEnv(map="occupancy", grid_shape=(36, 72), reward_step_cost=0.02)
    clone = pickle.loads(pickle.dumps(env))
    assert clone.config == env.config
    assert_same(rollout(env, 5, 10), rollout(clone, 5, 10))


def test_ten_thousand_random_steps_are_always_finite() -> None:
    vector = CupboardSearchVectorEnv(num_envs=4)
    vector.reset(seed=7)
    rng = np.random.default_rng(1)
    for _ in range(2500):  # 4 envs: 10,000 steps over many autoreset episodes
        obs, rewards, _, _, infos = vector.step(rng.uniform(-2, 2, (4, 3)))
        assert np.all(np.isfinite(rewards))
        assert np.all(np.isfinite(obs["proprio"])) and np.all(np.abs(obs["proprio"]) <= 1)
        for key, values in infos.items():
            assert np.all(np.isfinite(np.asarray(values, dtype=np.float64))), key


def test_the_oracle_solves_at_least_95_percent_of_100_seeds_without_tipping() -> None:
    env = CupboardSearchEnv()
    successes = 0
    for seed in range(100):
        env.reset(seed=seed)
        for _ in range(200):
            _, _, terminated, _, info = env.step(env.oracle_action())
            if terminated:
                successes += info["success"] and not info["tipped"]
                break
    assert successes >= 95


@pytest.mark.parametrize(
    ("kwargs", "error", "message"),
    [
        ({"map": "voxels"}, ValueError, "map must be one of"),
        ({"grid_shape": (40, 60)}, ValueError, "square cells"),
        ({"grid_shape": (20, 40)}, ValueError, r"grid_shape must be an int from 36 to \d+, got 20"),
        ({"grid_shape": 40}, TypeError, "grid_shape must be a pair of ints"),
        ({"reward_step_cost": -1.0}, ValueError, r"reward_step_cost must be >= 0, got -1"),
        ({"prior_mean": float("nan")}, ValueError, "prior_mean must be finite"),
        (
            {"finger_stiffness": 0},
            ValueError,
            r"finger_stiffness must be from 0.000001 to 1000000, got 0",
        ),
        ({"depth_noise_std": "big"}, TypeError, "depth_noise_std must be a float"),
        ({"max_steps": 0}, ValueError, r"max_steps must be an int >= 1, got 0"),
        ({"no_such_key": 1}, TypeError, "no_such_key"),
        ({"render_mode": "human"}, ValueError, "render_mode"),
    ],
)
def test_bad_constructor_arguments_raise_naming_them(
    kwargs: dict, error: type[Exception], message: str
) -> None:
    with pytest.raises(error, match=message):
        CupboardSearchEnv(**kwargs)


@pytest.mark.parametrize(
    ("action", "message"),
    [
        ([np.nan, 0.0, 0.0], "finite"),
        ([np.inf, 0.0, 0.0], "finite"),
        ([0.0, 0.0], r"shape \(3,\)"),
        ("left", "numeric"),
    ],
)
def test_bad_actions_raise_value_error(action: object, message: str) -> None:
    env = CupboardSearchEnv()
    env.reset(seed=0)
    with pytest.raises(ValueError, match=message):
        env.step(action)


@pytest.mark.parametrize("mode", MODES)
def test_render_draws_the_scene_beside_the_map_and_writes_a_gif(mode: str, tmp_path) -> None:
    pytest.importorskip("matplotlib")
    from tactile_search.render import save_gif

    env = CupboardSearchEnv(map=mode, render_mode="rgb_array")
    env.reset(seed=1)
    frames = [env.render()]
    env.step(env.oracle_action())
    frames.append(env.render())
    assert frames[0].dtype == np.uint8 and frames[0].ndim == 3 and frames[0].shape[2] == 3
    panels = {"gpis": 3, "occupancy": 2, "none": 1}[mode]
    assert frames[0].shape[1] > 250 * panels
    path = save_gif(frames, tmp_path / "episode.gif")
    assert path.stat().st_size > 1000
    # Without a render mode: gymnasium's convention, a warning and None.
    with pytest.warns(UserWarning, match="render mode"):
        assert CupboardSearchEnv(map=mode).render() is None


class SeedSpy:
    """A vector env's batch that records the layout seeds its episodes are reset with."""

    def __init__(self, batch) -> None:
        self.batch = batch
        self.seeds: list[int] = []

    def reset_many(self, pairs):
        self.seeds += [seed for _, seed in pairs]
        return self.batch.reset_many(pairs)

    def step(self, actions, resets):
        self.seeds += [seed for _, seed in resets or []]
        return self.batch.step(actions, resets)

    def __getattr__(self, name: str):
        return getattr(self.batch, name)


def drawn_layout_seeds(env: CupboardSearchVectorEnv, seed: int, steps: int) -> list[int]:
    spy = SeedSpy(env._batch)
    env._batch = spy
    env.reset(seed=seed)
    for _ in range(steps):
        env.step(np.ones((env.num_envs, 3), dtype=np.float32))
    return spy.seeds


def test_vector_env_draws_every_layout_from_its_layout_range() -> None:
    low, high = 2**32, 2**63
    env = CupboardSearchVectorEnv(num_envs=3, map="none", max_steps=4, layout_seeds=(low, high))
    seeds = drawn_layout_seeds(env, seed=7, steps=20)
    assert len(seeds) == 3 + 3 * 4  # the first episodes, then an autoreset every 5th step
    assert all(low <= s < high for s in seeds)
    narrow = CupboardSearchVectorEnv(num_envs=2, map="none", max_steps=2, layout_seeds=(10, 13))
    assert set(drawn_layout_seeds(narrow, seed=0, steps=30)) == {10, 11, 12}


def test_vector_env_default_layout_range_seeds_each_sub_env_as_the_single_env() -> None:
    # reset(seed=5): sub-env i is the single env reset with seed 5 + i (layout 5 + i), and
    # its next episode's layout comes from its own generator, seeded 5 + i.
    env = CupboardSearchVectorEnv(num_envs=3, map="none", max_steps=1)
    drawn = drawn_layout_seeds(env, seed=5, steps=2)
    expected = [int(gym.utils.seeding.np_random(5 + i)[0].integers(0, 2**63)) for i in range(3)]
    assert drawn == [5, 6, 7, *expected]


def test_vector_env_seed_outside_a_narrow_layout_range_seeds_the_draw() -> None:
    env = CupboardSearchVectorEnv(num_envs=2, map="none", layout_seeds=(2**32, 2**63))
    drawn = drawn_layout_seeds(env, seed=5, steps=0)
    expected = [int(gym.utils.seeding.np_random(5 + i)[0].integers(2**32, 2**63)) for i in range(2)]
    assert drawn == expected
    inside = drawn_layout_seeds(env, seed=2**40, steps=0)
    assert inside == [2**40, 2**40 + 1]


@pytest.mark.parametrize(
    ("layout_seeds", "error"),
    [((5, 5), ValueError), ((-1, 3), ValueError), ((0, 2**64 + 1), ValueError), ("ab", TypeError)],
)
def test_vector_env_refuses_a_bad_layout_range(layout_seeds, error) -> None:
    with pytest.raises(error, match="layout_seeds"):
        CupboardSearchVectorEnv(num_envs=1, map="none", layout_seeds=layout_seeds)


def test_a_raw_env_stepped_before_reset_raises() -> None:
    from gymnasium.error import ResetNeeded

    env = CupboardSearchEnv()
    with pytest.raises(ResetNeeded, match="call reset"):
        env.step(np.zeros(3))
    env.reset(seed=0)
    env.step(np.zeros(3))


def test_the_sb3_vec_env_without_sb3_names_the_extra(monkeypatch: pytest.MonkeyPatch) -> None:
    import importlib
    import sys

    for name in [m for m in sys.modules if m.split(".")[0] == "stable_baselines3"]:
        monkeypatch.setitem(sys.modules, name, None)  # as if not installed
    monkeypatch.setitem(sys.modules, "stable_baselines3", None)
    monkeypatch.delitem(sys.modules, "tactile_search.envs.sb3_vec_env", raising=False)
    with pytest.raises(ModuleNotFoundError, match=r"pip install 'tactile_search\[agents\]'"):
        importlib.import_module("tactile_search.envs.sb3_vec_env")
