"""``episodes.csv``: one typed row per agent and episode, written as episodes end, read back
for reuse (a row written, read back and written again is the same text)."""

from __future__ import annotations

import csv
import os
from collections.abc import Sequence
from pathlib import Path
from typing import Any

#: The file an evaluation writes its rows to, in its results folder.
EPISODES_FILE = "episodes.csv"
# The columns of episodes.csv and their types (those of run_episodes' values).
EPISODE_COLUMNS: dict[str, type] = {
    "agent": str,
    "map": str,
    "seed": int,
    "success": bool,
    "wrong_claim": bool,
    "steps": int,
    "actions": int,
    "tips": int,
    "jar_displacement": float,
    "max_jar_displacement": float,
    "iou": float,
    "reward": float,
    "map_score_mm": float,
    "map_score_iou": float,
    "map_score_area": float,
    "map_score_curve": str,
    "fingerprint": str,
}


#: Columns added since the first layout, with the value a row of an older file has: a file
#: written before the identify and map tasks has no ``wrong_claim`` (no search episode has
#: one) and no map scores (0 outside the map task), one written before the map task's curve
#: none (empty outside the map task).
ADDED_COLUMNS: dict[str, Any] = {
    "wrong_claim": False,
    "map_score_mm": 0.0,
    "map_score_iou": 0.0,
    "map_score_area": 0.0,
    "map_score_curve": "",
}


def _parse(kind: type, text: str) -> Any:
    if kind is bool:
        return {"True": True, "False": False}[text]
    return kind(text)


def episode_row(agent: str, map_mode: str, result: dict[str, Any], fingerprint: str) -> dict:
    """One row of episodes.csv, each value of its column's type: what ``read_episodes_csv``
    gives back, so a row written, read back and written again is the same text."""
    row = {"agent": agent, "map": map_mode, **result, "fingerprint": fingerprint}
    if set(row) != set(EPISODE_COLUMNS):
        raise ValueError(
            f"an episode's summary must have the columns {list(EPISODE_COLUMNS)} of "
            f"episodes.csv, got {sorted(row)} (a new metric goes into EPISODE_COLUMNS too)"
        )
    return {key: kind(row[key]) for key, kind in EPISODE_COLUMNS.items()}


def read_episodes_csv(path: Path) -> tuple[list[dict[str, Any]], int]:
    """The complete, well-formed rows of an episodes.csv, typed as ``run_episodes`` returns
    them, and how many lines were not (a line cut short by a kill, a file of another layout).
    A file of the layout before a column was added (``ADDED_COLUMNS``) is read with that
    column's value for every row."""
    if not path.is_file():
        return [], 0
    with path.open(newline="") as f:
        lines = f.read().splitlines(keepends=True)
    header = next(csv.reader(lines[:1]), [])
    # This layout, or an older one: the columns in order, some of the added ones missing.
    known = header == [key for key in EPISODE_COLUMNS if key in header]
    missing = set(EPISODE_COLUMNS) - set(header)
    if not header or not known or not missing <= set(ADDED_COLUMNS):
        return [], max(0, len(lines) - 1)
    columns = {key: EPISODE_COLUMNS[key] for key in header}
    rows, bad = [], 0
    for line in lines[1:]:
        values = next(csv.reader([line]), [])
        if not line.endswith("\n") or len(values) != len(columns):
            bad += 1
            continue
        try:
            parsed = {
                key: _parse(kind, text)
                for (key, kind), text in zip(columns.items(), values, strict=True)
            }
        except (ValueError, KeyError):
            bad += 1
            continue
        rows.append({key: parsed.get(key, ADDED_COLUMNS.get(key)) for key in EPISODE_COLUMNS})
    return rows, bad


def write_episodes_csv(path: Path, rows: Sequence[dict[str, Any]]) -> None:
    """Per-episode rows (agent, map, seed, metrics, fingerprint), written atomically."""
    with (path.with_name(path.name + ".tmp")).open("w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(EPISODE_COLUMNS))
        writer.writeheader()
        writer.writerows(rows)
    os.replace(path.with_name(path.name + ".tmp"), path)


def reusable_rows(
    csv_path: Path,
    names: Sequence[str],
    map_modes: Sequence[str],
    fingerprints: Sequence[str],
    seeds: Sequence[int],
) -> dict[tuple[str, int], dict[str, Any]]:
    """The rows of ``csv_path`` an evaluation of these agents (names, map modes and
    fingerprints, index by index) on ``seeds`` can reuse, by (agent name, seed); prints how
    many, and how many it drops (incomplete, or of other agents, seeds or code)."""
    wanted = {
        (name, map_mode, seed, fingerprint)
        for name, map_mode, fingerprint in zip(names, map_modes, fingerprints, strict=True)
        for seed in seeds
    }
    earlier, unreadable = read_episodes_csv(csv_path)
    done: dict[tuple[str, int], dict[str, Any]] = {}
    for row in earlier:
        if (row["agent"], row["map"], row["seed"], row["fingerprint"]) in wanted:
            done[row["agent"], row["seed"]] = row
    if earlier or unreadable:
        dropped = len(earlier) + unreadable - len(done)
        print(
            f"reusing {len(done)} episodes of {csv_path}"
            + (
                f" (dropped {dropped}: incomplete, or of other agents, seeds or code)"
                if dropped
                else ""
            ),
            flush=True,
        )
    return done
