"""An evaluation's summary as the cells of a markdown table row, by task: what a leaderboard
and a model card show of it. The search task: success with its 95 % Wilson interval, the
motions to success and the tip rate; the identify task: its wrong claims too; the map task,
which has no success: its outline distance over the motions and at the end, each with its
95 % interval (``statistics.mean_interval``), the final IoU and the tip rate.

A summary is read as a mapping (``dataclasses.asdict`` of a ``Summary``, or the ``summary``
of a result file, where a NaN is null)."""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

from tactile_search.envs.config import SETTINGS

#: The tasks (the core's ``task`` setting).
TASKS: tuple[str, ...] = tuple(next(s for s in SETTINGS if s["key"] == "task")["choices"])
#: The task whose episodes have no success: decided by its map scores (lower is better).
MAP_TASK = "map"


def _number(value: Any) -> float | None:
    """``value`` as a float, None for a missing or NaN one."""
    if value is None:
        return None
    number = float(value)
    return None if math.isnan(number) else number


def _with_interval(value: Any, low: Any, high: Any) -> str:
    """A distance (mm) with its interval in brackets (left out where it is unknown)."""
    number = _number(value)
    if number is None:
        return "-"
    low_n, high_n = _number(low), _number(high)
    if low_n is None or high_n is None:
        return f"{number:.2f}"
    return f"{number:.2f} [{low_n:.2f}, {high_n:.2f}]"


def _percent(value: Any) -> str:
    number = _number(value)
    return "-" if number is None else f"{100 * number:.1f} %"


def _steps(summary: Mapping[str, Any]) -> str:
    median = _number(summary.get("steps_median"))
    if median is None:
        return "-"
    q1, q3 = _number(summary.get("steps_q1")), _number(summary.get("steps_q3"))
    return f"{median:g} ({q1:g}, {q3:g})"


def _checked(task: str) -> str:
    if task not in TASKS:
        raise ValueError(f"task must be one of {list(TASKS)}, got {task!r}")
    return task


def summary_columns(task: str) -> list[str]:
    """The headers of ``summary_cells(task, ...)``."""
    if _checked(task) == MAP_TASK:
        return [
            "distance over the motions, mm (95 % CI)",
            "distance at the end, mm (95 % CI)",
            "final IoU",
            "tip rate",
        ]
    return [
        "success (95 % CI)",
        *(["wrong claims"] if task == "identify" else []),
        "motions to success, median (Q1, Q3)",
        "tip rate",
    ]


def summary_cells(task: str, summary: Mapping[str, Any]) -> list[str]:
    """The cells of ``summary`` (a ``Summary`` as a mapping) under ``summary_columns(task)``;
    ``ValueError`` for an unknown task, ``KeyError`` naming a field the summary lacks."""
    if _checked(task) == MAP_TASK:
        return [
            _with_interval(
                summary["map_score_area"],
                summary.get("map_score_area_low"),
                summary.get("map_score_area_high"),
            ),
            _with_interval(
                summary["map_score_mm"],
                summary.get("map_score_mm_low"),
                summary.get("map_score_mm_high"),
            ),
            f"{float(summary['map_score_iou']):.3f}",
            _percent(summary["tip_rate"]),
        ]
    success = int(summary["successes"]) / int(summary["episodes"])
    return [
        f"{100 * success:.1f} % [{100 * float(summary['success_low']):.1f}, "
        f"{100 * float(summary['success_high']):.1f}]",
        *([_percent(summary["wrong_claim_rate"])] if task == "identify" else []),
        _steps(summary),
        _percent(summary["tip_rate"]),
    ]


def markdown_row(cells: list[str]) -> str:
    """One row of a markdown table (a ``|`` inside a cell escaped)."""
    return "| " + " | ".join(cell.replace("|", "\\|") for cell in cells) + " |"
