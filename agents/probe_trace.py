"""How a probe-mode agent spends its episodes, on the validation layouts (the command)::

    python -m agents.probe_trace docs/results/models/ppo_gpis_seed0 --episodes 200

A thin CLI over ``agents.evaluation.probe_trace``, which documents what is traced.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from agents.evaluation.probe_trace import summary, summary_markdown, trace
from tactile_search.seed_ranges import held_out_seeds


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("runs", nargs="+", type=Path, help="run directories (probe mode)")
    parser.add_argument("--episodes", type=int, default=200, help="validation layouts")
    args = parser.parse_args(argv)
    seeds = held_out_seeds("validation", args.episodes)
    # A column per run, named by its directory (by its path where two share a name).
    names = [run.name for run in args.runs]
    if len(set(names)) < len(names):
        names = [str(run) for run in args.runs]
    summaries = {
        name: summary(trace(run, seeds)) for name, run in zip(names, args.runs, strict=True)
    }
    print(f"Validation layouts {seeds[0]}..{seeds[-1]}:\n")
    print(summary_markdown(summaries))


if __name__ == "__main__":
    main()
