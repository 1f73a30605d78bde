"""The end-to-end pipeline: train the learned agents, evaluate them with the scripted
baselines on held-out layouts, write the results.

Two budgets::

    python -m agents.pipeline --budget demo     # make demo: a few minutes, results/
    python -m agents.pipeline --budget full     # make results: docs/RESULTS.md

``demo`` trains the GPIS-map and the no-map PPO agents briefly, each warm-started from its
published model (``docs/results/models/``, when there is one), and evaluates them on 50
validation layouts; ``full`` trains every learned agent (PPO with each map mode and the
recurrent no-map agent) with training seeds 0, 1 and 2 at its recipe's ``n_timesteps``,
into ``docs/results/models/`` (the published models), and evaluates on 200 test layouts.

The grid (agents x training seeds, then the evaluation) runs on Ray when it is installed
(the ``scale`` extra; ``--scheduler ray``): training trials and the evaluation run as Ray
tasks over slices of the layouts, on this machine's cores, or on the cluster at
``--address`` / ``RAY_ADDRESS`` (``agents.ray_grid``). ``--scheduler local`` runs the same
trials one after another in this process; both give the same models and episode rows
(``agents.grid``).

Interrupted at any point (Ctrl-C, a kill), the same command finishes the work without
redoing what is done: a run whose ``model.zip`` exists is reused (delete the run directory
to retrain), a partly trained run resumes from its newest checkpoint
(``agents.train.train(..., resume=True)``), and the evaluation reuses the per-episode rows
already in ``episodes.csv`` (``agents.evaluate.evaluate``).
"""

from __future__ import annotations

import argparse
import importlib.util
import shutil
import sys
import time
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path

import yaml

from agents.comparison import comparison_markdown
from agents.evaluate import evaluate, markdown_table, read_episodes_csv
from agents.grid import TrainingTrial, train_trial
from agents.learned import learned_agent_name
from agents.seed_ranges import held_out_seeds
from agents.train import (
    INTERRUPTED_EXIT_STATUS,
    PUBLISHED_RUNS,
    code_version,
    load_hyperparams,
    run_name,
)


@dataclass(frozen=True)
class Budget:
    """What one budget trains and how many held-out episodes it evaluates.

    ``cpus_per_trial``: the CPUs a training trial declares, its torch threads and its
    environment batch's threads. Part of what fixes a model (torch may sum in another order
    with another thread count), so the same in every scheduler: on Ray, this machine runs
    ``cores / cpus_per_trial`` trials at once."""

    agents: tuple[tuple[str, str], ...]
    timesteps: int | None  # None: each recipe's n_timesteps
    episodes: int
    runs: Path
    results: Path
    cpus_per_trial: int
    # The held-out layouts (agents.seed_ranges): the test range is the final results' alone.
    split: str = "validation"
    # Training seeds (one run per agent each); the CLI's --seeds overrides.
    seeds: tuple[int, ...] = (0,)
    # Where the published models are (docs/results/models/<run>/): a run of this budget
    # warm-starts from the published run of the same agent and seed when there is one.
    warm_start_from: Path | None = None


# The documented budget's models (model.zip beside config.yml, one folder per run).
PUBLISHED_MODELS = Path(PUBLISHED_RUNS)

BUDGETS = {
    "demo": Budget(
        agents=(("ppo", "gpis"), ("ppo", "none")),
        timesteps=4096,
        episodes=50,
        runs=Path("runs/demo"),
        results=Path("results"),
        cpus_per_trial=2,
        warm_start_from=PUBLISHED_MODELS,
    ),
    # The published models are the full budget's run directories themselves (their
    # checkpoints and event files stay out of git): a rerun skips the finished ones.
    "full": Budget(
        agents=(("ppo", "gpis"), ("ppo", "occupancy"), ("ppo", "none"), ("recurrent_ppo", "none")),
        timesteps=None,
        episodes=200,
        runs=PUBLISHED_MODELS,
        results=Path("docs/results"),
        cpus_per_trial=1,
        split="test",
        seeds=(0, 1, 2),
    ),
}
SCRIPTED = ("random", "gpis_planner", "oracle")
# The agent every other is compared with.
REFERENCE_AGENT = learned_agent_name("ppo", "gpis")


SCHEDULERS = ("ray", "local")


def default_scheduler() -> str:
    """``ray`` when Ray is installed (the ``scale`` extra), else ``local``."""
    return "ray" if importlib.util.find_spec("ray") is not None else "local"


def trials(budget: Budget, seeds: list[int]) -> list[TrainingTrial]:
    """The budget's training trials: every learned agent with every training seed."""
    code = code_version()
    return [
        TrainingTrial(
            algo=algo,
            map_mode=map_mode,
            seed=seed,
            runs=str(budget.runs.resolve()),
            timesteps=budget.timesteps,
            cpus=budget.cpus_per_trial,
            code=code,
            init_from=warm_start_source(budget, algo, map_mode, seed),
        )
        for algo, map_mode in budget.agents
        for seed in seeds
    ]


