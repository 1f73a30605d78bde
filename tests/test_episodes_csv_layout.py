"""``episodes.csv`` written before a column was added (the published results have no
``wrong_claim``) reads back with that column's value for every row, and a file of any other
layout is not read."""

from __future__ import annotations

from pathlib import Path

from agents.evaluation.episodes_csv import (
    ADDED_COLUMNS,
    EPISODE_COLUMNS,
    read_episodes_csv,
    write_episodes_csv,
)

ROW = {
    "agent": "oracle", "map": "gpis", "seed": 1_000_000, "success": True, "wrong_claim": False,
    "steps": 44, "actions": 3, "tips": 0, "jar_displacement": 0.001,
    "max_jar_displacement": 0.0005, "iou": 0.3, "reward": 0.5, "map_score_mm": 0.0,
    "map_score_iou": 0.0, "map_score_area": 0.0, "map_score_curve": "", "fingerprint": "abc",
}  # fmt: skip


def test_a_file_without_the_added_columns_reads_with_their_values(tmp_path: Path) -> None:
    older = [key for key in EPISODE_COLUMNS if key not in ADDED_COLUMNS]
    path = tmp_path / "episodes.csv"
    path.write_text(",".join(older) + "\n" + ",".join(str(ROW[k]) for k in older) + "\n")
    rows, bad = read_episodes_csv(path)
    assert (rows, bad) == ([ROW], 0)


def test_a_file_of_the_current_layout_reads_back_as_written(tmp_path: Path) -> None:
    path = tmp_path / "episodes.csv"
    write_episodes_csv(path, [{**ROW, "wrong_claim": True}])
    assert read_episodes_csv(path) == ([{**ROW, "wrong_claim": True}], 0)


def test_a_file_of_another_layout_is_not_read(tmp_path: Path) -> None:
    path = tmp_path / "episodes.csv"
    path.write_text("agent,seed\noracle,1\n")
    assert read_episodes_csv(path) == ([], 1)


def test_a_file_of_the_layout_before_the_map_curve_reads_with_an_empty_curve(
    tmp_path: Path,
) -> None:
    before = [key for key in EPISODE_COLUMNS if key != "map_score_curve"]
    path = tmp_path / "episodes.csv"
    path.write_text(",".join(before) + "\n" + ",".join(str(ROW[k]) for k in before) + "\n")
    assert read_episodes_csv(path) == ([ROW], 0)
    # Out of order is another layout, not an older one.
    path.write_text(",".join(reversed(before)) + "\n" + ",".join("1" for _ in before) + "\n")
    assert read_episodes_csv(path) == ([], 1)
