"""Demonstrations recorded over a batch of episodes on every core: the vector env steps
``num_envs`` episodes at once in Rust, one of the core's planners labels all of them in one
parallel call (the GPIS probe planner, ``tactile_search._core.ProbePlanner``, by default;
any of ``agents.scripted.CORE_PLANNERS``: the identify planner labels with its claim entry),
and a student (DAgger) chooses all of their actions in one forward pass.

The layouts run in order, each sub-env taking the next layout as its episode ends; the
episodes are returned in the order of the layouts given, so the teacher's demonstrations
are exactly those of ``demonstrations.record`` (the planner and the scene are deterministic
per layout). A student samples its probes for the whole batch at once, so its draws (and
the episodes it plays) depend on ``num_envs``, not on the threads: a fixed seed and batch
give the same demonstrations whatever the cores.

A student with another map than the teacher's (the occupancy recipe) sees its own
observations: the episodes run in two vector envs of the same layouts stepped with the
same probes, the teacher reading one and the student the other (the scene does not depend
on the map mode; the hands' poses are checked to stay equal).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from agents.imitation.demonstrations import Demonstrations, episode_rows
from agents.imitation.teachers import PLANNER
from agents.scripted import CORE_PLANNERS
from tactile_search import CupboardSearchVectorEnv

#: A batch student: (observations of every sub-env, which of them start an episode) ->
#: one action per sub-env, ``(num_envs, entries)`` (the probe, and the claim where the task
#: claims).
BatchStudent = Callable[[dict[str, np.ndarray], np.ndarray], np.ndarray]


def teacher_face(teacher: str) -> Any:
    """The scripted face of the core planner named ``teacher`` (``CORE_PLANNERS``);
    ``ValueError`` naming the planners otherwise."""
    if teacher not in CORE_PLANNERS:
        raise ValueError(
            f"a batched teacher must be one of the core's planners {sorted(CORE_PLANNERS)}, "
            f"got {teacher!r}"
        )
    return CORE_PLANNERS[teacher][0]


def core_planner(face: Any, config: Any, num_envs: int) -> Any:
    """The core's planner of ``face`` for ``num_envs`` episodes of ``config`` (a function of
    this module's, so a profiler can wrap it)."""
    return face.core_class(config, num_envs)


@dataclasses.dataclass
class _Episode:
    """One running episode's rows."""

    order: int
    layout: int
    observations: list[dict[str, np.ndarray]] = dataclasses.field(default_factory=list)
    labels: list[np.ndarray] = dataclasses.field(default_factory=list)
    rewards: list[float] = dataclasses.field(default_factory=list)

    def finish(self, gamma: float, info: dict[str, Any], index: int) -> Demonstrations:
        """The episode's rows, sub-env ``index``'s entries of the last step's ``info``
        giving its outcome."""
        return episode_rows(
            self.observations,
            self.labels,
            self.rewards,
            gamma,
            self.layout,
            success=bool(info["success"][index]),
            tips=int(info["tips"][index]),
        )


