"""An evaluation under changed environment settings (``agents.evaluate --env-settings``,
``evaluate(env_settings=...)``): the settings reach every agent's environment over its own,
the agents' names say so, and their rows are kept apart from the unchanged ones."""

from __future__ import annotations

import csv
from pathlib import Path

import pytest

from agents.command_args import settings_label
from agents.evaluate import main as evaluate_main
from agents.evaluation.comparison import agent_and_seed
from agents.evaluation.evaluation import checked_env_settings, evaluate, evaluated_task

KWARGS = {"episodes": 2, "gifs": False}


def rows(path: Path) -> list[dict[str, str]]:
    with (path / "episodes.csv").open() as f:
        return list(csv.DictReader(f))


def test_the_settings_reach_the_environment_and_name_the_agent(tmp_path: Path) -> None:
    (plain,) = evaluate(["random"], out=tmp_path, **KWARGS)
    (short,) = evaluate(["random"], out=tmp_path, env_settings={"max_steps": 3}, **KWARGS)
    assert plain.agent == "random" and short.agent == "random [max_steps=3]"
    by_agent: dict[str, list[dict[str, str]]] = {}
    for row in rows(tmp_path):
        by_agent.setdefault(row["agent"], []).append(row)
    # Only the second evaluation's rows are kept (another fingerprint), each at most 3 steps.
    assert set(by_agent) == {"random [max_steps=3]"}
    assert all(int(row["steps"]) <= 3 for row in by_agent["random [max_steps=3]"])
    assert max(int(row["steps"]) for row in by_agent["random [max_steps=3]"]) == 3


def test_the_command_line_reads_the_values_as_yaml(tmp_path: Path) -> None:
    settings = ["--env-settings", "max_steps=2", "fast_free_motion=true"]
    evaluate_main(
        ["--scripted", "random", "--episodes", "1", "--no-gifs", "--out", str(tmp_path), *settings]
    )
    (row,) = rows(tmp_path)
    assert row["agent"] == "random [fast_free_motion=true, max_steps=2]"
    assert int(row["steps"]) <= 2


def test_a_learned_agents_seed_is_still_read_from_its_name() -> None:
    name = "ppo (gpis map, seed 1) [std=0] [fast_free_motion=true]"
    assert agent_and_seed(name) == ("ppo (gpis map) [std=0] [fast_free_motion=true]", 1)


@pytest.mark.parametrize(
    ("settings", "message"),
    [
        ({"fast_free_motions": True}, "'fast_free_motions' is not a setting"),
        ({"map": "none"}, "may not change 'map'"),
        ({"action_mode": "wrist"}, "may not change 'action_mode'"),
    ],
)
def test_an_unknown_setting_or_the_agents_own_mode_is_refused(
    settings: dict[str, object], message: str
) -> None:
    with pytest.raises(ValueError, match=message):
        checked_env_settings(settings)


def test_the_label_sorts_the_keys_and_writes_values_as_json() -> None:
    assert settings_label({"max_steps": 3, "fast_free_motion": True}) == (
        "fast_free_motion=true, max_steps=3"
    )


def test_the_task_evaluated_is_the_ids_unless_a_setting_changes_it() -> None:
    assert evaluated_task(None) == "search"
    assert evaluated_task("tactile_search/MapByTouch-v0") == "map"
    assert evaluated_task("tactile_search/MapByTouch-v0", {"task": "identify"}) == "identify"
    with pytest.raises(ValueError, match="env_id must be one of"):
        evaluated_task("tactile_search/Sorting-v0")


def test_a_map_evaluation_tables_its_scores_and_plots_no_success(tmp_path: Path) -> None:
    evaluate(
        ["random_map"],
        out=tmp_path,
        env_id="tactile_search/MapByTouch-v0",
        env_settings={"max_steps": 3},
        **KWARGS,
    )
    table = (tmp_path / "results.md").read_text()
    assert "distance over the motions, mm (95 % CI)" in table and "success" not in table
    assert not (tmp_path / "success.png").exists() and not (tmp_path / "steps.png").exists()
