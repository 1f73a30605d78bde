"""The experiment grid on a local Ray cluster (a head and a worker node on this machine):
training trials and evaluation shards as Ray tasks give the models and episode rows of
the same grid run one trial after another, a grid run again reuses what finished, and a
failing trial is reported while the rest of the grid finishes; a worker process killed
mid-trial costs a retry of its task and the same model."""

from __future__ import annotations

import csv
from pathlib import Path

import pytest

pytest.importorskip("ray")
pytest.importorskip("stable_baselines3")

import ray
from ray.cluster_utils import Cluster

from agents.evaluation.evaluation import evaluate
from agents.grid import ray_scheduler
from agents.grid.ray_session import connect
from agents.grid.trials import TrainingTrial, evaluate_shard, shards, train_trial
from agents.run_dir import model_digest
from tests.recipes import SMALL_IMITATION

# A few hundred steps a trial: two rollouts of 2 envs x 64 steps.
TIMESTEPS = 256
N_ENVS = 2
EPISODES = 4
SHARD_EPISODES = 2


@pytest.fixture(scope="module")
def cluster():
    """A head node and a worker node, one CPU each, on this machine."""
    local = Cluster(initialize_head=True, head_node_args={"num_cpus": 1})
    local.add_node(num_cpus=1)
    local.wait_for_nodes()
    connect(address=local.address)
    try:
        yield ray.cluster_resources()
    finally:
        ray.shutdown()
        local.shutdown()


def tiny_trials(
    runs: Path, maps: tuple[str, ...] = ("none", "gpis"), clone_first: bool = False
) -> list[TrainingTrial]:
    """A trial per map of a few hundred PPO steps; ``clone_first``: after a small clone
    stage, else PPO from scratch."""
    return [
        TrainingTrial(
            "ppo",
            map_mode,
            0,
            str(runs.resolve()),
            TIMESTEPS,
            1,
            n_envs=N_ENVS,
            imitation=SMALL_IMITATION if clone_first else None,
            from_scratch=not clone_first,
        )
        for map_mode in maps
    ]


def ppo_alone(runs: Path) -> TrainingTrial:
    """A trial of PPO from scratch with no map for a thousand steps (a few rollouts)."""
    return TrainingTrial(
        "ppo", "none", 0, str(runs.resolve()), 1024, 1, n_envs=N_ENVS, from_scratch=True
    )


def rows(path: Path) -> list[dict[str, str]]:
    with path.open(newline="") as f:
        return sorted(csv.DictReader(f), key=lambda row: (row["agent"], int(row["seed"])))


def test_cluster_has_two_nodes(cluster) -> None:
    assert len([node for node in ray.nodes() if node["Alive"]]) == 2
    assert cluster["CPU"] == 2


def test_grid_on_ray_equals_the_grid_run_one_trial_after_another(cluster, tmp_path) -> None:
    on_ray = ray_scheduler.train_on_ray(tiny_trials(tmp_path / "ray", clone_first=True))
    here = [train_trial(trial) for trial in tiny_trials(tmp_path / "local", clone_first=True)]
    assert [d.name for d in on_ray] == [d.name for d in here]
    for ray_run, local_run in zip(on_ray, here, strict=True):
        assert model_digest(ray_run / "model.zip") == model_digest(local_run / "model.zip")

    specs_ray = [*map(str, on_ray), "random"]
    ray_scheduler.evaluate_on_ray(
        specs_ray,
        out=tmp_path / "eval_ray",
        episodes=EPISODES,
        shard_episodes=SHARD_EPISODES,
        gifs=False,
    )
    evaluate(
        [*map(str, here), "random"], out=tmp_path / "eval_local", episodes=EPISODES, gifs=False
    )
    merged = rows(tmp_path / "eval_ray" / "episodes.csv")
    assert len(merged) == 3 * EPISODES  # 3 agents x 4 layouts, from 6 shards
    assert merged == rows(tmp_path / "eval_local" / "episodes.csv")
    assert (tmp_path / "eval_ray" / "results.md").read_text() == (
        tmp_path / "eval_local" / "results.md"
    ).read_text()

    # Run again: the finished runs are reused (not retrained), every row is reused.
    before = {d: (d / "model.zip").stat().st_mtime_ns for d in on_ray}
    again = ray_scheduler.train_on_ray(tiny_trials(tmp_path / "ray"))
    assert {d: (d / "model.zip").stat().st_mtime_ns for d in again} == before


def test_evaluation_resumes_from_the_rows_a_stopped_grid_kept(cluster, tmp_path, capsys) -> None:
    out = tmp_path / "eval"
    ray_scheduler.evaluate_on_ray(["random"], out=out, episodes=2, shard_episodes=1, gifs=False)
    complete = rows(out / "episodes.csv")
    # A stop after the first shard: only its row was written.
    lines = (out / "episodes.csv").read_text().splitlines(keepends=True)
    (out / "episodes.csv").write_text("".join(lines[:2]))
    capsys.readouterr()
    ray_scheduler.evaluate_on_ray(["random"], out=out, episodes=2, shard_episodes=1, gifs=False)
    assert "reusing 1 episodes" in capsys.readouterr().out
    assert rows(out / "episodes.csv") == complete


