"""Behaviour cloning from a Minari dataset alone: the worked example of learning from the
datasets ``python -m agents.datasets`` writes (``python -m agents.behaviour_cloning_from_dataset``).

Everything comes from the dataset: the spaces, every step's observation and the action taken
in it, and the environment to evaluate in (``dataset.recover_environment(eval_env=True)``,
the registered id with the agent's map and action mode). A small torch network (a CNN per
image entry of the Dict observation, the other entries as they are, one categorical head per
entry of a ``MultiDiscrete`` action, or one for a ``Discrete``) is trained to the dataset's
actions by their negative log-likelihood, then acts by its mode on validation layouts
(``tactile_search.seed_ranges``: never the training layouts the dataset holds), its mean
return normalised by the dataset's reference scores (``minari.get_normalized_score``).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from typing import Any

import minari
import numpy as np
import torch
from gymnasium import spaces
from torch import nn

from tactile_search._validation import as_count, as_real


@dataclasses.dataclass(frozen=True)
class BehaviourCloningSettings:
    """Passes over the dataset's steps, minibatch size, Adam's step, the hidden layer's
    width, and the seed of the weights and of the minibatches' order."""

    epochs: int = 5
    batch_size: int = 64
    learning_rate: float = 1e-3
    hidden: int = 128
    seed: int = 0

    def __post_init__(self) -> None:
        for name in ("epochs", "batch_size", "hidden"):
            as_count(name, getattr(self, name))
        as_count("seed", self.seed, minimum=0)
        if as_real("learning_rate", self.learning_rate) <= 0:
            raise ValueError(f"learning_rate must be > 0, got {self.learning_rate!r}")


def action_sizes(action_space: spaces.Space) -> list[int]:
    """The number of choices of each entry of a discrete action: a ``MultiDiscrete``'s
    ``nvec``, a ``Discrete``'s ``n``; ``TypeError`` for any other space (a wrist motion's
    ``Box`` is a regression, not cloned here)."""
    if isinstance(action_space, spaces.MultiDiscrete) and action_space.nvec.ndim == 1:
        return [int(n) for n in action_space.nvec]
    if isinstance(action_space, spaces.Discrete):
        return [int(action_space.n)]
    raise TypeError(
        "behaviour cloning here takes a Discrete or a one-dimensional MultiDiscrete action "
        f"space (the probe action mode), got {action_space}"
    )


def step_transitions(dataset: minari.MinariDataset) -> tuple[dict[str, np.ndarray], np.ndarray]:
    """Every step of every episode: the observation the action was taken in (each key
    stacked) and the action, one row per step (``(steps, entries)`` integers)."""
    if not isinstance(dataset.observation_space, spaces.Dict):
        raise TypeError(f"expected a Dict observation space, got {dataset.observation_space}")
    observations: dict[str, list[np.ndarray]] = {key: [] for key in dataset.observation_space}
    actions = []
    for episode in dataset.iterate_episodes():
        for key in observations:
            observations[key].append(episode.observations[key][:-1])  # the last one has no action
        actions.append(np.asarray(episode.actions).reshape(len(episode), -1))
    if not actions:
        raise ValueError(f"the dataset {dataset.spec.dataset_id} holds no episode")
    return {k: np.concatenate(v) for k, v in observations.items()}, np.concatenate(actions)


