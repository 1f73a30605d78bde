"""The benchmark's result file carries what a leaderboard row needs, and the leaderboard
page is a function of result files: the same files and command give the same bytes, in a
section per task with a table per registered id, best first; ``docs/LEADERBOARD.md`` is the
page of its result files."""

from __future__ import annotations

import copy
import dataclasses
import json
import re
import shlex
from pathlib import Path

import pytest

from tactile_search.benchmark.__main__ import main as benchmark
from tactile_search.benchmark.leaderboard import (
    leaderboard_markdown,
    ranking_key,
    result_paths,
    source_cell,
)
from tactile_search.benchmark.leaderboard import main as leaderboard
from tactile_search.benchmark.result_file import RESULT_FIELDS, model_source, read_result
from tactile_search.benchmark.statistics import summarize
from tactile_search.seed_ranges import held_out_seeds

ROOT = Path(__file__).resolve().parents[1]
#: A policy of each task (tests/benchmark_policies.py) and the settings it runs in.
POLICIES = {
    "search": ("tests.benchmark_policies:forward", "tactile_search/CupboardSearch-v0", []),
    "identify": (
        "tests.benchmark_policies:ProbeThenClaim", "tactile_search/IdentifyByTouch-v0",
        ["--env", "action_mode=probe"],
    ),
    "map": (
        "tests.benchmark_policies:RandomProbes", "tactile_search/MapByTouch-v0",
        ["--env", "action_mode=probe"],
    ),
}  # fmt: skip
EPISODES = 3


