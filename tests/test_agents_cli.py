"""The training and evaluation CLIs run end to end in a subprocess (a few hundred steps, two
episodes), and their building blocks check their input."""

from __future__ import annotations

import csv
import dataclasses
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

pytest.importorskip("stable_baselines3")
pytest.importorskip("sb3_contrib")

from agents.run_dir import PUBLISHED_RUNS, code_version
from agents.sb3.recipes import load_hyperparams
from agents.sb3.training import TrainSettings, train
from agents.sb3.training_env import TRAIN_LAYOUT_SEEDS
from tactile_search.benchmark.statistics import summarize, wilson_interval
from tactile_search.seed_ranges import held_out_seeds

REPO = Path(__file__).resolve().parents[1]


# The PPO recipe's clone stage at a size of seconds (``agents.train --imitation``).
SMALL_IMITATION_ARGS = (
    "--imitation",
    "demo_episodes=12",
    "dagger_rounds=1",
    "dagger_episodes=4",
    "dagger_epochs=1",
    "cloning={epochs: 2}",
)


def run_module(*args: str) -> subprocess.CompletedProcess:
    result = subprocess.run(
        [sys.executable, "-m", *args], cwd=REPO, capture_output=True, text=True, timeout=600
    )
    assert result.returncode == 0, result.stderr[-3000:]
    return result


