"""Trained probes per second per machine for each way of placing PPO training on the cores.

The ways a budget can use a machine of ``cores`` CPUs (``--cores``, default all usable):

- ``alone-1``: one run with one torch thread and one environment thread (the other cores
  idle: the floor);
- ``alone-all``: one run with every core for torch and for the environment batch (its
  rollouts and updates alternate, so each stage has all cores while the other waits);
- ``side-by-side``: ``cores`` runs at once, one torch and one environment thread each, as
  the ``full`` budget runs its trials (``cpus_per_trial`` = 1, ``agents/grid/budgets.py``).

Each run is the real command, ``python -m agents.train`` in a subprocess (training seed
``--seed`` + its index, ``--timesteps`` probes, the recipe of ``--hyperparams`` or
``agents/hyperparams/ppo.yml``), and its rate is the ``timesteps_done`` over the
``wall_clock_seconds`` of the ``config.yml`` it writes (start-up excluded). The machine's
rate for an arrangement is the sum of its runs' rates. Arrangements alternate over
``--rounds`` rounds so that the shared machine's load hits them alike; it prints each round,
then per arrangement the median machine rate and its ratio to ``alone-1``. From the
repository root::

    python -m benchmarks.train_arrangement [--timesteps 4096] [--rounds 2] [--map gpis]
        [--hyperparams docs/results/ablations_speed/space_to_depth.yml]
        [--json results/train_arrangement.json]
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

import yaml

from agents.run_dir import CONFIG_FILE
from benchmarks.arguments import positive_int
from benchmarks.performance_page import write_json

ARRANGEMENTS = ("alone-1", "alone-all", "side-by-side")


def train_command(args: argparse.Namespace, seed: int, threads: int, out: Path) -> list[str]:
    """The ``agents.train`` command of one run."""
    command = [
        sys.executable,
        "-m",
        "agents.train",
        "--algo",
        "ppo",
        "--map",
        args.map,
        "--seed",
        str(seed),
        "--timesteps",
        str(args.timesteps),
        "--torch-threads",
        str(threads),
        "--env-threads",
        str(threads),
        "--out",
        str(out),
        "--no-progress",
        # PPO's training speed: the recipe's clone stage is not measured.
        "--from-scratch",
    ]
    if args.hyperparams is not None:
        command += ["--hyperparams", str(args.hyperparams)]
    return command


def run_arrangement(arrangement: str, args: argparse.Namespace, out: Path) -> list[float]:
    """Runs ``arrangement`` once; the trained probes/s of each of its runs."""
    runs = args.cores if arrangement == "side-by-side" else 1
    threads = args.cores if arrangement == "alone-all" else 1
    processes = []
    for index in range(runs):
        command = train_command(args, args.seed + index, threads, out / f"run{index}")
        processes.append(
            subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        )
    rates = []
    for index, process in enumerate(processes):
        _, stderr = process.communicate()
        if process.returncode != 0:
            raise RuntimeError(f"{arrangement} run {index} failed:\n{stderr[-2000:]}")
        (run_dir,) = (out / f"run{index}").iterdir()
        config = yaml.safe_load((run_dir / CONFIG_FILE).read_text())
        rates.append(config["timesteps_done"] / config["wall_clock_seconds"])
    return rates


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("--timesteps", type=positive_int, default=4096, help="probes per run")
    parser.add_argument("--rounds", type=positive_int, default=2, help="alternating rounds")
    parser.add_argument("--map", default="gpis", help="the recipe's map mode (default gpis)")
    parser.add_argument("--hyperparams", type=Path, default=None, help="a recipe file")
    parser.add_argument("--seed", type=int, default=0, help="the first run's training seed")
    usable = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    parser.add_argument("--cores", type=positive_int, default=usable or 1)
    parser.add_argument("--arrangements", nargs="+", choices=ARRANGEMENTS, default=ARRANGEMENTS)
    parser.add_argument("--json", type=Path, default=None, help="write the figures here too")
    args = parser.parse_args(argv)
    print(
        f"PPO {args.map} ({args.hyperparams or 'agents/hyperparams/ppo.yml'}), {args.timesteps} "
        f"probes per run, {args.cores} cores, {args.rounds} rounds; load average "
        f"{os.getloadavg()[0]:.1f} at the start",
        flush=True,
    )
    machine: dict[str, list[float]] = {name: [] for name in args.arrangements}
    with tempfile.TemporaryDirectory() as tmp:
        for round_index in range(args.rounds):
            shift = round_index % len(args.arrangements)
            order = args.arrangements[shift:] + args.arrangements[:shift]
            for arrangement in order:
                out = Path(tmp) / f"r{round_index}_{arrangement}"
                rates = run_arrangement(arrangement, args, out)
                machine[arrangement].append(sum(rates))
                each = " + ".join(f"{rate:.1f}" for rate in rates)
                print(
                    f"round {round_index} {arrangement:>12}: {sum(rates):6.1f} probes/s "
                    f"per machine ({each}); load {os.getloadavg()[0]:.1f}",
                    flush=True,
                )
    base = statistics.median(machine[args.arrangements[0]])
    print(f"\n{'arrangement':>12} {'probes/s per machine':>21} {'vs ' + args.arrangements[0]:>12}")
    for arrangement, values in machine.items():
        median = statistics.median(values)
        print(f"{arrangement:>12} {median:21.1f} {median / base:12.2f}")
    if args.json is not None:
        figures = {
            "map": args.map, "hyperparams": str(args.hyperparams or "agents/hyperparams/ppo.yml"),
            "timesteps": args.timesteps, "rounds": args.rounds, "cores": args.cores,
            "base": args.arrangements[0],
            "arrangements": {
                name: {"rounds": values, "median": statistics.median(values),
                       "ratio": statistics.median(values) / base}
                for name, values in machine.items()
            },
        }  # fmt: skip
        write_json(args.json, "benchmarks.train_arrangement", argv, figures)


if __name__ == "__main__":
    main()
