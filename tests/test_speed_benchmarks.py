"""The training-speed benchmarks' arguments and recipes (``benchmarks.learner_speed``,
``benchmarks.train_arrangement``): what they would train, checked without training."""

from __future__ import annotations

import argparse

import pytest

pytest.importorskip("stable_baselines3")

from benchmarks import learner_speed, train_arrangement


def test_a_variant_names_a_recipe_and_its_overrides() -> None:
    assert learner_speed.variant_spec("recipe") == ("recipe", {})
    label, overrides = learner_speed.variant_spec("space_to_depth:n_epochs=5,batch_size=256")
    assert label == "space_to_depth:n_epochs=5,batch_size=256"
    assert overrides == {"n_epochs": 5, "batch_size": 256}
    with pytest.raises(argparse.ArgumentTypeError, match="variant must be one of"):
        learner_speed.variant_spec("resnet")
    with pytest.raises(argparse.ArgumentTypeError, match="key=value"):
        learner_speed.variant_spec("recipe:n_epochs")


def test_each_variant_trains_its_own_encoder_on_the_recipes_settings() -> None:
    spatial = learner_speed.variant_recipe("recipe", {})
    assert spatial["policy"].endswith("SpatialProbePolicy")
    recipe = learner_speed.variant_recipe("impala_factorised", {})
    faster = learner_speed.variant_recipe("space_to_depth", {})
    nature = learner_speed.variant_recipe("nature_cnn", {"n_epochs": 4})
    no_map = learner_speed.variant_recipe("mlp_no_map", {})
    kwargs = faster["policy_kwargs"]["features_extractor_kwargs"]
    assert kwargs["space_to_depth"] == 2 and kwargs["channels"] == [16, 16]
    assert "space_to_depth" not in recipe["policy_kwargs"]["features_extractor_kwargs"]
    assert "features_extractor_class" not in nature["policy_kwargs"]
    assert nature["n_epochs"] == 4 and recipe["n_epochs"] == 10
    assert no_map["env_kwargs"]["map"] == "none"
    # the ablation changes the encoder only: every other key is the recipe's
    for key in set(recipe) | set(faster):
        if key != "policy_kwargs":
            assert faster[key] == recipe[key], key


def test_an_env_kwargs_override_sets_one_setting_and_keeps_the_recipes_others() -> None:
    recipe = learner_speed.variant_recipe("recipe", {})
    stepped = learner_speed.variant_recipe("recipe", {"env_kwargs.fast_free_motion": False})
    assert stepped["env_kwargs"] == {**recipe["env_kwargs"], "fast_free_motion": False}
    assert "fast_free_motion" not in recipe["env_kwargs"]
    with pytest.raises(ValueError, match=r"only env_kwargs\.KEY"):
        learner_speed.variant_recipe("recipe", {"policy_kwargs.net_arch": [64]})


def test_arrangements_run_the_real_training_command() -> None:
    args = argparse.Namespace(map="gpis", timesteps=64, hyperparams=None)
    command = train_arrangement.train_command(args, seed=3, threads=2, out="runs/x")
    joined = " ".join(command[1:])
    assert joined.startswith("-m agents.train --algo ppo --map gpis --seed 3 --timesteps 64")
    assert "--torch-threads 2 --env-threads 2" in joined
    assert "--hyperparams" not in command
