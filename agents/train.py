"""Train a stable-baselines3 agent on ``tactile_search/CupboardSearch-v0``.

Importable functions under a thin CLI (the rl-baselines3-zoo layout)::

    python -m agents.train --algo ppo --map gpis --seed 0 --out runs
    python -m agents.train --algo recurrent_ppo --map none --timesteps 200000
    python -m agents.train --algo ppo --map gpis --seed 0 --out runs --resume

Hyperparameters come from ``agents/hyperparams/<algo>.yml``, keyed by env id and map mode.
Each run writes into ``<out>/<algo>_<map>_seed<seed>/``: ``model.zip``, ``config.yml`` (the
resolved recipe, the command's arguments, package versions and the wall-clock time),
``progress.csv``, TensorBoard events and ``checkpoints/`` (the last few, at rollout
boundaries). Training runs on ``CupboardSearchSb3VecEnv`` (the Rust batch, both cores) and
draws layout seeds from ``TRAIN_LAYOUT_SEEDS``, a range disjoint from the held-out
evaluation seeds of ``agents/evaluate.py``.

A killed run continues from its newest checkpoint with ``--resume`` (see ``train``); Ctrl-C
saves a checkpoint, prints the command that resumes it and exits with status 130.
"""

from __future__ import annotations

import argparse
import contextlib
import copy
import csv
import datetime
import importlib
import os
import platform
import re
import shlex
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path
from typing import IO, Any

import gymnasium as gym
import numpy as np
import yaml

import tactile_search
from agents import seed_ranges
from tactile_search.envs.config import MAP_MODES

# Torch's OpenMP threads busy-wait between parallel regions by default; on this 2-core
# machine they then fight the environment batch's worker threads (and other jobs) for the
# cores. Passive waiting, set before torch loads its OpenMP runtime, measured: PPO with the
# GPIS recipe on the Rust batch 417 vs ~100 steps/s (torch threads 2), and 0.81 instead of
# 0.52 of the speed on a zero-cost VecEnv (`python -m benchmarks.ppo_env_overhead`). A value
# the user set is kept.
os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")

ENV_ID = "tactile_search/CupboardSearch-v0"
HYPERPARAMS_DIR = Path(__file__).parent / "hyperparams"
# Where the published models are trained (agents.pipeline's full budget), from the repo root.
PUBLISHED_RUNS = "docs/results/models"
ALGORITHMS = ("ppo", "recurrent_ppo")
# Training layouts are drawn from [2**32, 2**63); evaluation holds out seeds below 2**32.
TRAIN_LAYOUT_SEEDS = seed_ranges.TRAINING
# Recipe keys that configure the run rather than the algorithm.
RUN_KEYS = (
    "n_timesteps",
    "max_minutes",
    "n_envs",
    "policy",
    "env_kwargs",
    "deterministic_evaluation",
)
# A checkpoint at the first rollout boundary after every this many env steps (with the
# recipes' 16 x 128-step rollouts, every 25th rollout: about a minute of training here), and
# how many of the newest are kept. A checkpoint of the GPIS-map PPO model is ~3 MB.
DEFAULT_CHECKPOINT_EVERY = 50_000
DEFAULT_KEEP_CHECKPOINTS = 3
CHECKPOINT_DIR = "checkpoints"
CHECKPOINT_PREFIX = "rl_model"
CHECKPOINT_NAME = re.compile(rf"{CHECKPOINT_PREFIX}_(\d+)_steps\.zip")
# The exit status after Ctrl-C (128 + SIGINT, the shell's convention).
INTERRUPTED_EXIT_STATUS = 130


def algorithm_class(algo: str) -> type:
    """The SB3 class of ``algo`` (``ppo`` or ``recurrent_ppo``)."""
    if algo == "ppo":
        from stable_baselines3 import PPO

        return PPO
    if algo == "recurrent_ppo":
        from sb3_contrib import RecurrentPPO

        return RecurrentPPO
    raise ValueError(f"algo must be one of {ALGORITHMS}, got {algo!r}")


