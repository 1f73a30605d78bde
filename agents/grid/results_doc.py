"""``docs/RESULTS.md``'s generated part: the commands, budgets, seeds and tables of a
pipeline run, with the machines, code versions and seed ranges read from the runs'
``config.yml``, written between markers that keep the hand-written findings around it."""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from agents.evaluation.comparison import (
    BOOTSTRAP_SAMPLES,
    agent_results,
    gap_change,
    interval_sources_markdown,
)
from agents.grid.budgets import Budget, Task
from agents.run_dir import clone_dir, read_run_config, recorded_config, task_folder
from agents.sb3.learned import learned_agent_name
from tactile_search.benchmark.summary_table import MAP_TASK
from tactile_search.seed_ranges import held_out_seeds


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


def wall_clock_text(run_dir: Path, config: dict) -> str:
    """A run's training wall-clock in minutes: its clone stage's (``<run>/imitation/``, when
    it has one) plus its PPO's, and their sum."""
    ppo = config["wall_clock_seconds"] / 60
    clone_config = recorded_config(clone_dir(run_dir))
    if clone_config is None:
        return f"{ppo:.1f}"
    clone = clone_config["wall_clock_seconds"] / 60
    return f"{clone:.1f} + {ppo:.1f} = {clone + ppo:.1f}"


def results_markdown(
    budget_name: str,
    budget: Budget,
    run_dirs: list[Path],
    table: str,
    comparison: str = "",
    sampled: str = "",
) -> str:
    """``RESULTS.md``: the commands, budgets, seeds and the table; the machines, code
    versions and seed ranges are read from the runs' ``config.yml``. ``sampled``: the
    learned agents' pooled comparison when sampling their probes, if evaluated so."""
    configs = [read_run_config(run_dir, required=()) for run_dir in run_dirs]
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
        "| agent | timesteps | training wall-clock (min): clone stage + PPO | training seed "
        "| recipe |",
        "|---|---|---|---|---|",
    ]
    for run_dir, config in zip(run_dirs, configs, strict=True):
        algo, map_mode = config["algo"], config["map"]
        recipe = config["hyperparams"]
        lines.append(
            f"| {algo} ({map_mode} map) | {config['timesteps_done']:,} "
            f"| {wall_clock_text(run_dir, config)} | {config['seed']} "
            f"| `agents/hyperparams/{algo}.yml`, n_envs {recipe['n_envs']}, "
            f"env {recipe['env_kwargs']} |"
        )
    seeds = held_out_seeds(budget.split, budget.episodes)
    lines += [
        "",
        f"Training draws layout seeds from {', '.join(distinct(map(range_text, configs)))}; "
        "evaluation uses the held-out "
        f"{budget.split} layouts {seeds[0]}..{seeds[-1]} "
        "(`python/tactile_search/seed_ranges.py`), the same for every agent,",
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
        *(
            [
                "Sampling their probes instead of taking the policy's mode (the learned agents "
                f"alone, `{budget.results.name}/sampled/`):",
                "",
                sampled,
            ]
            if sampled
            else []
        ),
        "Success against the wrist motions spent, every agent with its 95 % interval "
        "(`agents/evaluation/curves.py`):",
        "",
        "![curves](results/curves.png)",
        "",
        "![success](results/success.png)",
        "",
        "![steps](results/steps.png)",
        "",
        "![learning curves](results/learning_curves.png)",
        "",
    ]
    return "\n".join(lines)


@dataclass(frozen=True)
class TaskResults:
    """What a budget's run gives for one of its tasks: the runs of the agents that played it,
    where its results are (``episodes.csv``, ``results.md``, plots, the runs' records) and
    its results table."""

    task: Task
    run_dirs: list[Path]
    results: Path
    table: str


def task_results_markdown(budget: Budget, outcome: TaskResults, comparison: str) -> str:
    """A task's generated section of ``RESULTS.md`` (a task other than the default id's,
    whose page ``results_markdown`` writes): the agents that played it (their training
    wall-clock, or the id they were trained on), its held-out layouts, the table, and the
    pooled figures with the differences from the GPIS agent, the task's measures among them."""
    task = outcome.task
    folder = task_folder(task.env_id)
    seeds = held_out_seeds(budget.split, budget.episodes)
    lines = [f"Produced by `make results`: `{task.env_id}` (task `{task.task}`), "]
    if task.trained_on is None:
        configs = [read_run_config(run_dir, required=()) for run_dir in outcome.run_dirs]
        lines[0] += (
            "every learned agent trained on it "
            f"(`agents/hyperparams/`, key `{task.env_id}`) with code "
            f"{', '.join(distinct(map(commit_text, configs)))}; each run's config in "
            f"[`results/{folder}/training/`](results/{folder}/training/)."
        )
        lines += [
            "",
            "| agent | training seed | training wall-clock (min): clone stage + PPO |",
            "|---|---|---|",
            *(
                f"| {config['algo']} ({config['map']} map) | {config['seed']} "
                f"| {wall_clock_text(run_dir, config)} |"
                for run_dir, config in zip(outcome.run_dirs, configs, strict=True)
            ),
        ]
    else:
        lines[0] += (
            f"played by the agents trained on `{task.trained_on}` (how they generalise), unchanged."
        )
    lines += [
        "",
        f"Held-out {budget.split} layouts {seeds[0]}..{seeds[-1]} of `{task.env_id}`, the same "
        f"for every agent; rows and plots in [`results/{folder}/`](results/{folder}/).",
        "",
        outcome.table,
        "Pooled over training seeds (95 % bootstrap intervals over layouts and training "
        "seeds), and the GPIS agent minus each other agent (`python -m agents.comparison "
        f"docs/results/{folder}/episodes.csv --task {task.task} --reference "
        f'"{task.reference_agent()}"`):',
        "",
        comparison,
    ]
    if task.task == MAP_TASK:
        lines += [
            "The map's distance to the true outlines against the wrist motions spent, every "
            "agent with its 95 % interval:",
            "",
            f"![curves](results/{folder}/curves.png)",
            "",
        ]
    else:
        lines += [
            "Success against the wrist motions spent, every agent with its 95 % interval:",
            "",
            f"![curves](results/{folder}/curves.png)",
            "",
            f"![success](results/{folder}/success.png)",
            "",
            f"![steps](results/{folder}/steps.png)",
            "",
        ]
    return "\n".join(lines)


