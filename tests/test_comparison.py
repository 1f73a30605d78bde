"""Pooled results and differences between agents (agents/comparison.py): names split into
agent and training seed, the bootstrap over layouts and training seeds, the per-seed test."""

from __future__ import annotations

import numpy as np
import pytest

from agents.evaluation.comparison import (
    MEASURES,
    TASK_MEASURES,
    agent_and_seed,
    agent_results,
    beats_in_every_seed,
    comparison_markdown,
    difference,
    gap_change,
    interval_sources_markdown,
    overlap,
    overlap_markdown,
    pool,
    pooled_measure,
)

LAYOUTS = range(1_000_000, 1_000_200)


def rows_of(name: str, successes: np.ndarray, tips: int = 0) -> list[dict]:
    return [
        {
            "agent": name,
            "map": "gpis",
            "seed": layout,
            "success": bool(s),
            "tips": tips,
            "jar_displacement": 0.001,
            "steps": 120,
            "actions": 4,
        }
        for layout, s in zip(LAYOUTS, successes, strict=True)
    ]


def learned(label: str, rates: list[float], rng: np.random.Generator) -> list[dict]:
    rows = []
    for seed, rate in enumerate(rates):
        rows += rows_of(f"ppo ({label} map, seed {seed})", rng.random(len(LAYOUTS)) < rate)
    return rows


def test_names_split_into_agent_and_training_seed() -> None:
    assert agent_and_seed("ppo (gpis map, seed 12)") == ("ppo (gpis map)", 12)
    assert agent_and_seed("recurrent_ppo (none map, seed 0)") == ("recurrent_ppo (none map)", 0)
    assert agent_and_seed("ppo (gpis map)") == ("ppo (gpis map)", None)
    assert agent_and_seed("gpis_planner") == ("gpis_planner", None)
    assert agent_and_seed("ppo (gpis map, seed 2) [std=0]") == ("ppo (gpis map) [std=0]", 2)


def test_a_clear_difference_has_an_interval_around_it_that_excludes_zero() -> None:
    rng = np.random.default_rng(1)
    rows = learned("gpis", [0.9, 0.85, 0.9], rng) + learned("none", [0.3, 0.35, 0.3], rng)
    results = agent_results(rows)
    diff, low, high = difference(results["ppo (gpis map)"], results["ppo (none map)"], 2000)
    assert low < diff < high and 0.4 < low and high < 0.75
    gpis, none = pool(results["ppo (gpis map)"], 2000), pool(results["ppo (none map)"], 2000)
    assert gpis.training_seeds == (0, 1, 2) and gpis.episodes == 600
    assert beats_in_every_seed(gpis, none) is True
    assert beats_in_every_seed(none, gpis) is False


def test_the_same_agent_differs_from_itself_by_an_interval_around_zero() -> None:
    rng = np.random.default_rng(2)
    rows = learned("gpis", [0.6, 0.6, 0.6], rng)
    results = agent_results(rows)
    diff, low, high = difference(results["ppo (gpis map)"], results["ppo (gpis map)"], 2000)
    assert diff == 0.0 and low <= 0.0 <= high


def test_seeds_that_disagree_widen_the_pooled_interval() -> None:
    steady = agent_results(
        rows_of("ppo (gpis map, seed 0)", np.arange(200) % 2 == 0)
        + rows_of("ppo (gpis map, seed 1)", np.arange(200) % 2 == 1)
    )
    split = agent_results(
        rows_of("ppo (gpis map, seed 0)", np.ones(200))
        + rows_of("ppo (gpis map, seed 1)", np.zeros(200))
    )
    a, b = pool(steady["ppo (gpis map)"], 2000), pool(split["ppo (gpis map)"], 2000)
    assert a.success == b.success == 0.5
    assert b.spread == 1.0 and a.spread == 0.0
    assert (b.success_high - b.success_low) > 2 * (a.success_high - a.success_low)


def test_the_table_compares_the_reference_with_every_other_agent() -> None:
    rng = np.random.default_rng(3)
    rows = learned("gpis", [0.9, 0.9], rng) + rows_of("gpis_planner", rng.random(200) < 0.9)
    text = comparison_markdown(rows, samples=500)
    assert "| ppo (gpis map) | 0, 1 | 400 |" in text
    assert "| gpis_planner | - | 200 |" in text
    assert "| ppo (gpis map) minus |" in text and "| gpis_planner | " in text
    with pytest.raises(ValueError, match="reference"):
        comparison_markdown(rows, reference="nobody", samples=10)


def test_layouts_not_met_by_every_seed_are_left_out() -> None:
    rows = (
        rows_of("ppo (gpis map, seed 0)", np.ones(200))
        + rows_of("ppo (gpis map, seed 1)", np.ones(200))[:150]
    )
    (results,) = agent_results(rows).values()
    assert results.success.shape == (2, 150)


