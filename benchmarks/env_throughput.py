"""Throughput of CupboardSearch-v0: steps per second, reset time, step time vs index, memory.

Prints, per map mode (gpis, occupancy, none):
- steps/s of one env on one core over whole episodes (resets included), with a random
  policy and with the oracle (which touches jars, so the GPIS grows);
- median reset time;
- median step time by step index bucket (it must stay flat as the GPIS grows);
- resident memory added per env (16 envs built, reset and stepped after the baseline);
and the speed-up of the vector env (one Rust batch on all cores) over the same batch on one
thread. The machine is shared and noisy: compare medians and ratios from one run.

Usage: ``python benchmarks/env_throughput.py [--steps 3000] [--modes gpis none]``
"""

from __future__ import annotations

import argparse
import os
import statistics
import time

import numpy as np

from tactile_search import CupboardSearchEnv, CupboardSearchVectorEnv


def rss_mib() -> float:
    """Current resident set size of this process, MiB (from /proc; Linux only)."""
    with open("/proc/self/status") as status:
        for line in status:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024
    raise RuntimeError("VmRSS not found in /proc/self/status")


def run_policy(mode: str, policy: str, steps: int, seed: int) -> dict[str, float]:
    """Steps one env for ``steps`` steps over whole episodes; returns timings."""
    env = CupboardSearchEnv(map=mode)
    rng = np.random.default_rng(seed)
    resets, step_times, by_index = [], [], {}
    episode_seed = seed
    start = time.perf_counter()
    t = time.perf_counter()
    env.reset(seed=episode_seed)
    resets.append(time.perf_counter() - t)
    index = 0
    for _ in range(steps):
        action = env.oracle_action() if policy == "oracle" else rng.uniform(-1, 1, 3)
        t = time.perf_counter()
        _, _, terminated, _, _ = env.step(action)
        elapsed = time.perf_counter() - t
        step_times.append(elapsed)
        by_index.setdefault(min(index // 25, 7), []).append(elapsed)
        index += 1
        if terminated or index >= 200:
            episode_seed += 1
            t = time.perf_counter()
            env.reset(seed=episode_seed)
            resets.append(time.perf_counter() - t)
            index = 0
    total = time.perf_counter() - start
    return {
        "steps_per_s": steps / total,
        "step_ms": 1e3 * statistics.median(step_times),
        "reset_ms": 1e3 * statistics.median(resets),
        "episodes": len(resets),
        "by_index": {k: 1e3 * statistics.median(v) for k, v in sorted(by_index.items())},
    }


def vector_speedup(mode: str, num_envs: int, steps: int) -> tuple[float, float]:
    """Steps/s of one batch of ``num_envs`` on 1 thread and on every core."""
    rates = []
    for threads in (1, None):
        vector = CupboardSearchVectorEnv(num_envs=num_envs, threads=threads, map=mode)
        vector.reset(seed=0)
        rng = np.random.default_rng(0)
        start = time.perf_counter()
        for _ in range(steps):
            vector.step(rng.uniform(-1, 1, (num_envs, 3)))
        rates.append(num_envs * steps / (time.perf_counter() - start))
    return rates[0], rates[1]


def memory_per_env(mode: str, count: int = 16) -> float:
    """Resident memory added by ``count`` more envs (each reset and stepped), MiB per env."""
    before = rss_mib()
    envs = [CupboardSearchEnv(map=mode) for _ in range(count)]
    for seed, env in enumerate(envs):
        env.reset(seed=seed)
        for _ in range(50):
            if env.step(env.oracle_action())[2]:
                break
    return (rss_mib() - before) / count


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=3000, help="steps per measurement")
    parser.add_argument("--modes", nargs="+", default=["gpis", "occupancy", "none"])
    parser.add_argument("--num-envs", type=int, default=8, help="vector env size")
    args = parser.parse_args(argv)
    print(f"cores: {os.cpu_count()}; shared, noisy machine: medians from one run")
    for mode in args.modes:
        print(f"\n== map={mode}")
        for policy in ("random", "oracle"):
            r = run_policy(mode, policy, args.steps, seed=0)
            flat = " ".join(f"{25 * k}+:{v:.2f}" for k, v in r["by_index"].items())
            print(
                f"  {policy:>6}: {r['steps_per_s']:7.0f} steps/s over {r['episodes']} episodes "
                f"(resets included), median step {r['step_ms']:.3f} ms, "
                f"median reset {r['reset_ms']:.1f} ms"
            )
            print(f"          median step ms by step index: {flat}")
        one, every = vector_speedup(mode, args.num_envs, max(args.steps // args.num_envs, 50))
        print(
            f"  vector env ({args.num_envs} envs): {one:.0f} steps/s on 1 thread, "
            f"{every:.0f} on all cores, speed-up {every / one:.2f}x"
        )
        print(f"  resident memory added per env: {memory_per_env(mode):.2f} MiB")


if __name__ == "__main__":
    main()
