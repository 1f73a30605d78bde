"""The learner's updates in bfloat16 where the CPU computes it natively
(``agents.sb3.bfloat16``): that is read from the CPU's flags, PPO's update (and only the
update) and the clone stage's cloning run under autocast, the probe policies' logits and
log-probabilities stay float32 under it, and a model trained so saves and loads as a plain
PPO."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import torch

pytest.importorskip("stable_baselines3")

from agents.sb3 import bfloat16
from agents.sb3.bfloat16 import (
    BFloat16Updates,
    bfloat16_update_class,
    cpu_has_native_bf16,
    learner_precision,
    update_precision,
)
from agents.sb3.recipes import load_hyperparams, new_model, training_class
from agents.sb3.training_env import make_training_env
from tactile_search.networks.joint_probe import Float32Linear, JointCategoricalDistribution
from tactile_search.networks.recipe_classes import load_objects


def test_native_bfloat16_is_read_from_the_cpus_flags_not_from_a_substring(
    tmp_path: Path,
) -> None:
    cpuinfo = tmp_path / "cpuinfo"
    cpuinfo.write_text("processor\t: 0\nflags\t\t: fpu amx_tile amx_bf16 sse\n")
    assert cpu_has_native_bf16(cpuinfo)  # AMX tiles
    cpuinfo.write_text("processor\t: 0\nflags\t\t: fpu avx512f avx512_bf16 sse\n")
    assert cpu_has_native_bf16(cpuinfo)  # AVX-512's bfloat16 dot products
    cpuinfo.write_text("processor\t: 0\nflags\t\t: fpu avx512f amx_bf16x avx512_bf16x\n")
    assert not cpu_has_native_bf16(cpuinfo)
    assert not cpu_has_native_bf16(tmp_path / "missing")


def test_a_recipes_learner_precision_needs_its_flag_and_the_cpu() -> None:
    assert learner_precision({"bfloat16_updates": True}, native=True) == "bfloat16"
    assert learner_precision({"bfloat16_updates": True}, native=False) == "float32"
    assert learner_precision({"bfloat16_updates": False}, native=True) == "float32"
    assert learner_precision({}, native=True) == "float32"


class RecordsAutocast:
    """Stands in for an SB3 algorithm: ``train`` records the autocast state it ran in."""

    def train(self) -> None:
        self.seen = (torch.is_autocast_enabled("cpu"), torch.get_autocast_dtype("cpu"))

    def collect_rollouts(self) -> bool:
        return torch.is_autocast_enabled("cpu")


def test_the_update_alone_runs_under_bfloat16_autocast_and_only_where_native() -> None:
    fast = bfloat16_update_class(RecordsAutocast, native=True)
    algorithm = fast()
    algorithm.train()
    assert algorithm.seen == (True, torch.bfloat16)
    assert not algorithm.collect_rollouts()  # the rollouts stay float32
    assert not torch.is_autocast_enabled("cpu")  # and autocast ends with the update
    assert issubclass(fast, BFloat16Updates) and issubclass(fast, RecordsAutocast)
    assert bfloat16_update_class(RecordsAutocast, native=True) is fast  # one class
    assert bfloat16_update_class(RecordsAutocast, native=False) is RecordsAutocast
    assert (update_precision(fast), update_precision(RecordsAutocast)) == ("bfloat16", "float32")
    with pytest.raises(TypeError, match="SB3 algorithm class"):
        bfloat16_update_class(RecordsAutocast(), native=True)


def test_a_recipe_asks_for_bfloat16_updates_with_a_bool(monkeypatch: pytest.MonkeyPatch) -> None:
    from stable_baselines3 import PPO

    assert training_class("ppo", {}) is PPO
    assert training_class("ppo", {"bfloat16_updates": False}) is PPO
    monkeypatch.setattr(bfloat16, "cpu_has_native_bf16", lambda: True)
    fast = training_class("ppo", {"bfloat16_updates": True})
    assert issubclass(fast, PPO) and update_precision(fast) == "bfloat16"
    monkeypatch.setattr(bfloat16, "cpu_has_native_bf16", lambda: False)
    assert training_class("ppo", {"bfloat16_updates": True}) is PPO  # emulated: float32
    with pytest.raises(TypeError, match="bfloat16_updates must be a bool, got str"):
        training_class("ppo", {"bfloat16_updates": "yes"})


def test_probe_logits_and_log_probabilities_stay_float32_under_autocast() -> None:
    torch.manual_seed(0)
    layer = Float32Linear(16, 2 * 3 * 4)
    latent = torch.randn(5, 16)
    actions = torch.tensor([[0, 1, 2], [1, 2, 3], [0, 0, 0], [1, 0, 3], [0, 2, 1]])
    distribution = JointCategoricalDistribution([2, 3, 4])
    exact = distribution.proba_distribution(layer(latent)).log_prob(actions)
    with torch.autocast("cpu", dtype=torch.bfloat16):
        logits = layer(latent)
        log_prob = distribution.proba_distribution(logits).log_prob(actions)
        entropy = distribution.entropy()
        rounded = torch.nn.functional.linear(latent, layer.weight, layer.bias)
    assert logits.dtype == log_prob.dtype == entropy.dtype == torch.float32
    torch.testing.assert_close(log_prob, exact, rtol=0, atol=0)
    assert rounded.dtype == torch.bfloat16  # what the plain layer would have given
    assert list(layer.state_dict()) == ["weight", "bias"]  # a Linear's parameters


def test_ppo_trains_with_bfloat16_updates_and_loads_as_plain_ppo(tmp_path: Path) -> None:
    from stable_baselines3 import PPO

    recipe = load_hyperparams("ppo", "gpis")
    # A constant rate: the recipe's falls to 0 by a run's last update, this run's only one.
    recipe.update(n_steps=8, batch_size=16, n_epochs=1, learning_rate=1e-4)
    env = make_training_env(recipe["env_kwargs"], 2, seed=0, threads=1)
    model = new_model(bfloat16_update_class(PPO, native=True), recipe, env, seed=0)
    before = [p.detach().clone() for p in model.policy.parameters()]
    model.learn(16)
    after = list(model.policy.parameters())
    assert all(p.dtype == torch.float32 and torch.isfinite(p).all() for p in after)
    assert any(not torch.equal(b, a) for b, a in zip(before, after, strict=True))  # it learned
    observation = env.reset()
    action, _ = model.predict(observation, deterministic=True)
    model.save(tmp_path / "model.zip")
    loaded = PPO.load(tmp_path / "model.zip", device="cpu", custom_objects=load_objects(recipe))
    np.testing.assert_array_equal(loaded.predict(observation, deterministic=True)[0], action)
    env.close()


def test_cloning_runs_its_passes_under_the_precision_it_is_given(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """A bfloat16 pass evaluates the policy under autocast (a float32 one does not), its
    losses and weights stay finite float32, and the two precisions train differently."""
    from agents.imitation import cloning
    from agents.imitation.cloning import CloningSettings, clone
    from agents.imitation.demonstrations import Demonstrations

    recipe = load_hyperparams("ppo", "gpis")
    env = make_training_env(recipe["env_kwargs"], 2, seed=0, threads=1)
    observation = env.reset()
    env.close()
    rows = 8
    demonstrations = Demonstrations(
        observations={k: np.repeat(v[:1], rows, axis=0) for k, v in observation.items()},
        actions=np.tile([[3, 4, 5]], (rows, 1)),
        returns=np.linspace(0.0, 1.0, rows, dtype=np.float32),
        layout_seeds=np.arange(rows, dtype=np.int64),
        episode_success=np.ones(rows, dtype=bool),
        episode_tips=np.zeros(rows, dtype=np.int64),
        episode_steps=np.zeros(rows, dtype=np.int64),
    )
    seen: list[bool] = []
    evaluate = cloning._evaluate_actions

    def recording(policy, batch):  # type: ignore[no-untyped-def]
        seen.append(torch.is_autocast_enabled("cpu"))
        return evaluate(policy, batch)

    monkeypatch.setattr(cloning, "_evaluate_actions", recording)
    settings = CloningSettings(epochs=2, batch_size=4)
    weights = {}
    for precision in ("float32", "bfloat16"):
        seen.clear()
        model = new_model(
            training_class("ppo", recipe), recipe, make_training_env(recipe["env_kwargs"], 2, 0), 0
        )
        history = clone(model.policy, demonstrations, settings, precision=precision)
        assert seen == [precision == "bfloat16"] * 4, precision
        assert all(np.isfinite(row["nll"]) for row in history)
        params = list(model.policy.parameters())
        assert all(p.dtype == torch.float32 and torch.isfinite(p).all() for p in params)
        weights[precision] = [p.detach().clone() for p in params]
    assert any(
        not torch.equal(a, b) for a, b in zip(weights["float32"], weights["bfloat16"], strict=True)
    )
    with pytest.raises(ValueError, match="precision must be one of"):
        clone(model.policy, demonstrations, settings, precision="float16")
