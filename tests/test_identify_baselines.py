"""The identify task's scripted baselines: the identify planner and random_identify read only
the observation and the static configuration, the planner claims the square jar on
hand-checked validation layouts and judges shapes from contacts as a circle and a square give
them, random_identify claims only while touching, every scripted agent is registered for the
tasks it plays, their rows are the same side by side as one after another,
``agents.evaluate --env-id`` evaluates an identify id (example GIFs included,
a claim replayed), and the task standings write their tables."""

from __future__ import annotations

import csv
import json
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np
import pytest

from agents.evaluate import main as evaluate_main
from agents.evaluation.agent_specs import make_agent
from agents.evaluation.evaluation import env_id_settings
from agents.evaluation.gifs import record_gif
from agents.rollout import evaluate_agent, run_episodes
from agents.scripted import (
    SCRIPTED_AGENTS,
    SCRIPTED_TASKS,
    IdentifyPlanner,
    RandomIdentifyAgent,
    scripted_agents_for,
)
from agents.scripted.belief_identify import pair_evidence, shape_verdict
from benchmarks import task_standings
from tactile_search import ENV_IDS, CupboardSearchEnv
from tactile_search.envs.observation import PROPRIO
from tests.test_scripted_agents import NoGroundTruthEnv, StaticConfigOnly

IDENTIFY = "tactile_search/IdentifyByTouch-v0"
# Validation layouts where the planner's first touch of the square jar is a corner on the
# finger's side and it claims it at once (checked by eye in a render of the claim: the
# ring around the square jar, the finger on its corner).
HAND_CHECKED = [1_000_019, 1_000_030]
ROUND_RADII = (0.0225, 0.0275)


def identify_env(cls: type[CupboardSearchEnv] = CupboardSearchEnv) -> CupboardSearchEnv:
    return cls(**gym.spec(IDENTIFY).kwargs, action_mode="probe")


def play(agent: Any, env: CupboardSearchEnv, seed: int, handed: Any = None) -> list[tuple]:
    """An episode of ``agent``, handed ``handed`` (default: the env) at its reset and only
    the observation after; the (observation, action, info) of every step."""
    observation, info = env.reset(seed=seed)
    agent.reset(handed if handed is not None else env, observation, {})
    steps = []
    for _ in range(env.config.max_steps):
        action = agent.act(observation)
        assert action.dtype == np.int64 and env.action_space.contains(action)
        before = observation
        observation, _, terminated, truncated, info = env.step(action)
        steps.append((before, action, info))
        if terminated or truncated:
            break
    return steps


@pytest.mark.parametrize("seed", HAND_CHECKED)
def test_the_identify_planner_claims_the_square_jar_without_ground_truth(seed: int) -> None:
    steps = play(IdentifyPlanner(), identify_env(NoGroundTruthEnv), seed)
    _, action, info = steps[-1]
    assert action[3] == 1 and info["success"] and not info["wrong_claim"]
    env = identify_env()
    env.reset(seed=seed)
    jars = env.render_state()["jars"]
    assert jars[info["claimed_jar"]]["shape"] == "square"


def test_the_identify_agents_see_only_the_observation_and_the_static_configuration() -> None:
    env = identify_env()
    steps = play(IdentifyPlanner(), env, HAND_CHECKED[0], handed=StaticConfigOnly(env))
    assert steps[-1][2]["success"]
    steps = play(RandomIdentifyAgent(3), env, 1_000_002, handed=StaticConfigOnly(env))
    assert len(steps) > 1


def test_random_identify_claims_only_while_touching_and_is_seeded() -> None:
    env = identify_env()
    claims = 0
    for seed in range(1_000_000, 1_000_006):
        steps = play(RandomIdentifyAgent(seed), env, seed)
        for observation, action, _ in steps:
            if action[3] == 1:
                claims += 1
                assert observation["proprio"][PROPRIO["in_contact"]] == 1.0
        again = play(RandomIdentifyAgent(seed), env, seed)
        assert [a.tolist() for _, a, _ in again] == [a.tolist() for _, a, _ in steps]
    assert claims > 0


def test_identify_agents_refuse_the_search_task() -> None:
    env = CupboardSearchEnv(action_mode="probe")
    observation, info = env.reset(seed=0)
    for agent in (IdentifyPlanner(), RandomIdentifyAgent(0)):
        with pytest.raises(ValueError, match="identify"):
            agent.reset(env, observation, info)


def circle_contact(angle: float, radius: float = 0.025) -> tuple[np.ndarray, np.ndarray]:
    normal = np.array([np.cos(angle), np.sin(angle)])
    return np.array([0.1, 0.2]) + radius * normal, normal


