"""The evaluation's tables and plots: the markdown results table, success rates, steps to
success and the learning curves read from each run's ``progress.csv``."""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from agents.run_dir import progress_rows
from tactile_search.benchmark.statistics import Summary
from tactile_search.benchmark.summary_table import summary_cells, summary_columns
from tactile_search.envs.config import markdown_table as config_markdown_table


def markdown_table(summaries: Sequence[Summary], task: str = "search") -> str:
    """The results as a markdown table: the search task's columns, or another task's own
    (``summary_table``: the identify task's wrong claims, the map task's scores in place of
    a success it does not have) beside the jars displaced and the map's IoU."""
    if task != "search":
        return _task_table(summaries, task)
    lines = [
        "| agent | map | episodes | success | 95 % CI | steps to success, median [Q1, Q3] "
        "| jar displacement (mm, sum over jars) | in successful episodes (mm) "
        "| largest jar displacement (mm) | episodes with a tip "
        "| final map IoU (the map's own reading) |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for s in summaries:
        steps = (
            "-"
            if math.isnan(s.steps_median)
            else f"{s.steps_median:.0f} [{s.steps_q1:.0f}, {s.steps_q3:.0f}]"
        )
        in_successes = (
            "-" if math.isnan(s.success_displacement_mm) else f"{s.success_displacement_mm:.1f}"
        )
        lines.append(
            f"| {s.agent} | {s.map_mode} | {s.episodes} | {s.success_rate:.1%} "
            f"| [{s.success_low:.1%}, {s.success_high:.1%}] | {steps} "
            f"| {s.displacement_mm:.1f} | {in_successes} | {s.max_displacement_mm:.1f} "
            f"| {s.tip_rate:.1%} "
            f"| {_iou_text(s)} |"
        )
    return "\n".join(lines) + "\n"


def _iou_text(summary: Summary) -> str:
    return "-" if summary.map_mode == "none" else f"{summary.iou:.3f}"


def _task_table(summaries: Sequence[Summary], task: str) -> str:
    columns = [
        "agent",
        "map",
        "episodes",
        *summary_columns(task),
        "jar displacement (mm, sum over jars)",
        "largest jar displacement (mm)",
        "final map IoU (the map's own reading)",
    ]
    rows = [
        [
            s.agent,
            s.map_mode,
            str(s.episodes),
            *summary_cells(task, dataclasses.asdict(s)),
            f"{s.displacement_mm:.1f}",
            f"{s.max_displacement_mm:.1f}",
            _iou_text(s),
        ]
        for s in summaries
    ]
    return config_markdown_table(columns, rows) + "\n"


def plot_success(path: Path, summaries: Sequence[Summary]) -> None:
    """Success rate per agent with its 95 % interval."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(1.2 + 1.3 * len(summaries), 3.6))
    x = np.arange(len(summaries))
    rates = [s.success_rate for s in summaries]
    errors = [
        [s.success_rate - s.success_low for s in summaries],
        [s.success_high - s.success_rate for s in summaries],
    ]
    ax.bar(x, rates, yerr=errors, capsize=5, color="tab:blue", alpha=0.8)
    ax.set_xticks(x, [s.agent for s in summaries], rotation=20, ha="right")
    ax.set_ylim(0, 1.05)
    ax.set_ylabel("success rate (95 % CI)")
    ax.set_title(f"{summaries[0].episodes} held-out episodes per agent")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def plot_steps(path: Path, agents: Sequence[str], episodes: Sequence[Sequence[dict]]) -> None:
    """Steps to success per agent (successful episodes only)."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(1.2 + 1.3 * len(agents), 3.6))
    data = [[e["steps"] for e in runs if e["success"]] or [math.nan] for runs in episodes]
    ax.boxplot(data)
    ax.set_xticks(range(1, len(agents) + 1), agents, rotation=20, ha="right")
    ax.set_ylabel("steps to success")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def read_progress(run_dir: Path) -> dict[str, np.ndarray]:
    """``timesteps`` and ``success_rate`` columns of a run's ``progress.csv``; both empty for
    a run that has none (one cloned from the planner, ``agents.imitate``, trains no RL)."""
    timesteps, success = [], []
    for row in progress_rows(run_dir):
        if row.get("rollout/success_rate") not in (None, ""):
            timesteps.append(float(row["time/total_timesteps"]))
            success.append(float(row["rollout/success_rate"]))
    return {"timesteps": np.array(timesteps), "success_rate": np.array(success)}


def plot_learning_curves(path: Path, runs: Sequence[tuple[str, Path]]) -> list[str]:
    """Training success rate (last 100 episodes) against timesteps, per learned run, given
    as (agent, run directory): an agent's training seeds share a colour (one legend entry per
    agent). Returns the legend's entries."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 3.6))
    colours: dict[str, str] = {}
    for agent, run_dir in runs:
        first = agent not in colours
        colours.setdefault(agent, f"C{len(colours) % 10}")
        curve = read_progress(run_dir)
        ax.plot(
            curve["timesteps"],
            curve["success_rate"],
            color=colours[agent],
            alpha=0.8,
            label=agent if first else None,
        )
    ax.set_xlabel("training timesteps")
    ax.set_ylabel("success rate (last 100 episodes)")
    ax.set_ylim(0, 1.05)
    if runs:
        ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return list(colours)
