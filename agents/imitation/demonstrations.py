"""Demonstrations: the teacher's probe for every state of an episode, with what the policy sees
there and the return that followed.

The teacher is the GPIS probe planner by default, or an ensemble of trained runs
(``agents.imitation.teachers``): observation-only, so it can label any state, not only those
it reaches. ``record`` runs episodes in which either the teacher acts (behaviour
cloning's demonstrations) or a student acts while the teacher's belief follows the student's
probes and labels each state (DAgger). A student with another map than the teacher's
sees its own observation: the episode runs in two envs of the same layout stepped with the
same probes, the teacher reading one and the student the other (the scene does not depend on
the map mode; ``record`` checks the two hands stay in the same pose).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from agents.imitation.teachers import PLANNER, make_teacher
from agents.sb3.anchor import OBSERVATION_PREFIX, observations_in
from tactile_search import CupboardSearchEnv

#: The fields with one row per probe beside the observations, in the constructor's order.
PER_ROW = (
    "actions",
    "returns",
    "layout_seeds",
    "episode_success",
    "episode_tips",
    "episode_steps",
)

#: A student's policy for one episode: observation -> probe.
Student = Callable[[dict], np.ndarray]


@dataclasses.dataclass
class Demonstrations:
    """Labelled states, one row per probe: ``observations`` (key -> ``(n, ...)`` array, as the
    student's env returns them), ``actions`` (``(n, entries)`` int64, the teacher's probe,
    and its claim where the task claims),
    ``returns`` (``(n,)`` float32, the discounted return from the state on, under whoever
    acted), ``layout_seeds`` (``(n,)``, the episode's layout), the episode's outcome,
    ``episode_success`` and ``episode_tips`` (``(n,)``, the same on each of its rows), and
    ``episode_steps`` (``(n,)`` int64, the probe's index in its episode: an episode's rows
    are consecutive, from 0, so a recurrent student is cloned on whole episodes)."""

    observations: dict[str, np.ndarray]
    actions: np.ndarray
    returns: np.ndarray
    layout_seeds: np.ndarray
    episode_success: np.ndarray
    episode_tips: np.ndarray
    episode_steps: np.ndarray

    def __post_init__(self) -> None:
        n = len(self.actions)
        sizes = {key: len(value) for key, value in self.observations.items()}
        if self.actions.ndim != 2 or any(size != n for size in sizes.values()):
            raise ValueError(
                f"every field needs one row per probe: actions {self.actions.shape}, "
                f"observations {sizes}"
            )
        for name in PER_ROW:
            if len(getattr(self, name)) != n:
                raise ValueError(
                    f"{name} has {len(getattr(self, name))} rows, actions {n}: one per probe"
                )

    def __len__(self) -> int:
        return len(self.actions)

    def episode_slices(self) -> list[slice]:
        """Each episode's rows, in order (an episode starts where ``episode_steps`` is 0)."""
        starts = np.flatnonzero(self.episode_steps == 0)
        if len(self) and (len(starts) == 0 or starts[0] != 0):
            raise ValueError("the first row must start an episode (episode_steps 0)")
        ends = [*starts[1:], len(self)]
        return [slice(int(a), int(b)) for a, b in zip(starts, ends, strict=True)]

    @property
    def episodes(self) -> int:
        return len(np.unique(self.layout_seeds))

    def outcomes(self) -> dict[str, float]:
        """Over the episodes: the share that succeeded and the jars tipped in all."""
        _, first = np.unique(self.layout_seeds, return_index=True)
        return {
            "success": float(self.episode_success[first].mean()),
            "tips": int(self.episode_tips[first].sum()),
        }

    def rows(self, index: np.ndarray) -> Demonstrations:
        """The demonstrations at ``index`` (an index array or boolean mask)."""
        return Demonstrations(
            {key: value[index] for key, value in self.observations.items()},
            *(getattr(self, name)[index] for name in PER_ROW),
        )

    def split_by_layout(self, held_out: float, seed: int) -> tuple[Demonstrations, Demonstrations]:
        """(kept, held out): ``held_out`` of the layouts, drawn with ``seed``, go whole to
        the second part, so that no state of a held-out episode is trained on."""
        if not 0.0 < held_out < 1.0:
            raise ValueError(f"held_out must be a fraction in (0, 1), got {held_out!r}")
        layouts = np.unique(self.layout_seeds)
        rng = np.random.default_rng(seed)
        chosen = rng.choice(layouts, size=max(1, round(held_out * len(layouts))), replace=False)
        mask = np.isin(self.layout_seeds, chosen)
        return self.rows(~mask), self.rows(mask)

    @staticmethod
    def concatenate(parts: Sequence[Demonstrations]) -> Demonstrations:
        if not parts:
            raise ValueError("concatenate needs at least one Demonstrations")
        keys = parts[0].observations.keys()
        return Demonstrations(
            {key: np.concatenate([part.observations[key] for part in parts]) for key in keys},
            *(np.concatenate([getattr(part, name) for part in parts]) for name in PER_ROW),
        )

    def save(self, path: Path) -> None:
        """To a compressed ``.npz`` (the maps compress well)."""
        np.savez_compressed(
            path,
            **{name: getattr(self, name) for name in PER_ROW},
            **{f"{OBSERVATION_PREFIX}{key}": value for key, value in self.observations.items()},
        )

    @staticmethod
    def load(path: Path) -> Demonstrations:
        with np.load(path) as data:
            observations = observations_in(data)
            fields = {name: data[name] for name in PER_ROW if name in data.files}
            if "episode_steps" not in fields and "layout_seeds" in fields:
                # A file written before the field: each layout's rows are one episode.
                fields["episode_steps"] = _steps_by_layout(fields["layout_seeds"])
            missing = [name for name in PER_ROW if name not in fields]
            if missing or not observations:
                raise ValueError(
                    f"{path} is not a file of demonstrations: it lacks {missing or 'observations'}"
                )
            return Demonstrations(observations, *(fields[name] for name in PER_ROW))


def _steps_by_layout(layout_seeds: np.ndarray) -> np.ndarray:
    """Each row's index among the consecutive rows of its layout."""
    steps = np.zeros(len(layout_seeds), dtype=np.int64)
    for i in range(1, len(layout_seeds)):
        if layout_seeds[i] == layout_seeds[i - 1]:
            steps[i] = steps[i - 1] + 1
    return steps


def record(
    layout_seeds: Sequence[int],
    env_kwargs: dict[str, Any],
    gamma: float,
    student: Callable[[int], Student] | None = None,
    teacher: str = PLANNER,
) -> Demonstrations:
    """The labels of ``teacher`` (a spec, ``agents.imitation.teachers``; the GPIS probe planner
    by default) over one episode per layout seed in the env of ``env_kwargs`` (the student's
    settings: its map, reward and action mode, which must be the probe mode).

    Without ``student`` the teacher acts. With one, ``student(layout_seed)`` gives the
    episode's policy (observation -> probe) and its probes are carried out while the teacher
    labels. ``returns`` are discounted by ``gamma`` within the episode (the time limit's cut
    is not bootstrapped)."""
    if env_kwargs.get("action_mode") != "probe":
        raise ValueError(
            f"demonstrations need action_mode='probe' (the teacher's probes), got "
            f"{env_kwargs.get('action_mode')!r}"
        )
    student_env = CupboardSearchEnv(**env_kwargs)
    labeller = make_teacher(teacher)
    teacher_kwargs = {**env_kwargs, **labeller.env_kwargs}
    twin = teacher_kwargs != env_kwargs
    teacher_env = CupboardSearchEnv(**teacher_kwargs) if twin else student_env
    parts = []
    try:
        for layout_seed in layout_seeds:
            parts.append(
                _episode(int(layout_seed), student_env, teacher_env, labeller, gamma, student)
            )
    finally:
        student_env.close()
        if twin:
            teacher_env.close()
    return Demonstrations.concatenate(parts)


def _episode(
    layout_seed: int,
    student_env: CupboardSearchEnv,
    teacher_env: CupboardSearchEnv,
    teacher: Any,
    gamma: float,
    student: Callable[[int], Student] | None,
) -> Demonstrations:
    """One episode's labelled states."""
    observation, info = student_env.reset(seed=layout_seed)
    teacher_observation = observation
    if teacher_env is not student_env:
        teacher_observation, info = teacher_env.reset(seed=layout_seed)
    teacher.reset(teacher_env, teacher_observation, info)
    acting = student(layout_seed) if student is not None else None
    observations, actions, rewards = [], [], []
    done = False
    while not done:
        label = teacher.act(teacher_observation)
        action = label
        if acting is not None:
            action = np.asarray(acting(observation), dtype=np.int64).reshape(3)
            teacher.follow(action)
        observations.append(observation)
        actions.append(label)
        observation, reward, terminated, truncated, info = student_env.step(action)
        if teacher_env is not student_env:
            teacher_observation, *_ = teacher_env.step(action)
            if not np.array_equal(teacher_observation["proprio"], observation["proprio"]):
                raise RuntimeError(
                    f"layout {layout_seed}: the teacher's and the student's envs left the "
                    "same probe in different poses (the scene must not depend on the map)"
                )
        else:
            teacher_observation = observation
        rewards.append(float(reward))
        done = terminated or truncated
    return episode_rows(
        observations,
        actions,
        rewards,
        gamma,
        layout_seed,
        success=bool(info["success"]),
        tips=int(info["tips"]),
    )


def episode_rows(
    observations: Sequence[dict[str, np.ndarray]],
    labels: Sequence[np.ndarray],
    rewards: Sequence[float],
    gamma: float,
    layout_seed: int,
    *,
    success: bool,
    tips: int,
) -> Demonstrations:
    """One whole episode's rows: its observations and the teacher's labels per probe, the
    returns discounted by ``gamma`` from each probe on (the time limit's cut not
    bootstrapped), and the episode's layout and outcome on every row."""
    returns = np.zeros(len(rewards), dtype=np.float32)
    following = 0.0
    for i in range(len(rewards) - 1, -1, -1):
        following = rewards[i] + gamma * following
        returns[i] = following
    n = len(labels)
    return Demonstrations(
        {key: np.stack([o[key] for o in observations]) for key in observations[0]},
        np.stack(labels).astype(np.int64),
        returns,
        np.full(n, layout_seed, dtype=np.uint64),
        np.full(n, success),
        np.full(n, tips, dtype=np.int64),
        np.arange(n, dtype=np.int64),
    )
