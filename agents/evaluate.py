"""Evaluate trained models and scripted baselines on held-out layouts (the command)::

    python -m agents.evaluate --runs runs/ppo_gpis_seed0 runs/ppo_none_seed0 \\
        --scripted random gpis_probe_planner oracle --episodes 200 --out results
    python -m agents.evaluate --env-id tactile_search/IdentifyByTouch-v0 \\
        --scripted random_identify identify_planner oracle --out results/identify

A thin CLI over ``agents.evaluation.evaluation.evaluate``, which documents what it writes.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from agents.command_args import parse_setting
from agents.evaluation.agent_specs import ACTIONS
from agents.evaluation.evaluation import evaluate, evaluated_task
from agents.evaluation.report import markdown_table
from agents.scripted import SCRIPTED_AGENTS, scripted_agents_for
from tactile_search import ENV_ID, ENV_IDS
from tactile_search.seed_ranges import SPLITS


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--runs", nargs="*", default=[], help="run directories of agents.train")
    parser.add_argument(
        "--scripted",
        nargs="*",
        default=None,
        choices=list(SCRIPTED_AGENTS),
        help="scripted baselines to include (default: every one that plays the task of "
        "--env-id and --env-settings)",
    )
    parser.add_argument("--episodes", type=int, default=200)
    parser.add_argument(
        "--split",
        choices=sorted(SPLITS),
        default="validation",
        help="the held-out layouts (python/tactile_search/seed_ranges.py); test only with --final",
    )
    parser.add_argument(
        "--final",
        action="store_true",
        help="this is the final evaluation, which alone may read the test layouts",
    )
    parser.add_argument("--out", type=Path, default=Path("results"))
    parser.add_argument("--no-gifs", action="store_true")
    parser.add_argument("--gif-steps", type=int, default=200, help="steps shown per GIF")
    parser.add_argument(
        "--fresh",
        action="store_true",
        help="run every episode again instead of reusing the rows in --out/episodes.csv",
    )
    parser.add_argument(
        "--actions",
        choices=ACTIONS,
        default="recipe",
        help="learned agents' actions: as each recipe says (deterministic_evaluation), the "
        "policy's mode, sampled (seeded per episode), or the mode but sampled whenever the last "
        "probe left the observation unchanged (agents.evaluation.unstuck_mode)",
    )
    parser.add_argument(
        "--blank-map-channels",
        nargs="+",
        default=[],
        metavar="NAME=VALUE",
        help="every agent reads these map channels held at a pixel value, such as std=0 "
        "(agents.evaluation.map_ablation; the channel names of the core's observation layout)",
    )
    parser.add_argument(
        "--env-settings",
        nargs="+",
        type=parse_setting,
        default=[],
        metavar="KEY=VALUE",
        help="environment settings every agent is evaluated with over its own, values as YAML, "
        "such as fast_free_motion=true (CupboardSearchEnv's keyword arguments; the agents' "
        "names end with them)",
    )
    parser.add_argument(
        "--env-id",
        choices=list(ENV_IDS),
        default=None,
        help="the registered id whose task and tier every agent is evaluated in: its settings "
        "(gymnasium.spec(id).kwargs) go under --env-settings; the agents' names end with the "
        f"id's name (default: {ENV_ID}, the defaults)",
    )
    args = parser.parse_args(argv)
    task = evaluated_task(args.env_id, dict(args.env_settings))
    if args.scripted is None:
        args.scripted = scripted_agents_for(task)
    summaries = evaluate(
        [*args.runs, *args.scripted],
        out=args.out,
        episodes=args.episodes,
        split=args.split,
        final=args.final,
        gifs=not args.no_gifs,
        gif_steps=args.gif_steps,
        resume=not args.fresh,
        actions=args.actions,
        blanked=args.blank_map_channels,
        env_settings=dict(args.env_settings),
        env_id=args.env_id,
    )
    print(markdown_table(summaries, task))


if __name__ == "__main__":
    main()
