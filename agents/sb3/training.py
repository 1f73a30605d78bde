"""Training one stable-baselines3 agent on ``tactile_search/CupboardSearch-v0``: ``train``,
under the thin CLI ``python -m agents.train`` (the rl-baselines3-zoo layout).

Hyperparameters come from ``agents/hyperparams/<algo>.yml``, keyed by env id and map mode.
Each run writes into ``<out>/<algo>_<map>_seed<seed>/``: ``model.zip``, ``config.yml`` (the
resolved recipe, the command's arguments, package versions and the wall-clock time),
``progress.csv``, TensorBoard events and ``checkpoints/`` (the last few, at rollout
boundaries). Training runs on ``CupboardSearchSb3VecEnv`` (the Rust batch, on every core
unless told otherwise) and draws layout seeds from ``TRAIN_LAYOUT_SEEDS``, a range disjoint
from the held-out evaluation seeds (``tactile_search.seed_ranges``). What the run folder
holds is ``agents.run_dir``'s contract.

A killed run continues from its newest checkpoint with ``--resume`` (see ``train``); Ctrl-C
saves a checkpoint, prints the command that resumes it and exits with status
``INTERRUPTED_EXIT_STATUS``.
"""

from __future__ import annotations

import dataclasses
import datetime
import os
import shlex
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np

from agents.run_dir import (
    CHECKPOINT_PATTERN,
    checkpoint_dir,
    checkpoints,
    code_version,
    config_beside,
    config_path,
    holds_unfinished_run,
    is_finished,
    kept_progress,
    machine,
    model_digest,
    model_file,
    model_path,
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
    new_model,
    run_recipe,
    training_class,
)
from agents.sb3.training_env import TRAIN_LAYOUT_SEEDS, make_training_env
from tactile_search import ENV_ID
from tactile_search._validation import as_bool, as_count, as_real
from tactile_search.envs.config import MAP_MODES
from tactile_search.networks.recipe_classes import load_objects

# A checkpoint at the first rollout boundary after every this many env steps, and how many
# of the newest are kept: a kill loses little work, and the checkpoints (a few MB each for a
# map agent) do not pile up.
DEFAULT_CHECKPOINT_EVERY = 50_000


DEFAULT_KEEP_CHECKPOINTS = 3


# Torch's intra-op threads unless told otherwise (a grid trial passes the CPUs it declares).
DEFAULT_TORCH_THREADS = 2


# The exit status after Ctrl-C (128 + SIGINT, the shell's convention).
INTERRUPTED_EXIT_STATUS = 130


