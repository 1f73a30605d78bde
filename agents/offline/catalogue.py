"""Which datasets a registered id gets and what each is called.

Each task's datasets are its scripted teacher's (the core's planner its learned agents clone,
as the task's recipe names it: ``teacher``) and one per learned agent published for the id
(a finished run under ``docs/results/models/<the id's folder>/``,
``agents.run_dir.task_folder``). A dataset's Minari id is
``tactile_search/<task>/<agent>-v0``: the task of the id (``search``, ``identify``, ``map``;
a denser tier adds its own name, ``search_cupboardsearchdense``), the agent's name (a
scripted agent's, or the run directory's: ``ppo_gpis_seed0``).
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from agents.evaluation.evaluation import task_of
from agents.imitation.teachers import PLANNER
from agents.run_dir import PUBLISHED_RUNS, is_finished, recorded_config, task_folder
from agents.sb3.recipes import load_hyperparams
from agents.scripted import SCRIPTED_AGENTS, SCRIPTED_TASKS
from tactile_search import ENV_ID, ENV_IDS
from tactile_search._core import registered_envs

#: The namespace of every dataset written here.
NAMESPACE = "tactile_search"
#: The version every dataset id ends with (``-v0``).
DATASET_VERSION = 0
# What Minari accepts as a dataset's name (its DATASET_NAME_RE).
_DATASET_NAME = re.compile(r"[-_\w]+")


@dataclass(frozen=True)
class DatasetSource:
    """One dataset to write: the agent (a scripted name or a run directory, as
    ``agents.evaluation.agent_specs.make_agent`` takes it) playing registered id ``env_id``,
    and the dataset's Minari id."""

    env_id: str
    agent: str
    dataset_id: str


def default_env_ids() -> list[str]:
    """The first registered id of each task, in the registry's order (the default tiers:
    CupboardSearch-v0, IdentifyByTouch-v0, MapByTouch-v0)."""
    first: dict[str, str] = {}
    for env in registered_envs():
        first.setdefault(str(env["task"]), str(env["id"]))
    return list(first.values())


def teacher(env_id: str) -> str:
    """The scripted teacher of ``env_id``'s task: the planner its learned agents' clone stage
    learns from, as the recipe of the task's default tier names it (``imitation.teacher`` in
    ``agents/hyperparams/ppo.yml``, the same for every agent of an id:
    ``tests/test_recipes_by_id.py``), the GPIS probe planner where the recipe names none."""
    default_tier = {task_of(first): first for first in default_env_ids()}[task_of(env_id)]
    recipe = load_hyperparams("ppo", "gpis", default_tier)
    return str(recipe["imitation"].get("teacher", PLANNER))


def dataset_id(env_id: str, agent_name: str) -> str:
    """The Minari id of ``agent_name``'s dataset on registered id ``env_id``
    (``tactile_search/identify/identify_planner-v0``)."""
    if not isinstance(agent_name, str) or not _DATASET_NAME.fullmatch(agent_name):
        raise ValueError(
            f"a dataset's agent name must be letters, digits, '_' or '-', got {agent_name!r}"
        )
    task = task_of(env_id)
    group = task if env_id in default_env_ids() else f"{task}_{_id_name(env_id).lower()}"
    return f"{NAMESPACE}/{group}/{agent_name}-v{DATASET_VERSION}"


def _id_name(env_id: str) -> str:
    """``tactile_search/CupboardSearchDense-v0`` -> ``CupboardSearchDense``."""
    return env_id.split("/")[-1].rsplit("-v", 1)[0]


def published_runs(env_id: str, root: Path = Path(PUBLISHED_RUNS)) -> tuple[list[Path], list[str]]:
    """The finished runs of ``env_id`` published under ``root`` (in the id's folder,
    ``task_folder``), sorted by name, and a line for each folder passed over and why (a run
    not finished yet, none published yet). The default id's folder is ``root`` itself, whose
    other ids' folders are not runs."""
    folder = Path(root) / task_folder(env_id)
    if not folder.is_dir():
        return [], [f"{env_id}: no learned agent published yet (no folder {folder})"]
    other_ids = {task_folder(other) for other in ENV_IDS} - {""}
    runs, notes = [], []
    for candidate in sorted(path for path in folder.iterdir() if path.is_dir()):
        if folder == Path(root) and candidate.name in other_ids:
            continue
        config = recorded_config(candidate)
        if not isinstance(config, dict) or not is_finished(candidate, config):
            notes.append(f"{env_id}: skipped {candidate}, not a finished run (yet)")
        elif config.get("env_id", ENV_ID) != env_id:
            notes.append(f"{env_id}: skipped {candidate}, a run of {config.get('env_id')}")
        else:
            runs.append(candidate)
    if not runs:
        notes.append(f"{env_id}: no learned agent published yet (no finished run in {folder})")
    return runs, notes


def agent_name(agent: str) -> str:
    """What a dataset calls an agent: a scripted agent's name, a run directory's name."""
    return agent if agent in SCRIPTED_AGENTS else Path(agent).name


def plays(agent: str, env_id: str) -> bool:
    """Whether ``agent`` (a scripted name or a run directory) plays registered id ``env_id``:
    a scripted agent plays its tasks (``SCRIPTED_TASKS``), a run the id its ``config.yml``
    records. ``ValueError`` for a name that is neither."""
    if agent in SCRIPTED_AGENTS:
        return task_of(env_id) in SCRIPTED_TASKS[agent]
    config = recorded_config(Path(agent))
    if not isinstance(config, dict):
        raise ValueError(
            f"an agent must be a scripted agent {sorted(SCRIPTED_AGENTS)} or a training run's "
            f"directory, got {agent!r}"
        )
    return bool(config.get("env_id", ENV_ID) == env_id)


def dataset_sources(
    env_ids: Sequence[str],
    agents: Sequence[str] | None = None,
    published: Path = Path(PUBLISHED_RUNS),
) -> tuple[list[DatasetSource], list[str]]:
    """The datasets to write for ``env_ids`` and a line for everything passed over.

    Without ``agents``: each id's teacher (``teacher``) and its published runs
    (``published_runs`` under ``published``). With ``agents`` (scripted names or run
    directories): each on the ids among ``env_ids`` it plays (``plays``); ``ValueError`` for
    an agent that plays none of them."""
    sources: list[DatasetSource] = []
    notes: list[str] = []
    for env_id in env_ids:
        if agents is None:
            runs, skipped = published_runs(env_id, published)
            notes += skipped
            chosen = [teacher(env_id), *map(str, runs)]
        else:
            chosen = [agent for agent in agents if plays(agent, env_id)]
        sources += [DatasetSource(env_id, a, dataset_id(env_id, agent_name(a))) for a in chosen]
    unused = [a for a in agents or () if not any(s.agent == a for s in sources)]
    if unused:
        raise ValueError(f"{unused} play(s) none of the ids {list(env_ids)}")
    return sources, notes
