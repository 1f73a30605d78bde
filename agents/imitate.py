"""Clone the GPIS probe planner into the PPO recipe's network, with DAgger (the command)::

    python -m agents.imitate --map gpis --seed 0 --out runs/imitation
    python -m agents.imitate --map occupancy --seed 0 --demo-episodes 2000 --dagger-rounds 3

A thin CLI over ``agents.imitation.training.imitate``, which documents the run it writes.
The result evaluates as any run (``agents.evaluate --runs``) and warm-starts PPO
fine-tuning (``agents.train --init-from``).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from agents.imitation.cloning import CloningSettings
from agents.imitation.training import ImitationSettings, imitate
from agents.run_dir import ALGORITHMS
from tactile_search.envs.config import MAP_MODES


def main(argv: list[str] | None = None) -> None:
    defaults = ImitationSettings()
    cloning = CloningSettings()
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--algo", choices=ALGORITHMS, default="ppo", help="whose network")
    parser.add_argument("--map", choices=MAP_MODES, default="gpis", dest="map_mode")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--out", type=Path, default=Path("runs/imitation"))
    parser.add_argument("--hyperparams", type=Path, help="a PPO recipe file instead of the default")
    parser.add_argument("--demo-episodes", type=int, default=defaults.demo_episodes)
    parser.add_argument("--dagger-rounds", type=int, default=defaults.dagger_rounds)
    parser.add_argument("--dagger-episodes", type=int, default=defaults.dagger_episodes)
    parser.add_argument(
        "--epochs", type=int, default=cloning.epochs, help="passes over the teacher's demos"
    )
    parser.add_argument(
        "--dagger-epochs",
        type=int,
        default=defaults.dagger_epochs,
        help="passes over everything gathered, after each DAgger round",
    )
    parser.add_argument("--batch-size", type=int, default=cloning.batch_size)
    parser.add_argument("--learning-rate", type=float, default=cloning.learning_rate)
    parser.add_argument(
        "--demos",
        type=Path,
        help="an .npz keeping the teacher's demonstrations: read if it exists, else written",
    )
    parser.add_argument(
        "--mirror", action="store_true", help="clone the mirror image of every state too"
    )
    parser.add_argument(
        "--teacher",
        default=defaults.teacher,
        help="who labels the states: the planner, or ensemble:RUN,RUN,... (trained runs acting "
        "as one; agents.imitation.teachers)",
    )
    parser.add_argument(
        "--label", default="imitation", help="the agent's name in tables (a variant's name)"
    )
    parser.add_argument("--torch-threads", type=int, default=1)
    parser.add_argument("--quiet", action="store_true", help="no progress lines")
    args = parser.parse_args(argv)
    try:
        settings = ImitationSettings(
            demo_episodes=args.demo_episodes,
            dagger_rounds=args.dagger_rounds,
            dagger_episodes=args.dagger_episodes,
            dagger_epochs=args.dagger_epochs,
            mirror=args.mirror,
            teacher=args.teacher,
            cloning=CloningSettings(
                epochs=args.epochs,
                batch_size=args.batch_size,
                learning_rate=args.learning_rate,
                seed=args.seed,
            ),
        )
    except (TypeError, ValueError) as err:
        parser.error(str(err))
    run_dir = imitate(
        args.map_mode,
        out=args.out,
        seed=args.seed,
        settings=settings,
        hyperparams=args.hyperparams,
        torch_threads=args.torch_threads,
        progress=not args.quiet,
        demonstrations_file=args.demos,
        label=args.label,
        algo=args.algo,
    )
    print(run_dir)


if __name__ == "__main__":
    main()
