"""Behaviour cloning into an SB3 actor-critic's own heads.

The policy's action distribution is trained to the teacher's probes by their negative
log-likelihood (``evaluate_actions``: the same heads PPO later fine-tunes, so nothing is
translated between a cloned network and the RL one), and its value head to the demonstrated
returns, so that fine-tuning starts with a critic that knows the teacher's episodes
(a value warm-up). A small entropy bonus keeps the heads from collapsing onto one probe
where the teacher is undecided. Where the recipe asks for bfloat16 updates and the CPU
computes bfloat16 natively (``agents.sb3.bfloat16.learner_precision``), the forward and
backward passes run under bfloat16 autocast as PPO's update does; the logits, the
log-likelihoods and the weights stay float32.
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


#: The precisions a cloning pass runs in (``agents.sb3.bfloat16.learner_precision``).
PRECISIONS = ("float32", "bfloat16")


def clone(
    policy: Any,
    demonstrations: Demonstrations,
    settings: CloningSettings,
    progress: Any = None,
    precision: str = "float32",
) -> list[dict]:
    """Trains ``policy`` (an SB3 ``ActorCriticPolicy``, or sb3-contrib's recurrent one) on
    ``demonstrations``; per epoch, the mean action negative log-likelihood, value loss and
    entropy. A recurrent policy learns from whole episodes: each minibatch is episodes in
    their order, its memory starting empty at each episode's first probe. ``progress(1)``
    is called after each epoch (a progress bar's ``update``). ``precision`` ``bfloat16``
    runs the passes under bfloat16 autocast (the weights stay float32)."""
    import torch

    if len(demonstrations) == 0:
        raise ValueError("clone needs at least one demonstration")
    if precision not in PRECISIONS:
        raise ValueError(f"precision must be one of {PRECISIONS}, got {precision!r}")
    bfloat16 = precision == "bfloat16"
    optimizer = torch.optim.Adam(policy.parameters(), lr=settings.learning_rate)
    rng = np.random.default_rng(settings.seed)
    policy.set_training_mode(True)
    history = []
    for _ in range(settings.epochs):
        totals = np.zeros(3)
        for index in _minibatches(policy, demonstrations, settings.batch_size, rng):
            batch = demonstrations.rows(index)
            returns = torch.as_tensor(batch.returns, device=policy.device)
            with torch.autocast("cpu", dtype=torch.bfloat16, enabled=bfloat16):
                values, log_prob, entropy = _evaluate_actions(policy, batch)
            nll = -log_prob.float().mean()
            value_loss = torch.nn.functional.mse_loss(values.float().flatten(), returns)
            mean_entropy = entropy.float().mean()
            loss = nll + settings.value_weight * value_loss - settings.entropy_weight * mean_entropy
            optimizer.zero_grad()
            loss.backward()
            torch.nn.utils.clip_grad_norm_(policy.parameters(), 0.5)
            optimizer.step()
            totals += len(batch) * np.array([nll.item(), value_loss.item(), mean_entropy.item()])
        nll_, value_, entropy_ = totals / len(demonstrations)
        history.append({"nll": nll_, "value_loss": value_, "entropy": entropy_})
        if progress is not None:
            progress(1)
    policy.set_training_mode(False)
    return history


def is_recurrent(policy: Any) -> bool:
    """Whether ``policy`` carries a memory (sb3-contrib's ``RecurrentActorCriticPolicy``)."""
    return hasattr(policy, "lstm_actor")


def _minibatches(
    policy: Any, demonstrations: Demonstrations, batch_size: int, rng: np.random.Generator
) -> list[np.ndarray]:
    """One epoch's minibatches of row indices, shuffled with ``rng``: rows for a policy
    without memory; for a recurrent one, whole episodes (in their order) up to at least
    ``batch_size`` rows each."""
    if not is_recurrent(policy):
        order = rng.permutation(len(demonstrations))
        return [order[start : start + batch_size] for start in range(0, len(order), batch_size)]
    episodes = demonstrations.episode_slices()
    batches, current = [], []
    for i in rng.permutation(len(episodes)):
        current.append(np.arange(episodes[i].start, episodes[i].stop))
        if sum(map(len, current)) >= batch_size:
            batches.append(np.concatenate(current))
            current = []
    if current:
        batches.append(np.concatenate(current))
    return batches


def _in_order(policy: Any, demonstrations: Demonstrations, batch_size: int) -> list[np.ndarray]:
    """Every row once, in order, in batches of about ``batch_size`` that cut no episode of a
    recurrent policy."""
    n = len(demonstrations)
    if not is_recurrent(policy):
        return [np.arange(start, min(start + batch_size, n)) for start in range(0, n, batch_size)]
    batches, start = [], 0
    for episode in demonstrations.episode_slices():
        if episode.stop - start >= batch_size:
            batches.append(np.arange(start, episode.stop))
            start = episode.stop
    if start < n:
        batches.append(np.arange(start, n))
    return batches


def _as_sequences(policy: Any, batch: Demonstrations) -> tuple[Demonstrations, Any, Any, Any]:
    """``batch``'s episodes side by side, as sb3-contrib's recurrent policies take sequences:
    each padded to the longest by repeating its last row (the padding is masked out), an
    empty memory per sequence, the sequences' starts (the memory is emptied there), and the
    mask of the real rows (in ``batch``'s order)."""
    import torch
    from sb3_contrib.common.recurrent.type_aliases import RNNStates

    episodes = batch.episode_slices()
    length = max(episode.stop - episode.start for episode in episodes)
    index = np.concatenate(
        [np.minimum(np.arange(e.start, e.start + length), e.stop - 1) for e in episodes]
    )
    real = np.concatenate([np.arange(length) < e.stop - e.start for e in episodes])
    shape = list(policy.lstm_hidden_state_shape)  # (layers, sequences, hidden)
    shape[1] = len(episodes)

    def empty() -> tuple[Any, Any]:
        return torch.zeros(shape, device=policy.device), torch.zeros(shape, device=policy.device)

    starts = np.tile(np.arange(length) == 0, len(episodes)).astype(np.float32)
    return (
        batch.rows(index),
        RNNStates(empty(), empty()),
        torch.as_tensor(starts, device=policy.device),
        torch.as_tensor(real, device=policy.device),
    )


def _evaluate_actions(policy: Any, batch: Demonstrations) -> tuple[Any, Any, Any]:
    """The values, log-likelihoods of the teacher's probes and entropies over ``batch``."""
    import torch

    if not is_recurrent(policy):
        observations, _ = policy.obs_to_tensor(batch.observations)
        actions = torch.as_tensor(batch.actions, device=policy.device)
        return policy.evaluate_actions(observations, actions)
    padded, states, starts, real = _as_sequences(policy, batch)
    observations, _ = policy.obs_to_tensor(padded.observations)
    actions = torch.as_tensor(padded.actions, device=policy.device)
    values, log_prob, entropy = policy.evaluate_actions(observations, actions, states, starts)
    return values[real], log_prob[real], entropy[real]


def _modes(policy: Any, batch: Demonstrations) -> np.ndarray:
    """The policy's most likely probe at each row of ``batch`` (whole episodes for a
    recurrent one)."""
    if not is_recurrent(policy):
        observations, _ = policy.obs_to_tensor(batch.observations)
        return policy.get_distribution(observations).mode().cpu().numpy()
    padded, states, starts, real = _as_sequences(policy, batch)
    observations, _ = policy.obs_to_tensor(padded.observations)
    distribution, _ = policy.get_distribution(observations, states.pi, starts)
    return distribution.mode()[real].cpu().numpy()


def agreement(policy: Any, demonstrations: Demonstrations, batch_size: int = 512) -> dict:
    """How often the policy's mode is the teacher's action on ``demonstrations``: the whole
    action (``probe``) and each index (``lane``, ``depth``, ``sweep``), as fractions. Where
    the actions claim (a fourth entry), a claim is one action whatever probe entries it
    carries (a claim makes no motion): ``probe`` counts a claim for a claim and the same
    probe for a probe, ``claim`` how often the two agree on claiming, and the indices are
    over the teacher's probes alone."""
    import torch

    if len(demonstrations) == 0:
        raise ValueError("agreement needs at least one demonstration")
    policy.set_training_mode(False)
    modes = []
    with torch.no_grad():
        for index in _in_order(policy, demonstrations, batch_size):
            batch = demonstrations.rows(index)
            modes.append(_modes(policy, batch).reshape(batch.actions.shape))
    return matching(np.concatenate(modes), demonstrations.actions)


def matching(modes: np.ndarray, actions: np.ndarray) -> dict:
    """``agreement``'s fractions of the policy's ``modes`` against the teacher's ``actions``
    (rows of 3 entries, or 4 where the actions claim)."""
    equal = modes == actions
    if equal.shape[1] == 3:
        fractions = {
            name: float(equal[:, i].mean()) for i, name in enumerate(("lane", "depth", "sweep"))
        }
        return {"probe": float(equal.all(axis=1).mean()), **fractions}
    claims = actions[:, 3] == 1
    same_claim = equal[:, 3]
    same = same_claim & (claims | equal[:, :3].all(axis=1))
    probes = equal[~claims, :3]
    fractions = {
        name: float(probes[:, i].mean())
        for i, name in enumerate(("lane", "depth", "sweep"))
        if len(probes)  # none where the teacher only claimed
    }
    return {"probe": float(same.mean()), "claim": float(same_claim.mean()), **fractions}
