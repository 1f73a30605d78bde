"""One imitation run: the recipe's PPO network cloned from the GPIS probe planner, then DAgger.

``imitate`` builds the network the PPO recipe of the map mode trains (the same policy and
spaces, so the result warm-starts PPO fine-tuning with ``agents.train --init-from`` and
evaluates as any run does), records the teacher's demonstrations on training layouts, clones
them, and runs DAgger rounds: the student samples its own probes on fresh training layouts,
the teacher labels every state it visits, and the student is cloned again on everything
gathered so far. A tenth of the teacher's layouts is held out to measure how often the
student's mode is the teacher's probe.

The run directory is a training run's (``agents.run_dir``): ``model.zip`` and ``config.yml``,
whose ``imitation`` section records the settings and, per round, the states labelled, the
student's agreement with its teacher and its success on the layouts it played;
``timesteps_done`` counts the probes stepped (teacher's and student's). ``rounds/round<k>/``
holds the student before DAgger round k+1 as a run of its own (``round0``: behaviour
cloning alone), so each step evaluates on its own. ``demonstrations.npz`` keeps everything
the last clone learned from (``agents.sb3.anchor`` anchors fine-tuning to it).
"""

from __future__ import annotations

import dataclasses
import time
from pathlib import Path
from typing import Any

import numpy as np

from agents.imitation.batched import record_batched
from agents.imitation.cloning import CloningSettings, agreement, clone
from agents.imitation.demonstrations import Demonstrations, record
from agents.imitation.mirror import check_symmetric, mirrored
from agents.imitation.stage_progress import stage_bar
from agents.imitation.teachers import PLANNER, check_teacher
from agents.run_dir import (
    code_version,
    demonstrations_path,
    machine,
    model_path,
    round_dir,
    run_name,
    save_model_atomically,
    versions,
    write_run_config,
)
from agents.sb3.bfloat16 import learner_precision
from agents.sb3.recipes import algorithm_class, load_hyperparams, new_model
from agents.sb3.training_env import TRAIN_LAYOUT_SEEDS, make_training_env
from agents.scripted import CORE_PLANNERS
from agents.scripted.geometry import Geometry
from tactile_search import ENV_ID, CupboardSearchEnv
from tactile_search._validation import as_bool, as_count

#: The share of the teacher's layouts held out to measure agreement.
HELD_OUT = 0.1


@dataclasses.dataclass(frozen=True)
class ImitationSettings:
    """The teacher's episodes, the DAgger rounds, the student's episodes per round, the
    cloning (its ``epochs`` for the teacher's demonstrations), the passes over everything
    gathered after each DAgger round (continuing from the weights before it), and whether
    mirror images of the states are cloned too."""

    demo_episodes: int = 2000
    dagger_rounds: int = 3
    dagger_episodes: int = 1000
    cloning: CloningSettings = dataclasses.field(default_factory=CloningSettings)
    dagger_epochs: int = 15
    #: Clone each demonstrated state and its mirror image (``agents.imitation.mirror``).
    mirror: bool = False
    #: Who labels the states (``agents.imitation.teachers``): the GPIS probe planner, or
    #: ``ensemble:RUN,RUN,...`` (trained runs acting as one: distillation).
    teacher: str = PLANNER

    def __post_init__(self) -> None:
        as_count("demo_episodes", self.demo_episodes, minimum=2)
        as_count("dagger_rounds", self.dagger_rounds, minimum=0)
        as_count("dagger_episodes", self.dagger_episodes)
        as_count("dagger_epochs", self.dagger_epochs)
        as_bool("mirror", self.mirror)
        check_teacher(self.teacher)

    @classmethod
    def from_recipe(cls, section: Any, seed: int) -> ImitationSettings:
        """The settings a recipe's ``imitation`` section names (every key optional, the
        ``cloning`` keys nested; the minibatches' order seeded with the run's ``seed``, as
        ``agents.imitate`` does). Raises ``ValueError`` naming an unknown key, ``TypeError``
        for a section that is not a mapping."""
        section = as_mapping("the recipe's imitation section", section)
        fields = {field.name for field in dataclasses.fields(cls)}
        _known_keys("imitation", section, fields)
        cloning = as_mapping("imitation.cloning", section.get("cloning", {}))
        cloning_fields = {field.name for field in dataclasses.fields(CloningSettings)} - {"seed"}
        _known_keys("imitation.cloning", cloning, cloning_fields)
        return cls(**{**section, "cloning": CloningSettings(**{"seed": seed, **cloning})})

    def record(self) -> dict[str, Any]:
        """What ``config.yml`` keeps of the settings (the recipe section's form)."""
        return dataclasses.asdict(self)


