"""Behaviour cloning as an anchor while PPO fine-tunes a cloned policy (and the file of
demonstrations it reads, which ``agents.imitation`` writes).

Fine-tuned with PPO alone, a policy cloned from the planner improves for a while and then
drifts: its entropy collapses and it learns to repeat probes until the time runs out
(docs/RESULTS.md, "Learning from the planner"). The anchor keeps it near what it was taught: before
every rollout (after the previous update), a few minibatches of the demonstrations the
policy was cloned from are trained on again, their negative log-likelihood weighted by a
weight that decays linearly to zero over the first ``decay_timesteps``: the policy starts
as the teacher's clone and is free to improve on it later. An SB3 callback, so any
on-policy algorithm of SB3 takes it; the demonstrations are those ``agents.imitate`` kept
in its run (``demonstrations.npz``: ``actions`` and one ``observation_<key>`` array per
observation key, a row per state).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from agents.run_dir import demonstrations_beside
from tactile_search._validation import as_count

#: The prefix of an observation key's array in a file of demonstrations.
OBSERVATION_PREFIX = "observation_"


def observations_in(data: Any) -> dict[str, np.ndarray]:
    """The observation arrays of a loaded file of demonstrations, by observation key."""
    return {
        name.removeprefix(OBSERVATION_PREFIX): data[name]
        for name in data.files
        if name.startswith(OBSERVATION_PREFIX)
    }


class Demonstrated:
    """States and the probes demonstrated there: ``observations`` (key -> ``(n, ...)``) and
    ``actions`` (``(n, 3)``), as the anchor reads them."""

    def __init__(self, observations: dict[str, np.ndarray], actions: np.ndarray) -> None:
        if any(len(value) != len(actions) for value in observations.values()):
            raise ValueError("every observation array needs one row per action")
        self.observations, self.actions = observations, actions

    def __len__(self) -> int:
        return len(self.actions)


def behaviour_cloning_anchor(
    demonstrations: Demonstrated,
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
                observations, _ = policy.obs_to_tensor(
                    {key: value[index] for key, value in demonstrations.observations.items()}
                )
                actions = torch.as_tensor(demonstrations.actions[index], device=policy.device)
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


def anchor_demonstrations(init_from: Path) -> Demonstrated:
    """The demonstrations kept beside the model ``init_from`` (an imitation run's
    ``model.zip``); ``ValueError`` naming the file when there are none."""
    path = demonstrations_beside(Path(init_from))
    if not path.is_file():
        raise ValueError(
            f"the recipe anchors fine-tuning to the demonstrations of init_from, but "
            f"{path} is missing (init_from must be a run of agents.imitate)"
        )
    with np.load(path) as data:
        observations = observations_in(data)
        if "actions" not in data.files or not observations:
            raise ValueError(f"{path} is not a file of demonstrations")
        return Demonstrated(observations, data["actions"])