def load_hyperparams(
    algo: str, map_mode: str, env_id: str = ENV_ID, path: Path | None = None
) -> dict[str, Any]:
    """The recipe for ``algo`` on ``env_id`` with ``map_mode`` from its YAML file."""
    if algo not in ALGORITHMS:
        raise ValueError(f"algo must be one of {ALGORITHMS}, got {algo!r}")
    path = path or HYPERPARAMS_DIR / f"{algo}.yml"
    recipes = yaml.safe_load(path.read_text())
    if env_id not in recipes:
        raise ValueError(f"{path} has no recipe for env id {env_id!r}; it has {sorted(recipes)}")
    by_map = recipes[env_id]
    if map_mode not in by_map:
        raise ValueError(
            f"{path} has no {env_id!r} recipe for map {map_mode!r}; it has {sorted(by_map)}"
        )
    recipe = copy.deepcopy(by_map[map_mode])
    recipe.setdefault("env_kwargs", {})["map"] = map_mode
    return recipe


def make_training_env(
    env_kwargs: dict[str, Any],
    n_envs: int,
    seed: int,
    env_id: str = ENV_ID,
    threads: int | None = None,
) -> Any:
    """The SB3 vector env for training: the Rust batch (``threads`` worker threads, default
    every core), monitored for episode statistics."""
    from stable_baselines3.common.vec_env import VecMonitor

    from tactile_search.envs.sb3_vec_env import CupboardSearchSb3VecEnv

    # The time limit is the env's own `max_steps` (in env_kwargs or the core's default).
    venv = CupboardSearchSb3VecEnv(
        num_envs=n_envs,
        seed=seed,
        layout_seeds=TRAIN_LAYOUT_SEEDS,
        threads=threads,
        **env_kwargs,
    )
    return VecMonitor(venv, info_keywords=("success", "tips", "jar_displacement", "iou"))


# A recipe names classes in its policy_kwargs by dotted path (YAML holds no classes).
CLASS_KEYS = ("features_extractor_class",)


def algorithm_kwargs(recipe: dict[str, Any]) -> dict[str, Any]:
    """The recipe's arguments for the SB3 algorithm: every key but ``RUN_KEYS``, with the
    classes that ``policy_kwargs`` names by dotted path (``features_extractor_class:
    agents.encoders.ImpalaMapExtractor``) imported."""
    kwargs = {key: value for key, value in recipe.items() if key not in RUN_KEYS}
    policy_kwargs = dict(kwargs.get("policy_kwargs") or {})
    for key in CLASS_KEYS:
        name = policy_kwargs.get(key)
        if isinstance(name, str):
            module, _, attribute = name.rpartition(".")
            try:
                policy_kwargs[key] = getattr(importlib.import_module(module), attribute)
            except (ImportError, AttributeError, ValueError) as err:
                raise ValueError(
                    f"policy_kwargs.{key} must name an importable class as module.Class, "
                    f"got {name!r} ({type(err).__name__}: {err})"
                ) from err
    if policy_kwargs:
        kwargs["policy_kwargs"] = policy_kwargs
    return kwargs


def run_name(algo: str, map_mode: str, seed: int) -> str:
    """The run directory's name."""
    return f"{algo}_{map_mode}_seed{seed}"


def versions() -> dict[str, str]:
    """Versions of what produced a run."""
    import stable_baselines3
    import torch

    return {
        "tactile_search": tactile_search.__version__,
        "stable_baselines3": stable_baselines3.__version__,
        "torch": str(torch.__version__),
        "gymnasium": gym.__version__,
        "python": platform.python_version(),
    }


def machine() -> dict[str, Any]:
    """The machine a run trained on, as ``config.yml`` records it."""
    import torch

    return {
        "cpus": os.cpu_count(),
        "processor": platform.processor() or platform.machine(),
        "system": platform.platform(),
        "gpu": torch.cuda.get_device_name(0) if torch.cuda.is_available() else None,
    }


def code_version(repo: Path | None = None) -> dict[str, Any]:
    """The code that produced a run: the git commit of ``repo`` (default: the checkout this
    ``agents`` package sits in) and whether its tree differed from the commit (``dirty``:
    changed or new files that git does not ignore). Both ``None`` outside a git checkout,
    e.g. in a Ray worker's copy of ``agents``: there the driver's version is passed in."""
    repo = Path(__file__).resolve().parents[1] if repo is None else Path(repo)

    def git(*args: str) -> str:
        done = subprocess.run(
            ["git", "-C", str(repo), *args], capture_output=True, text=True, timeout=30
        )
        if done.returncode != 0:
            raise subprocess.SubprocessError(done.stderr.strip())
        return done.stdout.strip()

    try:
        commit = git("rev-parse", "HEAD")
        dirty = bool(git("status", "--porcelain", "--", ".", f":(exclude){PUBLISHED_RUNS}"))
    except (OSError, subprocess.SubprocessError):
        return {"commit": None, "dirty": None}
    return {"commit": commit, "dirty": dirty}