def record_batched(
    layout_seeds: Sequence[int],
    env_kwargs: dict[str, Any],
    gamma: float,
    student: BatchStudent | None = None,
    num_envs: int = 16,
    threads: int | None = None,
    progress: Callable[[int], Any] | None = None,
    teacher: str = PLANNER,
) -> Demonstrations:
    """The labels of the core planner ``teacher`` (``CORE_PLANNERS``, default the GPIS probe
    planner) over one episode per layout seed in the env of ``env_kwargs`` (the student's
    settings, the probe action mode), ``num_envs`` episodes at a time on ``threads`` cores
    (default every core). Without ``student`` the planner acts; with one, the student's
    actions are carried out while the planner labels (and follows their probes).
    ``returns`` are discounted by ``gamma`` within the episode. ``progress(k)`` is called as
    ``k`` more episodes finish (a progress bar's ``update``)."""
    if env_kwargs.get("action_mode") != "probe":
        raise ValueError(
            f"demonstrations need action_mode='probe' (the teacher's probes), got "
            f"{env_kwargs.get('action_mode')!r}"
        )
    face = teacher_face(teacher)
    layouts = [int(seed) for seed in layout_seeds]
    n = max(1, min(num_envs, len(layouts)))
    teacher_kwargs = {**env_kwargs, **face.env_kwargs}
    twin = teacher_kwargs != env_kwargs
    student_env = CupboardSearchVectorEnv(
        num_envs=n, threads=threads, autoreset_mode="disabled", **env_kwargs
    )
    teacher_env = (
        CupboardSearchVectorEnv(
            num_envs=n, threads=threads, autoreset_mode="disabled", **teacher_kwargs
        )
        if twin
        else student_env
    )
    planner = core_planner(face, teacher_env.config.core, n)
    finished: list[Demonstrations | None] = [None] * len(layouts)
    try:
        _run(layouts, student_env, teacher_env, planner, gamma, student, finished, progress)
    finally:
        student_env.close()
        if twin:
            teacher_env.close()
    return Demonstrations.concatenate([part for part in finished if part is not None])


def _run(
    layouts: list[int],
    student_env: CupboardSearchVectorEnv,
    teacher_env: CupboardSearchVectorEnv,
    planner: Any,
    gamma: float,
    student: BatchStudent | None,
    finished: list[Demonstrations | None],
    progress: Callable[[int], Any] | None,
) -> None:
    n = student_env.num_envs
    entries = len(student_env.single_action_space.nvec)
    twin = teacher_env is not student_env
    # Sub-envs past the last layout replay one (their rows are dropped) until all finish.
    running: list[_Episode | None] = [None] * n
    queue = iter(enumerate(layouts))
    starts = np.ones(n, dtype=bool)

    def start(mask: np.ndarray) -> tuple[dict[str, np.ndarray], dict[str, np.ndarray]]:
        seeds: list[int | None] = [None] * n
        for i in np.flatnonzero(mask).tolist():
            order, layout = next(queue, (None, layouts[-1]))
            running[i] = None if order is None else _Episode(order, layout)
            seeds[i] = layout
        options = {"reset_mask": mask}
        student_observation, _ = student_env.reset(seed=seeds, options=options)
        teacher_observation = (
            teacher_env.reset(seed=seeds, options=options)[0] if twin else student_observation
        )
        for i in np.flatnonzero(mask).tolist():
            planner.reset(i, teacher_observation["map"][i], teacher_observation["proprio"][i])
        return student_observation, teacher_observation

    observation, teacher_observation = start(np.ones(n, dtype=bool))
    while any(episode is not None for episode in running):
        labels = planner.act(teacher_observation["map"], teacher_observation["proprio"])
        actions = labels
        if student is not None:
            actions = np.asarray(student(observation, starts), dtype=np.int64).reshape(n, entries)
            for i in range(n):
                planner.follow(i, actions[i, :3].tolist())  # the probe, not the claim
        for i, episode in enumerate(running):
            if episode is not None:
                episode.observations.append({key: value[i] for key, value in observation.items()})
                episode.labels.append(labels[i])
        observation, rewards, terminated, truncated, info = student_env.step(actions)
        if twin:
            teacher_observation, *_ = teacher_env.step(actions)
            if not np.array_equal(teacher_observation["proprio"], observation["proprio"]):
                raise RuntimeError(
                    "the teacher's and the student's envs left the same probes in different "
                    "poses (the scene must not depend on the map)"
                )
        else:
            teacher_observation = observation
        ended = terminated | truncated
        for i, episode in enumerate(running):
            if episode is None:
                continue
            episode.rewards.append(float(rewards[i]))
            if ended[i]:
                finished[episode.order] = episode.finish(gamma, info, i)
                if progress is not None:
                    progress(1)
        starts = ended.copy()
        if ended.any():
            observation, teacher_observation = start(ended)
