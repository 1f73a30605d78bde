"""The experiment grid's units of work, whoever schedules them: a training trial (one agent,
map mode and training seed) and an evaluation shard (one agent on a slice of the layouts).

``agents.pipeline`` runs them one after another in this process, or hands them to Ray
(``agents.grid.ray_scheduler``: Ray tasks, on this machine or a cluster). What a unit
produces depends only on its own fields, never on where or in what order it ran:

- a trial's model is fixed by its algorithm's recipe (with its imitation section, the
  clone stage), map mode, seed, timesteps and ``cpus`` (its torch threads: torch's CPU
  kernels may sum in another order with another thread count; the environment batch's
  threads do not change its results);
- a shard's rows are fixed by the agent (its model's contents) and the layout seeds: every
  episode starts from its layout seed, and a scripted agent with a random generator is
  seeded per episode (``agents.evaluation.agent_specs.SeededPerEpisode``).
"""

from __future__ import annotations

import tempfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from agents.imitation.clone_stage import train_with_clone_stage
from agents.run_dir import (
    CONFIG_FILE,
    checkpoints,
    model_path,
    read_run_config,
    run_name,
    task_folder,
    write_evaluated_files,
)
from agents.sb3.recipes import run_recipe
from agents.sb3.training import TrainSettings
from tactile_search import ENV_ID


@dataclass(frozen=True)
class TrainingTrial:
    """One training run of the grid.

    ``runs``: the directory that holds the run directories (absolute, so a Ray trial, which
    may run in another working directory, writes to the same place). ``timesteps``: ``None`` for
    the recipe's ``n_timesteps``. ``cpus``: the CPUs the trial declares, used as its torch
    threads and its environment batch's threads. ``n_envs``: ``None`` for the recipe's.
    ``init_from``: a run directory or model file to warm-start from (``TrainSettings``'), or
    None. ``imitation``: overrides of the recipe's imitation section (the clone stage's,
    ``train_with_clone_stage``); ``from_scratch``: skip that stage (``TrainSettings``').
    ``env_id``: the registered id it trains on (its recipe's key); its run directory is
    ``runs/<task_folder(env_id)>/<run_name>``."""

    algo: str
    map_mode: str
    seed: int
    runs: str
    timesteps: int | None
    cpus: int
    n_envs: int | None = None
    # The code's git commit and dirty flag for config.yml, from where the grid was started
    # (a Ray worker's copy of ``agents`` is not a git checkout); None: the trainer's own.
    code: dict[str, Any] | None = field(default=None, hash=False)
    init_from: str | None = None
    imitation: dict[str, Any] | None = field(default=None, hash=False)
    from_scratch: bool = False
    env_id: str = ENV_ID

    def __post_init__(self) -> None:
        if not Path(self.runs).is_absolute():
            raise ValueError(f"runs must be an absolute path, got {self.runs!r}")
        if isinstance(self.cpus, bool) or not isinstance(self.cpus, int) or self.cpus < 1:
            raise ValueError(f"cpus must be an int >= 1, got {self.cpus!r}")
        task_folder(self.env_id)  # a registered id, or a clear error

    @property
    def run_dir(self) -> Path:
        return Path(self.runs) / self.name

    @property
    def name(self) -> str:
        """The run directory's path under ``runs``: unique in a grid of several ids."""
        run = run_name(self.algo, self.map_mode, self.seed)
        folder = task_folder(self.env_id)
        return f"{folder}/{run}" if folder else run


def changed_recipe_keys(trial: TrainingTrial) -> list[str]:
    """The recipe keys whose value in the ``config.yml`` of ``trial``'s run directory differs
    from the recipe ``trial`` trains now (``run_recipe`` with the trial's timesteps and
    ``n_envs``, as ``train`` records it), sorted; ``["config.yml"]`` when that file cannot
    be read as a run's config. The imitation section is left out: the clone stage checks its
    own clone (``agents.imitation.clone_stage``), and a warm start or PPO from scratch
    records none."""
    try:
        config = read_run_config(trial.run_dir, required=("algo", "map", "hyperparams", "versions"))
    except ValueError:
        return [CONFIG_FILE]
    recorded = config["hyperparams"]
    recipe = run_recipe(
        trial.algo, trial.map_mode, trial.env_id, timesteps=trial.timesteps, n_envs=trial.n_envs
    )
    keys = (recipe.keys() | recorded.keys()) - {"imitation"}
    return sorted(key for key in keys if recipe.get(key) != recorded.get(key))