def test_contacts_on_a_circle_are_curved_and_on_a_face_flat() -> None:
    (p1, n1), (p2, n2) = circle_contact(-0.2), circle_contact(0.2)  # 10 mm apart
    assert pair_evidence(p1, n1, p2, n2, ROUND_RADII) == "curved"
    face = np.array([0.0, -1.0])
    assert pair_evidence(np.r_[0.0, 0.0], face, np.r_[0.01, 0.0], face, ROUND_RADII) == "flat"
    # Adjacent faces of a square, where no round jar fits both contacts.
    side = np.array([1.0, 0.0])
    assert pair_evidence(np.r_[0.0, 0.0], face, np.r_[0.02, 0.01], side, ROUND_RADII) == "flat"
    # Too close together to tell.
    assert pair_evidence(p1, n1, p1 + 0.001, n1, ROUND_RADII) is None


def test_a_corner_on_the_fingers_side_says_square_and_a_tangent_touch_round() -> None:
    (p, n) = circle_contact(0.0)
    assert shape_verdict([p], [n], [0.3], ROUND_RADII) == "square"
    assert shape_verdict([p], [n], [0.01], ROUND_RADII) == "round"
    assert shape_verdict([p], [n], [None], ROUND_RADII) == "unknown"
    (q, m) = circle_contact(0.4)
    assert shape_verdict([p, q], [n, m], [None, None], ROUND_RADII) == "round"


def test_every_scripted_agent_is_registered_with_the_tasks_it_plays() -> None:
    assert set(SCRIPTED_TASKS) == set(SCRIPTED_AGENTS)
    assert scripted_agents_for("search") == ["random", "oracle", "gpis_probe_planner"]
    assert scripted_agents_for("identify") == ["oracle", "random_identify", "identify_planner"]
    assert task_standings.tier_agents(IDENTIFY) == ["random_identify", "identify_planner", "oracle"]
    # The standings run the ids of a task some baseline plays: the search and identify tiers.
    tasks = {env_id: gym.spec(env_id).kwargs.get("task", "search") for env_id in ENV_IDS}
    assert task_standings.standing_ids() == [
        env_id for env_id in ENV_IDS if tasks[env_id] in ("search", "identify")
    ]


def rows(path: Path) -> list[dict[str, str]]:
    with (path / "episodes.csv").open() as f:
        return list(csv.DictReader(f))


def test_the_evaluate_cli_runs_an_identify_id_with_its_tasks_agents(tmp_path: Path) -> None:
    evaluate_main(["--env-id", IDENTIFY, "--episodes", "2", "--no-gifs", "--out", str(tmp_path)])
    agents = {row["agent"] for row in rows(tmp_path)}
    assert agents == {f"{a} [IdentifyByTouch-v0]" for a in scripted_agents_for("identify")}
    assert "IdentifyByTouch-v0" in (tmp_path / "results.md").read_text()
    assert all(row["wrong_claim"] in ("True", "False") for row in rows(tmp_path))


def test_an_id_that_is_not_registered_is_refused() -> None:
    with pytest.raises(ValueError, match="env_id must be one of"):
        env_id_settings("tactile_search/Nothing-v0")
    with pytest.raises(SystemExit):
        evaluate_main(["--env-id", "tactile_search/Nothing-v0"])
    assert env_id_settings(IDENTIFY) == gym.spec(IDENTIFY).kwargs


def test_an_identify_gif_replays_the_probes_and_the_claim(tmp_path: Path) -> None:
    # Random probes on a layout where the second one claims a jar it touches.
    kwargs = {**gym.spec(IDENTIFY).kwargs, **RandomIdentifyAgent.env_kwargs}
    record_gif(tmp_path / "claim.gif", RandomIdentifyAgent(1_000_001), kwargs, 1_000_001)
    assert (tmp_path / "claim.gif").stat().st_size > 0


def test_the_standings_write_the_table_and_the_headroom(tmp_path: Path) -> None:
    result = task_standings.main(["--episodes", "2", "--env-ids", IDENTIFY, "--out", str(tmp_path)])
    assert [r["agent"] for r in result["standings"]] == task_standings.tier_agents(IDENTIFY)
    (gap,) = result["headroom"]
    assert gap["best_baseline"] != "oracle" and gap["env_id"] == IDENTIFY
    kept = json.loads((tmp_path / "standings.json").read_text())
    assert kept["standings"] == json.loads(json.dumps(result["standings"]))
    table = (tmp_path / "standings.md").read_text()
    assert "| IdentifyByTouch-v0 | identify_planner | probe |" in table


@pytest.mark.parametrize("spec", ["random_identify", "identify_planner"])
def test_an_identify_agents_rows_are_the_same_side_by_side_as_one_after_another(
    spec: str,
) -> None:
    seeds = list(range(1_000_000, 1_000_004))
    agent, env_kwargs = make_agent(spec)
    env_kwargs = {**env_kwargs, **gym.spec(IDENTIFY).kwargs}
    sequential = run_episodes(agent, seeds, **env_kwargs)
    assert evaluate_agent(agent, seeds, num_envs=2, **env_kwargs) == sequential