def warm_start_source(budget: Budget, algo: str, map_mode: str, seed: int) -> str | None:
    """The published run a trial of ``budget`` warm-starts from, if the budget warm-starts and
    that run is published (else the trial trains from scratch)."""
    if budget.warm_start_from is None:
        return None
    published = budget.warm_start_from / run_name(algo, map_mode, seed) / "model.zip"
    return str(published.resolve()) if published.is_file() else None


def train_all(grid: list[TrainingTrial], progress_bar: bool) -> list[Path]:
    """Trains (or reuses, or resumes) every trial here, one after another; returns the run
    directories."""
    return [train_trial(trial, progress_bar) for trial in grid]


def distinct(texts: Iterable[str]) -> list[str]:
    """``texts`` without repeats, in first-seen order."""
    return list(dict.fromkeys(texts))


def machine_text(config: dict) -> str:
    """The machine a run trained on, as its config records it."""
    record = config.get("machine")
    if not record:
        return "an unrecorded machine"
    gpu = record.get("gpu")
    return f"{record.get('cpus', '?')} CPU cores ({record.get('processor') or 'unknown CPU'}), " + (
        f"GPU {gpu}" if gpu else "no GPU"
    )


def commit_text(config: dict) -> str:
    """The git commit a run trained with, and whether its tree was dirty."""
    code = config.get("code") or {}
    commit = code.get("commit")
    if not commit:
        return "of an unrecorded version"
    return f"`{commit[:12]}`{' (with uncommitted changes)' if code.get('dirty') else ''}"


def range_text(config: dict) -> str:
    """The training layout range a run drew from."""
    bounds = config.get("train_layout_seeds")
    return f"[{bounds[0]:,}, {bounds[1]:,})" if bounds else "an unrecorded range"


def results_markdown(
    budget_name: str, budget: Budget, run_dirs: list[Path], table: str, comparison: str = ""
) -> str:
    """``RESULTS.md``: the commands, budgets, seeds and the table; the machines, code
    versions and seed ranges are read from the runs' ``config.yml``."""
    configs = [yaml.safe_load((run_dir / "config.yml").read_text()) for run_dir in run_dirs]
    lines = [
        f"Produced by `make results` (`python -m agents.pipeline --budget {budget_name}`), "
        f"training on {'; '.join(distinct(map(machine_text, configs)))}, "
        f"code {', '.join(distinct(map(commit_text, configs)))}. "
        "Figures and per-episode rows are in",
        f"[`{budget.results.name}/`]({budget.results.name}/); each run's config and training log",
        f"in `{budget.results.name}/training/`.",
        "",
        "## Budgets and seeds",
        "",
        "| agent | timesteps | training wall-clock (min) | training seed | recipe |",
        "|---|---|---|---|---|",
    ]
    for config in configs:
        algo, map_mode = config["algo"], config["map"]
        recipe = config["hyperparams"]
        lines.append(
            f"| {algo} ({map_mode} map) | {config['timesteps_done']:,} "
            f"| {config['wall_clock_seconds'] / 60:.1f} | {config['seed']} "
            f"| `agents/hyperparams/{algo}.yml`, n_envs {recipe['n_envs']}, "
            f"env {recipe['env_kwargs']} |"
        )
    seeds = held_out_seeds(budget.split, budget.episodes)
    lines += [
        "",
        f"Training draws layout seeds from {', '.join(distinct(map(range_text, configs)))}; "
        "evaluation uses the held-out "
        f"{budget.split} layouts {seeds[0]}..{seeds[-1]} (`agents/seed_ranges.py`), the same for "
        "every agent,",
        "with the environment's default reward (no shaping). Scripted agents run with the GPIS",
        "map (the planner reads it; the random agent and the oracle ignore it).",
        "",
        "## Table",
        "",
        "Each run (learned agents: one row per training seed):",
        "",
        table,
        "## Pooled over training seeds, and differences",
        "",
        "Pooled success with a 95 % bootstrap interval (over layouts and training seeds), each",
        "seed's success with its Wilson interval, and the GPIS agent's success minus each other",
        "agent's (`agents/comparison.py`):",
        "",
        comparison,
        "![success](results/success.png)",
        "",
        "![steps](results/steps.png)",
        "",
        "![learning curves](results/learning_curves.png)",
        "",
    ]
    return "\n".join(lines)


BEGIN = "<!-- generated by agents.pipeline: begin -->"
END = "<!-- generated by agents.pipeline: end -->"


def write_results(path: Path, generated: str) -> None:
    """Writes ``generated`` between the markers of ``path``, keeping the hand-written text
    around them (the findings); a new file holds just the generated part."""
    block = f"{BEGIN}\n{generated}\n{END}"
    text = path.read_text() if path.is_file() else ""
    if BEGIN in text and END in text:
        head, rest = text.split(BEGIN, 1)
        tail = rest.split(END, 1)[1]
        text = f"{head}{block}{tail}"
    else:
        text = f"{block}\n"
    path.write_text(text)


