"""Whether the core's GPIS probe planner makes the episodes the Python reference made: both
run on the same validation layouts, each in its own env, and every episode's probes, success,
motions (steps) and jar displacement are compared.

Prints the layouts run, the probes compared and every episode that differs (none is the
expected outcome: the core's planner computes the reference's rules in the reference's
float order)::

    python -m benchmarks.planner_agreement --episodes 200
"""

from __future__ import annotations

import argparse
from typing import Any

import numpy as np

from agents.scripted import BeliefProbePlanner, GpisProbePlanner
from benchmarks.arguments import positive_int
from tactile_search import CupboardSearchEnv
from tactile_search.seed_ranges import VALIDATION

SETTINGS = GpisProbePlanner.env_kwargs


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
    args = parser.parse_args(argv)
    layouts = range(VALIDATION[0], VALIDATION[0] + args.episodes)
    core_env, reference_env = CupboardSearchEnv(**SETTINGS), CupboardSearchEnv(**SETTINGS)
    differ, probes, successes = [], 0, 0
    for layout in layouts:
        core = episode(GpisProbePlanner(), core_env, layout)
        reference = episode(BeliefProbePlanner(), reference_env, layout)
        probes += len(reference["probes"])
        successes += reference["success"]
        if core != reference:
            differ.append((layout, core, reference))
    print(
        f"{args.episodes} validation layouts from {layouts[0]}, {probes} probes, "
        f"reference success {successes / args.episodes:.1%}: {len(differ)} episodes differ"
    )
    for layout, core, reference in differ:
        print(f"layout {layout}:\n  core      {core}\n  reference {reference}")


if __name__ == "__main__":
    main()