def interval_sources_text(
    rows: Sequence[dict[str, Any]], task: Task, samples: int = BOOTSTRAP_SAMPLES
) -> str:
    """A task section's table of where each difference's interval comes from
    (``interval_sources_markdown``), with the sentence that reads it."""
    folder = task_folder(task.env_id)
    return (
        "Where each difference's interval comes from: over test layouts and training seeds "
        "(as above), beside over the layouts alone with these training seeds held (`python "
        f"-m agents.comparison docs/results/{folder}/episodes.csv --task {task.task} "
        f'--reference "{task.reference_agent()}" --sources`). More layouts narrow the second; '
        "what the first adds is the training seeds' spread, which only more seeds narrow.\n\n"
        + interval_sources_markdown(rows, task.reference_agent(), task.task, samples)
    )


#: The agents whose gap to the GPIS agent the dense tier's section follows (H3: the no-map
#: gap widens with more jars).
NO_MAP_AGENTS = (("ppo", "none"), ("recurrent_ppo", "none"))


def gap_change_markdown(
    dense_rows: Sequence[dict[str, Any]],
    default_rows: Sequence[dict[str, Any]],
    dense: Task,
    default: Task,
    samples: int = BOOTSTRAP_SAMPLES,
) -> str:
    """A dense tier's table of how the GPIS agent's success gap over each no-map agent
    changes from its default tier to it (``comparison.gap_change``); agents missing from
    either tier's rows are left out."""
    dense_results, default_results = agent_results(dense_rows), agent_results(default_rows)
    lines = [
        f"The gap between the GPIS agent and each no-map agent on `{dense.env_id}` minus "
        f"that on `{default.env_id}` (the same models; each tier's layouts resampled on their "
        "own, each agent's training seeds once for both):",
        "",
        "| GPIS minus | gap, default tier | gap, dense tier | change | 95 % CI (bootstrap) |",
        "|---|---|---|---|---|",
    ]
    reference = (dense.reference_agent(), default.reference_agent())
    for algo, map_mode in NO_MAP_AGENTS:
        other = (dense.agent_name(algo, map_mode), default.agent_name(algo, map_mode))
        names = (*reference, *other)
        if not all(
            name in results
            for name, results in zip(names, (dense_results, default_results) * 2, strict=True)
        ):
            continue
        a_dense, a_default = dense_results[reference[0]], default_results[reference[1]]
        b_dense, b_default = dense_results[other[0]], default_results[other[1]]
        change, low, high = gap_change(a_dense, b_dense, a_default, b_default, samples)
        gap_default = a_default.success.mean() - b_default.success.mean()
        gap_dense = a_dense.success.mean() - b_dense.success.mean()
        lines.append(
            f"| {learned_agent_name(algo, map_mode)} | {100 * gap_default:+.1f} pts "
            f"| {100 * gap_dense:+.1f} pts | {100 * change:+.1f} pts "
            f"| [{100 * low:+.1f}, {100 * high:+.1f}] |"
        )
    return "\n".join(lines) + "\n"


BEGIN = "<!-- generated by agents.pipeline: begin -->"


END = "<!-- generated by agents.pipeline: end -->"


def markers(section: str = "") -> tuple[str, str]:
    """The markers around a generated section of ``RESULTS.md``: the default id's page's
    (``section`` ``""``, ``BEGIN`` and ``END``), or a task's, named by its folder."""
    if not section:
        return BEGIN, END
    return (
        f"<!-- generated by agents.pipeline for {section}: begin -->",
        f"<!-- generated by agents.pipeline for {section}: end -->",
    )


def write_results(path: Path, generated: str, section: str = "") -> None:
    """Writes ``generated`` between the markers of ``section`` (``markers``) in ``path``,
    keeping the hand-written text around them (the findings); a file without those markers
    gets the block at its end, and a new file holds just the generated part."""
    begin, end = markers(section)
    block = f"{begin}\n{generated}\n{end}"
    text = path.read_text() if path.is_file() else ""
    if begin in text and end in text:
        head, rest = text.split(begin, 1)
        tail = rest.split(end, 1)[1]
        text = f"{head}{block}{tail}"
    elif text:
        text = f"{text.rstrip()}\n\n{block}\n"
    else:
        text = f"{block}\n"
    path.write_text(text)
