"""The experiment grid on Ray against the same work one trial after another, on this machine.

Prints three figures (``python -m benchmarks.ray_grid``, from the repository root; ~10 min
on 2 cores):

1. **Grid speed-up.** Four equal trials (PPO with the GPIS map, training seeds 0-3, at
   ``--timesteps``), trained one after another in one process (``--scheduler local``) and as
   Ray tasks on a local Ray (each trial declares the full budget's one CPU). Each is a
   fresh process timed from start to end, so Ray's start-up counts against it.
   As a control, the same trials split over plain processes (one per trial slot, no Ray):
   the speed-up this machine's cores give at all.
2. **Overhead.** One trial (PPO with the GPIS map) run directly (``agents.grid.trials.train_trial``
   in a fresh process) and as the only trial on Ray (a fresh process that starts Ray); also
   without Ray's start-up (the time after ``ray.init`` returned).
3. **On paper.** The wall-clock of the documented grid (the 4 agents x 3 training seeds at
   their recipes' budgets, then 200 test layouts per agent, with the 3 scripted baselines) on
   1, 4 and 16 machines like this one, from each agent's training rate measured on Ray (one
   seed each at ``--rate-timesteps``, two trials sharing the machine), a trial's fixed cost
   on Ray measured in (2), and each agent's seconds per evaluation episode measured here
   (learned agents: those small models, which mostly run to the time limit: an upper bound).

The phases alternate over ``--repeats`` rounds and the medians are printed.
"""

from __future__ import annotations

import argparse
import heapq
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

from agents.grid.budgets import BUDGETS, SCRIPTED
from agents.sb3.recipes import load_hyperparams
from benchmarks.performance_page import write_json

#: The repository's root: the children's working directory (``python -c`` finds ``agents``
#: there).
REPO = Path(__file__).resolve().parents[1]

FULL = BUDGETS["full"]
# Training seeds of the documented grid, and its evaluation episodes per agent.
DOCUMENTED_SEEDS = 3

# What a child process runs: the trials given as JSON, one after another or on Ray; prints
# one JSON line with its timings.
CHILD = """
import json, sys, time
started = time.perf_counter()
from agents.grid.trials import TrainingTrial, train_trial
spec = json.loads(sys.argv[1])
trials = [TrainingTrial(**t) for t in spec["trials"]]
connected = started
if spec["scheduler"] == "ray":
    from pathlib import Path
    from agents.grid import ray_scheduler as ray_grid
    from agents.grid.ray_session import connect
    connect(num_cpus=spec["cpus"])
    connected = time.perf_counter()
    ray_grid.train_on_ray(trials)
else:
    for trial in trials:
        train_trial(trial)
ended = time.perf_counter()
print("RESULT " + json.dumps({"total": ended - started, "after_start": ended - connected}))
"""


def start_child(trials: list[dict], scheduler: str, cpus: int) -> subprocess.Popen:
    """Starts a fresh process that runs ``trials``."""
    spec = {"trials": trials, "scheduler": scheduler, "cpus": cpus}
    return subprocess.Popen(
        [sys.executable, "-c", CHILD, json.dumps(spec)],
        cwd=REPO,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )


def child_timings(child: subprocess.Popen, what: str) -> dict[str, float]:
    """The timings a child printed (seconds), once it has ended."""
    stdout, stderr = child.communicate()
    lines = [line for line in stdout.splitlines() if line.startswith("RESULT ")]
    if child.returncode != 0 or not lines:
        raise RuntimeError(f"the {what} run failed:\n{stdout[-3000:]}{stderr[-3000:]}")
    return json.loads(lines[-1].removeprefix("RESULT "))


def run_child(trials: list[dict], scheduler: str, cpus: int) -> dict[str, float]:
    """Runs ``trials`` in a fresh process; its timings (seconds)."""
    return child_timings(start_child(trials, scheduler, cpus), scheduler)


def run_split(trials: list[dict], processes: int) -> float:
    """Seconds to run ``trials`` split over ``processes`` plain processes at once, each
    running its share one after another (no Ray): what this machine's cores give."""
    started = time.perf_counter()
    children = [start_child(trials[i::processes], "local", 1) for i in range(processes)]
    for child in children:
        child_timings(child, "split")
    return time.perf_counter() - started


def trial_dicts(
    runs: Path, agents: list[tuple[str, str]], timesteps: int, cpus: int, seeds: int = 1
) -> list[dict]:
    """``TrainingTrial`` fields of each agent with training seeds ``0 .. seeds - 1``."""
    return [
        {
            "algo": algo,
            "map_mode": map_mode,
            "seed": seed,
            "runs": str(runs),
            "timesteps": timesteps,
            "cpus": cpus,
            "n_envs": None,
        }
        for algo, map_mode in agents
        for seed in range(seeds)
    ]


