"""Training one stable-baselines3 agent on ``tactile_search/CupboardSearch-v0``: ``train``,
under the thin CLI ``python -m agents.train`` (the rl-baselines3-zoo layout).

Hyperparameters come from ``agents/hyperparams/<algo>.yml``, keyed by env id and map mode.
Each run writes into ``<out>/<algo>_<map>_seed<seed>/``: ``model.zip``, ``config.yml`` (the
resolved recipe, the command's arguments, package versions and the wall-clock time),
``progress.csv``, TensorBoard events and ``checkpoints/`` (the last few, at rollout
boundaries). Training runs on ``CupboardSearchSb3VecEnv`` (the Rust batch, both cores) and
draws layout seeds from ``TRAIN_LAYOUT_SEEDS``, a range disjoint from the held-out
evaluation seeds (``tactile_search.seed_ranges``). What the run folder holds is
``agents.run_dir``'s contract.

A killed run continues from its newest checkpoint with ``--resume`` (see ``train``); Ctrl-C
saves a checkpoint, prints the command that resumes it and exits with status 130.
"""

from __future__ import annotations

import datetime
import shlex
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np
import yaml

from agents.run_dir import (
    CHECKPOINT_DIR,
    CHECKPOINT_PREFIX,
    CONFIG_FILE,
    MODEL_FILE,
    PROGRESS_FILE,
    checkpoints,
    code_version,
    holds_unfinished_run,
    is_finished,
    kept_progress,
    machine,
    model_file,
    read_run_config,
    run_name,
    save_model_atomically,
    versions,
    write_run_config,
)
from agents.sb3.bfloat16 import update_precision
from agents.sb3.callbacks import make_logger, rollout_checkpoints, wall_clock_limit
from agents.sb3.recipes import (
    ALGORITHMS,
    load_hyperparams,
    load_objects,
    new_model,
    run_recipe,
    training_class,
)
from agents.sb3.training_env import TRAIN_LAYOUT_SEEDS, make_training_env
from tactile_search import ENV_ID
from tactile_search._validation import as_bool, as_count
from tactile_search.envs.config import MAP_MODES

# A checkpoint at the first rollout boundary after every this many env steps (with the
# recipes' 16 x 128-step rollouts, every 25th rollout: about a minute of training here), and
# how many of the newest are kept. A checkpoint of the GPIS-map PPO model is ~3 MB.
DEFAULT_CHECKPOINT_EVERY = 50_000


DEFAULT_KEEP_CHECKPOINTS = 3


# The exit status after Ctrl-C (128 + SIGINT, the shell's convention).
INTERRUPTED_EXIT_STATUS = 130


