"""The GPIS probe planner on probe grids of different fineness (the command)::

    python -m agents.probe_grid --episodes 200 --grids default probe_sweeps=21 \\
        probe_sweeps=21,probe_depths=19

Each grid is a set of the core's probe settings (``probe_lanes``, ``probe_depths``,
``probe_sweeps``; ``default`` for none) that the env is built with; the planner
(``gpis_probe_planner``) chooses among that grid's probes on the same validation layouts.
Prints, per grid, its success with a 95 % interval, the median (Q1, Q3) wrist motions to
success and the tips, and, against the first grid, the layouts only one of the two solved
(a paired comparison: the same layouts, so these discordant layouts carry the difference).
It measures what a finer action grid would give the learned agents, whose recipes choose
the grid, before any is trained on it.
"""

from __future__ import annotations

import argparse
import json
from typing import Any

from agents.rollout import evaluate_agent
from agents.scripted import GpisProbePlanner
from tactile_search.benchmark.statistics import summarize
from tactile_search.seed_ranges import held_out_seeds


def parse_grid(text: str) -> dict[str, Any]:
    """``default`` or ``key=value,key=value`` (values as JSON: numbers)."""
    if text == "default":
        return {}
    settings = {}
    for item in text.split(","):
        key, sep, value = item.partition("=")
        if not sep or not key:
            raise argparse.ArgumentTypeError(f"expected key=value[,key=value...], got {text!r}")
        try:
            settings[key] = json.loads(value)
        except json.JSONDecodeError as err:
            raise argparse.ArgumentTypeError(f"{key}: {value!r} is not a number") from err
    return settings


def label(settings: dict[str, Any]) -> str:
    return ",".join(f"{k}={v}" for k, v in settings.items()) or "default"


def run_grid(settings: dict[str, Any], seeds: list[int]) -> list[dict[str, Any]]:
    """One planner episode per seed on the probe grid ``settings``."""
    env_kwargs = {**GpisProbePlanner.env_kwargs, **settings}
    return evaluate_agent(GpisProbePlanner(), seeds, **env_kwargs)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("--episodes", type=int, default=200, help="validation layouts")
    parser.add_argument(
        "--grids",
        nargs="+",
        type=parse_grid,
        default=[{}],
        help="probe settings per grid: default, or key=value[,key=value...]",
    )
    args = parser.parse_args(argv)
    seeds = held_out_seeds("validation", args.episodes)
    rows = {label(settings): run_grid(settings, seeds) for settings in args.grids}
    first_label, first = next(iter(rows.items()))
    print(f"gpis_probe_planner on validation layouts {seeds[0]}..{seeds[-1]}")
    print(
        "| probe grid | success | 95 % CI | motions to success, median [Q1, Q3] | tips "
        f"| solved only here / only by {first_label} |"
    )
    print("|---|---|---|---|---|---|")
    for name, episodes in rows.items():
        s = summarize(name, "gpis", episodes)
        only_here = sum(
            e["success"] and not f["success"] for e, f in zip(episodes, first, strict=True)
        )
        only_first = sum(
            f["success"] and not e["success"] for e, f in zip(episodes, first, strict=True)
        )
        print(
            f"| {name} | {100 * s.success_rate:.1f} % | [{100 * s.success_low:.1f}, "
            f"{100 * s.success_high:.1f}] | {s.steps_median:.0f} [{s.steps_q1:.0f}, "
            f"{s.steps_q3:.0f}] | {100 * s.tip_rate:.1f} % | {only_here} / {only_first} |"
        )


if __name__ == "__main__":
    main()