@pytest.fixture(scope="module")
def results(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A folder of result files, one per task, written by the benchmark's command line."""
    folder = tmp_path_factory.mktemp("results")
    for task, (policy, env_id, settings) in POLICIES.items():
        benchmark(
            ["--policy", policy, "--env-id", env_id, *settings, "--episodes", str(EPISODES),
             "--num-envs", "1", "--no-progress", "--json", str(folder / f"{task}.json")]
        )  # fmt: skip
    return folder


def test_a_result_file_carries_a_leaderboard_rows_fields(results: Path) -> None:
    for task, (policy, env_id, _) in POLICIES.items():
        record = read_result(results / f"{task}.json")
        assert list(record) == list(RESULT_FIELDS)
        assert (record["env_id"], record["task"], record["split"]) == (env_id, task, "validation")
        assert record["source"] == {"kind": "callable", "name": policy}
        assert record["episodes"] == EPISODES == len(record["rows"])
        assert [row["seed"] for row in record["rows"]] == held_out_seeds("validation", EPISODES)
        assert record["command"].startswith("python -m tactile_search.benchmark --policy ")
        summary = record["summary"]
        assert summary["agent"] == record["agent"]
        assert summary["success_low"] <= summary["successes"] / EPISODES <= summary["success_high"]
        expected = dataclasses.asdict(summarize(record["agent"], "gpis", record["rows"]))
        for key in ("map_score_area", "map_score_area_low", "map_score_area_high", "tip_rate"):
            assert summary[key] == pytest.approx(expected[key])
        assert summary["map_score_area_low"] <= summary["map_score_area"]
        assert summary["map_score_area"] <= summary["map_score_area_high"]


def test_the_page_is_regenerated_byte_for_byte(results: Path, tmp_path: Path) -> None:
    out = tmp_path / "LEADERBOARD.md"
    page = leaderboard([str(results), "--out", str(out)])
    first = out.read_bytes()
    out.unlink()
    leaderboard([str(results), "--out", str(out)])
    assert out.read_bytes() == first == page.encode()
    # The rows' order is the ranking's, not the files'.
    records = [read_result(path) for path in result_paths([results])]
    command = f"python -m tactile_search.benchmark.leaderboard {results} --out {out}"
    assert leaderboard_markdown(records[::-1], command) == page


def test_the_page_has_a_section_per_task_and_a_table_per_id(results: Path) -> None:
    page = leaderboard([str(results)])
    assert page.startswith("# Leaderboard\n")
    assert f"`python -m tactile_search.benchmark.leaderboard {results}`" in page
    sections = re.split(r"^## ", page, flags=re.MULTILINE)
    titles = [section.splitlines()[0] for section in sections[1:]]
    assert titles == [
        "Task: search", "Task: identify", "Task: map", "The result files' commands",
    ]  # fmt: skip
    for section, (task, (_, env_id, _)) in zip(sections[1:], POLICIES.items(), strict=False):
        record = read_result(results / f"{task}.json")
        assert f"### `{env_id}`" in section
        table = [line for line in section.splitlines() if line.startswith("| ")]
        assert len(table) == 2  # its header and the one result's row
        assert table[1].startswith(f"| {record['agent']} |")
        assert f"{EPISODES} validation" in table[1]
        assert ("distance over the motions" in table[0]) == (task == "map")
        assert ("wrong claims" in table[0]) == (task == "identify")
    assert page.count("- `python -m tactile_search.benchmark --policy") == len(POLICIES)


def test_rows_are_ranked_best_first(results: Path) -> None:
    search = read_result(results / "search.json")
    better = copy.deepcopy(search)
    better["agent"] = "better"
    better["summary"]["successes"] = search["summary"]["successes"] + 1
    assert ranking_key(better) < ranking_key(search)
    mapping = read_result(results / "map.json")
    closer = copy.deepcopy(mapping)
    closer["summary"]["map_score_area"] = mapping["summary"]["map_score_area"] - 1.0
    assert ranking_key(closer) < ranking_key(mapping)


def test_a_models_source_shows_its_path_and_digest() -> None:
    source = model_source("models/model.zip", "ab" * 32, verified=True)
    assert source_cell(source) == "`models/model.zip` (verified digest `abababababab`)"
    assert "unverified" in source_cell({**source, "verified": False})


def test_a_file_that_is_no_result_is_one_line_naming_it(tmp_path: Path, capsys) -> None:
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps({"format": 1}))
    with pytest.raises(SystemExit) as exit_:
        leaderboard([str(bad)])
    assert exit_.value.code == 2
    error = capsys.readouterr().err.strip().splitlines()
    assert len(error) == 1 and str(bad) in error[0] and "lacks the fields" in error[0]
    empty = tmp_path / "empty"
    empty.mkdir()
    with pytest.raises(ValueError, match="holds no result file"):
        result_paths([empty])


def test_a_scripted_baselines_result_file_reads_back(tmp_path: Path) -> None:
    pytest.importorskip("yaml")
    from agents.scripted_results import main as scripted_results

    (path,) = scripted_results(
        ["--agents", "oracle", "--episodes", "2", "--num-envs", "1", "--out", str(tmp_path)]
    )
    record = read_result(path)
    assert record["source"] == {"kind": "scripted", "name": "oracle"}
    assert record["agent"] == "oracle" and record["task"] == "search"
    assert [row["seed"] for row in record["rows"]] == held_out_seeds("validation", 2)
    expected = dataclasses.asdict(summarize("oracle", "gpis", record["rows"]))
    assert record["summary"]["successes"] == expected["successes"]
    assert record["command"].startswith("python -m agents.scripted_results --agents oracle")


def test_the_published_leaderboard_is_the_page_of_its_result_files() -> None:
    page = (ROOT / "docs" / "LEADERBOARD.md").read_text()
    command = re.search(r"Generated by `([^`]+)`", page)
    assert command is not None
    words = shlex.split(command.group(1))
    assert words[:3] == ["python", "-m", "tactile_search.benchmark.leaderboard"]
    inputs = [ROOT / word for word in words[3 : words.index("--out")]]
    records = [read_result(path) for path in result_paths(inputs)]
    assert leaderboard_markdown(records, command.group(1)) == page
