"""stable-baselines3 trains on the environment with its defaults (the map gets the CNN)."""

from __future__ import annotations

import gymnasium as gym
import pytest

import tactile_search  # noqa: F401  (registers the environment)

sb3 = pytest.importorskip("stable_baselines3")
torch = pytest.importorskip("torch")


def test_ppo_multi_input_policy_trains_with_its_defaults() -> None:
    torch.set_num_threads(1)
    env = gym.make("tactile_search/CupboardSearch-v0")
    model = sb3.PPO("MultiInputPolicy", env, seed=0)
    extractors = model.policy.features_extractor.extractors
    assert isinstance(extractors["map"], sb3.common.torch_layers.NatureCNN)
    model.learn(total_timesteps=256)  # one default rollout of 2048 steps and one update
    assert model.num_timesteps == 2048


def test_sb3_vec_env_is_an_sb3_vec_env_that_ppo_trains_on() -> None:
    torch.set_num_threads(1)
    from stable_baselines3.common.vec_env import VecEnv

    from tactile_search.envs.sb3_vec_env import CupboardSearchSb3VecEnv

    env = CupboardSearchSb3VecEnv(num_envs=2, max_steps=20, seed=0)
    assert isinstance(env, VecEnv)
    model = sb3.PPO("MultiInputPolicy", env, n_steps=32, batch_size=32, n_epochs=1, seed=0)
    model.learn(total_timesteps=64)
    assert model.num_timesteps == 64


def test_sb3_vec_env_resets_in_the_step_that_ends_an_episode() -> None:
    import numpy as np

    from tactile_search.envs.observation import PROPRIO
    from tactile_search.envs.sb3_vec_env import CupboardSearchSb3VecEnv

    time_left = PROPRIO["time_left"]
    env = CupboardSearchSb3VecEnv(num_envs=2, max_steps=3, seed=1, map="none")
    first = env.reset()
    for _ in range(3):
        observation, rewards, dones, infos = env.step(np.zeros((2, 3)))
    assert dones.all() and rewards.dtype == np.float32
    for index in range(2):
        assert infos[index]["TimeLimit.truncated"]
        terminal = infos[index]["terminal_observation"]["proprio"]
        assert terminal[time_left] == 0.0 < first["proprio"][index][time_left]  # time is up
        assert observation["proprio"][index][time_left] == 1.0  # a fresh episode: all left


def test_sb3_vec_env_renders_each_episode_as_vec_video_recorder_reads_it() -> None:
    import numpy as np
    from stable_baselines3.common.vec_env.base_vec_env import tile_images

    from tactile_search.envs.sb3_vec_env import CupboardSearchSb3VecEnv

    env = CupboardSearchSb3VecEnv(num_envs=2, seed=0, render_mode="rgb_array")
    env.reset()
    images = env.get_images()
    single = gym.make("tactile_search/CupboardSearch-v0", render_mode="rgb_array")
    single.reset(seed=int(env.get_attr("layout_seed", indices=1)[0]))
    np.testing.assert_array_equal(images[1], single.render())
    # VecVideoRecorder asserts render_mode == "rgb_array" and records render()'s tiles.
    assert env.render_mode == "rgb_array"
    np.testing.assert_array_equal(env.render(), tile_images(images))
    assert CupboardSearchSb3VecEnv(num_envs=2).get_images() == [None, None]
    with pytest.raises(ValueError, match="render_mode must be None or 'rgb_array'"):
        CupboardSearchSb3VecEnv(num_envs=2, render_mode="human")


def test_sb3_vec_env_methods_reach_only_the_indexed_episodes() -> None:
    import numpy as np

    from tactile_search.envs.sb3_vec_env import CupboardSearchSb3VecEnv

    env = CupboardSearchSb3VecEnv(num_envs=3, seed=0, map="none")
    env.reset()
    for _ in range(2):
        env.step(np.zeros((3, 3)))
    before = env.get_attr("layout_seed")
    ((reset_observation, info),) = env.env_method("reset", seed=77, indices=[1])
    assert reset_observation["proprio"].shape == env.observation_space["proprio"].shape
    assert env.get_attr("layout_seed") == [before[0], 77, before[2]]
    assert info["steps"] == 0
    *_, infos = env.step(np.zeros((3, 3)))
    assert [info["steps"] for info in infos] == [3, 1, 3]
    assert env.get_attr("index", indices=[2, 0]) == [2, 0]
    assert env.env_is_wrapped(gym.Wrapper, indices=1) == [False]
    with pytest.raises(ValueError, match="must set every episode"):
        env.set_attr("render_mode", None, indices=[0])
    with pytest.raises(ValueError, match="indices must be 0 to 2, got 3"):
        env.get_attr("index", indices=[3])


def test_pickled_sb3_vec_env_continues_as_the_original() -> None:
    import pickle

    import numpy as np

    from tactile_search.envs.sb3_vec_env import CupboardSearchSb3VecEnv

    env = CupboardSearchSb3VecEnv(num_envs=3, seed=0, max_steps=5, action_mode="probe")
    env.reset()
    rng = np.random.default_rng(0)

    def actions() -> np.ndarray:
        return rng.integers(0, env.action_space.nvec, size=(3, 3))

    for _ in range(7):  # past an autoreset
        env.step(actions())
    env.env_method("reset", indices=0)  # episodes of different lengths
    env.step(actions())
    copy = pickle.loads(pickle.dumps(env))
    for step in range(8):
        action = actions()
        ours, theirs = copy.step(action), env.step(action)
        for key in theirs[0]:
            np.testing.assert_array_equal(ours[0][key], theirs[0][key], err_msg=f"{step}")
        np.testing.assert_array_equal(ours[1], theirs[1])
        np.testing.assert_array_equal(ours[2], theirs[2])


def test_vec_video_recorder_records_the_sb3_vec_env(tmp_path) -> None:
    pytest.importorskip("moviepy")  # VecVideoRecorder writes with it (the dev extra has it)
    import numpy as np
    from stable_baselines3.common.vec_env import VecVideoRecorder

    from tactile_search.envs.sb3_vec_env import CupboardSearchSb3VecEnv

    env = VecVideoRecorder(
        CupboardSearchSb3VecEnv(num_envs=2, seed=0, map="none", render_mode="rgb_array"),
        str(tmp_path),
        record_video_trigger=lambda step: step == 0,
        video_length=5,
    )
    env.reset()
    for _ in range(6):
        env.step(np.zeros((2, 3)))
    env.close()
    (video,) = tmp_path.glob("*.mp4")
    assert video.stat().st_size > 0