@pytest.fixture(scope="module")
def trained_runs(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    out = tmp_path_factory.mktemp("runs")
    runs = {}
    for algo, map_mode in (("ppo", "gpis"), ("recurrent_ppo", "none")):
        run_module(
            "agents.train",
            "--algo",
            algo,
            "--map",
            map_mode,
            "--timesteps",
            "256",
            "--n-envs",
            "2",
            "--seed",
            "3",
            "--out",
            str(out),
            "--no-progress",
            *SMALL_IMITATION_ARGS,
        )
        runs[algo] = out / f"{algo}_{map_mode}_seed3"
    return runs


def test_the_training_cli_writes_the_model_its_config_and_logs(trained_runs: dict[str, Path]):
    for algo, run_dir in trained_runs.items():
        assert (run_dir / "model.zip").is_file()
        assert list(run_dir.glob("events.out.tfevents.*")), "TensorBoard events"
        with (run_dir / "progress.csv").open() as f:
            rows = list(csv.DictReader(f))
        assert rows and int(float(rows[-1]["time/total_timesteps"])) >= 256
        config = yaml.safe_load((run_dir / "config.yml").read_text())
        assert config["algo"] == algo and config["seed"] == 3
        assert config["timesteps_done"] >= 256 and config["wall_clock_seconds"] > 0
        assert config["hyperparams"]["n_envs"] == 2
        assert config["train_layout_seeds"] == list(TRAIN_LAYOUT_SEEDS)
        assert config["code"] == code_version()  # this checkout's commit and dirty flag
        assert config["code"]["commit"] is None or len(config["code"]["commit"]) == 40


def test_the_code_version_is_the_checkouts_commit_and_dirty_flag(tmp_path: Path):
    def git(*args: str) -> str:
        return subprocess.run(
            ["git", "-C", str(tmp_path), *args], capture_output=True, text=True, check=True
        ).stdout.strip()

    assert code_version(tmp_path) == {"commit": None, "dirty": None}  # not a checkout
    git("init", "-q")
    (tmp_path / "recipe.yml").write_text("a: 1\n")
    git("add", "recipe.yml")
    git("-c", "user.name=t", "-c", "user.email=t@t", "commit", "-qm", "first")
    assert code_version(tmp_path) == {"commit": git("rev-parse", "HEAD"), "dirty": False}
    # A run being trained into the published models' folder is not a change of the code.
    (tmp_path / PUBLISHED_RUNS / "ppo_gpis_seed1").mkdir(parents=True)
    (tmp_path / PUBLISHED_RUNS / "ppo_gpis_seed1" / "progress.csv").write_text("x\n")
    assert code_version(tmp_path)["dirty"] is False
    (tmp_path / "recipe.yml").write_text("a: 2\n")
    assert code_version(tmp_path)["dirty"] is True


def test_the_evaluation_cli_writes_the_table_plots_and_gifs(
    trained_runs: dict[str, Path], tmp_path: Path
):
    out = tmp_path / "results"
    run_module(
        "agents.evaluate",
        "--runs",
        *map(str, trained_runs.values()),
        "--scripted",
        "random",
        "oracle",
        "--episodes",
        "2",
        "--out",
        str(out),
        "--gif-steps",
        "4",
    )
    table = (out / "results.md").read_text()
    for name in ("ppo (gpis map)", "recurrent_ppo (none map)", "random", "oracle"):
        assert f"| {name} |" in table
    with (out / "episodes.csv").open() as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == 4 * 2
    assert {int(r["seed"]) for r in rows} == set(held_out_seeds("validation", 2))
    for figure in ("success.png", "steps.png", "learning_curves.png"):
        assert (out / figure).stat().st_size > 1000
    assert len(list((out / "gifs").glob("*.gif"))) == 4


@pytest.mark.parametrize(
    ("successes", "n", "low", "high"),
    [
        (0, 10, 0.0, 0.2775),
        (5, 10, 0.2366, 0.7634),
        (10, 10, 0.7225, 1.0),
        (180, 200, 0.8506, 0.9343),
    ],
)
def test_the_wilson_interval_matches_published_values(successes, n, low, high):
    got = wilson_interval(successes, n)
    assert got == pytest.approx((low, high), abs=1e-4)


def test_the_summary_reports_quartiles_of_successful_episodes_only():
    episodes = [
        {
            "success": s,
            "steps": t,
            "tips": 0,
            "jar_displacement": 0.002,
            "max_jar_displacement": 0.001,
            "iou": 0.5,
        }
        for s, t in [(True, 10), (True, 20), (True, 30), (False, 200), (True, 40)]
    ]
    summary = summarize("x", "gpis", episodes)
    assert summary.successes == 4 and summary.success_rate == 0.8
    assert summary.steps_median == 25
    assert (summary.steps_q1, summary.steps_q3) == (17.5, 32.5)
    assert summary.displacement_mm == pytest.approx(2.0)


def test_bad_training_arguments_raise_value_errors(tmp_path: Path):
    with pytest.raises(ValueError, match="map must be one of"):
        train(TrainSettings("ppo", "lidar", out=tmp_path))
    with pytest.raises(ValueError, match="algo must be one of"):
        load_hyperparams("dqn", "gpis")
    with pytest.raises(ValueError, match="no 'tactile_search/CupboardSearch-v0' recipe for map"):
        load_hyperparams("recurrent_ppo", "gpis")
    with pytest.raises(ValueError, match="timesteps must be at least 1, got 0"):
        train(TrainSettings("ppo", "gpis", out=tmp_path, timesteps=0))
    with pytest.raises(ValueError, match="successes must be"):
        wilson_interval(3, 2)


def test_train_settings_name_what_they_take_and_what_came(tmp_path: Path):
    with pytest.raises(TypeError, match="seed must be an integer, got str: '3'"):
        TrainSettings("ppo", "none", seed="3")
    with pytest.raises(ValueError, match="seed must be at least 0, got -1"):
        TrainSettings("ppo", "none", seed=-1)
    with pytest.raises(TypeError, match="out must be a path, got int: 3"):
        TrainSettings("ppo", "none", out=3)
    with pytest.raises(ValueError, match="max_minutes must be > 0, got 0"):
        TrainSettings("ppo", "none", max_minutes=0)
    with pytest.raises(TypeError, match="max_minutes must be a real number, got str"):
        TrainSettings("ppo", "none", max_minutes="5")
    with pytest.raises(TypeError, match="progress_bar must be a bool, got int: 1"):
        TrainSettings("ppo", "none", progress_bar=1)
    with pytest.raises(TypeError, match="label must be a str, got int: 7"):
        TrainSettings("ppo", "none", label=7)
    with pytest.raises(TypeError, match="imitation must be a dict, got list"):
        TrainSettings("ppo", "none", imitation=[1])
    with pytest.raises(ValueError, match="n_envs must be at least 1, got 0"):
        TrainSettings("ppo", "none", n_envs=0)
    with pytest.raises(TypeError, match="train takes a TrainSettings, got str"):
        train("ppo")
    settings = TrainSettings("ppo", "none", out=str(tmp_path), seed=4)
    assert settings.run_dir == tmp_path / "ppo_none_seed4"
    assert settings.imitation is None and settings.out == tmp_path
    with pytest.raises(dataclasses.FrozenInstanceError):
        settings.seed = 5  # type: ignore[misc]


def test_regenerated_results_keep_the_hand_written_findings(tmp_path: Path):
    from agents.grid.results_doc import write_results

    path = tmp_path / "RESULTS.md"
    write_results(path, "table v1")
    path.write_text("# Results\n\nintro\n\n" + path.read_text() + "\n## Findings\n\nwhy\n")
    write_results(path, "table v2")
    text = path.read_text()
    assert "table v2" in text and "table v1" not in text
    assert text.startswith("# Results\n\nintro") and text.endswith("## Findings\n\nwhy\n")


def test_a_wall_clock_limit_stops_training_early_and_is_recorded(tmp_path: Path):
    run_dir = train(
        TrainSettings(
            "ppo",
            "none",
            out=tmp_path,
            timesteps=10**6,
            n_envs=2,
            max_minutes=0.001,
            progress_bar=False,
            from_scratch=True,
        )
    )
    config = yaml.safe_load((run_dir / "config.yml").read_text())
    assert (run_dir / "model.zip").is_file()
    assert config["hyperparams"]["max_minutes"] == 0.001
    assert 0 < config["timesteps_done"] < 10**6


@pytest.mark.parametrize("n", [1, 2, 7, 50, 200, 1000])
def test_the_wilson_interval_holds_the_rate_even_at_zero_and_one(n):
    for successes in (0, n):
        low, high = wilson_interval(successes, n)
        assert 0.0 <= low <= successes / n <= high <= 1.0


def test_evaluation_builds_the_env_from_the_recipe_without_its_reward_terms(tmp_path: Path):
    from agents.evaluation.agent_specs import make_agent
    from agents.evaluation.evaluation import evaluate
    from tests.recipes import train_with_recipe

    env_kwargs = {"map": "gpis", "action_mode": "probe", "grid_shape": [36, 72], "jar_count": 3}
    rewards = {"reward_approach": 10.0, "reward_tip": 5.0}
    run_dir = train_with_recipe(tmp_path, "gpis", env_kwargs={**env_kwargs, **rewards})
    # The grid and the jars as trained (the model's spaces need the grid), the default reward.
    assert make_agent(str(run_dir))[1] == env_kwargs
    (summary,) = evaluate([str(run_dir)], out=tmp_path / "eval", episodes=1, gifs=False)
    assert summary.map_mode == "gpis" and summary.episodes == 1


def test_the_results_page_takes_machines_code_and_seeds_from_the_run_configs(tmp_path: Path):
    from agents.grid.budgets import BUDGETS
    from agents.grid.results_doc import results_markdown

    run_dirs = []
    for seed, dirty in ((0, False), (1, True)):
        run_dir = tmp_path / f"ppo_gpis_seed{seed}"
        run_dir.mkdir()
        config = {
            "algo": "ppo",
            "map": "gpis",
            "seed": seed,
            "timesteps_done": 1000,
            "wall_clock_seconds": 60.0,
            "train_layout_seeds": [2**32, 2**63],
            "hyperparams": {"n_envs": 16, "env_kwargs": {"map": "gpis"}},
            "code": {"commit": "0123456789abcdef" * 2 + "01234567", "dirty": dirty},
            "machine": {"cpus": 96, "processor": "a test CPU", "system": "x", "gpu": None},
        }
        (run_dir / "config.yml").write_text(yaml.safe_dump(config))
        run_dirs.append(run_dir)
    # Seed 1 fine-tuned its clone stage's clone: both stages' wall-clock count.
    (run_dirs[1] / "imitation").mkdir()
    (run_dirs[1] / "imitation" / "config.yml").write_text(
        yaml.safe_dump({"wall_clock_seconds": 1500.0})
    )
    page = results_markdown(
        "full", BUDGETS["full"], run_dirs, "| table |\n", "| pooled |\n", "| sampled pooled |\n"
    )
    assert "| 1.0 | 0 |" in page and "| 25.0 + 1.0 = 26.0 | 1 |" in page
    assert "Sampling their probes" in page and "| sampled pooled |" in page
    assert "96 CPU cores (a test CPU), no GPU" in page
    assert "`0123456789ab`, `0123456789ab` (with uncommitted changes)" in page
    assert "[4,294,967,296, 9,223,372,036,854,775,808)" in page
    assert "test layouts 2000000..2000499" in page
    assert "2-core" not in page  # nothing about the machine is a fixed string


def test_a_budget_warm_starts_each_trial_from_its_published_run_when_there_is_one(
    tmp_path: Path,
):
    import dataclasses

    from agents.grid.budgets import BUDGETS
    from agents.grid.pipeline import trials

    published = tmp_path / "models"
    (published / "ppo_gpis_seed0").mkdir(parents=True)
    (published / "ppo_gpis_seed0" / "model.zip").write_bytes(b"weights")
    budget = dataclasses.replace(BUDGETS["demo"], runs=tmp_path / "runs", warm_start_from=published)
    by_name = {trial.name: trial for trial in trials(budget, [0, 1])}
    assert by_name["ppo_gpis_seed0"].init_from == str(published / "ppo_gpis_seed0" / "model.zip")
    assert by_name["ppo_gpis_seed1"].init_from is None  # not published: from scratch
    assert by_name["ppo_none_seed0"].init_from is None
    # The full budget trains the published models themselves, from scratch, with 3 seeds.
    full = BUDGETS["full"]
    assert full.warm_start_from is None and full.seeds == (0, 1, 2)
    assert all(trial.init_from is None for trial in trials(full, list(full.seeds)))


def test_a_sampling_agent_repeats_each_episode_whatever_ran_before(tmp_path: Path):
    from agents.rollout import run_episodes
    from agents.sb3.learned import LearnedAgent
    from tests.recipes import train_with_recipe

    run_dir = train_with_recipe(tmp_path, "none", deterministic_evaluation=False)
    agent = LearnedAgent(run_dir)
    assert agent.deterministic is False  # from the recipe
    env_kwargs = agent.env_kwargs
    alone = run_episodes(agent, [1_000_003], **env_kwargs)
    after_others = run_episodes(agent, [1_000_001, 1_000_002, 1_000_003], **env_kwargs)
    assert after_others[-1] == alone[0]
    assert LearnedAgent(run_dir, deterministic=True).deterministic is True


def test_evaluate_actions_override_the_recipe_and_keep_rows_apart(tmp_path: Path):
    from agents.evaluation.evaluation import evaluate
    from tests.recipes import train_with_recipe

    run_dir = train_with_recipe(tmp_path, "none", deterministic_evaluation=False)
    out = tmp_path / "eval"
    kwargs = {"out": out, "episodes": 2, "gifs": False}
    (sampled,) = evaluate([str(run_dir)], **kwargs)
    (again,) = evaluate([str(run_dir)], actions="sample", **kwargs)  # the recipe's choice
    assert again == sampled
    rows = (out / "episodes.csv").read_text()
    evaluate([str(run_dir)], actions="mode", **kwargs)
    assert (out / "episodes.csv").read_text() != rows  # another fingerprint: run afresh
    with pytest.raises(ValueError, match="actions must be one of"):
        evaluate([str(run_dir)], actions="greedy", **kwargs)


def test_learning_curves_give_an_agents_training_seeds_one_legend_entry(
    trained_runs: dict[str, Path], tmp_path: Path
):
    from agents.evaluation.report import plot_learning_curves

    runs = [
        ("ppo (gpis map)", trained_runs["ppo"]),
        ("ppo (gpis map)", trained_runs["ppo"]),  # a second training seed's curve
        ("recurrent_ppo (none map)", trained_runs["recurrent_ppo"]),
    ]
    legend = plot_learning_curves(tmp_path / "curves.png", runs)
    assert legend == ["ppo (gpis map)", "recurrent_ppo (none map)"]
    assert (tmp_path / "curves.png").stat().st_size > 0


def test_an_agent_trained_with_several_seeds_gets_one_example_gif(
    trained_runs: dict[str, Path], tmp_path: Path
):
    import shutil

    from agents.evaluation.evaluation import evaluate

    second_seed = tmp_path / "ppo_gpis_seed4"
    shutil.copytree(trained_runs["ppo"], second_seed)
    config = yaml.safe_load((second_seed / "config.yml").read_text())
    config["seed"] = 4
    (second_seed / "config.yml").write_text(yaml.safe_dump(config))
    out = tmp_path / "results"
    evaluate(
        [str(trained_runs["ppo"]), str(second_seed), "random"], out=out, episodes=1, gif_steps=2
    )
    assert sorted(p.name for p in (out / "gifs").glob("*.gif")) == [
        "ppo_gpis_map.gif",
        "random.gif",
    ]
    table = (out / "results.md").read_text()
    assert "| ppo (gpis map, seed 3) |" in table and "| ppo (gpis map, seed 4) |" in table


def test_the_probe_trace_counts_waits_revisits_and_lane_change_costs():
    from agents.evaluation.probe_trace import Probe, TracedEpisode, summary

    def probe(lane: int, motions: int, waited: bool = False) -> Probe:
        return Probe(lane, 0, 0, motions, waited)

    episodes = [
        TracedEpisode(1, True, False, (probe(4, 30),)),
        TracedEpisode(2, False, True, (probe(4, 30), probe(9, 60))),  # a tip: not timed out
        # Timed out: lane 4, again lane 4, a wait in it, lane 5, back to lane 4.
        TracedEpisode(
            3,
            False,
            False,
            (probe(4, 40), probe(4, 10), probe(4, 1, waited=True), probe(5, 70), probe(4, 79)),
        ),
    ]
    figures = summary(episodes)
    assert figures["success"] == pytest.approx(1 / 3)
    assert figures["first-probe success"] == pytest.approx(1 / 3)
    assert figures["timed out"] == pytest.approx(1 / 3)
    assert figures["probes per timed-out episode"] == 5
    assert figures["waits (share of their probes)"] == pytest.approx(1 / 5)
    assert figures["probes in a lane already probed (share)"] == pytest.approx(3 / 5)
    assert figures["motions per probe, same lane"] == 10
    assert figures["motions per probe, lane changed"] == pytest.approx((70 + 79) / 2)


def test_the_probe_trace_table_shows_a_dash_where_there_was_nothing_to_count():
    from agents.evaluation.probe_trace import Probe, TracedEpisode, summary, summary_markdown

    # Timed out after two probes in different lanes: no same-lane probe to average.
    episodes = [
        TracedEpisode(1, False, False, (Probe(4, 0, 0, 30, False), Probe(5, 0, 0, 70, False)))
    ]
    table = summary_markdown({"run": summary(episodes)})
    assert "| motions per probe, same lane | - |" in table
    assert "| motions per probe, lane changed | 70 |" in table
    assert "nan" not in table


def test_the_probe_trace_cli_gives_each_run_its_own_column(
    trained_runs: dict[str, Path], tmp_path: Path
):
    # Two runs with the same directory name: each keeps its column, named by its path.
    twin = tmp_path / trained_runs["ppo"].name
    shutil.copytree(trained_runs["ppo"], twin)
    result = run_module(
        "agents.probe_trace", str(trained_runs["ppo"]), str(twin), "--episodes", "2"
    )
    assert "Validation layouts 1000000..1000001" in result.stdout
    assert f"| | {trained_runs['ppo']} | {twin} |" in result.stdout
    assert "| motions per probe, lane changed |" in result.stdout


def test_the_probe_trace_refuses_a_run_of_the_wrist_mode(tmp_path: Path):
    from agents.evaluation.probe_trace import trace

    # The no-map recipe without its action mode: the core's default, the wrist mode.
    from tactile_search import ENV_ID

    recipe = yaml.safe_load((REPO / "agents/hyperparams/ppo.yml").read_text())
    del recipe[ENV_ID]["none"]["env_kwargs"]["action_mode"]
    (tmp_path / "wrist.yml").write_text(yaml.safe_dump(recipe))
    run_module(
        "agents.train",
        *("--map", "none", "--timesteps", "64", "--n-envs", "2", "--no-progress", "--from-scratch"),
        *("--hyperparams", str(tmp_path / "wrist.yml"), "--out", str(tmp_path)),
    )
    with pytest.raises(ValueError, match="trained in the 'wrist' action mode"):
        trace(tmp_path / "ppo_none_seed0", [1_000_000])
