"""Whether one of the core's planners (``agents.scripted.CORE_PLANNERS``: the GPIS probe
planner, the identify planner, the variance and occupancy mappers) makes the episodes its
Python reference made: both run on the same validation layouts of an env id of the planner's
task, each in its own env, and every episode's actions, success, motions (steps), jar
displacement and map score are compared.

Prints the layouts run, the actions compared and every episode that differs (none is the
expected outcome: the core's planner computes the reference's rules in the reference's
float order)::

    python -m benchmarks.planner_agreement --episodes 200
    python -m benchmarks.planner_agreement --episodes 200 --planner identify_planner \
        --env-id tactile_search/IdentifyByTouchDense-v0
    python -m benchmarks.planner_agreement --episodes 200 --planner variance_mapper
"""

from __future__ import annotations

import argparse
from typing import Any

import gymnasium as gym
import numpy as np

from agents.scripted import CORE_PLANNERS, SCRIPTED_TASKS
from benchmarks.arguments import positive_int
from tactile_search import CupboardSearchEnv, registered_envs
from tactile_search.seed_ranges import VALIDATION


def first_id_of(task: str) -> str:
    """The first registered id of ``task`` (the core's table of ids): the one a planner of
    that task runs on unless told."""
    return next(env["id"] for env in registered_envs() if env["task"] == task)


def planner_settings(
    parser: argparse.ArgumentParser, planner: str, env_id: str | None
) -> tuple[str, dict[str, Any]]:
    """The env id (``env_id``, else the planner's task's id) and its settings in the
    planner's map and action mode; a parser error for an id of another task."""
    face = CORE_PLANNERS[planner][0]
    env_id = env_id or first_id_of(SCRIPTED_TASKS[planner][0])
    settings = {**gym.spec(env_id).kwargs, **face.env_kwargs}
    task = CupboardSearchEnv(**settings).config.task
    if task not in SCRIPTED_TASKS[planner]:
        parser.error(f"--env-id must be of the {planner}'s task, got one of task {task!r}")
    return env_id, settings


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
        "map_score_mm": info.get("map_score_mm"),
    }


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--episodes", type=positive_int, default=200)
    parser.add_argument("--planner", choices=sorted(CORE_PLANNERS), default="gpis_probe_planner")
    parser.add_argument("--env-id", help="an id of the planner's task (default: its task's)")
    args = parser.parse_args(argv)
    env_id, settings = planner_settings(parser, args.planner, args.env_id)
    core_env, reference_env = CupboardSearchEnv(**settings), CupboardSearchEnv(**settings)
    core_planner, reference_planner = CORE_PLANNERS[args.planner]
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
        f"{args.planner} on {env_id}: {args.episodes} validation layouts from {layouts[0]}, "
        f"{probes} actions, reference success {successes / args.episodes:.1%}: "
        f"{len(differ)} episodes differ"
    )
    for layout, core, reference in differ:
        print(f"layout {layout}:\n  core      {core}\n  reference {reference}")


if __name__ == "__main__":
    main()
