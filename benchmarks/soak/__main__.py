"""The soak's command line: ``python -m benchmarks.soak [--quick] [--rounds N]
[--seed-base S] [--out results/soak.png] [--json results/soak.json]``; the exit status is 1
if a check fails."""

from __future__ import annotations

import argparse
import dataclasses
import sys
from pathlib import Path

import benchmarks.soak
from benchmarks.performance_page import write_json
from benchmarks.soak.plan import FULL, QUICK, power_range
from benchmarks.soak.report import plot
from benchmarks.soak.run import run_soak
from tactile_search.seed_ranges import TRAINING


def parse_args(argv: list[str] | None = None) -> argparse.Namespace:
    """The options, with the scale they choose as ``args.scale``."""
    parser = argparse.ArgumentParser(
        prog="python -m benchmarks.soak",
        description=(benchmarks.soak.__doc__ or "").splitlines()[0],
    )
    parser.add_argument("--quick", action="store_true", help="the ~30 s version")
    parser.add_argument("--rounds", type=int, help="override the number of rounds")
    parser.add_argument(
        "--seed-base",
        type=int,
        default=TRAINING[0],
        help=f"first layout seed (training range {power_range(TRAINING)})",
    )
    parser.add_argument("--out", type=Path, default=Path("results/soak.png"), help="plot path")
    parser.add_argument("--json", type=Path, help="write the figures as JSON here")
    args = parser.parse_args(argv)
    args.scale = QUICK if args.quick else FULL
    if args.rounds is not None:
        if args.rounds < 2:
            parser.error("--rounds must be at least 2 (the warm-up and one more)")
        args.scale = dataclasses.replace(args.scale, rounds=args.rounds)
    return args


def main(argv: list[str] | None = None) -> int:
    args = parse_args(argv)
    result = run_soak(args.scale, seed_base=args.seed_base, log=lambda s: print(s, flush=True))
    print(result.text)
    print(plot(result, args.out))
    if args.json:
        write_json(args.json, "benchmarks.soak", argv, result.figures)
    return 0 if result.passed else 1


if __name__ == "__main__":
    sys.exit(main())