@dataclasses.dataclass(frozen=True)
class TrainSettings:
    """What one training run is: the agent, where its run directory goes, its seed, its
    budget, the threads it uses, its checkpoints and how it starts (afresh, resumed, warm).

    ``algo`` (``ppo`` or ``recurrent_ppo``) and ``map_mode`` pick the recipe of
    ``agents/hyperparams/<algo>.yml`` (or of ``hyperparams``, a recipe file keyed the same
    way) for ``env_id``; the run directory is ``<out>/<algo>_<map>_seed<seed>/``.

    ``timesteps``, ``n_envs`` and ``max_minutes`` override the recipe's ``n_timesteps``,
    ``n_envs`` and ``max_minutes`` (a wall-clock limit; ``config.yml`` records the timesteps
    done). ``torch_threads`` sets torch's intra-op threads: use 1 when two runs share the
    cores. ``env_threads`` sets the environment batch's worker threads (default: every core;
    the results do not depend on it); a run given one CPU (a Ray trial) uses one.

    Checkpoints go to ``<run_dir>/checkpoints/`` at the first rollout boundary after every
    ``checkpoint_every`` env steps; the newest ``keep_checkpoints`` are kept.

    ``resume`` continues the run in its directory from its newest checkpoint (see
    ``train``). ``init_from`` (a run directory or its ``model.zip``) warm-starts a new run
    from that model's weights. ``imitation`` is the recipe's imitation section as the clone
    stage that made ``init_from`` ran it (``agents.imitation.clone_stage``), which
    ``config.yml`` records; ``from_scratch`` trains such a recipe from fresh weights without
    its clone. ``label`` names the agent in tables instead of ``algo`` (a variant, such as a
    fine-tuned clone). ``code`` (the git commit and whether the tree was dirty) is what
    ``config.yml`` records of the code, by default ``code_version()`` of this checkout.

    Every field is checked on construction: ``TypeError`` for the wrong kind of value,
    ``ValueError`` for a wrong value, each naming the field, what it takes and what came.
    """

    algo: str
    map_mode: str
    _: dataclasses.KW_ONLY
    out: Path = Path("runs")
    seed: int = 0
    timesteps: int | None = None
    n_envs: int | None = None
    max_minutes: float | None = None
    hyperparams: Path | None = None
    env_id: str = ENV_ID
    torch_threads: int = DEFAULT_TORCH_THREADS
    env_threads: int | None = None
    progress_bar: bool = True
    checkpoint_every: int = DEFAULT_CHECKPOINT_EVERY
    keep_checkpoints: int = DEFAULT_KEEP_CHECKPOINTS
    resume: bool = False
    init_from: Path | None = None
    imitation: dict[str, Any] | None = dataclasses.field(default=None, hash=False)
    from_scratch: bool = False
    label: str | None = None
    code: dict[str, Any] | None = dataclasses.field(default=None, hash=False)

    def __post_init__(self) -> None:
        if self.algo not in ALGORITHMS:
            raise ValueError(f"algo must be one of {ALGORITHMS}, got {self.algo!r}")
        if self.map_mode not in MAP_MODES:
            raise ValueError(f"map must be one of {MAP_MODES}, got {self.map_mode!r}")
        for name in ("out", "hyperparams", "init_from"):
            value = getattr(self, name)
            if value is None and name != "out":
                continue
            if not isinstance(value, str | os.PathLike):
                raise TypeError(f"{name} must be a path, got {type(value).__name__}: {value!r}")
            object.__setattr__(self, name, Path(value))
        as_count("seed", self.seed, minimum=0)
        for name in ("timesteps", "n_envs", "env_threads"):
            if getattr(self, name) is not None:
                as_count(name, getattr(self, name))
        if self.max_minutes is not None and not as_real("max_minutes", self.max_minutes) > 0:
            raise ValueError(f"max_minutes must be > 0, got {self.max_minutes}")
        as_count("torch_threads", self.torch_threads)
        as_count("checkpoint_every", self.checkpoint_every)
        as_count("keep_checkpoints", self.keep_checkpoints)
        for name in ("progress_bar", "resume", "from_scratch"):
            as_bool(name, getattr(self, name))
        for name, kind in (("env_id", str), ("label", str), ("imitation", dict), ("code", dict)):
            value = getattr(self, name)
            if value is not None and not isinstance(value, kind):
                raise TypeError(
                    f"{name} must be a {kind.__name__}, got {type(value).__name__}: {value!r}"
                )
        if self.init_from is not None and self.resume:
            raise ValueError("init_from starts a new run; a resumed run keeps its own weights")

    @property
    def run_dir(self) -> Path:
        """The run directory: ``<out>/<algo>_<map>_seed<seed>``."""
        return self.out / run_name(self.algo, self.map_mode, self.seed)


def resumed_env_seed(seed: int, timesteps_done: int) -> int:
    """The seed of a resumed run's layout generator, torch and numpy: a function of the run's
    seed and the timesteps already done, so a resumed run neither replays the layouts of its
    start nor depends on anything but where it resumed."""
    sequence = np.random.SeedSequence([seed, timesteps_done])
    # 32 bits: SB3's set_random_seed also seeds numpy's legacy generator.
    return int(sequence.generate_state(1, dtype=np.uint32)[0])


def resume_command(settings: TrainSettings) -> str:
    """The shell command that resumes the run of ``settings`` (the recipe is the one its
    ``config.yml`` recorded; the settings a resume may change are given if not defaults)."""
    args = [sys.executable, "-m", "agents.train", "--algo", settings.algo]
    args += ["--map", settings.map_mode, "--seed", str(settings.seed)]
    args += ["--out", str(settings.out), "--resume"]
    if settings.checkpoint_every != DEFAULT_CHECKPOINT_EVERY:
        args += ["--checkpoint-every", str(settings.checkpoint_every)]
    if settings.keep_checkpoints != DEFAULT_KEEP_CHECKPOINTS:
        args += ["--keep-checkpoints", str(settings.keep_checkpoints)]
    if settings.torch_threads != DEFAULT_TORCH_THREADS:
        args += ["--torch-threads", str(settings.torch_threads)]
    if not settings.progress_bar:
        args.append("--no-progress")
    return shlex.join(args)


