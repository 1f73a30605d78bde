"""The pipeline on several tasks (agents.grid.budgets.Task): a budget trains each learned agent
on every id it trains on, into a folder per id; each task is evaluated with its own scripted
baselines and its agents' names carry the id; a dense tier is played by the agents of the
id they were trained on; each task's section of RESULTS.md is written between its own
markers, the hand-written text around them kept."""

from __future__ import annotations

import csv
import dataclasses
from pathlib import Path

import pytest

pytest.importorskip("stable_baselines3")

from agents.grid.budgets import BUDGETS, SCRIPTED, Budget, Task
from agents.grid.results_doc import TaskResults, markers, task_results_markdown, write_results
from agents.run_dir import task_folder
from tactile_search import ENV_ID
from tests.recipes import SMALL_IMITATION

IDENTIFY = "tactile_search/IdentifyByTouch-v0"
IDENTIFY_DENSE = "tactile_search/IdentifyByTouchDense-v0"


def test_each_id_keeps_its_runs_and_results_in_a_folder_of_its_name() -> None:
    assert task_folder(ENV_ID) == ""  # v0's runs and results came first, at the top
    assert task_folder(IDENTIFY) == "IdentifyByTouch-v0"
    with pytest.raises(ValueError, match="env_id must be one of"):
        task_folder("tactile_search/Nothing-v0")


def test_a_task_is_evaluated_with_its_own_scripted_baselines() -> None:
    assert Task().scripted() == SCRIPTED
    assert Task(IDENTIFY).scripted() == ("oracle", "random_identify", "identify_planner")
    assert "variance_mapper" in Task("tactile_search/MapByTouch-v0").scripted()
    assert Task(IDENTIFY).task == "identify" and Task().task == "search"
    assert Task(IDENTIFY).reference_agent() == "ppo (gpis map) [IdentifyByTouch-v0]"
    assert Task().reference_agent() == "ppo (gpis map)"


def test_a_dense_tier_must_be_played_by_agents_the_budget_trains() -> None:
    with pytest.raises(ValueError, match="does not train"):
        dataclasses.replace(BUDGETS["demo"], tasks=(Task(IDENTIFY_DENSE, trained_on=IDENTIFY),))
    full = BUDGETS["full"]
    assert full.trained_ids() == [
        ENV_ID,
        IDENTIFY,
        "tactile_search/MapByTouch-v0",
    ]  # the dense tiers: evaluated with the default tiers' agents, not trained on


def test_the_full_budget_trains_every_agent_on_every_task_id_with_its_recipe(
    tmp_path: Path,
) -> None:
    from agents.grid.pipeline import trials

    full = dataclasses.replace(BUDGETS["full"], runs=tmp_path / "models")
    grid = trials(full, list(full.seeds))
    assert len(grid) == 3 * len(full.agents) * len(full.seeds)
    by_name = {trial.name: trial for trial in grid}
    assert len(by_name) == len(grid)  # every run has a directory of its own
    identify = by_name["IdentifyByTouch-v0/ppo_gpis_seed2"]
    assert identify.env_id == IDENTIFY
    assert identify.run_dir == tmp_path / "models" / "IdentifyByTouch-v0" / "ppo_gpis_seed2"
    assert by_name["ppo_gpis_seed2"].run_dir == tmp_path / "models" / "ppo_gpis_seed2"


def rows(path: Path) -> list[dict[str, str]]:
    with path.open() as f:
        return list(csv.DictReader(f))


def test_a_budget_of_two_tasks_trains_once_and_evaluates_both(tmp_path: Path) -> None:
    from agents.grid.pipeline import run_budget

    budget = Budget(
        agents=(("ppo", "none"),),
        timesteps=128,
        episodes=2,
        runs=tmp_path / "runs",
        results=tmp_path / "results",
        cpus_per_trial=1,
        imitation=SMALL_IMITATION,
        tasks=(Task(IDENTIFY), Task(IDENTIFY_DENSE, trained_on=IDENTIFY)),
    )
    identify, dense = run_budget(budget, [0], "local", progress_bar=False)
    run_dir = tmp_path / "runs" / "IdentifyByTouch-v0" / "ppo_none_seed0"
    assert identify.run_dirs == dense.run_dirs == [run_dir]
    assert (run_dir / "model.zip").is_file()
    assert identify.results == tmp_path / "results" / "IdentifyByTouch-v0"
    assert (identify.results / "training" / "ppo_none_seed0" / "config.yml").is_file()
    assert not (dense.results / "training").exists()  # its runs' records are identify's
    agents = {r["agent"] for r in rows(identify.results / "episodes.csv")}
    assert agents == {
        "ppo (none map) [IdentifyByTouch-v0]",  # one training seed: no seed in its name
        "oracle [IdentifyByTouch-v0]",
        "random_identify [IdentifyByTouch-v0]",
        "identify_planner [IdentifyByTouch-v0]",
    }
    dense_agents = {r["agent"] for r in rows(dense.results / "episodes.csv")}
    assert "ppo (none map) [IdentifyByTouchDense-v0]" in dense_agents
    section = task_results_markdown(budget, identify, "| pooled |\n")
    assert "`tactile_search/IdentifyByTouch-v0` (task `identify`)" in section
    assert "| ppo (none map) | 0 |" in section and "| pooled |" in section
    assert "| wrong claims |" in identify.table and "success.png" in section
    dense_section = task_results_markdown(budget, dense, "| pooled |\n")
    assert f"played by the agents trained on `{IDENTIFY}`" in dense_section


