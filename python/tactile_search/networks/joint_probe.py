"""A policy whose probe is one categorical over every (lane, depth, sweep) of the grid.

SB3 gives a ``MultiDiscrete`` action space a factorised distribution: one independent
categorical per index, so a policy that wants "lane 3 turning right, or lane 20 turning
left" also samples lane 3 turning left. The probe planner's choices are exactly such joint
modes (the side to turn depends on the lane; the depth on both), so a policy cloned from it
needs the joint: ``JointCategoricalDistribution`` has one logit per probe (29 x 10 x 9 at the
defaults) and maps between a probe's index in that list and its ``(lane, depth, sweep)``
action, and ``JointProbePolicy`` is SB3's ``MultiInputPolicy`` with it as its action head.
Everything else (encoder, value head, PPO's losses) is SB3's own.

Where the task claims (``MultiDiscrete([lanes, depths, sweeps, 2])``), a claim makes no
motion: its probe entries mean nothing. ``ProbeOrClaimDistribution`` is then one categorical
over every probe and one outcome more, the claim: every action whose claim entry is 1 is
that one outcome (its log-probability does not depend on the probe entries it carries), and
a sampled claim is ``[0, 0, 0, 1]``.
"""

from __future__ import annotations

import math
from typing import Any, cast

import torch
from gymnasium import spaces
from stable_baselines3.common.distributions import MultiCategoricalDistribution
from stable_baselines3.common.policies import MultiInputActorCriticPolicy
from torch import nn
from torch.distributions import Categorical


class Float32Linear(nn.Linear):
    """``nn.Linear`` that computes in float32 even under autocast: the layer that makes a
    policy's logits, so an update under bfloat16 autocast does not round PPO's
    probability ratios. Its parameters are a ``Linear``'s, under the same names."""

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        with torch.autocast("cpu", enabled=False):
            return super().forward(x.float())


class JointCategoricalDistribution(MultiCategoricalDistribution):
    """One categorical over the product of ``action_dims``; actions are their index tuples
    (row-major, as ``numpy.ravel_multi_index``)."""

    def __init__(self, action_dims: list[int]) -> None:
        super().__init__(action_dims)
        dims = [int(n) for n in action_dims]
        # The place value of each index in the joint index (row-major).
        self._strides = [math.prod(dims[i + 1 :]) for i in range(len(dims))]
        self._dims = dims

    def proba_distribution_net(self, latent_dim: int) -> nn.Module:
        return Float32Linear(latent_dim, math.prod(self._dims))

    def proba_distribution(self, action_logits: torch.Tensor) -> JointCategoricalDistribution:
        # float32 under autocast too: log-probabilities of ~2,600 probes in bfloat16 would
        # round PPO's ratios by a few percent.
        with torch.autocast("cpu", enabled=False):
            self.distribution = Categorical(logits=action_logits.float())  # type: ignore[assignment]
        return self

    def joint_index(self, actions: torch.Tensor) -> torch.Tensor:
        """The joint index of each ``(batch, len(action_dims))`` action."""
        strides = torch.as_tensor(self._strides, device=actions.device)
        return (actions.long() * strides).sum(dim=1)

    def actions_of(self, index: torch.Tensor) -> torch.Tensor:
        """The index tuple of each joint ``index``."""
        return torch.stack(
            [(index // stride) % n for stride, n in zip(self._strides, self._dims, strict=True)],
            dim=1,
        )

    @property
    def joint(self) -> Categorical:
        """The one categorical over every joint index (held in SB3's ``distribution``, which
        its multi-categorical base types as a list of categoricals)."""
        return cast(Categorical, self.distribution)

    # Typed here: torch.distributions leaves its methods unannotated (Any).
    def log_prob(self, actions: torch.Tensor) -> torch.Tensor:
        log_prob: torch.Tensor = self.joint.log_prob(self.joint_index(actions))
        return log_prob

    def entropy(self) -> torch.Tensor:
        entropy: torch.Tensor = self.joint.entropy()
        return entropy

    def sample(self) -> torch.Tensor:
        return self.actions_of(self.joint.sample())

    def mode(self) -> torch.Tensor:
        return self.actions_of(torch.argmax(self.joint.probs, dim=1))


class ProbeOrClaimDistribution(JointCategoricalDistribution):
    """One categorical over every probe of ``action_dims[:3]`` (row-major) and, last, the
    claim (``action_dims[3]`` must be 2): see the module docs."""

    def __init__(self, action_dims: list[int]) -> None:
        dims = [int(n) for n in action_dims]
        if len(dims) != 4 or dims[3] != 2:
            raise ValueError(
                "ProbeOrClaimDistribution needs [lanes, depths, sweeps, 2] (a claim entry of "
                f"two values), got {dims}"
            )
        super().__init__(dims)
        #: The probes' count: the claim's index in the categorical.
        self.probes = math.prod(dims[:3])

    def proba_distribution_net(self, latent_dim: int) -> nn.Module:
        return Float32Linear(latent_dim, self.probes + 1)

    def joint_index(self, actions: torch.Tensor) -> torch.Tensor:
        actions = actions.long()
        strides = torch.as_tensor(self._strides[:3], device=actions.device) // 2
        probe = (actions[:, :3] * strides).sum(dim=1)
        return torch.where(actions[:, 3] == 1, self.probes, probe)

    def actions_of(self, index: torch.Tensor) -> torch.Tensor:
        strides = [stride // 2 for stride in self._strides[:3]]
        claims = index == self.probes
        probe = torch.where(claims, 0, index)
        entries = [(probe // stride) % n for stride, n in zip(strides, self._dims[:3], strict=True)]
        return torch.stack([*entries, claims.long()], dim=1)


def probe_distribution(action_dims: list[int]) -> JointCategoricalDistribution:
    """The joint distribution of a probe action space of ``action_dims``: over every probe
    (``[lanes, depths, sweeps]``), or every probe and the claim (``[..., 2]``)."""
    if len(action_dims) == 4:
        return ProbeOrClaimDistribution(action_dims)
    return JointCategoricalDistribution(action_dims)


class JointProbePolicy(MultiInputActorCriticPolicy):
    """SB3's ``MultiInputPolicy`` with ``JointCategoricalDistribution`` (or, where the
    action claims, ``ProbeOrClaimDistribution``) as its action head; for ``MultiDiscrete``
    action spaces only."""

    def __init__(self, observation_space: Any, action_space: Any, *args: Any, **kwargs: Any):
        from gymnasium import spaces

        if not isinstance(action_space, spaces.MultiDiscrete):
            raise ValueError(
                f"JointProbePolicy needs a MultiDiscrete action space (the probe mode), got "
                f"{action_space}"
            )
        super().__init__(observation_space, action_space, *args, **kwargs)

    def _build(self, lr_schedule: Any) -> None:
        # A MultiDiscrete action space (checked in __init__).
        nvec = cast(spaces.MultiDiscrete, self.action_space).nvec
        self.action_dist = probe_distribution([int(n) for n in nvec])
        super()._build(lr_schedule)