class _Session(NamedTuple):
    """A run's model, the training env it steps, its logger, and the wall-clock seconds
    spent before this process took it over (a resumed run's)."""

    model: Any
    env: Any
    logger: Any
    prior_seconds: float

    def close(self) -> None:
        self.logger.close()
        self.env.close()


def train(settings: TrainSettings) -> Path:
    """Trains the agent of ``settings`` and returns its run directory (``model.zip``,
    ``config.yml``, logs; ``agents.run_dir``'s contract).

    The steps: the recipe (a fresh run's, or the one a resumed run recorded), the model
    (new, warm-started from ``init_from``, or the newest checkpoint's) on its training env,
    the callbacks (checkpoints, the wall-clock limit, an anchor to the demonstrations of a
    clone), learning, and the model saved last.

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

    Ctrl-C saves a checkpoint of the state at the start of the rollout under way, prints
    where it is and the command that resumes it, and re-raises ``KeyboardInterrupt``.

    ``resume`` continues the run in the same directory from its newest checkpoint, with
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
    if not isinstance(settings, TrainSettings):
        raise TypeError(f"train takes a TrainSettings, got {type(settings).__name__}")
    init_from = None if settings.init_from is None else model_file(settings.init_from)
    if settings.resume:
        config = _resumed_config(settings)
        if config is None:  # finished already
            return settings.run_dir
    else:
        recipe = _fresh_recipe(settings, warm_start=init_from is not None)
        _clear_for_fresh_start(settings.run_dir)
        config = _fresh_config(settings, recipe)
    session = _open_session(settings, config, init_from)
    anchors = _anchors(config)
    config["checkpoint_every"] = settings.checkpoint_every
    write_run_config(settings.run_dir, config)
    try:
        seconds = _learn(settings, session, config, anchors)
    except KeyboardInterrupt:
        session.close()
        raise
    _finish(settings.run_dir, session, config, seconds)
    return settings.run_dir


def _fresh_recipe(settings: TrainSettings, warm_start: bool) -> dict[str, Any]:
    """The recipe a fresh run trains and records (``run_recipe`` with the settings'
    overrides), its imitation section as this run records it (``_imitation_section``)."""
    recipe = run_recipe(
        settings.algo,
        settings.map_mode,
        settings.env_id,
        settings.hyperparams,
        timesteps=settings.timesteps,
        n_envs=settings.n_envs,
        max_minutes=settings.max_minutes,
    )
    _imitation_section(recipe, settings, warm_start)
    return recipe


def _fresh_config(settings: TrainSettings, recipe: dict[str, Any]) -> dict[str, Any]:
    """A fresh run's ``config.yml`` before training: who, what, where it ran."""
    return {
        "algo": settings.algo,
        **({"label": settings.label} if settings.label else {}),
        "env_id": settings.env_id,
        "map": settings.map_mode,
        "seed": settings.seed,
        "torch_threads": settings.torch_threads,
        "train_layout_seeds": list(TRAIN_LAYOUT_SEEDS),
        "hyperparams": recipe,
        "versions": versions(),
        "code": settings.code or code_version(),
        "machine": machine(),
    }


def _imitation_section(recipe: dict[str, Any], settings: TrainSettings, warm_start: bool) -> None:
    """The recipe's ``imitation`` section as this run records it, in place: the section its
    clone stage ran (``settings.imitation``; ``init_from`` is that clone), else dropped
    (another warm start, or PPO from scratch). ``ValueError`` for a section with neither (the
    clone stage is ``agents.imitation.clone_stage``'s), or a section given for a recipe
    without one."""
    ran = settings.imitation
    if "imitation" not in recipe:
        if ran is not None:
            raise ValueError(
                f"imitation settings were given, but the recipe for the {settings.map_mode} "
                "map has no imitation section"
            )
        return
    if settings.from_scratch or (warm_start and ran is None):
        del recipe["imitation"]
    elif warm_start:
        recipe["imitation"] = ran
    else:
        raise ValueError(
            f"the recipe for the {settings.map_mode} map fine-tunes a clone of the planner (its "
            "imitation section): train it with agents.imitation.clone_stage."
            "train_with_clone_stage (as agents.train does), or give init_from or from_scratch"
        )


