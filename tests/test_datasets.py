"""The Minari datasets of ``python -m agents.datasets``: written to a temporary
``MINARI_DATASETS_PATH``, they load with ``minari.load_dataset`` offline, and each episode
replays from its recorded seed and actions in a fresh env (recovered from the dataset's own
spec) with the same observations, rewards and flags bit for bit. Only training layouts go in;
each task gets its teacher and its published runs, an id with none says so."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import gymnasium
import numpy as np
import pytest
import yaml

pytest.importorskip("minari")
pytest.importorskip("h5py")
pytest.importorskip("stable_baselines3")

import minari

from agents.evaluation.agent_specs import make_agent
from agents.evaluation.evaluation import task_of
from agents.imitation.teachers import PLANNER
from agents.offline.catalogue import (
    DatasetSource,
    dataset_id,
    dataset_sources,
    default_env_ids,
    published_runs,
    teacher,
)
from agents.offline.recording import make_env, record_episodes, training_seeds
from agents.offline.references import REFERENCE_AGENTS, ReferenceScores, reference_scores
from agents.offline.writing import datasets_root, write_agent_dataset
from agents.rollout import evaluate_agent
from agents.run_dir import code_version
from agents.sb3.recipes import load_hyperparams
from agents.scripted import SCRIPTED_TASKS, GpisProbePlanner
from tactile_search import ENV_IDS
from tactile_search.seed_ranges import TRAINING, VALIDATION, held_out_seeds

REPO = Path(__file__).resolve().parents[1]
REFERENCES = ReferenceScores("random", -2.0, "oracle", 0.5, episodes=1)


def teacher_source(env_id: str) -> DatasetSource:
    return DatasetSource(env_id, teacher(env_id), dataset_id(env_id, teacher(env_id)))


def assert_same(recorded: object, replayed: object, what: str) -> None:
    """Equal bit for bit: the same dtype and the same bytes."""
    recorded, replayed = np.asarray(recorded), np.asarray(replayed)
    assert recorded.dtype == replayed.dtype, what
    assert recorded.shape == replayed.shape, what
    assert recorded.tobytes() == replayed.tobytes(), what


@pytest.mark.parametrize("env_id", default_env_ids())
def test_a_teachers_dataset_loads_offline_and_replays_bit_for_bit(
    env_id: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("MINARI_DATASETS_PATH", str(tmp_path))
    source = teacher_source(env_id)
    seeds = training_seeds(3, first=TRAINING[0] + 7)
    written = write_agent_dataset(source, seeds, REFERENCES)
    assert written.episodes == 3 and written.steps > 0

    dataset = minari.load_dataset(source.dataset_id)  # from disk, no download
    assert dataset.total_episodes == 3 and dataset.total_steps == written.steps
    metadata = dataset.storage.metadata
    assert metadata["ref_min_score"] == REFERENCES.min_score
    assert metadata["ref_max_score"] == REFERENCES.max_score
    assert metadata["algorithm_name"] == source.agent
    assert metadata["code_commit"] == code_version()["commit"]
    assert dataset.spec.env_spec.id == env_id
    episode_seeds = [m["seed"] for m in dataset.storage.get_episode_metadata(range(3))]
    assert episode_seeds == seeds

    env = dataset.recover_environment()  # a fresh env from the dataset's own spec
    try:
        for episode, seed in zip(dataset.iterate_episodes(), episode_seeds, strict=True):
            observation, _ = env.reset(seed=seed)
            for key in dataset.observation_space:
                assert_same(episode.observations[key][0], observation[key], f"{key} at reset")
            for t, action in enumerate(episode.actions):
                observation, reward, terminated, truncated, _ = env.step(action)
                for key in dataset.observation_space:
                    assert_same(episode.observations[key][t + 1], observation[key], f"{key} {t}")
                assert reward == episode.rewards[t]
                assert (terminated, truncated) == (
                    episode.terminations[t],
                    episode.truncations[t],
                )
            assert terminated or truncated, "the recorded episode ended where the replay did"
    finally:
        env.close()


def test_datasets_refuse_layouts_outside_the_training_range() -> None:
    env_id = default_env_ids()[0]
    agent = GpisProbePlanner()
    env = make_env(env_id, GpisProbePlanner.env_kwargs)
    try:
        with pytest.raises(ValueError, match="training range"):
            record_episodes(env, agent, held_out_seeds("validation", 1))
    finally:
        env.close()
    with pytest.raises(ValueError, match="training range"):
        training_seeds(2, first=VALIDATION[0])
    with pytest.raises(ValueError, match="training range"):
        training_seeds(2, first=TRAINING[1] - 1)
    with pytest.raises(TypeError, match="episodes"):
        training_seeds(1.5)  # type: ignore[arg-type]


def test_each_ids_teacher_is_the_planner_every_learned_agent_of_its_task_clones() -> None:
    agents = (("ppo", "gpis"), ("ppo", "occupancy"), ("ppo", "none"), ("recurrent_ppo", "none"))
    for env_id in ENV_IDS:
        default_tier = next(i for i in default_env_ids() if task_of(i) == task_of(env_id))
        for algo, map_mode in agents:
            recipe = load_hyperparams(algo, map_mode, default_tier)
            assert teacher(env_id) == recipe["imitation"].get("teacher", PLANNER), (env_id, algo)
        assert task_of(env_id) in SCRIPTED_TASKS[teacher(env_id)], env_id


def test_the_reference_agents_play_their_task() -> None:
    assert set(REFERENCE_AGENTS) == {task_of(env_id) for env_id in default_env_ids()}
    for task, agents in REFERENCE_AGENTS.items():
        assert all(task in SCRIPTED_TASKS[agent] for agent in agents), (task, agents)


def test_the_reference_scores_are_the_random_and_oracle_returns() -> None:
    env_id = "tactile_search/MapByTouch-v0"
    seeds = training_seeds(2)
    scores = reference_scores(env_id, seeds)
    assert (scores.min_agent, scores.max_agent, scores.episodes) == ("random_map", "map_oracle", 2)
    # The same episodes through the evaluation's loop (the vector env) give the same means.
    for spec, score in ((scores.min_agent, scores.min_score), (scores.max_agent, scores.max_score)):
        agent, agent_kwargs = make_agent(spec)
        rows = evaluate_agent(agent, seeds, **{**gymnasium.spec(env_id).kwargs, **agent_kwargs})
        assert score == pytest.approx(np.mean([row["reward"] for row in rows]), abs=1e-9)


def test_an_id_without_published_runs_gets_its_teacher_and_a_line(tmp_path: Path) -> None:
    map_id = "tactile_search/MapByTouch-v0"
    sources, notes = dataset_sources([map_id], published=tmp_path)
    assert [s.dataset_id for s in sources] == ["tactile_search/map/occupancy_mapper-v0"]
    assert any("no learned agent published yet" in note for note in notes), notes


def test_finished_runs_are_published_and_unfinished_ones_skipped(tmp_path: Path) -> None:
    identify_id = "tactile_search/IdentifyByTouch-v0"
    folder = tmp_path / "IdentifyByTouch-v0"
    finished, unfinished = folder / "ppo_gpis_seed0", folder / "ppo_none_seed0"
    for run in (finished, unfinished):
        (run / "imitation").mkdir(parents=True)
    config = {"algo": "ppo", "map": "gpis", "env_id": identify_id, "timesteps_done": 1}
    (finished / "config.yml").write_text(yaml.safe_dump(config))
    (finished / "model.zip").write_bytes(b"")
    runs, notes = published_runs(identify_id, tmp_path)
    assert runs == [finished]
    assert any(str(unfinished) in note and "not a finished run" in note for note in notes)
    sources, _ = dataset_sources([identify_id], published=tmp_path)
    assert [s.dataset_id for s in sources] == [
        "tactile_search/identify/identify_planner-v0",
        "tactile_search/identify/ppo_gpis_seed0-v0",
    ]


def test_agents_that_play_none_of_the_ids_are_refused() -> None:
    with pytest.raises(ValueError, match="none of the ids"):
        dataset_sources(["tactile_search/MapByTouch-v0"], ["gpis_probe_planner"])
    with pytest.raises(ValueError, match="scripted agent"):
        dataset_sources(["tactile_search/MapByTouch-v0"], ["no_such_agent"])


def test_an_existing_dataset_is_refused_unless_overwritten(tmp_path: Path) -> None:
    source = teacher_source(default_env_ids()[0])
    seeds = training_seeds(1)
    with datasets_root(tmp_path):
        write_agent_dataset(source, seeds, REFERENCES)
        with pytest.raises(ValueError, match="--overwrite"):
            write_agent_dataset(source, seeds, REFERENCES)
        write_agent_dataset(source, training_seeds(2), REFERENCES, overwrite=True)
        assert minari.load_dataset(source.dataset_id).total_episodes == 2


def test_the_command_writes_each_ids_datasets_and_says_what_it_skipped(tmp_path: Path) -> None:
    out, published = tmp_path / "datasets", tmp_path / "published"
    published.mkdir()
    done = subprocess.run(
        [
            sys.executable,
            "-m",
            "agents.datasets",
            "--env-ids",
            "tactile_search/MapByTouch-v0",
            "--episodes",
            "2",
            "--reference-episodes",
            "1",
            "--out",
            str(out),
            "--published",
            str(published),
        ],
        cwd=REPO,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert done.returncode == 0, done.stderr[-3000:]
    assert "MapByTouch-v0: no learned agent published yet" in done.stdout
    assert "tactile_search/map/occupancy_mapper-v0: 2 episodes" in done.stdout
    with datasets_root(out):
        dataset = minari.load_dataset("tactile_search/map/occupancy_mapper-v0")
    assert dataset.storage.metadata["ref_min_agent"] == "random_map"
    assert dataset.storage.metadata["ref_episodes"] == 1
