"""Throughput of CupboardSearch-v0: steps per second, reset time, step time vs index, memory.

Prints, per map mode (gpis, occupancy, none):
- steps/s of one env on one core over whole episodes (resets included), with a random
  policy and with the oracle (which touches jars, so the GPIS grows);
- median reset time;
- median step time by step index bucket (it must stay flat as the GPIS grows);
- resident memory added per env (16 envs built, reset and stepped after the baseline);
and the speed-up of the vector env (one Rust batch on all cores) over the same batch on one
thread, for 8 and 16 envs in both action modes (``wrist`` and ``probe``, random actions;
totals over alternating rounds, resets included; with ``copy=False`` too where the env has
it), each with the machine's load average (``/proc/loadavg``) beside it. The machine is
shared and noisy: compare ratios from one run, and distrust a speed-up measured while the
load average is above the free cores.

Usage (from the repository root): ``python -m benchmarks.env_throughput [--steps 3000]
[--modes gpis none] [--action-modes wrist probe] [--num-envs 8 16] [--vector-only]
[--json results/env_throughput.json]`` (``--json``: the figures for ``docs/PERFORMANCE.md``,
``benchmarks.performance_page``)
"""

from __future__ import annotations

import argparse
import inspect
import multiprocessing
import os
import statistics
import time
from pathlib import Path
from typing import Any

import numpy as np
from gymnasium.spaces import MultiDiscrete

from benchmarks.performance_page import write_json
from tactile_search import CupboardSearchEnv, CupboardSearchVectorEnv
from tactile_search.envs.config import ACTION_MODES, MAP_MODES


def rss_mib() -> float:
    """Current resident set size of this process, MiB (from /proc; Linux only)."""
    with open("/proc/self/status") as status:
        for line in status:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024
    raise RuntimeError("VmRSS not found in /proc/self/status")


def run_policy(mode: str, policy: str, steps: int, seed: int) -> dict[str, float]:
    """Steps one env for ``steps`` steps over whole episodes; returns timings."""
    env = CupboardSearchEnv(map=mode, threads=1)
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


def load_average() -> str:
    """The 1-minute load average (``/proc/loadavg``), or ``"?"`` where there is none."""
    try:
        with open("/proc/loadavg") as loadavg:
            return loadavg.read().split()[0]
    except OSError:
        return "?"


def random_actions(env: CupboardSearchVectorEnv, rng: np.random.Generator) -> np.ndarray:
    """One random action per episode: wrist motions in [-1, 1]^3, or probe indices."""
    single = env.single_action_space
    if isinstance(single, MultiDiscrete):  # the probe mode
        return rng.integers(0, single.nvec, (env.num_envs, len(single.nvec)))
    return rng.uniform(-1, 1, (env.num_envs, *single.shape))


