"""Standings of the map task's scripted baselines on ``tactile_search/MapByTouch-v0``.

Each baseline (``agents.scripted.map_probe``: ``random_map``, ``variance_mapper``,
``occupancy_mapper``, ``map_oracle``) plays the first ``--episodes`` validation layouts
(``held_out_seeds("validation", N)``) in the probe action mode, on the registered id's
settings with its own map mode. Per baseline: the final outline distance
(``map_score_mm``, mean and 95 % t interval), the distance's mean over the budget
(``map_score_area``), the final IoU of the score's reconstruction (``map_score_iou``), the
probes, tips and jar displacement. Writes a markdown table and a JSON file with the
per-episode rows to the folder ``--out`` (the committed run:
``docs/results/map_standings/standings.md`` and ``standings.json`` beside it); the
baselines run in parallel processes (``--jobs``).

Run (from the repository root): ``python -m benchmarks.map_standings [--episodes 200]
[--out docs/results/map_standings] [--jobs 2]``.
"""

from __future__ import annotations

import argparse
import json
import math
import platform
import subprocess
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path
from typing import Any

import numpy as np
from scipy import stats

ENV_ID = "tactile_search/MapByTouch-v0"
BASELINES = ("random_map", "variance_mapper", "occupancy_mapper", "map_oracle")


def env_settings(name: str) -> dict[str, Any]:
    """The registered id's settings, then the baseline's own (map and action mode)."""
    import gymnasium

    import tactile_search  # noqa: F401  (registers the ids)
    from agents.scripted import SCRIPTED_AGENTS

    settings = dict(gymnasium.spec(ENV_ID).kwargs)
    settings.update({"map": "gpis", "action_mode": "probe"})
    settings.update(getattr(SCRIPTED_AGENTS[name], "env_kwargs", {}))
    return settings


def play(name: str, seeds: list[int]) -> list[dict[str, Any]]:
    """One episode per seed with baseline ``name``."""
    from agents.rollout import run_episodes
    from agents.scripted import SCRIPTED_AGENTS

    return run_episodes(SCRIPTED_AGENTS[name](), seeds, **env_settings(name))


def depth_look_only(seeds: list[int]) -> list[dict[str, Any]]:
    """The reference of no touch at all: each layout's score after the reset (the depth
    camera's first look alone), as the rows of an episode that never moves."""
    import gymnasium

    import tactile_search  # noqa: F401  (registers the ids)
    from tactile_search import CupboardSearchEnv

    env = CupboardSearchEnv(**gymnasium.spec(ENV_ID).kwargs)
    rows = []
    for seed in seeds:
        _, info = env.reset(seed=seed)
        rows.append(
            {
                "seed": seed,
                "map_score_mm": float(info["map_score_mm"]),
                "map_score_area": float(info["map_score_mm"]),
                "map_score_iou": float(info["map_score_iou"]),
                "actions": 0,
                "tips": 0,
                "jar_displacement": 0.0,
            }
        )
    env.close()
    return rows


def mean_interval(values: list[float]) -> tuple[float, float, float]:
    """Mean and its 95 % t interval."""
    x = np.asarray(values, dtype=float)
    mean = float(x.mean())
    if len(x) < 2:
        return mean, math.nan, math.nan
    half = float(stats.t.ppf(0.975, len(x) - 1) * x.std(ddof=1) / math.sqrt(len(x)))
    return mean, mean - half, mean + half


def summarize(
    name: str, rows: list[dict[str, Any]], seconds: float, settings: dict[str, Any] | None = None
) -> dict[str, Any]:
    mm = mean_interval([r["map_score_mm"] for r in rows])
    area = mean_interval([r["map_score_area"] for r in rows])
    iou = mean_interval([r["map_score_iou"] for r in rows])
    return {
        "agent": name,
        "settings": env_settings(name) if settings is None else settings,
        "episodes": len(rows),
        "map_score_mm": {"mean": mm[0], "ci95": [mm[1], mm[2]]},
        "map_score_area": {"mean": area[0], "ci95": [area[1], area[2]]},
        "map_score_iou": {"mean": iou[0], "ci95": [iou[1], iou[2]]},
        "probes": float(np.mean([r["actions"] for r in rows])),
        "tips": int(sum(r["tips"] for r in rows)),
        "tipped_episodes": int(sum(r["tips"] > 0 for r in rows)),
        "jar_displacement_mm": 1000.0 * float(np.mean([r["jar_displacement"] for r in rows])),
        "seconds": seconds,
    }


