"""The clone stage of a recipe: the teacher cloned first, then PPO fine-tunes the clone.

A recipe with an ``imitation`` section (``agents/hyperparams/ppo.yml``,
``recurrent_ppo.yml``) trains in two stages. ``train_with_clone_stage`` (what
``agents.train`` and the grid's trials run) first imitates the section's teacher (the GPIS
probe planner unless it names another, ``agents.imitation.teachers``) into the recipe's
network (``agents.imitation.training``: behaviour cloning and DAgger) as a run of its own in
``<run_dir>/imitation/`` (``agents.run_dir.clone_dir``), then trains that clone with PPO
(``agents.sb3.training.train``, warm-started from it); the run's ``config.yml`` records the
section as the clone stage ran it and the clone's digest under ``init_from``. Started again,
a run reuses a finished clone of the same algorithm, settings, seed and network, and a clone
stage killed half-way starts again from the teacher's demonstrations it kept.
"""

from __future__ import annotations

import dataclasses
import hashlib
import zipfile
from pathlib import Path
from typing import Any

from agents.imitation.demonstrations import Demonstrations
from agents.imitation.stage_progress import stage_plan
from agents.imitation.teachers import PLANNER
from agents.imitation.training import (
    ImitationSettings,
    as_mapping,
    imitate_into,
    run_layouts,
)
from agents.run_dir import (
    TEACHER_DEMONSTRATIONS_FILE,
    clone_dir,
    holds_unfinished_run,
    model_path,
    recorded_config,
)
from agents.sb3.recipes import load_hyperparams
from agents.sb3.training import TrainSettings, train
from tactile_search import ENV_ID


def teacher_demonstrations_file(teacher: str) -> str:
    """The file name of ``teacher``'s kept demonstrations: ``TEACHER_DEMONSTRATIONS_FILE`` for
    the planner, with a digest of the spec for another teacher (an ensemble: a digest of its
    runs' paths, not of their models: retrain a member and delete the file)."""
    if teacher == PLANNER:
        return TEACHER_DEMONSTRATIONS_FILE
    digest = hashlib.sha256(teacher.encode()).hexdigest()[:12]
    return TEACHER_DEMONSTRATIONS_FILE.replace(".npz", f"_{digest}.npz")


# The recipe keys that fix what a clone is: its network, spaces and environment.
NETWORK_KEYS = ("policy", "policy_kwargs", "env_kwargs", "n_envs")


def with_overrides(section: Any, overrides: Any) -> dict[str, Any]:
    """A recipe's ``imitation`` section with ``overrides`` (keys of the same form; the
    ``cloning`` keys merged one by one)."""
    section = dict(as_mapping("the recipe's imitation section", section))
    overrides = as_mapping("the imitation overrides", overrides)
    for key, value in overrides.items():
        if key == "cloning":
            base = as_mapping("imitation.cloning", section.get("cloning", {}))
            value = {**base, **as_mapping("the imitation overrides' cloning", value)}
        section[key] = value
    return section


def clone_stage(
    run_dir: Path,
    recipe: dict[str, Any],
    *,
    seed: int,
    algo: str = "ppo",
    torch_threads: int = 1,
    env_id: str = ENV_ID,
    progress: bool = True,
    env_threads: int | None = None,
) -> Path:
    """The clone that a run of ``algo``'s ``recipe`` (with an ``imitation`` section) starts from:
    ``<run_dir>/imitation``, imitated with the section's settings unless it already holds a
    finished clone of the same settings, seed and network (a run started again after its
    clone finished). A stage killed half-way starts again from the teacher's
    demonstrations it kept. Returns the clone's run directory."""
    settings = ImitationSettings.from_recipe(recipe["imitation"], seed)
    directory = clone_dir(run_dir)
    if _is_finished_clone(directory, algo, recipe, settings, seed):
        print(f"reusing the clone in {directory}", flush=True)
        return directory
    model_path(directory).unlink(missing_ok=True)  # another recipe's clone
    teacher_file = directory / teacher_demonstrations_file(settings.teacher)
    teacher_layouts = run_layouts(seed, settings)[: settings.demo_episodes]
    if teacher_file.is_file() and not _holds_layouts(teacher_file, teacher_layouts):
        teacher_file.unlink()
    directory.mkdir(parents=True, exist_ok=True)
    print(f"imitating the teacher into {directory}", flush=True)
    return imitate_into(
        directory,
        recipe,
        algo=algo,
        seed=seed,
        settings=settings,
        torch_threads=torch_threads,
        env_id=env_id,
        progress=progress,
        demonstrations_file=teacher_file,
        env_threads=env_threads,
    )


