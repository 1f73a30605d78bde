"""The map task through its registered id (``tactile_search/MapByTouch-v0``): it passes
gymnasium's and SB3's checkers, its info scores the reconstruction the same whatever map
the agent observes, its reward is the score's gain with the search task's costs, it ends
only by the budget or a tip, and the benchmark and its command line report its scores."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import tactile_search

MAP = "tactile_search/MapByTouch-v0"
SCORES = ("map_score_mm", "map_score_iou", "map_score_area", "reward_map")


@pytest.mark.parametrize("action_mode", ["wrist", "probe"])
def test_the_map_id_passes_the_checkers(action_mode: str) -> None:
    assert MAP in tactile_search.ENV_IDS
    env = gym.make(MAP, action_mode=action_mode)
    assert env.unwrapped.config.task == "map"
    check_env(env.unwrapped, skip_render_check=True)
    sb3_checker = pytest.importorskip("stable_baselines3.common.env_checker")
    sb3_checker.check_env(env.unwrapped, warn=True)


def probe_scores(map_mode: str) -> list[tuple[float, ...]]:
    env = gym.make(MAP, map=map_mode, action_mode="probe", max_steps=80)
    env.reset(seed=1_000_004)
    rng = np.random.default_rng(0)
    out = []
    for _ in range(6):
        _, reward, terminated, truncated, info = env.step(rng.integers(0, [29, 10, 9]))
        out.append(tuple(info[key] for key in SCORES))
        # The reward is the score's gain with the search task's costs (no step cost here).
        costs = info["reward_displacement"] + info["reward_tip"] + info["reward_step"]
        assert reward == pytest.approx(info["reward_map"] + costs, abs=1e-12)
        assert not info["success"]
        if terminated or truncated:
            break
    return out


def test_the_score_is_the_same_whatever_map_the_agent_observes() -> None:
    gpis = probe_scores("gpis")
    assert all(mm > 0 for mm, *_ in gpis)
    assert probe_scores("occupancy") == gpis
    assert probe_scores("none") == gpis


def test_the_budget_ends_the_episode_and_the_area_spans_it() -> None:
    env = gym.make(MAP, max_steps=12)
    env.reset(seed=1_000_001)
    mm = []
    for _ in range(12):
        _, _, terminated, truncated, info = env.step(np.array([0.0, 1.0, 0.0], np.float32))
        mm.append(info["map_score_mm"])
        if terminated:
            break
    assert truncated or info["tipped"]
    if truncated:
        assert info["map_score_area"] == pytest.approx(np.mean(mm), rel=1e-12)


def test_the_benchmark_reports_the_map_scores() -> None:
    from tactile_search.benchmark import evaluate
    from tactile_search.benchmark.__main__ import summary_line
    from tests.benchmark_policies import RandomProbes

    result = evaluate(
        RandomProbes(), episodes=2, num_envs=2, progress=False, env_id=MAP, action_mode="probe",
        max_steps=40,
    )  # fmt: skip
    assert result.task == "map"
    assert all(row["map_score_mm"] > 0 and row["map_score_area"] > 0 for row in result.rows)
    summary = result.summary
    assert summary.map_score_mm == pytest.approx(np.mean([r["map_score_mm"] for r in result.rows]))
    line = summary_line(result)
    assert "outline distance" in line and "area" in line and "success" not in line


def test_render_shows_the_reconstruction_the_score_is_measured_on() -> None:
    search = gym.make(tactile_search.ENV_ID, render_mode="rgb_array")
    mapping = gym.make(MAP, render_mode="rgb_array")
    search.reset(seed=1_000_002)
    mapping.reset(seed=1_000_002)
    state = mapping.unwrapped.render_state()
    assert state["score_mean"].shape == (40, 80)
    assert search.unwrapped.render_state()["score_mean"] is None
    # One more panel than the search task's frame: the reconstruction beside the map.
    wide, narrow = mapping.render(), search.render()
    assert wide.shape[0] == narrow.shape[0] and wide.shape[1] > narrow.shape[1]
