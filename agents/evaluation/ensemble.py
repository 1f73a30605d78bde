"""Several training seeds of one probe-mode agent acting as one: their probe probabilities
averaged, the most probable probe taken.

The learned agents' failures are mostly their own: on the validation layouts, the three GPIS
seeds and the planner each miss a few layouts the others solve (``agents.comparison
--overlap``). An ensemble measures how much of that is variance between training seeds that
averaging removes, the first question before distilling an ensemble into one policy. Given
to ``agents.evaluate`` as one spec, ``ensemble:RUN,RUN,...``::

    python -m agents.evaluate --runs ensemble:docs/results/models/ppo_gpis_seed0,\\
    docs/results/models/ppo_gpis_seed1,docs/results/models/ppo_gpis_seed2 --scripted

Members must be runs of the same algorithm, map and env settings, with a policy that holds
one categorical over every probe (``tactile_search.networks.joint_probe``: the spatial probe
policy and the joint probe policy); the ensemble takes the mode of the averaged distribution.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

ENSEMBLE_PREFIX = "ensemble:"


def ensemble_members(spec: str) -> list[Path] | None:
    """The run directories of an ``ensemble:RUN,RUN,...`` spec, or None for another spec;
    ``ValueError`` for an ensemble of fewer than two runs."""
    if not spec.startswith(ENSEMBLE_PREFIX):
        return None
    members = [Path(part) for part in spec[len(ENSEMBLE_PREFIX) :].split(",") if part.strip()]
    if len(members) < 2:
        raise ValueError(
            f"an ensemble is ensemble:RUN,RUN[,...] with two runs or more, got {spec!r}"
        )
    return members


class EnsembleAgent:
    """``members`` (``LearnedAgent`` s of one agent) by the mode of their averaged probe
    probabilities. ``name``: the members' own name and their number."""

    def __init__(self, members: Sequence[Any]) -> None:
        from tactile_search.networks.joint_probe import JointCategoricalDistribution

        first = members[0]
        for member in members:
            if member.env_kwargs != first.env_kwargs or member.name != first.name:
                raise ValueError(
                    "an ensemble's runs must be one agent with the same env settings, got "
                    f"{first.name} {first.env_kwargs} and {member.name} {member.env_kwargs}"
                )
            if not isinstance(member.model.policy.action_dist, JointCategoricalDistribution):
                raise ValueError(
                    f"an ensemble averages one categorical over every probe; {member.name}'s "
                    f"policy has {type(member.model.policy.action_dist).__name__}"
                )
        self.members = list(members)
        self.env_kwargs: dict[str, Any] = first.env_kwargs
        self.map_mode: str = first.map_mode
        self.name = f"{first.name[:-1]}, ensemble of {len(members)})"

    @classmethod
    def from_spec(cls, spec: str) -> EnsembleAgent:
        """The ensemble of an ``ensemble:RUN,RUN,...`` spec, each run loaded to act by its
        mode; ``ValueError`` for another spec."""
        from agents.sb3.learned import LearnedAgent

        members = ensemble_members(spec)
        if members is None:
            raise ValueError(f"an ensemble is {ENSEMBLE_PREFIX}RUN,RUN[,...], got {spec!r}")
        return cls([LearnedAgent(member, deterministic=True) for member in members])

    def reset(self, env: Any, observation: dict, info: dict) -> None:
        for member in self.members:
            member.reset(env, observation, info)

    def act(self, observation: dict) -> np.ndarray:
        import torch

        probabilities = []
        with torch.no_grad():
            for member in self.members:
                policy = member.model.policy
                tensor, _ = policy.obs_to_tensor(observation)
                distribution = policy.get_distribution(tensor)
                probabilities.append(distribution.distribution.probs)
            mean = torch.stack(probabilities).mean(dim=0)
            probe = distribution.actions_of(torch.argmax(mean, dim=1))
        return probe.reshape(3).numpy().astype(np.int64)