def discard_run(run_dir: Path) -> None:
    """Makes way for a fresh run in ``run_dir``: its model and checkpoints go (the model
    first, so that a kill in between leaves no model beside a config that does not describe
    it); ``config.yml`` and ``progress.csv`` are rewritten by the new run, and the clone in
    ``imitation/`` stays for the clone stage to reuse or replace."""
    model_path(run_dir).unlink(missing_ok=True)
    for _, path in checkpoints(run_dir):
        path.unlink()


def train_trial(trial: TrainingTrial, progress_bar: bool = False) -> Path:
    """Runs ``trial`` to its end: reuses a finished run (its ``model.zip`` exists) trained
    with the recipe the trial has now, resumes a partly trained one from its newest
    checkpoint, or trains it afresh. A run whose recorded recipe differs from the trial's
    (``changed_recipe_keys``: a recipe edited since, another budget) is discarded and
    trained again, with a line saying which keys changed. Returns the run directory."""
    run_dir = trial.run_dir
    if model_path(run_dir).is_file() or checkpoints(run_dir):
        changed = changed_recipe_keys(trial)
        if changed:
            print(
                f"training {run_dir} again: its recipe differs from the trial's in "
                f"{', '.join(changed)}",
                flush=True,
            )
            discard_run(run_dir)
        elif model_path(run_dir).is_file():
            print(f"reusing {run_dir}", flush=True)
            return run_dir
    resume = bool(checkpoints(run_dir))
    print(
        f"{'resuming' if resume else 'training'} {trial.algo} with the {trial.map_mode} map, "
        f"seed {trial.seed}",
        flush=True,
    )
    settings = TrainSettings(
        trial.algo,
        trial.map_mode,
        env_id=trial.env_id,
        out=run_dir.parent,
        seed=trial.seed,
        timesteps=trial.timesteps,
        n_envs=trial.n_envs,
        torch_threads=trial.cpus,
        env_threads=trial.cpus,
        progress_bar=progress_bar,
        resume=resume,
        code=trial.code,
        init_from=None if resume or trial.init_from is None else Path(trial.init_from),
        from_scratch=trial.from_scratch,
    )
    return train_with_clone_stage(settings, trial.imitation)


def evaluate_shard(
    spec: str,
    files: dict[str, bytes] | None,
    seeds: list[int],
    actions: str = "recipe",
    env_id: str | None = None,
) -> list[dict[str, Any]]:
    """One episode per seed of the agent ``spec`` (a scripted name, or a run whose ``files``
    are given), as ``agents.rollout.evaluate_agent`` summarises them; a learned agent acts
    as ``actions`` says (``agents.evaluation.agent_specs.ACTIONS``), in the task and tier
    of ``env_id`` when given (``agents.evaluation.evaluation.evaluate``'s). Uses one torch
    thread, as ``evaluate`` does."""
    from agents.evaluation.agent_specs import make_agent
    from agents.evaluation.evaluation import env_id_settings
    from agents.rollout import evaluate_agent

    if files is None:
        agent, env_kwargs = make_agent(spec, actions)
    else:
        import torch

        torch.set_num_threads(1)
        with tempfile.TemporaryDirectory(prefix="tactile_search_run_") as tmp:
            write_evaluated_files(Path(tmp), files)
            # The agent holds the model in memory from here on.
            agent, env_kwargs = make_agent(tmp, actions)
    env_kwargs = {**env_kwargs, **env_id_settings(env_id)}
    # One episode at a time on one thread: the task declares one CPU.
    return evaluate_agent(agent, seeds, num_envs=1, threads=1, **env_kwargs)


def shards(seeds: list[int], size: int) -> list[list[int]]:
    """``seeds`` in consecutive slices of at most ``size``."""
    if isinstance(size, bool) or not isinstance(size, int) or size < 1:
        raise ValueError(f"the shard size must be an int >= 1, got {size!r}")
    return [seeds[i : i + size] for i in range(0, len(seeds), size)]