def timed_play(name: str, seeds: list[int]) -> tuple[list[dict[str, Any]], float]:
    start = time.perf_counter()
    rows = play(name, seeds)
    return rows, time.perf_counter() - start


def cell(summary: dict[str, Any], key: str, digits: int) -> str:
    """A mean and its interval, as text."""
    m, (lo, hi) = summary[key]["mean"], summary[key]["ci95"]
    return f"{m:.{digits}f} [{lo:.{digits}f}, {hi:.{digits}f}]"


def table(summaries: list[dict[str, Any]]) -> str:
    lines = [
        "| baseline | map | final distance, mm (95 % CI) | area, mm (95 % CI) "
        "| final IoU (95 % CI) | probes | tips (episodes) | jar displacement, mm |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for s in summaries:
        lines.append(
            f"| `{s['agent']}` | {s['settings']['map']} | {cell(s, 'map_score_mm', 2)} "
            f"| {cell(s, 'map_score_area', 2)} | {cell(s, 'map_score_iou', 3)} "
            f"| {s['probes']:.1f} "
            f"| {s['tips']} ({s['tipped_episodes']}) | {s['jar_displacement_mm']:.1f} |"
        )
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--episodes", type=int, default=200)
    parser.add_argument("--out", type=Path, default=Path("docs/results/map_standings"))
    parser.add_argument("--jobs", type=int, default=2, help="parallel processes")
    parser.add_argument("--agents", nargs="+", default=list(BASELINES), choices=BASELINES)
    args = parser.parse_args(argv)

    from tactile_search.seed_ranges import held_out_seeds

    seeds = held_out_seeds("validation", args.episodes)
    with ProcessPoolExecutor(max_workers=args.jobs) as pool:
        futures = {name: pool.submit(timed_play, name, seeds) for name in args.agents}
        results = {name: future.result() for name, future in futures.items()}
    start = time.perf_counter()
    reference = depth_look_only(seeds)
    summaries = [
        summarize("depth_look_only", reference, time.perf_counter() - start, {"map": "(no motion)"})
    ]
    summaries += [summarize(name, *results[name]) for name in args.agents]

    commit = subprocess.run(
        ["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True, check=False
    ).stdout.strip()
    command = "python -m benchmarks.map_standings " + " ".join(
        sys.argv[1:] if argv is None else argv
    )
    meta = {
        "env_id": ENV_ID,
        "split": "validation",
        "seeds": [seeds[0], seeds[-1]],
        "episodes": len(seeds),
        "command": command.strip(),
        "commit": commit,
        "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
        "machine": f"{platform.machine()}, {platform.python_version()}",
    }
    args.out.mkdir(parents=True, exist_ok=True)
    payload = {
        **meta,
        "summaries": summaries,
        "rows": {
            "depth_look_only": reference,
            **{name: results[name][0] for name in args.agents},
        },
    }
    (args.out / "standings.json").write_text(json.dumps(payload, indent=1) + "\n")
    markdown = (
        f"# Map task standings: scripted baselines on `{ENV_ID}`\n\n"
        f"The first {len(seeds)} validation layouts (seeds {seeds[0]}..{seeds[-1]}), probe "
        "action mode, 200 wrist motions. Final distance: `map_score_mm` (mean outline "
        "distance of the score's GPIS to the true outlines, lower is better); area: "
        "`map_score_area` (its mean over the budget, lower is better); IoU: `map_score_iou`. "
        "Intervals: 95 % t intervals of the mean. `depth_look_only` is the score after the "
        "reset, before any motion (the depth camera's first look alone); `map_oracle` reads "
        "the ground truth.\n\n"
        f"{table(summaries)}\n\n"
        f"Command: `{meta['command']}` (commit {commit}, {meta['date']}, {meta['machine']}).\n"
    )
    (args.out / "standings.md").write_text(markdown)
    print(markdown)


if __name__ == "__main__":
    main()
