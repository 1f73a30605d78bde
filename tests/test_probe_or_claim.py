"""The identify task's probe-or-claim head (``ProbeOrClaimDistribution``, the spatial head
with ``claims``): a claim is one outcome whatever probe entries it carries, a probe its own
(lane, depth, sweep), and PPO trains, saves and loads the spatial policy on the identify
id, whose action carries the claim."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import torch

from agents.sb3.recipes import algorithm_class, load_hyperparams, new_model
from agents.sb3.training_env import make_training_env
from tactile_search.networks.joint_probe import ProbeOrClaimDistribution, probe_distribution
from tactile_search.networks.spatial_probe import SpatialProbeHead

DIMS = [29, 10, 9, 2]
PROBES = 29 * 10 * 9
IDENTIFY = "tactile_search/IdentifyByTouch-v0"


def test_a_probe_keeps_its_row_major_index_and_every_claim_is_the_last_outcome() -> None:
    distribution = ProbeOrClaimDistribution(DIMS)
    probes = torch.tensor([[0, 0, 0, 0], [28, 9, 8, 0], [3, 7, 2, 0]])
    index = distribution.joint_index(probes)
    expected = np.ravel_multi_index(probes[:, :3].numpy().T, DIMS[:3])
    np.testing.assert_array_equal(index.numpy(), expected)
    torch.testing.assert_close(distribution.actions_of(index), probes)
    claims = torch.tensor([[0, 0, 0, 1], [28, 9, 8, 1], [3, 7, 2, 1]])
    assert distribution.joint_index(claims).tolist() == [PROBES] * 3
    assert distribution.actions_of(torch.tensor([PROBES])).tolist() == [[0, 0, 0, 1]]


def test_a_claims_probability_is_its_one_logits_whatever_probe_it_carries() -> None:
    torch.manual_seed(0)
    logits = torch.randn(2, PROBES + 1)
    distribution = ProbeOrClaimDistribution(DIMS).proba_distribution(logits)
    claim = torch.log_softmax(logits, dim=1)[:, -1]
    for probe in ([0, 0, 0], [5, 5, 5]):
        actions = torch.tensor([[*probe, 1]] * 2)
        torch.testing.assert_close(distribution.log_prob(actions), claim)
    total = torch.logsumexp(torch.log_softmax(logits, dim=1), dim=1)
    torch.testing.assert_close(total, torch.zeros(2), atol=1e-6, rtol=0)
    sample = distribution.sample()
    assert sample.shape == (2, 4) and ((sample[:, 3] == 0) | (sample[:, :3] == 0).all(1)).all()


def test_the_distribution_follows_the_action_spaces_entries() -> None:
    assert type(probe_distribution([29, 10, 9])).__name__ == "JointCategoricalDistribution"
    assert isinstance(probe_distribution(DIMS), ProbeOrClaimDistribution)
    with pytest.raises(ValueError, match="two values"):
        ProbeOrClaimDistribution([29, 10, 9, 3])


def test_the_claim_logit_reads_the_context_alone() -> None:
    torch.manual_seed(0)
    head = SpatialProbeHead(global_dim=5, probes=6, point_features=4, sweeps=3, claims=True)
    features = torch.randn(2, 5 + 6 * 4)
    before = head(features)
    assert before.shape == (2, 6 * 3 + 1)
    changed = features.clone()
    changed[:, 5:] += 1.0  # every probe's point features
    assert torch.equal(head(changed)[:, -1], before[:, -1])
    changed[:, :5] += 1.0  # the global summary
    assert not torch.equal(head(changed)[:, -1], before[:, -1])


def test_ppo_trains_saves_and_loads_the_spatial_policy_that_claims(tmp_path: Path) -> None:
    from stable_baselines3 import PPO

    from tactile_search.networks.recipe_classes import load_objects

    recipe = load_hyperparams("ppo", "gpis", IDENTIFY)
    recipe.update(n_steps=8, batch_size=16, n_epochs=1)
    env = make_training_env(recipe["env_kwargs"], 2, seed=0, env_id=IDENTIFY, threads=1)
    assert list(env.action_space.nvec)[3] == 2
    model = new_model(algorithm_class("ppo"), recipe, env, seed=0)
    assert model.policy.action_net.claim is not None
    model.learn(16)
    observation = env.reset()
    action, _ = model.predict(observation, deterministic=False)
    assert all(env.action_space.contains(a) for a in action)
    model.save(tmp_path / "model.zip")
    loaded = PPO.load(tmp_path / "model.zip", device="cpu", custom_objects=load_objects(recipe))
    np.testing.assert_array_equal(
        loaded.predict(observation, deterministic=True)[0],
        model.predict(observation, deterministic=True)[0],
    )


def test_cloning_agreement_counts_a_claim_as_a_claim_whatever_probe_it_carries() -> None:
    from agents.imitation.cloning import matching

    teacher = np.array([[3, 4, 5, 1], [3, 4, 5, 0], [1, 1, 1, 0], [2, 2, 2, 1]])
    modes = np.array([[0, 0, 0, 1], [3, 4, 5, 0], [1, 2, 1, 0], [2, 2, 2, 0]])
    got = matching(modes, teacher)
    assert got == {"probe": 0.5, "claim": 0.75, "lane": 1.0, "depth": 0.5, "sweep": 1.0}
    three = matching(modes[:, :3], teacher[:, :3])
    assert three == {"probe": 0.5, "lane": 0.75, "depth": 0.5, "sweep": 0.75}