def _is_finished_clone(
    clone_dir: Path, algo: str, recipe: dict[str, Any], settings: ImitationSettings, seed: int
) -> bool:
    """Whether ``clone_dir`` holds a finished clone of ``settings``, ``seed`` and the
    network and env of ``algo``'s ``recipe``."""
    if not model_path(clone_dir).is_file():
        return False
    config = recorded_config(clone_dir)
    if not isinstance(config, dict) or (config.get("algo"), config.get("seed")) != (algo, seed):
        return False
    recorded = config.get("imitation") or {}
    if {key: recorded.get(key) for key in settings.record()} != settings.record():
        return False
    network = config.get("hyperparams") or {}
    return all(network.get(key) == recipe.get(key) for key in NETWORK_KEYS)


def _holds_layouts(path: Path, layouts: list[int]) -> bool:
    """Whether the demonstrations file at ``path`` holds exactly the episodes of ``layouts``
    (not if it does not read as demonstrations: a file cut short by a kill while written)."""
    try:
        kept = Demonstrations.load(path)
    except (OSError, ValueError, zipfile.BadZipFile, EOFError):
        return False
    return set(kept.layout_seeds.tolist()) == set(layouts)


def train_with_clone_stage(
    settings: TrainSettings, imitation_overrides: dict[str, Any] | None = None
) -> Path:
    """``agents.sb3.training.train`` of ``settings``, with the recipe's clone stage first when
    it has one; the run directory. ``imitation_overrides`` overrides keys of the recipe's
    section (``{"demo_episodes": 200}``). A resumed run, a warm start (``init_from``) and
    ``from_scratch`` clone nothing; the clone stage passes ``train`` the clone as
    ``init_from`` and the section as it ran as ``imitation``."""
    if not isinstance(settings, TrainSettings):
        raise TypeError(
            f"train_with_clone_stage takes a TrainSettings, got {type(settings).__name__}"
        )
    recipe = load_hyperparams(
        settings.algo, settings.map_mode, settings.env_id, settings.hyperparams
    )
    if "imitation" not in recipe:
        if imitation_overrides:
            raise ValueError(
                f"imitation settings were given, but the {settings.algo} recipe for the "
                f"{settings.map_mode} map has no imitation section"
            )
        return train(settings)
    run_dir = settings.run_dir
    if (
        settings.resume
        or settings.init_from is not None
        or settings.from_scratch
        or holds_unfinished_run(run_dir)
    ):
        # Nothing to clone: the run resumes, starts from another model or from fresh
        # weights (or ``train`` refuses to start afresh over an unfinished run).
        return train(settings)
    # clone_stage reads (and refuses bad) settings before any work.
    section = with_overrides(recipe["imitation"], imitation_overrides or {})
    if settings.n_envs is not None:
        recipe["n_envs"] = int(settings.n_envs)
    if settings.progress_bar:
        timesteps = settings.timesteps or recipe["n_timesteps"]
        plan = stage_plan(ImitationSettings.from_recipe(section, settings.seed), timesteps)
        print(f"{settings.algo} {settings.map_mode} seed {settings.seed}: {plan}", flush=True)
    clone = clone_stage(
        run_dir,
        {**recipe, "imitation": section},
        algo=settings.algo,
        seed=settings.seed,
        torch_threads=settings.torch_threads,
        env_threads=settings.env_threads,
        env_id=settings.env_id,
        progress=settings.progress_bar,
    )
    return train(dataclasses.replace(settings, init_from=clone, imitation=section))
