"""The end-to-end pipeline: train the learned agents, evaluate them with the scripted
baselines on held-out layouts, write the results.

Two budgets::

    python -m agents.pipeline --budget demo     # make demo: a few minutes, results/
    python -m agents.pipeline --budget full     # make results: docs/RESULTS.md

``demo`` trains the GPIS-map and the no-map PPO agents briefly, each warm-started from its
published model (``docs/results/models/``, when there is one), and evaluates them on 50
validation layouts; ``full`` trains every learned agent (PPO with each map mode and the
recurrent no-map agent) with training seeds 0, 1 and 2 at its recipe's ``n_timesteps``,
into ``docs/results/models/`` (the published models), and evaluates on 500 test layouts, on
each of its tasks (``agents.grid.budgets.Task``: the search task, identify and map by touch,
the dense tiers), each task's section of ``docs/RESULTS.md`` written between its markers.

The grid (agents x training seeds, then the evaluation) runs on Ray when it is installed
(the ``scale`` extra; ``--scheduler ray``): training trials and the evaluation run as Ray
tasks over slices of the layouts, on this machine's cores, or on the cluster at
``--address`` / ``RAY_ADDRESS`` (``agents.grid.ray_scheduler``). ``--scheduler local`` runs the same
trials one after another in this process; both give the same models and episode rows
(``agents.grid.trials``).

Interrupted at any point (Ctrl-C, a kill), the same command finishes the work without
redoing what is done: a run whose ``model.zip`` exists is reused (delete the run directory
to retrain), a partly trained run resumes from its newest checkpoint
(``agents.sb3.training.TrainSettings(resume=True)``), and the evaluation reuses the per-episode rows
already in ``episodes.csv`` (``agents.evaluation.evaluation.evaluate``). ``--tasks`` runs a
piece of a budget, some of its tasks (a dense tier with the id whose agents play it): their
training, evaluation and sections alone, the other sections of RESULTS.md kept as they are.
"""

from __future__ import annotations

import importlib.util
import time
from collections.abc import Sequence
from pathlib import Path

from agents.evaluation.comparison import comparison_markdown
from agents.evaluation.curves import plot_curves
from agents.evaluation.episodes_csv import read_episodes_csv
from agents.evaluation.evaluation import evaluate
from agents.evaluation.report import markdown_table
from agents.grid.budgets import BUDGETS, Budget
from agents.grid.model_card import write_model_cards
from agents.grid.results_doc import (
    TaskResults,
    gap_change_markdown,
    interval_sources_text,
    results_markdown,
    task_results_markdown,
    write_results,
)
from agents.grid.trials import TrainingTrial, train_trial
from agents.run_dir import code_version, copy_record, model_path, run_name, task_folder
from agents.sb3.recipes import load_hyperparams
from tactile_search import ENV_ID

SCHEDULERS = ("ray", "local")
# Where a task with ``sampled_too`` keeps the learned agents' rows sampling their probes.
SAMPLED_DIR = "sampled"


def default_scheduler() -> str:
    """``ray`` when Ray is installed (the ``scale`` extra), else ``local``."""
    return "ray" if importlib.util.find_spec("ray") is not None else "local"


def trials(budget: Budget, seeds: list[int]) -> list[TrainingTrial]:
    """The budget's training trials: every learned agent with every training seed, on every
    id it trains on (``Budget.trained_ids``)."""
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
            init_from=warm_start_source(budget, algo, map_mode, seed, env_id),
            imitation=(
                budget.imitation
                if "imitation" in load_hyperparams(algo, map_mode, env_id)
                else None
            ),
            env_id=env_id,
        )
        for env_id in budget.trained_ids()
        for algo, map_mode in budget.agents
        for seed in seeds
    ]


def warm_start_source(
    budget: Budget, algo: str, map_mode: str, seed: int, env_id: str = ENV_ID
) -> str | None:
    """The published run a trial of ``budget`` warm-starts from, if the budget warm-starts and
    that run is published (else the trial trains from scratch)."""
    if budget.warm_start_from is None:
        return None
    published = model_path(
        budget.warm_start_from / task_folder(env_id) / run_name(algo, map_mode, seed)
    )
    return str(published.resolve()) if published.is_file() else None


def train_all(grid: list[TrainingTrial], progress_bar: bool) -> list[Path]:
    """Trains (or reuses, or resumes) every trial here, one after another; returns the run
    directories."""
    return [train_trial(trial, progress_bar) for trial in grid]


