"""The scripted baselines' result files for the leaderboard (the command)::

    python -m agents.scripted_results --env-id tactile_search/CupboardSearch-v0 \\
        --episodes 50 --out docs/results/leaderboard

Every scripted agent that plays each id's task (or those given with ``--agents``) on the
first ``--episodes`` layouts of ``--split``, one result file each
(``<out>/<id's name>_<agent>.json``), as ``python -m tactile_search.benchmark --json`` writes
them. A thin CLI over ``agents.evaluation.scripted_results``; the page is then
``python -m tactile_search.benchmark.leaderboard <out> --out docs/LEADERBOARD.md``.
"""

from __future__ import annotations

import argparse
import shlex
import sys
from pathlib import Path

from agents.evaluation.evaluation import task_of
from agents.evaluation.scripted_results import result_file_name, scripted_result
from agents.scripted import SCRIPTED_AGENTS, scripted_agents_for
from tactile_search import ENV_ID, ENV_IDS
from tactile_search.benchmark.__main__ import summary_line
from tactile_search.benchmark.result_file import named_source, result_record, write_result
from tactile_search.benchmark.runner import DEFAULT_EPISODES
from tactile_search.seed_ranges import SPLITS

PROG = "python -m agents.scripted_results"


def main(argv: list[str] | None = None) -> list[Path]:
    parser = argparse.ArgumentParser(prog=PROG, description=__doc__.split("\n\n")[0])
    parser.add_argument("--env-id", nargs="+", choices=ENV_IDS, default=[ENV_ID])
    parser.add_argument(
        "--agents",
        nargs="+",
        choices=list(SCRIPTED_AGENTS),
        default=None,
        help="the scripted agents (default: every one that plays each id's task)",
    )
    parser.add_argument("--split", choices=sorted(SPLITS), default="validation")
    parser.add_argument("--final", action="store_true", help="the final evaluation (test split)")
    parser.add_argument("--episodes", type=int, default=DEFAULT_EPISODES)
    parser.add_argument("--num-envs", type=int, default=None, help="episodes side by side")
    parser.add_argument("--out", type=Path, required=True, help="the folder of result files")
    args = parser.parse_args(argv)
    command = f"{PROG} {shlex.join(sys.argv[1:] if argv is None else argv)}"
    written = []
    try:
        for env_id in args.env_id:
            for name in args.agents or scripted_agents_for(task_of(env_id)):
                result = scripted_result(
                    name, env_id, args.split, args.episodes,
                    final=args.final, num_envs=args.num_envs,
                )  # fmt: skip
                path = args.out / result_file_name(env_id, name)
                write_result(path, result_record(result, named_source("scripted", name), command))
                print(f"{env_id}: {summary_line(result)} -> {path}", flush=True)
                written.append(path)
    except ValueError as error:
        parser.exit(2, f"{PROG}: error: {' '.join(str(error).split())}\n")
    return written


if __name__ == "__main__":
    main()
