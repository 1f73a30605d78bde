"""``docs/RESULTS.md``'s generated part: the commands, budgets, seeds and tables of a
pipeline run, with the machines, code versions and seed ranges read from the runs'
``config.yml``, written between markers that keep the hand-written findings around it."""

from __future__ import annotations

from collections.abc import Iterable
from pathlib import Path

from agents.grid.budgets import Budget
from agents.run_dir import clone_dir, read_run_config, recorded_config
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
