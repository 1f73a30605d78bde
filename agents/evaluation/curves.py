"""A task's results at a glance: each agent's success against the wrist motions it spent, with
intervals (``docs/results/<task>/curves.png``, written by the pipeline for every task).

- A task with success (search, identify): for each budget of k motions, the share of
  episodes that succeeded within k motions, pooled over training seeds and layouts, with a
  95 % bootstrap band (``agents.evaluation.comparison.pooled_interval``: the layouts and each
  agent's training seeds resampled, the same draws at every k). The curve's right end is the
  agent's success; how fast it rises is how soon it finds the target.
- The map task (no episode succeeds: each runs its budget of motions): the outline distance
  against the motions spent (the rows' ``map_score_curve``,
  ``tactile_search.benchmark.map_curve``), pooled with its 95 % bootstrap band the same way;
  the lower and the sooner, the better.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from agents.evaluation.comparison import (
    TASK_MEASURES,
    AgentResults,
    agent_results,
    pooled_interval,
)
from tactile_search.benchmark.map_curve import MAP_CURVE_POINTS

# Bootstrap samples per point of a curve: a band's edge moves by well under a point between
# two draws of this many.
CURVE_SAMPLES = 2_000

# Points per curve: motion budgets evenly spaced from 0 to the longest episode.
CURVE_POINTS = 60


def pooled_band(
    matrices: list[np.ndarray], samples: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Each (seeds x layouts) matrix's pooled mean and 95 % bootstrap interval
    (``comparison.pooled_interval``: the same resampled layouts and seeds for each), as
    arrays along ``matrices``."""
    mean, low, high = zip(*(pooled_interval(matrix, samples) for matrix in matrices), strict=True)
    return np.array(mean), np.array(low), np.array(high)


def success_within(results: AgentResults, budget: float) -> np.ndarray:
    """The (seeds x layouts) 0/1 matrix of the episodes that succeeded within ``budget``
    wrist motions."""
    return results.success * (results.motions <= budget)


def success_curve(
    results: AgentResults, budgets: np.ndarray, samples: int = CURVE_SAMPLES
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """For each motion budget, the pooled share of episodes succeeded within it and its 95 %
    bootstrap interval (the same resampled layouts and seeds at every budget)."""
    return pooled_band([success_within(results, float(budget)) for budget in budgets], samples)


def map_score_curve(
    results: AgentResults, samples: int = CURVE_SAMPLES
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The map task's outline distance at each fraction of the budget (``MAP_CURVE_POINTS``
    from 0 to 1), pooled over training seeds and layouts, with its 95 % bootstrap interval
    (the same resampled layouts and seeds at every point)."""
    curves = results.map_curves  # (seeds, layouts, points)
    if curves is None:
        raise ValueError(f"{results.agent}'s rows hold no map score curve (not the map task's)")
    fractions = np.linspace(0.0, 1.0, MAP_CURVE_POINTS)
    return fractions, *pooled_band(
        [curves[:, :, point] for point in range(MAP_CURVE_POINTS)], samples
    )


def plot_curves(
    path: Path, rows: Sequence[dict[str, Any]], task: str, samples: int = CURVE_SAMPLES
) -> None:
    """Writes ``task``'s figure of the evaluation ``rows`` (``episodes.csv``'s) to ``path``."""
    if task not in TASK_MEASURES:
        raise ValueError(f"task must be one of {sorted(TASK_MEASURES)}, got {task!r}")
    results = agent_results(rows)
    if not results:
        raise ValueError("plot_curves needs the rows of at least one agent, got none")
    import matplotlib.pyplot as plt

    if "success" in TASK_MEASURES[task]:
        fig, ax = plt.subplots(figsize=(9.0, 4.2))
        longest = max(float(r.motions.max()) for r in results.values())
        budgets = np.linspace(0.0, longest, CURVE_POINTS)
        for index, (agent, r) in enumerate(results.items()):
            mean, low, high = success_curve(r, budgets, samples)
            colour = f"C{index % 10}"
            ax.plot(budgets, mean, color=colour, label=agent)
            ax.fill_between(budgets, low, high, color=colour, alpha=0.2, linewidth=0)
        ax.set_xlabel("wrist motions")
        ax.set_ylabel("episodes succeeded within (95 % CI)")
        ax.set_ylim(0, 1.02)
    else:
        fig, ax = plt.subplots(figsize=(9.0, 4.2))
        for index, (agent, r) in enumerate(results.items()):
            fractions, mean, low, high = map_score_curve(r, samples)
            colour = f"C{index % 10}"
            ax.plot(100 * fractions, mean, color=colour, label=agent)
            ax.fill_between(100 * fractions, low, high, color=colour, alpha=0.2, linewidth=0)
        ax.set_xlabel("wrist motions spent (% of the episode's budget)")
        # The axis spans the agents' distances (not from 0): they differ by a few mm of ~18.
        ax.set_ylabel("outline distance, mm (95 % CI; lower is better)")
    ax.legend(fontsize=7, loc="center left", bbox_to_anchor=(1.0, 0.5), frameon=False)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
