"""A task's figure (agents.evaluation.curves): success within k motions rises with k to the
agent's success, inside its bootstrap band; the map task's figure gives its scores; each
task's figure is written."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("matplotlib")

from agents.evaluation.comparison import agent_results
from agents.evaluation.curves import map_score_curve, plot_curves, success_curve
from tactile_search.benchmark.map_curve import MAP_CURVE_POINTS

LAYOUTS = range(1_000_000, 1_000_100)


def rows(rng: np.random.Generator, rate: float, seeds: int = 3) -> list[dict]:
    return [
        {
            "agent": f"ppo (gpis map, seed {seed})",
            "map": "gpis",
            "seed": layout,
            "success": bool(rng.random() < rate),
            "tips": 0,
            "jar_displacement": 0.0,
            "steps": int(rng.integers(20, 300)),
            "actions": 4,
            "wrong_claim": False,
            "map_score_area": float(rng.normal(20, 2)),
            "map_score_mm": float(rng.normal(10, 2)),
            "map_score_curve": " ".join(
                repr(float(v)) for v in np.sort(rng.normal(20, 3, MAP_CURVE_POINTS))[::-1]
            ),
        }
        for seed in range(seeds)
        for layout in LAYOUTS
    ]


def test_success_within_k_motions_rises_to_the_agents_success_inside_its_band() -> None:
    results = agent_results(rows(np.random.default_rng(0), 0.6))["ppo (gpis map)"]
    budgets = np.linspace(0, 300, 31)
    mean, low, high = success_curve(results, budgets, samples=500)
    assert mean[0] == 0.0 and np.all(np.diff(mean) >= 0)
    assert mean[-1] == pytest.approx(results.success.mean())
    assert np.all(low <= mean + 1e-12) and np.all(mean <= high + 1e-12)
    assert high[-1] - low[-1] > 0.02  # an interval, not a point


@pytest.mark.parametrize("task", ["search", "identify", "map"])
def test_each_tasks_figure_is_written(tmp_path: Path, task: str) -> None:
    path = tmp_path / f"{task}.png"
    plot_curves(path, rows(np.random.default_rng(1), 0.5), task, samples=200)
    assert path.read_bytes().startswith(b"\x89PNG")


def test_a_figure_of_no_rows_or_an_unknown_task_is_refused(tmp_path: Path) -> None:
    with pytest.raises(ValueError, match="at least one agent"):
        plot_curves(tmp_path / "x.png", [], "search")
    with pytest.raises(ValueError, match="task must be one of"):
        plot_curves(tmp_path / "x.png", rows(np.random.default_rng(2), 0.5), "sorting")


def test_the_map_tasks_curve_is_pooled_point_by_point_inside_its_band() -> None:
    results = agent_results(rows(np.random.default_rng(5), 0.0))["ppo (gpis map)"]
    fractions, mean, low, high = map_score_curve(results, samples=300)
    assert fractions[0] == 0.0 and fractions[-1] == 1.0 and len(mean) == MAP_CURVE_POINTS
    assert mean == pytest.approx(results.map_curves.mean(axis=(0, 1)))
    assert np.all(low <= mean + 1e-12) and np.all(mean <= high + 1e-12)


def test_rows_without_a_map_curve_give_no_map_figure() -> None:
    plain = [{**row, "map_score_curve": ""} for row in rows(np.random.default_rng(6), 0.5)]
    results = agent_results(plain)["ppo (gpis map)"]
    assert results.map_curves is None
    with pytest.raises(ValueError, match="no map score curve"):
        map_score_curve(results)
