"""When identify agents claim, on the validation layouts (the command)::

    python -m agents.claim_decisions M/ppo_gpis_seed0 M/ppo_gpis_seed1 M/ppo_occupancy_seed0 \\
        identify_planner --episodes 200 [--blank-map-channels std=0] [--out DIR]

A column per agent, its training seeds pooled (runs of one agent, told apart by their seed,
share a column). A thin CLI over ``agents.evaluation.claim_decisions``, which documents what
is traced. ``--out`` also writes the table (``<out>/claim_decisions.md``) and each
decision (``<out>/claim_decisions.csv``: agent, spec, touched, touch, claimed).
"""

from __future__ import annotations

import argparse
import csv
from pathlib import Path

from agents.evaluation.agent_specs import ACTIONS
from agents.evaluation.claim_decisions import Decision, decisions_markdown, trace_decisions
from agents.evaluation.evaluation import task_of
from tactile_search import ENV_IDS
from tactile_search.seed_ranges import held_out_seeds

#: The registered ids whose task claims, in the core registry's order (the default tier first).
IDENTIFY_IDS = [env_id for env_id in ENV_IDS if task_of(env_id) == "identify"]


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("agents", nargs="+", help="run directories and scripted agents' names")
    parser.add_argument("--episodes", type=int, default=200, help="validation layouts")
    parser.add_argument("--env-id", choices=IDENTIFY_IDS, default=IDENTIFY_IDS[0])
    parser.add_argument("--actions", choices=ACTIONS, default="mode")
    parser.add_argument(
        "--blank-map-channels", nargs="+", default=(), metavar="NAME=VALUE",
        help="map channels every agent reads held at a pixel value (agents.evaluate's)",
    )  # fmt: skip
    parser.add_argument("--out", type=Path, help="a folder for the table and the decisions")
    args = parser.parse_args(argv)
    seeds = held_out_seeds("validation", args.episodes)
    pooled: dict[str, list[Decision]] = {}
    rows = []
    for spec in args.agents:
        name, decisions = trace_decisions(
            spec, seeds, args.env_id, args.actions, args.blank_map_channels
        )
        pooled.setdefault(name, []).extend(decisions)
        rows += [
            {"agent": name, "spec": spec, "touched": d.touched, "touch": d.touch,
             "claimed": d.claimed}
            for d in decisions
        ]  # fmt: skip
    table = decisions_markdown(pooled)
    print(f"Validation layouts {seeds[0]}..{seeds[-1]}, {args.env_id}:\n\n{table}")
    if args.out is not None:
        args.out.mkdir(parents=True, exist_ok=True)
        (args.out / "claim_decisions.md").write_text(table + "\n")
        with (args.out / "claim_decisions.csv").open("w", newline="") as f:
            writer = csv.DictWriter(f, fieldnames=["agent", "spec", "touched", "touch", "claimed"])
            writer.writeheader()
            writer.writerows(rows)


if __name__ == "__main__":
    main()
