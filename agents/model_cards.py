"""Write the model cards of published runs and record their models' digests (the command)::

    python -m agents.model_cards                      # every published run
    python -m agents.model_cards runs/ppo_gpis_seed0 --results results

Each finished run gets ``MODEL_CARD.md`` and ``model.digest`` beside its ``model.zip``; the
benchmark (``python -m tactile_search.benchmark --policy <model.zip>``) checks the model
against that digest before loading it. A thin CLI over ``agents.grid.model_card``, which
documents what a card holds; the pipeline writes the cards of the runs it trains.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from agents.grid.model_card import PUBLISHED_RESULTS, published_runs, write_model_cards

PROG = "python -m agents.model_cards"


def main(argv: list[str] | None = None) -> list[Path]:
    parser = argparse.ArgumentParser(prog=PROG, description=__doc__.split("\n\n")[0])
    parser.add_argument(
        "runs", nargs="*", type=Path,
        help="finished run directories (default: every published run, docs/results/models/)",
    )  # fmt: skip
    parser.add_argument(
        "--results", type=Path, default=PUBLISHED_RESULTS,
        help="the results the runs were evaluated in: <results>/<id's name>/episodes.csv "
        "(default: the published results, docs/results/)",
    )  # fmt: skip
    args = parser.parse_args(argv)
    runs = args.runs or published_runs()
    if not runs:
        parser.exit(2, f"{PROG}: error: no finished run to write a card for\n")
    try:
        cards = write_model_cards(runs, args.results)
    except ValueError as error:
        parser.exit(2, f"{PROG}: error: {' '.join(str(error).split())}\n")
    for card in cards:
        print(card)
    return cards


if __name__ == "__main__":
    main()
