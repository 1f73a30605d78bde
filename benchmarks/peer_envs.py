"""Throughput of CupboardSearch-v0 beside gymnasium's MuJoCo Pusher-v5 and Ant-v5, in one process.

Our env runs in both action modes: the ``wrist`` mode (one wrist motion a step) per map
mode of ``--maps``, and the ``probe`` mode (one probe a step, which the core's controller
carries out as many wrist motions) per map mode of ``--probe-maps``; for a probe-mode env a
step is a probe, and the wrist motions it made (``info["motions"]``) are counted too.

Every environment is made by ``gymnasium.make`` with its default wrappers (ours:
OrderEnforcing and PassiveEnvChecker, the time limit being the core's own ``max_steps``;
the MuJoCo envs: also TimeLimit, 100 steps for Pusher-v5 and 1000 for Ant-v5), and is
driven by random actions from its own seeded ``action_space``. It measures, per env:

- steps/s over whole episodes: reset when an episode terminates or is truncated, with the
  resets inside the time (the actions are sampled before each timed stretch, so sampling is
  not timed). ``--rounds`` rounds; in each, every env in turn runs ``--steps`` steps (the
  order rotates from round to round). The machine is shared and noisy: alternating in one
  process spreads its load swings over all envs alike. Reported: the median steps/s over
  the rounds with min-max, and for each of our map modes its steps/s over Pusher-v5's in
  the same round, per round and their median.
  A probe-mode env runs ``--probes`` probes a round (its steps/s are probes/s; its wrist
  motions/s are reported beside them, and both over Pusher-v5's steps/s).
- median reset and step times (µs), timed one call at a time with ``time.perf_counter_ns``
  on the same envs: ``reset(seed=seed)`` for the first ``--reset-seeds`` layout seeds of the
  validation range (``tactile_search.seed_ranges``), each followed by its whole episode of
  random steps, every step timed; the envs take turns seed by seed. Our reset is also
  given in Pusher-v5 steps (its median reset time over Pusher-v5's median step time).

``--variant KEY=VALUE ...`` adds each of our envs once more with those settings, in the same
rounds (``--variant fast_free_motion=false``: every wrist command stepped, the environment
before its fast path of free motion became the default; ``--variant threads=1``: the single
env without the helper thread it lends its resets to by default).

Needs MuJoCo (gymnasium's MuJoCo envs): ``pip install -e '.[bench]'`` (``make bench`` does).

Usage (from the repository root)::

    python -m benchmarks.peer_envs [--rounds 5] [--steps 3000] [--maps gpis none]
        [--probe-maps gpis none] [--probes 400] [--reset-seeds 50] [--variant KEY=VALUE ...]
        [--json results/peer_envs.json]
"""

from __future__ import annotations

import argparse
import importlib.metadata
import importlib.util
import os
import platform
import statistics
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import gymnasium as gym

from agents.command_args import parse_setting, settings_label
from benchmarks.performance_page import write_json
from tactile_search import ENV_ID  # importing the package registers the environment
from tactile_search.envs.config import MAP_MODES
from tactile_search.seed_ranges import VALIDATION, held_out_seeds

#: Our env's name without its namespace, in the labels.
OUR_NAME = ENV_ID.rpartition("/")[2]
REFERENCE_ID = "Pusher-v5"
PEER_IDS = (REFERENCE_ID, "Ant-v5")
#: The modules gymnasium's MuJoCo envs import (imageio: its renderer, made with every env).
MUJOCO_MODULES = ("mujoco", "imageio")
INSTALL_HINT = "pip install -e '.[bench]'"


@dataclass
class Subject:
    """One environment under test and what was measured on it."""

    label: str
    env: gym.Env
    ours: bool
    probe: bool = False  # our env in the probe action mode: a step is a probe
    needs_reset: bool = True
    rates: list[float] = field(default_factory=list)  # steps/s, one per round
    motion_rates: list[float] = field(default_factory=list)  # wrist motions/s (ours), per round
    steps: int = 0  # steps taken in the timed rounds
    episodes_ended: int = 0  # terminated or truncated in the timed rounds
    reset_ns: list[int] = field(default_factory=list)
    step_ns: list[int] = field(default_factory=list)


