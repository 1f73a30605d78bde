"""What making an environment costs: ``gym.make`` and ``gym.make_vec`` of 16 envs.

Each round makes one single env and one vector env of 16 (``vector_entry_point``), then
one MuJoCo Pusher-v5 env (the reference, measured in the same rounds so the machine's load
swings hit all three). Only construction is timed; the env is closed and dropped after.
Prints the median of the rounds in milliseconds and as Pusher-v5 constructions.

    python -m benchmarks.construction --rounds 15
"""

from __future__ import annotations

import argparse
import statistics
import time
from collections.abc import Callable
from pathlib import Path

import gymnasium as gym

import tactile_search
from benchmarks.arguments import positive_int
from benchmarks.performance_page import write_json


def seconds_to_make(make: Callable[[], gym.Env | gym.vector.VectorEnv]) -> float:
    """Wall-clock seconds of one ``make()``; the env is closed after the clock stops."""
    started = time.perf_counter()
    env = make()
    elapsed = time.perf_counter() - started
    env.close()
    return elapsed


def makers(num_envs: int, map_mode: str) -> dict[str, Callable[[], object]]:
    """The constructions measured, by name."""

    def single() -> gym.Env:
        return gym.make(tactile_search.ENV_ID, map=map_mode)

    def vector() -> gym.vector.VectorEnv:
        return gym.make_vec(
            tactile_search.ENV_ID,
            num_envs=num_envs,
            vectorization_mode="vector_entry_point",
            map=map_mode,
        )

    def pusher() -> gym.Env:
        return gym.make("Pusher-v5")

    return {"gym.make": single, f"gym.make_vec({num_envs})": vector, "Pusher-v5": pusher}


def measure(rounds: int, num_envs: int, map_mode: str) -> dict[str, float]:
    """Median seconds per construction over ``rounds`` alternating rounds (one warm-up
    round first, not counted)."""
    named = makers(num_envs, map_mode)
    times: dict[str, list[float]] = {name: [] for name in named}
    for round_index in range(rounds + 1):
        for name, make in named.items():
            elapsed = seconds_to_make(make)
            if round_index:
                times[name].append(elapsed)
    return {name: statistics.median(values) for name, values in times.items()}


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rounds", type=positive_int, default=15)
    parser.add_argument("--num-envs", type=positive_int, default=16)
    parser.add_argument("--map", default="gpis", help="the map mode of the envs made")
    parser.add_argument("--json", type=Path, help="also write the figures to this JSON file")
    args = parser.parse_args(argv)
    medians = measure(args.rounds, args.num_envs, args.map)
    reference = medians["Pusher-v5"]
    print(f"construction, map={args.map}, median of {args.rounds} rounds:")
    for name, seconds in medians.items():
        print(f"  {name:<18} {1e3 * seconds:8.2f} ms  {seconds / reference:7.2f}x Pusher-v5")
    if args.json:
        figures = {"rounds": args.rounds, "map": args.map, "num_envs": args.num_envs}
        figures["seconds"] = medians
        write_json(args.json, "benchmarks.construction", argv, figures)


if __name__ == "__main__":
    main()
