"""Train behaviour cloning from a Minari dataset alone and evaluate it on validation layouts
(the command, the example of learning offline)::

    python -m agents.datasets --env-ids tactile_search/CupboardSearch-v0 \\
        --agents gpis_probe_planner --episodes 500
    python -m agents.behaviour_cloning_from_dataset \\
        --dataset tactile_search/search/gpis_probe_planner-v0 --epochs 5 --episodes 50

A thin CLI over ``agents.offline.behaviour_cloning``, which documents the network and what it
reads from the dataset. Prints the loss per epoch, then the clone's success rate, mean return
and normalised score on the first ``--episodes`` validation layouts beside the dataset's own
mean return.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import minari
import numpy as np
import torch

from agents.offline.behaviour_cloning import (
    BehaviourCloningSettings,
    evaluate_cloned_policy,
    train_behaviour_cloning,
)
from agents.offline.writing import datasets_root
from tactile_search.seed_ranges import held_out_seeds


def main(argv: list[str] | None = None) -> None:
    defaults = BehaviourCloningSettings()
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--dataset", required=True, help="a Minari dataset id")
    parser.add_argument(
        "--datasets-root",
        type=Path,
        default=None,
        help="where the dataset is (default: Minari's own, MINARI_DATASETS_PATH or "
        "~/.minari/datasets)",
    )
    parser.add_argument("--epochs", type=int, default=defaults.epochs)
    parser.add_argument("--batch-size", type=int, default=defaults.batch_size)
    parser.add_argument("--learning-rate", type=float, default=defaults.learning_rate)
    parser.add_argument("--hidden", type=int, default=defaults.hidden)
    parser.add_argument("--seed", type=int, default=defaults.seed)
    parser.add_argument("--episodes", type=int, default=20, help="validation layouts played")
    parser.add_argument(
        "--threads", type=int, default=1, help="torch's threads (the network is small)"
    )
    args = parser.parse_args(argv)
    if args.threads < 1:
        parser.error(f"--threads must be >= 1, got {args.threads}")
    torch.set_num_threads(args.threads)
    try:
        settings = BehaviourCloningSettings(
            epochs=args.epochs,
            batch_size=args.batch_size,
            learning_rate=args.learning_rate,
            hidden=args.hidden,
            seed=args.seed,
        )
        seeds = held_out_seeds("validation", args.episodes)
    except (TypeError, ValueError) as err:
        parser.error(str(err))
    with datasets_root(args.datasets_root):
        try:
            dataset = minari.load_dataset(args.dataset)
        except (FileNotFoundError, ValueError) as err:
            parser.error(str(err))
        policy, losses = train_behaviour_cloning(dataset, settings)
        for epoch, loss in enumerate(losses, 1):
            print(f"epoch {epoch}: loss {loss:.4f}")
        result = evaluate_cloned_policy(policy, dataset, seeds)
        data_return = np.mean([float(np.sum(episode.rewards)) for episode in dataset])
    print(
        f"{args.dataset}: {dataset.total_episodes} episodes, {dataset.total_steps} steps, "
        f"mean return {data_return:.3f}"
    )
    print(
        f"clone on {len(seeds)} validation layouts: success {result['success_rate']:.1%}, "
        f"mean return {result['mean_return']:.3f}, normalised score "
        f"{result['normalized_score']:.3f}"
    )


if __name__ == "__main__":
    main()