def wall_clock_limit(minutes: float) -> Any:
    """An SB3 callback that stops training once ``minutes`` of wall-clock time have passed
    (checked after every step; the model is then saved as usual)."""
    from stable_baselines3.common.callbacks import BaseCallback

    class StopAfter(BaseCallback):
        def _on_training_start(self) -> None:
            self.deadline = time.perf_counter() + 60.0 * minutes

        def _on_step(self) -> bool:
            return time.perf_counter() < self.deadline

    return StopAfter()


@contextlib.contextmanager
def replaced_atomically(path: Path, mode: str) -> Iterator[IO[Any]]:
    """A file to write ``path``'s new content into: a temporary file renamed over ``path``
    once written and synced, so a kill leaves either the old file or the new one, never
    half of one."""
    tmp = path.with_name(path.name + ".tmp")
    with tmp.open(mode) as f:
        yield f
        f.flush()
        os.fsync(f.fileno())
    os.replace(tmp, path)


def write_atomically(path: Path, text: str) -> None:
    """Writes ``text`` to ``path`` atomically (see ``replaced_atomically``)."""
    with replaced_atomically(path, "w") as f:
        f.write(text)


def save_model_atomically(model: Any, path: Path) -> None:
    """``model.save(path)`` atomically (see ``replaced_atomically``)."""
    with replaced_atomically(path, "wb") as f:
        model.save(f)


def checkpoints(run_dir: Path) -> list[tuple[int, Path]]:
    """The checkpoints of a run as ``(timesteps, path)``, oldest first."""
    found = []
    for path in (Path(run_dir) / CHECKPOINT_DIR).glob(f"{CHECKPOINT_PREFIX}_*_steps.zip"):
        match = CHECKPOINT_NAME.fullmatch(path.name)
        if match:
            found.append((int(match.group(1)), path))
    return sorted(found)


def resumed_env_seed(seed: int, timesteps_done: int) -> int:
    """The seed of a resumed run's layout generator, torch and numpy: a function of the run's
    seed and the timesteps already done, so a resumed run neither replays the layouts of its
    start nor depends on anything but where it resumed."""
    sequence = np.random.SeedSequence([seed, timesteps_done])
    # 32 bits: SB3's set_random_seed also seeds numpy's legacy generator.
    return int(sequence.generate_state(1, dtype=np.uint32)[0])


def read_run_config(run_dir: Path, required: tuple[str, ...] = ("algo", "map", "versions")) -> dict:
    """A run's ``config.yml``, checked: a mapping with the ``required`` keys, a known algo and
    map mode, written by this version of tactile_search. Raises ``ValueError`` naming the
    file and what is wrong."""
    run_dir = Path(run_dir)
    if not run_dir.is_dir():
        raise ValueError(f"{run_dir} is not a training run: no such directory")
    path = run_dir / "config.yml"
    if not path.is_file():
        raise ValueError(f"{run_dir} is not a training run: {path.name} is missing ({path})")
    try:
        config = yaml.safe_load(path.read_text())
    except (yaml.YAMLError, UnicodeDecodeError) as err:
        raise ValueError(f"{path} is not a readable YAML file: {err}") from err
    if not isinstance(config, dict):
        raise ValueError(
            f"{path} must hold a mapping of the run's settings, got {type(config).__name__}"
        )
    missing = [key for key in required if key not in config]
    if missing:
        raise ValueError(f"{path} lacks the keys {missing} (it has {sorted(config)})")
    if "algo" in required and config["algo"] not in ALGORITHMS:
        raise ValueError(f"{path}: algo must be one of {ALGORITHMS}, got {config['algo']!r}")
    if "map" in required and config["map"] not in MAP_MODES:
        raise ValueError(f"{path}: map must be one of {MAP_MODES}, got {config['map']!r}")
    if "versions" in required:
        versions_ = config["versions"]
        if not isinstance(versions_, dict) or "tactile_search" not in versions_:
            raise ValueError(
                f"{path}: versions must be a mapping with a tactile_search entry, got {versions_!r}"
            )
        if str(versions_["tactile_search"]) != tactile_search.__version__:
            raise ValueError(
                f"{path} was written by tactile_search {versions_['tactile_search']}, this is "
                f"tactile_search {tactile_search.__version__}: the environment may differ from "
                "the one the run trained in; retrain it, or install that version"
            )
    if "hyperparams" in required:
        recipe = config["hyperparams"]
        needed = ("n_timesteps", "n_envs", "policy", "env_kwargs")
        if not isinstance(recipe, dict) or any(key not in recipe for key in needed):
            raise ValueError(f"{path}: hyperparams must be a mapping with the keys {needed}")
    return config


