"""The map task's outline distance against the motions (tactile_search.benchmark.map_curve):
read at evenly spaced budgets as a step function of the steps' motions; a map episode's row
carries it from its first distance to its last, other tasks' rows carry none."""

from __future__ import annotations

import numpy as np
import pytest

from tactile_search.benchmark import evaluate
from tactile_search.benchmark.map_curve import MAP_CURVE_POINTS, MapScoreTrace, parse_map_curve


def test_the_curve_holds_the_distance_of_the_last_step_within_each_budget() -> None:
    trace = MapScoreTrace({"map_score_mm": 30.0})
    trace.step({"steps": 50, "map_score_mm": 20.0})
    trace.step({"steps": 100, "map_score_mm": 10.0})  # the episode ends early, at 100 of 200
    curve = parse_map_curve(trace.curve(200))
    budgets = np.linspace(0, 200, MAP_CURVE_POINTS)
    assert list(curve) == [30.0 if b < 50 else 20.0 if b < 100 else 10.0 for b in budgets]


def test_a_curve_of_another_length_is_refused() -> None:
    with pytest.raises(ValueError, match=f"has {MAP_CURVE_POINTS} values, got 2"):
        parse_map_curve("1.0 2.0")
    with pytest.raises(ValueError, match="got 0"):
        parse_map_curve("")


class RandomProbe:
    """A probe drawn at random each step (any task's action space)."""

    def __init__(self) -> None:
        self.rng = np.random.default_rng(0)

    def reset(self, observation: dict, info: dict) -> None:
        self.rng = np.random.default_rng(int(info.get("seed", 0)))

    def __call__(self, observation: dict) -> np.ndarray:
        return np.array([self.rng.integers(0, 3), self.rng.integers(0, 2), 0])


def test_a_map_episodes_row_carries_its_curve_from_first_to_last_distance() -> None:
    result = evaluate(
        RandomProbe(), episodes=2, num_envs=1, progress=False,
        env_id="tactile_search/MapByTouch-v0", action_mode="probe",
    )  # fmt: skip
    for row in result.rows:
        curve = parse_map_curve(row["map_score_curve"])
        assert curve[-1] == pytest.approx(row["map_score_mm"])
        assert np.all(np.isfinite(curve)) and np.all(curve > 0)
    search = evaluate(RandomProbe(), episodes=1, num_envs=1, progress=False, action_mode="probe")
    assert search.rows[0]["map_score_curve"] == ""
