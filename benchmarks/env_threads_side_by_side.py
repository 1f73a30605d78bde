"""What the single env's helper thread gives, and costs, when processes share the cores.

``CupboardSearchEnv(threads=2)`` (the default) lends each reset to a helper thread. Alone
on a machine that makes random probes faster (``python -m benchmarks.peer_envs``); this
measures the other case, envs already run one per core or more (``SubprocVecEnv``,
evaluation workers, trials side by side), where a helper finds no idle core.

For each count of processes in ``--processes``, it starts that many processes at once, each
stepping one ``gymnasium.make`` env of the probe mode with the GPIS map with random probes
(resets included) for ``--seconds`` from a common start, once with ``threads=1`` and once
with ``threads=2``, alternating over ``--rounds`` rounds so that the shared machine's load
hits both alike. The machine's rate is the sum of the processes' probes/s. It prints each
round, then per process count the median machine rate of each setting and their ratio,
with the load average. From the repository root::

    python -m benchmarks.env_threads_side_by_side [--processes 1 2 4 8] [--rounds 3]
        [--seconds 8] [--json results/env_threads_side_by_side.json]
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

from benchmarks.arguments import positive_int
from benchmarks.performance_page import write_json

THREAD_COUNTS = (1, 2)
#: Seconds between launching a round's processes and their common start (their imports).
START_DELAY = 3.0


def worker(threads: int, start: float, seconds: float, seed: int) -> None:
    """Waits until ``start`` (a ``time.time()``), then takes random probes for ``seconds``
    and prints ``{"probes_per_s": ...}``."""
    import gymnasium as gym

    from tactile_search import ENV_ID  # importing the package registers the env

    env = gym.make(ENV_ID, action_mode="probe", map="gpis", threads=threads)
    env.action_space.seed(seed)
    env.reset(seed=seed)
    time.sleep(max(0.0, start - time.time()))
    probes, began = 0, time.perf_counter()
    while time.perf_counter() - began < seconds:
        _, _, terminated, truncated, _ = env.step(env.action_space.sample())
        probes += 1
        if terminated or truncated:
            env.reset()
    rate = probes / (time.perf_counter() - began)
    env.close()
    print(json.dumps({"probes_per_s": rate}))


def machine_rate(processes: int, threads: int, seconds: float, seed: int) -> float:
    """Sum of the probes/s of ``processes`` envs of ``threads`` run side by side."""
    start = time.time() + START_DELAY
    launched = [
        subprocess.Popen(
            [
                sys.executable, "-m", "benchmarks.env_threads_side_by_side", "--worker",
                str(threads), repr(start), repr(seconds), str(seed + index),
            ],
            stdout=subprocess.PIPE,
            text=True,
        )
        for index in range(processes)
    ]  # fmt: skip
    total = 0.0
    for process in launched:
        out, _ = process.communicate()
        if process.returncode != 0:
            raise RuntimeError(f"a worker failed with exit code {process.returncode}")
        total += json.loads(out.strip().splitlines()[-1])["probes_per_s"]
    return total


def main(argv: list[str] | None = None) -> None:
    if argv is None and len(sys.argv) > 1 and sys.argv[1] == "--worker":
        threads, start, seconds, seed = sys.argv[2:6]
        worker(int(threads), float(start), float(seconds), int(seed))
        return
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--processes", type=positive_int, nargs="+", default=[1, 2, 4, 8])
    parser.add_argument("--rounds", type=positive_int, default=3)
    parser.add_argument("--seconds", type=float, default=8.0)
    parser.add_argument("--seed", type=int, default=1_000_000)
    parser.add_argument("--json", type=Path, default=None, help="write the figures here too")
    args = parser.parse_args(argv)
    if not args.seconds > 0:
        parser.error(f"--seconds must be > 0, got {args.seconds}")
    cores = len(os.sched_getaffinity(0))
    print(f"{cores} cores; random probes (GPIS map) per second per machine")
    rates: dict[tuple[int, int], list[float]] = {}
    for processes in args.processes:
        for round_index in range(args.rounds):
            for threads in THREAD_COUNTS:
                rate = machine_rate(processes, threads, args.seconds, args.seed)
                rates.setdefault((processes, threads), []).append(rate)
                print(
                    f"  round {round_index + 1}: {processes} processes, threads={threads}: "
                    f"{rate:8.1f} probes/s  (load {os.getloadavg()[0]:.2f})",
                    flush=True,
                )
    print("median machine rate: threads=1, threads=2, ratio")
    medians = []
    for processes in args.processes:
        one, two = (statistics.median(rates[(processes, t)]) for t in THREAD_COUNTS)
        print(f"  {processes} processes: {one:8.1f}  {two:8.1f}  {two / one:5.2f}x")
        medians.append(
            {"processes": processes, "threads_1": one, "threads_2": two, "ratio": two / one}
        )
    if args.json is not None:
        figures = {
            "cores": cores, "rounds": args.rounds, "seconds": args.seconds, "medians": medians,
            "rounds_probes_per_s": [
                {"processes": p, "threads": t, "probes_per_s": values}
                for (p, t), values in rates.items()
            ],
        }  # fmt: skip
        write_json(args.json, "benchmarks.env_threads_side_by_side", argv, figures)


if __name__ == "__main__":
    main()
