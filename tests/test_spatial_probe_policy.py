"""The spatial probe head (``tactile_search.networks.spatial_probe``): every probe reads the map at
its own points (from the env's geometry), its logits sit at its joint index, and PPO trains,
saves and loads it."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import torch

from agents.sb3.recipes import algorithm_class, load_hyperparams, new_model
from agents.sb3.training_env import make_training_env
from tactile_search import CupboardSearchEnv
from tactile_search.networks.spatial_probe import SpatialProbeHead, probe_points

SPATIAL = {
    "policy": "tactile_search.networks.spatial_probe.SpatialProbePolicy",
    "policy_kwargs": {
        "features_extractor_class": "tactile_search.networks.spatial_probe.SpatialProbeExtractor"
    },
}


def spatial_recipe(**env_changes: object) -> dict:
    recipe = load_hyperparams("ppo", "gpis")
    recipe.update(SPATIAL)
    recipe["env_kwargs"].update(env_changes)
    return recipe


def test_each_probe_reads_the_wrist_point_and_a_reach_ahead_on_the_map() -> None:
    geometry = CupboardSearchEnv(action_mode="probe").geometry()
    points = np.array(probe_points(geometry))
    lanes, depths = len(geometry["probe_lanes"]), len(geometry["probe_depths"])
    assert points.shape == (2 * lanes * depths, 2)
    middle_lane_opening = 2 * (lanes // 2) * depths  # lane 14 (x = 0), depth 0 (y = 0)
    np.testing.assert_allclose(points[middle_lane_opening], [0.0, -1.0], atol=1e-12)
    ahead = points[middle_lane_opening + 1]
    assert ahead[0] == pytest.approx(0.0, abs=1e-12)
    assert ahead[1] == pytest.approx(-1 + 2 * geometry["reach"] / geometry["depth"])
    assert np.all(np.abs(points) <= 1.0)


def test_a_probes_logits_sit_at_its_joint_index_and_read_its_own_features() -> None:
    torch.manual_seed(0)
    head = SpatialProbeHead(global_dim=5, probes=6, point_features=4, sweeps=3)
    features = torch.randn(2, 5 + 6 * 4)
    before = head(features)
    changed = features.clone()
    changed[:, 5 + 2 * 4 : 5 + 3 * 4] += 1.0  # probe 2's point features
    after = head(changed)
    moved = (after - before).abs().sum(dim=0) > 0
    assert moved.tolist() == [index // 3 == 2 for index in range(18)]


def test_the_head_is_its_mlp_on_each_probes_features_beside_the_context() -> None:
    """The head applies the context's half of its first layer once per sample; that must be
    the same function as its MLP on every probe's [features, context] concatenation."""
    torch.manual_seed(0)
    probes, point_features, global_dim = 12, 6, 10
    head = SpatialProbeHead(global_dim, probes, point_features, sweeps=4)
    features = torch.randn(5, global_dim + probes * point_features)
    context = torch.relu(head.context(features[:, :global_dim]))
    per_probe = features[:, global_dim:].reshape(5, probes, point_features)
    both = torch.cat([per_probe, context[:, None, :].expand(-1, probes, -1)], dim=2)
    expected = head.mlp(both).reshape(5, -1)
    torch.testing.assert_close(head(features), expected, rtol=1e-5, atol=1e-6)


def test_ppo_trains_saves_and_loads_the_spatial_policy(tmp_path: Path) -> None:
    from stable_baselines3 import PPO

    from tactile_search.networks.recipe_classes import load_objects

    recipe = spatial_recipe()
    recipe.update(n_steps=8, batch_size=16, n_epochs=1)
    env = make_training_env(recipe["env_kwargs"], 2, seed=0, threads=1)
    model = new_model(algorithm_class("ppo"), recipe, env, seed=0)
    sweeps = env.action_space.nvec[2]
    assert model.policy.action_net.mlp[-1].out_features == sweeps
    model.learn(16)
    observation = env.reset()
    action, _ = model.predict(observation, deterministic=True)
    assert all(env.action_space.contains(a) for a in action)
    model.save(tmp_path / "model.zip")
    loaded = PPO.load(tmp_path / "model.zip", device="cpu", custom_objects=load_objects(recipe))
    np.testing.assert_array_equal(loaded.predict(observation, deterministic=True)[0], action)


def test_probe_points_of_another_grid_are_refused() -> None:
    recipe = spatial_recipe()
    env = make_training_env({**recipe["env_kwargs"], "probe_lanes": 7}, 2, seed=0, threads=1)
    with pytest.raises(ValueError, match="probes"):
        new_model(algorithm_class("ppo"), recipe, env, seed=0)
