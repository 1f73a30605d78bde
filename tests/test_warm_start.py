"""Warm starts (``TrainSettings(init_from=...)``, ``--init-from``): the policy starts from a
model's weights, the run records where they came from, and a model of another network,
observation or action space is refused naming what differs."""

from __future__ import annotations

from pathlib import Path

import pytest
import torch
import yaml

from agents.sb3.training import TrainSettings, train, warm_start
from tactile_search.envs.sb3_vec_env import CupboardSearchSb3VecEnv
from tests.recipes import train_with_recipe


def _states_equal(a: dict, b: dict) -> bool:
    return a.keys() == b.keys() and all(torch.equal(a[k], b[k]) for k in a)


def test_a_warm_start_loads_the_weights_and_records_their_source(tmp_path: Path) -> None:
    from stable_baselines3 import PPO

    source = train_with_recipe(tmp_path / "a", "none")
    run = train_with_recipe(tmp_path / "b", "none", train_kwargs={"init_from": source})
    record = yaml.safe_load((run / "config.yml").read_text())["init_from"]
    assert record["path"] == str(source / "model.zip") and len(record["model_digest"]) == 64
    # The loading itself: a fresh model of the same recipe gets exactly the source's weights.
    trained = PPO.load(source / "model.zip", device="cpu")
    env = CupboardSearchSb3VecEnv(num_envs=1, map="none", action_mode="probe", seed=0)
    fresh = PPO("MultiInputPolicy", env, device="cpu")  # the none recipe's network
    assert not _states_equal(fresh.policy.state_dict(), trained.policy.state_dict())
    warm_start(fresh, PPO, source / "model.zip")
    assert _states_equal(fresh.policy.state_dict(), trained.policy.state_dict())


def test_a_model_of_another_observation_or_action_space_is_refused(tmp_path: Path) -> None:
    source = train_with_recipe(tmp_path / "a", "none")
    with pytest.raises(ValueError, match="observations"):
        train_with_recipe(tmp_path / "b", "gpis", train_kwargs={"init_from": source})
    wrist = {"map": "none", "reward_approach": 10.0}
    with pytest.raises(ValueError, match="actions"):
        train_with_recipe(
            tmp_path / "c", "none", env_kwargs=wrist, train_kwargs={"init_from": source}
        )


def test_bad_warm_starts_raise_value_error(tmp_path: Path) -> None:
    with pytest.raises(ValueError, match="init_from must be a run directory"):
        train(TrainSettings("ppo", "none", out=tmp_path, init_from=tmp_path / "missing"))
    with pytest.raises(ValueError, match="resumed run keeps its own weights"):
        train(TrainSettings("ppo", "none", out=tmp_path, init_from=tmp_path, resume=True))
