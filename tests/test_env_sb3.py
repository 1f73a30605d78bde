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
