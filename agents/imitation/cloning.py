"""Behaviour cloning into an SB3 actor-critic's own heads.

The policy's action distribution is trained to the teacher's probes by their negative
log-likelihood (``evaluate_actions``: the same heads PPO later fine-tunes, so nothing is
translated between a cloned network and the RL one), and its value head to the demonstrated
returns, so that fine-tuning starts with a critic that knows the teacher's episodes
(a value warm-up). A small entropy bonus keeps the heads from collapsing onto one probe
where the teacher is undecided.
"""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np

from agents.imitation.demonstrations import Demonstrations
from tactile_search._validation import as_count


@dataclasses.dataclass(frozen=True)
class CloningSettings:
    """How a policy is cloned: passes over the demonstrations, minibatch size, Adam's step,
    the value loss's weight beside the action's negative log-likelihood, the entropy bonus's
    weight, and the seed of the minibatches' order."""

    epochs: int = 40
    batch_size: int = 128
    learning_rate: float = 3e-4
    value_weight: float = 0.5
    entropy_weight: float = 1e-3
    seed: int = 0

    def __post_init__(self) -> None:
        as_count("epochs", self.epochs)
        as_count("batch_size", self.batch_size)
        for name in ("learning_rate", "value_weight", "entropy_weight"):
            value = getattr(self, name)
            if not isinstance(value, (int, float)) or not np.isfinite(value) or value < 0:
                raise ValueError(f"{name} must be a finite number >= 0, got {value!r}")
        if self.learning_rate <= 0:
            raise ValueError(f"learning_rate must be > 0, got {self.learning_rate!r}")


def clone(policy: Any, demonstrations: Demonstrations, settings: CloningSettings) -> list[dict]:
    """Trains ``policy`` (an SB3 ``ActorCriticPolicy``) on ``demonstrations``; per epoch,
    the mean action negative log-likelihood, value loss and entropy."""
    import torch

    if len(demonstrations) == 0:
        raise ValueError("clone needs at least one demonstration")
    optimizer = torch.optim.Adam(policy.parameters(), lr=settings.learning_rate)
    rng = np.random.default_rng(settings.seed)
    policy.set_training_mode(True)
    history = []
    for _ in range(settings.epochs):
        order = rng.permutation(len(demonstrations))
        totals = np.zeros(3)
        for start in range(0, len(order), settings.batch_size):
            batch = demonstrations.rows(order[start : start + settings.batch_size])
            observations, _ = policy.obs_to_tensor(batch.observations)
            actions = torch.as_tensor(batch.actions, device=policy.device)
            returns = torch.as_tensor(batch.returns, device=policy.device)
            values, log_prob, entropy = policy.evaluate_actions(observations, actions)
            nll = -log_prob.mean()
            value_loss = torch.nn.functional.mse_loss(values.flatten(), returns)
            mean_entropy = entropy.mean()
            loss = nll + settings.value_weight * value_loss - settings.entropy_weight * mean_entropy
            optimizer.zero_grad()
            loss.backward()
            torch.nn.utils.clip_grad_norm_(policy.parameters(), 0.5)
            optimizer.step()
            totals += len(batch) * np.array([nll.item(), value_loss.item(), mean_entropy.item()])
        nll_, value_, entropy_ = totals / len(demonstrations)
        history.append({"nll": nll_, "value_loss": value_, "entropy": entropy_})
    policy.set_training_mode(False)
    return history


def agreement(policy: Any, demonstrations: Demonstrations, batch_size: int = 512) -> dict:
    """How often the policy's mode is the teacher's probe on ``demonstrations``: the whole
    probe (``probe``) and each index (``lane``, ``depth``, ``sweep``), as fractions."""
    import torch

    if len(demonstrations) == 0:
        raise ValueError("agreement needs at least one demonstration")
    policy.set_training_mode(False)
    matches = []
    with torch.no_grad():
        for start in range(0, len(demonstrations), batch_size):
            batch = demonstrations.rows(
                np.arange(start, min(start + batch_size, len(demonstrations)))
            )
            observations, _ = policy.obs_to_tensor(batch.observations)
            mode = policy.get_distribution(observations).mode().cpu().numpy()
            matches.append(mode.reshape(batch.actions.shape) == batch.actions)
    equal = np.concatenate(matches)
    fractions = {
        name: float(equal[:, i].mean()) for i, name in enumerate(("lane", "depth", "sweep"))
    }
    return {"probe": float(equal.all(axis=1).mean()), **fractions}
