"""What the vector env's Python costs per batch step beyond the core's own step.

Two vector envs of the same settings, reset on the same layouts: one takes random actions
through ``CupboardSearchVectorEnv.step`` (the gymnasium face: seeding, autoreset
bookkeeping, the episode log, the info's masks, copies), the other's batch then replays
the very calls the face made to its batch (the same actions and autoresets: the core's
work alone, the reference measured in the same run). Rounds alternate between the two, so
the machine's load swings hit both. Both do the same work whatever rule draws new layouts:
the figure is the face's cost, not the layouts'.

Run it on two builds (``PYTHONPATH`` at each checkout's ``python/``) to compare faces side
by side on equal work:

    python -m benchmarks.vector_overhead --num-envs 8 16 [--json results/vector_overhead.json]
"""

from __future__ import annotations

import argparse
import statistics
import time
from pathlib import Path

import numpy as np
from gymnasium.spaces import MultiDiscrete

from benchmarks.arguments import positive_int
from benchmarks.performance_page import write_json
from tactile_search import CupboardSearchVectorEnv
from tactile_search.envs.config import ACTION_MODES, MAP_MODES


class RecordedBatch:
    """A batch that records the ``step`` calls made to it (then replayed on another)."""

    def __init__(self, batch: object) -> None:
        self.batch = batch
        self.calls: list[tuple] = []

    def step(self, actions: np.ndarray, resets: list | None = None) -> tuple:
        self.calls.append((actions, resets))
        return self.batch.step(actions, resets)

    def __getattr__(self, name: str) -> object:
        return getattr(self.batch, name)


def env_pair(mode: str, action_mode: str, num_envs: int) -> tuple:
    """The env stepped through its face (its batch recorded) and the env whose batch
    replays those calls."""
    settings = {"map": mode, "action_mode": action_mode, "threads": 1}
    pair = tuple(CupboardSearchVectorEnv(num_envs=num_envs, **settings) for _ in range(2))
    for env in pair:
        env.reset(seed=list(range(num_envs)))
    pair[0]._batch = RecordedBatch(pair[0]._batch)
    return pair


def random_actions(env: CupboardSearchVectorEnv, count: int, seed: int) -> list[np.ndarray]:
    rng = np.random.default_rng(seed)
    single = env.single_action_space
    if isinstance(single, MultiDiscrete):
        return [rng.integers(0, single.nvec, (env.num_envs, 3)) for _ in range(count)]
    return [rng.uniform(-1, 1, (env.num_envs, 3)) for _ in range(count)]


def measure(mode: str, action_mode: str, num_envs: int, steps: int, rounds: int) -> dict:
    """Median µs per batch step through the face and through the batch alone."""
    face, core = env_pair(mode, action_mode, num_envs)
    actions = random_actions(face, steps, seed=0)
    per_round = steps // rounds
    times: dict[str, list[float]] = {"face": [], "core": []}
    for r in range(rounds):
        chunk = actions[r * per_round : (r + 1) * per_round]
        start = time.perf_counter()
        for action in chunk:
            face.step(action)
        times["face"].append((time.perf_counter() - start) / len(chunk) * 1e6)
        calls, face._batch.calls = face._batch.calls, []
        start = time.perf_counter()
        for action, resets in calls:
            core._batch.step(action, resets)
        times["core"].append((time.perf_counter() - start) / len(chunk) * 1e6)
    return {key: statistics.median(values) for key, values in times.items()}


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--num-envs", type=positive_int, nargs="+", default=[8, 16])
    parser.add_argument("--modes", nargs="+", choices=MAP_MODES, default=list(MAP_MODES))
    parser.add_argument(
        "--action-modes", nargs="+", choices=ACTION_MODES, default=list(ACTION_MODES)
    )
    parser.add_argument("--steps", type=positive_int, default=2000, help="batch steps per env")
    parser.add_argument("--rounds", type=positive_int, default=10)
    parser.add_argument("--json", type=Path, default=None, help="write the figures here too")
    args = parser.parse_args(argv)
    rows = []
    print("us per batch step, one thread: through the vector env's face / the batch alone")
    for mode in args.modes:
        for action_mode in args.action_modes:
            steps = args.steps if action_mode == "wrist" else max(args.rounds, args.steps // 20)
            for num_envs in args.num_envs:
                t = measure(mode, action_mode, num_envs, steps, args.rounds)
                print(
                    f"  {mode:9s} {action_mode:5s} {num_envs:3d} envs: face {t['face']:9.1f}"
                    f"  core {t['core']:9.1f}  face's cost {t['face'] - t['core']:+7.1f} us"
                    f" ({t['face'] / t['core']:.3f}x)"
                )
                rows.append({
                    "map": mode, "action_mode": action_mode, "num_envs": num_envs,
                    "batch_steps": steps, "face_us": t["face"], "core_us": t["core"],
                    "cost_us": t["face"] - t["core"], "ratio": t["face"] / t["core"],
                })  # fmt: skip
    if args.json is not None:
        figures = {"steps": args.steps, "rounds": args.rounds, "rows": rows}
        write_json(args.json, "benchmarks.vector_overhead", argv, figures)


if __name__ == "__main__":
    main()