def check_mujoco() -> None:
    """Exits with a message naming the extra to install if MuJoCo's modules are missing."""
    missing = [name for name in MUJOCO_MODULES if importlib.util.find_spec(name) is None]
    if missing:
        sys.exit(
            f"benchmarks.peer_envs compares with gymnasium's MuJoCo envs, which need "
            f"{' and '.join(missing)} (not installed). Install the 'bench' extra: "
            f"{INSTALL_HINT}  (or `make bench`)"
        )


def version(package: str) -> str:
    """The installed version of ``package``, or ``?``."""
    try:
        return importlib.metadata.version(package)
    except importlib.metadata.PackageNotFoundError:
        return "?"


def header() -> dict[str, Any]:
    """Versions and cores, as printed and written to the JSON."""
    usable = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else None
    return {
        "gymnasium": version("gymnasium"),
        "mujoco": version("mujoco"),
        "numpy": version("numpy"),
        "python": platform.python_version(),
        "tactile_search": version("tactile_search"),
        "cpu_count": os.cpu_count(),
        "usable_cpus": usable,
    }


def make_subjects(
    maps: list[str], probe_maps: list[str], seed: int, variant: dict[str, Any] | None = None
) -> list[Subject]:
    """Our env once per map mode in the wrist mode and once per probe map mode in the probe
    mode (each once more with the ``variant`` settings, if any, its label ending with them),
    then the MuJoCo peers; each reset and its action space seeded with ``seed``."""
    variants: list[dict[str, Any]] = [{}, variant] if variant else [{}]
    subjects = []
    for settings in variants:
        suffix = f" [{settings_label(settings)}]" if settings else ""
        subjects += [
            Subject(f"{OUR_NAME} map={m}{suffix}", gym.make(ENV_ID, map=m, **settings), True)
            for m in maps
        ]
        subjects += [
            Subject(
                f"{OUR_NAME} map={m} probe{suffix}",
                gym.make(ENV_ID, map=m, action_mode="probe", **settings),
                True,
                probe=True,
            )
            for m in probe_maps
        ]
    subjects += [Subject(env_id, gym.make(env_id), False) for env_id in PEER_IDS]
    for subject in subjects:
        subject.env.action_space.seed(seed)
        subject.env.reset(seed=seed)
        subject.needs_reset = False
    return subjects


def run_steps(subject: Subject, steps: int) -> tuple[int, int, int]:
    """``steps`` random steps over whole episodes (reset on termination or truncation, the
    resets timed too); returns (elapsed ns, episodes ended, wrist motions: our env's
    ``info["motions"]`` summed, the steps for the peers)."""
    env = subject.env
    actions = [env.action_space.sample() for _ in range(steps)]
    ended = 0
    motions = 0
    start = time.perf_counter_ns()
    if subject.needs_reset:
        env.reset()
    for action in actions:
        _, _, terminated, truncated, info = env.step(action)
        motions += int(info["motions"]) if subject.ours else 1
        if terminated or truncated:
            ended += 1
            env.reset()
    elapsed = time.perf_counter_ns() - start
    subject.needs_reset = False
    return elapsed, ended, motions


