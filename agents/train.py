"""Train a stable-baselines3 agent on a registered id, ``tactile_search/CupboardSearch-v0``
by default (the command)::

    python -m agents.train --algo ppo --map gpis --seed 0 --out runs
    python -m agents.train --env-id tactile_search/IdentifyByTouch-v0 --out runs/identify
    python -m agents.train --algo recurrent_ppo --map none --timesteps 200000
    python -m agents.train --algo ppo --map gpis --seed 0 --out runs --resume

A thin CLI over ``agents.imitation.clone_stage.train_with_clone_stage``: a PPO recipe's clone
stage (the recipe's teacher, the GPIS probe planner unless it names another, cloned into the
network, ``--imitation`` overrides its settings,
``--from-scratch`` skips it), then ``agents.sb3.training.train``, which documents the run
it writes.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from agents.command_args import parse_setting
from agents.imitation.clone_stage import train_with_clone_stage
from agents.run_dir import MODEL_FILE
from agents.sb3.recipes import ALGORITHMS
from agents.sb3.training import (
    DEFAULT_CHECKPOINT_EVERY,
    DEFAULT_KEEP_CHECKPOINTS,
    DEFAULT_TORCH_THREADS,
    INTERRUPTED_EXIT_STATUS,
    TrainSettings,
)
from tactile_search import ENV_ID, ENV_IDS
from tactile_search.envs.config import MAP_MODES


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--algo", choices=ALGORITHMS, default="ppo")
    parser.add_argument("--map", choices=MAP_MODES, default="gpis", dest="map_mode")
    parser.add_argument(
        "--env-id",
        choices=ENV_IDS,
        default=ENV_ID,
        help="the registered id to train on: its task and settings, and the recipe keyed by "
        "it (a run directory's name does not say the id: give each id its own --out)",
    )
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--timesteps", type=int, help="override the recipe's n_timesteps")
    parser.add_argument("--n-envs", type=int, help="override the recipe's n_envs")
    parser.add_argument("--max-minutes", type=float, help="stop after this much wall-clock")
    parser.add_argument("--torch-threads", type=int, default=DEFAULT_TORCH_THREADS)
    parser.add_argument(
        "--env-threads", type=int, help="the environment batch's threads (default: every core)"
    )
    parser.add_argument("--out", type=Path, default=Path("runs"))
    parser.add_argument("--label", help="the agent's name in tables instead of the algo")
    parser.add_argument("--hyperparams", type=Path, help="a recipe file instead of the default")
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    parser.add_argument(
        "--checkpoint-every",
        type=int,
        default=DEFAULT_CHECKPOINT_EVERY,
        help="env steps between checkpoints (taken at the next rollout boundary)",
    )
    parser.add_argument(
        "--keep-checkpoints",
        type=int,
        default=DEFAULT_KEEP_CHECKPOINTS,
        help="how many of the newest checkpoints to keep",
    )
    parser.add_argument(
        "--resume",
        action="store_true",
        help="continue the run in --out from its newest checkpoint to its total timesteps",
    )
    parser.add_argument(
        "--init-from",
        type=Path,
        help=f"warm start: a run directory (or {MODEL_FILE}) whose policy weights this run "
        "starts from",
    )
    parser.add_argument(
        "--imitation",
        nargs="+",
        type=parse_setting,
        metavar="KEY=VALUE",
        help="override keys of the recipe's imitation section (demo_episodes=200 "
        "dagger_rounds=1 cloning={epochs: 10})",
    )
    parser.add_argument(
        "--from-scratch",
        action="store_true",
        help="PPO from fresh weights: skip the recipe's imitation section (the clone stage)",
    )
    args = parser.parse_args(argv)
    settings = TrainSettings(
        args.algo,
        args.map_mode,
        env_id=args.env_id,
        out=args.out,
        seed=args.seed,
        timesteps=args.timesteps,
        n_envs=args.n_envs,
        torch_threads=args.torch_threads,
        env_threads=args.env_threads,
        progress_bar=not args.no_progress,
        hyperparams=args.hyperparams,
        max_minutes=args.max_minutes,
        checkpoint_every=args.checkpoint_every,
        keep_checkpoints=args.keep_checkpoints,
        resume=args.resume,
        init_from=args.init_from,
        from_scratch=args.from_scratch,
        label=args.label,
    )
    try:
        run_dir = train_with_clone_stage(settings, dict(args.imitation) if args.imitation else None)
    except KeyboardInterrupt:
        sys.exit(INTERRUPTED_EXIT_STATUS)
    print(f"trained {run_dir}")


if __name__ == "__main__":
    main()
