"""Train RLlib's PPO (new API stack) on ``CupboardSearch-v0`` (the command)::

    python -m agents.rllib_ppo --map gpis --env-runners 2 --envs-per-runner 4 --iterations 5
    python -m agents.rllib_ppo --map none --grid-shape 36 72 --setting max_steps=64
    RAY_ADDRESS=HEAD:6379 python -m agents.rllib_ppo --map gpis --out runs/rllib_gpis

A thin CLI over ``agents.rllib.training``, which documents the setup.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence

from agents.command_args import parse_setting
from agents.rllib.training import train_rllib
from tactile_search.envs.config import MAP_MODES


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--map", choices=MAP_MODES, default="gpis")
    parser.add_argument("--env-runners", type=int, default=2)
    parser.add_argument("--envs-per-runner", type=int, default=4)
    parser.add_argument("--fragment", type=int, default=128, help="env steps per env a round")
    parser.add_argument("--iterations", type=int, default=5)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument(
        "--address",
        default=None,
        help="a Ray cluster's address (default: RAY_ADDRESS, else a fresh Ray on this machine)",
    )
    parser.add_argument("--out", default=None, help="save the algorithm here at the end")
    parser.add_argument("--grid-shape", type=int, nargs=2, metavar=("H", "W"), default=None)
    parser.add_argument(
        "--setting",
        type=parse_setting,
        action="append",
        default=[],
        metavar="KEY=VALUE",
        help="an env setting (CupboardSearchConfig field), repeatable",
    )
    args = parser.parse_args(argv)
    settings = dict(args.setting)
    if args.grid_shape is not None:
        settings["grid_shape"] = tuple(args.grid_shape)
    rows = train_rllib(
        iterations=args.iterations,
        address=args.address,
        out=args.out,
        map_mode=args.map,
        env_runners=args.env_runners,
        envs_per_runner=args.envs_per_runner,
        fragment=args.fragment,
        seed=args.seed,
        settings=settings,
    )
    later = rows[1:] or rows
    steps = sum(r["env_steps"] for r in later)
    seconds = sum(r["seconds"] for r in later)
    first, last = later[0]["iteration"], rows[-1]["iteration"]
    print(f"{steps / seconds:.0f} env steps/s over iterations {first}-{last}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
