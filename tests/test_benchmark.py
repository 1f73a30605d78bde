"""``tactile_search.benchmark``: the standard evaluation of any policy, on the vector env,
with the splits from ``seed_ranges`` and the project's statistics; and its command line."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from tactile_search.benchmark import ROW_KEYS, evaluate
from tactile_search.benchmark.__main__ import main
from tactile_search.seed_ranges import VALIDATION, held_out_seeds
from tests.benchmark_policies import RandomProbes, Weaving, forward

ROOT = Path(__file__).resolve().parents[1]


def test_a_scripted_policys_rows_do_not_depend_on_how_many_run_side_by_side() -> None:
    one = evaluate(Weaving(), episodes=7, map="none", num_envs=1, progress=False)
    three = evaluate(Weaving(), episodes=7, map="none", num_envs=3, progress=False)
    assert one.rows == three.rows
    assert [row["seed"] for row in one.rows] == held_out_seeds("validation", 7)
    assert all(tuple(row) == ROW_KEYS for row in one.rows)
    summary = one.summary
    assert summary.agent == "weaving" and summary.episodes == 7
    assert summary.successes == sum(row["success"] for row in one.rows)
    assert summary.success_low <= summary.success_rate <= summary.success_high


def test_the_rows_equal_the_agents_own_sequential_loop() -> None:
    import numpy as np

    from agents.rollout import run_episodes

    class Agent:
        name = "weaving"

        def reset(self, env: object, observation: dict, info: dict) -> None:
            self.policy = Weaving()

        def act(self, observation: dict) -> np.ndarray:
            return self.policy(observation)

    seeds = held_out_seeds("validation", 5)
    rows = evaluate(Weaving(), episodes=5, map="occupancy", num_envs=2, progress=False).rows
    assert rows == run_episodes(Agent(), seeds, map="occupancy")


def test_a_random_probe_policy_runs_in_the_probe_mode() -> None:
    result = evaluate(
        RandomProbes(), episodes=4, map="none", action_mode="probe", num_envs=3, progress=False
    )
    assert len(result.rows) == 4 and all(row["actions"] <= row["steps"] for row in result.rows)


def test_the_test_split_is_read_only_by_a_final_evaluation() -> None:
    with pytest.raises(ValueError, match="held out for the final result"):
        evaluate(forward, split="test", episodes=2, map="none", progress=False)
    result = evaluate(forward, split="test", episodes=2, final=True, map="none", progress=False)
    assert [row["seed"] for row in result.rows] == held_out_seeds("test", 2)
    with pytest.raises(ValueError, match="split must be one of"):
        evaluate(forward, split="training", episodes=2, progress=False)
    with pytest.raises(TypeError, match="policy must be callable"):
        evaluate("forward", episodes=2, progress=False)  # type: ignore[arg-type]


def test_the_command_line_writes_the_rows_and_summary(tmp_path: Path) -> None:
    out = tmp_path / "result.json"
    rows = tmp_path / "rows.csv"
    result = main(
        ["--policy", "tests.benchmark_policies:Weaving", "--episodes", "3", "--env", "map=none",
         "--json", str(out), "--csv", str(rows), "--no-progress"]
    )  # fmt: skip
    written = json.loads(out.read_text())
    assert written["summary"]["episodes"] == 3 and written["summary"]["agent"] == "weaving"
    assert [row["seed"] for row in written["rows"]] == [VALIDATION[0] + i for i in range(3)]
    assert rows.read_text().splitlines()[0] == ",".join(ROW_KEYS)
    assert [row["success"] for row in written["rows"]] == [r["success"] for r in result.rows]


def test_the_command_line_runs_as_a_module_and_refuses_bad_policies() -> None:
    command = [sys.executable, "-m", "tactile_search.benchmark", "--episodes", "2", "--no-progress",
               "--env", "map=none"]  # fmt: skip
    ok = subprocess.run(
        [*command, "--policy", "tests.benchmark_policies:forward"],
        capture_output=True, text=True, cwd=ROOT,
    )  # fmt: skip
    assert ok.returncode == 0, ok.stderr
    assert "forward on 2 validation layouts (none map): success" in ok.stdout
    bad = subprocess.run(
        [*command, "--policy", "tests.benchmark_policies"], capture_output=True, text=True,
        cwd=ROOT,
    )  # fmt: skip
    assert bad.returncode == 2 and "module:callable" in bad.stderr


def test_the_command_line_evaluates_an_sb3_model_zip(tmp_path: Path) -> None:
    sb3 = pytest.importorskip("stable_baselines3")
    torch = pytest.importorskip("torch")
    from tactile_search import CupboardSearchEnv

    torch.set_num_threads(1)
    model = sb3.PPO("MultiInputPolicy", CupboardSearchEnv(map="none"), n_steps=16, seed=0)
    path = tmp_path / "model.zip"
    model.save(path)
    result = main(["--policy", str(path), "--episodes", "2", "--env", "map=none", "--no-progress"])
    assert result.summary.episodes == 2 and result.summary.agent.startswith("ppo (")


@pytest.mark.parametrize(
    "spec",
    [
        "random",
        "gpis_probe_planner",
        "oracle",
        "docs/results/ablations_speed/runs/ppo_gpis_seed0",
    ],
)
def test_the_agents_evaluation_through_the_runner_gives_the_sequential_rows(spec: str) -> None:
    """The project's own evaluation runs on the benchmark runner: every agent (scripted,
    and a published model sampling its probes) gives the rows of one episode after another
    in one env, on two slots side by side."""
    if spec.startswith("docs/"):
        pytest.importorskip("stable_baselines3")
    from agents.evaluation.agent_specs import make_agent
    from agents.rollout import evaluate_agent, run_episodes

    seeds = held_out_seeds("validation", 5)
    agent, env_kwargs = make_agent(str(ROOT / spec) if spec.startswith("docs/") else spec)
    sequential = run_episodes(agent, seeds, **env_kwargs)
    streamed: list[dict] = []
    rows = evaluate_agent(agent, seeds, on_episode=streamed.append, num_envs=2, **env_kwargs)
    assert rows == sequential
    assert sorted(streamed, key=lambda row: row["seed"]) == sequential