def training_rates(runs: Path) -> dict[tuple[str, str], float]:
    """Env steps per second of each run under ``runs`` (from its config.yml)."""
    from agents.run_dir import read_run_config

    rates = {}
    for run_dir in sorted(runs.iterdir()):
        if (run_dir / "model.zip").is_file():
            config = read_run_config(run_dir)
            rates[config["algo"], config["map"]] = (
                config["timesteps_done"] / config["wall_clock_seconds"]
            )
    return rates


def episode_seconds(runs: Path, episodes: int) -> dict[str, float]:
    """Seconds per evaluation episode of each learned run under ``runs`` and each scripted
    agent, on validation layouts."""
    from agents.grid.trials import evaluate_shard
    from agents.run_dir import evaluated_files
    from tactile_search.seed_ranges import held_out_seeds

    seeds = held_out_seeds("validation", episodes)
    specs = {
        run_dir.name: (str(run_dir), evaluated_files(run_dir)) for run_dir in sorted(runs.iterdir())
    }
    specs.update({name: (name, None) for name in SCRIPTED})
    seconds = {}
    for name, (spec, files) in specs.items():
        started = time.perf_counter()
        evaluate_shard(spec, files, seeds)
        seconds[name] = (time.perf_counter() - started) / episodes
    return seconds


def makespan(durations: list[float], slots: int) -> float:
    """The wall-clock of ``durations`` on ``slots`` parallel slots, longest first (LPT)."""
    finish = [0.0] * slots
    for duration in sorted(durations, reverse=True):
        heapq.heappush(finish, heapq.heappop(finish) + duration)
    return max(finish)


