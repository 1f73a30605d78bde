"""The end-to-end pipeline (the command)::

    python -m agents.pipeline --budget demo     # make demo: a few minutes, results/
    python -m agents.pipeline --budget full     # make results: docs/RESULTS.md
    python -m agents.pipeline --budget full --tasks tactile_search/CupboardSearch-v0  # a piece

A thin CLI over ``agents.grid.pipeline.run``, which documents the budgets and the grid.
"""

from __future__ import annotations

import argparse
import sys

from agents.grid.budgets import BUDGETS
from agents.grid.pipeline import SCHEDULERS, default_scheduler, run
from agents.sb3.training import INTERRUPTED_EXIT_STATUS
from tactile_search import ENV_IDS


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--budget", choices=sorted(BUDGETS), default="demo")
    parser.add_argument(
        "--seeds",
        type=int,
        nargs="+",
        help="training seeds, one run per agent each (default: the budget's; full: 0 1 2)",
    )
    parser.add_argument(
        "--scheduler",
        choices=SCHEDULERS,
        default=default_scheduler(),
        help="ray: Ray tasks (the default when Ray is installed); "
        "local: one run after another in this process",
    )
    parser.add_argument(
        "--address", help="a Ray cluster's address (default: RAY_ADDRESS, else Ray on this machine)"
    )
    parser.add_argument(
        "--tasks",
        nargs="+",
        choices=ENV_IDS,
        metavar="ID",
        help="run only these tasks of the budget, by id (default: all; a dense tier needs the "
        "id whose agents play it too): a piece of a long grid, the other tasks' sections "
        "of RESULTS.md kept",
    )
    parser.add_argument("--no-progress", action="store_true")
    args = parser.parse_args(argv)
    if args.tasks is not None:
        try:
            BUDGETS[args.budget].only(args.tasks)
        except ValueError as error:  # an id the budget lacks, a tier without its agents' id
            parser.error(str(error))
    try:
        run(
            args.budget,
            args.seeds,
            args.scheduler,
            args.address,
            progress_bar=not args.no_progress,
            env_ids=args.tasks,
        )
    except KeyboardInterrupt:
        print(
            "\ninterrupted: run the same command again to finish (finished runs are reused, a "
            "partly trained run resumes from its checkpoint, the evaluation from its rows)",
            file=sys.stderr,
            flush=True,
        )
        sys.exit(INTERRUPTED_EXIT_STATUS)


if __name__ == "__main__":
    main()
