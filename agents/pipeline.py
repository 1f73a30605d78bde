"""The end-to-end pipeline: train the learned agents, evaluate them with the scripted
baselines on held-out layouts, write the results.

Two budgets::

    python -m agents.pipeline --budget demo     # make demo: ~10 min of training, results/
    python -m agents.pipeline --budget full     # make results: docs/RESULTS.md

``demo`` trains the GPIS-map and the no-map PPO agents briefly and evaluates on 50
layouts; ``full`` trains every learned agent (PPO with each map mode and the recurrent
no-map agent) at its recipe's ``n_timesteps`` and evaluates on 200 layouts. A run whose
``model.zip`` already exists is reused, so an interrupted pipeline picks up where it stopped
(delete the run directory to retrain).
"""

from __future__ import annotations

import argparse
import time
from dataclasses import dataclass
from pathlib import Path

import yaml

from agents.evaluate import EVAL_SEED_START, evaluate, markdown_table
from agents.train import load_hyperparams, run_name, train


@dataclass(frozen=True)
class Budget:
    """What one budget trains and how many held-out episodes it evaluates."""

    agents: tuple[tuple[str, str], ...]
    timesteps: int | None  # None: each recipe's n_timesteps
    episodes: int
    runs: Path
    results: Path


BUDGETS = {
    "demo": Budget(
        agents=(("ppo", "gpis"), ("ppo", "none")),
        timesteps=150_000,
        episodes=50,
        runs=Path("runs/demo"),
        results=Path("results"),
    ),
    "full": Budget(
        agents=(("ppo", "gpis"), ("ppo", "occupancy"), ("ppo", "none"), ("recurrent_ppo", "none")),
        timesteps=None,
        episodes=200,
        runs=Path("runs/full"),
        results=Path("docs/results"),
    ),
}
SCRIPTED = ("random", "gpis_planner", "oracle")


def train_all(budget: Budget, seed: int, progress_bar: bool) -> list[Path]:
    """Trains (or reuses) every learned agent of ``budget``; returns the run directories."""
    run_dirs = []
    for algo, map_mode in budget.agents:
        run_dir = budget.runs / run_name(algo, map_mode, seed)
        if (run_dir / "model.zip").is_file():
            print(f"reusing {run_dir}", flush=True)
        else:
            print(f"training {algo} with the {map_mode} map", flush=True)
            train(
                algo,
                map_mode,
                out=budget.runs,
                seed=seed,
                timesteps=budget.timesteps,
                progress_bar=progress_bar,
            )
        run_dirs.append(run_dir)
    return run_dirs


def results_markdown(budget_name: str, budget: Budget, run_dirs: list[Path], table: str) -> str:
    """``RESULTS.md``: the commands, budgets, seeds and the table."""
    lines = [
        "# Results: does the GPIS map help?",
        "",
        f"Produced by `make results` (`python -m agents.pipeline --budget {budget_name}`) on a",
        "2-core CPU machine without a GPU. Figures and per-episode rows are in",
        f"[`{budget.results.name}/`]({budget.results.name}/).",
        "",
        "## Budgets and seeds",
        "",
        "| agent | timesteps | training wall-clock (min) | training seed | recipe |",
        "|---|---|---|---|---|",
    ]
    for run_dir in run_dirs:
        config = yaml.safe_load((run_dir / "config.yml").read_text())
        algo, map_mode = config["algo"], config["map"]
        recipe = config["hyperparams"]
        lines.append(
            f"| {algo} ({map_mode} map) | {config['timesteps_done']:,} "
            f"| {config['wall_clock_seconds'] / 60:.1f} | {config['seed']} "
            f"| `agents/hyperparams/{algo}.yml`, n_envs {recipe['n_envs']}, "
            f"env {recipe['env_kwargs']} |"
        )
    lines += [
        "",
        f"Training draws layout seeds from [2^32, 2^63); evaluation uses the held-out layouts "
        f"{EVAL_SEED_START}..{EVAL_SEED_START + budget.episodes - 1}, the same for every agent,",
        "with the environment's default reward (no shaping). Scripted agents run with the GPIS",
        "map (the planner reads it; the random agent and the oracle ignore it).",
        "",
        "## Table",
        "",
        table,
        "![success](results/success.png)",
        "",
        "![steps](results/steps.png)",
        "",
        "![learning curves](results/learning_curves.png)",
        "",
    ]
    return "\n".join(lines)


def run(budget_name: str, seed: int = 0, progress_bar: bool = True) -> Path:
    """Trains, evaluates and writes the results of ``budget_name``; returns the results dir."""
    if budget_name not in BUDGETS:
        raise ValueError(f"budget must be one of {sorted(BUDGETS)}, got {budget_name!r}")
    budget = BUDGETS[budget_name]
    for algo, map_mode in budget.agents:
        load_hyperparams(algo, map_mode)  # fail before hours of training, not after
    started = time.perf_counter()
    run_dirs = train_all(budget, seed, progress_bar)
    summaries = evaluate(
        [*map(str, run_dirs), *SCRIPTED], out=budget.results, episodes=budget.episodes
    )
    table = markdown_table(summaries)
    if budget_name == "full":
        path = budget.results.parent / "RESULTS.md"
        path.write_text(results_markdown(budget_name, budget, run_dirs, table))
        print(f"wrote {path}")
    print(table)
    print(f"pipeline took {(time.perf_counter() - started) / 60:.1f} min; see {budget.results}/")
    return budget.results


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--budget", choices=sorted(BUDGETS), default="demo")
    parser.add_argument("--seed", type=int, default=0, help="training seed")
    parser.add_argument("--no-progress", action="store_true")
    args = parser.parse_args(argv)
    run(args.budget, args.seed, progress_bar=not args.no_progress)


if __name__ == "__main__":
    main()
