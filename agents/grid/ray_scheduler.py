"""The experiment grid on Ray: each training trial a Ray task, the evaluation Ray tasks too (one
per agent and slice of the layouts), on this machine or on a cluster.

Plain tasks, not Tune trials: a grid of fixed recipes needs no search, and a Tune trial adds
its own start-up and bookkeeping and runs the training in a thread beside Tune's work.

Where it runs: connect first (``agents.grid.ray_session.connect``): with no address (neither
``address`` nor ``RAY_ADDRESS``) on this machine with its cores, else on that cluster. Every
node needs this repository's environment installed (``make build``, or ``pip install`` of
the package with the ``agents`` extra). On a cluster the run directories must be on a file
system every node sees (NFS): a trial writes its run there, and a retried or resumed trial
reads its checkpoints back, wherever it runs; an evaluation shard gets its model's files
sent with it and needs no shared files.

What a trial or shard produces depends only on its fields (``agents.grid.trials``), so the grid run
here gives the models and episode rows of the grid run one trial after another. A trial that
fails is retried (``max_failures``), resuming from its newest checkpoint; the other trials go
on, and the failures are reported at the end (``GridError``). A grid stopped half-way resumes
when run again: finished runs are reused, partly trained ones resume, and the evaluation
reuses the rows already in ``episodes.csv``.
"""

from __future__ import annotations

import csv
from collections.abc import Sequence
from dataclasses import asdict
from pathlib import Path
from typing import Any

import ray

from agents.evaluation.episodes_csv import EPISODE_COLUMNS, episode_row
from agents.evaluation.evaluation import evaluate, evaluation_seeds, prepare_evaluation
from agents.grid.trials import TrainingTrial, evaluate_shard, shards, train_trial
from agents.run_dir import evaluated_files
from agents.scripted import SCRIPTED_AGENTS
from tactile_search.benchmark.statistics import Summary

# Retries of a failed training trial or evaluation shard before it is reported as failed.
DEFAULT_MAX_FAILURES = 2


# Episodes per evaluation task: small enough to spread an evaluation's layouts over many
# cores, large enough that loading the model is a small part of a task.
DEFAULT_SHARD_EPISODES = 25


class GridError(RuntimeError):
    """Some trials or shards failed after their retries (the rest finished and was kept)."""


@ray.remote
def _training_task(fields: dict[str, Any]) -> str:
    """One training trial (``agents.grid.trials.train_trial``): trains, resumes or reuses it."""
    return str(train_trial(TrainingTrial(**fields)))


def train_on_ray(
    trials: Sequence[TrainingTrial], max_failures: int = DEFAULT_MAX_FAILURES
) -> list[Path]:
    """Runs ``trials`` as Ray tasks, each declaring its ``cpus``, as many at once as the
    cluster's CPUs hold. Returns the run directories in the order of ``trials``; raises
    ``GridError`` naming the trials that failed after ``max_failures`` retries (a retry
    resumes from the trial's newest checkpoint; the other trials' runs are finished and
    kept)."""
    names = [trial.name for trial in trials]
    if len(set(names)) != len(names):
        raise ValueError(f"each trial may appear once, got {names}")
    pending = {
        _training_task.options(
            num_cpus=trial.cpus, max_retries=max_failures, retry_exceptions=True
        ).remote(asdict(trial)): trial
        for trial in trials
    }
    failed, finished = [], 0
    while pending:
        [ready], _ = ray.wait(list(pending), num_returns=1)
        trial = pending.pop(ready)
        try:
            ray.get(ready)
        except Exception as err:  # the trial's error after its retries
            failed.append(f"{trial.name}: {err!r}")
            print(f"failed: {trial.name} ({type(err).__name__})", flush=True)
            continue
        finished += 1
        print(f"finished {trial.name} ({finished} of {len(trials)})", flush=True)
    if failed:
        raise GridError(
            f"{len(failed)} of {len(trials)} training trials failed after {max_failures} "
            "retries (the finished runs are kept; run the same command again to retry):\n  "
            + "\n  ".join(failed)
        )
    return [trial.run_dir for trial in trials]


@ray.remote(num_cpus=1)
def _evaluation_task(
    spec: str, files: dict[str, bytes] | None, seeds: list[int], actions: str, env_id: str | None
) -> list[dict]:
    return evaluate_shard(spec, files, seeds, actions, env_id)


def evaluate_on_ray(
    agent_specs: Sequence[str],
    *,
    out: Path,
    episodes: int,
    split: str = "validation",
    final: bool = False,
    shard_episodes: int = DEFAULT_SHARD_EPISODES,
    max_failures: int = DEFAULT_MAX_FAILURES,
    gifs: bool = True,
    actions: str = "recipe",
    env_id: str | None = None,
) -> list[Summary]:
    """``agents.evaluation.evaluation.evaluate`` with the episodes run as Ray tasks: each
    agent's missing (layout) episodes in slices of ``shard_episodes``, every row appended to
    ``<out>/episodes.csv`` as its task ends. Then ``evaluate`` writes the table, plots and
    GIFs from those rows (reusing them all), as it does after a run of its own. A task that
    fails is retried ``max_failures`` times; if some still fail, ``GridError`` names them
    after the others have finished (their rows are kept: run again to finish). ``actions``:
    how learned agents act, ``env_id`` the task and tier they play (``evaluate``'s)."""
    out = Path(out)
    seeds = evaluation_seeds(split, episodes, final)
    made, names, fingerprints, done = prepare_evaluation(
        agent_specs, out, seeds, resume=True, actions=actions, env_id=env_id
    )
    map_modes = [env_kwargs["map"] for _, env_kwargs in made]
    csv_path = out / "episodes.csv"
    task = _evaluation_task.options(max_retries=max_failures, retry_exceptions=True)
    pending: dict[Any, tuple[str, str, str, list[int]]] = {}
    for spec, name, map_mode in zip(agent_specs, names, map_modes, strict=True):
        todo = [seed for seed in seeds if (name, seed) not in done]
        files = None if spec in SCRIPTED_AGENTS else ray.put(evaluated_files(Path(spec)))
        for shard in shards(todo, shard_episodes):
            pending[task.remote(spec, files, shard, actions, env_id)] = (
                name,
                map_mode,
                fingerprints[spec],
                shard,
            )
    failed = []
    with csv_path.open("a", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(EPISODE_COLUMNS))
        while pending:
            [ready], _ = ray.wait(list(pending), num_returns=1)
            name, map_mode, fingerprint, shard = pending.pop(ready)
            try:
                results = ray.get(ready)
            except Exception as err:  # the task's error after its retries
                failed.append(f"{name}, seeds {shard[0]}..{shard[-1]}: {err!r}")
                continue
            writer.writerows(episode_row(name, map_mode, r, fingerprint) for r in results)
            f.flush()
    if failed:
        raise GridError(
            f"{len(failed)} evaluation shards failed after {max_failures} retries (the other "
            "rows are in episodes.csv; run the same command again to finish):\n  "
            + "\n  ".join(failed)
        )
    return evaluate(
        agent_specs,
        out=out,
        episodes=episodes,
        split=split,
        final=final,
        gifs=gifs,
        resume=True,
        actions=actions,
        env_id=env_id,
    )
