"""Training speed of PPO against torch's thread count (the ``--torch-threads`` default).

Trains the GPIS-map PPO recipe for a fixed number of timesteps with each thread count,
alternating the counts over ``--repeats`` rounds so that a noisy machine affects them
alike, and prints the median timesteps per second of each (from the repository root)::

    python -m benchmarks.train_threads --timesteps 16384 --repeats 3
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
from pathlib import Path

import yaml

from agents.sb3.training import train


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--timesteps", type=int, default=16384)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--threads", type=int, nargs="+", default=[1, 2])
    parser.add_argument("--map", default="gpis")
    args = parser.parse_args()
    speeds: dict[int, list[float]] = {t: [] for t in args.threads}
    with tempfile.TemporaryDirectory() as tmp:
        for round_index in range(args.repeats):
            for threads in args.threads:
                run_dir = train(
                    "ppo",
                    args.map,
                    out=Path(tmp) / f"r{round_index}_t{threads}",
                    timesteps=args.timesteps,
                    torch_threads=threads,
                    progress_bar=False,
                )
                config = yaml.safe_load((run_dir / "config.yml").read_text())
                fps = config["timesteps_done"] / config["wall_clock_seconds"]
                speeds[threads].append(fps)
                print(f"round {round_index} threads {threads}: {fps:.0f} timesteps/s", flush=True)
    base = statistics.median(speeds[args.threads[0]])
    print(f"\nPPO {args.map} map, {args.timesteps} timesteps per run, {args.repeats} rounds:")
    for threads, values in speeds.items():
        median = statistics.median(values)
        print(
            f"  torch threads {threads}: median {median:.0f} timesteps/s "
            f"({median / base:.2f}x of {args.threads[0]} thread)"
        )


if __name__ == "__main__":
    main()
