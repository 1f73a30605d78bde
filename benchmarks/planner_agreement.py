"""Whether the core's planner of an env id's task makes the episodes its Python reference
made (the GPIS probe planner for a search id, the identify planner for an identify id): both
run on the same validation layouts, each in its own env, and every episode's actions,
success, motions (steps) and jar displacement are compared.

Prints the layouts run, the actions compared and every episode that differs (none is the
expected outcome: the core's planner computes the reference's rules in the reference's
float order)::

    python -m benchmarks.planner_agreement --episodes 200
    python -m benchmarks.planner_agreement --episodes 200 --env-id tactile_search/IdentifyByTouch-v0
"""

from __future__ import annotations

import argparse
from typing import Any

import gymnasium as gym
import numpy as np

from agents.scripted import CORE_PLANNERS, GpisProbePlanner
from benchmarks.arguments import positive_int
from tactile_search import ENV_ID, CupboardSearchEnv
from tactile_search.seed_ranges import VALIDATION


def episode(planner: Any, env: CupboardSearchEnv, layout: int) -> dict[str, Any]:
    observation, info = env.reset(seed=layout)
    planner.reset(env, observation, info)
    probes, done = [], False
    while not done:
        action = np.asarray(planner.act(observation), dtype=np.int64)
        probes.append(tuple(int(i) for i in action))
        observation, _, terminated, truncated, info = env.step(action)
        done = terminated or truncated
    return {
        "probes": probes,
        "success": bool(info["success"]),
        "steps": int(info["steps"]),
        "displacement": float(info["jar_displacement"]),
    }


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--episodes", type=positive_int, default=200)
    parser.add_argument("--env-id", default=ENV_ID, help="a search or identify id")
    args = parser.parse_args(argv)
    settings = {**gym.spec(args.env_id).kwargs, **GpisProbePlanner.env_kwargs}
    core_env, reference_env = CupboardSearchEnv(**settings), CupboardSearchEnv(**settings)
    task = core_env.config.task
    if task not in CORE_PLANNERS:
        parser.error(f"--env-id must be of a task in {sorted(CORE_PLANNERS)}, got {task!r}")
    core_planner, reference_planner = CORE_PLANNERS[task]
    layouts = range(VALIDATION[0], VALIDATION[0] + args.episodes)
    differ, probes, successes = [], 0, 0
    for layout in layouts:
        core = episode(core_planner(), core_env, layout)
        reference = episode(reference_planner(), reference_env, layout)
        probes += len(reference["probes"])
        successes += reference["success"]
        if core != reference:
            differ.append((layout, core, reference))
    print(
        f"{args.env_id}: {args.episodes} validation layouts from {layouts[0]}, {probes} actions, "
        f"reference success {successes / args.episodes:.1%}: {len(differ)} episodes differ"
    )
    for layout, core, reference in differ:
        print(f"layout {layout}:\n  core      {core}\n  reference {reference}")


if __name__ == "__main__":
    main()