def throughput(subjects: list[Subject], rounds: int, steps: int, probes: int, warmup: int) -> None:
    """Alternating rounds: each subject in turn runs ``steps`` steps per round (``probes``
    for a probe-mode env; the order rotated by one each round); fills ``rates``,
    ``motion_rates``, ``steps`` and ``episodes_ended``."""
    for subject in subjects:
        run_steps(subject, max(1, warmup // 20) if subject.probe else warmup)
    for r in range(rounds):
        shift = r % len(subjects)
        for subject in subjects[shift:] + subjects[:shift]:
            count = probes if subject.probe else steps
            elapsed, ended, motions = run_steps(subject, count)
            subject.rates.append(count / (elapsed * 1e-9))
            subject.motion_rates.append(motions / (elapsed * 1e-9))
            subject.steps += count
            subject.episodes_ended += ended


def call_times(subjects: list[Subject], seeds: int) -> None:
    """``reset(seed=seed)`` for the first ``seeds`` validation seeds and every step of the
    episode that follows, each call timed on its own; the subjects take turns seed by seed."""
    for seed in held_out_seeds("validation", seeds):
        for subject in subjects:
            env = subject.env
            start = time.perf_counter_ns()
            env.reset(seed=seed)
            subject.reset_ns.append(time.perf_counter_ns() - start)
            done = False
            while not done:
                action = env.action_space.sample()
                start = time.perf_counter_ns()
                _, _, terminated, truncated, _ = env.step(action)
                subject.step_ns.append(time.perf_counter_ns() - start)
                done = terminated or truncated
            subject.needs_reset = True


def summary(subject: Subject, reference: Subject) -> dict[str, Any]:
    """The figures of one subject (ratios to ``reference`` for ours)."""
    figures: dict[str, Any] = {
        "steps_per_s_rounds": subject.rates,
        "steps_per_s_median": statistics.median(subject.rates),
        "steps_per_s_min": min(subject.rates),
        "steps_per_s_max": max(subject.rates),
        "mean_episode_length": subject.steps / subject.episodes_ended
        if subject.episodes_ended
        else None,
        "reset_us_median": statistics.median(subject.reset_ns) / 1e3,
        "step_us_median": statistics.median(subject.step_ns) / 1e3,
        "resets_timed": len(subject.reset_ns),
        "steps_timed": len(subject.step_ns),
        "action_mode": ("probe" if subject.probe else "wrist") if subject.ours else None,
    }
    if subject.ours:
        ratios = [ours / ref for ours, ref in zip(subject.rates, reference.rates, strict=True)]
        figures["ratio_to_reference_rounds"] = ratios
        figures["ratio_to_reference_median"] = statistics.median(ratios)
        motion_ratios = [
            ours / ref for ours, ref in zip(subject.motion_rates, reference.rates, strict=True)
        ]
        figures["motions_per_s_median"] = statistics.median(subject.motion_rates)
        figures["motions_ratio_to_reference_median"] = statistics.median(motion_ratios)
        figures["reset_in_reference_steps"] = statistics.median(subject.reset_ns) / (
            statistics.median(reference.step_ns)
        )
    return figures


def print_report(meta: dict[str, Any], args: argparse.Namespace, results: dict[str, Any]) -> None:
    """The table of throughput, reset and step times, then the ratios to Pusher-v5."""
    print(
        f"\nthroughput: {args.rounds} alternating rounds of {args.steps} random-action steps "
        f"per env (after {args.warmup} warm-up steps), whole episodes, resets timed"
    )
    print(
        f"reset/step: medians of reset(seed={VALIDATION[0]}+i) for {args.reset_seeds} seeds "
        f"and of every step of those episodes, each call timed on its own\n"
    )
    width = max(len(label) for label in results)
    print(
        f"{'env':<{width}}  {'steps/s':>8}  {'min-max':>13}  {'ep. len':>7}  "
        f"{'reset µs':>9}  {'step µs':>8}  {'vs ' + REFERENCE_ID:>13}  {'motions/s':>9}  "
        f"{'vs ' + REFERENCE_ID:>13}  {'reset in ' + REFERENCE_ID + ' steps':>23}"
    )
    for label, f in results.items():
        span = f"{f['steps_per_s_min']:.0f}-{f['steps_per_s_max']:.0f}"
        length = f["mean_episode_length"]
        ratio = f.get("ratio_to_reference_median")
        motions = f.get("motions_per_s_median")
        motion_ratio = f.get("motions_ratio_to_reference_median")
        reset_steps = f.get("reset_in_reference_steps")
        print(
            f"{label:<{width}}  {f['steps_per_s_median']:8.0f}  {span:>13}  "
            f"{'-' if length is None else f'{length:.0f}':>7}  "
            f"{f['reset_us_median']:9.1f}  {f['step_us_median']:8.1f}  "
            f"{'' if ratio is None else f'{ratio:.4f}x':>13}  "
            f"{'' if motions is None else f'{motions:.0f}':>9}  "
            f"{'' if motion_ratio is None else f'{motion_ratio:.3f}x':>13}  "
            f"{'' if reset_steps is None else f'{reset_steps:.1f}':>23}"
        )
    print("(a probe-mode env's steps are probes: steps/s = probes/s; motions/s its wrist motions)")
    print(f"\nours / {REFERENCE_ID} steps/s, round by round (same round):")
    for label, f in results.items():
        if "ratio_to_reference_rounds" in f:
            rounds = " ".join(f"{r:.3f}" for r in f["ratio_to_reference_rounds"])
            print(f"  {label:<{width}}  {rounds}  -> median {f['ratio_to_reference_median']:.4f}x")
    print(
        f"(steps/s and ratios: medians over rounds; ep. len: steps per ended episode in "
        f"the rounds; {meta['usable_cpus']} usable cores, shared machine)"
    )


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("--rounds", type=int, default=5, help="alternating rounds (default 5)")
    parser.add_argument(
        "--steps", type=int, default=3000, help="steps per env per round (default 3000)"
    )
    parser.add_argument(
        "--maps",
        nargs="+",
        choices=MAP_MODES,
        default=["gpis", "none"],
        help="our map modes to include in the wrist mode (default: gpis none)",
    )
    parser.add_argument(
        "--probe-maps",
        nargs="*",
        choices=MAP_MODES,
        default=["gpis", "none"],
        help="our map modes in the probe mode (default: gpis none; no value: none)",
    )
    parser.add_argument(
        "--probes", type=int, default=400, help="probes per probe-mode env per round (default 400)"
    )
    parser.add_argument(
        "--reset-seeds", type=int, default=50, help="seeds for the reset/step timings"
    )
    parser.add_argument("--warmup", type=int, default=300, help="untimed steps per env first")
    parser.add_argument("--seed", type=int, default=0, help="seed of the envs and actions")
    parser.add_argument(
        "--variant",
        nargs="+",
        type=parse_setting,
        default=[],
        metavar="KEY=VALUE",
        help="our envs once more with these settings, side by side (values as YAML), e.g. "
        "fast_free_motion=false: the environment before its fast path of free motion",
    )
    parser.add_argument("--json", type=Path, default=None, help="write the figures here")
    args = parser.parse_args(argv)
    if min(args.rounds, args.steps, args.probes, args.reset_seeds) < 1 or args.warmup < 0:
        parser.error("--rounds, --steps, --probes and --reset-seeds must be >= 1, --warmup >= 0")

    check_mujoco()
    meta = header()
    print(
        f"gymnasium {meta['gymnasium']}, mujoco {meta['mujoco']}, numpy {meta['numpy']}, "
        f"python {meta['python']}, tactile_search {meta['tactile_search']}; "
        f"{meta['cpu_count']} CPUs ({meta['usable_cpus']} usable); shared, noisy machine: "
        f"figures are medians from one run"
    )
    subjects = make_subjects(args.maps, args.probe_maps, args.seed, dict(args.variant))
    throughput(subjects, args.rounds, args.steps, args.probes, args.warmup)
    call_times(subjects, args.reset_seeds)
    reference = next(s for s in subjects if s.label == REFERENCE_ID)
    results = {s.label: summary(s, reference) for s in subjects}
    print_report(meta, args, results)
    for subject in subjects:
        subject.env.close()
    if args.json is not None:
        settings = {k: str(v) if isinstance(v, Path) else v for k, v in vars(args).items()}
        document = {"meta": meta, "settings": settings, "envs": results}
        write_json(args.json, "benchmarks.peer_envs", argv, document)


if __name__ == "__main__":
    main()