def _resumed_config(settings: TrainSettings) -> dict[str, Any] | None:
    """The ``config.yml`` of the run to resume, checked against ``settings`` (the same
    agent and seed; a recipe, if given, the one it recorded); None if the run has finished.
    ``ValueError`` if it disagrees or has no checkpoint to resume from."""
    run_dir = settings.run_dir
    config_file = config_path(run_dir)
    config = read_run_config(
        run_dir, required=("algo", "env_id", "map", "seed", "hyperparams", "versions")
    )
    identity = {
        "algo": settings.algo,
        "env_id": settings.env_id,
        "map": settings.map_mode,
        "seed": settings.seed,
    }
    for key, value in identity.items():
        if config[key] != value:
            raise ValueError(f"{config_file}: {key} is {config[key]!r}, not {value!r}")
    recipe = config["hyperparams"]
    asked = {
        "n_timesteps": settings.timesteps,
        "n_envs": settings.n_envs,
        "max_minutes": settings.max_minutes,
    }
    if settings.hyperparams is not None:
        loaded = load_hyperparams(
            settings.algo, settings.map_mode, settings.env_id, settings.hyperparams
        )
        asked = {**loaded, **asked}
    for key, value in asked.items():
        if value is not None and recipe.get(key) != value:
            raise ValueError(
                f"a resumed run keeps the recipe in {config_file}: its {key} is "
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
            f"{run_dir} has no checkpoint to resume from ({checkpoint_dir(run_dir)} holds "
            f"no {CHECKPOINT_PATTERN}); start it afresh without --resume"
        )
    return config


def _clear_for_fresh_start(run_dir: Path) -> None:
    """Makes way for a fresh run in ``run_dir``: a finished run's checkpoints and model go
    (its model first, so that a kill before the new one is saved leaves no model beside a
    config that does not describe it); an unfinished run's checkpoints raise ``ValueError``
    (resume it, or delete them)."""
    if holds_unfinished_run(run_dir):
        raise ValueError(
            f"{run_dir} holds an unfinished run with a checkpoint at "
            f"{checkpoints(run_dir)[-1][0]:,} timesteps: resume it (--resume, "
            f"TrainSettings(resume=True)) or delete {checkpoint_dir(run_dir)} to start afresh"
        )
    for _, path in checkpoints(run_dir):
        path.unlink()
    model_path(run_dir).unlink(missing_ok=True)


def _open_session(
    settings: TrainSettings, config: dict[str, Any], init_from: Path | None
) -> _Session:
    """The run's model on its training env, with its logger: new (warm-started from
    ``init_from``) or the newest checkpoint's; ``config`` records the update's precision
    (bfloat16 only with the recipe's ``bfloat16_updates`` on a CPU with AMX,
    ``agents.sb3.bfloat16``, else float32; a resume on another CPU records its own)."""
    import torch

    settings.run_dir.mkdir(parents=True, exist_ok=True)
    torch.set_num_threads(settings.torch_threads)
    cls = training_class(settings.algo, config["hyperparams"])
    precision = update_precision(cls)
    if settings.resume:
        session = _resumed_model(settings, cls, config)
        if precision != config.get("update_precision", "float32"):
            config["resumes"][-1]["update_precision"] = precision
    else:
        config["update_precision"] = precision
        session = _new_model(settings, cls, config, init_from)
    session.model.set_logger(session.logger)
    return session


def _new_model(
    settings: TrainSettings, cls: type, config: dict[str, Any], init_from: Path | None
) -> _Session:
    """A fresh run's model (warm-started from ``init_from``, recorded in ``config``), its
    training env and its logger; every random stream seeded with the run's seed."""
    from stable_baselines3.common.utils import set_random_seed

    recipe = config["hyperparams"]
    seed = settings.seed
    set_random_seed(seed)
    env = make_training_env(
        recipe["env_kwargs"], recipe["n_envs"], seed, settings.env_id, settings.env_threads
    )
    model = new_model(cls, recipe, env, seed)
    if init_from is not None:
        config["init_from"] = warm_start(model, cls, init_from)
    return _Session(model, env, make_logger(settings.run_dir), 0.0)


