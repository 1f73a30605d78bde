"""How many depth points the GPIS prior needs: map quality and reset time against
``max_prior_depth_points``, on validation layouts.

For each value, over the same validation seeds (the first of
``tactile_search.seed_ranges.VALIDATION``), the environment is reset
(the map is the depth prior alone: ``info["iou"]`` and rows) and the scripted GPIS probe planner,
which reads only the observation, runs the episode (success, and the IoU of the map that
depth and touch built by its end). Reset times are medians of ``env.reset`` in the same
run. The prior's cost grows as rows² times grid cells, so fewer points make resets cheaper; the
question is where the map starts to suffer.

Run (from the repository root): ``python -m benchmarks.prior_rows [--seeds 40]
[--points 96 64 48 32] [--json results/prior_rows.json]``.
"""

from __future__ import annotations

import argparse
import statistics
import time
from pathlib import Path

from agents.scripted import GpisProbePlanner
from benchmarks.performance_page import write_json
from tactile_search import CupboardSearchEnv
from tactile_search.benchmark.statistics import wilson_interval
from tactile_search.seed_ranges import held_out_seeds


def interval(successes: int, n: int) -> str:
    """The project's Wilson 95 % interval of a rate (``wilson_interval``), as text."""
    if n == 0:
        return "-"
    low, high = wilson_interval(successes, n)
    return f"[{100 * low:.0f}, {100 * high:.0f}]"


def measure(points: int, seeds: list[int]) -> dict[str, float | str]:
    env = CupboardSearchEnv(max_prior_depth_points=points, **GpisProbePlanner.env_kwargs)
    planner = GpisProbePlanner()
    prior_iou, final_iou, rows, resets = [], [], [], []
    successes = 0
    for seed in seeds:
        start = time.perf_counter()
        observation, info = env.reset(seed=seed)
        resets.append(time.perf_counter() - start)
        prior_iou.append(info["iou"])
        rows.append(info["gpis_rows"])
        planner.reset(env, observation, info)
        for _ in range(env.config.max_steps):
            observation, _, terminated, truncated, info = env.step(planner.act(observation))
            if terminated or truncated:
                break
        successes += int(info["success"])
        final_iou.append(info["iou"])
    env.close()
    return {
        "points": points,
        "rows": statistics.fmean(rows),
        "reset_ms": 1e3 * statistics.median(resets),
        "prior_iou": statistics.fmean(prior_iou),
        "prior_iou_sd": statistics.pstdev(prior_iou),
        "final_iou": statistics.fmean(final_iou),
        "final_iou_sd": statistics.pstdev(final_iou),
        "success": 100 * successes / len(seeds),
        "success_ci": interval(successes, len(seeds)),
    }


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=40)
    parser.add_argument("--points", type=int, nargs="+", default=[96, 64, 48, 32])
    parser.add_argument("--json", type=Path, default=None, help="write the figures here too")
    args = parser.parse_args(argv)
    rows = []
    seeds = held_out_seeds("validation", args.seeds)
    print(f"validation seeds {seeds[0]}..{seeds[-1]}; reset times are medians (ms)")
    print(
        f"{'points':>6} {'rows':>6} {'reset':>7} {'prior IoU':>12} {'final IoU':>12} "
        f"{'planner success':>20}"
    )
    for points in args.points:
        r = measure(points, seeds)
        rows.append(r)
        print(
            f"{r['points']:>6} {r['rows']:>6.0f} {r['reset_ms']:>7.2f} "
            f"{r['prior_iou']:>6.3f}±{r['prior_iou_sd']:.3f} "
            f"{r['final_iou']:>6.3f}±{r['final_iou_sd']:.3f} "
            f"{r['success']:>6.0f} % {r['success_ci']:>11}"
        )
    if args.json is not None:
        figures = {"seeds": len(seeds), "first_seed": seeds[0], "rows": rows}
        write_json(args.json, "benchmarks.prior_rows", argv, figures)


if __name__ == "__main__":
    main()
