"""Write Minari datasets of the scripted teachers' and the published learned agents' episodes
on training layouts (the command)::

    python -m agents.datasets --episodes 500
    python -m agents.datasets --env-ids tactile_search/IdentifyByTouch-v0 \\
        --agents identify_planner --episodes 50 --out datasets

For each id (by default the first of each task: CupboardSearch-v0, IdentifyByTouch-v0,
MapByTouch-v0) a dataset of its teacher and one per finished run published for it
(``agents.offline.catalogue``; an id with none says so), each on the same training layouts,
with the reference scores of its task's random baseline and oracle (``agents.offline``
documents the rest). ``minari.load_dataset("tactile_search/search/gpis_probe_planner-v0")``
reads one back (with ``MINARI_DATASETS_PATH`` set to ``--out`` if given).
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from agents.offline.catalogue import dataset_sources, default_env_ids
from agents.offline.recording import training_seeds
from agents.offline.references import reference_scores
from agents.offline.writing import datasets_root, write_agent_dataset
from agents.run_dir import PUBLISHED_RUNS
from tactile_search import ENV_IDS
from tactile_search.seed_ranges import TRAINING


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--episodes", type=int, default=200, help="episodes per dataset")
    parser.add_argument(
        "--out",
        type=Path,
        default=None,
        help="the datasets' root (default: Minari's own, MINARI_DATASETS_PATH or "
        "~/.minari/datasets)",
    )
    parser.add_argument(
        "--agents",
        nargs="+",
        default=None,
        help="scripted agents or run directories, each on the ids it plays (default: each "
        "id's teacher and its published runs)",
    )
    parser.add_argument(
        "--env-ids",
        nargs="+",
        choices=list(ENV_IDS),
        default=default_env_ids(),
        help="the registered ids (default: the first of each task)",
    )
    parser.add_argument(
        "--first-seed",
        type=int,
        default=TRAINING[0],
        help="the first layout seed; the episodes take consecutive seeds of the training range",
    )
    parser.add_argument(
        "--reference-episodes",
        type=int,
        default=50,
        help="layouts (the first of the datasets') the random baseline and the oracle play for "
        "the reference scores",
    )
    parser.add_argument(
        "--published",
        type=Path,
        default=Path(PUBLISHED_RUNS),
        help="where the published runs are, a folder per id",
    )
    parser.add_argument("--overwrite", action="store_true", help="replace existing datasets")
    args = parser.parse_args(argv)
    if args.reference_episodes < 1:
        parser.error(f"--reference-episodes must be >= 1, got {args.reference_episodes}")
    try:
        seeds = training_seeds(args.episodes, args.first_seed)
        sources, notes = dataset_sources(args.env_ids, args.agents, args.published)
    except ValueError as err:
        parser.error(str(err))
    reference_seeds = seeds[: args.reference_episodes]
    for note in notes:
        print(note)
    with datasets_root(args.out):
        for env_id in args.env_ids:
            todo = [source for source in sources if source.env_id == env_id]
            if not todo:
                continue
            start = time.perf_counter()
            references = reference_scores(env_id, reference_seeds)
            print(
                f"{env_id}: reference scores {references.min_agent} "
                f"{references.min_score:.3f}, {references.max_agent} "
                f"{references.max_score:.3f} ({references.episodes} layouts, "
                f"{time.perf_counter() - start:.1f} s)"
            )
            for source in todo:
                written = write_agent_dataset(source, seeds, references, args.overwrite)
                print(
                    f"{written.dataset_id}: {written.episodes} episodes, {written.steps} steps, "
                    f"mean return {written.mean_return:.3f}, {written.seconds:.1f} s"
                )


if __name__ == "__main__":
    main()