def resumed_env_seed(seed: int, timesteps_done: int) -> int:
    """The seed of a resumed run's layout generator, torch and numpy: a function of the run's
    seed and the timesteps already done, so a resumed run neither replays the layouts of its
    start nor depends on anything but where it resumed."""
    sequence = np.random.SeedSequence([seed, timesteps_done])
    # 32 bits: SB3's set_random_seed also seeds numpy's legacy generator.
    return int(sequence.generate_state(1, dtype=np.uint32)[0])


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
    label: str | None = None,
    imitation: dict[str, Any] | None = None,
    from_scratch: bool = False,
) -> Path:
    """Trains one agent and returns its run directory (``model.zip``, ``config.yml``, logs).

    A PPO recipe with an ``imitation`` section (``agents/hyperparams/ppo.yml``) fine-tunes a
    clone of the GPIS probe planner: ``agents.imitation.clone_stage.train_with_clone_stage``
    (what ``agents.train`` runs) makes the clone and passes it here as ``init_from``, with
    ``imitation``, the section as its clone stage ran it, which ``config.yml`` records. Such
    a recipe needs ``init_from`` (a clone, or any model to warm-start from: the section is
    then dropped from the recorded recipe) or ``from_scratch`` (PPO from fresh weights, an
    ablation or a speed benchmark of PPO alone); ``ValueError`` otherwise.

    ``init_from`` (a run directory or its ``model.zip``, e.g. a published model under
    ``docs/results/models/``) warm-starts the policy: its weights, for the same algorithm and
    network, are loaded before training (the optimizer starts afresh); ``config.yml`` records
    the path and the model's digest under ``init_from``.

    ``label`` (recorded in ``config.yml``) names the agent in tables instead of ``algo``
    (a variant, such as a fine-tuned clone).

    ``config.yml`` records ``code`` (the git commit and whether the tree was dirty), by
    default ``code_version()`` of this checkout.

    ``timesteps`` and ``n_envs`` override the recipe's ``n_timesteps`` and ``n_envs``;
    ``max_minutes`` (or the recipe's ``max_minutes``) stops training earlier on wall-clock
    time, and ``config.yml`` records the timesteps done.
    ``torch_threads`` sets torch's intra-op threads. On this 2-core machine, training alone,
    2 threads ran PPO with the GPIS map 1.38x faster than 1 (median 1148 vs 832 steps/s,
    ``python -m benchmarks.train_threads --timesteps 8192 --repeats 2``); use 1 when two
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
    _check_arguments(
        algo,
        map_mode,
        seed,
        timesteps,
        torch_threads,
        env_threads,
        max_minutes,
        checkpoint_every,
        keep_checkpoints,
        resume,
        init_from,
    )
    as_bool("from_scratch", from_scratch)
    if init_from is not None:
        init_from = model_file(Path(init_from))
    run_dir = Path(out) / run_name(algo, map_mode, seed)
    if resume:
        asked = {"n_timesteps": timesteps, "n_envs": n_envs, "max_minutes": max_minutes}
        config = _resumed_config(run_dir, algo, env_id, map_mode, seed, hyperparams, asked)
        if config is None:
            return run_dir
    else:
        recipe = run_recipe(
            algo,
            map_mode,
            env_id,
            hyperparams,
            timesteps=timesteps,
            n_envs=n_envs,
            max_minutes=max_minutes,
        )
        _imitation_section(recipe, map_mode, imitation, init_from is not None, from_scratch)
        _clear_for_fresh_start(run_dir)
        config = {
            "algo": algo,
            **({"label": label} if label else {}),
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

    run_dir.mkdir(parents=True, exist_ok=True)
    torch.set_num_threads(torch_threads)
    cls = training_class(algo, config["hyperparams"])
    # The update's precision: bfloat16 only with the recipe's bfloat16_updates on a CPU with
    # AMX (agents.sb3.bfloat16), else float32; a resume on another CPU records its own.
    precision = update_precision(cls)
    if resume:
        model, env, logger, prior_seconds = _resumed_model(
            run_dir, cls, config, seed, env_id, env_threads, code
        )
        if precision != config.get("update_precision", "float32"):
            config["resumes"][-1]["update_precision"] = precision
    else:
        config["update_precision"] = precision
        model, env, logger = _new_model(run_dir, cls, config, seed, env_id, env_threads, init_from)
        prior_seconds = 0.0
    model.set_logger(logger)
    anchors = _anchors(config)
    config["checkpoint_every"] = checkpoint_every
    write_run_config(run_dir, config)
    command = resume_command(
        algo, map_mode, seed, out, checkpoint_every, keep_checkpoints, torch_threads, progress_bar
    )
    try:
        seconds = _learn(
            model,
            run_dir,
            config,
            checkpoint_every,
            keep_checkpoints,
            prior_seconds,
            progress_bar,
            resume,
            command,
            anchors,
        )
    except KeyboardInterrupt:
        logger.close()
        env.close()
        raise
    config["wall_clock_seconds"] = round(seconds, 1)
    config["timesteps_done"] = int(model.num_timesteps)
    write_run_config(run_dir, config)
    save_model_atomically(model, run_dir / MODEL_FILE)
    logger.close()
    env.close()
    return run_dir


def _imitation_section(
    recipe: dict[str, Any],
    map_mode: str,
    ran: dict[str, Any] | None,
    warm_start: bool,
    from_scratch: bool,
) -> None:
    """The recipe's ``imitation`` section as this run records it, in place: the section its
    clone stage ``ran`` (``init_from`` is that clone), else dropped (another warm start, or
    PPO from scratch). ``ValueError`` for a section with neither (the clone stage is
    ``agents.imitation.clone_stage``'s), or a section given for a recipe without one."""
    if "imitation" not in recipe:
        if ran is not None:
            raise ValueError(
                f"imitation settings were given, but the recipe for the {map_mode} "
                "map has no imitation section"
            )
        return
    if from_scratch or (warm_start and ran is None):
        del recipe["imitation"]
    elif warm_start:
        recipe["imitation"] = ran
    else:
        raise ValueError(
            f"the recipe for the {map_mode} map fine-tunes a clone of the planner (its "
            "imitation section): train it with agents.imitation.clone_stage."
            "train_with_clone_stage (as agents.train does), or give init_from or from_scratch"
        )


def _check_arguments(
    algo: str,
    map_mode: str,
    seed: int,
    timesteps: int | None,
    torch_threads: int,
    env_threads: int | None,
    max_minutes: float | None,
    checkpoint_every: int,
    keep_checkpoints: int,
    resume: bool,
    init_from: Path | None,
) -> None:
    """``train``'s arguments, checked before anything is read or written."""
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
        as_count("env_threads", env_threads)
    if max_minutes is not None and not max_minutes > 0:
        raise ValueError(f"max_minutes must be > 0, got {max_minutes}")
    as_count("checkpoint_every", checkpoint_every)
    as_count("keep_checkpoints", keep_checkpoints)
    as_bool("resume", resume)
    if init_from is not None and resume:
        raise ValueError("init_from starts a new run; a resumed run keeps its own weights")


def _resumed_config(
    run_dir: Path,
    algo: str,
    env_id: str,
    map_mode: str,
    seed: int,
    hyperparams: Path | None,
    asked: dict[str, Any],
) -> dict[str, Any] | None:
    """The ``config.yml`` of the run to resume, checked against what was asked (the same
    agent and seed; a recipe, if given, the one it recorded); None if the run has finished.
    ``ValueError`` if it disagrees or has no checkpoint to resume from."""
    config_path = run_dir / CONFIG_FILE
    config = read_run_config(
        run_dir, required=("algo", "env_id", "map", "seed", "hyperparams", "versions")
    )
    for key, value in (("algo", algo), ("env_id", env_id), ("map", map_mode), ("seed", seed)):
        if config[key] != value:
            raise ValueError(f"{config_path}: {key} is {config[key]!r}, not {value!r}")
    recipe = config["hyperparams"]
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
        return None
    if not checkpoints(run_dir):
        raise ValueError(
            f"{run_dir} has no checkpoint to resume from ({run_dir / CHECKPOINT_DIR} holds "
            f"no {CHECKPOINT_PREFIX}_<timesteps>_steps.zip); start it afresh without "
            "--resume"
        )
    return config


def _clear_for_fresh_start(run_dir: Path) -> None:
    """Makes way for a fresh run in ``run_dir``: a finished run's checkpoints and model go
    (its model first, so that a kill before the new one is saved leaves no model beside a
    config that does not describe it); an unfinished run's checkpoints raise ``ValueError``
    (resume it, or delete them)."""
    earlier = checkpoints(run_dir)
    if holds_unfinished_run(run_dir):
        raise ValueError(
            f"{run_dir} holds an unfinished run with a checkpoint at "
            f"{earlier[-1][0]:,} timesteps: resume it (--resume, train(..., "
            f"resume=True)) or delete {run_dir / CHECKPOINT_DIR} to start afresh"
        )
    for _, path in earlier:
        path.unlink()
    (run_dir / MODEL_FILE).unlink(missing_ok=True)


def _new_model(
    run_dir: Path,
    cls: type,
    config: dict[str, Any],
    seed: int,
    env_id: str,
    env_threads: int | None,
    init_from: Path | None,
) -> tuple[Any, Any, Any]:
    """A fresh run's model (warm-started from ``init_from``, recorded in ``config``), its
    training env and its logger; every random stream seeded with ``seed``."""
    from stable_baselines3.common.utils import set_random_seed

    recipe = config["hyperparams"]
    set_random_seed(seed)
    env = make_training_env(recipe["env_kwargs"], recipe["n_envs"], seed, env_id, env_threads)
    model = new_model(cls, recipe, env, seed)
    if init_from is not None:
        config["init_from"] = warm_start(model, cls, init_from)
    return model, env, make_logger(run_dir)


def _resumed_model(
    run_dir: Path,
    cls: type,
    config: dict[str, Any],
    seed: int,
    env_id: str,
    env_threads: int | None,
    code: dict[str, Any] | None,
) -> tuple[Any, Any, Any, float]:
    """A resumed run's model (its newest checkpoint that loads), its training env and
    logger (``progress.csv`` kept up to the checkpoint), and the wall-clock seconds already
    spent; ``config`` gets the resume recorded. The random streams are seeded with
    ``resumed_env_seed``."""
    recipe = config["hyperparams"]
    done = checkpoints(run_dir)[-1][0]
    env = make_training_env(
        recipe["env_kwargs"], recipe["n_envs"], resumed_env_seed(seed, done), env_id, env_threads
    )
    model = None
    for _, path in reversed(checkpoints(run_dir)):
        try:
            model = cls.load(path, env=env, device="cpu", custom_objects=load_objects(recipe))
            break
        except Exception as err:  # a damaged checkpoint: fall back to the one before
            print(f"cannot load {path} ({type(err).__name__}: {err}); trying an older one")
    if model is None:
        env.close()
        raise ValueError(f"none of the checkpoints in {run_dir / CHECKPOINT_DIR} loads")
    done = int(model.num_timesteps)
    env_seed = resumed_env_seed(seed, done)
    model.set_random_seed(env_seed)  # torch, numpy, the action space, the layouts
    prior_seconds = 0.0
    record = config.get("checkpoint")
    if isinstance(record, dict) and record.get("timesteps") == done:
        prior_seconds = float(record.get("wall_clock_seconds", 0.0))
    logger = make_logger(run_dir, kept_progress(run_dir / PROGRESS_FILE, done))
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
    return model, env, logger, prior_seconds


def _learn(
    model: Any,
    run_dir: Path,
    config: dict[str, Any],
    checkpoint_every: int,
    keep_checkpoints: int,
    prior_seconds: float,
    progress_bar: bool,
    resume: bool,
    resume_hint: str,
    extra_callbacks: list[Any] | None = None,
) -> float:
    """Trains ``model`` to the recipe's total timesteps (or its wall-clock limit) with
    checkpoints, each recorded in ``config.yml``; returns the run's wall-clock seconds.
    Ctrl-C saves a checkpoint of the rollout under way, prints ``resume_hint`` (the command
    that resumes) and re-raises ``KeyboardInterrupt``."""
    from stable_baselines3.common.callbacks import CallbackList

    recipe = config["hyperparams"]
    started = time.perf_counter()

    def elapsed() -> float:
        return prior_seconds + time.perf_counter() - started

    def on_save(timesteps_done: int, path: Path) -> None:
        config["checkpoint"] = {
            "timesteps": timesteps_done,
            "file": path.name,
            "wall_clock_seconds": round(elapsed(), 1),
        }
        write_run_config(run_dir, config)

    checkpointer = rollout_checkpoints(run_dir, checkpoint_every, keep_checkpoints, on_save)
    callbacks = [checkpointer, *(extra_callbacks or [])]
    limit = recipe.get("max_minutes")
    minutes_left = None if limit is None else limit - prior_seconds / 60
    if minutes_left is not None:
        callbacks.append(wall_clock_limit(minutes_left))
    remaining = recipe["n_timesteps"] - model.num_timesteps
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
        print(
            f"\ninterrupted: saved {path} ({model.num_timesteps:,} of "
            f"{recipe['n_timesteps']:,} timesteps); resume with\n  {resume_hint}",
            file=sys.stderr,
            flush=True,
        )
        raise
    return elapsed()


def _anchors(config: dict[str, Any]) -> list[Any]:
    """The recipe's anchor to the demonstrations its policy was cloned from
    (``anchor_weight`` > 0 and ``anchor_decay_timesteps``; ``agents.imitation.anchor``), for
    a run warm-started from an imitation run; none without ``anchor_weight``."""
    recipe = config["hyperparams"]
    weight = recipe.get("anchor_weight")
    if not weight:
        return []
    source = config.get("init_from")
    if not isinstance(source, dict) or "path" not in source:
        raise ValueError(
            "the recipe's anchor_weight anchors fine-tuning to the demonstrations of the "
            "model it starts from: give init_from (a run of agents.imitate)"
        )
    from agents.sb3.anchor import anchor_demonstrations, behaviour_cloning_anchor

    decay = recipe.get("anchor_decay_timesteps", recipe["n_timesteps"])
    demonstrations = anchor_demonstrations(Path(source["path"]))
    return [
        behaviour_cloning_anchor(demonstrations, float(weight), int(decay), seed=config["seed"])
    ]


def _source_objects(path: Path) -> dict[str, Any]:
    """The classes to load the model file ``path`` with: those of the recipe in the
    ``config.yml`` beside it, if there is one (``load_objects``: a published model names its
    encoder by the module it was trained in, which may have moved), else its own."""
    config_path = path.parent / CONFIG_FILE
    if not config_path.is_file():
        return {}
    config = yaml.safe_load(config_path.read_text())
    recipe = config.get("hyperparams") if isinstance(config, dict) else None
    return load_objects(recipe) if isinstance(recipe, dict) else {}


def warm_start(model: Any, cls: type, path: Path) -> dict[str, str]:
    """Loads the policy weights of the model at ``path`` into ``model`` (same algorithm and
    network, else ``ValueError`` naming what differs); returns what config.yml records."""
    from agents.run_dir import model_digest

    try:
        source = cls.load(path, device="cpu", custom_objects=_source_objects(path))
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