def test_the_seeded_names_evaluate_writes_are_read_back() -> None:
    from agents.evaluation.agent_specs import seeded_name

    assert agent_and_seed(seeded_name("recurrent_ppo", "none", 2)) == (
        "recurrent_ppo (none map)",
        2,
    )


def test_a_failure_without_a_tip_counts_as_a_time_out() -> None:
    # An episode ends at success, at a tip, or at the time limit: of four layouts, one
    # success, one failure ended by a tip, two failures that ran out of time.
    rows = rows_of("ppo (gpis map, seed 0)", np.array([1, 0, 0, 0] * 50))
    for row in rows[1::4]:
        row["tips"] = 1
    pooled = pool(agent_results(rows)["ppo (gpis map)"], 200)
    assert pooled.success == 0.25 and pooled.tip_rate == 0.25 and pooled.timeout_rate == 0.5
    assert "| 25.0% | 50.0% | 1.0 | 30.0 |" in comparison_markdown(rows, samples=200)


def test_the_overlap_counts_who_succeeds_where_seed_by_seed_and_layout_by_layout() -> None:
    n = len(LAYOUTS)
    seed0 = np.arange(n) % 2 == 0  # the even layouts
    seed1 = np.arange(n) % 4 == 0  # every fourth layout
    planner = np.arange(n) < n // 2  # the first half
    rows = (
        rows_of("ppo (gpis map, seed 0)", seed0)
        + rows_of("ppo (gpis map, seed 1)", seed1)
        + rows_of("gpis_planner", planner)
    )
    o = overlap(agent_results(rows), "ppo (gpis map)", "gpis_planner")
    agent = np.stack([seed0, seed1])
    assert o.pairs == 2 * n
    assert o.both == (agent & planner).sum()
    assert o.a_alone == (agent & ~planner).sum()
    assert o.b_alone == (~agent & planner).sum()
    assert o.both + o.a_alone + o.b_alone + o.neither == o.pairs
    assert o.a_always_fails == n // 2  # the odd layouts
    assert o.of_those_b_fails == n // 4  # the odd layouts of the second half
    assert f"{o.a_always_fails} of the {n} layouts" in overlap_markdown(
        rows, "ppo (gpis map)", "gpis_planner"
    )
    with pytest.raises(ValueError, match="agents are"):
        overlap(agent_results(rows), "ppo (gpis map)", "oracle")


def task_rows(name: str, seed: int, wrong: np.ndarray, area_mm: np.ndarray) -> list[dict]:
    return [
        {
            **row,
            "agent": f"ppo ({name} map, seed {seed})",
            "wrong_claim": bool(w),
            "map_score_area": float(a),
            "map_score_mm": float(a) / 2,
        }
        for row, w, a in zip(rows_of("x", np.zeros(len(LAYOUTS))), wrong, area_mm, strict=True)
    ]


def test_a_task_measure_is_differenced_with_an_interval_like_success() -> None:
    rng = np.random.default_rng(3)
    n = len(LAYOUTS)
    rows = []
    for seed in range(3):
        rows += task_rows("gpis", seed, rng.random(n) < 0.1, 20 + rng.normal(0, 2, n))
        rows += task_rows("occupancy", seed, rng.random(n) < 0.4, 30 + rng.normal(0, 2, n))
    results = agent_results(rows)
    gpis, occupancy = results["ppo (gpis map)"], results["ppo (occupancy map)"]
    diff, low, high = difference(gpis, occupancy, 2000, "wrong_claims")
    assert low < diff < high < 0
    diff, low, high = difference(gpis, occupancy, 2000, "map_score_area")
    assert -12 < low < diff < high < -8
    assert pooled_measure(gpis, "map_score_mm", 2000)[0] == pytest.approx(gpis.map_score_mm.mean())


def test_the_identify_table_adds_wrong_claims_and_the_map_table_its_scores() -> None:
    rng = np.random.default_rng(4)
    n = len(LAYOUTS)
    rows = task_rows("gpis", 0, rng.random(n) < 0.1, np.full(n, 20.0))
    rows += task_rows("occupancy", 0, rng.random(n) < 0.4, np.full(n, 30.0))
    search = comparison_markdown(rows, samples=200)
    identify = comparison_markdown(rows, samples=200, task="identify")
    mapping = comparison_markdown(rows, samples=200, task="map")
    assert "wrong claims" not in search and "map distance" not in search
    assert "wrong claims, difference" in identify and "map distance" not in identify
    assert "| ppo (occupancy map) | -10.0 | [-10.0, -10.0] |" in mapping
    # Each seed's figures of the task's measures: the map distance with its interval over
    # layouts, the identify task's wrong claims beside its success.
    assert "| ppo (gpis map) | 0 | 20.0 | [20.0, 20.0] | 10.0 | [10.0, 10.0] |" in mapping
    assert "| training seed | success | 95 % CI (Wilson) | wrong claims |" in identify
    assert "map distance at the end (mm), difference" in mapping
    with pytest.raises(ValueError, match="task must be one of"):
        comparison_markdown(rows, task="sorting")
    with pytest.raises(ValueError, match="measure must be one of"):
        agent_results(rows)["ppo (gpis map)"].measure("reward")


