"""The table: means and standard deviations over seeds, the default prior's choice, and
the CSV and markdown the driver writes."""

from __future__ import annotations

import csv
import statistics
from collections.abc import Sequence
from pathlib import Path

from experiments.paper.episodes import DEFAULT_DEPTH_NOISE


def summarise(rows: Sequence[dict[str, object]]) -> list[dict[str, object]]:
    """Mean and standard deviation over seeds for each (noise, shape, prior, data)."""
    groups: dict[tuple, list[dict[str, object]]] = {}
    for row in rows:
        key = (row["depth_noise"], row["shape"], row["prior"], row["data"])
        groups.setdefault(key, []).append(row)
    out = []
    for (noise, shape, prior, data), members in groups.items():
        iou = [float(m["iou"]) for m in members]
        dist = [float(m["outline_distance"]) for m in members]
        spurious = [float(m["spurious_distance"]) for m in members]
        out.append(
            {
                "depth_noise": noise,
                "shape": shape,
                "prior": prior,
                "data": data,
                "seeds": len(members),
                "iou_mean": statistics.fmean(iou),
                "iou_std": statistics.pstdev(iou),
                "outline_mm_mean": 1e3 * statistics.fmean(dist),
                "outline_mm_std": 1e3 * statistics.pstdev(dist),
                "spurious_mm_mean": 1e3 * statistics.fmean(spurious),
                "rows_mean": statistics.fmean(float(m["rows"]) for m in members),
            }
        )
    return out


def choose_default(summary: Sequence[dict[str, object]]) -> str:
    """The prior with the best depth + touch IoU at the default noise, averaged over shapes
    (ties broken by the smaller outline distance)."""
    scores: dict[str, list[tuple[float, float]]] = {}
    for row in summary:
        if row["data"] == "depth + touch" and row["depth_noise"] == DEFAULT_DEPTH_NOISE:
            scores.setdefault(str(row["prior"]), []).append(
                (float(row["iou_mean"]), float(row["outline_mm_mean"]))
            )
    return max(
        scores,
        key=lambda p: (
            statistics.fmean(s[0] for s in scores[p]),
            -statistics.fmean(s[1] for s in scores[p]),
        ),
    )


def write_csv(rows: Sequence[dict[str, object]], path: Path) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    with path.open("w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        for row in rows:
            writer.writerow({k: f"{v:.6g}" if isinstance(v, float) else v for k, v in row.items()})


def markdown_table(summary: Sequence[dict[str, object]]) -> str:
    """The summary as a markdown table, one line per (noise, shape, prior), depth-only and
    depth + touch side by side."""
    by_key: dict[tuple, dict[str, dict[str, object]]] = {}
    for row in summary:
        by_key.setdefault((row["depth_noise"], row["shape"], row["prior"]), {})[
            str(row["data"])
        ] = row
    lines = [
        "| depth noise (mm) | jars | prior | IoU depth only | IoU depth + touch "
        "| outline dist. depth only (mm) | outline dist. depth + touch (mm) "
        "| zero set to truth, depth + touch (mm) | seeds |",
        "|---:|---|---|---:|---:|---:|---:|---:|---:|",
    ]
    for (noise, shape, prior), pair in by_key.items():
        d, t = pair["depth only"], pair["depth + touch"]
        lines.append(
            f"| {1e3 * float(noise):g} | {shape} | {prior} "
            f"| {d['iou_mean']:.3f} +- {d['iou_std']:.3f} "
            f"| {t['iou_mean']:.3f} +- {t['iou_std']:.3f} "
            f"| {d['outline_mm_mean']:.1f} +- {d['outline_mm_std']:.1f} "
            f"| {t['outline_mm_mean']:.1f} +- {t['outline_mm_std']:.1f} "
            f"| {t['spurious_mm_mean']:.1f} | {d['seeds']} |"
        )
    return "\n".join(lines) + "\n"


def headline(summary: Sequence[dict[str, object]], default: str, seeds: str) -> str:
    """Averages at the default depth noise, per prior, shape and data."""
    lines = [
        f"Averages over layout seeds {seeds} (validation range) at the default depth noise "
        f"({1e3 * DEFAULT_DEPTH_NOISE:g} mm).",
        "",
        "| prior | jars | IoU depth only | IoU depth + touch | outline dist. depth only (mm) "
        "| outline dist. depth + touch (mm) | zero set to truth, depth + touch (mm) |",
        "|---|---|---:|---:|---:|---:|---:|",
    ]
    pairs: dict[tuple, dict[str, dict[str, object]]] = {}
    for row in summary:
        if row["depth_noise"] == DEFAULT_DEPTH_NOISE:
            pairs.setdefault((row["prior"], row["shape"]), {})[str(row["data"])] = row
    for (prior, shape), pair in pairs.items():
        d, t = pair["depth only"], pair["depth + touch"]
        lines.append(
            f"| {prior} | {shape} | {d['iou_mean']:.3f} | {t['iou_mean']:.3f} "
            f"| {d['outline_mm_mean']:.1f} | {t['outline_mm_mean']:.1f} "
            f"| {t['spurious_mm_mean']:.1f} |"
        )
    lines += ["", f"Chosen default prior (best depth + touch IoU, both shapes): **{default}**."]
    return "\n".join(lines) + "\n"
