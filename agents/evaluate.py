"""Evaluate trained models and scripted baselines on held-out layouts.

Importable functions under a thin CLI::

    python -m agents.evaluate --runs runs/ppo_gpis_seed0 runs/ppo_none_seed0 \\
        --scripted random gpis_planner oracle --episodes 200 --out results

Every agent meets the same held-out layouts: seeds ``EVAL_SEED_START ...`` (below 2**32,
never drawn in training: ``agents.train.TRAIN_LAYOUT_SEEDS``), in the environment's default
reward (no shaping) with the map mode the agent was trained with (scripted agents use the
GPIS map). Writes to ``--out``:

- ``results.md``: the table (success rate with its 95 % Wilson interval, steps to success
  as median and quartiles, jar displacement, tips, final map IoU);
- ``episodes.csv``: one row per agent and episode;
- ``success.png``, ``steps.png``, ``learning_curves.png`` (from each run's ``progress.csv``);
- ``gifs/<agent>.gif``: one example episode per agent (the first held-out seed).
"""

from __future__ import annotations

import argparse
import csv
import math
import statistics
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

import tactile_search  # noqa: F401  (registers the environment)
from agents.scripted import SCRIPTED_AGENTS
from agents.scripted.rollout import run_episodes
from agents.train import TRAIN_LAYOUT_SEEDS

EVAL_SEED_START = 1_000_000
assert EVAL_SEED_START + 100_000 < TRAIN_LAYOUT_SEEDS[0]
# The z of a two-sided 95 % interval.
Z_95 = 1.959963984540054


@dataclass(frozen=True)
class Summary:
    """One agent's results over the held-out episodes."""

    agent: str
    map_mode: str
    episodes: int
    successes: int
    success_low: float
    success_high: float
    steps_median: float
    steps_q1: float
    steps_q3: float
    displacement_mm: float
    max_displacement_mm: float
    tip_rate: float
    iou: float

    @property
    def success_rate(self) -> float:
        return self.successes / self.episodes


def wilson_interval(successes: int, n: int, z: float = Z_95) -> tuple[float, float]:
    """The Wilson score interval of a binomial proportion (95 % by default)."""
    if n <= 0:
        raise ValueError(f"n must be positive, got {n}")
    if not 0 <= successes <= n:
        raise ValueError(f"successes must be in [0, {n}], got {successes}")
    p = successes / n
    denominator = 1 + z * z / n
    centre = (p + z * z / (2 * n)) / denominator
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / denominator
    # The interval always holds p (at p = 0 or 1 rounding could leave it a hair outside).
    return max(0.0, min(p, centre - half)), min(1.0, max(p, centre + half))


def held_out_seeds(episodes: int) -> list[int]:
    """The first ``episodes`` held-out layout seeds."""
    if episodes < 1:
        raise ValueError(f"episodes must be >= 1, got {episodes}")
    return list(range(EVAL_SEED_START, EVAL_SEED_START + episodes))


def summarize(agent: str, map_mode: str, episodes: Sequence[dict[str, Any]]) -> Summary:
    """The table row of one agent's per-episode results (``run_episodes`` dicts)."""
    n = len(episodes)
    successes = sum(bool(e["success"]) for e in episodes)
    low, high = wilson_interval(successes, n)
    steps = sorted(e["steps"] for e in episodes if e["success"])
    if len(steps) >= 2:
        q1, median, q3 = statistics.quantiles(steps, n=4, method="inclusive")
    elif steps:
        q1 = median = q3 = float(steps[0])
    else:
        q1 = median = q3 = math.nan
    return Summary(
        agent=agent,
        map_mode=map_mode,
        episodes=n,
        successes=successes,
        success_low=low,
        success_high=high,
        steps_median=median,
        steps_q1=q1,
        steps_q3=q3,
        displacement_mm=1000 * statistics.fmean(e["jar_displacement"] for e in episodes),
        max_displacement_mm=1000 * statistics.fmean(e["max_jar_displacement"] for e in episodes),
        tip_rate=statistics.fmean(e["tips"] > 0 for e in episodes),
        iou=statistics.fmean(e["iou"] for e in episodes),
    )