def test_the_map_tasks_section_shows_its_scores_figure_and_no_success(tmp_path: Path) -> None:
    budget = dataclasses.replace(BUDGETS["full"], results=tmp_path)
    outcome = TaskResults(Task("tactile_search/MapByTouch-v0"), [], tmp_path, "| table |\n")
    section = task_results_markdown(budget, outcome, "| pooled |\n")
    assert "results/MapByTouch-v0/curves.png" in section
    assert "success" not in section.lower() and "steps.png" not in section


def test_each_task_section_is_written_between_its_own_markers(tmp_path: Path) -> None:
    path = tmp_path / "RESULTS.md"
    write_results(path, "v0 table")
    path.write_text(f"# Results\n{path.read_text()}\nfindings by hand\n")
    write_results(path, "identify table", section="IdentifyByTouch-v0")
    write_results(path, "identify table, again", section="IdentifyByTouch-v0")
    write_results(path, "v0 table, again")
    text = path.read_text()
    begin, end = markers("IdentifyByTouch-v0")
    assert text.count(begin) == 1 and text.count(end) == 1
    assert "identify table, again" in text and "identify table\n" not in text
    assert "v0 table, again" in text and "v0 table\n" not in text
    assert text.startswith("# Results\n") and "findings by hand" in text
    assert text.index("findings by hand") < text.index(begin)  # a new section at the end


def seeded_rows(name: str, rate: float, suffix: str, rng) -> list[dict]:
    """Three training seeds of agent ``name`` (``ppo (gpis map)``) succeeding at ``rate`` on
    200 layouts, named as an evaluation on the id of ``suffix`` names them."""
    algo, rest = name.split(" (", 1)
    return [
        {
            "agent": f"{algo} ({rest[:-1]}, seed {seed}){suffix}",
            "map": "gpis",
            "seed": layout,
            "success": bool(rng.random() < rate),
            "tips": 0,
            "jar_displacement": 0.0,
            "steps": 100,
            "actions": 3,
        }
        for seed in range(3)
        for layout in range(1_000_000, 1_000_200)
    ]


def test_the_dense_tiers_section_gives_the_change_of_each_no_map_gap() -> None:
    import numpy as np

    from agents.grid.results_doc import gap_change_markdown

    rng = np.random.default_rng(0)
    dense = Task("tactile_search/CupboardSearchDense-v0", trained_on=ENV_ID)
    suffix = " [CupboardSearchDense-v0]"
    dense_rows = seeded_rows("ppo (gpis map)", 0.8, suffix, rng)
    dense_rows += seeded_rows("ppo (none map)", 0.3, suffix, rng)
    default_rows = seeded_rows("ppo (gpis map)", 0.9, "", rng)
    default_rows += seeded_rows("ppo (none map)", 0.7, "", rng)
    table = gap_change_markdown(dense_rows, default_rows, dense, Task(), samples=500)
    (row,) = [line for line in table.splitlines() if line.startswith("| ppo (none map)")]
    gap_default, gap_dense, change = (float(cell.split()[0]) for cell in row.split("|")[2:5])
    assert change == pytest.approx(gap_dense - gap_default, abs=0.11)
    assert 20 < change < 40  # 50 - 20 points, give or take the draws
    assert "recurrent_ppo" not in table  # not in the rows: left out


def test_a_piece_of_a_budget_keeps_only_the_tasks_it_names_in_the_budgets_order() -> None:
    full = BUDGETS["full"]
    piece = full.only([IDENTIFY_DENSE, IDENTIFY])
    assert [task.env_id for task in piece.tasks] == [IDENTIFY, IDENTIFY_DENSE]
    assert piece.trained_ids() == [IDENTIFY]
    assert piece.agents == full.agents and piece.runs == full.runs
    with pytest.raises(ValueError, match="does not train"):
        full.only([IDENTIFY_DENSE])  # a dense tier without the agents that play it
    with pytest.raises(ValueError, match="tasks must be some of"):
        BUDGETS["demo"].only([IDENTIFY])
    with pytest.raises(ValueError, match="tasks must be some of"):
        full.only([])


def test_the_pipeline_command_refuses_a_piece_the_budget_cannot_run(
    capsys: pytest.CaptureFixture[str],
) -> None:
    from agents.pipeline import main

    with pytest.raises(SystemExit) as exit_info:
        main(["--budget", "full", "--tasks", IDENTIFY_DENSE])
    assert exit_info.value.code == 2
    assert "does not train" in capsys.readouterr().err