def is_finished(run_dir: Path, config: dict) -> bool:
    """Whether a run finished: its ``model.zip`` exists and its config records the timesteps
    done (the config is written first, then the model, each atomically)."""
    return (Path(run_dir) / "model.zip").is_file() and "timesteps_done" in config


def kept_progress(path: Path, timesteps: int) -> tuple[list[str], list[str]] | None:
    """The header and the complete rows of a ``progress.csv`` logged at or before
    ``timesteps`` (the later rows belong to work a resumed run redoes; a row cut short by a
    kill is dropped). None if there is no usable file."""
    if not path.is_file():
        return None
    lines = path.read_text().splitlines(keepends=True)
    if not lines or not lines[0].endswith("\n"):
        return None
    header = next(csv.reader([lines[0]]))
    if "time/total_timesteps" not in header:
        return header, []
    column = header.index("time/total_timesteps")
    kept = []
    for line in lines[1:]:
        if not line.endswith("\n"):
            break
        row = next(csv.reader([line]), [])
        if len(row) != len(header):
            continue
        try:
            done = float(row[column])
        except ValueError:
            continue
        if done <= timesteps:
            kept.append(line)
    return header, kept


def make_logger(run_dir: Path, kept: tuple[list[str], list[str]] | None = None) -> Any:
    """SB3's logger writing ``progress.csv`` and TensorBoard events into ``run_dir``.

    With ``kept`` (a header and rows from ``kept_progress``), ``progress.csv`` is first
    replaced (atomically) by those rows and the new rows are appended: SB3's own CSV writer
    opens the file with mode ``"w"`` and would wipe the rows of the run's earlier part.
    """
    from stable_baselines3.common.logger import CSVOutputFormat, Logger, make_output_format

    class AppendingCSVOutputFormat(CSVOutputFormat):
        """SB3's CSV writer, continuing a file that already holds ``header`` and ``rows``."""

        def __init__(self, filename: Path, header: list[str], rows: list[str]) -> None:
            buffer = [",".join(header) + "\n", *rows]
            write_atomically(filename, "".join(buffer))
            self.file = open(filename, "r+")  # closed by Logger.close
            self.file.seek(0, os.SEEK_END)
            self.keys = list(header)
            self.separator = ","
            self.quotechar = '"'

    path = Path(run_dir) / "progress.csv"
    if kept is None:
        csv_format = CSVOutputFormat(str(path))
    else:
        csv_format = AppendingCSVOutputFormat(path, *kept)
    return Logger(str(run_dir), [csv_format, make_output_format("tensorboard", str(run_dir))])


def rollout_checkpoints(run_dir: Path, every: int, keep: int, on_save: Any = None) -> Any:
    """SB3's ``CheckpointCallback`` saving into ``<run_dir>/checkpoints/`` at rollout
    boundaries: at the start of the first rollout at least ``every`` env steps after the last
    checkpoint, when the policy has been updated with every rollout counted in
    ``num_timesteps``. (SB3's own callback saves every so many steps, mid-rollout: a run
    resumed from such a checkpoint counts steps its policy never learned from and ends at
    another total.) Keeps the newest ``keep``; ``on_save(timesteps, path)`` runs after each.
    ``save_interrupted()`` saves the state at the start of the rollout under way (after
    Ctrl-C)."""
    from stable_baselines3.common.callbacks import CheckpointCallback

    class RolloutCheckpoints(CheckpointCallback):
        def __init__(self) -> None:
            super().__init__(
                save_freq=every,
                save_path=str(Path(run_dir) / CHECKPOINT_DIR),
                name_prefix=CHECKPOINT_PREFIX,
            )
            self._last_saved = 0
            self._boundary: int | None = None
            self._collecting = False
            self._before_update: tuple | None = None

        def _on_training_start(self) -> None:
            self._last_saved = self.model.num_timesteps

        def _on_rollout_start(self) -> None:
            self._boundary = self.model.num_timesteps
            self._before_update = None
            self._collecting = True
            if self._boundary - self._last_saved >= every:
                self.save()

        def _on_rollout_end(self) -> None:
            # The policy (and its optimizer) as the rollout found it: Ctrl-C during the
            # update that follows restores it rather than keep a half-done update.
            policy = self.model.policy
            self._before_update = (
                copy.deepcopy(policy.state_dict()),
                copy.deepcopy(policy.optimizer.state_dict()),
                self.model._n_updates,
            )
            self._collecting = False

        def _on_step(self) -> bool:
            return True

        def save(self) -> Path:
            self.num_timesteps = self.model.num_timesteps
            path = Path(self._checkpoint_path(extension="zip"))
            path.parent.mkdir(parents=True, exist_ok=True)
            save_model_atomically(self.model, path)
            self._last_saved = self.model.num_timesteps
            for _, old in checkpoints(run_dir)[:-keep]:
                old.unlink(missing_ok=True)
            if on_save is not None:
                on_save(self.model.num_timesteps, path)
            return path

        def save_interrupted(self) -> Path:
            model = self.model
            if self._boundary is not None:
                if not self._collecting and self._before_update is not None:
                    state, optimizer, n_updates = self._before_update
                    model.policy.load_state_dict(state)
                    model.policy.optimizer.load_state_dict(optimizer)
                    model._n_updates = n_updates
                model.num_timesteps = self._boundary
            return self.save()

    return RolloutCheckpoints()


