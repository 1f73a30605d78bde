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