def as_mapping(what: str, value: Any) -> dict[str, Any]:
    if not isinstance(value, dict):
        raise TypeError(f"{what} must be a mapping of settings, got {type(value).__name__}")
    return value


def _known_keys(what: str, section: dict[str, Any], known: set[str]) -> None:
    unknown = sorted(set(section) - known)
    if unknown:
        raise ValueError(f"{what} has no setting {unknown}; it has {sorted(known)}")


def imitate(
    map_mode: str,
    *,
    out: Path = Path("runs"),
    seed: int = 0,
    settings: ImitationSettings | None = None,
    hyperparams: Path | None = None,
    torch_threads: int = 1,
    env_id: str = ENV_ID,
    progress: bool = True,
    demonstrations_file: Path | None = None,
    label: str = "imitation",
    algo: str = "ppo",
) -> Path:
    """Clones the planner into the network of ``algo``'s recipe for ``map_mode`` (``ppo``, or
    ``recurrent_ppo``: a memory, cloned on whole episodes); the run directory
    (``<out>/<algo>_<map>_seed<seed>``).

    ``demonstrations_file`` (an ``.npz``) keeps the teacher's demonstrations: read if it
    exists (it must hold this run's layouts), else recorded and written there, so that
    variants of a run clone the same demonstrations. ``label`` names the agent in tables
    (``config.yml``'s ``label``; evaluations call it ``imitation (gpis map)``)."""
    recipe = load_hyperparams(algo, map_mode, env_id, hyperparams)
    return imitate_into(
        Path(out) / run_name(algo, map_mode, seed),
        recipe,
        algo=algo,
        seed=seed,
        settings=settings or ImitationSettings(),
        torch_threads=torch_threads,
        env_id=env_id,
        progress=progress,
        demonstrations_file=demonstrations_file,
        label=label,
    )