def vector_speedup(
    mode: str, num_envs: int, steps: int, rounds: int = 12, **kwargs: object
) -> dict[int | None, dict[str, float]]:
    """Steps/s of one batch of ``num_envs`` on 1 thread (key 1) and on every core (key
    None) over ``rounds`` short alternating rounds of ``steps / rounds`` batch steps (the
    machine is shared: fine alternation spreads its load swings over both), random actions
    of the env's action mode, one stream for each env, the same for both. The figures are
    totals over the rounds, whole episodes with their resets: a median of rounds would
    leave out the few rounds that hold the resets (all sub-envs time out in the same batch
    step). Where the batch reports the time its episodes' work took with the GIL released
    (``parallel_seconds``), also the ms per batch step of that parallel part and of the
    serial rest. ``kwargs`` go to the vector env (``copy=False``, ``action_mode``)."""
    envs = {
        threads: CupboardSearchVectorEnv(num_envs=num_envs, threads=threads, map=mode, **kwargs)
        for threads in (1, None)
    }
    totals = {t: {"steps": 0, "seconds": 0.0, "inside": 0.0} for t in envs}
    for vector in envs.values():
        vector.reset(seed=0)
    # One stream of actions per env, going on from round to round (a stream restarted
    # every round would repeat its first steps' actions over and over).
    streams = {threads: np.random.default_rng(0) for threads in envs}
    for _ in range(rounds):
        for threads, vector in envs.items():
            rng = streams[threads]
            actions = [random_actions(vector, rng) for _ in range(steps // rounds)]
            inside = getattr(vector._batch, "parallel_seconds", float("nan"))
            start = time.perf_counter()
            for action in actions:
                vector.step(action)
            totals[threads]["seconds"] += time.perf_counter() - start
            totals[threads]["inside"] += (
                getattr(vector._batch, "parallel_seconds", float("nan")) - inside
            )
            totals[threads]["steps"] += len(actions)
    return {
        t: {
            "rate": num_envs * total["steps"] / total["seconds"],
            "parallel_ms": 1e3 * total["inside"] / total["steps"],
            "serial_ms": 1e3 * (total["seconds"] - total["inside"]) / total["steps"],
        }
        for t, total in totals.items()
    }


def _burn(count: int) -> float:
    """CPU-bound work of a known size; returns its wall-clock seconds."""
    start = time.perf_counter()
    total = 0
    for i in range(count):
        total += i * i
    return time.perf_counter() - start


def free_cores(count: int = 3_000_000, rounds: int = 3) -> float:
    """How many cores this process can get right now: the work two processes do at once
    over the work one does alone in the same time (2.0 on two idle cores). The control for
    the vector env's speed-up on a machine shared with other jobs."""
    ratios = []
    with multiprocessing.get_context("spawn").Pool(2) as pool:
        pool.map(_burn, [1000, 1000])  # start both workers
        for _ in range(rounds):
            alone = pool.apply(_burn, (count,))
            together = max(pool.map(_burn, [count, count]))
            ratios.append(2 * alone / together)
    return statistics.median(ratios)


def _synced_bursts(barrier: Any, bursts: int, count: int) -> None:
    """``bursts`` bursts of work, each followed by waiting for the other worker."""
    for _ in range(bursts):
        _burn(count)
        barrier.wait()


def synced_free_cores(bursts: int = 300, count: int = 60_000) -> float:
    """Like ``free_cores``, but the two processes meet at a barrier after every burst of a
    few ms, as the batch's workers do after every step: on a machine shared with other jobs,
    a worker that loses its time slice holds the other up, so this is the ceiling for a
    batch stepped in lock step (2.0 on two idle cores)."""
    context = multiprocessing.get_context("spawn")
    start = time.perf_counter()
    _burn(2 * bursts * count)
    alone = time.perf_counter() - start
    barrier = context.Barrier(2)
    workers = [
        context.Process(target=_synced_bursts, args=(barrier, bursts, count)) for _ in range(2)
    ]
    for worker in workers:
        worker.start()
    start = time.perf_counter()
    for worker in workers:
        worker.join()
    together = time.perf_counter() - start
    return alone / together


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
    parser.add_argument("--modes", nargs="+", default=list(MAP_MODES))
    parser.add_argument("--num-envs", type=int, nargs="+", default=[8, 16], help="vector env sizes")
    parser.add_argument(
        "--action-modes",
        nargs="+",
        choices=ACTION_MODES,
        default=list(ACTION_MODES),
        help="vector env action modes",
    )
    parser.add_argument("--vector-only", action="store_true", help="only the vector env speed-ups")
    parser.add_argument("--json", type=Path, default=None, help="write the figures here too")
    args = parser.parse_args(argv)
    figures: dict[str, Any] = {
        "controls": {}, "single": [], "vector": [], "memory_mib_per_env": {},
    }  # fmt: skip
    controls = figures["controls"]
    print(f"cores: {os.cpu_count()}; shared, noisy machine: medians from one run")
    controls["free_cores_before"] = free_cores()
    print(
        f"control: two CPU-bound processes get {controls['free_cores_before']:.2f}x the work of one"
    )
    controls["synced_free_cores"] = synced_free_cores()
    print(
        f"control: two processes meeting after every burst of a few ms get "
        f"{controls['synced_free_cores']:.2f}x the work of one"
    )
    for mode in args.modes:
        print(f"\n== map={mode}")
        for policy in () if args.vector_only else ("random", "oracle"):
            r = run_policy(mode, policy, args.steps, seed=0)
            figures["single"].append({"map": mode, "policy": policy, **r})
            flat = " ".join(f"{25 * k}+:{v:.2f}" for k, v in r["by_index"].items())
            print(
                f"  {policy:>6}: {r['steps_per_s']:7.0f} steps/s over {r['episodes']} episodes "
                f"(resets included), median step {r['step_ms']:.3f} ms, "
                f"median reset {r['reset_ms']:.1f} ms"
            )
            print(f"          median step ms by step index: {flat}")
        variants: list[tuple[str, dict]] = [("", {})]
        if "copy" in inspect.signature(CupboardSearchVectorEnv.__init__).parameters:
            variants.append((", copy=False", {"copy": False}))
        for action_mode in args.action_modes:
            # A probe step is 10 to 60 wrist motions: fewer batch steps measure as long. At
            # the defaults a wrist-mode batch of 16 takes 1,500 steps, seven episodes each.
            per_step = 1 if action_mode == "wrist" else 5
            for num_envs in args.num_envs:
                for label, kwargs in variants:
                    steps = max(8 * args.steps // (num_envs * per_step), 120 // per_step, 12)
                    load = load_average()
                    r = vector_speedup(mode, num_envs, steps, action_mode=action_mode, **kwargs)
                    one, every = r[1], r[None]
                    figures["vector"].append({
                        "map": mode, "action_mode": action_mode, "num_envs": num_envs,
                        "copy": kwargs.get("copy", True), "batch_steps": steps,
                        "rate_one_thread": one["rate"], "rate_all_cores": every["rate"],
                        "speedup": every["rate"] / one["rate"],
                        "load_before": load, "load_after": load_average(),
                        "parallel_ms": [one["parallel_ms"], every["parallel_ms"]],
                        "serial_ms": [one["serial_ms"], every["serial_ms"]],
                    })  # fmt: skip
                    print(
                        f"  vector env ({action_mode}, {num_envs} envs{label}): "
                        f"{one['rate']:.0f} steps/s on 1 thread, {every['rate']:.0f} on all "
                        f"cores, speed-up {every['rate'] / one['rate']:.2f}x "
                        f"(load average {load} before, {load_average()} after)"
                    )
                    if not np.isnan(one["parallel_ms"]):
                        print(
                            f"          per batch step: parallel part {one['parallel_ms']:.2f} "
                            f"ms on 1 thread, {every['parallel_ms']:.2f} ms on all cores "
                            f"({one['parallel_ms'] / every['parallel_ms']:.2f}x); serial part "
                            f"{one['serial_ms']:.3f} / {every['serial_ms']:.3f} ms"
                        )
        if not args.vector_only:
            figures["memory_mib_per_env"][mode] = memory_per_env(mode)
            print(f"  resident memory added per env: {figures['memory_mib_per_env'][mode]:.2f} MiB")
    controls["free_cores_after"] = free_cores()
    print(
        f"control: two CPU-bound processes get {controls['free_cores_after']:.2f}x the work of one"
    )
    if args.json is not None:
        write_json(args.json, "benchmarks.env_throughput", argv, figures)


if __name__ == "__main__":
    main()