def on_paper(
    rates: dict[tuple[str, str], float],
    per_episode: dict[str, float],
    fixed: float,
    machines: int,
    cores: int,
) -> tuple[float, float]:
    """Training and evaluation wall-clock (s) of the documented grid on ``machines``: each
    trial its recipe's steps at its measured rate plus ``fixed`` seconds, on as many slots
    as the machines' cores hold trials; evaluation shards of 25 episodes, one per core."""
    slots = machines * cores // FULL.cpus_per_trial
    trial_seconds = []
    for algo, map_mode in FULL.agents:
        recipe = load_hyperparams(algo, map_mode)
        seconds = recipe["n_timesteps"] / rates[algo, map_mode]
        if recipe.get("max_minutes") is not None:
            seconds = min(seconds, 60 * recipe["max_minutes"])
        trial_seconds += [seconds + fixed] * DOCUMENTED_SEEDS
    training = makespan(trial_seconds, slots)
    shard = 25
    learned = [per_episode[f"{algo}_{map_mode}_seed0"] for algo, map_mode in FULL.agents]
    shard_seconds = [
        seconds * shard
        for seconds in [*learned * DOCUMENTED_SEEDS, *(per_episode[s] for s in SCRIPTED)]
        for _ in range(FULL.episodes // shard)
    ]
    evaluation = makespan(shard_seconds, machines * cores)
    return training, evaluation


def timed_pair(
    tmp: Path, label: str, trials_of: Callable[[Path], list[dict]], kinds: tuple[str, str]
) -> dict[str, dict[str, float]]:
    """Runs the trials of ``trials_of(runs)`` with each scheduler in ``kinds`` (in that
    order) in fresh processes; their timings by scheduler."""
    timings = {}
    for scheduler in kinds:
        runs = tmp / f"{label}_{scheduler}"
        timings[scheduler] = run_child(trials_of(runs), scheduler, os.cpu_count())
        timings[scheduler]["runs"] = str(runs)
        print(f"{label}, {scheduler}: {timings[scheduler]['total']:.1f} s", flush=True)
    return timings


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--timesteps", type=int, default=32_768, help="per trial in (1), (2)")
    parser.add_argument(
        "--rate-timesteps", type=int, default=8_192, help="per trial of the rates for (3)"
    )
    parser.add_argument("--repeats", type=int, default=1, help="rounds of (1) and (2)")
    parser.add_argument("--episodes", type=int, default=4, help="per agent, for episode times")
    parser.add_argument("--json", type=Path, help="write the figures here too")
    args = parser.parse_args(argv)
    cores = os.cpu_count() or 1
    cpus = FULL.cpus_per_trial
    grid: dict[str, list[float]] = {"local": [], "ray": [], "split": []}
    single: dict[str, list[float]] = {"local": [], "ray": [], "ray_after_start": []}
    with tempfile.TemporaryDirectory(prefix="ray_grid_bench_") as tmp_name:
        tmp = Path(tmp_name)
        for round_index in range(args.repeats):
            kinds = ("local", "ray") if round_index % 2 == 0 else ("ray", "local")
            # (1) Four equal trials: PPO with the GPIS map, training seeds 0..3.
            timings = timed_pair(
                tmp,
                f"grid_{round_index}",
                lambda runs: trial_dicts(runs, [("ppo", "gpis")], args.timesteps, cpus, seeds=4),
                kinds,
            )
            for kind in kinds:
                grid[kind].append(timings[kind]["total"])
            # The machine's own ceiling: the same trials in plain processes, one per slot.
            four = trial_dicts(
                tmp / f"split_{round_index}", [("ppo", "gpis")], args.timesteps, cpus, 4
            )
            grid["split"].append(run_split(four, cores // cpus))
            print(f"grid_{round_index}, plain processes: {grid['split'][-1]:.1f} s", flush=True)
            # (2) One of them alone.
            timings = timed_pair(
                tmp,
                f"single_{round_index}",
                lambda runs: trial_dicts(runs, [("ppo", "gpis")], args.timesteps, cpus),
                kinds,
            )
            for kind in kinds:
                single[kind].append(timings[kind]["total"])
            single["ray_after_start"].append(timings["ray"]["after_start"])
            (rate,) = training_rates(Path(timings["ray"]["runs"])).values()
            fixed = timings["ray"]["total"] - args.timesteps / rate
        # (3) Each agent of the documented grid on Ray, two trials sharing the machine.
        runs = tmp / "agents_ray"
        run_child(
            trial_dicts(runs, list(FULL.agents), args.rate_timesteps, cpus),
            "ray",
            cores,
        )
        rates = training_rates(runs)
        per_episode = episode_seconds(runs, args.episodes)
    local, on_ray = statistics.median(grid["local"]), statistics.median(grid["ray"])
    split = statistics.median(grid["split"])
    direct, single_ray = statistics.median(single["local"]), statistics.median(single["ray"])
    after_start = statistics.median(single["ray_after_start"])
    print()
    print(
        f"machine: {cores} cores; each trial declares {cpus} CPU; ppo gpis trials of "
        f"{args.timesteps} steps; {args.repeats} round(s), medians"
    )
    print(
        f"(1) grid of 4 trials: one after another {local:.1f} s, on Ray {on_ray:.1f} s: "
        f"x{local / on_ray:.2f} (target >= 1.7); in {cores // cpus} plain processes without "
        f"Ray {split:.1f} s: x{local / split:.2f}, what the cores give at all"
    )
    print(
        f"(2) one trial: directly {direct:.1f} s, on Ray {single_ray:.1f} s "
        f"({100 * (single_ray / direct - 1):+.1f} %, target <= +10 %); after Ray's start-up "
        f"{after_start:.1f} s ({100 * (after_start / direct - 1):+.1f} %)"
    )
    print(
        "(3) training rates on Ray, two trials sharing the machine (steps/s): "
        + ", ".join(f"{algo} {map_mode} {rate:.0f}" for (algo, map_mode), rate in rates.items())
    )
    print(
        "    evaluation (s/episode): "
        + ", ".join(f"{name} {value:.2f}" for name, value in per_episode.items())
    )
    print(f"    a trial's fixed cost on Ray (start-up, building, saving): {fixed:.1f} s")
    print(
        f"\nthe documented grid ({len(FULL.agents)} agents x {DOCUMENTED_SEEDS} seeds, "
        f"{FULL.episodes} test layouts), on paper:"
    )
    print("| machines | training (h) | evaluation (h) | total (h) |")
    print("|---|---|---|---|")
    paper = {}
    for machines in (1, 4, 16):
        training, evaluation = on_paper(rates, per_episode, fixed, machines, cores)
        paper[machines] = {"training_s": training, "evaluation_s": evaluation}
        print(
            f"| {machines} | {training / 3600:.2f} | {evaluation / 3600:.2f} "
            f"| {(training + evaluation) / 3600:.2f} |"
        )
    if args.json:
        figures = {
            "cores": cores,
            "timesteps": args.timesteps,
            "grid_seconds": grid,
            "single_seconds": single,
            "rates_on_ray": {f"{algo} {map_mode}": r for (algo, map_mode), r in rates.items()},
            "episode_seconds": per_episode,
            "fixed_seconds": fixed,
            "on_paper_seconds": paper,
        }
        write_json(args.json, "benchmarks.ray_grid", argv, figures)


if __name__ == "__main__":
    main()