def resume_command(
    algo: str,
    map_mode: str,
    seed: int,
    out: Path,
    checkpoint_every: int,
    keep_checkpoints: int,
    torch_threads: int,
    progress_bar: bool,
) -> str:
    """The shell command that resumes a run."""
    args = [sys.executable, "-m", "agents.train", "--algo", algo, "--map", map_mode]
    args += ["--seed", str(seed), "--out", str(out), "--resume"]
    if checkpoint_every != DEFAULT_CHECKPOINT_EVERY:
        args += ["--checkpoint-every", str(checkpoint_every)]
    if keep_checkpoints != DEFAULT_KEEP_CHECKPOINTS:
        args += ["--keep-checkpoints", str(keep_checkpoints)]
    if torch_threads != 2:
        args += ["--torch-threads", str(torch_threads)]
    if not progress_bar:
        args.append("--no-progress")
    return shlex.join(args)


def _check_positive_int(name: str, value: Any) -> None:
    if isinstance(value, bool) or not isinstance(value, int) or value < 1:
        raise ValueError(f"{name} must be an int >= 1, got {value!r}")


def train(
    algo: str,
    map_mode: str,
    *,
    out: Path = Path("runs"),
    seed: int = 0,
    timesteps: int | None = None,
    n_envs: int | None = None,
    torch_threads: int = 2,
    env_threads: int | None = None,
    progress_bar: bool = True,
    env_id: str = ENV_ID,
    hyperparams: Path | None = None,
    max_minutes: float | None = None,
    checkpoint_every: int = DEFAULT_CHECKPOINT_EVERY,
    keep_checkpoints: int = DEFAULT_KEEP_CHECKPOINTS,
    resume: bool = False,
    code: dict[str, Any] | None = None,
    init_from: Path | None = None,
) -> Path:
    """Trains one agent and returns its run directory (``model.zip``, ``config.yml``, logs).

    ``init_from`` (a run directory or its ``model.zip``, e.g. a published model under
    ``docs/results/models/``) warm-starts the policy: its weights, for the same algorithm and
    network, are loaded before training (the optimizer starts afresh); ``config.yml`` records
    the path and the model's digest under ``init_from``.

    ``config.yml`` records ``code`` (the git commit and whether the tree was dirty), by
    default ``code_version()`` of this checkout.

    ``timesteps`` and ``n_envs`` override the recipe's ``n_timesteps`` and ``n_envs``;
    ``max_minutes`` (or the recipe's ``max_minutes``) stops training earlier on wall-clock
    time, and ``config.yml`` records the timesteps done.
    ``torch_threads`` sets torch's intra-op threads. On this 2-core machine, training alone,
    2 threads ran PPO with the GPIS map 1.38x faster than 1 (median 1148 vs 832 steps/s,
    ``python benchmarks/train_threads.py --timesteps 8192 --repeats 2``); use 1 when two
    runs share the cores. ``env_threads`` sets the environment batch's worker threads
    (default: every core; the results do not depend on it); a run given one CPU (a Ray
    trial) uses one.

    Checkpoints go to ``<run_dir>/checkpoints/`` at the first rollout boundary after every
    ``checkpoint_every`` env steps; the newest ``keep_checkpoints`` are kept. Ctrl-C saves a
    checkpoint of the state at the start of the rollout under way, prints where it is and the
    command that resumes it, and re-raises ``KeyboardInterrupt``.

    ``resume=True`` continues the run in the same directory from its newest checkpoint, with
    the recipe recorded in its ``config.yml`` (``timesteps``, ``n_envs``, ``hyperparams`` and
    ``max_minutes``, if given, must agree with it), to the same total timesteps; the rows of
    ``progress.csv`` up to the checkpoint are kept, later ones (work that is redone) dropped;
    TensorBoard events go on in a new file in the same directory; ``config.yml`` lists each
    resume under ``resumes``. Resuming a finished run prints so and returns; resuming a run
    without a checkpoint raises ``ValueError`` (start it afresh without ``resume``). Starting
    afresh where an unfinished run left checkpoints raises ``ValueError`` too (resume it, or
    delete its ``checkpoints/``).

    A resumed run is not bit-identical to an uninterrupted one: a checkpoint holds the
    policy, its optimizer and the counters, but not the vector env's episodes in flight nor
    the random streams (layout seeds, torch's action noise). The resumed part starts new
    episodes, its layouts drawn from a generator seeded by ``resumed_env_seed(seed,
    timesteps done)`` (not replaying the layouts of the run's start), and seeds torch and
    numpy the same way. The policy, the timestep count and the total are exact.
    """
    if algo not in ALGORITHMS:
        raise ValueError(f"algo must be one of {ALGORITHMS}, got {algo!r}")
    if map_mode not in MAP_MODES:
        raise ValueError(f"map must be one of {MAP_MODES}, got {map_mode!r}")
    if not isinstance(seed, int) or seed < 0:
        raise ValueError(f"seed must be a non-negative int, got {seed!r}")
    if timesteps is not None and timesteps < 1:
        raise ValueError(f"timesteps must be >= 1, got {timesteps}")
    if torch_threads < 1:
        raise ValueError(f"torch_threads must be >= 1, got {torch_threads}")
    if env_threads is not None:
        _check_positive_int("env_threads", env_threads)
    if max_minutes is not None and not max_minutes > 0:
        raise ValueError(f"max_minutes must be > 0, got {max_minutes}")
    _check_positive_int("checkpoint_every", checkpoint_every)
    _check_positive_int("keep_checkpoints", keep_checkpoints)
    if not isinstance(resume, bool):
        raise TypeError(f"resume must be a bool, got {type(resume).__name__}")
    if init_from is not None:
        if resume:
            raise ValueError("init_from starts a new run; a resumed run keeps its own weights")
        init_from = model_file(Path(init_from))
    run_dir = Path(out) / run_name(algo, map_mode, seed)
    config_path = run_dir / "config.yml"
    if resume:
        config = read_run_config(
            run_dir, required=("algo", "env_id", "map", "seed", "hyperparams", "versions")
        )
        for key, value in (("algo", algo), ("env_id", env_id), ("map", map_mode), ("seed", seed)):
            if config[key] != value:
                raise ValueError(f"{config_path}: {key} is {config[key]!r}, not {value!r}")
        recipe = config["hyperparams"]
        asked = {"n_timesteps": timesteps, "n_envs": n_envs, "max_minutes": max_minutes}
        if hyperparams is not None:
            asked = {**load_hyperparams(algo, map_mode, env_id, hyperparams), **asked}
        for key, value in asked.items():
            if value is not None and recipe.get(key) != value:
                raise ValueError(
                    f"a resumed run keeps the recipe in {config_path}: its {key} is "
                    f"{recipe.get(key)!r}, asked for {value!r} (start a new run to change it)"
                )
        if is_finished(run_dir, config):
            print(
                f"{run_dir} already finished ({config['timesteps_done']:,} timesteps): "
                "nothing to resume",
                flush=True,
            )
            return run_dir
        if not checkpoints(run_dir):
            raise ValueError(
                f"{run_dir} has no checkpoint to resume from ({run_dir / CHECKPOINT_DIR} holds "
                f"no {CHECKPOINT_PREFIX}_<timesteps>_steps.zip); start it afresh without "
                "--resume"
            )
    else:
        recipe = load_hyperparams(algo, map_mode, env_id, hyperparams)
        if timesteps is not None:
            recipe["n_timesteps"] = int(timesteps)
        if n_envs is not None:
            recipe["n_envs"] = int(n_envs)
        if max_minutes is not None:
            recipe["max_minutes"] = float(max_minutes)
        earlier = checkpoints(run_dir)
        if earlier:
            previous = yaml.safe_load(config_path.read_text()) if config_path.is_file() else None
            if not (isinstance(previous, dict) and is_finished(run_dir, previous)):
                raise ValueError(
                    f"{run_dir} holds an unfinished run with a checkpoint at "
                    f"{earlier[-1][0]:,} timesteps: resume it (--resume, train(..., "
                    f"resume=True)) or delete {run_dir / CHECKPOINT_DIR} to start afresh"
                )
            for _, path in earlier:
                path.unlink()
        # A fresh start replaces a finished run: its model goes first, so that a kill before
        # the new one is saved leaves no model beside a config that does not describe it.
        (run_dir / "model.zip").unlink(missing_ok=True)
        config = {
            "algo": algo,
            "env_id": env_id,
            "map": map_mode,
            "seed": seed,
            "torch_threads": torch_threads,
            "train_layout_seeds": list(TRAIN_LAYOUT_SEEDS),
            "hyperparams": recipe,
            "versions": versions(),
            "code": code or code_version(),
            "machine": machine(),
        }
    import torch
    from stable_baselines3.common.callbacks import CallbackList
    from stable_baselines3.common.utils import set_random_seed

    run_dir.mkdir(parents=True, exist_ok=True)
    torch.set_num_threads(torch_threads)
    cls = algorithm_class(algo)
    prior_seconds = 0.0
    if resume:
        done = checkpoints(run_dir)[-1][0]
        env = make_training_env(
            recipe["env_kwargs"],
            recipe["n_envs"],
            resumed_env_seed(seed, done),
            env_id,
            env_threads,
        )
        model = None
        for _, path in reversed(checkpoints(run_dir)):
            try:
                model = cls.load(path, env=env, device="cpu")
                break
            except Exception as err:  # a damaged checkpoint: fall back to the one before
                print(f"cannot load {path} ({type(err).__name__}: {err}); trying an older one")
        if model is None:
            env.close()
            raise ValueError(f"none of the checkpoints in {run_dir / CHECKPOINT_DIR} loads")
        done = int(model.num_timesteps)
        env_seed = resumed_env_seed(seed, done)
        model.set_random_seed(env_seed)  # torch, numpy, the action space, the layouts
        record = config.get("checkpoint")
        if isinstance(record, dict) and record.get("timesteps") == done:
            prior_seconds = float(record.get("wall_clock_seconds", 0.0))
        logger = make_logger(run_dir, kept_progress(run_dir / "progress.csv", done))
        for key in ("timesteps_done", "wall_clock_seconds"):
            config.pop(key, None)
        config.setdefault("resumes", []).append(
            {
                "from_timesteps": done,
                "checkpoint": path.name,
                "env_seed": env_seed,
                "at": datetime.datetime.now().isoformat(timespec="seconds"),
            }
        )
        if versions() != config["versions"]:  # the packages the rest was trained with
            config["resumes"][-1]["versions"] = versions()
        resumed_code = code or code_version()
        if resumed_code != config.get("code"):  # the code the rest ran
            config["resumes"][-1]["code"] = resumed_code
        print(f"resuming {run_dir} from {path} ({done:,} timesteps)", flush=True)
    else:
        done = 0
        set_random_seed(seed)
        env = make_training_env(recipe["env_kwargs"], recipe["n_envs"], seed, env_id, env_threads)
        algo_kwargs = algorithm_kwargs(recipe)
        model = cls(recipe["policy"], env, seed=seed, device="cpu", **algo_kwargs)
        if init_from is not None:
            config["init_from"] = warm_start(model, cls, init_from)
        logger = make_logger(run_dir)
    model.set_logger(logger)
    config["checkpoint_every"] = checkpoint_every
    write_atomically(config_path, yaml.safe_dump(config, sort_keys=False))

    started = time.perf_counter()

    def elapsed() -> float:
        return prior_seconds + time.perf_counter() - started

    def on_save(timesteps_done: int, path: Path) -> None:
        config["checkpoint"] = {
            "timesteps": timesteps_done,
            "file": path.name,
            "wall_clock_seconds": round(elapsed(), 1),
        }
        write_atomically(config_path, yaml.safe_dump(config, sort_keys=False))

    checkpointer = rollout_checkpoints(run_dir, checkpoint_every, keep_checkpoints, on_save)
    callbacks = [checkpointer]
    limit = recipe.get("max_minutes")
    minutes_left = None if limit is None else limit - prior_seconds / 60
    if minutes_left is not None:
        callbacks.append(wall_clock_limit(minutes_left))
    remaining = recipe["n_timesteps"] - done
    try:
        if remaining > 0 and (minutes_left is None or minutes_left > 0):
            model.learn(
                total_timesteps=remaining,
                callback=CallbackList(callbacks),
                progress_bar=progress_bar,
                reset_num_timesteps=not resume,
            )
    except KeyboardInterrupt:
        path = checkpointer.save_interrupted()
        logger.close()
        env.close()
        command = resume_command(
            algo,
            map_mode,
            seed,
            out,
            checkpoint_every,
            keep_checkpoints,
            torch_threads,
            progress_bar,
        )
        print(
            f"\ninterrupted: saved {path} ({model.num_timesteps:,} of "
            f"{recipe['n_timesteps']:,} timesteps); resume with\n  {command}",
            file=sys.stderr,
            flush=True,
        )
        raise
    config["wall_clock_seconds"] = round(elapsed(), 1)
    config["timesteps_done"] = int(model.num_timesteps)
    write_atomically(config_path, yaml.safe_dump(config, sort_keys=False))
    save_model_atomically(model, run_dir / "model.zip")
    logger.close()
    env.close()
    return run_dir