def imitate_into(
    run_dir: Path,
    recipe: dict[str, Any],
    *,
    seed: int,
    settings: ImitationSettings,
    torch_threads: int = 1,
    env_id: str = ENV_ID,
    progress: bool = True,
    demonstrations_file: Path | None = None,
    label: str = "imitation",
    algo: str = "ppo",
    env_threads: int | None = None,
) -> Path:
    """``imitate`` with ``algo``'s ``recipe`` given (its network, spaces and env) and the run
    written to ``run_dir``; returns ``run_dir``. The planner's demonstrations and the DAgger
    rounds run ``recipe["n_envs"]`` episodes at a time on ``env_threads`` cores (default
    every core; ``agents.imitation.batched``); an ensemble teacher labels one episode at a
    time."""
    import torch
    from stable_baselines3.common.utils import set_random_seed

    started = time.monotonic()
    map_mode = recipe["env_kwargs"]["map"]
    env_kwargs = dict(recipe["env_kwargs"])
    if env_kwargs.get("action_mode") != "probe":
        raise ValueError(
            f"imitation needs a probe-mode recipe (the teacher chooses probes); the {map_mode} "
            f"recipe has action_mode {env_kwargs.get('action_mode')!r}"
        )
    torch.set_num_threads(torch_threads)
    set_random_seed(seed)
    spaces_env = make_training_env(env_kwargs, recipe["n_envs"], seed, env_id, threads=1)
    try:
        model = new_model(algorithm_class(algo), recipe, spaces_env, seed)
    finally:
        spaces_env.close()
    policy = model.policy
    gamma = float(model.gamma)
    layouts = run_layouts(seed, settings)

    def say(text: str) -> None:
        if progress:
            print(f"[{time.monotonic() - started:7.1f} s] {text}", flush=True)

    def recording(round_layouts: list[int], student: Any, stage: str) -> Demonstrations:
        """The teacher's labels on ``round_layouts``, the teacher or ``model`` acting."""
        with stage_bar(stage, len(round_layouts), "episode", progress) as update:
            if settings.teacher in CORE_PLANNERS:
                return record_batched(
                    round_layouts,
                    env_kwargs,
                    gamma,
                    student=None if student is None else _sampling_batch_student(student),
                    num_envs=recipe["n_envs"],
                    threads=env_threads,
                    progress=update,
                    teacher=settings.teacher,
                )
            acting = None if student is None else _sampling_student(student)
            return record(
                round_layouts, env_kwargs, gamma, student=acting, teacher=settings.teacher
            )

    precision = learner_precision(recipe)

    def cloning(data: Demonstrations, cloning_settings: CloningSettings, stage: str) -> list:
        with stage_bar(stage, cloning_settings.epochs, "epoch", progress) as update:
            return clone(policy, data, cloning_settings, progress=update, precision=precision)

    teacher_layouts = layouts[: settings.demo_episodes]
    if demonstrations_file is not None and Path(demonstrations_file).is_file():
        demonstrations = Demonstrations.load(demonstrations_file)
        if set(demonstrations.layout_seeds.tolist()) != set(teacher_layouts):
            raise ValueError(
                f"{demonstrations_file} holds demonstrations of other layouts than this run's "
                f"{len(teacher_layouts)} (seed {seed}); give another file"
            )
    else:
        demonstrations = recording(teacher_layouts, None, "teacher's demonstrations")
        if demonstrations_file is not None:
            demonstrations.save(demonstrations_file)
    train, held_out = demonstrations.split_by_layout(HELD_OUT, seed)
    say(f"teacher: {len(demonstrations)} probes on {len(teacher_layouts)} layouts")
    run_dir = Path(run_dir)
    config: dict[str, Any] = {
        "algo": algo,
        "label": label,
        "env_id": env_id,
        "map": map_mode,
        "seed": seed,
        "torch_threads": torch_threads,
        "env_threads": env_threads,
        "train_layout_seeds": list(TRAIN_LAYOUT_SEEDS),
        "hyperparams": recipe,
        "versions": versions(),
        "code": code_version(),
        "machine": machine(),
        "update_precision": precision,
        "imitation": {
            **settings.record(),
            "held_out_layouts": held_out.episodes,
            "rounds": [],
        },
    }

    def save(directory: Path, probes: int, name: str) -> None:
        done = {
            "label": name,
            "timesteps_done": probes,
            "wall_clock_seconds": round(time.monotonic() - started, 1),
        }
        directory.mkdir(parents=True, exist_ok=True)
        write_run_config(directory, {**config, **done})
        save_model_atomically(model, model_path(directory))

    augmented = _augmentation(settings.mirror, env_kwargs)
    train = augmented(train)
    history = cloning(train, settings.cloning, "behaviour cloning")
    rounds = config["imitation"]["rounds"]
    rounds.append(_round_record(0, demonstrations, history, policy, held_out))
    say(f"cloned: {rounds[-1]}")
    gathered = train
    probes = len(demonstrations)
    for index in range(1, settings.dagger_rounds + 1):
        # The student before this round, as its own run (BC alone is round 0).
        save(round_dir(run_dir, index - 1), probes, f"{label}_round{index - 1}")
        start = settings.demo_episodes + (index - 1) * settings.dagger_episodes
        round_layouts = layouts[start : start + settings.dagger_episodes]
        torch.manual_seed(seed * 1000 + index)
        rounds_in_all = settings.dagger_rounds
        labelled = recording(round_layouts, model, f"DAgger {index}/{rounds_in_all} rollouts")
        probes += len(labelled)
        gathered = Demonstrations.concatenate([gathered, augmented(labelled)])
        again = dataclasses.replace(
            settings.cloning, epochs=settings.dagger_epochs, seed=settings.cloning.seed + index
        )
        history = cloning(gathered, again, f"DAgger {index}/{rounds_in_all} cloning")
        rounds.append(_round_record(index, labelled, history, policy, held_out))
        say(f"DAgger round {index}: {rounds[-1]}")
    save(run_dir, probes, label)
    # What the last clone learned from, for anchoring PPO fine-tuning to it.
    gathered.save(demonstrations_path(run_dir))
    return run_dir