def test_a_failing_trial_is_reported_and_the_rest_of_the_grid_finishes(cluster, tmp_path) -> None:
    good = tiny_trials(tmp_path / "runs", maps=("none",))
    # An unknown algorithm fails inside the trial, on every attempt.
    bad = TrainingTrial("not_an_algo", "none", 0, str((tmp_path / "runs").resolve()), 256, 1)
    with pytest.raises(ray_scheduler.GridError, match="not_an_algo_none_seed0") as caught:
        ray_scheduler.train_on_ray([good[0], bad], max_failures=1)
    assert "1 of 2 training trials failed" in str(caught.value)
    assert (good[0].run_dir / "model.zip").is_file()


def test_trials_and_shards_refuse_what_they_cannot_run(tmp_path) -> None:
    with pytest.raises(ValueError, match="absolute"):
        TrainingTrial("ppo", "none", 0, "relative/runs", 256, 1)
    with pytest.raises(ValueError, match="cpus"):
        TrainingTrial("ppo", "none", 0, str(tmp_path.resolve()), 256, 0)
    with pytest.raises(ValueError, match="shard size"):
        shards([1, 2, 3], 0)
    assert shards([1, 2, 3, 4, 5], 2) == [[1, 2], [3, 4], [5]]
    with pytest.raises(ValueError, match="each trial may appear once"):
        trial = tiny_trials(tmp_path, maps=("none",))[0]
        ray_scheduler.train_on_ray([trial, trial])


def test_a_shard_runs_the_episodes_of_its_seeds() -> None:
    results = evaluate_shard("random", None, [1_000_000, 1_000_001])
    assert [r["seed"] for r in results] == [1_000_000, 1_000_001]


def test_the_pipeline_gives_the_same_table_on_ray_and_locally(cluster, tmp_path) -> None:
    from agents.grid.budgets import Budget, Task
    from agents.grid.pipeline import run_budget

    tables = {}
    for scheduler in ("ray", "local"):
        budget = Budget(
            agents=(("ppo", "none"),),
            timesteps=TIMESTEPS,
            episodes=2,
            runs=tmp_path / scheduler / "runs",
            results=tmp_path / scheduler / "results",
            cpus_per_trial=1,
            imitation=SMALL_IMITATION,
            tasks=(Task(sampled_too=True),),
        )
        (outcome,) = run_budget(budget, [0, 1], scheduler, progress_bar=False)
        tables[scheduler] = outcome.table
        assert [d.name for d in outcome.run_dirs] == ["ppo_none_seed0", "ppo_none_seed1"]
        assert (budget.results / "training" / "ppo_none_seed1" / "config.yml").is_file()
    assert tables["ray"] == tables["local"]
    # The learned agents sampling their probes, too, the same rows either way.
    sampled = [rows(tmp_path / s / "results" / "sampled" / "episodes.csv") for s in tables]
    assert sampled[0] == sampled[1] and {r["agent"] for r in sampled[0]} == {
        "ppo (none map, seed 0)",
        "ppo (none map, seed 1)",
    }
    assert "seed 1" in tables["ray"]  # two training seeds of one agent, told apart


def _task_pids(name: str) -> list[int]:
    """The processes running the Ray task ``name`` (Ray titles a worker ``ray::<task>``)."""
    pids = []
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                cmdline = (entry / "cmdline").read_bytes()
            except OSError:  # gone meanwhile
                continue
            if cmdline.startswith(f"ray::{name}".encode()):
                pids.append(int(entry.name))
    return pids


def test_a_killed_worker_costs_a_retry_and_the_grid_finishes_as_undisturbed(
    cluster, tmp_path
) -> None:
    import os
    import signal
    import threading
    import time

    trial = ppo_alone(tmp_path / "ray")
    outcome: dict[str, object] = {}

    def grid() -> None:
        try:
            outcome["runs"] = ray_scheduler.train_on_ray([trial])
        except Exception as err:  # reported below
            outcome["error"] = err

    runner = threading.Thread(target=grid)
    runner.start()
    killed = []
    deadline = time.monotonic() + 300
    # Kill the worker once its trial has started writing its run (mid-training).
    while not killed and runner.is_alive() and time.monotonic() < deadline:
        pids = _task_pids("_training_task")
        if pids and (trial.run_dir / "config.yml").exists():
            os.kill(pids[0], signal.SIGKILL)
            killed.append(pids[0])
            outcome["finished_before_the_kill"] = (trial.run_dir / "model.zip").exists()
        time.sleep(0.02)
    runner.join(timeout=600)
    assert killed, "the trial ended before its worker could be killed"
    assert outcome["finished_before_the_kill"] is False  # killed mid-training
    assert "error" not in outcome, outcome.get("error")  # Ray retried the task ...
    assert outcome["runs"] == [trial.run_dir]  # ... and the grid finished
    # The retried trial gives the model of an undisturbed run of the same trial.
    undisturbed = train_trial(ppo_alone(tmp_path / "here"))
    assert model_digest(trial.run_dir / "model.zip") == model_digest(undisturbed / "model.zip")