def run_budget(
    budget: Budget,
    seeds: Sequence[int],
    scheduler: str,
    address: str | None = None,
    progress_bar: bool = True,
) -> tuple[list[Path], str]:
    """Trains every agent of ``budget`` with every seed in ``seeds``, evaluates them with the
    scripted baselines and keeps each run's record beside the results; returns the run
    directories and the results table. ``scheduler``: ``ray`` (Ray tasks, on
    the cluster at ``address`` or ``RAY_ADDRESS``, else on this machine) or ``local`` (one
    after another in this process)."""
    if scheduler not in SCHEDULERS:
        raise ValueError(f"scheduler must be one of {SCHEDULERS}, got {scheduler!r}")
    if address is not None and scheduler != "ray":
        raise ValueError(f"an address is for the ray scheduler, got scheduler {scheduler!r}")
    for algo, map_mode in budget.agents:
        load_hyperparams(algo, map_mode)  # fail before hours of training, not after
    grid = trials(budget, list(seeds))
    if scheduler == "ray":
        import ray

        from agents import ray_grid
        from agents.ray_session import connect

        connect(address)
        cpus = ray.cluster_resources().get("CPU", 0)
        print(f"Ray: {cpus:g} CPUs; {len(grid)} training trials", flush=True)
        run_dirs = ray_grid.train_on_ray(grid)
        summaries = ray_grid.evaluate_on_ray(
            [*map(str, run_dirs), *SCRIPTED],
            out=budget.results,
            episodes=budget.episodes,
            split=budget.split,
            final=budget.split == "test",
        )
    else:
        run_dirs = train_all(grid, progress_bar)
        summaries = evaluate(
            [*map(str, run_dirs), *SCRIPTED],
            out=budget.results,
            episodes=budget.episodes,
            split=budget.split,
            final=budget.split == "test",
        )
    for run_dir in run_dirs:  # the record of each run beside the results (models stay out)
        record = budget.results / "training" / run_dir.name
        record.mkdir(parents=True, exist_ok=True)
        for name in ("config.yml", "progress.csv"):
            shutil.copyfile(run_dir / name, record / name)
    return run_dirs, markdown_table(summaries)


def run(
    budget_name: str,
    seeds: Sequence[int] | None = None,
    scheduler: str | None = None,
    address: str | None = None,
    progress_bar: bool = True,
) -> Path:
    """Trains, evaluates and writes the results of ``budget_name``; returns the results dir.
    ``seeds`` defaults to the budget's; ``scheduler`` to ``default_scheduler()``."""
    if budget_name not in BUDGETS:
        raise ValueError(f"budget must be one of {sorted(BUDGETS)}, got {budget_name!r}")
    budget = BUDGETS[budget_name]
    started = time.perf_counter()
    run_dirs, table = run_budget(
        budget,
        budget.seeds if seeds is None else seeds,
        scheduler or default_scheduler(),
        address,
        progress_bar,
    )
    rows, _ = read_episodes_csv(budget.results / "episodes.csv")
    comparison = comparison_markdown(rows, reference=REFERENCE_AGENT)
    if budget_name == "full":
        path = budget.results.parent / "RESULTS.md"
        write_results(path, results_markdown(budget_name, budget, run_dirs, table, comparison))
        print(f"wrote {path}")
    print(table)
    print(comparison)
    print(f"pipeline took {(time.perf_counter() - started) / 60:.1f} min; see {budget.results}/")
    return budget.results


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--budget", choices=sorted(BUDGETS), default="demo")
    parser.add_argument(
        "--seeds",
        type=int,
        nargs="+",
        help="training seeds, one run per agent each (default: the budget's; full: 0 1 2)",
    )
    parser.add_argument(
        "--scheduler",
        choices=SCHEDULERS,
        default=default_scheduler(),
        help="ray: Ray tasks (the default when Ray is installed); "
        "local: one run after another in this process",
    )
    parser.add_argument(
        "--address", help="a Ray cluster's address (default: RAY_ADDRESS, else Ray on this machine)"
    )
    parser.add_argument("--no-progress", action="store_true")
    args = parser.parse_args(argv)
    try:
        run(
            args.budget,
            args.seeds,
            args.scheduler,
            args.address,
            progress_bar=not args.no_progress,
        )
    except KeyboardInterrupt:
        print(
            "\ninterrupted: run the same command again to finish (finished runs are reused, a "
            "partly trained run resumes from its checkpoint, the evaluation from its rows)",
            file=sys.stderr,
            flush=True,
        )
        sys.exit(INTERRUPTED_EXIT_STATUS)


if __name__ == "__main__":
    main()