def _augmentation(mirror: bool, env_kwargs: dict[str, Any]) -> Any:
    """Demonstrations -> what is cloned: with ``mirror``, each state and its mirror image
    (the scene's symmetry is checked here, once), else the states as they are."""
    if not mirror:
        return lambda demonstrations: demonstrations
    env = CupboardSearchEnv(**env_kwargs)
    geometry = Geometry.from_env(env)
    env.close()
    check_symmetric(geometry)

    def with_mirror_images(demonstrations: Demonstrations) -> Demonstrations:
        return Demonstrations.concatenate([demonstrations, mirrored(demonstrations, geometry)])

    return with_mirror_images


def run_layouts(seed: int, settings: ImitationSettings) -> list[int]:
    """The layouts of a run: the teacher's, then each DAgger round's, in order."""
    return _training_layouts(
        seed, settings.demo_episodes + settings.dagger_rounds * settings.dagger_episodes
    )


def _training_layouts(seed: int, count: int) -> list[int]:
    """``count`` distinct layout seeds from the training range, drawn with ``seed``."""
    low, high = TRAIN_LAYOUT_SEEDS
    rng = np.random.default_rng([seed, 24])
    chosen: dict[int, None] = {}
    while len(chosen) < count:
        for value in rng.integers(low, high, size=count - len(chosen), dtype=np.uint64):
            chosen[int(value)] = None
    return list(chosen)


def _sampling_student(model: Any) -> Any:
    """Per episode, the model's policy sampling its probes (as PPO explores)."""

    def start(_layout_seed: int) -> Any:
        memory = None  # a recurrent policy's, from the episode's start
        first = True

        def act(observation: dict) -> np.ndarray:
            nonlocal memory, first
            action, memory = model.predict(
                observation, state=memory, episode_start=np.array([first]), deterministic=False
            )
            first = False
            return np.asarray(action)

        return act

    return start


def _sampling_batch_student(model: Any) -> Any:
    """The model's policy sampling the probes of a batch of episodes at once (as PPO
    explores), a recurrent policy's memory per episode (reset where one starts)."""
    memory = None

    def act(observations: dict, starts: np.ndarray) -> np.ndarray:
        nonlocal memory
        actions, memory = model.predict(
            observations, state=memory, episode_start=starts, deterministic=False
        )
        return np.asarray(actions)

    return act


def _round_record(
    index: int,
    labelled: Demonstrations,
    history: list[dict],
    policy: Any,
    held_out: Demonstrations,
) -> dict[str, Any]:
    """What ``config.yml`` keeps of a round: its states, the success of whoever acted (the
    teacher in round 0, the student after), the last epoch's losses and the held-out
    agreement afterwards."""
    last = history[-1]
    acted = labelled.outcomes()
    return {
        "round": index,
        "states": len(labelled),
        "layouts": labelled.episodes,
        "acting_success": round(acted["success"], 4),
        "acting_tips": acted["tips"],
        "nll": round(float(last["nll"]), 4),
        "value_loss": round(float(last["value_loss"]), 4),
        "held_out_agreement": {
            key: round(value, 4) for key, value in agreement(policy, held_out).items()
        },
    }
