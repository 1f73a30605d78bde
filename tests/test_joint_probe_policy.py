"""The joint probe head (``tactile_search.networks.joint_probe``): one categorical over every
(lane, depth, sweep), whose actions are the probe-mode env's index triples, and which PPO
trains as SB3's own heads."""

from __future__ import annotations

import numpy as np
import pytest
import torch

from tactile_search.networks.joint_probe import JointCategoricalDistribution, JointProbePolicy

DIMS = [29, 10, 9]


def test_a_probes_joint_index_is_numpys_row_major_index_and_back() -> None:
    distribution = JointCategoricalDistribution(DIMS)
    actions = torch.tensor([[0, 0, 0], [28, 9, 8], [3, 7, 2], [15, 0, 8]])
    index = distribution.joint_index(actions)
    expected = np.ravel_multi_index(actions.numpy().T, DIMS)
    np.testing.assert_array_equal(index.numpy(), expected)
    torch.testing.assert_close(distribution.actions_of(index), actions)


def test_log_prob_sample_and_mode_read_one_logit_per_probe() -> None:
    torch.manual_seed(0)
    logits = torch.randn(4, int(np.prod(DIMS)))
    distribution = JointCategoricalDistribution(DIMS).proba_distribution(logits)
    best = logits.argmax(dim=1)
    mode = distribution.mode()
    torch.testing.assert_close(distribution.joint_index(mode), best)
    torch.testing.assert_close(
        distribution.log_prob(mode), torch.log_softmax(logits, dim=1).gather(1, best[:, None])[:, 0]
    )
    sample = distribution.sample()
    assert sample.shape == (4, 3) and all((sample[:, i] < n).all() for i, n in enumerate(DIMS))
    assert torch.allclose(
        distribution.entropy(), torch.distributions.Categorical(logits=logits).entropy()
    )


def test_ppo_trains_the_joint_head_on_the_probe_mode() -> None:
    from stable_baselines3 import PPO

    from tactile_search.envs.sb3_vec_env import CupboardSearchSb3VecEnv

    env = CupboardSearchSb3VecEnv(num_envs=2, map="none", action_mode="probe", seed=0)
    model = PPO(JointProbePolicy, env, n_steps=16, batch_size=32, n_epochs=1, device="cpu")
    assert model.policy.action_net.out_features == int(np.prod(DIMS))
    before = [p.detach().clone() for p in model.policy.action_net.parameters()]
    model.learn(total_timesteps=32)
    after = list(model.policy.action_net.parameters())
    assert any(not torch.equal(a, b) for a, b in zip(before, after, strict=True))
    action, _ = model.predict(env.reset(), deterministic=True)
    assert all(env.action_space.contains(a) for a in action)


def test_the_joint_head_needs_a_multi_discrete_action_space() -> None:
    from stable_baselines3 import PPO

    from tactile_search.envs.sb3_vec_env import CupboardSearchSb3VecEnv

    env = CupboardSearchSb3VecEnv(num_envs=1, map="none", seed=0)
    with pytest.raises(ValueError, match="MultiDiscrete"):
        PPO(JointProbePolicy, env, device="cpu")