def run_budget(
    budget: Budget,
    seeds: Sequence[int],
    scheduler: str,
    address: str | None = None,
    progress_bar: bool = True,
) -> list[TaskResults]:
    """Trains every agent of ``budget`` with every seed in ``seeds`` on every id it trains
    on, evaluates them on each of its tasks with the task's scripted baselines, keeps each
    run's record beside the task's results and writes each run's model card and digest
    record (``agents.grid.model_card``); returns each task's results, in the order of
    ``budget.tasks``. ``scheduler``: ``ray`` (Ray tasks, on the cluster at ``address`` or
    ``RAY_ADDRESS``, else on this machine) or ``local`` (one after another in this
    process)."""
    if scheduler not in SCHEDULERS:
        raise ValueError(f"scheduler must be one of {SCHEDULERS}, got {scheduler!r}")
    if address is not None and scheduler != "ray":
        raise ValueError(f"an address is for the ray scheduler, got scheduler {scheduler!r}")
    for env_id in budget.trained_ids():
        for algo, map_mode in budget.agents:
            load_hyperparams(algo, map_mode, env_id)  # fail before hours of training, not after
    grid = trials(budget, list(seeds))
    if scheduler == "ray":
        import ray

        from agents.grid import ray_scheduler
        from agents.grid.ray_session import connect

        connect(address)
        cpus = ray.cluster_resources().get("CPU", 0)
        print(f"Ray: {cpus:g} CPUs; {len(grid)} training trials", flush=True)
        run_dirs = ray_scheduler.train_on_ray(grid)
        evaluation = ray_scheduler.evaluate_on_ray
    else:
        run_dirs = train_all(grid, progress_bar)
        evaluation = evaluate
    outcomes = []
    for task in budget.tasks:
        task_runs = [
            run_dir
            for trial, run_dir in zip(grid, run_dirs, strict=True)
            if trial.env_id == task.agents_from
        ]
        results = budget.results / task_folder(task.env_id)
        summaries = evaluation(
            [*map(str, task_runs), *task.scripted()],
            out=results,
            episodes=budget.episodes,
            split=budget.split,
            final=budget.split == "test",
            env_id=task.env_id,
        )
        if task.sampled_too:
            evaluation(
                list(map(str, task_runs)),
                out=results / SAMPLED_DIR,
                episodes=budget.episodes,
                split=budget.split,
                final=budget.split == "test",
                gifs=False,
                actions="sample",
                env_id=task.env_id,
            )
        if task.trained_on is None:  # the record of each run beside its results (models stay out)
            for run_dir in task_runs:
                copy_record(run_dir, results / "training" / run_dir.name)
        outcomes.append(TaskResults(task, task_runs, results, markdown_table(summaries, task.task)))
    # Each trained run's card (its evaluations on every task) and its model's digest record.
    write_model_cards(run_dirs, budget.results)
    return outcomes


def run(
    budget_name: str,
    seeds: Sequence[int] | None = None,
    scheduler: str | None = None,
    address: str | None = None,
    progress_bar: bool = True,
    env_ids: Sequence[str] | None = None,
) -> Path:
    """Trains, evaluates and writes the results of ``budget_name``; returns the results dir.
    ``seeds`` defaults to the budget's; ``scheduler`` to ``default_scheduler()``;
    ``env_ids`` to every task of the budget (else those tasks alone, ``Budget.only``)."""
    if budget_name not in BUDGETS:
        raise ValueError(f"budget must be one of {sorted(BUDGETS)}, got {budget_name!r}")
    budget = BUDGETS[budget_name]
    if env_ids is not None:
        budget = budget.only(env_ids)
    started = time.perf_counter()
    outcomes = run_budget(
        budget,
        budget.seeds if seeds is None else seeds,
        scheduler or default_scheduler(),
        address,
        progress_bar,
    )
    path = budget.results.parent / "RESULTS.md"
    by_id = {outcome.task.env_id: outcome for outcome in outcomes}
    for outcome in outcomes:
        task = outcome.task
        rows, _ = read_episodes_csv(outcome.results / "episodes.csv")
        comparison = comparison_markdown(rows, reference=task.reference_agent(), task=task.task)
        if task.env_id != ENV_ID:  # a new task's section (v0's stays as it was published)
            comparison += "\n" + interval_sources_text(rows, task)
        if task.trained_on is not None:  # a dense tier: how the no-map gap changes (H3)
            default = by_id[task.trained_on]
            default_rows, _ = read_episodes_csv(default.results / "episodes.csv")
            comparison += "\n" + gap_change_markdown(rows, default_rows, task, default.task)
        plot_curves(outcome.results / "curves.png", rows, task.task)
        sampled = ""
        if task.sampled_too:
            sampled_rows, _ = read_episodes_csv(outcome.results / SAMPLED_DIR / "episodes.csv")
            sampled = comparison_markdown(sampled_rows, reference=task.reference_agent())
        if budget_name == "full":
            if task.env_id == ENV_ID:
                generated = results_markdown(
                    budget_name, budget, outcome.run_dirs, outcome.table, comparison, sampled
                )
            else:
                generated = task_results_markdown(budget, outcome, comparison)
            write_results(path, generated, section=task_folder(task.env_id))
        print(f"{task.env_id}:")
        print(outcome.table)
        print(comparison)
        print(sampled)
    if budget_name == "full":
        print(f"wrote {path}")
    print(f"pipeline took {(time.perf_counter() - started) / 60:.1f} min; see {budget.results}/")
    return budget.results