def _resumed_model(settings: TrainSettings, cls: type, config: dict[str, Any]) -> _Session:
    """A resumed run's model (its newest checkpoint that loads), its training env and
    logger (``progress.csv`` kept up to the checkpoint), and the wall-clock seconds already
    spent; ``config`` gets the resume recorded. The random streams are seeded with
    ``resumed_env_seed``."""
    run_dir, seed = settings.run_dir, settings.seed
    recipe = config["hyperparams"]
    done = checkpoints(run_dir)[-1][0]
    env = make_training_env(
        recipe["env_kwargs"],
        recipe["n_envs"],
        resumed_env_seed(seed, done),
        settings.env_id,
        settings.env_threads,
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
        raise ValueError(f"none of the checkpoints in {checkpoint_dir(run_dir)} loads")
    done = int(model.num_timesteps)
    env_seed = resumed_env_seed(seed, done)
    model.set_random_seed(env_seed)  # torch, numpy, the action space, the layouts
    prior_seconds = 0.0
    record = config.get("checkpoint")
    if isinstance(record, dict) and record.get("timesteps") == done:
        prior_seconds = float(record.get("wall_clock_seconds", 0.0))
    logger = make_logger(run_dir, kept_progress(run_dir, done))
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
    resumed_code = settings.code or code_version()
    if resumed_code != config.get("code"):  # the code the rest ran
        config["resumes"][-1]["code"] = resumed_code
    print(f"resuming {run_dir} from {path} ({done:,} timesteps)", flush=True)
    return _Session(model, env, logger, prior_seconds)


def _callbacks(
    settings: TrainSettings,
    config: dict[str, Any],
    elapsed: Callable[[], float],
    minutes_left: float | None,
    anchors: list[Any],
) -> tuple[Any, list[Any]]:
    """The checkpoints (each recorded in ``config.yml`` with the wall-clock ``elapsed()``
    at it), the ``anchors`` and a wall-clock limit of ``minutes_left``: the checkpointer and
    every callback, in the order SB3 calls them."""
    run_dir = settings.run_dir

    def on_save(timesteps_done: int, path: Path) -> None:
        config["checkpoint"] = {
            "timesteps": timesteps_done,
            "file": path.name,
            "wall_clock_seconds": round(elapsed(), 1),
        }
        write_run_config(run_dir, config)

    checkpointer = rollout_checkpoints(
        run_dir, settings.checkpoint_every, settings.keep_checkpoints, on_save
    )
    callbacks = [checkpointer, *anchors]
    if minutes_left is not None:
        callbacks.append(wall_clock_limit(minutes_left))
    return checkpointer, callbacks


def _learn(
    settings: TrainSettings, session: _Session, config: dict[str, Any], anchors: list[Any]
) -> float:
    """Trains the session's model to the recipe's total timesteps (or its wall-clock limit)
    with checkpoints; returns the run's wall-clock seconds. Ctrl-C saves a checkpoint of the
    rollout under way, prints the command that resumes and re-raises
    ``KeyboardInterrupt``."""
    from stable_baselines3.common.callbacks import CallbackList

    model = session.model
    recipe = config["hyperparams"]
    started = time.perf_counter()

    def elapsed() -> float:
        return session.prior_seconds + time.perf_counter() - started

    limit = recipe.get("max_minutes")
    minutes_left = None if limit is None else limit - session.prior_seconds / 60
    checkpointer, callbacks = _callbacks(settings, config, elapsed, minutes_left, anchors)
    remaining = recipe["n_timesteps"] - model.num_timesteps
    try:
        if remaining > 0 and (minutes_left is None or minutes_left > 0):
            model.learn(
                total_timesteps=remaining,
                callback=CallbackList(callbacks),
                progress_bar=settings.progress_bar,
                reset_num_timesteps=not settings.resume,
            )
    except KeyboardInterrupt:
        path = checkpointer.save_interrupted()
        print(
            f"\ninterrupted: saved {path} ({model.num_timesteps:,} of "
            f"{recipe['n_timesteps']:,} timesteps); resume with\n  {resume_command(settings)}",
            file=sys.stderr,
            flush=True,
        )
        raise
    return elapsed()


def _finish(run_dir: Path, session: _Session, config: dict[str, Any], seconds: float) -> None:
    """Records the run's wall-clock and timesteps done, then saves the model (last: a run is
    finished when both are there) and closes the session."""
    config["wall_clock_seconds"] = round(seconds, 1)
    config["timesteps_done"] = int(session.model.num_timesteps)
    write_run_config(run_dir, config)
    save_model_atomically(session.model, model_path(run_dir))
    session.close()


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
    config = config_beside(path)
    recipe = config.get("hyperparams") if isinstance(config, dict) else None
    return load_objects(recipe) if isinstance(recipe, dict) else {}


def warm_start(model: Any, cls: type, path: Path) -> dict[str, str]:
    """Loads the policy weights of the model at ``path`` into ``model`` (same algorithm and
    network, else ``ValueError`` naming what differs); returns what config.yml records."""
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