def model_file(path: Path) -> Path:
    """``path`` if it is a model file, else ``path/model.zip``; ``ValueError`` if neither is."""
    candidate = path / "model.zip" if path.is_dir() else path
    if not candidate.is_file():
        raise ValueError(
            f"init_from must be a run directory with model.zip or a model file, got {path}"
        )
    return candidate


def warm_start(model: Any, cls: type, path: Path) -> dict[str, str]:
    """Loads the policy weights of the model at ``path`` into ``model`` (same algorithm and
    network, else ``ValueError`` naming what differs); returns what config.yml records."""
    from agents.evaluate import model_digest

    try:
        source = cls.load(path, device="cpu")
    except Exception as err:
        raise ValueError(f"init_from {path} does not load as {cls.__name__}: {err}") from err
    if source.observation_space != model.observation_space:
        raise ValueError(
            f"init_from {path} was trained on observations {source.observation_space}, "
            f"this run has {model.observation_space}"
        )
    if source.action_space != model.action_space:
        raise ValueError(
            f"init_from {path} was trained with actions {source.action_space}, "
            f"this run has {model.action_space}"
        )
    try:
        model.policy.load_state_dict(source.policy.state_dict())
    except RuntimeError as err:
        raise ValueError(f"init_from {path} has another network than this recipe's: {err}") from err
    return {"path": str(path), "model_digest": model_digest(path).hex()}


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--algo", choices=ALGORITHMS, default="ppo")
    parser.add_argument("--map", choices=MAP_MODES, default="gpis", dest="map_mode")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--timesteps", type=int, help="override the recipe's n_timesteps")
    parser.add_argument("--n-envs", type=int, help="override the recipe's n_envs")
    parser.add_argument("--max-minutes", type=float, help="stop after this much wall-clock")
    parser.add_argument("--torch-threads", type=int, default=2)
    parser.add_argument(
        "--env-threads", type=int, help="the environment batch's threads (default: every core)"
    )
    parser.add_argument("--out", type=Path, default=Path("runs"))
    parser.add_argument("--hyperparams", type=Path, help="a recipe file instead of the default")
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    parser.add_argument(
        "--checkpoint-every",
        type=int,
        default=DEFAULT_CHECKPOINT_EVERY,
        help="env steps between checkpoints (taken at the next rollout boundary)",
    )
    parser.add_argument(
        "--keep-checkpoints",
        type=int,
        default=DEFAULT_KEEP_CHECKPOINTS,
        help="how many of the newest checkpoints to keep",
    )
    parser.add_argument(
        "--resume",
        action="store_true",
        help="continue the run in --out from its newest checkpoint to its total timesteps",
    )
    parser.add_argument(
        "--init-from",
        type=Path,
        help="warm start: a run directory (or model.zip) whose policy weights this run starts from",
    )
    args = parser.parse_args(argv)
    try:
        run_dir = train(
            args.algo,
            args.map_mode,
            out=args.out,
            seed=args.seed,
            timesteps=args.timesteps,
            n_envs=args.n_envs,
            torch_threads=args.torch_threads,
            env_threads=args.env_threads,
            progress_bar=not args.no_progress,
            hyperparams=args.hyperparams,
            max_minutes=args.max_minutes,
            checkpoint_every=args.checkpoint_every,
            keep_checkpoints=args.keep_checkpoints,
            resume=args.resume,
            init_from=args.init_from,
        )
    except KeyboardInterrupt:
        sys.exit(INTERRUPTED_EXIT_STATUS)
    print(f"trained {run_dir}")


if __name__ == "__main__":
    main()