def markdown_table(summaries: Sequence[Summary]) -> str:
    """The results as a markdown table."""
    lines = [
        "| agent | map | episodes | success | 95 % CI | steps to success, median [Q1, Q3] "
        "| jar displacement (mm, sum over jars) | largest jar displacement (mm) "
        "| episodes with a tip | final map IoU |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for s in summaries:
        steps = (
            "-"
            if math.isnan(s.steps_median)
            else f"{s.steps_median:.0f} [{s.steps_q1:.0f}, {s.steps_q3:.0f}]"
        )
        iou = "-" if s.map_mode == "none" else f"{s.iou:.3f}"
        lines.append(
            f"| {s.agent} | {s.map_mode} | {s.episodes} | {s.success_rate:.1%} "
            f"| [{s.success_low:.1%}, {s.success_high:.1%}] | {steps} "
            f"| {s.displacement_mm:.1f} | {s.max_displacement_mm:.1f} | {s.tip_rate:.1%} "
            f"| {iou} |"
        )
    return "\n".join(lines) + "\n"


def make_agent(spec: str) -> tuple[Any, str]:
    """An agent and its map mode from a scripted name or a run directory."""
    if spec in SCRIPTED_AGENTS:
        return SCRIPTED_AGENTS[spec](), "gpis"
    from agents.learned import LearnedAgent

    agent = LearnedAgent(Path(spec))
    return agent, agent.map_mode


def write_episodes_csv(path: Path, rows: Sequence[dict[str, Any]]) -> None:
    """Per-episode rows (agent, map, seed, metrics)."""
    with path.open("w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)


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
    """``timesteps`` and ``success_rate`` columns of a run's ``progress.csv``."""
    with (Path(run_dir) / "progress.csv").open() as f:
        rows = list(csv.DictReader(f))
    timesteps, success = [], []
    for row in rows:
        if row.get("rollout/success_rate") not in (None, ""):
            timesteps.append(float(row["time/total_timesteps"]))
            success.append(float(row["rollout/success_rate"]))
    return {"timesteps": np.array(timesteps), "success_rate": np.array(success)}


def plot_learning_curves(path: Path, runs: dict[str, Path]) -> None:
    """Training success rate (last 100 episodes) against timesteps, per learned agent."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 3.6))
    for name, run_dir in runs.items():
        curve = read_progress(run_dir)
        ax.plot(curve["timesteps"], curve["success_rate"], label=name)
    ax.set_xlabel("training timesteps")
    ax.set_ylabel("success rate (last 100 episodes)")
    ax.set_ylim(0, 1.05)
    if runs:
        ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def record_gif(
    path: Path, agent: Any, map_mode: str, seed: int, max_steps: int = 200, stride: int = 2
) -> None:
    """The first ``max_steps`` steps of ``agent`` on layout ``seed`` as a GIF, one frame every
    ``stride`` steps plus the last (a frame takes ~0.2 s to draw)."""
    from tactile_search.render import save_gif

    frames: list[np.ndarray] = []

    def capture(env: Any, step: int, done: bool) -> None:
        if step % stride == 0 or done:
            frames.append(env.render())

    run_episodes(
        agent, [seed], max_steps=max_steps, on_step=capture, map=map_mode, render_mode="rgb_array"
    )
    save_gif(frames, path)


def evaluate(
    agent_specs: Sequence[str],
    *,
    out: Path = Path("results"),
    episodes: int = 200,
    gifs: bool = True,
    gif_steps: int = 200,
    torch_threads: int = 1,
) -> list[Summary]:
    """Runs every agent on the same held-out layouts and writes the table, plots and GIFs.

    ``agent_specs``: scripted agent names (``random``, ``gpis_planner``, ``oracle``) and run
    directories of ``agents.train``. ``gif_steps`` caps the steps an example GIF shows.
    ``torch_threads``: one thread predicts a single observation fastest (more threads only
    add synchronisation, and spin against anything else running).
    """
    if not agent_specs:
        raise ValueError("give at least one agent (a scripted name or a run directory)")
    if any(spec not in SCRIPTED_AGENTS for spec in agent_specs):
        import torch

        torch.set_num_threads(torch_threads)
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    seeds = held_out_seeds(episodes)
    summaries, all_episodes, rows, names = [], [], [], []
    runs: dict[str, Path] = {}
    for spec in agent_specs:
        agent, map_mode = make_agent(spec)
        results = run_episodes(agent, seeds, map=map_mode)
        summaries.append(summarize(agent.name, map_mode, results))
        all_episodes.append(results)
        names.append(agent.name)
        rows += [{"agent": agent.name, "map": map_mode, **r} for r in results]
        if spec not in SCRIPTED_AGENTS:
            runs[agent.name] = Path(spec)
        if gifs:
            (out / "gifs").mkdir(exist_ok=True)
            file_name = agent.name.replace(" ", "_").replace("(", "").replace(")", "")
            gif_path = out / "gifs" / f"{file_name}.gif"
            record_gif(gif_path, agent, map_mode, seeds[0], max_steps=gif_steps)
        print(markdown_table(summaries[-1:]).splitlines()[-1], flush=True)
    table = markdown_table(summaries)
    (out / "results.md").write_text(
        f"Held-out layout seeds {seeds[0]}..{seeds[-1]} ({episodes} per agent).\n\n{table}"
    )
    write_episodes_csv(out / "episodes.csv", rows)
    plot_success(out / "success.png", summaries)
    plot_steps(out / "steps.png", names, all_episodes)
    plot_learning_curves(out / "learning_curves.png", runs)
    return summaries


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--runs", nargs="*", default=[], help="run directories of agents.train")
    parser.add_argument(
        "--scripted",
        nargs="*",
        default=list(SCRIPTED_AGENTS),
        choices=list(SCRIPTED_AGENTS),
        help="scripted baselines to include",
    )
    parser.add_argument("--episodes", type=int, default=200)
    parser.add_argument("--out", type=Path, default=Path("results"))
    parser.add_argument("--no-gifs", action="store_true")
    parser.add_argument("--gif-steps", type=int, default=200, help="steps shown per GIF")
    args = parser.parse_args(argv)
    summaries = evaluate(
        [*args.runs, *args.scripted],
        out=args.out,
        episodes=args.episodes,
        gifs=not args.no_gifs,
        gif_steps=args.gif_steps,
    )
    print(markdown_table(summaries))


if __name__ == "__main__":
    main()
