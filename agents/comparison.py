"""Results pooled over training seeds, and differences between agents with intervals (the
command)::

    python -m agents.comparison docs/results/episodes.csv [--reference AGENT] [--task identify]
    python -m agents.comparison docs/results/MapByTouch-v0/episodes.csv --task map \\
        --reference "ppo (gpis map) [MapByTouch-v0]" --sources   # the layouts' share
    python -m agents.comparison docs/results/episodes.csv \\
        --overlap "ppo (gpis map)" gpis_probe_planner    # who fails where

A thin CLI over ``agents.evaluation.comparison``, which documents the statistics.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from agents.evaluation.comparison import (
    TASK_MEASURES,
    comparison_markdown,
    interval_sources_markdown,
    overlap_markdown,
)
from agents.evaluation.episodes_csv import read_episodes_csv


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("episodes", type=Path, help="an evaluation's episodes.csv")
    parser.add_argument("--reference", help="the agent the differences are taken from")
    parser.add_argument(
        "--task",
        choices=sorted(TASK_MEASURES),
        default="search",
        help="the task the rows are of: its measures are pooled and differenced too "
        "(identify: wrong claims; map: the map scores)",
    )
    parser.add_argument(
        "--sources",
        action="store_true",
        help="instead: each difference from the reference (needed) beside its interval over "
        "the layouts alone, the training seeds held",
    )
    parser.add_argument(
        "--overlap",
        nargs=2,
        metavar=("A", "B"),
        help="instead: where agents A and B succeed and fail, layout by layout",
    )
    args = parser.parse_args(argv)
    rows, _ = read_episodes_csv(args.episodes)
    if not rows:
        raise SystemExit(f"{args.episodes} holds no episode")
    if args.overlap:
        print(overlap_markdown(rows, *args.overlap))
    elif args.sources:
        if args.reference is None:
            raise SystemExit("--sources needs --reference: the agent the differences are from")
        print(interval_sources_markdown(rows, args.reference, task=args.task))
    else:
        print(comparison_markdown(rows, args.reference, task=args.task))


if __name__ == "__main__":
    main()