def test_a_gap_that_widens_on_the_dense_tier_has_an_interval_above_zero() -> None:
    rng = np.random.default_rng(7)
    default = agent_results(learned("gpis", [0.9] * 3, rng) + learned("none", [0.7] * 3, rng))
    dense = agent_results(learned("gpis", [0.8] * 3, rng) + learned("none", [0.3] * 3, rng))
    change, low, high = gap_change(
        dense["ppo (gpis map)"], dense["ppo (none map)"],
        default["ppo (gpis map)"], default["ppo (none map)"], samples=2000,
    )  # fmt: skip
    assert 0 < low < change < high  # 0.5 - 0.2 = 0.3, give or take the draws
    assert change == pytest.approx(0.3, abs=0.1)
    same, low, high = gap_change(
        default["ppo (gpis map)"], default["ppo (none map)"],
        default["ppo (gpis map)"], default["ppo (none map)"], samples=2000,
    )  # fmt: skip
    assert same == 0.0 and low < 0 < high


def test_a_gap_change_needs_the_same_models_on_both_tiers() -> None:
    rng = np.random.default_rng(8)
    three = agent_results(learned("gpis", [0.9] * 3, rng) + learned("none", [0.7] * 3, rng))
    two = agent_results(learned("gpis", [0.9] * 2, rng) + learned("none", [0.7] * 2, rng))
    with pytest.raises(ValueError, match="other training seeds"):
        gap_change(
            two["ppo (gpis map)"], two["ppo (none map)"],
            three["ppo (gpis map)"], three["ppo (none map)"], samples=100,
        )  # fmt: skip


def test_a_wrong_claim_is_no_time_out() -> None:
    rows = task_rows("gpis", 0, np.array([True, False] * 100), np.full(200, 20.0))
    results = agent_results(rows)["ppo (gpis map)"]  # no success, no tip in these rows
    assert results.wrong_claims.mean() == 0.5 and results.timeouts.mean() == 0.5


def test_every_task_of_the_core_has_the_measures_that_decide_it() -> None:
    from tactile_search.benchmark.summary_table import TASKS

    assert set(TASK_MEASURES) == set(TASKS)
    assert all(set(names) <= set(MEASURES) for names in TASK_MEASURES.values())


def test_the_map_task_which_has_no_success_shows_none() -> None:
    rng = np.random.default_rng(5)
    n = len(LAYOUTS)
    rows = task_rows("gpis", 0, np.zeros(n), 20 + rng.normal(0, 1, n))
    rows += task_rows("occupancy", 0, np.zeros(n), 22 + rng.normal(0, 1, n))
    mapping = comparison_markdown(rows, samples=200, task="map")
    assert "success" not in mapping and "timed out" not in mapping
    assert "| ppo (gpis map) | 0 | 200 | 0.0% | 1.0 | 30.0 |" in mapping


def test_the_layouts_alone_interval_leaves_out_what_the_seeds_disagree_on() -> None:
    # Two GPIS seeds far apart (0.9 and 0.5) against two occupancy seeds alike (0.7): the
    # difference's interval over layouts and seeds is wide, the one over layouts alone narrow.
    n = len(LAYOUTS)
    rows = (
        rows_of("ppo (gpis map, seed 0)", np.arange(n) % 10 < 9)
        + rows_of("ppo (gpis map, seed 1)", np.arange(n) % 10 < 5)
        + rows_of("ppo (occupancy map, seed 0)", np.arange(n) % 10 < 7)
        + rows_of("ppo (occupancy map, seed 1)", np.arange(n) % 10 < 7)
        + rows_of("gpis_planner", np.ones(n))
    )
    text = interval_sources_markdown(rows, "ppo (gpis map)", samples=2000)
    (line,) = [row for row in text.splitlines() if row.startswith("| ppo (occupancy map) |")]
    full, fixed = (cell.strip("[] |").split(", ") for cell in line.split(" | ")[3:5])
    assert float(full[1]) - float(full[0]) > 2 * (float(fixed[1]) - float(fixed[0]))
    assert "gpis_planner" not in text  # one run: no seeds to hold
    with pytest.raises(ValueError, match="reference must be one of"):
        interval_sources_markdown(rows, "nobody")
