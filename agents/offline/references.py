"""The reference scores that normalise a dataset's returns (Minari's ``ref_min_score`` and
``ref_max_score``, ``minari.get_normalized_score``): the mean episode return of the task's
random baseline and of its oracle, each in its own action mode and map over the registered
id's settings, on the same training layouts.

An episode's return is comparable across action modes: a probe's reward is the sum of its
wrist motions' (``docs/DESIGN.md`` §4.1). The map task's oracle reads the true jars; the
search and identify oracle follows the core's oracle path in the wrist mode.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import gymnasium
import numpy as np

from agents.evaluation.agent_specs import make_agent
from agents.evaluation.evaluation import task_of
from agents.offline.recording import agent_settings, check_training_seeds
from agents.rollout import run_episodes

#: Each task's bounds: (the random baseline, the oracle).
REFERENCE_AGENTS: dict[str, tuple[str, str]] = {
    "search": ("random", "oracle"),
    "identify": ("random_identify", "oracle"),
    "map": ("random_map", "map_oracle"),
}


@dataclass(frozen=True)
class ReferenceScores:
    """The mean returns bounding a task's scores and who made them, on ``episodes``
    layouts."""

    min_agent: str
    min_score: float
    max_agent: str
    max_score: float
    episodes: int


def mean_return(agent_spec: str, env_id: str, seeds: Sequence[int]) -> float:
    """The mean episode return of scripted agent ``agent_spec`` on registered id ``env_id``
    (its own map and action mode over the id's settings) on the training layouts ``seeds``."""
    check_training_seeds(seeds)
    agent, agent_kwargs = make_agent(agent_spec)
    settings = {**gymnasium.spec(env_id).kwargs, **agent_settings(env_id, agent_kwargs)}
    rows = run_episodes(agent, list(seeds), **settings)
    return float(np.mean([row["reward"] for row in rows]))


def reference_scores(env_id: str, seeds: Sequence[int]) -> ReferenceScores:
    """The random baseline's and the oracle's mean returns on ``env_id`` (``REFERENCE_AGENTS``
    of its task) on ``seeds``."""
    low, high = REFERENCE_AGENTS[task_of(env_id)]
    return ReferenceScores(
        min_agent=low,
        min_score=mean_return(low, env_id, seeds),
        max_agent=high,
        max_score=mean_return(high, env_id, seeds),
        episodes=len(seeds),
    )
