"""A dataset written in Minari's format (HDF5, lossless) with the metadata that makes it usable
and reproducible: the env's spec (the registered id with the agent's map and action mode) as
the data's and the evaluation's, the reference scores, the agent's name, the code's git commit
(``agents.run_dir.code_version``) and the tactile_search version it needs; each episode's
layout seed is in its episode metadata (``dataset.storage.get_episode_metadata``).

Datasets live where Minari keeps them (``MINARI_DATASETS_PATH``, else ``~/.minari/datasets``)
unless a root is given; ``minari.load_dataset(id)`` reads them offline from there.
"""

from __future__ import annotations

import contextlib
import os
import time
import warnings
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import gymnasium
import minari
import numpy as np
from minari.data_collector import EpisodeBuffer
from minari.storage.datasets_root_dir import get_dataset_path

import tactile_search
from agents.evaluation.agent_specs import make_agent
from agents.offline.catalogue import DatasetSource
from agents.offline.recording import make_env, record_episodes
from agents.offline.references import ReferenceScores
from agents.run_dir import code_version
from tactile_search.seed_ranges import TRAINING

#: The environment variable Minari reads its datasets' root from.
DATASETS_PATH_VARIABLE = "MINARI_DATASETS_PATH"
#: Who a dataset's metadata names as its author.
AUTHOR = "tactile_search"
# Minari stores this format without extra packages beyond h5py, the default of its loader.
DATA_FORMAT = "hdf5"


@contextlib.contextmanager
def datasets_root(root: Path | None) -> Iterator[None]:
    """Minari reads and writes its datasets under ``root`` inside the block (the
    ``MINARI_DATASETS_PATH`` it reads, restored afterwards); None leaves Minari's own."""
    if root is None:
        yield
        return
    before = os.environ.get(DATASETS_PATH_VARIABLE)
    os.environ[DATASETS_PATH_VARIABLE] = str(Path(root).resolve())
    try:
        yield
    finally:
        if before is None:
            del os.environ[DATASETS_PATH_VARIABLE]
        else:
            os.environ[DATASETS_PATH_VARIABLE] = before


def code_permalink() -> tuple[str, dict[str, Any]]:
    """What produced a dataset: a line for Minari's ``code_permalink`` (the git commit, and
    whether the tree had changes) and the commit as ``code_version`` gives it."""
    code = code_version()
    if code["commit"] is None:
        return f"tactile_search {tactile_search.__version__}, outside a git checkout", code
    changes = " with uncommitted changes" if code["dirty"] else ""
    return f"tactile_search git commit {code['commit']}{changes}", code


def write_dataset(
    dataset_id: str,
    env: gymnasium.Env,
    buffers: Sequence[EpisodeBuffer],
    references: ReferenceScores,
    algorithm_name: str,
    extra_metadata: dict[str, Any] | None = None,
    overwrite: bool = False,
) -> minari.MinariDataset:
    """Writes ``buffers``, episodes of ``env``, as Minari dataset ``dataset_id`` (under the
    root Minari reads, ``datasets_root``). ``ValueError`` if it exists, unless
    ``overwrite``."""
    if not buffers:
        raise ValueError(f"{dataset_id}: a dataset needs at least one episode, got none")
    if get_dataset_path(dataset_id).exists():
        if not overwrite:
            raise ValueError(
                f"the dataset {dataset_id} exists already ({get_dataset_path(dataset_id)}): "
                "delete it (minari.delete_dataset) or write again with overwrite (--overwrite)"
            )
        minari.delete_dataset(dataset_id)
    permalink, code = code_permalink()
    seeds = [int(buffer.seed) for buffer in buffers if buffer.seed is not None]
    description = (
        f"{algorithm_name} on {env.spec.id if env.spec else env}: {len(buffers)} episodes on "
        f"training layouts (seeds {min(seeds)} to {max(seeds)}; each episode's seed is in its "
        "metadata: reset the env with it and step the actions to replay it). Reference "
        f"scores: the mean return of {references.min_agent} (min) and {references.max_agent} "
        f"(max) on {references.episodes} of these layouts."
    )
    with warnings.catch_warnings():
        # No contact address is kept for a project's datasets.
        warnings.filterwarnings("ignore", message="`author_email` is set to None")
        dataset = minari.create_dataset_from_buffers(
            dataset_id=dataset_id,
            buffer=list(buffers),
            env=env,
            eval_env=env.spec,
            algorithm_name=algorithm_name,
            author=AUTHOR,
            code_permalink=permalink,
            ref_min_score=references.min_score,
            ref_max_score=references.max_score,
            num_episodes_average_score=references.episodes,
            description=description,
            data_format=DATA_FORMAT,
            requirements=[f"tactile_search=={tactile_search.__version__}"],
            jpeg_encoding=False,  # lossless: the replay reproduces the stored observations
        )
    dataset.storage.update_metadata(
        {
            "code_commit": code["commit"],
            "code_dirty": code["dirty"],
            "tactile_search_version": tactile_search.__version__,
            "layout_seed_range": list(TRAINING),
            "ref_min_agent": references.min_agent,
            "ref_max_agent": references.max_agent,
            "ref_episodes": references.episodes,
            **(extra_metadata or {}),
        }
    )
    return dataset


@dataclass(frozen=True)
class WrittenDataset:
    """What ``write_agent_dataset`` wrote: the dataset's id, its episodes and steps, their
    mean return and the seconds recording and writing took."""

    dataset_id: str
    episodes: int
    steps: int
    mean_return: float
    seconds: float


def write_agent_dataset(
    source: DatasetSource,
    seeds: Sequence[int],
    references: ReferenceScores,
    overwrite: bool = False,
) -> WrittenDataset:
    """Plays ``source``'s agent on ``seeds`` (training layouts) in its env of the source's id
    and writes the episodes as the source's dataset (``write_dataset``)."""
    start = time.perf_counter()
    agent, agent_kwargs = make_agent(source.agent)
    env = make_env(source.env_id, agent_kwargs)
    try:
        buffers = record_episodes(env, agent, seeds)
        write_dataset(
            source.dataset_id,
            env,
            buffers,
            references,
            algorithm_name=agent.name,
            extra_metadata={"agent": source.agent},
            overwrite=overwrite,
        )
    finally:
        env.close()
    return WrittenDataset(
        dataset_id=source.dataset_id,
        episodes=len(buffers),
        steps=sum(len(buffer) for buffer in buffers),
        mean_return=float(np.mean([sum(buffer.rewards) for buffer in buffers])),
        seconds=time.perf_counter() - start,
    )
