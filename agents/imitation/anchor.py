"""Behaviour cloning as an anchor while PPO fine-tunes a cloned policy.

Fine-tuned with PPO alone, a policy cloned from the planner improves for a while and then
drifts: its entropy collapses and it learns to repeat probes until the time runs out
(docs/RESULTS.md, issue 24's rows). The anchor keeps it near what it was taught: before
every rollout (after the previous update), a few minibatches of the demonstrations the
policy was cloned from are trained on again, their negative log-likelihood weighted by a
weight that decays linearly to zero over the first ``decay_timesteps``: the policy starts
as the teacher's clone and is free to improve on it later. An SB3 callback, so any
on-policy algorithm of SB3 takes it; the demonstrations are those ``agents.imitate`` kept
in its run (``demonstrations.npz``).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from agents.imitation.demonstrations import Demonstrations
from tactile_search._validation import as_count

#: The demonstrations an imitation run keeps beside its model: what its last clone learned.
DEMONSTRATIONS_FILE = "demonstrations.npz"


def behaviour_cloning_anchor(
    demonstrations: Demonstrations,
    weight: float,
    decay_timesteps: int,
    batches: int = 4,
    batch_size: int = 128,
    seed: int = 0,
) -> Any:
    """The callback: before each rollout, ``batches`` minibatches of ``batch_size``
    demonstrations, their mean NLL times ``weight * max(0, 1 - timesteps /
    decay_timesteps)``, one step of the policy's own optimizer each (its gradient clipped
    as the algorithm clips). Logs ``anchor/weight`` and ``anchor/nll``."""
    import torch
    from stable_baselines3.common.callbacks import BaseCallback

    if len(demonstrations) == 0:
        raise ValueError("the anchor needs at least one demonstration")
    if not isinstance(weight, (int, float)) or not np.isfinite(weight) or weight < 0:
        raise ValueError(f"anchor weight must be a finite number >= 0, got {weight!r}")
    decay_timesteps = as_count("decay_timesteps", decay_timesteps)
    batches = as_count("batches", batches)
    batch_size = as_count("batch_size", batch_size)

    class BehaviourCloningAnchor(BaseCallback):
        def __init__(self) -> None:
            super().__init__()
            self.rng = np.random.default_rng(seed)

        def _on_rollout_start(self) -> None:
            share = max(0.0, 1.0 - self.model.num_timesteps / decay_timesteps)
            now = weight * share
            self.logger.record("anchor/weight", now)
            if now == 0.0:
                return
            policy = self.model.policy
            policy.set_training_mode(True)
            total = 0.0
            for _ in range(batches):
                index = self.rng.integers(len(demonstrations), size=batch_size)
                batch = demonstrations.rows(index)
                observations, _ = policy.obs_to_tensor(batch.observations)
                actions = torch.as_tensor(batch.actions, device=policy.device)
                _, log_prob, _ = policy.evaluate_actions(observations, actions)
                nll = -log_prob.mean()
                policy.optimizer.zero_grad()
                (now * nll).backward()
                torch.nn.utils.clip_grad_norm_(policy.parameters(), self.model.max_grad_norm)
                policy.optimizer.step()
                total += nll.item()
            policy.set_training_mode(False)
            self.logger.record("anchor/nll", total / batches)

        def _on_step(self) -> bool:
            return True

    return BehaviourCloningAnchor()


def anchor_demonstrations(init_from: Path) -> Demonstrations:
    """The demonstrations kept beside the model ``init_from`` (an imitation run's
    ``model.zip``); ``ValueError`` naming the file when there are none."""
    path = Path(init_from).parent / DEMONSTRATIONS_FILE
    if not path.is_file():
        raise ValueError(
            f"the recipe anchors fine-tuning to the demonstrations of init_from, but "
            f"{path} is missing (init_from must be a run of agents.imitate)"
        )
    return Demonstrations.load(path)