class ClonedPolicy(nn.Module):
    """A CNN per image entry (a 3-d ``Box``: channels, height, width; uint8 scaled to [0, 1]),
    the other entries flattened, a two-layer trunk and one categorical head per action
    entry."""

    def __init__(
        self, observation_space: spaces.Dict, action_space: spaces.Space, hidden: int = 128
    ) -> None:
        super().__init__()
        self.sizes = action_sizes(action_space)
        self.image_keys = [k for k, s in observation_space.items() if len(s.shape) == 3]
        self.vector_keys = [k for k in observation_space if k not in self.image_keys]
        self.scales = {
            key: 255.0 if space.dtype == np.uint8 else 1.0
            for key, space in observation_space.items()
        }
        self.encoders = nn.ModuleDict(
            {
                key: nn.Sequential(
                    nn.Conv2d(observation_space[key].shape[0], 16, 5, stride=2, padding=2),
                    nn.ReLU(),
                    nn.Conv2d(16, 32, 3, stride=2, padding=1),
                    nn.ReLU(),
                    nn.AdaptiveAvgPool2d((4, 8)),
                    nn.Flatten(),
                )
                for key in self.image_keys
            }
        )
        width = 32 * 4 * 8 * len(self.image_keys)
        width += sum(int(np.prod(observation_space[k].shape)) for k in self.vector_keys)
        self.trunk = nn.Sequential(
            nn.Linear(width, hidden), nn.ReLU(), nn.Linear(hidden, hidden), nn.ReLU()
        )
        self.head = nn.Linear(hidden, sum(self.sizes))

    def forward(self, observation: dict[str, torch.Tensor]) -> list[torch.Tensor]:
        """The logits of each action entry, ``(batch, choices)`` each."""
        features = [
            self.encoders[k](observation[k].float() / self.scales[k]) for k in self.image_keys
        ]
        features += [observation[k].float().flatten(1) / self.scales[k] for k in self.vector_keys]
        return list(torch.split(self.head(self.trunk(torch.cat(features, 1))), self.sizes, 1))

    def negative_log_likelihood(
        self, observation: dict[str, torch.Tensor], actions: torch.Tensor
    ) -> torch.Tensor:
        """The mean over the batch of the actions' negative log-likelihood (summed over
        their entries)."""
        logits = self(observation)
        return sum(
            nn.functional.cross_entropy(entry, actions[:, i]) for i, entry in enumerate(logits)
        )  # type: ignore[return-value]

    @torch.no_grad()
    def act(self, observation: dict[str, np.ndarray]) -> np.ndarray:
        """The mode of each entry for one observation, as the env takes it (int64 entries,
        a plain index for a ``Discrete`` space)."""
        batch = {k: torch.as_tensor(np.asarray(v))[None] for k, v in observation.items()}
        action = np.array([int(entry.argmax(1)) for entry in self(batch)], dtype=np.int64)
        return action if len(self.sizes) > 1 else action[0]


def train_behaviour_cloning(
    dataset: minari.MinariDataset, settings: BehaviourCloningSettings | None = None
) -> tuple[ClonedPolicy, list[float]]:
    """A ``ClonedPolicy`` trained to the dataset's actions, and its mean training loss per
    epoch."""
    settings = settings or BehaviourCloningSettings()
    torch.manual_seed(settings.seed)
    observations, actions = step_transitions(dataset)
    policy = ClonedPolicy(dataset.observation_space, dataset.action_space, settings.hidden)
    optimizer = torch.optim.Adam(policy.parameters(), lr=settings.learning_rate)
    inputs = {k: torch.as_tensor(v) for k, v in observations.items()}
    targets = torch.as_tensor(actions, dtype=torch.int64)
    order = torch.Generator().manual_seed(settings.seed)
    losses = []
    for _ in range(settings.epochs):
        total = 0.0
        permutation = torch.randperm(len(targets), generator=order)
        for start in range(0, len(targets), settings.batch_size):
            rows = permutation[start : start + settings.batch_size]
            batch = {key: values[rows] for key, values in inputs.items()}
            loss = policy.negative_log_likelihood(batch, targets[rows])
            optimizer.zero_grad()
            loss.backward()
            optimizer.step()
            total += loss.item() * len(rows)
        losses.append(total / len(targets))
    return policy, losses


def evaluate_cloned_policy(
    policy: ClonedPolicy, dataset: minari.MinariDataset, seeds: Sequence[int]
) -> dict[str, Any]:
    """The policy's episodes in the dataset's evaluation env on layouts ``seeds``: the
    returns, the success rate, the mean return and its normalised score (0 the dataset's
    ``ref_min_score``, 1 its ``ref_max_score``)."""
    env = dataset.recover_environment(eval_env=True)
    returns, successes = [], []
    policy.eval()
    try:
        for seed in seeds:
            observation, info = env.reset(seed=int(seed))
            total, done = 0.0, False
            while not done:
                observation, reward, terminated, truncated, info = env.step(policy.act(observation))
                total += float(reward)
                done = terminated or truncated
            returns.append(total)
            successes.append(bool(info["success"]))
    finally:
        env.close()
    mean_return = float(np.mean(returns))
    return {
        "returns": returns,
        "success_rate": float(np.mean(successes)),
        "mean_return": mean_return,
        "normalized_score": float(minari.get_normalized_score(dataset, np.array(mean_return))),
    }
